//! `lgsvi converge`: the convergence studies of `lgsvi_experiments::convergence` on the
//! problem the flags describe, printed as a table and written as JSON or CSV.

use crate::config::{node_count, node_range, positive_step, ConvergeOptions, Format, StudyKind};
use crate::error::{CliError, Result};
use crate::problem::{whole_steps, Problem};
use lgsvi_experiments::convergence::{study, Reference, Refinement, MAX_CURVE_SAMPLES};
use lgsvi_reports::convergence::{csv, table};

/// `lgsvi converge`.
pub fn run_converge(options: ConvergeOptions) -> Result<()> {
    let mut options = options;
    if let Some(path) = options.base.config.clone() {
        if let (_, Some(table)) = crate::config::read_config_table(&path, "converge")? {
            let base = std::mem::take(&mut options.base);
            options = crate::config::overlaid(table, &options, &path, "[converge] ")?;
            options.base = base;
        }
    }
    let base = &options.base;
    let measures = "converge measures every run's error against a reference itself";
    let exact = "converge always measures against the exact solution when there is one";
    crate::error::refuse_simulate_only(&[
        ("--check", base.check, measures),
        ("--no-check", base.no_check, measures),
        ("--exact", base.exact, exact),
        (
            "--every",
            base.every.is_some(),
            "converge measures every step",
        ),
        (
            "--stop-when",
            base.stop_when.is_some(),
            "converge runs every setting to the same end",
        ),
        (
            "--settle-when",
            base.settle_when.is_some(),
            "converge measures errors, not settling times",
        ),
        (
            "--target-quaternion",
            base.target_quaternion.is_some() && base.attitude_gain.is_none(),
            "without --attitude-gain the target is what --stop-when and --settle-when's \
             `error` is measured from, and converge watches neither",
        ),
        (
            "--sample-period",
            base.sample_period.is_some(),
            "converge runs steps of many lengths, and a sampled law needs its period to be \
             a whole number of each (not built; the continuous law converges)",
        ),
    ])?;
    if let Some(samples) = options.curve_samples {
        if !(1..=MAX_CURVE_SAMPLES).contains(&samples) {
            return Err(CliError::invalid(
                "--curve-samples",
                samples,
                format!("from 1 (no curve check) to {MAX_CURVE_SAMPLES}"),
            ));
        }
    }
    let kind = options.study.unwrap_or(StudyKind::Both);
    let (problem, base) = Problem::resolve(std::mem::take(&mut options.base))?;
    if matches!(kind, StudyKind::Estimate | StudyKind::Tolerance) {
        let estimate = kind == StudyKind::Estimate;
        return crate::tolerance::run(&options, problem, base, estimate);
    }
    if problem.scenario.motion.is_some() || problem.scenario.wheels.is_some() {
        return Err(CliError::NotForSystem {
            flag: "converge",
            system: problem.name,
            applies: "the SO(3) systems (rigid-body, heavy-top) for --study nodes, step and \
                 both; --study estimate and tolerance run every system"
                .into(),
        });
    }
    let [first, last] = options.nodes_range.unwrap_or([2, 16]);
    // Values from a config file did not pass the flags' parsers.
    if let Some([a, b]) = options.nodes_range {
        node_range(&format!("{a}..{b}")).map_err(|reason| CliError::ConfigValue {
            key: "nodes-range",
            reason,
        })?;
    }
    for h in options.steps.iter().flatten() {
        positive_step(&h.to_string()).map_err(|reason| CliError::ConfigValue {
            key: "steps",
            reason,
        })?;
        whole_steps(problem.t_end, *h).map_err(|e| CliError::ConfigValue {
            key: "steps",
            reason: e.to_string(),
        })?;
    }
    for n in options.step_nodes.iter().flatten() {
        node_count(&n.to_string()).map_err(|reason| CliError::ConfigValue {
            key: "step-nodes",
            reason,
        })?;
    }
    let nodes: Vec<usize> = if kind == StudyKind::Step {
        Vec::new()
    } else {
        (first..=last).collect()
    };
    let steps = if kind == StudyKind::Nodes {
        Vec::new()
    } else {
        options
            .steps
            .unwrap_or_else(|| vec![1.0, 0.5, 0.25, 0.125, 0.0625])
    };
    let step_nodes = if kind == StudyKind::Nodes {
        Vec::new()
    } else {
        options.step_nodes.unwrap_or_else(|| vec![2, 3, 4, 5])
    };
    let curve_samples = options.curve_samples.unwrap_or(8).max(1);
    let t_end = problem.t_end;
    let progress = crate::progress::bar(
        (nodes.len() + steps.len() * step_nodes.len()) as u64,
        "converge",
        "runs",
        problem.quiet,
    );
    let reference = Reference::for_subject(&problem.scenario, t_end)?;
    let refinement = Refinement {
        h: problem.settings().h(),
        nodes,
        steps,
        step_nodes,
        t_end,
        curve_samples,
    };
    let result = study(&problem.scenario, &reference, &refinement, || {
        progress.inc(1)
    })?;
    progress.finish_and_clear();
    print!("{}", table(&result));
    if let Some(path) = &base.out {
        let text = match base.format.unwrap_or(Format::Json) {
            Format::Json => {
                let mut t = serde_json::to_string_pretty(&serde_json::json!({
                    "description": problem.description,
                    "study": result,
                }))?;
                t.push('\n');
                t
            }
            Format::Csv => {
                let mut t = csv(&result.nodes_refinement.iter().collect::<Vec<_>>(), "nodes");
                let h_rows = csv(&result.step_refinement.iter().collect::<Vec<_>>(), "step");
                t.push_str(h_rows.split_once('\n').map(|(_, rest)| rest).unwrap_or(""));
                t
            }
        };
        crate::files::write(path, text.as_bytes())?;
    }
    Ok(())
}
