//! `lgsvi`: Lie group spectral variational integrators from the command line.
//!
//! `lgsvi` alone runs the main job (the paper's free rigid body on embedded defaults, a
//! short report); `lgsvi simulate` runs one trajectory from flags and/or a TOML config and
//! writes JSON or CSV. Errors are one line on standard error and a non-zero exit.

mod bench;
mod config;
mod output;
mod plot;
mod problem;
mod reproduce;
mod study;

use clap::{Parser, Subcommand};
use config::SimulateOptions;
use lgsvi_mechanics::Trajectory;
use problem::Problem;
use std::process::ExitCode;
use std::time::Instant;

#[derive(Debug, Parser)]
#[command(
    name = "lgsvi",
    version,
    about = "Lie group spectral variational integrators (Hall & Leok) for rotating bodies",
    long_about = "Lie group spectral variational integrators (Hall & Leok) for rotating bodies.\n\n\
                  Without a command, runs the paper's free rigid body on embedded defaults and prints a report."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run one trajectory (or print the exact one, `--exact`) and write it as JSON or CSV.
    Simulate(SimulateOptions),
    /// n- and h-refinement studies: errors, fitted rates, a table and CSV/JSON.
    Converge(study::ConvergeOptions),
    /// Work-precision against DOP853, LGVI and splitting baselines (table, JSON, plots).
    Bench(bench::BenchOptions),
    /// Regenerate the paper's nine figures, their data and a report (the default command).
    Reproduce(reproduce::ReproduceOptions),
}

/// A finished run: the trajectory, the integration's wall time, and a description.
pub struct Run {
    pub trajectory: Trajectory,
    pub energies: Vec<f64>,
    pub wall_time_s: f64,
    pub steps: usize,
    pub newton_iterations: usize,
    pub max_newton_iterations: usize,
    pub description: serde_json::Value,
}

fn integrate(problem: &Problem) -> Result<Run, String> {
    let mut integrator = problem.integrator(problem.settings)?;
    let steps = integrator
        .steps_until(problem.t_end)
        .map_err(|e| e.to_string())?;
    let progress = progress_bar(steps as u64, "integrating", "steps", problem.quiet);
    let start = Instant::now();
    let trajectory = integrator
        .run_with_progress(steps, problem.every, |k| {
            if k % 64 == 0 {
                progress.set_position(k as u64);
            }
        })
        .map_err(|e| e.to_string())?;
    let wall_time_s = start.elapsed().as_secs_f64();
    progress.finish_and_clear();
    let energies = trajectory
        .states
        .iter()
        .map(|s| s.energy(integrator.system()))
        .collect();
    let stats = integrator.statistics();
    let mut description = problem.description.clone();
    description["settings"] =
        Problem::settings_json(&problem.settings, problem.t_end, problem.every);
    description["solution"] = "integrator".into();
    Ok(Run {
        trajectory,
        energies,
        wall_time_s,
        steps: stats.steps,
        newton_iterations: stats.newton_iterations,
        max_newton_iterations: stats.max_newton_iterations,
        description,
    })
}

/// The exact free-body solution at the times the integrator would record.
fn exact_run(problem: &Problem) -> Result<Run, String> {
    let body = problem.exact()?;
    let h = problem.settings.step();
    let steps = problem
        .integrator(problem.settings)?
        .steps_until(problem.t_end)
        .map_err(|e| e.to_string())?;
    let start = Instant::now();
    let mut trajectory = Trajectory::default();
    for k in (0..=steps).filter(|k| k % problem.every == 0 || *k == steps) {
        trajectory
            .states
            .push(body.state(k as f64 * h).map_err(|e| e.to_string())?);
        trajectory.newton_iterations.push(0);
    }
    let wall_time_s = start.elapsed().as_secs_f64();
    let energies = trajectory
        .states
        .iter()
        .map(|s| s.energy(&problem.system))
        .collect();
    let mut description = problem.description.clone();
    description["settings"] =
        Problem::settings_json(&problem.settings, problem.t_end, problem.every);
    description["solution"] = "exact (Jacobi elliptic functions)".into();
    description["regime"] = format!("{:?}", body.regime()).into();
    Ok(Run {
        trajectory,
        energies,
        wall_time_s,
        steps: 0,
        newton_iterations: 0,
        max_newton_iterations: 0,
        description,
    })
}

/// A progress bar on standard error, hidden for `--quiet`, for short jobs, or when standard
/// error is not a terminal (so files and pipes never receive control characters).
pub fn progress_bar(len: u64, message: &str, unit: &str, quiet: bool) -> indicatif::ProgressBar {
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

/// Resolves the options (config, flags, defaults) and runs.
fn simulate(options: SimulateOptions) -> Result<(Run, SimulateOptions), String> {
    let (problem, options) = Problem::resolve(options)?;
    let run = if options.exact {
        exact_run(&problem)?
    } else {
        integrate(&problem)?
    };
    Ok((run, options))
}

fn run_simulate(options: SimulateOptions) -> Result<(), String> {
    let (run, options) = simulate(options)?;
    let text = match options.format.unwrap_or(config::Format::Json) {
        config::Format::Json => output::json(&run),
        config::Format::Csv => output::csv(&run),
    };
    match &options.out {
        Some(path) => {
            std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
        }
        None => {
            use std::io::Write;
            std::io::stdout()
                .write_all(text.as_bytes())
                .map_err(|e| format!("cannot write to standard output: {e}"))
        }
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
                let _ = e.print();
                return ExitCode::SUCCESS;
            }
            // One line: clap's first line names the bad flag or value; the allowed values,
            // when clap lists them, are folded into it.
            let rendered = e.to_string();
            let mut line = rendered
                .lines()
                .next()
                .unwrap_or("error: invalid arguments")
                .to_string();
            if let Some(values) = rendered.lines().find(|l| l.contains("possible values")) {
                line.push(' ');
                line.push_str(values.trim());
            }
            eprintln!("{line}");
            return ExitCode::from(2);
        }
    };
    let result = match cli.command {
        Some(Command::Simulate(options)) => run_simulate(options),
        Some(Command::Converge(options)) => study::run_converge(options),
        Some(Command::Reproduce(options)) => reproduce::run(options),
        Some(Command::Bench(options)) => bench::run(options),
        None => reproduce::run(reproduce::ReproduceOptions::default()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {}", message.replace('\n', " "));
            ExitCode::FAILURE
        }
    }
}
