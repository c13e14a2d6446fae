//! A 3D figure: curves on a sphere, with the sphere's wireframe.

use crate::draw::draw_legend;
use crate::figure::color;
use crate::layout::{text_size, LegendRow, Swatch, TITLE_FONT};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A 3D figure: curves on the sphere `|y| = radius`, with a wireframe of the sphere.
#[derive(Debug, Clone)]
pub struct SphereFigure {
    /// Drawn across the top.
    pub title: String,
    /// The sphere's radius.
    pub radius: f64,
    /// Each curve is a list of points, drawn as markers.
    pub curves: Vec<Vec<(f64, f64, f64)>>,
    /// One legend label per curve.
    pub labels: Vec<String>,
    /// The names of the three coordinates, drawn at the positive ends of their axes.
    pub axes: [String; 3],
}

/// The sphere figure's canvas: the 3D plot, and a legend panel on its right.
pub(crate) const SPHERE_SIZE: (u32, u32) = (1080, 720);
pub(crate) const SPHERE_PLOT_WIDTH: u32 = 760;

pub(crate) fn draw_sphere<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    fig: &SphereFigure,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (w, _) = root.dim_in_pixel();
    let mut title_font = TITLE_FONT;
    while title_font > 10.0 && text_size(&fig.title, title_font).0 + 20 > w {
        title_font -= 1.0;
    }
    let title_height = text_size(&fig.title, title_font).1 + 14;
    let (title, rest) = root.split_vertically(title_height);
    title
        .draw(&Text::new(
            fig.title.clone(),
            (w as i32 / 2, 6),
            ("sans-serif", title_font)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Top)),
        ))
        .map_err(|e| e.to_string())?;
    let (plot_area, legend_area) = rest.split_horizontally(SPHERE_PLOT_WIDTH);
    let rows: Vec<LegendRow> = fig
        .labels
        .iter()
        .enumerate()
        .map(|(i, label)| LegendRow {
            label: label.clone(),
            color: color(i),
            kind: Swatch::Marker,
        })
        .collect();
    draw_legend(&legend_area, &rows)?;
    let r = fig.radius * 1.2;
    let mut chart = ChartBuilder::on(&plot_area)
        .margin(10)
        .build_cartesian_3d(-r..r, -r..r, -r..r)
        .map_err(|e| e.to_string())?;
    chart.with_projection(|mut p| {
        p.pitch = 0.45;
        p.yaw = 0.7;
        p.scale = 0.78;
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
    // The coordinate axes through the centre, named at their positive ends; plotters'
    // (x, y, z) has y vertical, so the figure's (a, b, c) is drawn at (a, c, b).
    let dark = RGBColor(60, 60, 60);
    let label_font = ("sans-serif", 20).into_font().color(&dark);
    for (k, name) in fig.axes.iter().enumerate() {
        let mut end = [0.0; 3];
        end[k] = radius * 1.12;
        let at = |v: [f64; 3], scale: f64| (v[0] * scale, v[2] * scale, v[1] * scale);
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![at(end, -1.0), at(end, 1.0)],
                dark.stroke_width(1),
            )))
            .map_err(|e| e.to_string())?;
        chart
            .draw_series(std::iter::once(Text::new(
                name.clone(),
                at(end, 1.06),
                label_font.clone(),
            )))
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
