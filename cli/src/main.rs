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
mod output;
mod plot;
mod problem;
mod reproduce;
mod study;
mod tolerance;

use clap::{Parser, Subcommand};
use config::SimulateOptions;
use error::{CliError, Result};
use lgsvi_mechanics::control::GroupLog;
use lgsvi_mechanics::{
    Checked, ElementOf, GroupChart, GroupLagrangian, Integrator, MechanicsError, State,
    StepSettings, ToleranceCheck, Trajectory,
};
use problem::Problem;
use std::process::ExitCode;
use std::time::Instant;

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

/// A finished run: the trajectory, the integration's wall time, and a description.
pub struct Run {
    /// The states (for an SE(3) run, the rotational part: `R`, `Ω`, `JΩ`).
    pub trajectory: Trajectory,
    pub energies: Vec<f64>,
    /// The work of the torque and damping up to each recorded state, for a forced run.
    pub work: Option<Vec<f64>>,
    /// Position, velocity and spatial momenta of each recorded state, for an SE(3) run.
    pub motion: Option<Vec<MotionRecord>>,
    /// The wheels of each recorded state, for a gyrostat run.
    pub wheels: Option<Vec<WheelRecord>>,
    pub wall_time_s: f64,
    pub steps: usize,
    pub newton_iterations: usize,
    pub max_newton_iterations: usize,
    /// Newton matrices assembled and factored (the other iterations reused one).
    pub factorizations: usize,
    /// The integrator's error accounting: the sum of the steps' local error estimates,
    /// the steps per node count, and (adaptive runs) the solves redone with more nodes.
    pub estimates: Option<Estimates>,
    pub description: serde_json::Value,
}

/// What a run's error estimates say.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimates {
    /// The sum of the local error estimates.
    pub global: f64,
    /// `(n, steps with n nodes)`, by increasing `n`.
    pub nodes: Vec<(usize, usize)>,
    /// Solves redone with more nodes (adaptive runs).
    pub rejected: usize,
    /// A checked `--tol` run's measurement (`global` is then its difference at the end).
    pub check: Option<CheckRecord>,
}

/// What a `--tol` run's companion measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckRecord {
    /// The largest difference along the run, its time and step.
    pub largest: lgsvi_mechanics::Difference,
    /// The sum of the local estimates (the unchecked model), for comparison.
    pub local_sum: f64,
    /// Runs taken (the first, and each with a tightened share per step).
    pub attempts: usize,
    /// The accepted run's share per step against the first's.
    pub tightened: f64,
}

/// The translational part of a recorded SE(3) state.
#[derive(Debug, Clone, Copy)]
pub struct MotionRecord {
    /// Centre of mass `x`, world frame.
    pub position: nalgebra::Vector3<f64>,
    /// `ẋ`, world frame.
    pub velocity: nalgebra::Vector3<f64>,
    /// The spatial momentum `(RJΩ + x × mẋ, mẋ)`: angular momentum about the world
    /// origin and linear momentum.
    pub spatial_momentum: nalgebra::SVector<f64, 6>,
}

/// The wheels of a recorded gyrostat state.
#[derive(Debug, Clone)]
pub struct WheelRecord {
    /// The wheel angles `φ_i` relative to the body.
    pub angles: Vec<f64>,
    /// Their rates `φ̇_i`.
    pub speeds: Vec<f64>,
    /// The wheels' axial momenta `p_i = I_i (a_iᵀΩ + φ̇_i)`.
    pub momenta: Vec<f64>,
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
    if let Some(wheels) = &problem.wheels {
        return integrate_gyrostat(problem, wheels);
    }
    match &problem.motion {
        None => integrate_with(
            problem,
            |settings| problem.integrator(settings),
            |s| (*s, None, None),
        ),
        // SE(3): the rotational part as the SO(3) columns, the translation beside them.
        Some(motion) => integrate_with(
            problem,
            |settings| Ok(motion.integrator(settings)?),
            |s| {
                let entry = MotionRecord {
                    position: s.position(),
                    velocity: s.linear_velocity(),
                    spatial_momentum: s.spatial_momentum(),
                };
                let rotation = State {
                    time: s.time,
                    configuration: *s.attitude(),
                    momentum: s.momentum.fixed_rows::<3>(0).into_owned(),
                    velocity: s.angular_velocity(),
                };
                (rotation, Some(entry), None)
            },
        ),
    }
}

/// A gyrostat run: the body's attitude, rate and total angular momentum `h` as the SO(3)
/// columns (the spatial `Rh` is what the wheels conserve), the wheels beside them.
fn integrate_gyrostat(problem: &Problem, wheels: &problem::Wheels) -> Result<Run> {
    use problem::AnyGyrostat;
    macro_rules! run {
        ($craft:expr, $k:literal, $d:literal) => {{
            let make = |settings| {
                wheels.integrator::<$k, $d>($craft, settings, problem.attitude0, problem.omega0)
            };
            integrate_with(problem, make, |s| {
                let rotation = State {
                    time: s.time,
                    configuration: s.configuration.attitude,
                    momentum: s.momentum.fixed_rows::<3>(0).into_owned(),
                    velocity: s.velocity.fixed_rows::<3>(0).into_owned(),
                };
                // The body momentum is (h, p): the wheels' axial momenta are its last K
                // entries, as their rates are the velocity's.
                let record = WheelRecord {
                    angles: s.configuration.wheels.iter().copied().collect(),
                    speeds: s.velocity.iter().skip(3).copied().collect(),
                    momenta: s.momentum.iter().skip(3).copied().collect(),
                };
                (rotation, None, Some(record))
            })
        }};
    }
    match wheels.system {
        AnyGyrostat::One(craft) => run!(craft, 1, 4),
        AnyGyrostat::Two(craft) => run!(craft, 2, 5),
        AnyGyrostat::Three(craft) => run!(craft, 3, 6),
        AnyGyrostat::Four(craft) => run!(craft, 4, 7),
    }
}

/// What steps a run: the integrator alone, or with its companion check.
trait Runner<S: GroupLagrangian<D>, C: GroupChart<S::Group, D>, const D: usize> {
    fn advance(&mut self) -> std::result::Result<usize, lgsvi_mechanics::MechanicsError>;
    fn integrator(&self) -> &Integrator<S, C, D>;
    /// The checked difference now and at its largest.
    fn checked(&self) -> Option<(f64, lgsvi_mechanics::Difference)>;
}

impl<S: GroupLagrangian<D>, C: GroupChart<S::Group, D>, const D: usize> Runner<S, C, D>
    for Integrator<S, C, D>
{
    fn advance(&mut self) -> std::result::Result<usize, lgsvi_mechanics::MechanicsError> {
        self.step()
    }
    fn integrator(&self) -> &Integrator<S, C, D> {
        self
    }
    fn checked(&self) -> Option<(f64, lgsvi_mechanics::Difference)> {
        None
    }
}

impl<S, C, const D: usize> Runner<S, C, D> for Checked<S, C, D>
where
    S: GroupLagrangian<D> + Clone,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: GroupLog<D>,
{
    fn advance(&mut self) -> std::result::Result<usize, lgsvi_mechanics::MechanicsError> {
        self.step()
    }
    fn integrator(&self) -> &Integrator<S, C, D> {
        Checked::integrator(self)
    }
    fn checked(&self) -> Option<(f64, lgsvi_mechanics::Difference)> {
        Some((self.difference(), self.largest_difference()))
    }
}

/// Runs to the problem's horizon with the integrators `make` builds (the problem's
/// settings, or a `--tol` run's tightened ones): unchecked, one run; checked (`--tol`
/// without `--no-check`), runs beside their companion with the settings
/// [`ToleranceCheck`] gives, until it accepts one or refuses.
fn integrate_with<S, C, const D: usize>(
    problem: &Problem,
    make: impl Fn(StepSettings) -> Result<Integrator<S, C, D>>,
    split: impl Fn(&State<ElementOf<S, D>, D>) -> (State, Option<MotionRecord>, Option<WheelRecord>),
) -> Result<Run>
where
    S: GroupLagrangian<D> + Copy,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: GroupLog<D>,
{
    let tol = match problem.check {
        problem::Check::None => return record(problem, make(problem.settings)?, &split),
        problem::Check::Measure => {
            return record(problem, Checked::new(make(problem.settings)?)?, &split)
        }
        problem::Check::Tolerance(tol) => tol,
    };
    let mut policy = ToleranceCheck::new(problem.settings, tol)?;
    let mut wall_time = 0.0;
    loop {
        let mut run = record(problem, Checked::new(make(policy.settings())?)?, &split)?;
        wall_time += run.wall_time_s;
        run.wall_time_s = wall_time;
        let estimates = run
            .estimates
            .as_mut()
            .expect("an integrated run has estimates");
        let check = estimates
            .check
            .as_mut()
            .expect("a checked run has its check");
        check.attempts = policy.attempt();
        check.tightened = policy.tightened();
        let largest = check.largest;
        if policy.judge(largest).map_err(|error| match error {
            MechanicsError::ToleranceNotChecked {
                attempts,
                tightened,
                measured,
                time,
                step,
                at_floor,
                best,
                ..
            } => CliError::ToleranceNotChecked {
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
            other => other.into(),
        })? {
            return Ok(run);
        }
    }
}

/// Runs `runner` to the problem's horizon: every state is checked (its rotational part,
/// from `split`, and the translation `split` returns beside it), every `problem.every`-th
/// and the last are recorded. The integration alone is timed (with its companion, for a
/// checked run): not the checks, the recording or the output.
fn record<S, C, const D: usize>(
    problem: &Problem,
    mut runner: impl Runner<S, C, D>,
    split: &impl Fn(&State<ElementOf<S, D>, D>) -> (State, Option<MotionRecord>, Option<WheelRecord>),
) -> Result<Run>
where
    S: GroupLagrangian<D> + Copy,
    C: GroupChart<S::Group, D>,
{
    let steps = runner.integrator().steps_until(problem.t_end)?;
    let system = *runner.integrator().system();
    // Forced: by the system's own force, or by an input (a gyrostat's motor torques).
    let forced = system.is_forced() || runner.integrator().input().iter().any(|&u| u != 0.0);
    let mut trajectory = Trajectory::default();
    let (mut energies, mut work, mut records) = (Vec::new(), Vec::new(), Vec::new());
    let mut wheel_records = Vec::new();
    let mut visit = |k: usize,
                     state: &State<ElementOf<S, D>, D>,
                     iterations: Option<usize>,
                     done: f64|
     -> Result<()> {
        let energy = state.energy(&system);
        let (rotation, entry, wheel) = split(state);
        check_finite_state(k, &rotation, energy)?;
        if let Some(entry) = &entry {
            let translation = [entry.position, entry.velocity];
            if translation.iter().any(|v| v.iter().any(|x| !x.is_finite())) {
                return Err(CliError::Overflow {
                    step: k,
                    time: state.time,
                    quantity: "position x or velocity ẋ",
                    values: format!("{translation:?}"),
                });
            }
        }
        let Some(iterations) = iterations else {
            return Ok(());
        };
        trajectory.states.push(rotation);
        trajectory.newton_iterations.push(iterations);
        energies.push(energy);
        work.push(done);
        records.extend(entry);
        wheel_records.extend(wheel);
        Ok(())
    };
    visit(0, runner.integrator().state(), Some(0), 0.0)?;
    let progress = progress_bar(steps as u64, "integrating", "steps", problem.quiet);
    let mut wall_time = std::time::Duration::ZERO;
    for k in 1..=steps {
        let start = Instant::now();
        let iterations = runner.advance()?;
        wall_time += start.elapsed();
        let recorded = k % problem.every == 0 || k == steps;
        let integrator = runner.integrator();
        visit(
            k,
            integrator.state(),
            recorded.then_some(iterations),
            integrator.work_done(),
        )?;
        if k % 64 == 0 {
            progress.set_position(k as u64);
        }
    }
    progress.finish_and_clear();
    let integrator = runner.integrator();
    let stats = integrator.statistics();
    let local_sum = integrator.estimated_global_error();
    let check = runner.checked();
    let estimates = Estimates {
        // A checked run reports what its companion measured at the end.
        global: check.map_or(local_sum, |(now, _)| now),
        nodes: integrator.nodes_used().collect(),
        rejected: stats.rejected_steps,
        check: check.map(|(_, largest)| CheckRecord {
            largest,
            local_sum,
            attempts: 1,
            tightened: 1.0,
        }),
    };
    let mut description = problem.description.clone();
    description["settings"] =
        Problem::settings_json(&problem.settings, problem.t_end, problem.every);
    description["solution"] = "integrator".into();
    Ok(Run {
        trajectory,
        energies,
        work: forced.then_some(work),
        motion: problem.motion.is_some().then_some(records),
        wheels: problem.wheels.is_some().then_some(wheel_records),
        wall_time_s: wall_time.as_secs_f64(),
        steps: stats.steps,
        newton_iterations: stats.newton_iterations,
        max_newton_iterations: stats.max_newton_iterations,
        factorizations: stats.factorizations,
        estimates: Some(estimates),
        description,
    })
}

/// The exact free-body solution at the times the integrator would record.
fn exact_run(problem: &Problem) -> Result<Run> {
    let body = lgsvi_experiments::Subject::exact(problem).ok_or(CliError::NoExactSolution)??;
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
        work: None,
        motion: None,
        wheels: None,
        wall_time_s,
        steps: 0,
        newton_iterations: 0,
        max_newton_iterations: 0,
        factorizations: 0,
        estimates: None,
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
        integrate(&problem).map_err(|error| match error {
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
        })?
    };
    if let Some(warning) = run
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

/// The conservation figure of a run: `|E − E₀ − W|/|E₀|` (the energy balance; `W = 0`
/// unforced) and, for an unforced run, the drift of the spatial momentum's conserved
/// components relative to its size (all of it for a free body, the angular part about
/// the centre for an orbiting one, the vertical one for the heavy top).
fn conservation_figure(run: &Run, problem_name: &str) -> plot::Figure {
    let states = &run.trajectory.states;
    let e0 = run.energies[0];
    let scale = e0.abs().max(f64::MIN_POSITIVE);
    let work = |k: usize| run.work.as_ref().map_or(0.0, |w| w[k]);
    let balance: Vec<(f64, f64)> = states
        .iter()
        .enumerate()
        .skip(1)
        .map(|(k, s)| (s.time, (run.energies[k] - e0 - work(k)).abs() / scale))
        .collect();
    let label = if run.work.is_some() {
        "energy balance |E − E₀ − W|/|E₀|"
    } else {
        "energy error |E − E₀|/|E₀|"
    };
    let mut series = vec![plot::Series {
        label: label.into(),
        points: balance,
        style: plot::Style::Line,
        color: 0,
    }];
    if run.work.is_none() {
        // The components a symmetry conserves: all of the spatial momentum for a free
        // body, the angular momentum about the centre for an orbiting one, the component
        // along gravity for the heavy top.
        let direction: Vec<f64> = run.description["gravity_direction"]
            .as_array()
            .map(|d| d.iter().filter_map(|x| x.as_f64()).collect())
            .unwrap_or_default();
        let conserved = |k: usize| -> Vec<f64> {
            match (&run.motion, problem_name) {
                (Some(m), "orbiting-body") => {
                    m[k].spatial_momentum.iter().take(3).copied().collect()
                }
                (Some(m), _) => m[k].spatial_momentum.iter().copied().collect(),
                (None, "heavy-top") if direction.len() == 3 => {
                    let pi = states[k].spatial_momentum();
                    vec![pi.iter().zip(&direction).map(|(a, b)| a * b).sum()]
                }
                (None, _) => states[k].spatial_momentum().iter().copied().collect(),
            }
        };
        let p0 = conserved(0);
        let size = p0.iter().map(|x| x.abs()).fold(f64::MIN_POSITIVE, f64::max);
        let drift = (1..states.len())
            .map(|k| {
                let d = conserved(k)
                    .iter()
                    .zip(&p0)
                    .map(|(p, q)| (p - q).abs())
                    .fold(0.0, f64::max);
                (states[k].time, d / size)
            })
            .collect();
        series.push(plot::Series {
            label: "momentum drift (conserved components)".into(),
            points: drift,
            style: plot::Style::Line,
            color: 1,
        });
    }
    plot::Figure {
        title: format!("{problem_name}: conservation over {} steps", run.steps),
        x_label: "time t".into(),
        y_label: "relative error".into(),
        x_log: false,
        y_log: true,
        series,
        hlines: vec![],
    }
}

fn run_simulate(options: SimulateOptions) -> Result<()> {
    check_outputs(&options)?;
    let (run, options) = simulate(options)?;
    if let Some(base) = &options.plot {
        let name = run.description["system"]
            .as_str()
            .unwrap_or("run")
            .to_string();
        plot::save(&conservation_figure(&run, &name), base)?;
    }
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
