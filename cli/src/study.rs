//! `lgsvi converge`: the convergence studies of `lgsvi_experiments::convergence` on the
//! problem the flags describe, printed as a table and written as JSON or CSV.

use crate::config::{node_count, node_range, positive_step, ConvergeOptions, Format, StudyKind};
use crate::error::{CliError, Result};
use crate::problem::{whole_steps, Problem};
use lgsvi_experiments::convergence::{
    study, Measurement, Reference, Refinement, Study, MAX_CURVE_SAMPLES,
};
use lgsvi_experiments::fit::FIT_CEILING;
use std::fmt::Write;

fn fmt_err(e: f64) -> String {
    if e.is_finite() {
        format!("{e:9.2e}")
    } else {
        format!("{:>9}", "failed")
    }
}

/// The printed table.
pub fn table(study: &Study) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "errors against {}", study.reference);
    let header = "    n  degree        h  steps   ‖R−Rref‖   |Ω−Ωref|    curve    energy   Newton";
    let row = |out: &mut String, m: &Measurement| {
        let _ = writeln!(
            out,
            "{:5} {:7} {:8} {:6} {}  {}  {}  {}  {:7}{}",
            m.nodes,
            m.degree,
            m.h,
            m.steps,
            fmt_err(m.error_r),
            fmt_err(m.error_omega),
            fmt_err(m.error_curve),
            fmt_err(m.energy_error),
            m.newton_iterations,
            m.failure
                .as_ref()
                .map(|f| format!("  ({f})"))
                .unwrap_or_default()
        );
    };
    if let Some(first) = study.nodes_refinement.first() {
        let _ = writeln!(
            out,
            "\nn-refinement: {} chart, {} matching, h = {}, T = {}",
            first.chart, first.matching, first.h, first.t_end
        );
        let _ = writeln!(out, "{header}");
        for m in &study.nodes_refinement {
            row(&mut out, m);
        }
        for (_, _, _, factor) in &study.geometric_factors {
            match factor {
                Some(q) => {
                    let _ = writeln!(
                        out,
                        "fitted: the error falls by ×{q:.1} per node (asymptotic errors: below {FIT_CEILING}, above the rounding floor)"
                    );
                }
                None => {
                    let _ = writeln!(out, "fitted: too few asymptotic errors to fit");
                }
            }
        }
    }
    if let Some(first) = study.step_refinement.first() {
        let _ = writeln!(
            out,
            "\nh-refinement: {} chart, {} matching, T = {}",
            first.chart, first.matching, first.t_end
        );
        let _ = writeln!(out, "{header}");
        for m in &study.step_refinement {
            row(&mut out, m);
        }
        for (_, _, n, order) in &study.orders {
            let _ = match order {
                Some(p) => writeln!(
                    out,
                    "fitted: n = {n} (degree {}): order {p:.2} (nodal superconvergence predicts {})",
                    n - 1,
                    2 * (n - 1)
                ),
                None => writeln!(out, "fitted: n = {n}: too few errors above the floor"),
            };
        }
    }
    out
}

/// The measurements as CSV.
pub fn csv(rows: &[&Measurement], study: &str) -> String {
    let mut out = String::from(
        "study,chart,matching,nodes,degree,h,steps,t_end,error_R,error_omega,error_curve,energy_error,momentum_drift,newton_iterations,wall_time_s,failure\n",
    );
    for m in rows {
        let _ = writeln!(
            out,
            "{study},{},{},{},{},{},{},{},{:e},{:e},{:e},{:e},{:e},{},{},{}",
            m.chart,
            m.matching,
            m.nodes,
            m.degree,
            m.h,
            m.steps,
            m.t_end,
            m.error_r,
            m.error_omega,
            m.error_curve,
            m.energy_error,
            m.momentum_drift,
            m.newton_iterations,
            m.wall_time_s,
            m.failure.as_deref().unwrap_or("").replace(',', ";")
        );
    }
    out
}

/// `lgsvi converge`.
pub fn run_converge(options: ConvergeOptions) -> Result<()> {
    let mut options = options;
    if let Some(path) = options.base.config.clone() {
        let (_, table) = crate::config::read_config_table(&path)?;
        if let Some(table) = table {
            let file: ConvergeOptions =
                crate::config::deserialize_naming_the_key(table, &path, "[converge] ")?;
            options.study = options.study.or(file.study);
            options.nodes_range = options.nodes_range.or(file.nodes_range);
            options.steps = options.steps.or(file.steps);
            options.step_nodes = options.step_nodes.or(file.step_nodes);
            options.curve_samples = options.curve_samples.or(file.curve_samples);
            options.tols = options.tols.or(file.tols);
        }
    }
    if options.base.no_check || options.base.check {
        return Err(CliError::SimulateOnly {
            flag: if options.base.check {
                "--check"
            } else {
                "--no-check"
            },
            why: "converge measures every run's error against a reference itself",
        });
    }
    if options.base.exact {
        return Err(CliError::SimulateOnly {
            flag: "--exact",
            why: "converge always measures against the exact solution when there is one",
        });
    }
    if options.base.every.is_some() {
        return Err(CliError::SimulateOnly {
            flag: "--every",
            why: "converge measures every step",
        });
    }
    if let Some(samples) = options.curve_samples {
        if !(1..=MAX_CURVE_SAMPLES).contains(&samples) {
            return Err(CliError::Invalid {
                flag: "--curve-samples",
                value: samples.to_string(),
                reason: format!("from 1 (no curve check) to {MAX_CURVE_SAMPLES}"),
            });
        }
    }
    let kind = options.study.unwrap_or(StudyKind::Both);
    if matches!(kind, StudyKind::Estimate | StudyKind::Tolerance) {
        return crate::tolerance::run(options, kind == StudyKind::Estimate);
    }
    let (problem, base) = Problem::resolve(options.base)?;
    if problem.wheels.is_some() {
        return Err(CliError::NotForSystem {
            flag: "converge",
            system: "gyrostat",
            applies: "rigid-body, heavy-top, se3-body and orbiting-body",
        });
    }
    if problem.motion.is_some() {
        return Err(CliError::NotForSystem {
            flag: "converge",
            system: if base.system() == crate::config::SystemKind::OrbitingBody {
                "orbiting-body"
            } else {
                "se3-body"
            },
            applies: "the SO(3) systems (rigid-body, heavy-top) for --study nodes, step and \
                 both; --study estimate and tolerance run every system",
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
    let progress = crate::progress_bar(
        (nodes.len() + steps.len() * step_nodes.len()) as u64,
        "converge",
        "runs",
        problem.quiet,
    );
    let reference = Reference::for_subject(&problem, t_end)?;
    let refinement = Refinement {
        h: problem.settings.step(),
        nodes,
        steps,
        step_nodes,
        t_end,
        curve_samples,
    };
    let result = study(&problem, &reference, &refinement, || progress.inc(1))?;
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
