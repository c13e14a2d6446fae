//! Tolerance-driven runs, measured (`lgsvi converge --study estimate | tolerance`):
//!
//! - **estimate**: every step of runs over a grid of `(h, n)` is compared with the step from
//!   the same state with [`TRUTH_EXTRA_NODES`] more nodes (spectral convergence makes that
//!   the exact flow to rounding at these steps); the ratio of the step's own error estimate
//!   ([`Integrator::error_estimate`]) to that true local error is its calibration.
//! - **tolerance**: `--tol` runs for a list of tolerances against a high-accuracy reference at
//!   the horizon, each beside the fastest fixed `(h, n)` of a grid that is at least as
//!   accurate, with the run's own estimate of its global error and its nodes per step.
//!
//! Both work for every system `simulate` runs, SO(3) and SE(3); the error of a state is the
//! largest difference in the entries of `R`, `Ω` and, on SE(3), `x` and `ẋ`.

use crate::error::{CliError, Result};
use crate::plot::{Figure, Series, Style};
use crate::problem::Problem;
use lgsvi_mechanics::lie::{ChartKind, SE3, SO3};
use lgsvi_mechanics::{ElementOf, GroupChart, GroupLagrangian, Integrator, State, StepSettings};
use serde::Serialize;
use std::fmt::Write;
use std::time::Instant;

/// The truth of a step: the same step with this many more nodes (at `h ≤ 1.25` on the
/// reference cases, 14 more nodes than 5…12 put the step's error below 1e-15).
pub const TRUTH_EXTRA_NODES: usize = 14;

/// Local errors at or below this are rounding and are left out of the calibration.
pub const LOCAL_FLOOR: f64 = 1e-14;

/// The reference of the tolerance study: `h ≈ 0.25` dividing the horizon, this many nodes.
pub const REFERENCE_NODES: usize = 24;

/// Timing repetitions of every run of the tolerance study (the fastest is kept).
pub const REPEATS: usize = 5;

/// What a study compares: the entries of `R`, `Ω` (and `x`, `ẋ` on SE(3)).
trait Observe {
    fn observe(&self) -> Vec<f64>;
}

/// `R`'s entries, row by row.
fn rows(r: &SO3) -> Vec<f64> {
    r.matrix().transpose().iter().copied().collect()
}

impl Observe for State<SO3, 3> {
    fn observe(&self) -> Vec<f64> {
        let mut v = rows(self.attitude());
        v.extend(self.velocity.iter());
        v
    }
}

impl Observe for State<SE3, 6> {
    fn observe(&self) -> Vec<f64> {
        let mut v = rows(self.attitude());
        v.extend(self.angular_velocity().iter());
        v.extend(self.position().iter());
        v.extend(self.linear_velocity().iter());
        v
    }
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// One step of the estimate study.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct LocalError {
    pub h: f64,
    pub nodes: usize,
    pub step: usize,
    pub estimate: f64,
    pub truth: f64,
}

/// One tolerance of the tolerance study.
#[derive(Debug, Clone, Serialize)]
pub struct ToleranceRun {
    pub tol: f64,
    pub h: f64,
    /// The error at the horizon against the reference.
    pub error: f64,
    /// The run's own estimate of it (the sum of its local estimates).
    pub estimated_error: f64,
    pub wall_time_s: f64,
    /// `(n, steps with n nodes)`.
    pub nodes: Vec<(usize, usize)>,
    pub rejected_steps: usize,
    /// The fastest fixed `(h, n)` of the grid with an error at most `error`:
    /// `(h, n, error, time)`.
    pub best_fixed: Option<(f64, usize, f64, f64)>,
    pub failure: Option<String>,
}

/// A fixed `(h, n)` run of the tolerance study's grid.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct FixedRun {
    pub h: f64,
    pub nodes: usize,
    pub error: f64,
    pub wall_time_s: f64,
}

/// The local errors of every step of runs with `steps × nodes` to `t_end`.
fn local_errors<S, C, const D: usize>(
    make: &dyn Fn(StepSettings) -> Result<Integrator<S, C, D>>,
    steps: &[f64],
    nodes: &[usize],
    t_end: f64,
    tick: &mut dyn FnMut(),
) -> Result<Vec<LocalError>>
where
    S: GroupLagrangian<D>,
    C: GroupChart<S::Group, D>,
    State<ElementOf<S, D>, D>: Observe,
{
    let mut out = Vec::new();
    for &h in steps {
        for &n in nodes {
            tick();
            let run = || -> Result<Vec<LocalError>> {
                let mut integrator = make(StepSettings::new(h, n)?)?;
                let mut truth = make(StepSettings::new(h, n + TRUTH_EXTRA_NODES)?)?;
                let count = integrator.steps_until(t_end)?;
                let mut rows = Vec::with_capacity(count);
                for step in 0..count {
                    let s = *integrator.state();
                    truth.reset(s.time, s.configuration, s.velocity)?;
                    truth.step()?;
                    integrator.step()?;
                    rows.push(LocalError {
                        h,
                        nodes: n,
                        step,
                        estimate: integrator.error_estimate(),
                        truth: distance(&integrator.state().observe(), &truth.state().observe()),
                    });
                }
                Ok(rows)
            };
            // A setting the chart cannot follow (a long Cayley step) has no steps to show.
            if let Ok(rows) = run() {
                out.extend(rows);
            }
        }
    }
    Ok(out)
}

/// Runs `settings` to `t_end` [`REPEATS`] times: the final state, the fastest time, and
/// the integrator's accounts of the last run.
fn timed<S, C, const D: usize>(
    make: &dyn Fn(StepSettings) -> Result<Integrator<S, C, D>>,
    settings: StepSettings,
    t_end: f64,
) -> Result<(Vec<f64>, f64, Integrator<S, C, D>)>
where
    S: GroupLagrangian<D>,
    C: GroupChart<S::Group, D>,
    State<ElementOf<S, D>, D>: Observe,
{
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..REPEATS {
        let mut integrator = make(settings)?;
        let steps = integrator.steps_until(t_end)?;
        let start = Instant::now();
        for _ in 0..steps {
            integrator.step()?;
        }
        best = best.min(start.elapsed().as_secs_f64());
        last = Some(integrator);
    }
    let integrator = last.expect("REPEATS > 0");
    Ok((integrator.state().observe(), best, integrator))
}

/// The tolerance study: `--tol` runs (settings from `adaptive(tol)`), the fixed grid, and
/// the reference they are measured against, in the chart `make` uses (named `chart`).
#[allow(clippy::too_many_arguments)]
fn tolerance_runs<S, C, const D: usize>(
    make: &dyn Fn(StepSettings) -> Result<Integrator<S, C, D>>,
    chart: ChartKind,
    adaptive: &dyn Fn(f64) -> Result<StepSettings>,
    tols: &[f64],
    steps: &[f64],
    nodes: &[usize],
    t_end: f64,
    tick: &mut dyn FnMut(),
) -> Result<(String, Vec<ToleranceRun>, Vec<FixedRun>)>
where
    S: GroupLagrangian<D>,
    C: GroupChart<S::Group, D>,
    State<ElementOf<S, D>, D>: Observe,
{
    let reference_step = t_end / (t_end / 0.25).ceil().max(1.0);
    let reference = |n: usize| -> Result<Vec<f64>> {
        let mut integrator = make(StepSettings::new(reference_step, n)?)?;
        let steps = integrator.steps_until(t_end)?;
        integrator
            .run(steps, steps.max(1))
            .map_err(|source| CliError::Run {
                context: "reference run".into(),
                source,
            })?;
        Ok(integrator.state().observe())
    };
    let truth = reference(REFERENCE_NODES)?;
    let check = distance(&truth, &reference(REFERENCE_NODES + 4)?);
    let describe = format!(
        "a run with h = {reference_step}, n = {REFERENCE_NODES} ({chart} chart, exact matching; \
         differs from n = {} by {check:.1e} at T = {t_end})",
        REFERENCE_NODES + 4
    );
    let mut fixed = Vec::new();
    for &h in steps {
        for &n in nodes {
            tick();
            if let Ok((end, time, _)) = timed(make, StepSettings::new(h, n)?, t_end) {
                fixed.push(FixedRun {
                    h,
                    nodes: n,
                    error: distance(&end, &truth),
                    wall_time_s: time,
                });
            }
        }
    }
    let mut runs = Vec::new();
    for &tol in tols {
        tick();
        let settings = adaptive(tol)?;
        let mut run = ToleranceRun {
            tol,
            h: settings.step(),
            error: f64::NAN,
            estimated_error: f64::NAN,
            wall_time_s: f64::NAN,
            nodes: Vec::new(),
            rejected_steps: 0,
            best_fixed: None,
            failure: None,
        };
        match timed(make, settings, t_end) {
            Ok((end, time, integrator)) => {
                run.error = distance(&end, &truth);
                run.estimated_error = integrator.estimated_global_error();
                run.wall_time_s = time;
                run.nodes = integrator.nodes_used().collect();
                run.rejected_steps = integrator.statistics().rejected_steps;
                run.best_fixed = fixed
                    .iter()
                    .filter(|f| f.error <= run.error.max(check))
                    .min_by(|a, b| a.wall_time_s.total_cmp(&b.wall_time_s))
                    .map(|f| (f.h, f.nodes, f.error, f.wall_time_s));
            }
            Err(e) => run.failure = Some(e.to_string()),
        }
        runs.push(run);
    }
    Ok((describe, runs, fixed))
}

/// The estimate study of `problem`.
pub fn estimate_study(
    problem: &Problem,
    steps: &[f64],
    nodes: &[usize],
    tick: &mut dyn FnMut(),
) -> Result<Vec<LocalError>> {
    let chart = problem.settings.chart();
    let t_end = problem.t_end;
    match &problem.motion {
        Some(motion) => {
            let make = |s: StepSettings| motion.integrator(s.with_chart(chart));
            local_errors::<_, ChartKind, 6>(&make, steps, nodes, t_end, tick)
        }
        None => {
            let make = |s: StepSettings| problem.integrator(s.with_chart(chart));
            local_errors::<_, ChartKind, 3>(&make, steps, nodes, t_end, tick)
        }
    }
}

/// The tolerance study of `problem`; `adaptive(tol)` gives a `--tol` run's settings.
pub fn tolerance_study(
    problem: &Problem,
    adaptive: &dyn Fn(f64) -> Result<StepSettings>,
    tols: &[f64],
    steps: &[f64],
    nodes: &[usize],
    tick: &mut dyn FnMut(),
) -> Result<(String, Vec<ToleranceRun>, Vec<FixedRun>)> {
    let chart = problem.settings.chart();
    let t_end = problem.t_end;
    match &problem.motion {
        Some(motion) => {
            let make = |s: StepSettings| motion.integrator(s.with_chart(chart));
            tolerance_runs::<_, ChartKind, 6>(
                &make, chart, adaptive, tols, steps, nodes, t_end, tick,
            )
        }
        None => {
            let make = |s: StepSettings| problem.integrator(s.with_chart(chart));
            tolerance_runs::<_, ChartKind, 3>(
                &make, chart, adaptive, tols, steps, nodes, t_end, tick,
            )
        }
    }
}

/// `log10(estimate / truth)` over the steps above [`LOCAL_FLOOR`]: mean, standard
/// deviation, least, largest, and the share of steps within a factor 30 either way.
pub fn calibration(rows: &[LocalError]) -> Option<(f64, f64, f64, f64, f64, usize)> {
    let logs: Vec<f64> = rows
        .iter()
        .filter(|r| r.truth > LOCAL_FLOOR && r.estimate > 0.0)
        .map(|r| (r.estimate / r.truth).log10())
        .collect();
    if logs.is_empty() {
        return None;
    }
    let count = logs.len() as f64;
    let mean = logs.iter().sum::<f64>() / count;
    let sd = (logs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / count).sqrt();
    let lo = logs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = logs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let within = logs.iter().filter(|x| x.abs() <= 30f64.log10()).count() as f64 / count;
    Some((mean, sd, lo, hi, within, logs.len()))
}

/// The estimate study as a table: per `(h, n)`, then over all steps.
pub fn estimate_table(rows: &[LocalError]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Local error estimate against the true local error (the step with {TRUTH_EXTRA_NODES} \
         more nodes from the same state); log10(estimate / truth) over the steps whose true \
         error is above {LOCAL_FLOOR:.0e}:"
    );
    let _ = writeln!(
        out,
        "{:>6} {:>4} {:>6} {:>9} {:>9} {:>8} {:>8} {:>8}",
        "h", "n", "steps", "truth max", "est max", "mean", "sd", "range"
    );
    let mut keys: Vec<(f64, usize)> = rows.iter().map(|r| (r.h, r.nodes)).collect();
    keys.dedup();
    for (h, n) in keys {
        let group: Vec<LocalError> = rows
            .iter()
            .filter(|r| r.h == h && r.nodes == n)
            .copied()
            .collect();
        let truth = group.iter().map(|r| r.truth).fold(0.0, f64::max);
        let est = group.iter().map(|r| r.estimate).fold(0.0, f64::max);
        match calibration(&group) {
            Some((mean, sd, lo, hi, _, count)) => {
                let _ = writeln!(
                    out,
                    "{h:>6} {n:>4} {count:>6} {truth:>9.1e} {est:>9.1e} {mean:>+8.2} {sd:>8.2} {lo:>+5.1}..{hi:+.1}"
                );
            }
            None => {
                let _ = writeln!(
                    out,
                    "{h:>6} {n:>4} {:>6} {truth:>9.1e} {est:>9.1e}   (at rounding)",
                    0
                );
            }
        }
    }
    if let Some((mean, sd, lo, hi, within, count)) = calibration(rows) {
        let _ = writeln!(
            out,
            "all: {count} steps, mean {mean:+.2}, sd {sd:.2}, range {lo:+.2}..{hi:+.2} decades; \
             {:.0}% within a factor 30",
            100.0 * within
        );
    }
    out
}

/// The tolerance study as a table.
pub fn tolerance_table(describe: &str, runs: &[ToleranceRun]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "Reference: {describe}.");
    let _ = writeln!(
        out,
        "{:>7} {:>7} {:>9} {:>7} {:>9} {:>9} {:>22} {:>6}  nodes (n:steps)",
        "tol", "h", "error", "err/tol", "estimate", "time ms", "best fixed h, n, ms", "ratio"
    );
    for r in runs {
        if let Some(why) = &r.failure {
            let _ = writeln!(out, "{:>7.0e} failed: {why}", r.tol);
            continue;
        }
        let best = r
            .best_fixed
            .map_or("none as accurate".to_string(), |(h, n, _, t)| {
                format!("{h}, {n}, {:.3}", t * 1e3)
            });
        let ratio = r.best_fixed.map_or(String::new(), |(_, _, _, t)| {
            format!("{:.2}", r.wall_time_s / t)
        });
        let nodes: Vec<String> = r.nodes.iter().map(|(n, c)| format!("{n}:{c}")).collect();
        let _ = writeln!(
            out,
            "{:>7.0e} {:>7.4} {:>9.1e} {:>7.2} {:>9.1e} {:>9.3} {:>22} {:>6}  {}{}",
            r.tol,
            r.h,
            r.error,
            r.error / r.tol,
            r.estimated_error,
            r.wall_time_s * 1e3,
            best,
            ratio,
            nodes.join(" "),
            if r.rejected_steps > 0 {
                format!(" ({} redone)", r.rejected_steps)
            } else {
                String::new()
            }
        );
    }
    out
}

/// The estimate-vs-truth scatter, with the diagonal and the factor-30 band.
pub fn estimate_figure(title: &str, rows: &[LocalError]) -> Figure {
    let kept: Vec<&LocalError> = rows
        .iter()
        .filter(|r| r.truth > LOCAL_FLOOR && r.estimate > 0.0)
        .collect();
    let mut nodes: Vec<usize> = kept.iter().map(|r| r.nodes).collect();
    nodes.sort_unstable();
    nodes.dedup();
    let mut series: Vec<Series> = nodes
        .iter()
        .enumerate()
        .map(|(i, &n)| Series {
            label: format!("n = {n}"),
            points: kept
                .iter()
                .filter(|r| r.nodes == n)
                .map(|r| (r.truth, r.estimate))
                .collect(),
            style: Style::Markers,
            color: i,
        })
        .collect();
    let lo = kept.iter().map(|r| r.truth).fold(f64::INFINITY, f64::min);
    let hi = kept.iter().map(|r| r.truth).fold(0.0, f64::max);
    if lo < hi {
        series.push(Series {
            label: "estimate = truth".into(),
            points: vec![(lo, lo), (hi, hi)],
            style: Style::Line,
            color: 11,
        });
        series.push(Series {
            label: "30 × truth".into(),
            points: vec![(lo, lo * 30.0), (hi, hi * 30.0)],
            style: Style::DashedMarkers,
            color: 8,
        });
        series.push(Series {
            label: "truth / 30".into(),
            points: vec![(lo, lo / 30.0), (hi, hi / 30.0)],
            style: Style::DashedMarkers,
            color: 8,
        });
    }
    Figure {
        title: title.into(),
        x_label: "true local error (the step with 14 more nodes)".into(),
        y_label: "estimated local error".into(),
        x_log: true,
        y_log: true,
        series,
        hlines: Vec::new(),
    }
}

/// The default grid of steps (each divides the default horizon 10).
pub const DEFAULT_STEPS: [f64; 5] = [0.25, 0.5, 0.625, 1.0, 1.25];

/// `lgsvi converge --study estimate` (`estimate`) or `--study tolerance`.
pub fn run(options: crate::config::ConvergeOptions, estimate: bool) -> Result<()> {
    let tols = options.tols.clone();
    let steps_given = options.steps.clone();
    let range = options.nodes_range;
    let (problem, base) = Problem::resolve(options.base)?;
    if problem.wheels.is_some() {
        return Err(CliError::NotForSystem {
            flag: "converge",
            system: "gyrostat",
            applies: "rigid-body, heavy-top, se3-body and orbiting-body",
        });
    }
    let t_end = problem.t_end;
    let steps = steps_given.unwrap_or_else(|| DEFAULT_STEPS.to_vec());
    for &h in &steps {
        crate::problem::whole_steps(t_end, h).map_err(|e| CliError::ConfigValue {
            key: "steps",
            reason: e.to_string(),
        })?;
    }
    let [first, last] = range.unwrap_or(if estimate { [5, 12] } else { [4, 20] });
    let top = lgsvi_mechanics::MAX_NODES - TRUTH_EXTRA_NODES;
    if !(2 <= first && first <= last && last <= top) {
        return Err(CliError::ConfigValue {
            key: "nodes-range",
            reason: format!(
                "need 2 ≤ first ≤ last ≤ {top} (the truth takes {TRUTH_EXTRA_NODES} more nodes)"
            ),
        });
    }
    let nodes: Vec<usize> = (first..=last).collect();
    let tols = tols.unwrap_or_else(|| match base.tol {
        Some(tol) => vec![tol],
        None => (6..=13).map(|k| 10f64.powi(-k)).collect(),
    });
    let runs = if estimate {
        steps.len() * nodes.len()
    } else {
        steps.len() * nodes.len() + tols.len()
    };
    let progress = crate::progress_bar(runs as u64, "converge", "runs", problem.quiet);
    let mut tick = || progress.inc(1);
    let system = problem.description["system"]
        .as_str()
        .unwrap_or("system")
        .to_string();
    let (text, json, figure) = if estimate {
        let rows = estimate_study(&problem, &steps, &nodes, &mut tick)?;
        let figure = estimate_figure(
            &format!("{system}: local error estimate against the true local error"),
            &rows,
        );
        let json = serde_json::json!({
            "description": problem.description,
            "truth": format!("the step with {TRUTH_EXTRA_NODES} more nodes from the same state"),
            "calibration_log10": calibration(&rows),
            "steps": rows,
        });
        (estimate_table(&rows), json, figure)
    } else {
        let adaptive = |tol: f64| -> Result<StepSettings> {
            let mut o = base.clone();
            o.tol = Some(tol);
            crate::problem::step_settings(&o, t_end, problem.rate)
        };
        let (describe, runs, fixed) =
            tolerance_study(&problem, &adaptive, &tols, &steps, &nodes, &mut tick)?;
        let figure = tolerance_figure(&format!("{system}: --tol runs at T = {t_end}"), &runs);
        let json = serde_json::json!({
            "description": problem.description,
            "reference": describe,
            "runs": runs,
            "fixed": fixed,
        });
        (tolerance_table(&describe, &runs), json, figure)
    };
    progress.finish_and_clear();
    print!("{text}");
    if let Some(path) = &base.out {
        let mut body = serde_json::to_string_pretty(&json)?;
        body.push('\n');
        crate::files::write(path, body.as_bytes())?;
    }
    if let Some(plot) = &base.plot {
        crate::plot::save(&figure, plot)?;
    }
    Ok(())
}

/// Achieved error and the run's own estimate against the tolerance, with the window
/// `[tol/100, 10 tol]`.
pub fn tolerance_figure(title: &str, runs: &[ToleranceRun]) -> Figure {
    let ok: Vec<&ToleranceRun> = runs.iter().filter(|r| r.failure.is_none()).collect();
    let line = |label: &str, factor: f64, style: Style, color: usize| Series {
        label: label.into(),
        points: ok.iter().map(|r| (r.tol, r.tol * factor)).collect(),
        style,
        color,
    };
    Figure {
        title: title.into(),
        x_label: "tolerance".into(),
        y_label: "error at the horizon".into(),
        x_log: true,
        y_log: true,
        series: vec![
            Series {
                label: "error against the reference".into(),
                points: ok.iter().map(|r| (r.tol, r.error)).collect(),
                style: Style::LineMarkers,
                color: 0,
            },
            Series {
                label: "the run's own estimate".into(),
                points: ok.iter().map(|r| (r.tol, r.estimated_error)).collect(),
                style: Style::DashedMarkers,
                color: 1,
            },
            line("10 × tol", 10.0, Style::Line, 11),
            line("tol / 100", 0.01, Style::DashedMarkers, 8),
        ],
        hlines: Vec::new(),
    }
}
