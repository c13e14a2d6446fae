//! The high-precision reference trajectories of `tests/data/rigid_body_refs.json`
//! (copied from the project's shared references; see `tests/data/rigid_body_refs.README.md`),
//! and helpers to run the integrator on the paper's cases.
#![allow(dead_code)]

use lgsvi_lie::SO3;
use lgsvi_mechanics::{
    HeavyTop, Inertia, Integrator, MechanicsError, RigidBody, Statistics, StepSettings, Trajectory,
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

fn num(v: &serde_json::Value) -> f64 {
    v.as_str().unwrap().parse().unwrap()
}

fn nums(v: &serde_json::Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(num).collect()
}

pub fn case(name: &str) -> Case {
    let all: serde_json::Value =
        serde_json::from_str(include_str!("../../data/rigid_body_refs.json")).unwrap();
    let c = &all["cases"][name];
    let jd = nums(&c["J_d"]);
    let states = c["states"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| RefState {
            t: num(&s["t"]),
            r: Matrix3::from_row_slice(&nums(&s["R"])),
            omega: Vector3::from_row_slice(&nums(&s["omega"])),
            energy: num(&s["energy"]),
            pi: Vector3::from_row_slice(&nums(&s["pi"])),
        })
        .collect();
    Case {
        name: name.into(),
        free: c["kind"].as_str().unwrap() == "free",
        jd: [jd[0], jd[1], jd[2]],
        mg: if c["kind"].as_str().unwrap() == "free" {
            0.0
        } else {
            num(&c["mg"])
        },
        r0: Matrix3::from_row_slice(&nums(&c["R0"])),
        omega0: Vector3::from_row_slice(&nums(&c["omega0"])),
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
