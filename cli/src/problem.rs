//! A problem resolved from options: the system, its initial state and the integrator's
//! settings, with the paper's parameters as defaults.

use crate::config::{Numbers, SimulateOptions, SystemKind};
use crate::error::{CliError, Result};
use lgsvi_experiments::{Subject, Symmetry, Tracker};
use lgsvi_mechanics::exact::FreeRigidBodyExact;
use lgsvi_mechanics::gyrostat::{BodyAndWheels, BodyWheels, Gyrostat};
use lgsvi_mechanics::lie::{ChartKind, SE3, SO3};
use lgsvi_mechanics::{
    AngularDamping, BodyTorque, Forced, FreeBody, GroupChart, GroupLagrangian, HeavyTop, Inertia,
    Integrator, MechanicsError, OrbitingBody, RigidBody, RigidMotions, StepSettings,
    DEFAULT_ADAPTIVE_NODES, ROUNDING_FLOOR,
};
use nalgebra::{Matrix3, SVector, Vector3};

/// The paper's parameters per system (`docs/paper-notes.md` §4): case A and case B.
pub struct Defaults {
    pub inertia_d: [f64; 3],
    pub omega0: [f64; 3],
}

pub fn defaults(system: SystemKind) -> Defaults {
    let case = named_case(match system {
        SystemKind::RigidBody | SystemKind::Se3Body => "A",
        SystemKind::HeavyTop => "B",
        SystemKind::Gyrostat => {
            // A small spacecraft: J = diag(10, 12, 8) with the wheels locked, i.e.
            // J_d = (5, 3, 7), turning slowly.
            return Defaults {
                inertia_d: [5.0, 3.0, 7.0],
                omega0: [0.01, -0.02, 0.03],
            };
        }
        SystemKind::OrbitingBody => {
            // The orbiting body's reference case (cases/data/se3_forced_refs.json, O1):
            // J = diag(0.3, 0.2, 0.4), i.e. J_d = (0.15, 0.25, 0.05).
            return Defaults {
                inertia_d: [0.15, 0.25, 0.05],
                omega0: [0.2, -0.3, 0.5],
            };
        }
    });
    Defaults {
        inertia_d: case.inertia_d.expect("the paper's cases state J_d"),
        omega0: case.omega0.into(),
    }
}

/// A case the binary names itself (`"A"`, `"B"`, `"C"`, `"O1"`, `"F1"`): a literal, so
/// its absence would be a defect of the build (the cases crate's tests list them).
pub fn named_case(name: &str) -> &'static lgsvi_cases::Case {
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
            below: ratio.floor() * h,
            above: ratio.ceil() * h,
            fitted: t_end / ratio.ceil(),
            steps: ratio.ceil(),
        });
    }
    Ok(steps as usize)
}

pub use lgsvi_experiments::tolerance::{first_nodes as tolerance_first_nodes, pendulum_frequency};

/// A `--tol` run's step over `[0, t_end]` at the motion's rate `rate` in `chart`
/// (`lgsvi_experiments::tolerance::step_count`), refused above [`MAX_RUN_STEPS`].
pub fn tolerance_step(t_end: f64, rate: f64, chart: ChartKind) -> Result<f64> {
    let steps = lgsvi_experiments::tolerance::step_count(t_end, rate, chart);
    if steps > MAX_RUN_STEPS {
        return Err(CliError::TooManySteps {
            t_end,
            h: t_end / steps,
            steps,
            most: MAX_RUN_STEPS,
        });
    }
    Ok(t_end / steps)
}

/// The step settings of `options` over `[0, t_end]`; with `--tol`, the step (unless given)
/// takes `lgsvi_experiments::tolerance::STEP_ROTATION` at the rate `rate` and divides `t_end`, and the
/// nodes adapt to an error per unit time of `tol / t_end`.
pub fn step_settings(options: &SimulateOptions, t_end: f64, rate: f64) -> Result<StepSettings> {
    let chart = options.chart.map(Into::into).unwrap_or_default();
    let h = match (options.h, options.tol) {
        (Some(h), _) => h,
        (None, Some(_)) if t_end > 0.0 => tolerance_step(t_end, rate, chart)?,
        _ => 0.5,
    };
    let first = options.tol.map_or(10, tolerance_first_nodes);
    let mut settings = StepSettings::new(h, options.nodes.unwrap_or(first))?;
    if let Some(m) = options.quad {
        settings = settings.with_quadrature_points(m)?;
    }
    if let Some(tol) = options.tol {
        let (least, most) = DEFAULT_ADAPTIVE_NODES;
        if let Some(n) = options.nodes.filter(|n| !(least..=most).contains(n)) {
            return Err(CliError::Invalid {
                flag: "--nodes",
                value: n.to_string(),
                reason: format!(
                    "with --tol, --nodes is the first step's count within the adaptive \
                     range {least} to {most}"
                ),
            });
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
                    CliError::Invalid {
                        flag: "--tol",
                        value: format!("{tol:e}"),
                        reason: format!(
                            "below what double precision can deliver over this run: {steps} \
                             steps of h = {h} round to about {floor:.1e} (4ε each); ask for at \
                             least that, or take longer steps (--h)"
                        ),
                    }
                }
                other => other.into(),
            })?;
    }
    whole_steps(t_end, h)?;
    Ok(settings
        .with_chart(chart)
        .with_matching(options.matching.map(Into::into).unwrap_or_default())
        .with_jacobian(options.jacobian.map(Into::into).unwrap_or_default()))
}

/// Whether and how a companion checks a run (`lgsvi_mechanics::Checked`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Check {
    /// Unchecked: `estimated_error` is the sum of the local estimates.
    None,
    /// A fixed run measured by its companion (`--check`).
    Measure,
    /// A `--tol` run accepted or refused by the check (`ToleranceCheck`).
    Tolerance(f64),
}

/// A built-in SO(3) system: one type, so that studies need not be generic.
pub use lgsvi_experiments::BuiltIn as System;

/// The torque and damping every system accepts (`--torque`, `--damping`): zero for
/// neither, and then the steps are the unforced system's, bit for bit.
pub type Drive = (BodyTorque, AngularDamping);

/// A built-in SO(3) system under the run's torque and damping.
pub type Driven = Forced<System, Drive>;

/// A built-in SE(3) system.
pub use lgsvi_experiments::BuiltInMotion as MotionSystem;

/// An SE(3) run: the system under the run's torque and damping, and its start.
#[derive(Debug, Clone, Copy)]
pub struct Motion {
    pub system: Forced<MotionSystem, Drive>,
    pub start: SE3,
    pub velocity0: SVector<f64, 6>,
}

impl Motion {
    /// An integrator in the settings' chart.
    pub fn integrator(
        &self,
        settings: StepSettings,
    ) -> std::result::Result<
        Integrator<Forced<MotionSystem, Drive>, lgsvi_mechanics::lie::ChartKind, 6>,
        MechanicsError,
    > {
        let chart = settings.chart();
        debug_assert_eq!(
            GroupChart::<RigidMotions, 6>::name(&chart),
            chart.to_string()
        );
        Integrator::new(self.system, settings, self.start, self.velocity0)
    }
}

pub use lgsvi_mechanics::gyrostat::AnyGyrostat;

/// A gyrostat run (`--system gyrostat`): the spacecraft, its wheels' start and their
/// constant motor torques.
#[derive(Debug, Clone)]
pub struct Wheels {
    pub system: AnyGyrostat,
    pub speeds0: Vec<f64>,
    pub torque: Vec<f64>,
}

impl Wheels {
    /// From the wheel flags and the spacecraft's inertia with the wheels locked; the
    /// wheels as given go into `description`.
    fn resolve(
        options: &SimulateOptions,
        inertia: &Inertia,
        description: &mut serde_json::Value,
    ) -> Result<Self> {
        let axes_given = options
            .wheel_axes
            .clone()
            .map(|n| n.0)
            .unwrap_or_else(|| vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
        let k = axes_given.len() / 3;
        if !axes_given.len().is_multiple_of(3) || !(1..=4).contains(&k) {
            return Err(CliError::Invalid {
                flag: "--wheel-axes",
                value: format!("{axes_given:?}"),
                reason: "three numbers per wheel, 1 to 4 wheels".into(),
            });
        }
        let per_wheel = |flag: &'static str, given: &Option<Numbers>, default: f64| {
            let values = given
                .clone()
                .map(|n| n.0)
                .unwrap_or_else(|| vec![default; k]);
            if values.len() == k {
                Ok(values)
            } else {
                Err(CliError::Invalid {
                    flag,
                    value: format!("{values:?}"),
                    reason: format!("one number per wheel: --wheel-axes gives {k}"),
                })
            }
        };
        let wheel_inertia = per_wheel("--wheel-inertia", &options.wheel_inertia, 0.05)?;
        let speeds0 = per_wheel("--wheel-speeds0", &options.wheel_speeds0, 0.0)?;
        let torque = per_wheel("--wheel-torque", &options.wheel_torque, 0.0)?;
        let j = inertia.matrix();
        let vectors: Vec<Vector3<f64>> = axes_given
            .chunks_exact(3)
            .map(Vector3::from_column_slice)
            .collect();
        let input = |source| CliError::Input {
            flag: "--wheel-axes/--wheel-inertia",
            source,
        };
        let system = AnyGyrostat::new(j, &vectors, &wheel_inertia).map_err(input)?;
        // The wheels as given (the axes before normalising), for the output's description.
        description["wheel_axes"] = axes_given.into();
        description["wheel_inertia"] = wheel_inertia.into();
        description["wheel_speeds0"] = speeds0.clone().into();
        description["wheel_torque"] = torque.clone().into();
        Ok(Self {
            system,
            speeds0,
            torque,
        })
    }

    /// An integrator for `craft` (this run's gyrostat with `K` wheels, `D = 3 + K`) from
    /// `(R₀, φ = 0)` with velocity `(Ω₀, φ̇₀)`, the motor torques set as its input
    /// `(0, τ_m)`.
    pub fn integrator<const K: usize, const D: usize>(
        &self,
        craft: Gyrostat<K>,
        settings: StepSettings,
        attitude: SO3,
        omega: Vector3<f64>,
    ) -> Result<Integrator<Gyrostat<K>, ChartKind, D>>
    where
        Gyrostat<K>: GroupLagrangian<D, Group = BodyAndWheels<K>>,
        BodyAndWheels<K>: lgsvi_mechanics::ConfigurationGroup<D, Element<f64> = BodyWheels<f64, K>>,
        ChartKind: GroupChart<BodyAndWheels<K>, D>,
    {
        let mut velocity = SVector::<f64, D>::zeros();
        let mut input = SVector::<f64, D>::zeros();
        velocity.fixed_rows_mut::<3>(0).copy_from(&omega);
        for i in 0..K {
            velocity[3 + i] = self.speeds0[i];
            input[3 + i] = self.torque[i];
        }
        let start = BodyWheels {
            attitude,
            wheels: SVector::<f64, K>::zeros(),
        };
        let mut integrator = Integrator::new(craft, settings, start, velocity)?;
        integrator.set_input(input)?;
        Ok(integrator)
    }
}

/// Everything a run needs.
#[derive(Debug, Clone)]
pub struct Problem {
    /// The SO(3) system (for an SE(3) run, its rotational part as a free body: unused).
    pub system: Driven,
    /// The SE(3) run, for `--system se3-body` and `orbiting-body`.
    pub motion: Option<Motion>,
    /// The gyrostat run, for `--system gyrostat`.
    pub wheels: Option<Wheels>,
    pub inertia: Inertia,
    pub attitude0: SO3,
    pub omega0: Vector3<f64>,
    pub settings: StepSettings,
    /// The initial motion's fastest rate (rad per unit time): the spin plus the system's
    /// own natural frequency; a `--tol` run's step turns `lgsvi_experiments::tolerance::STEP_ROTATION` at it.
    pub rate: f64,
    pub t_end: f64,
    pub every: usize,
    pub quiet: bool,
    /// Whether a companion checks the run: a `--tol` run unless `--no-check`, a fixed run
    /// with `--check`.
    pub check: Check,
    /// The inputs as given, for the output's `description`.
    pub description: serde_json::Value,
}

impl Problem {
    /// Resolves config file, flags and defaults.
    pub fn resolve(options: SimulateOptions) -> Result<(Problem, SimulateOptions)> {
        let mut options = options.merged_with_config()?;
        let kind = options.system();
        let d = defaults(kind);
        if options.omega0.is_none() {
            options.omega0 = Some(d.omega0);
        }
        let inertia = match (options.inertia, options.inertia_d, options.inertia_tensor) {
            (Some(j), None, None) => {
                Inertia::from_principal_moments(j).map_err(|source| CliError::Input {
                    flag: "--inertia",
                    source,
                })?
            }
            (None, Some(jd), None) => {
                Inertia::from_paper_jd(jd).map_err(|source| CliError::Input {
                    flag: "--inertia-d",
                    source,
                })?
            }
            (None, None, Some(t)) => {
                Inertia::from_tensor(Matrix3::from_row_slice(&t)).map_err(|source| {
                    CliError::Input {
                        flag: "--inertia-tensor",
                        source,
                    }
                })?
            }
            (None, None, None) => Inertia::from_paper_jd(d.inertia_d)?,
            (Some(_), Some(_), _) => return Err(CliError::Conflict("--inertia", "--inertia-d")),
            (Some(_), _, Some(_)) => {
                return Err(CliError::Conflict("--inertia", "--inertia-tensor"))
            }
            (_, Some(_), Some(_)) => {
                return Err(CliError::Conflict("--inertia-d", "--inertia-tensor"))
            }
        };
        let name = match kind {
            SystemKind::RigidBody => "rigid-body",
            SystemKind::HeavyTop => "heavy-top",
            SystemKind::Se3Body => "se3-body",
            SystemKind::OrbitingBody => "orbiting-body",
            SystemKind::Gyrostat => "gyrostat",
        };
        let not_for = |flag: &'static str, applies: &'static str| CliError::NotForSystem {
            flag,
            system: name,
            applies,
        };
        if kind == SystemKind::RigidBody {
            // The mass is the heavy top's and the bodies in space's (its help says so).
            if options.mass.is_some() {
                return Err(not_for(
                    "--mass",
                    "heavy-top, se3-body and orbiting-body (a free rotating body's motion does \
                     not depend on its mass)",
                ));
            }
            for (flag, given) in [
                ("--gravity", options.gravity.is_some()),
                ("--com", options.com.is_some()),
                ("--gravity-direction", options.gravity_direction.is_some()),
            ] {
                if given {
                    return Err(CliError::HeavyTopOnly { flag });
                }
            }
        }
        if kind.is_rigid_motion() {
            for (flag, given) in [
                ("--gravity", options.gravity.is_some()),
                ("--com", options.com.is_some()),
                ("--gravity-direction", options.gravity_direction.is_some()),
            ] {
                if given {
                    return Err(not_for(flag, "the heavy top (--system heavy-top)"));
                }
            }
            if options.exact {
                return Err(not_for(
                    "--exact",
                    "the free rigid body (--system rigid-body)",
                ));
            }
        } else {
            for (flag, given) in [
                ("--position0", options.position0.is_some()),
                ("--velocity0", options.velocity0.is_some()),
            ] {
                if given {
                    return Err(not_for(flag, "se3-body and orbiting-body"));
                }
            }
        }
        if kind == SystemKind::Gyrostat {
            for (flag, given, applies) in [
                (
                    "--mass",
                    options.mass.is_some(),
                    "heavy-top, se3-body and orbiting-body (a gyrostat's inertia J holds its \
                     mass distribution)",
                ),
                (
                    "--gravity",
                    options.gravity.is_some(),
                    "the heavy top (--system heavy-top)",
                ),
                (
                    "--com",
                    options.com.is_some(),
                    "the heavy top (--system heavy-top)",
                ),
                (
                    "--gravity-direction",
                    options.gravity_direction.is_some(),
                    "the heavy top (--system heavy-top)",
                ),
                (
                    "--torque",
                    options.torque.is_some(),
                    "rigid-body, heavy-top, se3-body and orbiting-body (a gyrostat's wheels \
                     take --wheel-torque)",
                ),
                (
                    "--damping",
                    options.damping.is_some(),
                    "rigid-body, heavy-top, se3-body and orbiting-body",
                ),
                (
                    "--exact",
                    options.exact,
                    "the free rigid body (--system rigid-body)",
                ),
            ] {
                if given {
                    return Err(not_for(flag, applies));
                }
            }
        } else {
            for (flag, given) in [
                ("--wheel-axes", options.wheel_axes.is_some()),
                ("--wheel-inertia", options.wheel_inertia.is_some()),
                ("--wheel-speeds0", options.wheel_speeds0.is_some()),
                ("--wheel-torque", options.wheel_torque.is_some()),
            ] {
                if given {
                    return Err(not_for(flag, "the gyrostat (--system gyrostat)"));
                }
            }
        }
        if options.mu.is_some() && kind != SystemKind::OrbitingBody {
            return Err(not_for("--mu", "orbiting-body"));
        }
        let torque = Vector3::from(options.torque.unwrap_or([0.0; 3]));
        let damping = options.damping.unwrap_or(0.0);
        if !(damping.is_finite() && damping >= 0.0) {
            return Err(CliError::Invalid {
                flag: "--damping",
                value: damping.to_string(),
                reason: "the damping c of the torque −cΩ must be finite and non-negative".into(),
            });
        }
        let drive: Drive = (BodyTorque(torque), AngularDamping(damping));
        let t_end = options.t_end.unwrap_or(10.0);
        if !(t_end.is_finite() && t_end >= 0.0) {
            return Err(CliError::Invalid {
                flag: "--t-end",
                value: t_end.to_string(),
                reason: "must be finite and non-negative".into(),
            });
        }
        if let Some(tol) = options.tol {
            if !(tol.is_finite() && tol > 0.0) {
                return Err(CliError::Invalid {
                    flag: "--tol",
                    value: tol.to_string(),
                    reason: "the accuracy must be positive and finite, e.g. 1e-10".into(),
                });
            }
            if options.quad.is_some() {
                return Err(CliError::Conflict("--tol", "--quad"));
            }
            if options.check {
                return Err(CliError::Invalid {
                    flag: "--check",
                    value: "given".into(),
                    reason: "--tol runs are checked anyway (--no-check skips it): drop --check"
                        .into(),
                });
            }
        } else if options.no_check {
            return Err(CliError::Invalid {
                flag: "--no-check",
                value: "given".into(),
                reason: "it skips the check of a --tol run: give --tol, or drop --no-check".into(),
            });
        }
        let every = options.every.unwrap_or(1);
        if every == 0 {
            return Err(CliError::Invalid {
                flag: "--every",
                value: "0".into(),
                reason: "keep every K-th step with K ≥ 1".into(),
            });
        }
        // The inertia as the user gave it (J or J_d), the other form derived from it, so the
        // description echoes the input without the rounding of a round trip.
        let inertia_j = options.inertia.unwrap_or(inertia.principal_moments());
        let inertia_jd = options
            .inertia_d
            .or(
                (options.inertia.is_none() && options.inertia_tensor.is_none())
                    .then_some(d.inertia_d),
            )
            .unwrap_or(inertia.paper_jd());
        let mut description = serde_json::json!({
            "inertia_J": inertia_j,
            "inertia_Jd": inertia_jd,
            "omega0": options.omega0,
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
        if let Some(tol) = options.tol {
            description["tolerance"] = tol.into();
        }
        description["system"] = name.into();
        let mut motion = None;
        let mut wheels = None;
        // The fastest natural motion besides the spin, for the step of a --tol run.
        let mut frequency = 0.0;
        let system = match kind {
            SystemKind::RigidBody => System::Free(RigidBody::new(inertia)),
            SystemKind::Gyrostat => {
                let run = Wheels::resolve(&options, &inertia, &mut description)?;
                // The wheels' spin joins the fastest motion a --tol step must follow.
                frequency = run.speeds0.iter().fold(0.0f64, |m, w| m.max(w.abs()));
                wheels = Some(run);
                System::Free(RigidBody::new(inertia))
            }
            SystemKind::Se3Body | SystemKind::OrbitingBody => {
                let orbiting = kind == SystemKind::OrbitingBody;
                let mass = options.mass.unwrap_or(1.0);
                let input = |flag| move |source| CliError::Input { flag, source };
                let (x0, v0) = if orbiting {
                    ([3.0, 0.0, 0.0], [0.0, 0.55, 0.05])
                } else {
                    ([0.0; 3], [0.0; 3])
                };
                let position = Vector3::from(options.position0.unwrap_or(x0));
                let velocity = Vector3::from(options.velocity0.unwrap_or(v0));
                let inner = if orbiting {
                    let mu = options.mu.unwrap_or(1.0);
                    description["mu"] = mu.into();
                    // At (or next to) the attracting centre the potential −μm/r and its
                    // gradient-gradient terms ~ μm/r³ are singular or overflow.
                    // |x| without underflow (1e-300 squared is zero).
                    let scale = position.amax();
                    let r = if scale > 0.0 {
                        scale * (position / scale).norm()
                    } else {
                        0.0
                    };
                    if mu != 0.0 && !(r > 0.0 && (mu * mass / r.powi(3)).is_finite()) {
                        return Err(CliError::Invalid {
                            flag: "--position0",
                            value: format!("{:?}", position.as_slice()),
                            reason: format!(
                                "the orbiting body starts at the attracting centre (r = {r:e}), \
                                 where the potential −μm/r and its gravity gradient are \
                                 singular: start it away from the origin"
                            ),
                        });
                    }
                    // The gravity gradient's Hessian forms x xᵀ (xᵀJx) ~ r⁴ |J|, which
                    // overflows from about r = 1e77 (measured: 1e70 runs, 1e80 fails).
                    if mu != 0.0 && r > 1e75 {
                        return Err(CliError::Invalid {
                            flag: "--position0",
                            value: format!("{:?}", position.as_slice()),
                            reason: format!(
                                "the orbiting body starts at r = {r:e}, where its gravity \
                                 gradient's terms (of order r⁴) overflow double precision \
                                 (r ≤ 1e75): express lengths in larger units"
                            ),
                        });
                    }
                    // The gravity-gradient libration, √3 times the orbit's mean motion.
                    frequency = (3.0 * mu.abs() / r.powi(3)).sqrt();
                    MotionSystem::Orbit(
                        OrbitingBody::new(inertia, mass, mu).map_err(input("--mass/--mu"))?,
                    )
                } else {
                    MotionSystem::Free(FreeBody::new(inertia, mass).map_err(input("--mass"))?)
                };
                description["mass"] = mass.into();
                description["position0"] = position.as_slice().into();
                description["velocity0"] = velocity.as_slice().into();
                let attitude = options.attitude()?;
                let omega = Vector3::from(options.omega0.unwrap_or(d.omega0));
                // Body velocities: (Ω, v) with ẋ = R v.
                let v = attitude.matrix().transpose() * velocity;
                motion = Some(Motion {
                    system: Forced::new(inner, drive),
                    start: SE3::new(attitude, position),
                    velocity0: SVector::<f64, 6>::new(omega.x, omega.y, omega.z, v.x, v.y, v.z),
                });
                System::Free(RigidBody::new(inertia))
            }
            SystemKind::HeavyTop => {
                let paper = named_case("B");
                // The compiled-in case B has both (checked by the cases' test).
                let mass = options.mass.unwrap_or(paper.mass.expect("case B's mass"));
                let gravity = options
                    .gravity
                    .unwrap_or(paper.gravity.expect("case B's g"));
                let com = Vector3::from(options.com.unwrap_or([0.0, 0.0, 1.0]));
                let direction = Vector3::from(options.gravity_direction.unwrap_or([0.0, 0.0, 1.0]));
                let top = HeavyTop::new(inertia, mass, gravity, com, direction)?;
                frequency =
                    pendulum_frequency(inertia.principal_moments(), mass * gravity * com.norm());
                description["mass"] = mass.into();
                description["gravity"] = gravity.into();
                description["com"] = com.as_slice().into();
                description["gravity_direction"] = top.gravity_direction().as_slice().into();
                System::Top(top)
            }
        };
        let omega0 = Vector3::from(options.omega0.unwrap_or(d.omega0));
        let rate = omega0.norm() + frequency;
        let settings = step_settings(&options, t_end, rate)?;
        let problem = Problem {
            system: Forced::new(system, drive),
            motion,
            wheels,
            inertia,
            attitude0: options.attitude()?,
            omega0,
            settings,
            rate,
            t_end,
            every,
            quiet: options.quiet,
            check: match (options.tol, options.no_check, options.check) {
                (Some(tol), false, _) => Check::Tolerance(tol),
                (None, _, true) => Check::Measure,
                _ => Check::None,
            },
            description,
        };
        Ok((problem, options))
    }

    /// An integrator for this problem with other settings (SO(3) systems).
    pub fn integrator(&self, settings: StepSettings) -> Result<Integrator<Driven>> {
        Ok(Subject::integrator(self, settings)?)
    }
}

/// The SO(3) problem as the studies of `lgsvi-experiments` run it.
impl Subject for Problem {
    type System = Driven;

    fn system(&self) -> &Driven {
        &self.system
    }

    fn settings(&self) -> StepSettings {
        self.settings
    }

    fn integrator(
        &self,
        settings: StepSettings,
    ) -> std::result::Result<Integrator<Driven>, MechanicsError> {
        Integrator::new(self.system, settings, self.attitude0, self.omega0)
    }

    /// The invariant tracker from `state` (the run's start), with what the system says it
    /// conserves (`Symmetry::of`): all of `Rμ` for a free body, the component along the
    /// heavy top's own gravity direction for the top, nothing under a torque or damping.
    fn tracker(&self, state: &lgsvi_mechanics::State) -> Tracker {
        Tracker::with_symmetry(
            state.energy(&self.system),
            state.attitude().matrix(),
            &state.momentum,
            Symmetry::of(&self.system),
        )
    }

    /// The exact solution, for a free body.
    fn exact(&self) -> Option<std::result::Result<FreeRigidBodyExact, MechanicsError>> {
        self.is_free()
            .then(|| FreeRigidBodyExact::new(self.inertia, self.attitude0, self.omega0))
    }
}
