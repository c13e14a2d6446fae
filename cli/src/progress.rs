//! Progress on standard error: a bar per long job, none when quiet or not on a terminal.

use lgsvi_experiments::paper::Progress;

/// A progress bar on standard error, hidden for `--quiet`, for short jobs, or when standard
/// error is not a terminal (so files and pipes never receive control characters).
pub fn bar(len: u64, message: &str, unit: &str, quiet: bool) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    let short = unit == "steps" && len < PROGRESS_FROM_STEPS;
    if quiet || short || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(len);
    let template = format!("{{msg:28}} [{{bar:40}}] {{pos}}/{{len}} {unit}, {{eta}} left");
    if let Ok(style) = indicatif::ProgressStyle::with_template(&template) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message(message.to_string());
    bar
}

/// Runs of at least this many steps show a progress bar (on a terminal, unless `--quiet`).
const PROGRESS_FROM_STEPS: u64 = 1000;

/// `reproduce`'s progress bars: one per measurement, none when quiet.
pub struct Bars {
    pub quiet: bool,
    pub bar: Option<indicatif::ProgressBar>,
}

impl Progress for Bars {
    fn begin(&mut self, what: &str, units: u64) {
        self.bar = Some(bar(units, what, "units", self.quiet));
    }
    fn advance(&mut self, units: u64) {
        if let Some(bar) = &self.bar {
            bar.inc(units);
        }
    }
    fn end(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}
