//! What `reproduce` measures is `lgsvi_experiments::paper`; here, the problems it measures
//! (resolved as `simulate` resolves its flags) and the progress bars it shows.

use crate::config::{ChartArg, MatchingArg, SimulateOptions, SystemKind};
use crate::error::Result;
use crate::problem::Problem;
use lgsvi_experiments::paper::Progress;

/// The problem of `system` with the paper's defaults and these settings; `unstable` starts
/// the pendulum near its unstable equilibrium (case C).
pub(super) fn problem(
    system: SystemKind,
    chart: ChartArg,
    matching: MatchingArg,
    h: f64,
    nodes: usize,
    t_end: f64,
    unstable: bool,
) -> Result<Problem> {
    let options = SimulateOptions {
        system: Some(system),
        chart: Some(chart),
        matching: Some(matching),
        h: Some(h),
        nodes: Some(nodes),
        t_end: Some(t_end),
        attitude0: unstable.then(|| {
            let r = crate::problem::named_case("C").attitude0;
            std::array::from_fn(|i| r[(i / 3, i % 3)])
        }),
        quiet: true,
        ..SimulateOptions::default()
    };
    Ok(Problem::resolve(options)?.0)
}

/// `reproduce`'s progress bars: one per measurement, none when quiet.
pub(super) struct Bars {
    quiet: bool,
    bar: Option<indicatif::ProgressBar>,
}

impl Bars {
    pub(super) fn new(quiet: bool) -> Self {
        Self { quiet, bar: None }
    }
}

impl Progress for Bars {
    fn begin(&mut self, what: &str, units: u64) {
        self.bar = Some(crate::progress_bar(units, what, "units", self.quiet));
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
