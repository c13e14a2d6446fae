//! `lgsvi`: Lie group spectral variational integrators from the command line.
//!
//! `lgsvi` alone runs the main job, `lgsvi reproduce` on embedded defaults (the paper's
//! nine figures, their data and a report); `lgsvi simulate` runs one trajectory from flags
//! and/or a TOML config and writes JSON or CSV. Errors are one line on standard error and a non-zero exit.

mod bench;
mod config;
mod error;
mod files;
mod linearize;
mod plot;
mod problem;
mod reproduce;
mod study;
mod tolerance;

use clap::{Parser, Subcommand};
use config::SimulateOptions;
use error::{CliError, Result};
use lgsvi_experiments::record::{record, record_exact, record_to_tolerance, Columns, Recording};
use lgsvi_mechanics::control::GroupLog;
use lgsvi_mechanics::{
    Checked, ElementOf, GroupChart, GroupLagrangian, Integrator, MechanicsError, StepSettings,
};
use lgsvi_reports::trajectory::{
    conservation_figure, settings_json, write_csv, write_json, Conserved,
};
use problem::Problem;
use std::process::ExitCode;

#[derive(Debug, Parser)]
#[command(
    name = "lgsvi",
    version,
    about = "Lie group spectral variational integrators (Hall & Leok) for rotating and moving bodies",
    long_about = "Lie group spectral variational integrators (Hall & Leok) for rotating bodies on SO(3) \
                  and moving ones on SE(3).\n\n\
                  Without a command, runs `lgsvi reproduce` on embedded defaults: the paper's nine figures \
                  (rigid body and 3D pendulum) with their data and a report, into ./lgsvi-reproduce \
                  (`lgsvi --quiet`, `lgsvi --out DIR` take reproduce's flags).",
    args_conflicts_with_subcommands = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// The main job's flags (`lgsvi` without a command is `lgsvi reproduce`).
    #[command(flatten)]
    reproduce: reproduce::ReproduceOptions,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run one trajectory (or print the exact one, `--exact`) and write it as JSON or CSV.
    Simulate(SimulateOptions),
    /// n- and h-refinement studies: errors, fitted rates, a table and CSV/JSON.
    Converge(config::ConvergeOptions),
    /// Work-precision against DOP853, LGVI and splitting baselines (table, JSON, plots).
    Bench(bench::BenchOptions),
    /// The exact linearisation A = ∂x₊/∂x, B = ∂x₊/∂u of one step from the initial state
    /// (simulate's system flags), as JSON.
    Linearize(linearize::LinearizeOptions),
    /// Regenerate the paper's nine figures, their data and a report (the default command).
    Reproduce(reproduce::ReproduceOptions),
}

/// A finished run and the inputs as given, for the output's `description`.
pub struct Run {
    pub recording: Recording,
    pub description: serde_json::Value,
}

/// The run the problem describes, recorded.
fn integrate(problem: &Problem) -> Result<Recording> {
    if let Some(wheels) = &problem.wheels {
        use problem::AnyGyrostat;
        macro_rules! run {
            ($craft:expr, $k:literal, $d:literal) => {
                integrate_with(problem, |settings| {
                    wheels.integrator::<$k, $d>($craft, settings, problem.attitude0, problem.omega0)
                })
            };
        }
        return match wheels.system {
            AnyGyrostat::One(craft) => run!(craft, 1, 4),
            AnyGyrostat::Two(craft) => run!(craft, 2, 5),
            AnyGyrostat::Three(craft) => run!(craft, 3, 6),
            AnyGyrostat::Four(craft) => run!(craft, 4, 7),
        };
    }
    match &problem.motion {
        None => integrate_with(problem, |settings| problem.integrator(settings)),
        Some(motion) => integrate_with(problem, |settings| Ok(motion.integrator(settings)?)),
    }
}

/// Runs to the problem's horizon with the integrators `make` builds (the problem's
/// settings, or a `--tol` run's tightened ones): unchecked, one run; checked, beside the
/// companion (`--check`), or until [`lgsvi_mechanics::ToleranceCheck`] accepts a run or
/// refuses (`--tol` without `--no-check`).
fn integrate_with<S, C, const D: usize>(
    problem: &Problem,
    make: impl Fn(StepSettings) -> Result<Integrator<S, C, D>>,
) -> Result<Recording>
where
    S: GroupLagrangian<D> + Copy,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: Columns<D> + GroupLog<D>,
{
    let steps = problem::whole_steps(problem.t_end, problem.settings.step())?;
    let bar = progress_bar(steps as u64, "integrating", "steps", problem.quiet);
    let mut progress = |k: usize| bar.set_position(k as u64);
    let (t_end, every) = (problem.t_end, problem.every);
    let recorded = match problem.check {
        problem::Check::None => record(make(problem.settings)?, t_end, every, &mut progress),
        problem::Check::Measure => {
            let runner = Checked::new(make(problem.settings)?)?;
            record(runner, t_end, every, &mut progress)
        }
        problem::Check::Tolerance(tol) => {
            return record_to_tolerance(make, problem.settings, tol, t_end, every, &mut progress)
                .map_err(|error| tolerance_not_checked(error, tol, problem));
        }
    };
    bar.finish_and_clear();
    Ok(recorded?)
}

/// A `--tol` run that no run met, with what to change.
fn tolerance_not_checked(error: CliError, tol: f64, problem: &Problem) -> CliError {
    match error.into_mechanics() {
        CliError::Mechanics(MechanicsError::ToleranceNotChecked {
            attempts,
            tightened,
            measured,
            time,
            step,
            at_floor,
            best,
            ..
        }) => CliError::ToleranceNotChecked {
            tol,
            attempts,
            tightened,
            measured,
            time,
            step,
            advice: if at_floor {
                format!(
                    "at the rounding of every step (4ε), this motion amplifies rounding \
                     errors to about that (the closest of the runs: {best:.1e}): ask for \
                     --tol {best:.0e} or more"
                )
            } else {
                format!(
                    "the motion amplifies each step's error: raise --tol, or shorten the \
                     step (--h {:?} or less)",
                    problem.settings.step() / 3.0
                )
            },
        },
        other => other,
    }
}

/// The exact free-body solution at the times the integrator would record, and the
/// motion's regime (for the output's description).
fn exact_run(problem: &Problem) -> Result<(Recording, String)> {
    let body = lgsvi_experiments::Subject::exact(problem).ok_or(CliError::NoExactSolution)??;
    let steps = problem
        .integrator(problem.settings)?
        .steps_until(problem.t_end)?;
    let h = problem.settings.step();
    let recording = record_exact(&body, &problem.system, h, steps, problem.every)?;
    Ok((recording, format!("{:?}", body.regime())))
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
    let (recording, regime) = if options.exact {
        let (recording, regime) = exact_run(&problem)?;
        (recording, Some(regime))
    } else {
        let recording = integrate(&problem).map_err(|error| match error.into_mechanics() {
            CliError::Mechanics(lgsvi_mechanics::MechanicsError::ToleranceNotMet {
                step,
                time,
                estimate,
                budget,
                nodes,
                ..
            }) => CliError::ToleranceNotMet {
                step,
                time,
                estimate,
                budget,
                nodes,
                shorter: problem.settings.step() / 10.0,
            },
            other => other,
        })?;
        (recording, None)
    };
    let mut description = problem.description.clone();
    description["settings"] = settings_json(&problem.settings, problem.t_end, problem.every);
    match regime {
        Some(regime) => {
            description["solution"] = "exact (Jacobi elliptic functions)".into();
            description["regime"] = regime.into();
        }
        None => description["solution"] = "integrator".into(),
    }
    let run = Run {
        recording,
        description,
    };
    if let Some(warning) = run
        .recording
        .estimates
        .as_ref()
        .and_then(|e| estimate_warning(e.global))
    {
        eprintln!("{warning}");
    }
    Ok((run, options))
}

/// Refuses outputs of one run that land on one file (`--out p.svg --plot p`).
fn check_outputs(options: &SimulateOptions) -> Result<()> {
    let mut outputs = Vec::new();
    if let Some(out) = &options.out {
        outputs.push(("--out", out.clone()));
    }
    if let Some(base) = &options.plot {
        let (svg, png) = plot::plot_paths(base);
        outputs.push(("--plot", svg));
        outputs.push(("--plot", png));
    }
    files::check_distinct(&outputs)
}

/// The attitude's scale (`R`'s entries are at most 1), against which a run's estimated
/// error is read: past [`ESTIMATE_WARNING`] of it, the run is not the motion to the
/// digits a user of this integrator expects, and says so.
const ESTIMATE_WARNING: f64 = 1e-6;

/// The one-line warning of a run whose estimated error exceeds [`ESTIMATE_WARNING`].
fn estimate_warning(estimated: f64) -> Option<String> {
    (estimated > ESTIMATE_WARNING).then(|| {
        format!(
            "warning: the run's estimated error {estimated:.1e} exceeds {ESTIMATE_WARNING:e} of \
             the attitude's scale: shorten --h, add --nodes, or give --tol"
        )
    })
}

fn run_simulate(options: SimulateOptions) -> Result<()> {
    check_outputs(&options)?;
    let (run, options) = simulate(options)?;
    if let Some(base) = &options.plot {
        let name = run.description["system"]
            .as_str()
            .unwrap_or("run")
            .to_string();
        let conserved = match name.as_str() {
            "orbiting-body" => Conserved::AngularAboutOrigin,
            "heavy-top" => match run.description["gravity_direction"].as_array() {
                Some(d) if d.len() == 3 => Conserved::Along(nalgebra::Vector3::from_iterator(
                    d.iter().map(|x| x.as_f64().unwrap_or(f64::NAN)),
                )),
                _ => Conserved::Spatial,
            },
            _ => Conserved::Spatial,
        };
        let figure = conservation_figure(&run.recording, &name, conserved);
        plot::save(&figure, base)?;
    }
    let format = options.format.unwrap_or(config::Format::Json);
    let write = |out: &mut dyn std::io::Write| match format {
        config::Format::Json => write_json(&run.recording, &run.description, out),
        config::Format::Csv => write_csv(&run.recording, out),
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
        Some(Command::Converge(options)) => {
            check_outputs(&options.base).and_then(|()| study::run_converge(options))
        }
        Some(Command::Reproduce(options)) => reproduce::run(options),
        Some(Command::Bench(options)) => bench::run(options),
        Some(Command::Linearize(options)) => linearize::run(options),
        None => reproduce::run(cli.reproduce),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {}", error.to_string().replace('\n', " "));
            ExitCode::FAILURE
        }
    }
}
