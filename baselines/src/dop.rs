//! DOP853 (Hairer's 8(5,3) Runge–Kutta, the `ode_solvers` crate) on the rigid body.

use crate::{BaselineError, Model, State};
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use ode_solvers::dop853::Dop853;
use ode_solvers::dop_shared::OutputType;
use ode_solvers::SVector;

/// Which state DOP853 integrates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dop853State {
    /// `(q, Ω)`, `q` a quaternion (w, x, y, z) with `q̇ = ½ q ⊗ (0, Ω)`: 7 unknowns.
    /// Its norm drifts; the attitude is read from the normalised `q`.
    Quaternion,
    /// `(R, Ω)` with `Ṙ = RΩ̂`: 12 unknowns; `R` leaves SO(3) as errors accumulate.
    Matrix,
}

struct Quaternion(Model);
struct MatrixState(Model);

fn omega_dot(model: &Model, r: &Matrix3<f64>, w: &Vector3<f64>) -> Vector3<f64> {
    let j = Vector3::from(model.inertia);
    let mu = j.component_mul(w);
    (mu.cross(w) + model.torque(r)).component_div(&j)
}

pub(crate) fn quaternion_matrix(q: &[f64]) -> Matrix3<f64> {
    let unit = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]));
    unit.to_rotation_matrix().into_inner()
}

impl ode_solvers::System<f64, SVector<f64, 7>> for Quaternion {
    fn system(&self, _t: f64, y: &SVector<f64, 7>, dy: &mut SVector<f64, 7>) {
        let (w, x, yy, z) = (y[0], y[1], y[2], y[3]);
        let om = Vector3::new(y[4], y[5], y[6]);
        // q̇ = ½ q ⊗ (0, Ω).
        dy[0] = 0.5 * (-x * om.x - yy * om.y - z * om.z);
        dy[1] = 0.5 * (w * om.x + yy * om.z - z * om.y);
        dy[2] = 0.5 * (w * om.y + z * om.x - x * om.z);
        dy[3] = 0.5 * (w * om.z + x * om.y - yy * om.x);
        let r = if self.0.mg == 0.0 {
            Matrix3::identity()
        } else {
            quaternion_matrix(&[w, x, yy, z])
        };
        let wd = omega_dot(&self.0, &r, &om);
        dy[4] = wd.x;
        dy[5] = wd.y;
        dy[6] = wd.z;
    }
}

impl ode_solvers::System<f64, SVector<f64, 12>> for MatrixState {
    fn system(&self, _t: f64, y: &SVector<f64, 12>, dy: &mut SVector<f64, 12>) {
        let r = Matrix3::from_row_slice(&y.as_slice()[..9]);
        let om = Vector3::new(y[9], y[10], y[11]);
        let hat = Matrix3::new(0.0, -om.z, om.y, om.z, 0.0, -om.x, -om.y, om.x, 0.0);
        let rd = r * hat;
        for i in 0..3 {
            for k in 0..3 {
                dy[3 * i + k] = rd[(i, k)];
            }
        }
        let wd = omega_dot(&self.0, &r, &om);
        dy[9] = wd.x;
        dy[10] = wd.y;
        dy[11] = wd.z;
    }
}

/// DOP853 with sparse output from `y0` over `[0, t_end]`: the final state and the number
/// of right-hand-side evaluations.
pub(crate) fn solve<const N: usize, S: ode_solvers::System<f64, SVector<f64, N>>>(
    system: S,
    y0: SVector<f64, N>,
    t_end: f64,
    tol: f64,
) -> Result<(SVector<f64, N>, u32), BaselineError> {
    // Hairer's defaults (safety 0.9, β = 0, step factors in [1/3, 6]), no step cap.
    let mut solver = Dop853::from_param(
        system,
        0.0,
        t_end,
        t_end,
        y0,
        tol,
        tol,
        0.9,
        0.0,
        0.333,
        6.0,
        t_end,
        0.0,
        u32::MAX / 16,
        1000,
        OutputType::Sparse,
    );
    let stats = solver
        .integrate()
        .map_err(|e| BaselineError::Dop853(e.to_string()))?;
    Ok((solver.y_out().last().copied().unwrap_or(y0), stats.num_eval))
}

/// DOP853 from `state` over `[0, t_end]` with relative and absolute tolerance `tol`;
/// returns the final state (attitude as stored: for the matrix state it is not
/// re-orthogonalised) and the number of right-hand-side evaluations.
///
/// # Errors
/// [`BaselineError::Dop853`] when the solver gives up (too many steps, stiffness).
pub fn dop853(
    model: &Model,
    state: &State,
    t_end: f64,
    tol: f64,
    kind: Dop853State,
) -> Result<(State, u32), BaselineError> {
    let w0 = model.velocity(&state.momentum);
    let j = Vector3::from(model.inertia);
    match kind {
        Dop853State::Quaternion => {
            let q = UnitQuaternion::from_matrix(&state.attitude);
            let y0 = SVector::<f64, 7>::from_row_slice(&[q.w, q.i, q.j, q.k, w0.x, w0.y, w0.z]);
            let (y, evals) = solve(Quaternion(*model), y0, t_end, tol)?;
            let attitude = quaternion_matrix(&y.as_slice()[..4]);
            let momentum = j.component_mul(&Vector3::new(y[4], y[5], y[6]));
            Ok((State { attitude, momentum }, evals))
        }
        Dop853State::Matrix => {
            let mut init = [0.0; 12];
            for i in 0..3 {
                for k in 0..3 {
                    init[3 * i + k] = state.attitude[(i, k)];
                }
            }
            init[9..].copy_from_slice(w0.as_slice());
            let y0 = SVector::<f64, 12>::from_row_slice(&init);
            let (y, evals) = solve(MatrixState(*model), y0, t_end, tol)?;
            let attitude = Matrix3::from_row_slice(&y.as_slice()[..9]);
            let momentum = j.component_mul(&Vector3::new(y[9], y[10], y[11]));
            Ok((State { attitude, momentum }, evals))
        }
    }
}
