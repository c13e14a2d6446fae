//! What a figure is (its series, axes and reference lines) and the geometry every
//! renderer shares: axis ranges, the points drawn, failed runs, dense series binned by
//! pixel column.

use plotters::prelude::*;

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
    /// Its legend label.
    pub label: String,
    /// `(x, y)`; a finite `x` with a non-finite `y` is a failed run.
    pub points: Vec<(f64, f64)>,
    /// How it is drawn.
    pub style: Style,
    /// Index into the palette.
    pub color: usize,
}

/// A 2D figure.
#[derive(Debug, Clone)]
pub struct Figure {
    /// Drawn across the top (shrunk until it fits).
    pub title: String,
    /// The x axis' label.
    pub x_label: String,
    /// The y axis' label.
    pub y_label: String,
    /// Whether the x axis is logarithmic.
    pub x_log: bool,
    /// Whether the y axis is logarithmic (values at or below zero on its bottom edge).
    pub y_log: bool,
    /// The data.
    pub series: Vec<Series>,
    /// Horizontal reference lines `(y, label)`.
    pub hlines: Vec<(f64, String)>,
}

/// Twelve distinguishable colours (Tableau's ten, then olive and black): the bench's
/// work-precision plots draw ten series, which eight colours made repeat.
pub(crate) const PALETTE: [RGBColor; 12] = [
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

pub(crate) fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// The range of an axis: on a log axis from the decade below the smallest positive value
/// (values at or below zero, exact zeros of an error, are drawn on that bottom edge and
/// the legend says so; the CSV keeps them).
pub(crate) fn range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
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

/// The axes' ranges `(x0, x1, y0, y1)`.
pub(crate) fn axes(fig: &Figure) -> (f64, f64, f64, f64) {
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
pub(crate) fn drawable(fig: &Figure, s: &Series, x0: f64, y0: f64) -> Vec<(f64, f64)> {
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
pub(crate) fn has_zeros(fig: &Figure) -> bool {
    fig.y_log
        && fig
            .series
            .iter()
            .flat_map(|s| &s.points)
            .any(|p| p.0.is_finite() && p.1.is_finite() && p.1 <= 0.0)
}

/// The `x` of failed runs: finite `x`, non-finite `y`.
pub(crate) fn failures(s: &Series) -> impl Iterator<Item = f64> + '_ {
    s.points
        .iter()
        .filter(|p| p.0.is_finite() && !p.1.is_finite())
        .map(|p| p.0)
}

/// Pixel columns of the plot area (approximately; dense series are binned to this).
pub(crate) const DENSE_BINS: usize = 900;

pub(crate) fn is_dense(s: &Series) -> bool {
    s.points.len() > 2 * DENSE_BINS
}

/// A dense series binned by pixel column: per bin `(x, first, min, max, last)` in the
/// data's order. Drawn as a vertical segment from min to max per bin and a segment from
/// each bin's last value to the next bin's first, every segment a path of two points: the
/// picture's extremes are the data's, and there are no joins for a renderer to spike.
pub(crate) fn envelope(
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
