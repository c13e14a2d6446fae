//! Figures, drawn by `lgsvi-plot`, written as `base.svg` and `base.png`, each through a
//! temporary file renamed into place (a failed run leaves the previous figure).

use crate::error::CliError;
use crate::files::Partial;
pub use lgsvi_plot::Drawing;
use std::path::{Path, PathBuf};

/// The two files a figure with base `base` writes: `base.svg` and `base.png`.
pub fn plot_paths(base: &Path) -> (PathBuf, PathBuf) {
    (base.with_extension("svg"), base.with_extension("png"))
}

/// Writes `base.svg` and `base.png`.
pub fn save(fig: &impl Drawing, base: &Path) -> Result<(), CliError> {
    let (svg_path, png_path) = plot_paths(base);
    // Removed on every error: no `.partial-*` file is left behind.
    let (svg_partial, png_partial) = (Partial::new(&svg_path)?, Partial::new(&png_path)?);
    let failed = |path: &Path| {
        let path = path.to_path_buf();
        move |e: lgsvi_plot::PlotError| CliError::Plot {
            path,
            message: e.message,
        }
    };
    fig.write_svg(svg_partial.path())
        .map_err(failed(&svg_path))?;
    fig.write_png(png_partial.path())
        .map_err(failed(&png_path))?;
    svg_partial.commit(&svg_path)?;
    png_partial.commit(&png_path)
}
