//! `lgsvi converge --study estimate | tolerance`: the error-estimate calibration and the
//! tolerance study of `lgsvi_experiments::tolerance` on the problem the flags describe (SO(3),
//! SE(3) or a gyrostat), printed and written through `lgsvi_reports::tolerance`.

use crate::error::{CliError, Result};
use crate::problem::Problem;
use lgsvi_experiments::tolerance::{calibration, ToleranceStudy, TRUTH_EXTRA_NODES};
use lgsvi_reports::tolerance::{
    estimate_figure, estimate_table, tolerance_figure, tolerance_table,
};

/// The default grid of steps (each divides the default horizon 10).
pub const DEFAULT_STEPS: [f64; 5] = [0.25, 0.5, 0.625, 1.0, 1.25];

/// `lgsvi converge --study estimate` (`estimate`) or `--study tolerance`.
pub fn run(
    options: &crate::config::ConvergeOptions,
    problem: Problem,
    base: crate::config::SimulateOptions,
    estimate: bool,
) -> Result<()> {
    let (tols, steps_given, range) = (
        options.tols.clone(),
        options.steps.clone(),
        options.nodes_range,
    );
    let t_end = problem.t_end;
    let chart = problem.settings().chart();
    let steps = steps_given.unwrap_or_else(|| DEFAULT_STEPS.to_vec());
    for &h in &steps {
        crate::problem::whole_steps(t_end, h).map_err(|e| CliError::ConfigValue {
            key: "steps",
            reason: e.to_string(),
        })?;
    }
    let [first, last] = range.unwrap_or(if estimate { [5, 12] } else { [4, 20] });
    let top = lgsvi_mechanics::settings::MAX_NODES - TRUTH_EXTRA_NODES;
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
    let progress = crate::progress::bar(runs as u64, "converge", "runs", problem.quiet);
    let mut tick = || progress.inc(1);
    let system = problem.name;
    let (text, json, figure) = if estimate {
        let rows = problem
            .scenario
            .local_errors(chart, &steps, &nodes, t_end, &mut tick)?;
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
                Ok((
                    tol,
                    crate::problem::step_settings(&o, t_end, problem.scenario.rate()?)?,
                ))
            })
            .collect::<Result<Vec<_>>>()?;
        let ToleranceStudy {
            reference: describe,
            runs,
            fixed,
        } = problem
            .scenario
            .tolerance_runs(chart, &settings, &steps, &nodes, t_end, &mut tick)?;
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
