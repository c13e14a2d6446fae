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

/// The options of `lgsvi linearize`: simulate's system, initial state and step flags (its
/// run, output and check flags are not listed in the help, and refused if given).
#[derive(Debug, Args)]
#[command(
    mut_arg("t_end", |a| a.hide(true)),
    mut_arg("every", |a| a.hide(true)),
    mut_arg("format", |a| a.hide(true)),
    mut_arg("plot", |a| a.hide(true)),
    mut_arg("exact", |a| a.hide(true)),
    mut_arg("check", |a| a.hide(true)),
    mut_arg("no_check", |a| a.hide(true)),
    mut_arg("tol", |a| a.hide(true)),
    mut_arg("stop_when", |a| a.hide(true)),
    mut_arg("settle_when", |a| a.hide(true))
)]
pub struct LinearizeOptions {
    #[command(flatten)]
    pub base: SimulateOptions,
    /// Write the matrices in momentum coordinates (θ, δμ) instead of (θ, ω).
    #[arg(long)]
    pub momentum: bool,
}

/// Runs `lgsvi linearize`.
pub fn run(options: LinearizeOptions) -> Result<()> {
    let b = &options.base;
    let fixed = "linearize takes one step of fixed --h and --nodes";
    let measures = "linearize takes one step and measures nothing";
    let integrator = "linearize linearises the integrator's step";
    crate::error::refuse_simulate_only(&[
        (
            "--t-end",
            b.t_end.is_some(),
            "linearize takes one step of --h",
        ),
        ("--every", b.every.is_some(), "linearize takes one step"),
        ("--format", b.format.is_some(), "linearize writes JSON"),
        ("--plot", b.plot.is_some(), "linearize draws nothing"),
        ("--exact", b.exact, integrator),
        ("--check", b.check, measures),
        ("--no-check", b.no_check, fixed),
        ("--tol", b.tol.is_some(), fixed),
        (
            "--stop-when",
            b.stop_when.is_some(),
            "linearize takes one step",
        ),
        (
            "--settle-when",
            b.settle_when.is_some(),
            "linearize takes one step",
        ),
        (
            "--target-quaternion",
            b.target_quaternion.is_some() && b.attitude_gain.is_none(),
            "without --attitude-gain the target is what --stop-when and --settle-when's \
             `error` is measured from, and linearize takes one step",
        ),
        (
            "--sample-period",
            b.sample_period.is_some(),
            "linearize gives the open step's B, the derivative by a held input: a sampled \
             law's torque is such an input (drop --sample-period for the continuous law's \
             closed-loop step)",
        ),
    ])?;
    let out = b.out.clone();
    let momentum = options.momentum;
    let (problem, _) = Problem::resolve(options.base)?;
    let mut report = json!({
        "command": "linearize",
        "description": problem.description,
        "settings": settings_json(&problem.settings(), problem.settings().h(), 1),
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
