//! `lgsvi linearize`: the exact linearisation of one step from simulate's initial state,
//! as JSON (`lgsvi_reports::linearization`: `a`, `b` as lists of rows, the coordinates in
//! words, the states before and after the step).

use crate::config::SimulateOptions;
use crate::error::{CliError, Result};
use crate::files;
use crate::problem::Problem;
use clap::Args;
use lgsvi_reports::linearization::linearize;
use lgsvi_reports::trajectory::settings_json;
use serde_json::json;

/// The options of `lgsvi linearize`: simulate's system, initial state and step flags.
#[derive(Debug, Args)]
pub struct LinearizeOptions {
    #[command(flatten)]
    pub base: SimulateOptions,
    /// Write the matrices in momentum coordinates (θ, δμ) instead of (θ, ω).
    #[arg(long)]
    pub momentum: bool,
}

/// Runs `lgsvi linearize`.
pub fn run(options: LinearizeOptions) -> Result<()> {
    let base = &options.base;
    for (flag, given, why) in [
        (
            "--t-end",
            base.t_end.is_some(),
            "linearize takes one step of --h",
        ),
        ("--every", base.every.is_some(), "linearize takes one step"),
        ("--format", base.format.is_some(), "linearize writes JSON"),
        ("--plot", base.plot.is_some(), "linearize draws nothing"),
        (
            "--exact",
            base.exact,
            "linearize linearises the integrator's step",
        ),
        (
            "--check",
            base.check,
            "linearize takes one step and measures nothing",
        ),
        (
            "--no-check",
            base.no_check,
            "linearize takes one step of fixed --h and --nodes",
        ),
        (
            "--tol",
            base.tol.is_some(),
            "linearize takes one step of fixed --h and --nodes",
        ),
    ] {
        if given {
            return Err(CliError::SimulateOnly { flag, why });
        }
    }
    let out = base.out.clone();
    let momentum = options.momentum;
    let (problem, _) = Problem::resolve(options.base)?;
    let mut report = json!({
        "command": "linearize",
        "description": problem.description,
        "settings": settings_json(&problem.settings(), problem.settings().step(), 1),
        "coordinates_kind": if momentum { "momentum" } else { "velocity" },
    });
    linearize(&problem.scenario, problem.settings(), momentum, &mut report)?;
    let text = serde_json::to_string_pretty(&report)? + "\n";
    match &out {
        Some(path) => files::write(path, text.as_bytes()),
        None => {
            use std::io::Write;
            let stdout = std::io::stdout();
            let mut lock = stdout.lock();
            lock.write_all(text.as_bytes())
                .and_then(|()| lock.flush())
                .map_err(CliError::Stdout)
        }
    }
}
