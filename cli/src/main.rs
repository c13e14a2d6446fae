//! `lgsvi`: Lie group spectral variational integrators from the command line.
//!
//! `lgsvi` alone runs the main job, `lgsvi reproduce` on embedded defaults (the paper's
//! nine figures, their data and a report); `lgsvi simulate` runs one trajectory from flags
//! and/or a TOML config and writes JSON or CSV. Errors are one line on standard error and a non-zero exit.

mod bench;
mod cases;
mod config;
mod error;
mod files;
mod invariants;
mod output;
mod plot;
mod problem;
mod reproduce;
mod study;

use clap::{Parser, Subcommand};
use config::SimulateOptions;
use error::{CliError, Result};
use lgsvi_mechanics::{State, Trajectory};
use problem::Problem;
use std::process::ExitCode;
use std::time::Instant;

#[derive(Debug, Parser)]
#[command(
    name = "lgsvi",
    version,
    about = "Lie group spectral variational integrators (Hall & Leok) for rotating bodies",
    long_about = "Lie group spectral variational integrators (Hall & Leok) for rotating bodies on SO(3).\n\n\
                  Without a command, runs `lgsvi reproduce` on embedded defaults: the paper's nine figures \
                  (rigid body and 3D pendulum) with their data and a report, into ./lgsvi-reproduce."
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

/// Checks that a recorded state and its invariants are finite: a run whose numbers
/// overflow stops there, naming the step and the quantity, instead of writing `null` or
/// `inf`.
fn check_finite_state(step: usize, state: &State, energy: f64) -> Result<()> {
    let pi = state.spatial_momentum();
    let quantities: [(&str, &[f64]); 6] = [
        ("attitude R", &state.attitude().to_row_major()),
        ("angular velocity Ω", state.velocity.as_slice()),
        ("body momentum μ", state.momentum.as_slice()),
        ("energy", &[energy]),
        ("Casimir |μ|²", &[state.casimir()]),
        ("spatial momentum Rμ", pi.as_slice()),
    ];
    for (quantity, values) in quantities {
        if values.iter().any(|x| !x.is_finite()) {
            return Err(CliError::Overflow {
                step,
                time: state.time,
                quantity,
                values: format!("{values:?}"),
            });
        }
    }
    Ok(())
}

fn integrate(problem: &Problem) -> Result<Run> {
    let mut integrator = problem.integrator(problem.settings)?;
    let steps = integrator.steps_until(problem.t_end)?;
    let progress = progress_bar(steps as u64, "integrating", "steps", problem.quiet);
    let system = *integrator.system();
    let mut trajectory = Trajectory::default();
    let mut energies = Vec::new();
    let mut record = |k: usize, state: &State, iterations: usize| -> Result<()> {
        let energy = state.energy(&system);
        check_finite_state(k, state, energy)?;
        trajectory.states.push(*state);
        trajectory.newton_iterations.push(iterations);
        energies.push(energy);
        Ok(())
    };
    record(0, integrator.state(), 0)?;
    // The integration alone is timed: not the checks, the recording or the output.
    let mut wall_time = std::time::Duration::ZERO;
    for k in 1..=steps {
        let start = Instant::now();
        let iterations = integrator.step()?;
        wall_time += start.elapsed();
        let state = integrator.state();
        if k % problem.every == 0 || k == steps {
            record(k, state, iterations)?;
        } else {
            check_finite_state(k, state, state.energy(&system))?;
        }
        if k % 64 == 0 {
            progress.set_position(k as u64);
        }
    }
    progress.finish_and_clear();
    let stats = integrator.statistics();
    let mut description = problem.description.clone();
    description["settings"] =
        Problem::settings_json(&problem.settings, problem.t_end, problem.every);
    description["solution"] = "integrator".into();
    Ok(Run {
        trajectory,
        energies,
        wall_time_s: wall_time.as_secs_f64(),
        steps: stats.steps,
        newton_iterations: stats.newton_iterations,
        max_newton_iterations: stats.max_newton_iterations,
        description,
    })
}

/// The exact free-body solution at the times the integrator would record.
fn exact_run(problem: &Problem) -> Result<Run> {
    let body = problem.exact()?;
    let h = problem.settings.step();
    let steps = problem
        .integrator(problem.settings)?
        .steps_until(problem.t_end)?;
    let start = Instant::now();
    let mut trajectory = Trajectory::default();
    for k in (0..=steps).filter(|k| k % problem.every == 0 || *k == steps) {
        trajectory.states.push(body.state(k as f64 * h)?);
        trajectory.newton_iterations.push(0);
    }
    let wall_time_s = start.elapsed().as_secs_f64();
    let energies: Vec<f64> = trajectory
        .states
        .iter()
        .map(|s| s.energy(&problem.system))
        .collect();
    for (state, energy) in trajectory.states.iter().zip(&energies) {
        // The step the integrator would have reached at this time.
        check_finite_state((state.time / h).round() as usize, state, *energy)?;
    }
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
fn simulate(options: SimulateOptions) -> Result<(Run, SimulateOptions)> {
    let (problem, options) = Problem::resolve(options)?;
    let run = if options.exact {
        exact_run(&problem)?
    } else {
        integrate(&problem)?
    };
    Ok((run, options))
}

fn run_simulate(options: SimulateOptions) -> Result<()> {
    let (run, options) = simulate(options)?;
    let format = options.format.unwrap_or(config::Format::Json);
    let write = |out: &mut dyn std::io::Write| match format {
        config::Format::Json => output::write_json(&run, out),
        config::Format::Csv => output::write_csv(&run, out),
    };
    match &options.out {
        Some(path) => files::write_with(path, |out| write(out)),
        None => {
            let stdout = std::io::stdout();
            let mut out = std::io::BufWriter::new(stdout.lock());
            write(&mut out)
                .and_then(|()| std::io::Write::flush(&mut out))
                .map_err(CliError::Stdout)
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
        Err(error) => {
            eprintln!("error: {}", error.to_string().replace('\n', " "));
            ExitCode::FAILURE
        }
    }
}
