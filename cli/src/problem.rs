//! A problem resolved from options: the system, its initial state and the integrator's
//! settings, with the paper's parameters as defaults.

use crate::config::{SimulateOptions, SystemKind};
use crate::error::{CliError, Result};
use crate::invariants::Tracker;
use lgsvi_mechanics::exact::FreeRigidBodyExact;
use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::{
    HeavyTop, Inertia, Integrator, Lagrangian, LagrangianDerivatives, RigidBody, StepSettings,
};
use nalgebra::{Matrix3, RealField, Vector3};

/// The paper's parameters per system (`docs/paper-notes.md` §4): case A and case B.
pub struct Defaults {
    pub inertia_d: [f64; 3],
    pub omega0: [f64; 3],
}

pub fn defaults(system: SystemKind) -> Defaults {
    let case = crate::cases::case(match system {
        SystemKind::RigidBody => "A",
        SystemKind::HeavyTop => "B",
    });
    Defaults {
        inertia_d: case.inertia_d,
        omega0: case.omega0,
    }
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

/// A built-in system: one type, so that studies need not be generic.
#[derive(Debug, Clone, Copy)]
pub enum System {
    Free(RigidBody),
    Top(HeavyTop),
}

impl Lagrangian for System {
    fn lagrangian<T: RealField + Copy>(&self, r: &Matrix3<T>, w: &Vector3<T>) -> T {
        match self {
            System::Free(s) => s.lagrangian(r, w),
            System::Top(s) => s.lagrangian(r, w),
        }
    }
    fn is_left_invariant(&self) -> bool {
        match self {
            System::Free(s) => s.is_left_invariant(),
            System::Top(s) => s.is_left_invariant(),
        }
    }
    fn velocity_from_momentum(&self, r: &Matrix3<f64>, mu: &Vector3<f64>) -> Option<Vector3<f64>> {
        match self {
            System::Free(s) => s.velocity_from_momentum(r, mu),
            System::Top(s) => s.velocity_from_momentum(r, mu),
        }
    }
    // Forwarded: the built-ins' closed forms are ~10× faster than the default dual numbers.
    fn derivatives(&self, r: &Matrix3<f64>, w: &Vector3<f64>) -> LagrangianDerivatives {
        match self {
            System::Free(s) => s.derivatives(r, w),
            System::Top(s) => s.derivatives(r, w),
        }
    }
}

/// Everything a run needs.
#[derive(Debug, Clone)]
pub struct Problem {
    pub system: System,
    pub inertia: Inertia,
    pub attitude0: SO3,
    pub omega0: Vector3<f64>,
    pub settings: StepSettings,
    pub t_end: f64,
    pub every: usize,
    pub quiet: bool,
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
        let inertia = match (options.inertia, options.inertia_d) {
            (Some(j), None) => {
                Inertia::from_principal_moments(j).map_err(|source| CliError::Input {
                    flag: "--inertia",
                    source,
                })?
            }
            (None, Some(jd)) => Inertia::from_paper_jd(jd).map_err(|source| CliError::Input {
                flag: "--inertia-d",
                source,
            })?,
            (None, None) => Inertia::from_paper_jd(d.inertia_d)?,
            (Some(_), Some(_)) => return Err(CliError::Conflict("--inertia", "--inertia-d")),
        };
        if kind == SystemKind::RigidBody {
            for (flag, given) in [
                ("--mass", options.mass.is_some()),
                ("--gravity", options.gravity.is_some()),
                ("--com", options.com.is_some()),
                ("--gravity-direction", options.gravity_direction.is_some()),
            ] {
                if given {
                    return Err(CliError::HeavyTopOnly { flag });
                }
            }
        }
        let h = options.h.unwrap_or(0.5);
        let nodes = options.nodes.unwrap_or(10);
        let mut settings = StepSettings::new(h, nodes)?;
        if let Some(m) = options.quad {
            settings = settings.with_quadrature_points(m)?;
        }
        settings = settings
            .with_chart(options.chart.map(Into::into).unwrap_or_default())
            .with_matching(options.matching.map(Into::into).unwrap_or_default())
            .with_jacobian(options.jacobian.map(Into::into).unwrap_or_default());
        let t_end = options.t_end.unwrap_or(10.0);
        if !(t_end.is_finite() && t_end >= 0.0) {
            return Err(CliError::Invalid {
                flag: "--t-end",
                value: t_end.to_string(),
                reason: "must be finite and non-negative".into(),
            });
        }
        whole_steps(t_end, h)?;
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
            .or(options.inertia.is_none().then_some(d.inertia_d))
            .unwrap_or(inertia.paper_jd());
        let mut description = serde_json::json!({
            "inertia_J": inertia_j,
            "inertia_Jd": inertia_jd,
            "omega0": options.omega0,
        });
        let system = match kind {
            SystemKind::RigidBody => {
                description["system"] = "rigid-body".into();
                System::Free(RigidBody::new(inertia))
            }
            SystemKind::HeavyTop => {
                let paper = crate::cases::case("B");
                // The compiled-in case B has both (checked by the cases' test).
                let mass = options.mass.unwrap_or(paper.mass.expect("case B's mass"));
                let gravity = options
                    .gravity
                    .unwrap_or(paper.gravity.expect("case B's g"));
                let com = Vector3::from(options.com.unwrap_or([0.0, 0.0, 1.0]));
                let direction = Vector3::from(options.gravity_direction.unwrap_or([0.0, 0.0, 1.0]));
                let top = HeavyTop::new(inertia, mass, gravity, com, direction)?;
                description["system"] = "heavy-top".into();
                description["mass"] = mass.into();
                description["gravity"] = gravity.into();
                description["com"] = com.as_slice().into();
                description["gravity_direction"] = top.gravity_direction().as_slice().into();
                System::Top(top)
            }
        };
        let problem = Problem {
            system,
            inertia,
            attitude0: options.attitude()?,
            omega0: Vector3::from(options.omega0.unwrap_or(d.omega0)),
            settings,
            t_end,
            every,
            quiet: options.quiet,
            description,
        };
        Ok((problem, options))
    }

    /// The settings as JSON.
    pub fn settings_json(settings: &StepSettings, t_end: f64, every: usize) -> serde_json::Value {
        serde_json::json!({
            "h": settings.step(), "nodes": settings.nodes(), "degree": settings.degree(),
            "quadrature_points": settings.quadrature_points(), "chart": settings.chart().to_string(),
            "matching": format!("{:?}", settings.matching()).to_lowercase(),
            "jacobian": match settings.jacobian() { lgsvi_mechanics::NewtonJacobian::Exact => "exact", _ => "finite-difference" },
            "t_end": t_end, "every": every,
        })
    }

    /// An integrator for this problem with other settings.
    pub fn integrator(&self, settings: StepSettings) -> Result<Integrator<System>> {
        Ok(Integrator::new(
            self.system,
            settings,
            self.attitude0,
            self.omega0,
        )?)
    }

    /// The invariant tracker from `state` (the run's start), with this system's symmetry.
    pub fn tracker(&self, state: &lgsvi_mechanics::State) -> Tracker {
        Tracker::new(
            state.energy(&self.system),
            state.attitude().matrix(),
            &state.momentum,
            self.is_free(),
        )
    }

    /// Whether the system is a free body (a heavy top without weight counts).
    pub fn is_free(&self) -> bool {
        self.system.is_left_invariant()
    }

    /// The exact solution, for a free body.
    pub fn exact(&self) -> Result<FreeRigidBodyExact> {
        if !self.is_free() {
            return Err(CliError::NoExactSolution);
        }
        Ok(FreeRigidBodyExact::new(
            self.inertia,
            self.attitude0,
            self.omega0,
        )?)
    }
}
