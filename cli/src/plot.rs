//! Figures: 2D line/marker plots with linear or log axes, written as SVG and PNG
//! (plotters), and a 3D plot of curves on a sphere.

use crate::files::{commit, partial_path};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// A solid line with markers at the data.
    LineMarkers,
    /// A solid line.
    Line,
    /// A dashed line with markers.
    DashedMarkers,
    /// Markers only.
    Markers,
}

/// One series.
#[derive(Debug, Clone)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
    /// Index into the palette.
    pub color: usize,
}

/// A 2D figure.
#[derive(Debug, Clone)]
pub struct Figure {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_log: bool,
    pub y_log: bool,
    pub series: Vec<Series>,
    /// Horizontal reference lines `(y, label)`.
    pub hlines: Vec<(f64, String)>,
    /// Put the legend in the upper left corner (default: upper right).
    pub legend_left: bool,
}

/// Twelve distinguishable colours (Tableau's ten, then olive and black): the bench's
/// work-precision plots draw ten series, which eight colours made repeat.
const PALETTE: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(128, 128, 0),
    RGBColor(0, 0, 0),
];

fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Values below this are drawn at this value on a log axis (the CSV keeps them).
const LOG_FLOOR: f64 = 1e-17;

fn range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        let v = if log { v.max(LOG_FLOOR) } else { v };
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return if log { (1e-16, 1.0) } else { (0.0, 1.0) };
    }
    if log {
        let (a, b) = (
            lo.log10().floor(),
            hi.log10().ceil().max(lo.log10().floor() + 1.0),
        );
        (10f64.powf(a), 10f64.powf(b))
    } else {
        let pad = if hi > lo {
            0.05 * (hi - lo)
        } else {
            0.5 * hi.abs().max(1.0)
        };
        (lo - pad, hi + pad)
    }
}

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, fig: &Figure) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let xs = fig.series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    let ys = fig
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .chain(fig.hlines.iter().map(|h| h.0));
    let (x0, x1) = range(xs, fig.x_log);
    let (y0, y1) = range(ys, fig.y_log);
    let mut builder = ChartBuilder::on(&root);
    builder
        .caption(&fig.title, ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(78);
    macro_rules! body {
        ($chart:ident) => {{
            $chart
                .configure_mesh()
                .x_desc(fig.x_label.as_str())
                .y_desc(fig.y_label.as_str())
                .label_style(("sans-serif", 15))
                .axis_desc_style(("sans-serif", 17))
                .y_label_formatter(&|v| {
                    if fig.y_log {
                        format!("{:.0e}", v)
                    } else {
                        format!("{:.3}", v)
                    }
                })
                .x_label_formatter(&|v| {
                    if fig.x_log {
                        format!("{}", v)
                    } else {
                        format!("{}", (v * 1000.0).round() / 1000.0)
                    }
                })
                .draw()
                .map_err(|e| e.to_string())?;
            let clamp = |p: &(f64, f64)| {
                (
                    if fig.x_log { p.0.max(LOG_FLOOR) } else { p.0 },
                    if fig.y_log { p.1.max(LOG_FLOOR) } else { p.1 },
                )
            };
            for (y, label) in &fig.hlines {
                let y = if fig.y_log { y.max(LOG_FLOOR) } else { *y };
                $chart
                    .draw_series(LineSeries::new(
                        vec![(x0, y), (x1, y)],
                        BLACK.mix(0.5).stroke_width(1),
                    ))
                    .map_err(|e| e.to_string())?
                    .label(label.as_str())
                    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.mix(0.5)));
            }
            for s in &fig.series {
                let c = color(s.color);
                let pts: Vec<(f64, f64)> = s
                    .points
                    .iter()
                    .filter(|p| p.0.is_finite() && p.1.is_finite())
                    .map(clamp)
                    .collect();
                let line = matches!(s.style, Style::LineMarkers | Style::Line);
                let dashed = s.style == Style::DashedMarkers;
                let markers = s.style != Style::Line;
                if line {
                    $chart
                        .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                        .map_err(|e| e.to_string())?;
                }
                if dashed {
                    $chart
                        .draw_series(DashedLineSeries::new(pts.clone(), 8, 5, c.stroke_width(2)))
                        .map_err(|e| e.to_string())?;
                }
                let anno = if markers {
                    $chart
                        .draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))
                        .map_err(|e| e.to_string())?
                } else {
                    $chart
                        .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                        .map_err(|e| e.to_string())?
                };
                anno.label(s.label.as_str()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                });
            }
            $chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 14))
                .position(if fig.legend_left {
                    SeriesLabelPosition::UpperLeft
                } else {
                    SeriesLabelPosition::UpperRight
                })
                .draw()
                .map_err(|e| e.to_string())?;
        }};
    }
    match (fig.x_log, fig.y_log) {
        (false, false) => {
            let mut chart = builder
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|e| e.to_string())?;
            body!(chart);
        }
        (false, true) => {
            let mut chart = builder
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                .map_err(|e| e.to_string())?;
            body!(chart);
        }
        (true, false) => {
            let mut chart = builder
                .build_cartesian_2d((x0..x1).log_scale(), y0..y1)
                .map_err(|e| e.to_string())?;
            body!(chart);
        }
        (true, true) => {
            let mut chart = builder
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(|e| e.to_string())?;
            body!(chart);
        }
    }
    root.present().map_err(|e| e.to_string())?;
    Ok(())
}

/// Pixel size of every figure.
const SIZE: (u32, u32) = (960, 620);

/// Writes `base.svg` and `base.png`.
pub fn save(fig: &Figure, base: &Path) -> Result<(), String> {
    let (svg, png) = (base.with_extension("svg"), base.with_extension("png"));
    let (svg_partial, png_partial) = (partial_path(&svg), partial_path(&png));
    draw(SVGBackend::new(&svg_partial, SIZE).into_drawing_area(), fig)
        .map_err(|e| format!("{}: {e}", svg.display()))?;
    draw(
        BitMapBackend::new(&png_partial, SIZE).into_drawing_area(),
        fig,
    )
    .map_err(|e| format!("{}: {e}", png.display()))?;
    commit(&svg_partial, &svg)?;
    commit(&png_partial, &png)
}

/// A 3D figure: curves on the sphere `|y| = radius`, with a wireframe of the sphere.
#[derive(Debug, Clone)]
pub struct SphereFigure {
    pub title: String,
    pub radius: f64,
    /// Each curve is a list of points, drawn as markers.
    pub curves: Vec<Vec<(f64, f64, f64)>>,
}

fn draw_sphere<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    fig: &SphereFigure,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let r = fig.radius * 1.05;
    let mut chart = ChartBuilder::on(&root)
        .caption(&fig.title, ("sans-serif", 22))
        .margin(10)
        .build_cartesian_3d(-r..r, -r..r, -r..r)
        .map_err(|e| e.to_string())?;
    chart.with_projection(|mut p| {
        p.pitch = 0.45;
        p.yaw = 0.7;
        p.scale = 0.85;
        p.into_matrix()
    });
    chart
        .configure_axes()
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(|e| e.to_string())?;
    // Wireframe: meridians and parallels.
    let grey = RGBColor(190, 190, 190);
    let radius = fig.radius;
    for k in 0..12 {
        let phi = std::f64::consts::PI * k as f64 / 12.0;
        let meridian: Vec<_> = (0..=60)
            .map(|j| {
                let th = 2.0 * std::f64::consts::PI * j as f64 / 60.0;
                (
                    radius * th.sin() * phi.cos(),
                    radius * th.cos(),
                    radius * th.sin() * phi.sin(),
                )
            })
            .collect();
        chart
            .draw_series(LineSeries::new(meridian, grey))
            .map_err(|e| e.to_string())?;
    }
    for k in 1..8 {
        let th = std::f64::consts::PI * k as f64 / 8.0;
        let parallel: Vec<_> = (0..=60)
            .map(|j| {
                let phi = 2.0 * std::f64::consts::PI * j as f64 / 60.0;
                (
                    radius * th.sin() * phi.cos(),
                    radius * th.cos(),
                    radius * th.sin() * phi.sin(),
                )
            })
            .collect();
        chart
            .draw_series(LineSeries::new(parallel, grey))
            .map_err(|e| e.to_string())?;
    }
    for (i, curve) in fig.curves.iter().enumerate() {
        let c = color(i);
        // plotters' 3D axes: (x, y, z) with y vertical; draw body axis 3 vertical.
        chart
            .draw_series(
                curve
                    .iter()
                    .map(|&(x, y, z)| Circle::new((x, z, y), 2, c.filled())),
            )
            .map_err(|e| e.to_string())?;
    }
    root.present().map_err(|e| e.to_string())?;
    Ok(())
}

/// Writes `base.svg` and `base.png` of a sphere figure.
pub fn save_sphere(fig: &SphereFigure, base: &Path) -> Result<(), String> {
    let (svg, png) = (base.with_extension("svg"), base.with_extension("png"));
    let (svg_partial, png_partial) = (partial_path(&svg), partial_path(&png));
    draw_sphere(
        SVGBackend::new(&svg_partial, (760, 720)).into_drawing_area(),
        fig,
    )
    .map_err(|e| format!("{}: {e}", svg.display()))?;
    draw_sphere(
        BitMapBackend::new(&png_partial, (760, 720)).into_drawing_area(),
        fig,
    )
    .map_err(|e| format!("{}: {e}", png.display()))?;
    commit(&svg_partial, &svg)?;
    commit(&png_partial, &png)
}
