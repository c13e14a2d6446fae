//! Where the parts of a 2D figure go: the title (shrunk to fit), the plot, and the legend
//! in a panel of its own beside the plot, sized to its longest label.

use crate::figure::{axes, color, failures, has_zeros, is_dense, Figure, Style};
use plotters::prelude::*;

/// Pixel size of every 2D figure: the plot on the left, the legend in a panel of its own
/// on the right (so that it never covers data), the title across the top.
pub const SIZE: (u32, u32) = (1200, 620);
pub(crate) const TITLE_FONT: f64 = 22.0;
pub(crate) const LEGEND_FONT: f64 = 14.0;
/// The legend panel's width: the longest label plus a swatch, within these bounds.
pub(crate) const LEGEND_WIDTH: (u32, u32) = (150, 480);
pub(crate) const SWATCH: i32 = 28;
pub(crate) const LEGEND_ROW: i32 = 22;

/// Text size in pixels, from the font's metrics (the same for SVG and PNG); a rough
/// estimate where the font cannot be measured.
pub(crate) fn text_size(text: &str, size: f64) -> (u32, u32) {
    ("sans-serif", size).into_font().box_size(text).unwrap_or((
        (0.6 * size * text.chars().count() as f64) as u32,
        size as u32,
    ))
}

/// Where a legend label starts, from the legend panel's left edge.
pub const LEGEND_TEXT_X: i32 = 12 + SWATCH + 8;

/// The width of a legend label in pixels.
pub fn legend_text_width(label: &str) -> u32 {
    text_size(label, LEGEND_FONT).0
}

/// The labels of a figure's legend, in order.
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
pub(crate) struct LegendRow {
    pub(crate) label: String,
    pub(crate) color: RGBColor,
    pub(crate) kind: Swatch,
}

#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Swatch {
    Line,
    Dashed,
    LineMarker,
    DashedMarker,
    Marker,
    Reference,
    Failed,
    Zero,
}

pub(crate) fn legend_rows(fig: &Figure) -> Vec<LegendRow> {
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
