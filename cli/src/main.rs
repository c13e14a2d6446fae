//! `lgsvi`: Lie group spectral variational integrators from the command line.
//!
//! `lgsvi` alone runs the main job (the paper's free rigid body on embedded defaults, a
//! short report); `lgsvi simulate` runs one trajectory from flags and/or a TOML config and
//! writes JSON or CSV. Errors are one line on standard error and a non-zero exit.

mod config;
mod output;

use clap::{Parser, Subcommand};
use config::{SimulateOptions, SystemKind};
use lgsvi_mechanics::{
    HeavyTop, Inertia, Integrator, Lagrangian, RigidBody, StepSettings, Trajectory,
};
use nalgebra::Vector3;
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
    /// Run one trajectory and write it as JSON or CSV.
    Simulate(SimulateOptions),
}

/// The paper's parameters per system (`paper/README.md`): case A and case B.
struct Defaults {
    inertia_d: [f64; 3],
    omega0: [f64; 3],
}

fn defaults(system: SystemKind) -> Defaults {
    match system {
        SystemKind::RigidBody => Defaults {
            inertia_d: [1.3, 2.1, 1.2],
            omega0: [-2.0, 1.9, -1.0],
        },
        SystemKind::HeavyTop => Defaults {
            inertia_d: [1.0, 2.8, 2.0],
            omega0: [0.5, -0.5, 0.4],
        },
    }
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

fn integrate<L: Lagrangian>(
    system: L,
    settings: StepSettings,
    options: &SimulateOptions,
    description: serde_json::Value,
) -> Result<Run, String> {
    let omega0 = Vector3::from(options.omega0.expect("filled by defaults"));
    let attitude = options.attitude()?;
    let mut integrator =
        Integrator::new(system, settings, attitude, omega0).map_err(|e| e.to_string())?;
    let t_end = options.t_end.unwrap_or(10.0);
    let every = options.every.unwrap_or(1);
    if every == 0 {
        return Err("invalid --every 0: keep every K-th step with K ≥ 1".into());
    }
    let steps = integrator.steps_until(t_end).map_err(|e| e.to_string())?;
    let progress = progress_bar(steps, options.quiet);
    let start = Instant::now();
    let trajectory = integrator
        .run_with_progress(steps, every, |k| {
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

/// Runs of at least this many steps show a progress bar (on a terminal, unless `--quiet`).
const PROGRESS_FROM_STEPS: usize = 1000;

/// A progress bar on standard error, hidden for short runs, `--quiet`, or when standard
/// error is not a terminal (so files and pipes never receive control characters).
fn progress_bar(steps: usize, quiet: bool) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if quiet || steps < PROGRESS_FROM_STEPS || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(steps as u64);
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} steps, {eta} left")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message("integrating");
    bar
}

/// Resolves the options (config, flags, defaults) and runs.
fn simulate(options: SimulateOptions) -> Result<(Run, SimulateOptions), String> {
    let mut options = options.merged_with_config()?;
    let system = options.system();
    let d = defaults(system);
    if options.omega0.is_none() {
        options.omega0 = Some(d.omega0);
    }
    let inertia = match (options.inertia, options.inertia_d) {
        (Some(j), None) => {
            Inertia::from_principal_moments(j).map_err(|e| format!("--inertia: {e}"))?
        }
        (None, Some(jd)) => Inertia::from_paper_jd(jd).map_err(|e| format!("--inertia-d: {e}"))?,
        (None, None) => Inertia::from_paper_jd(d.inertia_d).map_err(|e| e.to_string())?,
        (Some(_), Some(_)) => return Err("give --inertia or --inertia-d, not both".into()),
    };
    let h = options.h.unwrap_or(0.5);
    let nodes = options.nodes.unwrap_or(10);
    let mut settings = StepSettings::new(h, nodes).map_err(|e| e.to_string())?;
    if let Some(m) = options.quad {
        settings = settings
            .with_quadrature_points(m)
            .map_err(|e| e.to_string())?;
    }
    let chart = options.chart.map(Into::into).unwrap_or_default();
    settings = settings
        .with_chart(chart)
        .with_matching(options.matching.map(Into::into).unwrap_or_default())
        .with_jacobian(options.jacobian.map(Into::into).unwrap_or_default());
    if let Some(t) = options.t_end {
        if !(t.is_finite() && t >= 0.0) {
            return Err(format!(
                "invalid --t-end {t}: must be finite and non-negative"
            ));
        }
    }
    let settings_json = serde_json::json!({
        "h": settings.step(), "nodes": settings.nodes(), "degree": settings.degree(),
        "quadrature_points": settings.quadrature_points(), "chart": settings.chart().to_string(),
        "matching": format!("{:?}", settings.matching()).to_lowercase(),
        "jacobian": match settings.jacobian() { lgsvi_mechanics::NewtonJacobian::Exact => "exact", _ => "finite-difference" },
        "t_end": options.t_end.unwrap_or(10.0), "every": options.every.unwrap_or(1),
    });
    // The inertia as the user gave it (J or J_d), the other form derived from it, so the
    // description echoes the input without the rounding of a round trip.
    let inertia_j = options.inertia.unwrap_or(inertia.principal_moments());
    let inertia_jd = options
        .inertia_d
        .or(options.inertia.is_none().then_some(d.inertia_d))
        .unwrap_or(inertia.paper_jd());
    let run = match system {
        SystemKind::RigidBody => {
            let description = serde_json::json!({
                "system": "rigid-body", "inertia_J": inertia_j,
                "inertia_Jd": inertia_jd,
                "settings": settings_json,
            });
            integrate(RigidBody::new(inertia), settings, &options, description)?
        }
        SystemKind::HeavyTop => {
            let mass = options.mass.unwrap_or(1.0);
            let gravity = options.gravity.unwrap_or(9.81);
            let com = Vector3::from(options.com.unwrap_or([0.0, 0.0, 1.0]));
            let direction = Vector3::from(options.gravity_direction.unwrap_or([0.0, 0.0, 1.0]));
            let top =
                HeavyTop::new(inertia, mass, gravity, com, direction).map_err(|e| e.to_string())?;
            let description = serde_json::json!({
                "system": "heavy-top", "inertia_J": inertia_j,
                "inertia_Jd": inertia_jd,
                "mass": mass, "gravity": gravity, "com": com.as_slice(), "gravity_direction": top.gravity_direction().as_slice(),
                "settings": settings_json,
            });
            integrate(top, settings, &options, description)?
        }
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
        None => output::main_job(simulate(SimulateOptions::default())),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {}", message.replace('\n', " "));
            ExitCode::FAILURE
        }
    }
}
