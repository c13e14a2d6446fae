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
use lgsvi_experiments::tolerance::{
    calibration, local_errors, tolerance_runs, LocalError, ToleranceRun, ToleranceStudy,
    LOCAL_FLOOR, TRUTH_EXTRA_NODES,
};
use lgsvi_experiments::Subject;
use lgsvi_mechanics::lie::ChartKind;
use lgsvi_mechanics::StepSettings;
use std::fmt::Write;

/// The estimate study of `problem`.
pub fn estimate_study(
    problem: &Problem,
    steps: &[f64],
    nodes: &[usize],
    tick: &mut dyn FnMut(),
) -> Result<Vec<LocalError>> {
    let chart = problem.settings.chart();
    let t_end = problem.t_end;
    Ok(match &problem.motion {
        Some(motion) => {
            let make = |s: StepSettings| motion.integrator(s.with_chart(chart));
            local_errors::<_, ChartKind, 6>(&make, steps, nodes, t_end, tick)
        }
        None => {
            let make = |s: StepSettings| Subject::integrator(problem, s.with_chart(chart));
            local_errors::<_, ChartKind, 3>(&make, steps, nodes, t_end, tick)
        }
    }?)
}

/// The tolerance study of `problem`; `settings` holds each `--tol` run's tolerance and
/// settings.
pub fn tolerance_study(
    problem: &Problem,
    settings: &[(f64, StepSettings)],
    steps: &[f64],
    nodes: &[usize],
    tick: &mut dyn FnMut(),
) -> Result<ToleranceStudy> {
    let chart = problem.settings.chart();
    let t_end = problem.t_end;
    Ok(match &problem.motion {
        Some(motion) => {
            let make = |s: StepSettings| motion.integrator(s.with_chart(chart));
            tolerance_runs::<_, ChartKind, 6>(&make, chart, settings, steps, nodes, t_end, tick)
        }
        None => {
            let make = |s: StepSettings| Subject::integrator(problem, s.with_chart(chart));
            tolerance_runs::<_, ChartKind, 3>(&make, chart, settings, steps, nodes, t_end, tick)
        }
    }?)
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
        let settings = tols
            .iter()
            .map(|&tol| {
                let mut o = base.clone();
                o.tol = Some(tol);
                Ok((tol, crate::problem::step_settings(&o, t_end, problem.rate)?))
            })
            .collect::<Result<Vec<_>>>()?;
        let ToleranceStudy {
            reference: describe,
            runs,
            fixed,
        } = tolerance_study(&problem, &settings, &steps, &nodes, &mut tick)?;
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
