//! `lgsvi optimize`: the slew of a rigid body, a heavy top (`--gravity`) or a spacecraft by
//! its three reaction wheels (`--wheels`) at the least input energy in a fixed time or in
//! the least time, torques bounded per axis or wheel ([`lgsvi_optimal`]), written as JSON with optional figures of the
//! torques, the rates and the attitude error.

use crate::error::{CliError, Result};
use clap::{Args, ValueEnum};
use lgsvi_mechanics::lie::{LieGroup, SO3};
use lgsvi_mechanics::Inertia;
use lgsvi_optimal::{OptimalError, Slew};
use nalgebra::Vector3;
use serde_json::json;
use std::path::PathBuf;

/// What a slew minimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Cost {
    /// `∫ |u|² dt` in the fixed time `--t-end`.
    Energy,
    /// The final time, the torques bounded by `--torque-max` (with --space the forces by
    /// `--force-max` too; `--t-end` is then a first guess).
    Time,
}

/// How the torque varies within a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum InputShape {
    /// Held constant over each step.
    Constant,
    /// A polynomial within each step, given at its Gauss points (the energy cost only).
    Polynomial,
}

/// The options of `lgsvi optimize`.
#[derive(Debug, Clone, Args)]
pub struct OptimizeOptions {
    /// Principal moments of inertia J = diag(a, b, c), kg·m² [default: 3.3,2.5,3.4, the
    /// paper's body].
    #[arg(long, value_parser = crate::config::numbers::<3>, allow_hyphen_values = true, value_name = "A,B,C")]
    pub inertia: Option<[f64; 3]>,
    /// Gravity g ≥ 0: the body becomes a heavy top about its fixed point,
    /// `ℓ = ½ΩᵀJΩ + m g dᵀRρ` (the torques also hold it against gravity).
    #[arg(long, allow_hyphen_values = true)]
    pub gravity: Option<f64>,
    /// The heavy top's mass m ≥ 0, or with --space the body's m > 0, kg [default: 1].
    #[arg(long, allow_hyphen_values = true)]
    pub mass: Option<f64>,
    /// The heavy top's centre of mass ρ from the fixed point, body frame [default: 0,0,1].
    #[arg(long, value_parser = crate::config::numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub com: Option<[f64; 3]>,
    /// The direction d gravity pulls in, world frame [default: 0,0,1].
    #[arg(long, value_parser = crate::config::numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub gravity_direction: Option<[f64; 3]>,
    /// Slew by three reaction wheels: the torques solved for (and bounded by --torque-max)
    /// are the wheels' motor torques, J (--inertia) the spacecraft's with its wheels locked.
    #[arg(long)]
    pub wheels: bool,
    /// With --wheels: the three wheel axes in the body frame [default: the body axes x, y, z].
    #[arg(long, value_parser = crate::config::numbers::<9>, allow_hyphen_values = true, value_name = "X1,Y1,Z1,X2,Y2,Z2,X3,Y3,Z3")]
    pub wheel_axes: Option<[f64; 9]>,
    /// With --wheels: each wheel's axial inertia I_i > 0, kg·m² (one value for all three, or
    /// three) [default: 0.05].
    #[arg(long, value_parser = torque_bound, allow_hyphen_values = true, value_name = "I or I1,I2,I3")]
    pub wheel_inertia: Option<[f64; 3]>,
    /// With --wheels: the wheels' rates relative to the body at the start, rad/s (their
    /// final rates are free) [default: 0,0,0].
    #[arg(long, value_parser = crate::config::numbers::<3>, allow_hyphen_values = true, value_name = "W1,W2,W3")]
    pub wheel_speeds0: Option<[f64; 3]>,
    /// Manoeuvre a body in space (SE(3)): the free body of --inertia and --mass (with --mu,
    /// the body orbiting a point mass at the origin), its attitude, centre of mass and
    /// their rates driven by a body wrench (torque and force, body frame) at the least
    /// ∫(|τ|² + |f|²) dt in --t-end, or with --cost time in the least time, bounded by
    /// --torque-max and --force-max.
    #[arg(long)]
    pub space: bool,
    /// With --space: the gravitational parameter μ = GM ≥ 0 of a point mass at the origin
    /// that the body orbits (MacCullagh's potential).
    #[arg(long, allow_hyphen_values = true)]
    pub mu: Option<f64>,
    /// With --space: the start's centre of mass, world frame, m [default: 0,0,0].
    #[arg(long, value_parser = crate::config::numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub position0: Option<[f64; 3]>,
    /// With --space: the target centre of mass, world frame, m [default: the start's].
    #[arg(long, value_parser = crate::config::numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub position_final: Option<[f64; 3]>,
    /// With --space: the start's centre-of-mass velocity ẋ, world frame, m/s [default:
    /// 0,0,0].
    #[arg(long, value_parser = crate::config::numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub velocity0: Option<[f64; 3]>,
    /// With --space: the target centre-of-mass velocity ẋ, world frame, m/s [default:
    /// 0,0,0].
    #[arg(long, value_parser = crate::config::numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub velocity_final: Option<[f64; 3]>,
    /// With --space: the largest force per body axis, N: one value for all three, or
    /// X,Y,Z.
    #[arg(long, value_parser = torque_bound, allow_hyphen_values = true, value_name = "F or X,Y,Z")]
    pub force_max: Option<[f64; 3]>,
    /// The start attitude as a rotation vector (radians, body to world) [default: 0,0,0].
    #[arg(long, value_parser = crate::config::numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub attitude0: Option<[f64; 3]>,
    /// The target attitude as a rotation vector (radians, body to world); needed for a
    /// slew [with --space, default: the start's].
    #[arg(long, value_parser = crate::config::numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub attitude_final: Option<[f64; 3]>,
    /// The start body rates, rad/s [default: 0,0,0].
    #[arg(long, value_parser = crate::config::numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub omega0: Option<[f64; 3]>,
    /// The target body rates, rad/s [default: 0,0,0].
    #[arg(long, value_parser = crate::config::numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub omega_final: Option<[f64; 3]>,
    /// The slew's duration T, s; with `--cost time` a first guess [default there: the
    /// bang-bang turn about the rotation's axis; with --space the longest of that turn's,
    /// the straight move's at the weakest force and the velocity changes'].
    #[arg(long, allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    /// What is minimised [default: energy]. The least time needs --torque-max (and with
    /// --space --force-max too).
    #[arg(long, value_enum)]
    pub cost: Option<Cost>,
    /// How the torque varies within a step [default: constant]; polynomial: the cost
    /// converges at the integrator's order (with --cost energy).
    #[arg(long, value_enum)]
    pub inputs: Option<InputShape>,
    /// Replace the exact target by a cost Q_THETA |log(R_fᵀ R_K)|² + Q_OMEGA |Ω_K − Ω_f|²
    /// (a soft target; with --cost energy); with --space four weights,
    /// Q_THETA,Q_X,Q_OMEGA,Q_V, the position's and its velocity's (world frame) between.
    #[arg(long, value_parser = weights, allow_hyphen_values = true, value_name = "Q_THETA,Q_OMEGA")]
    pub terminal_cost: Option<Weights>,
    /// Track a reference motion: a JSON file with `R` (row-major attitudes) and `omega`
    /// (body rates) at the K step boundaries after the start (or K + 1 with the start,
    /// which is then skipped), as `lgsvi simulate --h T/K` and `lgsvi optimize` write them;
    /// adds Q_THETA |log(R_refᵀ R_k)|² + Q_OMEGA |Ω_k − Ω_ref|² per step (with --cost energy).
    /// With --space the file holds the positions (`position` or `x`) and velocities
    /// (`velocity`, world frame) too, and each step adds Q_X |x_k − x_ref|² and
    /// Q_V |ẋ_k − ẋ_ref|².
    #[arg(long, value_name = "FILE")]
    pub track: Option<PathBuf>,
    /// The tracking weights [default: 1,1; with --space 1,1,1,1].
    #[arg(long, value_parser = weights, allow_hyphen_values = true, value_name = "Q_THETA,Q_OMEGA")]
    pub track_weights: Option<Weights>,
    /// The largest torque per body axis (with --wheels, per wheel), N·m: one value for all
    /// three, or X,Y,Z.
    #[arg(long, value_parser = torque_bound, allow_hyphen_values = true, value_name = "U or X,Y,Z")]
    pub torque_max: Option<[f64; 3]>,
    /// A constant disturbance torque on the body, body frame, N·m: known (solar pressure,
    /// outgassing, a mean gravity-gradient torque) and worked against by the torques (with
    /// --wheels, by the motors, whose wheels take up its momentum). Not part of the cost
    /// nor of the output's inputs; a replay adds it to them.
    #[arg(long, value_parser = crate::config::numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub disturbance: Option<[f64; 3]>,
    /// With --space: a constant disturbance force on the body, body frame, N (a leak, a
    /// thruster's misalignment), beside --disturbance's torque; as that one, worked
    /// against, not part of the cost nor of the output's inputs.
    #[arg(long, value_parser = crate::config::numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub disturbance_force: Option<[f64; 3]>,
    /// Steps K (the torque is constant over each) [default: 40].
    #[arg(long)]
    pub steps: Option<usize>,
    /// Nodes n per step [default: 10].
    #[arg(long)]
    pub nodes: Option<usize>,
    /// The scaled KKT residual to reach [default: 1e-10].
    #[arg(long)]
    pub tolerance: Option<f64>,
    /// The most SQP iterations [default: 100; 500 with --space].
    #[arg(long)]
    pub max_iterations: Option<usize>,
    /// Output file (JSON) [default: standard output].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also draw the torques, the rates and the attitude error to PLOT_*.svg and .png (with
    /// --space: the torques, the forces, the centre of mass and the attitude error).
    #[arg(long, value_name = "PLOT")]
    pub plot: Option<PathBuf>,
    /// No progress line.
    #[arg(long)]
    pub quiet: bool,
}

/// `--torque-max`, `--wheel-inertia`: one value for all three, or three.
fn torque_bound(text: &str) -> std::result::Result<[f64; 3], String> {
    if text.contains(',') {
        crate::config::numbers::<3>(text)
    } else {
        let [u] = crate::config::numbers::<1>(text)?;
        Ok([u; 3])
    }
}

/// Runs `lgsvi optimize`.
pub fn run(options: OptimizeOptions) -> Result<()> {
    if options.space {
        return crate::manoeuvre::run(&options);
    }
    crate::manoeuvre::refuse_space_only(&options)?;
    let minimum_time = options.cost == Some(Cost::Time);
    if minimum_time && options.torque_max.is_none() {
        return Err(CliError::invalid(
            "--torque-max",
            "(none)",
            "a minimum-time slew needs a torque bound (without one, any time is reachable): \
             give --torque-max U or X,Y,Z in N·m",
        ));
    }
    if !minimum_time && options.t_end.is_none() {
        return Err(CliError::invalid(
            "--t-end",
            "(none)",
            "a minimum-energy slew takes a fixed duration: give --t-end T in seconds (or \
             --cost time with --torque-max for the least time)",
        ));
    }
    let inertia = inertia(&options)?;
    let gravity = heavy_top(&options)?;
    let start = SO3::exp(&Vector3::from(options.attitude0.unwrap_or([0.0; 3])));
    let attitude_final = options.attitude_final.ok_or(CliError::invalid(
        "--attitude-final",
        "(none)",
        "a slew needs its target attitude: give --attitude-final X,Y,Z (a rotation vector, \
         radians, body to world)",
    ))?;
    let target = SO3::exp(&Vector3::from(attitude_final));
    let omega0 = Vector3::from(options.omega0.unwrap_or([0.0; 3]));
    let omega_final = Vector3::from(options.omega_final.unwrap_or([0.0; 3]));
    let (steps, nodes) = (options.steps.unwrap_or(40), options.nodes.unwrap_or(10));
    let bounds_valid = options
        .torque_max
        .is_none_or(|b| b.iter().all(|u| u.is_finite() && *u > 0.0));
    let t_end = match options.t_end {
        Some(t) => t,
        // A bound the solver refuses (naming --torque-max) needs no guess.
        None if !bounds_valid => 1.0,
        None => lgsvi_optimal::eigen_axis_time(
            &inertia,
            &start.inverse().compose(&target),
            options.torque_max.unwrap_or([1.0; 3]),
        )
        .ok_or(CliError::invalid(
            "--attitude-final",
            attitude_final.map(|x| format!("{x:?}")).join(","),
            "the target attitude is the start's: give another target, or --t-end as the \
             first guess of the time",
        ))?,
    };
    let mut slew = Slew::new(inertia, t_end)
        .from(start, omega0)
        .to(target, omega_final)
        .steps(steps)
        .nodes(nodes)
        .cost(if minimum_time {
            lgsvi_optimal::Cost::Time
        } else {
            lgsvi_optimal::Cost::Energy
        });
    if let Some(bound) = options.torque_max {
        slew = slew.torque_max(bound);
    }
    if let Some(torque) = options.disturbance {
        slew = slew.disturbance(torque);
    }
    if let Some(gravity) = gravity {
        slew = slew.gravity(gravity);
    }
    let wheels = reaction_wheels(&options)?;
    if let Some(wheels) = wheels {
        slew = slew.wheels(wheels);
    }
    if let Some(weights) = &options.terminal_cost {
        slew = slew.terminal_cost(weight_count("--terminal-cost", &weights.0, "for a slew")?);
    }
    if let Some((reference, weights)) = tracking(&options, steps, reference_motion, "for a slew")? {
        slew = slew.track(reference, weights);
    }
    if options.inputs == Some(InputShape::Polynomial) {
        slew = slew.inputs(lgsvi_optimal::Inputs::Polynomial);
    }
    if let Some(tolerance) = options.tolerance {
        slew = slew.tolerance(tolerance);
    }
    if let Some(iterations) = options.max_iterations {
        slew = slew.max_iterations(iterations);
    }
    if !options.quiet {
        let angle = start.inverse().compose(&target).log().norm().to_degrees();
        if minimum_time {
            eprintln!(
                "optimize: a {angle:.1}° slew in the least time (first guess {t_end:.6} s), \
                 {steps} steps of {nodes} nodes …"
            );
        } else {
            eprintln!(
                "optimize: a {angle:.1}° slew in {t_end} s, {steps} steps of {nodes} nodes …"
            );
        }
    }
    let solution = slew.solve().map_err(|error| named(error, &options))?;
    if !options.quiet {
        report(
            solution.cost,
            if minimum_time { " s" } else { "" },
            &solution.statistics,
        );
    }
    let times: Vec<f64> = solution.states.iter().map(|s| s.time).collect();
    let error_deg: Vec<f64> = solution
        .states
        .iter()
        .map(|s| {
            s.configuration
                .inverse()
                .compose(&target)
                .log()
                .norm()
                .to_degrees()
        })
        .collect();
    let output = json!({
        "command": "optimize",
        "cost": solution.cost,
        "cost_kind": if minimum_time { "time: the final time in s" } else { "energy: the integral of |u|^2 dt" },
        "t_end": solution.t_end,
        "h": solution.h,
        "steps": steps,
        "nodes": nodes,
        "converged": solution.converged,
        "iterations": solution.statistics.iterations,
        "kkt_residuals": solution.statistics.kkt_residuals,
        "time_s": solution.statistics.time_s,
        "torque_max": options.torque_max,
        "disturbance": options.disturbance,
        "gravity": gravity.map(|g| json!({
            "mass": g.mass,
            "g": g.gravity,
            "com": g.center_of_mass.as_slice(),
            "gravity_direction": g.direction.as_slice(),
        })),
        "wheels": wheels.map(|w| json!({
            "axes": w.axes.iter().map(|a| [a.x, a.y, a.z]).collect::<Vec<_>>(),
            "inertia": w.inertia,
            "speeds0": w.speeds.as_slice(),
        })),
        "wheel_speeds": solution.wheel_speeds.iter().map(|w| [w.x, w.y, w.z]).collect::<Vec<_>>(),
        "multipliers": solution.multipliers,
        "t": times,
        "inputs": solution.inputs.iter().map(|u| [u.x, u.y, u.z]).collect::<Vec<_>>(),
        "inputs_at_points": solution.inputs_at_points.iter().map(|step| step.iter().map(|u| [u.x, u.y, u.z]).collect::<Vec<_>>()).collect::<Vec<_>>(),
        "quadrature_nodes": solution.quadrature_nodes,
        "R": solution.states.iter().map(|s| s.attitude().to_row_major()).collect::<Vec<_>>(),
        "omega": solution.states.iter().map(|s| [s.velocity.x, s.velocity.y, s.velocity.z]).collect::<Vec<_>>(),
        "attitude_error_deg": error_deg,
    });
    let drawn = match options.plot {
        Some(_) => figures(&solution, &times, &error_deg),
        None => Vec::new(),
    };
    write(&options, &output, drawn)
}

/// Writes a solve's figures to `--plot`'s base name with their suffixes and its JSON to
/// `--out` (or standard output).
pub fn write(
    options: &OptimizeOptions,
    output: &serde_json::Value,
    figures: Vec<(&'static str, lgsvi_plot::Figure)>,
) -> Result<()> {
    if let Some(base) = &options.plot {
        for (suffix, figure) in figures {
            let mut path = base.clone().into_os_string();
            path.push(suffix);
            crate::plot::save(&figure, &PathBuf::from(path))?;
        }
    }
    let text = serde_json::to_string_pretty(output)? + "\n";
    match &options.out {
        Some(path) => crate::files::write(path, text.as_bytes()),
        None => {
            print!("{text}");
            Ok(())
        }
    }
}

/// The progress line of a solve that ended: the cost (with its `unit`), the iterations,
/// the last scaled KKT residual and the time.
pub fn report(cost: f64, unit: &str, statistics: &lgsvi_optimal::Statistics) {
    eprintln!(
        "optimize: cost {cost:.12e}{unit} after {} iterations, scaled KKT residual {:.1e}, \
         {:.1} ms",
        statistics.iterations,
        statistics.kkt_residuals.last().copied().unwrap_or(f64::NAN),
        1e3 * statistics.time_s
    );
}

/// The body's `--inertia` (principal moments; the default body's without it), checked.
pub(crate) fn inertia(options: &OptimizeOptions) -> Result<Inertia> {
    let moments = options.inertia.unwrap_or([3.3, 2.5, 3.4]);
    Inertia::from_principal_moments(moments).map_err(|e| {
        CliError::invalid(
            "--inertia",
            moments.map(|x| x.to_string()).join(","),
            e.to_string(),
        )
    })
}

/// The weights of `--terminal-cost` or `--track-weights`: a slew's `Q_THETA,Q_OMEGA`, a
/// manoeuvre's `Q_THETA,Q_X,Q_OMEGA,Q_V`.
#[derive(Debug, Clone, PartialEq)]
pub struct Weights(pub Vec<f64>);

/// [`Weights`] from 2 or 4 comma-separated finite numbers.
fn weights(text: &str) -> std::result::Result<Weights, String> {
    match text.split(',').count() {
        2 => crate::config::numbers::<2>(text).map(|w| Weights(w.to_vec())),
        4 => crate::config::numbers::<4>(text).map(|w| Weights(w.to_vec())),
        n => Err(format!(
            "expected 2 comma-separated weights (a slew's Q_THETA,Q_OMEGA) or 4 (with --space, \
             Q_THETA,Q_X,Q_OMEGA,Q_V), got {n} in {text:?}"
        )),
    }
}

/// The `N` weights a problem takes from `flag`'s list, or an error saying how many.
pub(crate) fn weight_count<const N: usize>(
    flag: &'static str,
    weights: &[f64],
    what: &str,
) -> Result<[f64; N]> {
    <[f64; N]>::try_from(weights).map_err(|_| {
        let list = weights.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>();
        CliError::invalid(
            flag,
            list.join(","),
            format!(
                "{N} weights {what} ({})",
                if N == 2 {
                    "Q_THETA,Q_OMEGA"
                } else {
                    "Q_THETA,Q_X,Q_OMEGA,Q_V: the attitude, the position, the rates, the velocity"
                }
            ),
        )
    })
}

/// `--track FILE` read by `read` for `steps` steps, with `--track-weights` (`N` of them,
/// ones by default; `what` says for which problem): `None` without `--track`, refused
/// where the weights come alone.
#[allow(clippy::type_complexity)]
pub(crate) fn tracking<T, const N: usize>(
    options: &OptimizeOptions,
    steps: usize,
    read: impl Fn(&std::path::Path, usize) -> Result<Vec<T>>,
    what: &str,
) -> Result<Option<(Vec<T>, [f64; N])>> {
    match (&options.track, &options.track_weights) {
        (Some(path), weights) => {
            let weights = match weights {
                Some(w) => weight_count("--track-weights", &w.0, what)?,
                None => [1.0; N],
            };
            Ok(Some((read(path, steps)?, weights)))
        }
        (None, Some(_)) => Err(CliError::invalid(
            "--track-weights",
            "given",
            "they weigh a tracking cost: give --track FILE as well",
        )),
        (None, None) => Ok(None),
    }
}

/// The JSON of a `--track` file, and how to refuse it.
fn track_file(path: &std::path::Path) -> Result<serde_json::Value> {
    let refused = |reason: String| CliError::invalid("--track", path.display(), reason);
    let text =
        std::fs::read_to_string(path).map_err(|e| refused(format!("cannot be read: {e}")))?;
    serde_json::from_str(&text).map_err(|e| refused(format!("not JSON: {e}")))
}

/// The rows of `key` in a `--track` file's JSON, each `width` finite numbers.
fn track_rows(
    path: &std::path::Path,
    json: &serde_json::Value,
    key: &str,
    width: usize,
) -> Result<Vec<Vec<f64>>> {
    let refused = |reason: String| CliError::invalid("--track", path.display(), reason);
    let list = json[key].as_array().ok_or_else(|| {
        refused(format!(
            "no \"{key}\" array (the file holds R and omega per state, as simulate's JSON, and \
             for a body in space its position and velocity)"
        ))
    })?;
    list.iter()
        .enumerate()
        .map(|(k, row)| {
            let values: Option<Vec<f64>> = row
                .as_array()
                .map(|r| r.iter().map(serde_json::Value::as_f64).collect())
                .and_then(|v: Option<Vec<f64>>| v);
            match values {
                Some(v) if v.len() == width && v.iter().all(|x| x.is_finite()) => Ok(v),
                _ => Err(refused(format!("{key}[{k}] is not {width} finite numbers"))),
            }
        })
        .collect()
}

/// How many leading states of a `--track` file's `count` to skip for `steps` steps: none
/// for K, the start for K + 1.
fn track_skip(path: &std::path::Path, count: usize, steps: usize) -> Result<usize> {
    match count {
        n if n == steps => Ok(0),
        n if n == steps + 1 => Ok(1),
        n => Err(CliError::invalid(
            "--track",
            path.display(),
            format!(
                "{n} states for {steps} steps: give K (after the start) or K + 1 (with it); \
                 a simulate run with --h T/K and --t-end T records K + 1"
            ),
        )),
    }
}

/// The reference motion of a body in space's `--track`: the `steps` states after the
/// start of a JSON file with `R` (row-major), `position` (or `x`), `omega` and `velocity`
/// (world frame) per state, as simulate and `optimize --space` write them: poses and body
/// velocities `(Ω, Rᵀ ẋ)`.
pub(crate) fn reference_motion_in_space(
    path: &std::path::Path,
    steps: usize,
) -> Result<Vec<(lgsvi_mechanics::lie::SE3, nalgebra::Vector6<f64>)>> {
    let json = track_file(path)?;
    let key = if json["position"].is_array() {
        "position"
    } else {
        "x"
    };
    let attitudes = track_rows(path, &json, "R", 9)?;
    let positions = track_rows(path, &json, key, 3)?;
    let rates = track_rows(path, &json, "omega", 3)?;
    let velocities = track_rows(path, &json, "velocity", 3)?;
    let counts = [positions.len(), rates.len(), velocities.len()];
    if counts.iter().any(|n| *n != attitudes.len()) {
        return Err(CliError::invalid(
            "--track",
            path.display(),
            format!(
                "{} attitudes, {} positions, {} rates and {} velocities: one of each per state",
                attitudes.len(),
                counts[0],
                counts[1],
                counts[2]
            ),
        ));
    }
    let skip = track_skip(path, attitudes.len(), steps)?;
    (skip..attitudes.len())
        .map(|k| {
            let r = SO3::from_matrix_unchecked(nalgebra::Matrix3::from_row_slice(&attitudes[k]));
            if r.orthogonality_error() > 1e-9 {
                return Err(CliError::invalid(
                    "--track",
                    path.display(),
                    format!("R[{k}] is not a rotation"),
                ));
            }
            let v = r.matrix().transpose() * Vector3::from_column_slice(&velocities[k]);
            let w = &rates[k];
            Ok((
                lgsvi_mechanics::lie::SE3::new(r, Vector3::from_column_slice(&positions[k])),
                nalgebra::Vector6::new(w[0], w[1], w[2], v.x, v.y, v.z),
            ))
        })
        .collect()
}

/// The reference motion of `--track`: the `steps` states after the start of a JSON file
/// with `R` (row-major) and `omega` per state, as simulate and optimize write them.
fn reference_motion(path: &std::path::Path, steps: usize) -> Result<Vec<lgsvi_optimal::Target>> {
    let json = track_file(path)?;
    let (attitudes, rates) = (
        track_rows(path, &json, "R", 9)?,
        track_rows(path, &json, "omega", 3)?,
    );
    if attitudes.len() != rates.len() {
        return Err(CliError::invalid(
            "--track",
            path.display(),
            format!(
                "{} attitudes and {} rates: one of each per state",
                attitudes.len(),
                rates.len()
            ),
        ));
    }
    let skip = track_skip(path, attitudes.len(), steps)?;
    (skip..attitudes.len())
        .map(|k| {
            let attitude =
                SO3::from_matrix_unchecked(nalgebra::Matrix3::from_row_slice(&attitudes[k]));
            if attitude.orthogonality_error() > 1e-9 {
                return Err(CliError::invalid(
                    "--track",
                    path.display(),
                    format!("R[{k}] is not a rotation"),
                ));
            }
            let w = &rates[k];
            Ok((attitude, Vector3::new(w[0], w[1], w[2])))
        })
        .collect()
}

/// The heavy top's gravity from `--gravity` (and `--mass`, `--com`, `--gravity-direction`,
/// which need it), checked as the heavy top checks them; `None` for a free body.
fn heavy_top(options: &OptimizeOptions) -> Result<Option<lgsvi_optimal::Gravity>> {
    let Some(g) = options.gravity else {
        for (flag, given) in [
            ("--mass", options.mass.is_some()),
            ("--com", options.com.is_some()),
            ("--gravity-direction", options.gravity_direction.is_some()),
        ] {
            if given {
                return Err(CliError::invalid(
                    flag,
                    "given",
                    "it describes a heavy top: give --gravity G as well (or drop it for a free \
                     body, or give --space for a body in space)",
                ));
            }
        }
        return Ok(None);
    };
    let gravity = lgsvi_optimal::Gravity {
        mass: options.mass.unwrap_or(1.0),
        gravity: g,
        center_of_mass: Vector3::from(options.com.unwrap_or([0.0, 0.0, 1.0])),
        direction: Vector3::from(options.gravity_direction.unwrap_or([0.0, 0.0, 1.0])),
    };
    let inertia = Inertia::from_principal_moments([1.0; 3]).expect("a unit sphere");
    lgsvi_mechanics::HeavyTop::new(
        inertia,
        gravity.mass,
        gravity.gravity,
        gravity.center_of_mass,
        gravity.direction,
    )
    .map_err(|error| {
        let (flag, value) = match &error {
            lgsvi_mechanics::MechanicsError::InvalidSetting { name: "mass", .. }
            | lgsvi_mechanics::MechanicsError::NonFinite { what: "mass", .. } => {
                ("--mass", format!("{:?}", gravity.mass))
            }
            lgsvi_mechanics::MechanicsError::InvalidSetting {
                name: "gravity direction",
                ..
            }
            | lgsvi_mechanics::MechanicsError::NonFinite {
                what: "gravity direction",
                ..
            } => (
                "--gravity-direction",
                format!("{:?}", gravity.direction.as_slice()),
            ),
            lgsvi_mechanics::MechanicsError::NonFinite {
                what: "centre of mass",
                ..
            } => ("--com", format!("{:?}", gravity.center_of_mass.as_slice())),
            _ => ("--gravity", format!("{g:?}")),
        };
        let reason = error
            .to_string()
            .replace("with gravity_direction", "with --gravity-direction");
        CliError::invalid(flag, value, reason)
    })?;
    Ok(Some(gravity))
}

/// The reaction wheels of `--wheels` (and `--wheel-axes`, `--wheel-inertia`,
/// `--wheel-speeds0`, refused without it).
fn reaction_wheels(options: &OptimizeOptions) -> Result<Option<lgsvi_optimal::Wheels>> {
    if !options.wheels {
        for (flag, given) in [
            ("--wheel-axes", options.wheel_axes.is_some()),
            ("--wheel-inertia", options.wheel_inertia.is_some()),
            ("--wheel-speeds0", options.wheel_speeds0.is_some()),
        ] {
            if given {
                return Err(CliError::invalid(
                    flag,
                    "given",
                    "it describes reaction wheels: give --wheels as well",
                ));
            }
        }
        return Ok(None);
    }
    let axes = options
        .wheel_axes
        .unwrap_or([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
    // The solver checks the wheels (`named` maps its settings to these flags).
    Ok(Some(lgsvi_optimal::Wheels {
        axes: std::array::from_fn(|i| Vector3::new(axes[3 * i], axes[3 * i + 1], axes[3 * i + 2])),
        inertia: options.wheel_inertia.unwrap_or([0.05; 3]),
        speeds: Vector3::from(options.wheel_speeds0.unwrap_or([0.0; 3])),
    }))
}

/// A solver's error naming the flag to change.
fn named(error: OptimalError, options: &OptimizeOptions) -> CliError {
    use lgsvi_mechanics::MechanicsError as M;
    let flag = match &error {
        OptimalError::InvalidSetting { name, .. } => match *name {
            "t_end" => "--t-end",
            "steps" => "--steps",
            "torque_max" => "--torque-max",
            "tolerance" => "--tolerance",
            "start" => "--attitude0/--omega0",
            "target" => "--attitude-final/--omega-final",
            "inputs" => "--inputs",
            "terminal_cost" => "--terminal-cost",
            "track" => "--track-weights",
            "cost" => "--cost",
            "wheels" => "--wheels",
            "wheel axes" => "--wheel-axes",
            "wheel inertia" => "--wheel-inertia",
            "inertia and wheel inertia" => "--inertia/--wheel-inertia",
            "wheel speeds" => "--wheel-speeds0",
            "disturbance" => "--disturbance",
            _ => "--steps",
        },
        OptimalError::Infeasible { bounded: true, .. } => "--torque-max",
        OptimalError::Infeasible { bounded: false, .. } | OptimalError::Subproblem(_) => {
            "--t-end/--inertia/--steps"
        }
        OptimalError::NotConverged { .. } => "--max-iterations",
        OptimalError::Mechanics(M::InvalidSetting { name: "nodes", .. }) => "--nodes",
        OptimalError::Mechanics(
            M::DegenerateLagrangian { .. } | M::IllConditioned { .. } | M::InvalidInertia { .. },
        ) => "--inertia",
        OptimalError::Mechanics(_) => "--steps",
        _ => "--tolerance",
    };
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:?}"))
            .collect::<Vec<_>>()
            .join(",")
    };
    let value = match flag {
        "--t-end" => options.t_end.map_or(String::new(), |t| format!("{t:?}")),
        "--torque-max" => options.torque_max.map_or(String::new(), |u| list(&u)),
        "--steps" => options.steps.unwrap_or(40).to_string(),
        "--nodes" => options.nodes.unwrap_or(10).to_string(),
        "--max-iterations" => options.max_iterations.unwrap_or(100).to_string(),
        "--tolerance" => format!("{:?}", options.tolerance.unwrap_or(1e-10)),
        "--inertia" => list(&options.inertia.unwrap_or([3.3, 2.5, 3.4])),
        "--inputs" => "polynomial".into(),
        "--terminal-cost" => options
            .terminal_cost
            .as_ref()
            .map_or(String::new(), |w| list(&w.0)),
        "--track-weights" => options
            .track_weights
            .as_ref()
            .map_or(String::new(), |w| list(&w.0)),
        "--cost" => "time".into(),
        "--wheel-axes" => list(
            &options
                .wheel_axes
                .unwrap_or([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]),
        ),
        "--wheels" => "with --gravity".into(),
        "--wheel-inertia" => list(&options.wheel_inertia.unwrap_or([0.05; 3])),
        "--inertia/--wheel-inertia" => format!(
            "{}; {}",
            list(&options.inertia.unwrap_or([3.3, 2.5, 3.4])),
            list(&options.wheel_inertia.unwrap_or([0.05; 3]))
        ),
        "--wheel-speeds0" => list(&options.wheel_speeds0.unwrap_or([0.0; 3])),
        "--disturbance" => options.disturbance.map_or(String::new(), |d| list(&d)),
        _ => format!(
            "{}, {}, {}",
            options
                .t_end
                .map_or(String::from("(first guess)"), |t| format!("{t:?}")),
            list(&options.inertia.unwrap_or([3.3, 2.5, 3.4])),
            options.steps.unwrap_or(40)
        ),
    };
    let reason = recalling_disturbances(&error, &[("--disturbance", options.disturbance)]);
    CliError::invalid(flag, value, reason)
}

/// The solver's message; where the bounds left the target out of reach, it also recalls
/// the disturbances given (flag and value), which the inputs work against within the same
/// bounds.
pub(crate) fn recalling_disturbances(
    error: &OptimalError,
    disturbances: &[(&str, Option<[f64; 3]>)],
) -> String {
    let mut reason = error.to_string();
    if matches!(error, OptimalError::Infeasible { bounded: true, .. }) {
        let given: Vec<String> = disturbances
            .iter()
            .filter_map(|(flag, d)| {
                d.map(|d| format!("{flag} {}", d.map(|x| format!("{x:?}")).join(",")))
            })
            .collect();
        if !given.is_empty() {
            reason += &format!(
                " (and the inputs work against {} within the same bounds)",
                given.join(" and ")
            );
        }
    }
    reason
}

/// Entry `entry` of the optimal inputs over time, labelled `{name}_{color + 1}`: held over
/// each step, a staircase; polynomial within a step, its values at the Gauss points
/// (`nodes`, fractions of the step `h`) joined.
#[allow(clippy::too_many_arguments)]
pub fn input_series<const M: usize>(
    inputs: &[nalgebra::SVector<f64, M>],
    at_points: &[Vec<nalgebra::SVector<f64, M>>],
    nodes: &[f64],
    h: f64,
    times: &[f64],
    entry: usize,
    color: usize,
    name: &str,
) -> lgsvi_plot::Series {
    let points = if at_points.is_empty() {
        inputs
            .iter()
            .enumerate()
            .flat_map(|(k, u)| [(times[k], u[entry]), (times[k + 1], u[entry])])
            .collect()
    } else {
        at_points
            .iter()
            .enumerate()
            .flat_map(|(k, step)| {
                step.iter()
                    .zip(nodes)
                    .map(move |(u, c)| (times[k] + c * h, u[entry]))
            })
            .collect()
    };
    lgsvi_plot::Series {
        label: format!("{name}_{}", color + 1),
        points,
        style: lgsvi_plot::Style::Line,
        color,
    }
}

/// The torques, rates and attitude error over time.
fn figures(
    solution: &lgsvi_optimal::Solution,
    times: &[f64],
    error_deg: &[f64],
) -> Vec<(&'static str, lgsvi_plot::Figure)> {
    let axis = |points: Vec<(f64, f64)>, i: usize, name: &str| lgsvi_plot::Series {
        label: format!("{name}_{}", i + 1),
        points,
        style: lgsvi_plot::Style::Line,
        color: i,
    };
    let figure = |title: &str, y: &str, series| lgsvi_plot::Figure {
        title: title.into(),
        x_label: "t (s)".into(),
        y_label: y.into(),
        x_log: false,
        y_log: false,
        series,
        hlines: vec![],
    };
    let torque = (0..3)
        .map(|i| {
            input_series(
                &solution.inputs,
                &solution.inputs_at_points,
                &solution.quadrature_nodes,
                solution.h,
                times,
                i,
                i,
                "u",
            )
        })
        .collect();
    let rates = (0..3)
        .map(|i| {
            let points = solution
                .states
                .iter()
                .map(|s| (s.time, s.velocity[i]))
                .collect();
            axis(points, i, "omega")
        })
        .collect();
    let error = vec![lgsvi_plot::Series {
        label: "angle to the target".into(),
        points: times
            .iter()
            .copied()
            .zip(error_deg.iter().copied())
            .collect(),
        style: lgsvi_plot::Style::Line,
        color: 0,
    }];
    vec![
        (
            "_torques",
            figure(
                match (
                    solution.wheel_speeds.is_empty(),
                    solution.inputs_at_points.is_empty(),
                ) {
                    (true, true) => "optimal torques (held over each step)",
                    (true, false) => "optimal torques (at each step's Gauss points)",
                    (false, true) => "optimal wheel motor torques (held over each step)",
                    (false, false) => "optimal wheel motor torques (at each step's Gauss points)",
                },
                "u (N·m)",
                torque,
            ),
        ),
        ("_rates", figure("body rates", "Ω (rad/s)", rates)),
        (
            "_attitude_error",
            figure("attitude error", "angle to the target (deg)", error),
        ),
    ]
}
