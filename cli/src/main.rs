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
mod manoeuvre;
mod montecarlo;
mod optimize;
mod plot;
mod problem;
mod progress;
mod reproduce;
mod study;
mod tolerance;

use clap::{Parser, Subcommand};
use config::SimulateOptions;
use error::{CliError, Result};
use lgsvi_experiments::record::Recording;
use lgsvi_mechanics::MechanicsError;
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
    /// (simulate's system flags), and P = ∂x₊/∂p in the inertia entries (and the mass, an
    /// orbiting body's gravitational parameter or the wheels' inertias), as JSON.
    Linearize(linearize::LinearizeOptions),
    /// Regenerate the paper's nine figures, their data and a report (the default command).
    Reproduce(reproduce::ReproduceOptions),
    /// Monte Carlo dispersion analysis: many runs of simulate's system with dispersed
    /// inertia, start, torque, mass and wheels, in parallel; members.csv (one row per
    /// member) and summary.json (final-state statistics, stop and settling times, every
    /// failure with its seed and cause). Exit status 3 when members failed.
    Montecarlo(Box<montecarlo::MontecarloOptions>),
    /// A rigid body's slew of least energy in a fixed time (or of least time,
    /// `--cost time`), torques bounded per axis; a heavy top's (`--gravity`) or a
    /// spacecraft's by its three reaction wheels (`--wheels`); a body in space's manoeuvre by
    /// a body wrench (`--space`): sequential quadratic programming with lgsvi's step as the
    /// dynamics; JSON with the inputs and states, figures with --plot.
    Optimize(optimize::OptimizeOptions),
    /// Print this command line's reference (every command's help) as Markdown: the
    /// source of docs/reference/cli.md.
    #[command(hide = true)]
    CliReference,
}

/// Every command's long help as Markdown, at a fixed width (docs/reference/cli.md, kept in
/// sync by a test).
fn cli_reference() -> String {
    use clap::CommandFactory;
    let mut command = Cli::command().term_width(100).max_term_width(100);
    command.build();
    let mut text = String::from(
        "# Command-line reference\n\n\
         Every command of `lgsvi` with its flags, as `lgsvi COMMAND --help` prints them. This \
         page is generated (`lgsvi cli-reference > docs/reference/cli.md`) and a test keeps it \
         in sync with the binary.\n",
    );
    let mut section = |title: String, command: &mut clap::Command| {
        let help = command.render_long_help().to_string();
        let help: Vec<&str> = help.lines().map(str::trim_end).collect();
        text.push_str(&format!(
            "\n## {title}\n\n```text\n{}\n```\n",
            help.join("\n")
        ));
    };
    section("lgsvi".into(), &mut command.clone());
    let names: Vec<String> = command
        .get_subcommands()
        .filter(|c| !c.is_hide_set() && c.get_name() != "help")
        .map(|c| c.get_name().to_string())
        .collect();
    for name in names {
        let sub = command
            .find_subcommand_mut(&name)
            .expect("a listed command");
        section(format!("lgsvi {name}"), sub);
    }
    text
}

/// The run the problem describes, recorded; a `--tol` run that failed says what to change.
fn integrate(problem: &Problem) -> Result<Recording> {
    let settings = problem.settings();
    let steps = problem::whole_steps(problem.t_end, settings.h())?;
    let bar = progress::bar(steps as u64, "integrating", "steps", problem.quiet);
    let mut progress = |k: usize| bar.set_position(k as u64);
    let (t_end, every, check) = (problem.t_end, problem.every, problem.check);
    let recorded =
        problem
            .scenario
            .record(settings, check, t_end, every, &problem.watch, &mut progress);
    bar.finish_and_clear();
    recorded.map_err(|error| match CliError::from(error).into_mechanics() {
        CliError::Experiment(lgsvi_experiments::ExperimentError::Stop { condition, reason }) => {
            problem.condition_error(condition, reason)
        }
        CliError::Mechanics(
            source @ (MechanicsError::ToleranceNotMet { .. }
            | MechanicsError::ToleranceNotChecked { .. }),
        ) => CliError::Tolerance {
            source,
            h: settings.h(),
        },
        other => other,
    })
}

/// Where a stop condition ended the run, as JSON: the condition, the crossing's time and
/// the state there (the attitude row-major, the rates; the translation or wheels).
fn stopped_json(stopped: &lgsvi_experiments::record::Stopped) -> serde_json::Value {
    let r = stopped.state.attitude().to_row_major();
    let mut json = serde_json::json!({
        "condition": stopped.condition,
        "t": stopped.time,
        "R": r,
        "omega": stopped.state.velocity.as_slice(),
    });
    if let Some(motion) = &stopped.motion {
        json["position"] = motion.position.as_slice().into();
        json["velocity"] = motion.velocity.as_slice().into();
    }
    if let Some(wheels) = &stopped.wheels {
        json["wheel_speeds"] = wheels.speeds.clone().into();
    }
    json
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

/// The condition number of the inertia from which a run warns that its accuracy is
/// limited by it: the velocity is recovered from the momentum to `ε` times it (`2e-10`),
/// and the steps' errors along the thin axis grow by up to that factor.
const CONDITIONING_WARNING: f64 = 1e6;

/// The one-line warning of a body whose principal moments span more than
/// [`CONDITIONING_WARNING`] (a thin rod).
fn conditioning_warning(inertia: &lgsvi_mechanics::Inertia) -> Option<String> {
    let (least, most) = problem::moment_range(inertia);
    let condition = most / least;
    (condition > CONDITIONING_WARNING).then(|| {
        format!(
            "warning: the principal moments of inertia span {least:e} to {most:e} (condition \
             {condition:.1e}): the velocity follows from the momentum only to about {:.0e} of \
             its size, and the steps' errors grow by up to that factor (the estimated error is \
             measured by the run's companion); give the smallest moment a size within \
             {CONDITIONING_WARNING:e} of the largest",
            f64::EPSILON * condition
        )
    })
}

/// `lgsvi simulate`: resolves the options (config, flags, defaults), runs (or evaluates
/// the exact solution), warns of a large estimated error, draws and writes.
pub(crate) fn run_simulate(options: SimulateOptions) -> Result<()> {
    check_outputs(&options)?;
    let (problem, options) = Problem::resolve(options)?;
    let mut description = problem.description.clone();
    description["settings"] = settings_json(&problem.settings(), problem.t_end, problem.every);
    description["solution"] = "integrator".into();
    for (flag, given) in [
        ("--stop-when", &options.stop_when),
        ("--settle-when", &options.settle_when),
    ] {
        if let (true, Some(condition)) = (options.exact, given) {
            return Err(CliError::invalid(
                flag,
                condition,
                "--exact prints the closed form at the recorded times and watches no \
                 condition: drop one of the two",
            ));
        }
    }
    let recording = if options.exact {
        let exact = problem
            .scenario
            .record_exact(problem.settings(), problem.t_end, problem.every);
        let (recording, regime) = exact.ok_or(CliError::NoExactSolution)??;
        description["solution"] = "exact (Jacobi elliptic functions)".into();
        description["regime"] = format!("{regime:?}").into();
        recording
    } else {
        integrate(&problem)?
    };
    if let Some(stopped) = &recording.stopped {
        description["stopped"] = stopped_json(stopped);
        if !problem.quiet {
            eprintln!(
                "stopped: {} at t = {} (the run ends at t = {}, the end of that step)",
                stopped.condition,
                stopped.time,
                recording.states.last().map_or(stopped.time, |s| s.time)
            );
        }
    }
    if let Some(settled) = &recording.settled {
        description["settled"] = serde_json::json!({
            "condition": settled.condition,
            "t": settled.time,
        });
        if !problem.quiet {
            match settled.time {
                Some(t) => eprintln!("settled: {} from t = {t} on", settled.condition),
                None => eprintln!(
                    "not settled: {} does not hold at the end",
                    settled.condition
                ),
            }
        }
    }
    let estimate = recording.estimates.as_ref().map(|e| e.global);
    if let Some(warning) = estimate.and_then(estimate_warning) {
        eprintln!("{warning}");
    }
    if let Some(warning) = conditioning_warning(&problem.scenario.inertia) {
        eprintln!("{warning}");
    }
    if let Some(base) = &options.plot {
        let conserved = Conserved::of(&problem.scenario);
        plot::save(
            &conservation_figure(&recording, problem.name, conserved),
            base,
        )?;
    }
    let format = options.format.unwrap_or(config::Format::Json);
    let write = |out: &mut dyn std::io::Write| match format {
        config::Format::Json => write_json(&recording, &description, out),
        config::Format::Csv => write_csv(&recording, out),
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
        Some(Command::Montecarlo(options)) => montecarlo::run(*options),
        Some(Command::Optimize(options)) => optimize::run(options),
        Some(Command::CliReference) => {
            print!("{}", cli_reference());
            Ok(())
        }
        None => reproduce::run(cli.reproduce),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // A Monte Carlo run whose outputs were written, some members failing.
        Err(error @ CliError::MembersFailed { .. }) => {
            eprintln!("error: {error}");
            ExitCode::from(3)
        }
        Err(error) => {
            eprintln!("error: {}", error.to_string().replace('\n', " "));
            ExitCode::FAILURE
        }
    }
}
