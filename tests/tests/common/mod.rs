//! The paper's cases and their high-precision references (`lgsvi_cases`:
//! `cases/data/rigid_body_refs.json`, see its README), in the form these tests read, and
//! helpers to run the integrator on them.
#![allow(dead_code)]

use lgsvi_lie::SO3;
use lgsvi_mechanics::integrator::Statistics;
use lgsvi_mechanics::Stepper;
use lgsvi_mechanics::{
    HeavyTop, Inertia, Integrator, MechanicsError, RigidBody, StepSettings, Trajectory,
};
use nalgebra::{Matrix3, Vector3};

/// One reference state.
#[derive(Debug, Clone)]
pub struct RefState {
    pub t: f64,
    pub r: Matrix3<f64>,
    pub omega: Vector3<f64>,
    pub energy: f64,
    pub pi: Vector3<f64>,
}

/// One reference case.
#[derive(Debug, Clone)]
pub struct Case {
    pub name: String,
    pub free: bool,
    pub jd: [f64; 3],
    pub mg: f64,
    pub r0: Matrix3<f64>,
    pub omega0: Vector3<f64>,
    pub states: Vec<RefState>,
}

/// Case `name` of `lgsvi_cases`, in the form these tests read.
pub fn case(name: &str) -> Case {
    let c = lgsvi_cases::case(name).unwrap();
    let states = c
        .states
        .iter()
        .map(|s| RefState {
            t: s.t,
            r: s.attitude,
            omega: s.omega,
            energy: s.energy.unwrap(),
            pi: s.spatial_momentum.unwrap(),
        })
        .collect();
    Case {
        name: name.into(),
        free: c.kind == lgsvi_cases::Kind::FreeBody,
        jd: c.inertia_d.unwrap(),
        mg: c.weight().unwrap_or(0.0),
        r0: c.attitude0,
        omega0: c.omega0,
        states,
    }
}

/// Runs a case for `steps` steps of the settings' `h`, recording every `every`-th state.
pub fn run(
    case: &Case,
    settings: StepSettings,
    steps: usize,
    every: usize,
) -> Result<(Trajectory, Statistics), MechanicsError> {
    let inertia = Inertia::from_paper_jd(case.jd)?;
    let r0 = SO3::try_from_matrix(case.r0)?;
    if case.free {
        let mut it = Integrator::new(RigidBody::new(inertia), settings, r0, case.omega0)?;
        let t = it.run(steps, every)?;
        Ok((t, *it.statistics()))
    } else {
        // m g is stored; m = 1 and g = m g reproduce it exactly.
        let top = HeavyTop::new(inertia, 1.0, case.mg, Vector3::z(), Vector3::z())?;
        let mut it = Integrator::new(top, settings, r0, case.omega0)?;
        let t = it.run(steps, every)?;
        Ok((t, *it.statistics()))
    }
}

/// Energy of a state of the case's system.
pub fn energy(case: &Case, state: &lgsvi_mechanics::State) -> f64 {
    let inertia = Inertia::from_paper_jd(case.jd).unwrap();
    if case.free {
        state.energy(&RigidBody::new(inertia))
    } else {
        state.energy(&HeavyTop::new(inertia, 1.0, case.mg, Vector3::z(), Vector3::z()).unwrap())
    }
}

/// Largest ‖R − R_ref‖₂ and ‖Ω − Ω_ref‖ over the reference times `t ≤ t_max` a trajectory
/// recorded every `every` steps of `h` passes through.
pub fn max_errors(case: &Case, trajectory: &Trajectory, t_max: f64) -> (f64, f64) {
    let (mut er, mut ew) = (0.0f64, 0.0f64);
    for s in &trajectory.states {
        if s.time > t_max + 1e-9 {
            continue;
        }
        if let Some(r) = case.states.iter().find(|r| (r.t - s.time).abs() < 1e-9) {
            let diff = s.attitude().matrix() - r.r;
            er = er.max(diff.svd(false, false).singular_values.max());
            ew = ew.max((s.velocity - r.omega).norm());
        }
    }
    (er, ew)
}
