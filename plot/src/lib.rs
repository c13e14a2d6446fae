//! Figures for integrator studies, drawn with plotters as SVG and PNG: 2D line and marker
//! plots on linear or log axes ([`Figure`]) and curves on a sphere ([`SphereFigure`]).
//!
//! What a study needs that a generic plot does not: the legend sits in a panel beside the
//! plot and never covers data; a value of zero on a log axis is drawn on the bottom edge
//! and the legend says so; a run that failed (finite `x`, non-finite `y`) is marked with a
//! cross at the top rather than left out; a series denser than the plot's pixel columns is
//! drawn as its per-column envelope, so the picture's extremes are the data's and no
//! renderer join invents a spike; long titles shrink to fit.
//!
//! ```
//! use lgsvi_plot::{Drawing, Figure, Series, Style};
//! let fig = Figure {
//!     title: "error against nodes".into(),
//!     x_label: "n".into(),
//!     y_label: "error".into(),
//!     x_log: false,
//!     y_log: true,
//!     series: vec![Series {
//!         label: "h = 0.5".into(),
//!         points: vec![(4.0, 1e-4), (8.0, 1e-9), (12.0, 1e-14), (16.0, 0.0)],
//!         style: Style::LineMarkers,
//!         color: 0,
//!     }],
//!     hlines: vec![(1e-12, "tolerance".into())],
//! };
//! let dir = std::env::temp_dir().join(format!("lgsvi-plot-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//! fig.write_svg(&dir.join("error.svg"))?;
//! fig.write_png(&dir.join("error.png"))?;
//! // The zero at n = 16 is drawn on the bottom edge, and the legend says so.
//! assert!(lgsvi_plot::legend_labels(&fig).iter().any(|l| l.contains("values of 0")));
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![deny(missing_docs)]

mod draw;
mod figure;
mod layout;
mod sphere;
#[cfg(test)]
mod tests;

pub use draw::{inspect, Drawn};
pub use figure::{Figure, Series, Style};
pub use layout::{layout, legend_labels, legend_text_width, Layout, LEGEND_TEXT_X, SIZE};
pub use sphere::SphereFigure;

use plotters::prelude::{BitMapBackend, IntoDrawingArea, SVGBackend};
use std::path::{Path, PathBuf};

/// A figure could not be drawn or written.
#[derive(Debug, thiserror::Error)]
#[error("cannot draw {path}: {message}")]
pub struct PlotError {
    /// The file being written.
    pub path: PathBuf,
    /// What plotters reported.
    pub message: String,
}

/// A figure this crate draws: [`Figure`] or [`SphereFigure`].
pub trait Drawing {
    /// The canvas in pixels.
    fn size(&self) -> (u32, u32);

    /// Writes the figure to `path` as SVG.
    ///
    /// # Errors
    /// [`PlotError`] when plotters cannot draw or write it.
    fn write_svg(&self, path: &Path) -> Result<(), PlotError>;

    /// Writes the figure to `path` as PNG.
    ///
    /// # Errors
    /// [`PlotError`] when plotters cannot draw or write it.
    fn write_png(&self, path: &Path) -> Result<(), PlotError>;
}

fn failed(path: &Path) -> impl FnOnce(String) -> PlotError {
    let path = path.to_path_buf();
    move |message| PlotError { path, message }
}

impl Drawing for Figure {
    fn size(&self) -> (u32, u32) {
        SIZE
    }
    fn write_svg(&self, path: &Path) -> Result<(), PlotError> {
        draw::draw(SVGBackend::new(path, SIZE).into_drawing_area(), self).map_err(failed(path))
    }
    fn write_png(&self, path: &Path) -> Result<(), PlotError> {
        draw::draw(BitMapBackend::new(path, SIZE).into_drawing_area(), self).map_err(failed(path))
    }
}

impl Drawing for SphereFigure {
    fn size(&self) -> (u32, u32) {
        sphere::SPHERE_SIZE
    }
    fn write_svg(&self, path: &Path) -> Result<(), PlotError> {
        sphere::draw_sphere(
            SVGBackend::new(path, sphere::SPHERE_SIZE).into_drawing_area(),
            self,
        )
        .map_err(failed(path))
    }
    fn write_png(&self, path: &Path) -> Result<(), PlotError> {
        sphere::draw_sphere(
            BitMapBackend::new(path, sphere::SPHERE_SIZE).into_drawing_area(),
            self,
        )
        .map_err(failed(path))
    }
}

/// This crate's `README.md`, whose Rust example is compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
