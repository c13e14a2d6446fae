//! Figures: 2D line/marker plots with linear or log axes, written as SVG and PNG
//! (plotters), and a 3D plot of curves on a sphere.

use crate::error::CliError;
use crate::files::Partial;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::{Path, PathBuf};

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

/// One series. A point with a finite `x` and a non-finite `y` is a run that failed: it is
/// marked with a cross at the top of the plot, not left out.
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

/// The range of an axis: on a log axis from the decade below the smallest positive value
/// (values at or below zero, exact zeros of an error, are drawn on that bottom edge and
/// the legend says so; the CSV keeps them).
fn range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
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

/// Pixel size of every 2D figure: the plot on the left, the legend in a panel of its own
/// on the right (so that it never covers data), the title across the top.
pub const SIZE: (u32, u32) = (1200, 620);
const TITLE_FONT: f64 = 22.0;
const LEGEND_FONT: f64 = 14.0;
/// The legend panel's width: the longest label plus a swatch, within these bounds.
const LEGEND_WIDTH: (u32, u32) = (150, 480);
const SWATCH: i32 = 28;
const LEGEND_ROW: i32 = 22;
/// Pixel columns of the plot area (approximately; dense series are binned to this).
const DENSE_BINS: usize = 900;

/// Text size in pixels, from the font's metrics (the same for SVG and PNG); a rough
/// estimate where the font cannot be measured.
fn text_size(text: &str, size: f64) -> (u32, u32) {
    ("sans-serif", size).into_font().box_size(text).unwrap_or((
        (0.6 * size * text.chars().count() as f64) as u32,
        size as u32,
    ))
}

/// Where a legend label starts, from the legend panel's left edge.
pub const LEGEND_TEXT_X: i32 = 12 + SWATCH + 8;

/// The width of a legend label in pixels.
#[cfg(test)]
pub fn legend_text_width(label: &str) -> u32 {
    text_size(label, LEGEND_FONT).0
}

/// The labels of a figure's legend, in order.
#[cfg(test)]
pub fn legend_labels(fig: &Figure) -> Vec<String> {
    legend_rows(fig).into_iter().map(|r| r.label).collect()
}

/// Where the parts of a figure go, in pixels (`(x0, y0, x1, y1)`, y down).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layout {
    /// The title's font size, shrunk until the title fits the width.
    pub title_font: f64,
    /// Whether the title fits the width at that size.
    pub title_fits: bool,
    /// The title's box.
    pub title: (i32, i32, i32, i32),
    /// The area of the axes, labels and data.
    pub plot: (i32, i32, i32, i32),
    /// The legend panel.
    pub legend: (i32, i32, i32, i32),
}

/// One legend row: the label, its colour, and how the swatch is drawn.
struct LegendRow {
    label: String,
    color: RGBColor,
    kind: Swatch,
}

#[derive(Clone, Copy, PartialEq)]
enum Swatch {
    Line,
    Dashed,
    LineMarker,
    DashedMarker,
    Marker,
    Reference,
    Failed,
    Zero,
}

fn legend_rows(fig: &Figure) -> Vec<LegendRow> {
    let mut rows: Vec<LegendRow> = fig
        .hlines
        .iter()
        .map(|(_, label)| LegendRow {
            label: label.clone(),
            color: RGBColor(128, 128, 128),
            kind: Swatch::Reference,
        })
        .collect();
    for s in &fig.series {
        let kind = match s.style {
            Style::Line => Swatch::Line,
            Style::LineMarkers => Swatch::LineMarker,
            Style::DashedMarkers => Swatch::DashedMarker,
            Style::Markers => Swatch::Marker,
        };
        // A dense line is drawn as a band without markers (see `draw_dense`).
        let kind = match (kind, is_dense(s)) {
            (Swatch::LineMarker | Swatch::Marker, true) => Swatch::Line,
            (Swatch::DashedMarker, true) => Swatch::Dashed,
            (k, _) => k,
        };
        rows.push(LegendRow {
            label: s.label.clone(),
            color: color(s.color),
            kind,
        });
    }
    if has_zeros(fig) {
        rows.push(LegendRow {
            label: format!("bottom edge ({:.0e}): values of 0", axes(fig).2),
            color: RGBColor(0, 0, 0),
            kind: Swatch::Zero,
        });
    }
    if fig.series.iter().any(|s| failures(s).next().is_some()) {
        rows.push(LegendRow {
            label: "at the top: a run that failed".into(),
            color: RGBColor(0, 0, 0),
            kind: Swatch::Failed,
        });
    }
    rows
}

/// The layout of `fig` on a canvas of `size` pixels.
pub fn layout(fig: &Figure, size: (u32, u32)) -> Layout {
    let (w, h) = (size.0 as i32, size.1 as i32);
    let mut title_font = TITLE_FONT;
    while title_font > 10.0 && text_size(&fig.title, title_font).0 as i32 > w - 20 {
        title_font -= 1.0;
    }
    let title_height = text_size(&fig.title, title_font).1 as i32 + 14;
    let widest = legend_rows(fig)
        .iter()
        .map(|r| text_size(&r.label, LEGEND_FONT).0)
        .max()
        .unwrap_or(0);
    let legend_width =
        (widest + LEGEND_TEXT_X as u32 + 24).clamp(LEGEND_WIDTH.0, LEGEND_WIDTH.1) as i32;
    Layout {
        title_font,
        title_fits: text_size(&fig.title, title_font).0 as i32 <= w - 20,
        title: (0, 0, w, title_height),
        plot: (0, title_height, w - legend_width, h),
        legend: (w - legend_width, title_height, w, h),
    }
}

/// The axes' ranges `(x0, x1, y0, y1)`.
fn axes(fig: &Figure) -> (f64, f64, f64, f64) {
    let xs = fig.series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    let ys = fig
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .chain(fig.hlines.iter().map(|h| h.0));
    let ((x0, x1), (y0, y1)) = (range(xs, fig.x_log), range(ys, fig.y_log));
    (x0, x1, y0, y1)
}

/// The points of a series that are drawn as data (finite), those at or below zero on a
/// log axis moved to its bottom or left edge (`y0`, `x0` of [`axes`]).
fn drawable(fig: &Figure, s: &Series, x0: f64, y0: f64) -> Vec<(f64, f64)> {
    s.points
        .iter()
        .filter(|p| p.0.is_finite() && p.1.is_finite())
        .map(|p| {
            (
                if fig.x_log { p.0.max(x0) } else { p.0 },
                if fig.y_log { p.1.max(y0) } else { p.1 },
            )
        })
        .collect()
}

/// Whether some value sits on the bottom edge of a log axis because it is zero.
fn has_zeros(fig: &Figure) -> bool {
    fig.y_log
        && fig
            .series
            .iter()
            .flat_map(|s| &s.points)
            .any(|p| p.0.is_finite() && p.1.is_finite() && p.1 <= 0.0)
}

/// The `x` of failed runs: finite `x`, non-finite `y`.
fn failures(s: &Series) -> impl Iterator<Item = f64> + '_ {
    s.points
        .iter()
        .filter(|p| p.0.is_finite() && !p.1.is_finite())
        .map(|p| p.0)
}

fn is_dense(s: &Series) -> bool {
    s.points.len() > 2 * DENSE_BINS
}

/// A dense series binned by pixel column: per bin `(x, first, min, max, last)` in the
/// data's order. Drawn as a vertical segment from min to max per bin and a segment from
/// each bin's last value to the next bin's first, every segment a path of two points: the
/// picture's extremes are the data's, and there are no joins for a renderer to spike.
fn envelope(
    points: &[(f64, f64)],
    x0: f64,
    x1: f64,
    x_log: bool,
) -> Vec<(f64, f64, f64, f64, f64)> {
    let position = |x: f64| {
        if x_log {
            (x.ln() - x0.ln()) / (x1.ln() - x0.ln())
        } else {
            (x - x0) / (x1 - x0)
        }
    };
    let mut bins: Vec<(f64, f64, f64, f64, f64)> = Vec::new();
    let mut current = usize::MAX;
    for &(x, y) in points {
        let bin = (position(x).clamp(0.0, 1.0) * DENSE_BINS as f64) as usize;
        match bins.last_mut() {
            Some(b) if bin == current => {
                b.2 = b.2.min(y);
                b.3 = b.3.max(y);
                b.4 = y;
            }
            _ => {
                bins.push((x, y, y, y, y));
                current = bin;
            }
        }
    }
    bins
}

/// What a figure draws, for checks: per series, the extremes of its data and of what is
/// drawn for it, and the failures marked.
#[cfg(test)]
#[derive(Debug, Clone, PartialEq)]
pub struct Drawn {
    pub label: String,
    /// `(min y, max y)` of the finite data (log-clamped as drawn).
    pub data: Option<(f64, f64)>,
    /// `(min y, max y)` of the drawn marks.
    pub drawn: Option<(f64, f64)>,
    pub failures: usize,
}

#[cfg(test)]
fn extremes(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values.fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// The extremes of every series' data beside those of what is drawn for it.
#[cfg(test)]
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
fn linear_tick(v: f64, span: f64) -> String {
    let step = span / 10.0;
    let decimals = if step > 0.0 && step.is_finite() {
        (-step.log10().floor()).clamp(0.0, 12.0) as usize
    } else {
        3
    };
    if v.abs() < 1e-9 * span.abs().max(f64::MIN_POSITIVE) {
        return "0".into();
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

fn draw_legend<DB: DrawingBackend>(
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

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, fig: &Figure) -> Result<(), String>
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

/// Renders a figure as `base.svg` and `base.png` (each through a temporary file renamed
/// into place), drawing it with `svg` and `png`.
fn render(
    base: &Path,
    size: (u32, u32),
    svg: impl FnOnce(DrawingArea<SVGBackend, Shift>) -> Result<(), String>,
    png: impl FnOnce(DrawingArea<BitMapBackend, Shift>) -> Result<(), String>,
) -> Result<(), CliError> {
    let (svg_path, png_path) = plot_paths(base);
    // Removed on every error: no `.partial-*` file is left behind.
    let (svg_partial, png_partial) = (Partial::new(&svg_path), Partial::new(&png_path));
    let failed = |path: &Path| {
        let path = path.to_path_buf();
        move |message| CliError::Plot { path, message }
    };
    svg(SVGBackend::new(svg_partial.path(), size).into_drawing_area())
        .map_err(failed(&svg_path))?;
    png(BitMapBackend::new(png_partial.path(), size).into_drawing_area())
        .map_err(failed(&png_path))?;
    svg_partial.commit(&svg_path)?;
    png_partial.commit(&png_path)
}

/// The two files a figure with base `base` writes: `base.svg` and `base.png`.
pub fn plot_paths(base: &Path) -> (PathBuf, PathBuf) {
    (base.with_extension("svg"), base.with_extension("png"))
}

/// Writes `base.svg` and `base.png`.
pub fn save(fig: &Figure, base: &Path) -> Result<(), CliError> {
    render(base, SIZE, |area| draw(area, fig), |area| draw(area, fig))
}

/// A 3D figure: curves on the sphere `|y| = radius`, with a wireframe of the sphere.
#[derive(Debug, Clone)]
pub struct SphereFigure {
    pub title: String,
    pub radius: f64,
    /// Each curve is a list of points, drawn as markers.
    pub curves: Vec<Vec<(f64, f64, f64)>>,
    /// One legend label per curve.
    pub labels: Vec<String>,
    /// The names of the three coordinates, drawn at the positive ends of their axes.
    pub axes: [String; 3],
}

/// The sphere figure's canvas: the 3D plot, and a legend panel on its right.
const SPHERE_SIZE: (u32, u32) = (1080, 720);
const SPHERE_PLOT_WIDTH: u32 = 760;

fn draw_sphere<DB: DrawingBackend>(
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

/// Writes `base.svg` and `base.png` of a sphere figure.
pub fn save_sphere(fig: &SphereFigure, base: &Path) -> Result<(), CliError> {
    render(
        base,
        SPHERE_SIZE,
        |area| draw_sphere(area, fig),
        |area| draw_sphere(area, fig),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

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
            save(&fig, &base).unwrap();
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
}
