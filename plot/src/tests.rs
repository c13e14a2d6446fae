//! Rendering checks: the PNG shows no value beyond the data, ticks, layout.

use crate::draw::linear_tick;
use crate::figure::color;
use crate::layout::{text_size, TITLE_FONT};
use crate::{inspect, layout, Drawing, Figure, Series, Style, SIZE};
use std::path::Path;

/// A series that zigzags over three decades from point to point (as an energy error at
/// rounding level does), with reference lines at its largest and smallest value.
fn zigzag(points: usize) -> (Figure, f64, f64) {
    let data: Vec<(f64, f64)> = (0..points)
        .map(|k| {
            let wobble = 1.0 + ((k * 7919) % 13) as f64 / 13.0;
            let y = if k % 2 == 0 {
                1e-8 * wobble
            } else {
                1e-11 * wobble
            };
            (k as f64, y)
        })
        .collect();
    let hi = data.iter().map(|p| p.1).fold(0.0, f64::max);
    let lo = data.iter().map(|p| p.1).fold(1.0, f64::min);
    let fig = Figure {
        title: "zigzag".into(),
        x_label: "t".into(),
        y_label: "error".into(),
        x_log: false,
        y_log: true,
        series: vec![Series {
            label: "data".into(),
            points: data,
            style: Style::Line,
            color: 0,
        }],
        hlines: vec![(hi, "max".into()), (lo, "min".into())],
    };
    (fig, lo, hi)
}

/// The rows of the PNG's plot area holding the series' colour, and the two rows of the
/// reference lines.
fn rows(fig: &Figure, path: &Path) -> (u32, u32, Vec<u32>) {
    let image = image::open(path).unwrap().to_rgb8();
    let plot_right = layout(fig, SIZE).plot.2 as u32;
    let series = color(0);
    let (mut top, mut bottom) = (u32::MAX, 0);
    let mut grey = Vec::new();
    for y in 0..image.height() {
        let mut count = 0;
        for x in 0..plot_right {
            let p = image.get_pixel(x, y).0;
            if p == [series.0, series.1, series.2] {
                top = top.min(y);
                bottom = bottom.max(y);
            }
            if p == [128, 128, 128] {
                count += 1;
            }
        }
        if count > plot_right / 2 {
            grey.push(y);
        }
    }
    (top, bottom, grey)
}

/// The renderer must not invent values: thick polylines with acute joins spiked two
/// decades above the data in the PNG. Both the segment-by-segment drawing (sparse
/// series) and the per-pixel envelope (dense ones) stay within the data.
#[test]
fn the_png_shows_no_value_beyond_the_data() {
    let dir = std::env::temp_dir().join(format!("lgsvi-plot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for points in [1000, 10_000] {
        let (fig, lo, hi) = zigzag(points);
        let drawn = &inspect(&fig)[0];
        assert_eq!(drawn.drawn, Some((lo, hi)));
        assert_eq!(drawn.data, Some((lo, hi)));
        let base = dir.join(format!("zigzag{points}"));
        fig.write_png(&base.with_extension("png")).unwrap();
        let (top, bottom, grey) = rows(&fig, &base.with_extension("png"));
        let (max_row, min_row) = (grey[0], *grey.last().unwrap());
        // A 2-pixel stroke reaches at most one row past its end point.
        assert!(
            top + 2 >= max_row,
            "{points}: drawn up to row {top}, data max at {max_row}"
        );
        assert!(
            bottom <= min_row + 2,
            "{points}: drawn down to row {bottom}, data min at {min_row}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn linear_ticks_have_no_negative_zero_and_fit_the_spacing() {
    assert_eq!(linear_tick(-1e-17, 2.0), "0");
    assert_eq!(linear_tick(0.0, 2.0), "0");
    assert_eq!(linear_tick(1.0, 2.0), "1.0");
    assert_eq!(linear_tick(-0.2, 2.0), "-0.2");
    assert_eq!(linear_tick(1500.0, 1500.0), "1500");
    assert_eq!(linear_tick(0.0004, 0.001), "0.0004");
    // Tiny and huge spans in scientific notation, each tick told apart from its
    // neighbours (ticks 2e-16 apart), never all "0".
    assert_eq!(linear_tick(-4e-15, 1e-14), "-4e-15");
    assert_eq!(linear_tick(1.2e-15, 2e-15), "1.2e-15");
    assert_ne!(linear_tick(1.2e-15, 2e-15), linear_tick(1.4e-15, 2e-15));
    assert_eq!(linear_tick(3.5e7, 1e7), "3.5e7");
    assert_eq!(linear_tick(4e7, 1e8), "4e7");
}

#[test]
fn long_titles_shrink_and_legends_sit_beside_the_plot() {
    let (mut fig, _, _) = zigzag(10);
    fig.title = "3D pendulum (unstable): centre-of-mass direction Rρ, n = 20, h = 0.6 (unscaled Cayley (paper), exact matching), and more words to make it wider than any canvas we draw".into();
    let l = layout(&fig, SIZE);
    assert!(
        l.title_fits && l.title_font < TITLE_FONT,
        "{l:?} {:?}",
        text_size(&fig.title, l.title_font)
    );
    assert!(l.plot.2 <= l.legend.0);
}
