//! The bodies beyond the free body and the top: the orbiting body O1 (SE(3),
//! MacCullagh's potential) and the torqued body F1 (SO(3), a constant body torque), from
//! `cases/data/se3_forced_refs.json`, against DOP853 on `(q, Ω, x, ẋ)` (or `(q, Ω)`) —
//! the same protocol as the SO(3) table: a sweep of `(h, n)` and of tolerances, each run
//! timed whole (construction included, median of the repeats), the best run per error
//! target. Errors: O1 `max(‖R − R_ref‖_F, ‖x − x_ref‖)`, F1 `‖R − R_ref‖_F`, at `T`.

use crate::error::BenchError;
use lgsvi_baselines::{dop853_in_space, space_problem, SpaceModel, SpaceState};
use lgsvi_experiments::work_precision::{median_time, Point};
use lgsvi_mechanics::forces::BodyTorque;
use lgsvi_mechanics::lie::{ChartKind, SE3, SO3};
use lgsvi_mechanics::Stepper;
use lgsvi_mechanics::{Forced, Inertia, Integrator, OrbitingBody, RigidBody, StepSettings};
use nalgebra::{Matrix3, SVector, Vector3};

type Result<T> = std::result::Result<T, BenchError>;

/// lgsvi's sweeps: `(h, nodes)`, steps that divide both horizons: the SO(3) table's
/// steps (0.5, 0.625, 1, 1.25, 2) and the orbiting body's longer ones (its best runs take
/// steps of about a sixth of its orbit).
pub const SWEEPS: [(f64, std::ops::RangeInclusive<usize>); 7] = [
    (0.5, 4..=14),
    (0.625, 6..=16),
    (1.0, 6..=20),
    (1.25, 8..=20),
    (2.0, 5..=20),
    (2.5, 6..=20),
    (5.0, 8..=24),
];

/// DOP853's tolerances `10^-k`.
pub const TOLERANCES: std::ops::RangeInclusive<i32> = 3..=14;

/// The cases.
pub const CASES: [&str; 2] = ["O1", "F1"];
/// The horizons.
pub const HORIZONS: [f64; 2] = [10.0, 100.0];

/// The runs of the sweep (for the progress bar).
pub fn runs() -> usize {
    let lgsvi: usize = SWEEPS.iter().map(|(_, n)| n.clone().count()).sum();
    CASES.len() * HORIZONS.len() * (lgsvi + TOLERANCES.count())
}

/// A case: the model both integrators share, its start and the reference at each horizon.
struct Case {
    model: SpaceModel,
    start: SpaceState,
    /// `(t, R, x)` at 10 and 100.
    references: Vec<(f64, Matrix3<f64>, Vector3<f64>)>,
}

fn case(name: &'static str) -> Case {
    let c = crate::named_case(name);
    let (model, start) = space_problem(c).expect("O1 and F1 are bodies in space with a diagonal J");
    let references = c
        .states
        .iter()
        .filter(|s| HORIZONS.contains(&s.t))
        .map(|s| (s.t, s.attitude, s.position.unwrap_or_else(Vector3::zeros)))
        .collect();
    Case {
        model,
        start,
        references,
    }
}

/// One lgsvi run to `t_end`: `(R, x)` at the end.
fn lgsvi_run(case: &Case, t_end: f64, h: f64, n: usize) -> Result<(Matrix3<f64>, Vector3<f64>)> {
    let settings = StepSettings::new(h, n)?.with_chart(ChartKind::Exp);
    let steps = (t_end / h).round() as usize;
    let inertia = Inertia::from_principal_moments(case.model.inertia)?;
    let w = case.start.omega;
    if case.model.mu != 0.0 {
        let body = OrbitingBody::new(inertia, case.model.mass, case.model.mu)?;
        let start = SE3::new(SO3::identity(), case.start.position);
        let v = case.start.velocity;
        let xi = SVector::<f64, 6>::new(w.x, w.y, w.z, v.x, v.y, v.z);
        let mut it = Integrator::new(body, settings, start, xi)?;
        it.run(steps, steps)?;
        Ok((*it.state().attitude().matrix(), it.state().position()))
    } else {
        let body = Forced::new(RigidBody::new(inertia), BodyTorque(case.model.torque));
        let mut it = Integrator::new(body, settings, SO3::identity(), w)?;
        it.run(steps, steps)?;
        Ok((*it.state().attitude().matrix(), Vector3::zeros()))
    }
}

/// The sweep: every case, horizon, `(h, n)` and DOP853 tolerance.
pub fn sweep(repeats: usize, mut tick: impl FnMut()) -> Vec<Point> {
    let mut points = Vec::new();
    for name in CASES {
        let case = case(name);
        for (t_end, r_ref, x_ref) in case.references.clone() {
            let mut push = |method: &str,
                            knob: String,
                            result: Result<(Matrix3<f64>, Vector3<f64>)>,
                            time_s: f64| {
                let error = result.map(|(r, x)| (r - r_ref).norm().max((x - x_ref).norm()));
                points.push(Point::new(name, t_end, method, knob, error, time_s));
            };
            let run = |h, n| lgsvi_run(&case, t_end, h, n);
            crate::lgsvi_fixed_runs(repeats, &SWEEPS, run, &mut push, &mut tick);
            for k in TOLERANCES {
                let tol = 10f64.powi(-k);
                let (r, t) = median_time(repeats, || {
                    dop853_in_space(&case.model, &case.start, t_end, tol)
                        .map(|(s, _)| (s.attitude, s.position))
                        .map_err(BenchError::from)
                });
                push("DOP853 (quaternion)", format!("tol = 1e-{k}"), r, t);
                tick();
            }
        }
    }
    points
}
