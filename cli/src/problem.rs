//! A problem resolved from options: the system, its initial state and the integrator's
//! settings, with the paper's parameters as defaults.

use crate::config::{Numbers, SimulateOptions, SystemKind};
use crate::error::{CliError, Result};
use lgsvi_experiments::control::SampledLaw;
use lgsvi_experiments::record::Check;
use lgsvi_experiments::scenario::{drive, Model, Orbit, Scenario, Space, Top, Wheels};
use lgsvi_experiments::stop::{StopWhen, Watch};
use lgsvi_experiments::ExperimentError;
use lgsvi_mechanics::built_in::BuiltInSo3;
use lgsvi_mechanics::control::PdLaw;
use lgsvi_mechanics::forces::AttitudeSpring;
use lgsvi_mechanics::lie::So3Chart;
use lgsvi_mechanics::settings::{DEFAULT_ADAPTIVE_NODES, ROUNDING_FLOOR};
use lgsvi_mechanics::tolerance::{first_nodes, step_count};
use lgsvi_mechanics::{Inertia, MechanicsError, StepSettings};
use nalgebra::{Matrix3, Vector3};
use serde_json::Value;

/// The paper's parameters per system (`docs/paper-notes.md` §4), `(J_d, Ω₀)`: case A and
/// case B; a small spacecraft for the gyrostat (`J = diag(10, 12, 8)` with the wheels
/// locked, turning slowly); the orbiting body's reference case O1 of
/// `cases/data/se3_forced_refs.json` (`J = diag(0.3, 0.2, 0.4)`).
fn defaults(system: SystemKind) -> ([f64; 3], [f64; 3]) {
    let case = |name| {
        let case = named_case(name);
        (
            case.inertia_d.expect("the paper's cases state J_d"),
            case.omega0.into(),
        )
    };
    match system {
        SystemKind::RigidBody | SystemKind::Se3Body => case("A"),
        SystemKind::HeavyTop => case("B"),
        SystemKind::Gyrostat => ([5.0, 3.0, 7.0], [0.01, -0.02, 0.03]),
        SystemKind::OrbitingBody => ([0.15, 0.25, 0.05], [0.2, -0.3, 0.5]),
    }
}

/// A case the binary names itself (`"A"`, `"B"`, `"C"`, `"O1"`, `"F1"`): a literal, so
/// its absence would be a defect of the build (the cases crate's tests list them).
fn named_case(name: &str) -> &'static lgsvi_cases::Case {
    lgsvi_cases::case(name).unwrap_or_else(|e| panic!("{e}"))
}

/// The most steps one run may take (a run of 10⁹ steps takes hours; a mistyped horizon
/// or step should not run for ever).
pub const MAX_RUN_STEPS: f64 = 1e9;

/// The number of steps `h` that make up `t_end`, or a one-line error: the method has a
/// fixed step, and a run ends at a whole number of them. A relative slack of 1e-9 of a
/// step absorbs the rounding of decimal inputs (`t_end = 10`, `h = 0.1`).
pub fn whole_steps(t_end: f64, h: f64) -> Result<usize> {
    let ratio = t_end / h;
    if ratio.is_nan() || ratio > MAX_RUN_STEPS {
        return Err(CliError::TooManySteps {
            t_end,
            h,
            steps: ratio,
            most: MAX_RUN_STEPS,
        });
    }
    let steps = ratio.round();
    if (ratio - steps).abs() > 1e-9 * steps.max(1.0) {
        return Err(CliError::NotWholeSteps {
            t_end,
            h,
            below: decimal(ratio.floor() * h),
            above: decimal(ratio.ceil() * h),
            fitted: decimal(t_end / ratio.ceil()),
            steps: ratio.ceil(),
        });
    }
    Ok(steps as usize)
}

/// `x` to 12 significant digits, as a suggestion to type back: `3 × 0.3` is printed `0.9`,
/// not `0.8999999999999999`, and the whole-step check's slack (1e-9 of a step) accepts it.
fn decimal(x: f64) -> f64 {
    format!("{x:.11e}").parse().unwrap_or(x)
}

/// The step settings of `options` over `[0, t_end]`; with `--tol`, the library's policy
/// (`lgsvi_mechanics::tolerance`): the step (unless given) turns `STEP_ROTATION` at the
/// rate `rate` and divides `t_end` (`step_count`), the first step takes `first_nodes`, and
/// the nodes adapt to an error per unit time of `tol / t_end`.
/// Every step must divide `t_end` in at most [`MAX_RUN_STEPS`] steps.
pub fn step_settings(options: &SimulateOptions, t_end: f64, rate: f64) -> Result<StepSettings> {
    let chart = options.chart.map(Into::into).unwrap_or_default();
    let h = match (options.h, options.tol) {
        (Some(h), _) => h,
        (None, Some(_)) if t_end > 0.0 => {
            t_end / step_count(t_end, rate, So3Chart::max_rotation_angle(&chart))
        }
        _ => 0.5,
    };
    let first = options.tol.map_or(10, first_nodes);
    let mut settings = StepSettings::new(h, options.nodes.unwrap_or(first))?;
    // A step the library takes, then a whole number of them, before the tolerance's share
    // per step is judged (a share of a 10¹²-step run is below any floor).
    whole_steps(t_end, h)?;
    if let Some(m) = options.quad {
        settings = settings.with_quadrature_points(m)?;
    }
    if let Some(tol) = options.tol {
        let (least, most) = DEFAULT_ADAPTIVE_NODES;
        if let Some(n) = options.nodes.filter(|n| !(least..=most).contains(n)) {
            return Err(CliError::invalid(
                "--nodes",
                n,
                format!(
                    "with --tol, --nodes is the first step's count within the adaptive \
                     range {least} to {most}"
                ),
            ));
        }
        // The library refuses a step's share below the rounding of a step (4ε; the
        // tolerance's positivity was checked with the other flags): said here as the
        // run's floor, whatever its nodes.
        settings = settings
            .with_tolerance(tol / t_end.max(h))
            .map_err(|error| match error {
                MechanicsError::InvalidSetting { name: "tol", .. } => {
                    let steps = (t_end.max(h) / h).round().max(1.0);
                    let floor = steps * ROUNDING_FLOOR;
                    CliError::invalid(
                        "--tol",
                        format!("{tol:e}"),
                        format!(
                            "below what double precision can deliver over this run: {steps} \
                             steps of h = {h} round to about {floor:.1e} (4ε each); ask for at \
                             least that, or take longer steps (--h)"
                        ),
                    )
                }
                other => other.into(),
            })?;
    }
    Ok(settings
        .with_chart(chart)
        .with_matching(options.matching.map(Into::into).unwrap_or_default())
        .with_jacobian(options.jacobian.map(Into::into).unwrap_or_default()))
}

/// The condition number of the inertia (largest over least principal moment) from which a
/// fixed run is measured by its companion: the error in the velocity is the momentum's
/// divided by the inertia, so the steps' errors along the thin axis grow with the
/// condition while their coefficients' decay (the estimate) does not see it. Measured on
/// rods `J = (δ, 1, 1)` against the exact solution (`h = 0.5`, `n = 10`, T = 4): the
/// estimate 7e-15 against errors 3e-14 (δ = 0.1), 3e-13 (0.01), 1e-12 (1e-3), 2e-10
/// (1e-4), 2.5e-7 (1e-5); the companion measured 5e-13, 5e-12, 3e-11, 1e-7.
const BLIND_CONDITION: f64 = 100.0;

/// Whether a fixed run's sum of local estimates is known to fall more than 10× below its
/// error, so that it is measured by its companion instead: an inertia conditioned worse
/// than [`BLIND_CONDITION`], or any body on SE(3), whose momentum update moves the linear
/// momentum's rounding (`ε h m|v|²` a step) into the angular momentum (measured: the
/// free body at `|v| = 10` 40× below, an orbiting body of mass 100 17× below, a satellite
/// in low Earth orbit 10⁹× below its companion, which the closed forms confirm).
fn estimates_are_blind(scenario: &Scenario) -> bool {
    let (j_min, j_max) = moment_range(&scenario.inertia);
    scenario.motion.is_some() || j_max >= BLIND_CONDITION * j_min
}

/// The least and the largest principal moment.
pub fn moment_range(inertia: &Inertia) -> (f64, f64) {
    let moments = inertia.principal_moments();
    let least = moments.into_iter().fold(f64::INFINITY, f64::min);
    let most = moments.into_iter().fold(0.0, f64::max);
    (least, most)
}

/// Refuses a fixed run whose damping is too stiff for its steps: where `c·h/J_min` exceeds
/// `n²/2`, a polynomial of degree `n − 1` cannot follow the decay `e^{−ct/J}` within a step,
/// and the step's own error estimate (the decay of its coefficients) falls below the true
/// error; measured on the rigid body with `n` = 4, 10 and 20: the estimate is above the
/// error up to `n²/2` and 2–45× below it from `n²` on, where the companion check (`--check`)
/// fails too.
fn check_damping_stiffness(damping: f64, j_min: f64, settings: &StepSettings) -> Result<()> {
    let (h, n) = (settings.h(), settings.nodes() as f64);
    let stiffness = damping * h / j_min;
    let limit = 0.5 * n * n;
    if stiffness > limit {
        let h_max = limit * j_min / damping;
        let n_min = (2.0 * stiffness).sqrt().ceil();
        return Err(CliError::invalid(
            "--damping",
            damping,
            format!(
                "the damping decays the rates at c/J_min = {:.3e} per unit time (J_min = {}, the least \
                 principal moment), {stiffness:.3e} times over a step of h = {h}: more than a \
                 step of {n} nodes follows (n²/2 = {limit}), and the run's error estimate would \
                 fall below its true error; shorten the step (--h {h_max:.3e} or less), raise \
                 --nodes to {n_min} or more, or give --tol (its steps follow the decay)",
                damping / j_min,
                j_min,
            ),
        ));
    }
    Ok(())
}

/// Everything a run needs.
#[derive(Debug, Clone)]
pub struct Problem {
    /// The system, its start and the run's settings.
    pub scenario: Scenario,
    /// The system's name (`--system`).
    pub name: &'static str,
    /// The system's own parameters (the top's mass, the wheels, the body in space's
    /// start), as resolved from the flags.
    pub model: Model,
    pub t_end: f64,
    pub every: usize,
    pub quiet: bool,
    /// Whether a companion checks the run: a `--tol` run unless `--no-check`, a fixed run
    /// with `--check`.
    pub check: Check,
    /// Where the run stops early (`--stop-when`) and the condition whose settling time it
    /// reports (`--settle-when`).
    pub watch: Watch,
    /// The inputs as given, for the output's `description`.
    pub description: serde_json::Value,
}

/// The sampled PD law of `--sample-period` (with `--attitude-gain`, `--damping` as its
/// gains and `--torque-limit`), `None` for a continuous law; without `--h`, the step
/// becomes the longest up to 0.5 that divides the period (and the run, where one at
/// least an eighth as long does).
fn sampled_law(
    options: &mut SimulateOptions,
    spring: AttitudeSpring,
    damping: f64,
) -> Result<Option<SampledLaw>> {
    let Some(period) = options.sample_period else {
        if let Some(limit) = options.torque_limit {
            let reason = "the limit applies to a sampled law: give --sample-period (a limit on \
                          the continuous law is not built)";
            return Err(CliError::invalid("--torque-limit", limit, reason));
        }
        return Ok(None);
    };
    if !(period.is_finite() && period > 0.0) {
        let reason = "the controller's sample period must be positive and finite";
        return Err(CliError::invalid("--sample-period", period, reason));
    }
    if options.tol.is_some() {
        let reason = "a --tol run chooses its own step, which a sampled law needs to divide \
                      its period: give --h instead (a period divided by a whole number)";
        return Err(CliError::invalid("--sample-period", period, reason));
    }
    if options.attitude_gain.is_none() && options.damping.is_none() {
        let reason = "the sampled law's gains are --attitude-gain K and --damping C: give \
                      at least one";
        return Err(CliError::invalid("--sample-period", period, reason));
    }
    let law = PdLaw::new(*spring.target(), spring.stiffness(), damping)?;
    let law = match options.torque_limit {
        Some(limit) => law.with_limit(limit).map_err(|_| {
            let reason = "the actuator's largest torque must be positive (N·m)";
            CliError::invalid("--torque-limit", limit, reason)
        })?,
        None => law,
    };
    if options.h.is_none() {
        // The longest step up to 0.5 that divides the period and, where one at least an
        // eighth as long does, the run too (else the run's length is refused, naming the
        // ends that would fit).
        let t_end = options.t_end.unwrap_or(10.0);
        let least = (period / 0.5).ceil().clamp(1.0, 1e6) as u32;
        let whole = |x: f64| (x - x.round()).abs() <= 1e-9 * x.max(1.0);
        let steps = (least..=least * 8)
            .find(|&m| whole(t_end * f64::from(m) / period))
            .unwrap_or(least);
        let h = period / f64::from(steps);
        if !(lgsvi_mechanics::settings::STEP_RANGE.0..=0.5).contains(&h) {
            let reason = "the default step (at most 0.5, up to a million a period) cannot \
                          divide it: give --h, a period divided by a whole number";
            return Err(CliError::invalid("--sample-period", period, reason));
        }
        options.h = Some(h);
    }
    Ok(Some(SampledLaw::new(law, period).map_err(scenario_error)?))
}

/// Refuses a system's flag given for another system: the first, in the order below.
fn check_applicable(options: &SimulateOptions, kind: SystemKind) -> Result<()> {
    use SystemKind::*;
    let (top, moving, wheels) = (
        &[HeavyTop][..],
        &[Se3Body, OrbitingBody][..],
        &[Gyrostat][..],
    );
    let (massive, bodies) = (&[HeavyTop, Se3Body, OrbitingBody], &[RigidBody, HeavyTop]);
    let forced = &[RigidBody, HeavyTop, Se3Body, OrbitingBody][..];
    let mass_why = match kind {
        Gyrostat => "(a gyrostat's inertia J holds its mass distribution)",
        _ => "(a free rotating body's motion does not depend on its mass)",
    };
    let mass_applies = format!("heavy-top, se3-body and orbiting-body {mass_why}");
    let o = options;
    let rows: [(&'static str, bool, &[SystemKind], &str); 16] = [
        ("--mass", o.mass.is_some(), massive, &mass_applies),
        ("--gravity", o.gravity.is_some(), top, "the heavy top (--system heavy-top)"),
        ("--com", o.com.is_some(), top, "the heavy top (--system heavy-top)"),
        ("--gravity-direction", o.gravity_direction.is_some(), top, "the heavy top (--system heavy-top)"),
        ("--torque", o.torque.is_some(), forced, "rigid-body, heavy-top, se3-body and orbiting-body (a gyrostat's wheels take --wheel-torque)"),
        ("--damping", o.damping.is_some(), forced, "rigid-body, heavy-top, se3-body and orbiting-body"),
        ("--attitude-gain", o.attitude_gain.is_some(), forced, "rigid-body, heavy-top, se3-body and orbiting-body (a gyrostat turns by its wheels, --wheel-torque)"),
        ("--sample-period", o.sample_period.is_some(), forced, "rigid-body, heavy-top, se3-body and orbiting-body (a gyrostat turns by its wheels, --wheel-torque)"),
        ("--exact", o.exact, bodies, "the free rigid body (--system rigid-body)"),
        ("--position0", o.position0.is_some(), moving, "se3-body and orbiting-body"),
        ("--velocity0", o.velocity0.is_some(), moving, "se3-body and orbiting-body"),
        ("--wheel-axes", o.wheel_axes.is_some(), wheels, "the gyrostat (--system gyrostat)"),
        ("--wheel-inertia", o.wheel_inertia.is_some(), wheels, "the gyrostat (--system gyrostat)"),
        ("--wheel-speeds0", o.wheel_speeds0.is_some(), wheels, "the gyrostat (--system gyrostat)"),
        ("--wheel-torque", o.wheel_torque.is_some(), wheels, "the gyrostat (--system gyrostat)"),
        ("--mu", o.mu.is_some(), &[OrbitingBody], "orbiting-body"),
    ];
    match rows
        .iter()
        .find(|(_, given, on, _)| *given && !on.contains(&kind))
    {
        // The free body's own message: it is the heavy top without gravity.
        Some((flag, _, on, _)) if kind == RigidBody && *on == top => {
            Err(CliError::HeavyTopOnly { flag })
        }
        Some((flag, _, _, applies)) => Err(CliError::NotForSystem {
            flag,
            system: kind.name(),
            applies: applies.to_string(),
        }),
        None => Ok(()),
    }
}

/// The inertia from whichever of `--inertia`, `--inertia-d`, `--inertia-tensor` is given
/// (the system's default if none).
fn inertia(options: &SimulateOptions, default_jd: [f64; 3]) -> Result<Inertia> {
    let input = |flag| move |source| CliError::Input { flag, source };
    match (options.inertia, options.inertia_d, options.inertia_tensor) {
        (Some(j), None, None) => Inertia::from_principal_moments(j).map_err(input("--inertia")),
        (None, Some(jd), None) => Inertia::from_paper_jd(jd).map_err(input("--inertia-d")),
        (None, None, Some(t)) => {
            Inertia::from_tensor(Matrix3::from_row_slice(&t)).map_err(input("--inertia-tensor"))
        }
        (None, None, None) => Ok(Inertia::from_paper_jd(default_jd)?),
        (Some(_), Some(_), _) => Err(CliError::Conflict("--inertia", "--inertia-d")),
        (Some(_), _, Some(_)) => Err(CliError::Conflict("--inertia", "--inertia-tensor")),
        (_, Some(_), Some(_)) => Err(CliError::Conflict("--inertia-d", "--inertia-tensor")),
    }
}

/// The system's own parameters from the flags over their defaults; those given go into
/// `description`.
fn model(o: &SimulateOptions, kind: SystemKind, description: &mut Value) -> Result<Model> {
    let or = |given: Option<[f64; 3]>, default: Vector3<f64>| given.map_or(default, Vector3::from);
    Ok(match kind {
        SystemKind::RigidBody => Model::RigidBody,
        SystemKind::Gyrostat => Model::Gyrostat(wheels(o, description)?),
        SystemKind::HeavyTop => {
            let paper = named_case("B");
            // The compiled-in case B has both (checked by the cases' test).
            let top = Top {
                mass: o.mass.unwrap_or(paper.mass.expect("case B's mass")),
                gravity: o.gravity.unwrap_or(paper.gravity.expect("case B's g")),
                com: or(o.com, Vector3::z()),
                direction: or(o.gravity_direction, Vector3::z()),
            };
            description["mass"] = top.mass.into();
            description["gravity"] = top.gravity.into();
            description["com"] = top.com.as_slice().into();
            Model::HeavyTop(top)
        }
        SystemKind::Se3Body | SystemKind::OrbitingBody => {
            let orbit = Orbit::default();
            let orbiting = kind == SystemKind::OrbitingBody;
            let start = if orbiting {
                orbit.body
            } else {
                Space::default()
            };
            let body = Space {
                mass: o.mass.unwrap_or(start.mass),
                position: or(o.position0, start.position),
                velocity: or(o.velocity0, start.velocity),
            };
            description["mass"] = body.mass.into();
            description["position0"] = body.position.as_slice().into();
            description["velocity0"] = body.velocity.as_slice().into();
            if orbiting {
                let mu = o.mu.unwrap_or(orbit.mu);
                description["mu"] = mu.into();
                Model::Orbiting(Orbit { body, mu })
            } else {
                Model::FreeInSpace(body)
            }
        }
    })
}

/// The gyrostat's wheels from the wheel flags: one to four axes (the body axes unless
/// given), one inertia, start speed and motor torque per wheel; the wheels as given (the
/// axes before normalising) go into `description`.
fn wheels(options: &SimulateOptions, description: &mut Value) -> Result<Wheels> {
    let given = |n: &Option<Numbers>| n.clone().map(|n| n.0);
    let axes =
        given(&options.wheel_axes).unwrap_or_else(|| vec![1., 0., 0., 0., 1., 0., 0., 0., 1.]);
    let k = axes.len() / 3;
    if !axes.len().is_multiple_of(3) || !(1..=4).contains(&k) {
        return Err(CliError::invalid(
            "--wheel-axes",
            format!("{axes:?}"),
            "three numbers per wheel, 1 to 4 wheels",
        ));
    }
    let per_wheel = |flag: &'static str, values: Option<Vec<f64>>, default: &[f64]| {
        let values = values.unwrap_or_else(|| default.to_vec());
        if values.len() == k {
            Ok(values)
        } else {
            Err(CliError::invalid(
                flag,
                format!("{values:?}"),
                format!("one number per wheel: --wheel-axes gives {k}"),
            ))
        }
    };
    let defaults = Wheels::on(
        axes.chunks_exact(3)
            .map(Vector3::from_column_slice)
            .collect(),
    );
    let mut wheels = defaults.clone();
    wheels.inertia = per_wheel(
        "--wheel-inertia",
        given(&options.wheel_inertia),
        &defaults.inertia,
    )?;
    wheels.speeds0 = per_wheel(
        "--wheel-speeds0",
        given(&options.wheel_speeds0),
        &defaults.speeds0,
    )?;
    wheels.torque = per_wheel(
        "--wheel-torque",
        given(&options.wheel_torque),
        &defaults.torque,
    )?;
    description["wheel_axes"] = axes.into();
    description["wheel_inertia"] = wheels.inertia.clone().into();
    description["wheel_speeds0"] = wheels.speeds0.clone().into();
    description["wheel_torque"] = wheels.torque.clone().into();
    Ok(wheels)
}

impl Problem {
    /// Resolves config file, flags and defaults.
    pub fn resolve(options: SimulateOptions) -> Result<(Problem, SimulateOptions)> {
        let mut options = options.merged_with_config()?;
        let kind = options.system();
        let (default_jd, default_omega0) = defaults(kind);
        let omega0 = Vector3::from(*options.omega0.get_or_insert(default_omega0));
        let inertia = inertia(&options, default_jd)?;
        check_applicable(&options, kind)?;
        let torque = Vector3::from(options.torque.unwrap_or([0.0; 3]));
        let damping = options.damping.unwrap_or(0.0);
        let t_end = options.t_end.unwrap_or(10.0);
        let every = options.every.unwrap_or(1);
        let tol = options.tol;
        let invalid = |flag, value: &dyn std::fmt::Display, reason: &str| {
            Err(CliError::invalid(flag, value, reason))
        };
        if !(damping.is_finite() && damping >= 0.0) {
            let reason = "the damping c of the torque −cΩ must be finite and non-negative";
            return invalid("--damping", &damping, reason);
        }
        let target = options.target()?;
        let gain = options.attitude_gain.unwrap_or(0.0);
        let spring = AttitudeSpring::new(target, gain).map_err(|_| {
            let reason = "the gain K of the torque −Kθ toward the target attitude must be \
                          finite and non-negative (N·m per radian)";
            CliError::invalid("--attitude-gain", gain, reason)
        })?;
        let control = sampled_law(&mut options, spring, damping)?;
        if !(t_end.is_finite() && t_end >= 0.0) {
            return invalid("--t-end", &t_end, "must be finite and non-negative");
        }
        if let Some(tol) = tol.filter(|t| !(t.is_finite() && *t > 0.0)) {
            let reason = "the accuracy must be positive and finite, e.g. 1e-10";
            return invalid("--tol", &tol, reason);
        }
        if tol.is_some() && options.quad.is_some() {
            return Err(CliError::Conflict("--tol", "--quad"));
        }
        if tol.is_some() && options.check {
            let reason = "--tol runs are checked anyway (--no-check skips it): drop --check";
            return invalid("--check", &"given", reason);
        }
        if tol.is_none() && options.no_check {
            let reason = "it skips the check of a --tol run: give --tol, or drop --no-check";
            return invalid("--no-check", &"given", reason);
        }
        if every == 0 {
            return invalid("--every", &0, "keep every K-th step with K ≥ 1");
        }
        // The inertia as the user gave it (J or J_d), the other form derived from it, so the
        // description echoes the input without the rounding of a round trip.
        let inertia_j = options.inertia.unwrap_or(inertia.principal_moments());
        let inertia_jd = options
            .inertia_d
            .or(
                (options.inertia.is_none() && options.inertia_tensor.is_none())
                    .then_some(default_jd),
            )
            .unwrap_or(inertia.paper_jd());
        let mut description = serde_json::json!({
            "inertia_J": inertia_j,
            "inertia_Jd": inertia_jd,
            "omega0": options.omega0,
            "system": kind.name(),
        });
        if let Some(t) = options.inertia_tensor {
            description["inertia_tensor"] = t.as_slice().into();
        }
        if options.torque.is_some() {
            description["torque"] = torque.as_slice().into();
        }
        if options.damping.is_some() {
            description["damping"] = damping.into();
        }
        if options.attitude_gain.is_some() {
            description["attitude_gain"] = gain.into();
        }
        if let Some(period) = options.sample_period {
            description["sample_period"] = period.into();
        }
        if let Some(limit) = options.torque_limit {
            description["torque_limit"] = limit.into();
        }
        if let Some(q) = options.target_quaternion {
            description["target_quaternion"] = q.as_slice().into();
        }
        if let Some(tol) = options.tol {
            description["tolerance"] = tol.into();
        }
        let model = model(&options, kind, &mut description)?;
        // A sampled law takes the gains: the continuous drive keeps the torque alone.
        let drive = match control {
            Some(_) => drive(torque, 0.0, AttitudeSpring::none()),
            None => drive(torque, damping, spring),
        };
        let mut scenario =
            Scenario::driven(model.clone(), inertia, options.attitude()?, omega0, drive)
                .map_err(scenario_error)?;
        if let Some(control) = control {
            scenario = scenario.with_control(control).map_err(scenario_error)?;
        }
        if let BuiltInSo3::Top(top) = &scenario.system.system {
            description["gravity_direction"] = top.gravity_direction().as_slice().into();
        }
        // A damping torque −cΩ makes the rates decay at up to c/J_min: a motion rate of its
        // own, which a --tol run's first step follows as it follows the spin.
        let (j_min, _) = moment_range(&inertia);
        let decay = damping / j_min;
        // The spring's frequency √(K/J_min) likewise (the rate of a small libration about
        // the target).
        let libration = (gain / j_min).sqrt();
        let rate = scenario.rate()?.max(decay).max(libration);
        let settings = step_settings(&options, t_end, rate)?;
        if let Some(control) = &scenario.control {
            control.check_step(settings.h()).map_err(|_| {
                let period = control.period();
                let reason = format!(
                    "the sample period must be a whole number of steps of h = {}: take --h \
                     as the period divided by a whole number (e.g. {})",
                    settings.h(),
                    period / (period / settings.h()).ceil()
                );
                CliError::invalid("--sample-period", period, reason)
            })?;
        } else if options.tol.is_none() {
            check_damping_stiffness(damping, j_min, &settings)?;
        }
        // Where the steps' own estimates are known to miss the error, a fixed run is
        // measured by its companion (see `estimates_are_blind`).
        let estimates_are_blind = estimates_are_blind(&scenario);
        let problem = Problem {
            scenario: scenario.with_settings(settings),
            name: kind.name(),
            model,
            t_end,
            every,
            quiet: options.quiet,
            check: match (options.tol, options.no_check, options.check) {
                (Some(tol), false, _) => Check::Tolerance(tol),
                (None, _, true) => Check::Measure,
                (None, _, false) if estimates_are_blind => Check::Measure,
                _ => Check::None,
            },
            description,
            watch: Watch {
                stop: condition(&options.stop_when, "--stop-when")?,
                settle: condition(&options.settle_when, "--settle-when")?,
                // A run with a target (or an attitude law toward the identity) measures
                // its pointing error from it.
                target: (options.target_quaternion.is_some() || options.attitude_gain.is_some())
                    .then_some(target),
            },
        };
        Ok((problem, options))
    }

    /// A refused condition (`ExperimentError::Stop`) as an error naming the flag that gave
    /// it, `--settle-when` or `--stop-when`.
    pub fn condition_error(&self, condition: String, reason: String) -> CliError {
        let flag = if self.watch.names_settle(&condition) {
            "--settle-when"
        } else {
            "--stop-when"
        };
        CliError::invalid(flag, condition, reason)
    }

    /// Refuses a condition on a quantity the system lacks, before any run (a Monte Carlo
    /// run's members would each fail on it), naming its flag.
    pub fn check_watch(&self) -> Result<()> {
        self.scenario
            .check_watch(&self.watch)
            .map_err(|error| match error {
                ExperimentError::Stop { condition, reason } => {
                    self.condition_error(condition, reason)
                }
                other => other.into(),
            })
    }

    /// The run's settings.
    pub fn settings(&self) -> StepSettings {
        self.scenario.settings
    }
}

/// The condition a flag gives, parsed; an error naming the flag.
fn condition(text: &Option<String>, flag: &'static str) -> Result<Option<StopWhen>> {
    text.as_deref()
        .map(|text| {
            text.parse::<StopWhen>()
                .map_err(|reason| CliError::invalid(flag, text, reason))
        })
        .transpose()
}

/// A scenario's refusal, naming the flags.
fn scenario_error(error: ExperimentError) -> CliError {
    match error {
        ExperimentError::Parameter { parameter, source } => CliError::Input {
            flag: match parameter {
                "mass" => "--mass",
                "mu" => "--mu",
                "mass/mu" => "--mass/--mu",
                "axes/inertia" => "--wheel-axes/--wheel-inertia",
                "speeds0/torque" => "--wheel-speeds0/--wheel-torque",
                "control" => "--sample-period",
                _ => "--torque/--damping",
            },
            source,
        },
        ExperimentError::InvalidStart { value, reason } => CliError::Invalid {
            flag: "--position0",
            value,
            reason,
        },
        // A system's own refusal (the heavy top's parameters), naming its flag.
        ExperimentError::Mechanics(source) => source.into(),
        other => other.into(),
    }
}
