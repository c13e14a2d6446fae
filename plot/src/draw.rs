//! Drawing a 2D figure on any plotters backend, and [`inspect`], what a figure draws,
//! for checks.

use crate::figure::{axes, color, drawable, envelope, failures, is_dense, Figure, Style};
use crate::layout::{
    layout, legend_rows, LegendRow, Swatch, LEGEND_FONT, LEGEND_ROW, LEGEND_TEXT_X, SWATCH,
};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// What a figure draws, for checks: per series, the extremes of its data and of what is
/// drawn for it, and the failures marked.
#[derive(Debug, Clone, PartialEq)]
pub struct Drawn {
    /// The series' label.
    pub label: String,
    /// `(min y, max y)` of the finite data (log-clamped as drawn).
    pub data: Option<(f64, f64)>,
    /// `(min y, max y)` of the drawn marks.
    pub drawn: Option<(f64, f64)>,
    /// How many failed runs are marked.
    pub failures: usize,
}

pub(crate) fn extremes(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values.fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// The extremes of every series' data beside those of what is drawn for it.
pub fn inspect(fig: &Figure) -> Vec<Drawn> {
    let (x0, x1, y0, _) = axes(fig);
    fig.series
        .iter()
        .map(|s| {
            let pts = drawable(fig, s, x0, y0);
            let drawn = if is_dense(s) {
                extremes(
                    envelope(&pts, x0, x1, fig.x_log)
                        .iter()
                        .flat_map(|b| [b.2, b.3]),
                )
            } else {
                extremes(pts.iter().map(|p| p.1))
            };
            Drawn {
                label: s.label.clone(),
                data: extremes(pts.iter().map(|p| p.1)),
                drawn,
                failures: failures(s).count(),
            }
        })
        .collect()
}

/// Tick labels on a linear axis: as many decimals as the tick spacing needs, and no
/// negative zero.
pub(crate) fn linear_tick(v: f64, span: f64) -> String {
    let step = span / 10.0;
    let decimals = if step > 0.0 && step.is_finite() {
        (-step.log10().floor()).clamp(0.0, 12.0) as usize
    } else {
        3
    };
    if v.abs() < 1e-9 * span.abs().max(f64::MIN_POSITIVE) {
        return "0".into();
    }
    // Ticks far below a ten-thousandth apart (an energy error of 1e-15) or a million and
    // more: in scientific notation with the digits that tell them apart (fixed decimals
    // would print every one as 0, or fifteen digits).
    if step > 0.0 && step.is_finite() && !(1e-4..1e6).contains(&step) {
        let precision = (v.abs().log10().floor() - step.log10().floor()).clamp(0.0, 6.0) as usize;
        return format!("{v:.precision$e}");
    }
    let text = format!("{v:.decimals$}");
    if text
        .trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        "0".into()
    } else {
        text
    }
}

pub(crate) fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    rows: &[LegendRow],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let font = ("sans-serif", LEGEND_FONT).into_font().color(&BLACK);
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let x = LEGEND_TEXT_X - SWATCH - 8;
    for (k, row) in rows.iter().enumerate() {
        let y = 40 + k as i32 * LEGEND_ROW;
        let c = row.color;
        let segment = |a: i32, b: i32, width: u32| {
            PathElement::new(vec![(a, y), (b, y)], c.stroke_width(width))
        };
        match row.kind {
            Swatch::Line | Swatch::LineMarker => {
                area.draw(&segment(x, x + SWATCH, 2)).map_err(e)?
            }
            Swatch::Reference => area.draw(&segment(x, x + SWATCH, 1)).map_err(e)?,
            Swatch::Dashed | Swatch::DashedMarker => {
                for a in [x, x + 11, x + 22] {
                    area.draw(&segment(a, (a + 6).min(x + SWATCH), 2))
                        .map_err(e)?;
                }
            }
            Swatch::Marker | Swatch::Failed => {}
            Swatch::Zero => area
                .draw(&PathElement::new(
                    vec![(x, y + 6), (x + SWATCH, y + 6)],
                    c.stroke_width(1),
                ))
                .map_err(e)?,
        }
        match row.kind {
            Swatch::LineMarker | Swatch::DashedMarker | Swatch::Marker => area
                .draw(&Circle::new((x + SWATCH / 2, y), 3, c.filled()))
                .map_err(e)?,
            Swatch::Failed => area
                .draw(&Cross::new((x + SWATCH / 2, y), 4, c.stroke_width(2)))
                .map_err(e)?,
            _ => {}
        }
        area.draw(&Text::new(
            row.label.clone(),
            (LEGEND_TEXT_X, y - (LEGEND_FONT as i32) / 2 - 1),
            font.clone(),
        ))
        .map_err(e)?;
    }
    Ok(())
}

pub(crate) fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    fig: &Figure,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (w, h) = root.dim_in_pixel();
    let layout = layout(fig, (w, h));
    let (title, rest) = root.split_vertically(layout.title.3);
    title
        .draw(&Text::new(
            fig.title.clone(),
            (w as i32 / 2, 6),
            ("sans-serif", layout.title_font)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Center, VPos::Top)),
        ))
        .map_err(|e| e.to_string())?;
    let (plot_area, legend_area) = rest.split_horizontally(layout.plot.2);
    draw_legend(&legend_area, &legend_rows(fig))?;
    let (x0, x1, y0, y1) = axes(fig);
    let mut builder = ChartBuilder::on(&plot_area);
    builder
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
                        linear_tick(*v, y1 - y0)
                    }
                })
                .x_label_formatter(&|v| {
                    if fig.x_log {
                        // Decades far from 1 as powers of ten: `{}` writes 1e-13 out as
                        // fifteen digits, and neighbouring labels run into each other.
                        if (1e-2..=1e3).contains(&v.abs()) {
                            format!("{}", v)
                        } else {
                            format!("{:.0e}", v)
                        }
                    } else {
                        linear_tick(*v, x1 - x0)
                    }
                })
                .draw()
                .map_err(|e| e.to_string())?;
            let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
            for (y, _) in &fig.hlines {
                let y = if fig.y_log { y.max(y0) } else { *y };
                $chart
                    .draw_series(std::iter::once(PathElement::new(
                        vec![(x0, y), (x1, y)],
                        RGBColor(128, 128, 128).stroke_width(1),
                    )))
                    .map_err(err)?;
            }
            // Failed runs at the same x are stacked downwards, one cross per series.
            let mut seen: Vec<(f64, i32)> = Vec::new();
            let stacked: Vec<Vec<(f64, i32)>> = fig
                .series
                .iter()
                .map(|s| {
                    failures(s)
                        .map(|x| {
                            let k = match seen.iter_mut().find(|(v, _)| *v == x) {
                                Some(entry) => {
                                    entry.1 += 1;
                                    entry.1
                                }
                                None => {
                                    seen.push((x, 0));
                                    0
                                }
                            };
                            (x, k)
                        })
                        .collect()
                })
                .collect();
            for (s, crosses) in fig.series.iter().zip(&stacked) {
                let c = color(s.color);
                let pts = drawable(fig, s, x0, y0);
                if is_dense(s) {
                    let bins = envelope(&pts, x0, x1, fig.x_log);
                    let style = c.stroke_width(1);
                    $chart
                        .draw_series(
                            bins.iter()
                                .map(|b| PathElement::new(vec![(b.0, b.2), (b.0, b.3)], style)),
                        )
                        .map_err(err)?;
                    $chart
                        .draw_series(bins.windows(2).map(|p| {
                            PathElement::new(vec![(p[0].0, p[0].4), (p[1].0, p[1].1)], style)
                        }))
                        .map_err(err)?;
                } else {
                    match s.style {
                        // Segment by segment: no joins between them for a renderer to spike.
                        Style::LineMarkers | Style::Line => {
                            $chart
                                .draw_series(
                                    pts.windows(2).map(|p| {
                                        PathElement::new(vec![p[0], p[1]], c.stroke_width(2))
                                    }),
                                )
                                .map_err(err)?;
                        }
                        Style::DashedMarkers => {
                            $chart
                                .draw_series(DashedLineSeries::new(
                                    pts.clone(),
                                    8,
                                    5,
                                    c.stroke_width(2),
                                ))
                                .map_err(err)?;
                        }
                        Style::Markers => {}
                    }
                    if s.style != Style::Line {
                        $chart
                            .draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))
                            .map_err(err)?;
                    }
                }
                // Failed runs: a cross at the top of the plot, at their x.
                $chart
                    .draw_series(crosses.iter().map(|&(x, k)| {
                        let x = if fig.x_log { x.max(x0) } else { x };
                        EmptyElement::at((x, y1))
                            + Cross::new((0, 8 + 13 * k), 5, c.stroke_width(2))
                    }))
                    .map_err(err)?;
            }
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
