//! DOP853 on a rigid body in space, the peer of lgsvi's bodies on SE(3): a body of
//! principal moments `J` and mass `m` under a constant body torque `τ`, orbiting a point
//! mass `μ = GM` at the origin with MacCullagh's potential
//! `V = −μm/r − (μ/(2r³))(tr J − 3 x̂ᵀRJRᵀx̂)`. State `(q, Ω, x, ẋ)` (13 unknowns; `q` a
//! quaternion, `q̇ = ½ q ⊗ (0, Ω)`), or `(q, Ω)` (7) when `μ = 0`:
//!
//! - `J Ω̇ = (JΩ) × Ω + τ + b × ∇W(b)`, `b = Rᵀx` the position in the body frame;
//! - `m ẍ = −R ∇W(b)`,
//!
//! with `W(b) = −μm/r − (μ tr J)/(2r³) + (3μ/2) bᵀJb/r⁵` (`V` written in `b`, `r = |b|`),
//! `∇W = b (μm/r³ + 3μ tr J/(2r⁵) − 15μ bᵀJb/(2r⁷)) + 3μ Jb/r⁵`.

use crate::dop::{quaternion_matrix, solve};
use crate::BaselineError;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use ode_solvers::SVector;

/// A rigid body in space: principal moments, mass, gravitational parameter (0: no
/// gravity) and a constant body torque.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpaceModel {
    /// Principal moments `J` (body axes along the principal axes).
    pub inertia: [f64; 3],
    /// Mass `m`.
    pub mass: f64,
    /// `μ = GM` of the point mass at the origin (0 for no gravity).
    pub mu: f64,
    /// Constant body-frame torque `τ`.
    pub torque: Vector3<f64>,
}

/// A state of a [`SpaceModel`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpaceState {
    /// `R = world_from_body`.
    pub attitude: Matrix3<f64>,
    /// Body angular velocity `Ω`.
    pub omega: Vector3<f64>,
    /// Centre of mass `x` (world frame).
    pub position: Vector3<f64>,
    /// `ẋ` (world frame).
    pub velocity: Vector3<f64>,
}

impl SpaceModel {
    /// `(Ω̇, ẍ)` at attitude `R`, angular velocity `Ω` and position `x`.
    fn accelerations(
        &self,
        r: &Matrix3<f64>,
        w: &Vector3<f64>,
        x: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let j = Vector3::from(self.inertia);
        let mut torque = j.component_mul(w).cross(w) + self.torque;
        let mut xdd = Vector3::zeros();
        if self.mu != 0.0 {
            let b = r.transpose() * x;
            let r2 = b.norm_squared();
            let d = r2.sqrt();
            let (r3, r5) = (r2 * d, r2 * r2 * d);
            let r7 = r5 * r2;
            let jb = j.component_mul(&b);
            let q = b.dot(&jb);
            let trace = j.sum();
            let mu = self.mu;
            let grad = b * (mu * self.mass / r3 + 1.5 * mu * trace / r5 - 7.5 * mu * q / r7)
                + jb * (3.0 * mu / r5);
            torque += b.cross(&grad);
            xdd = -(r * grad) / self.mass;
        }
        (torque.component_div(&j), xdd)
    }
}

/// `q̇ = ½ q ⊗ (0, Ω)` into `dy[..4]`.
fn quaternion_rate(y: &[f64], om: &Vector3<f64>, dy: &mut [f64]) {
    let (w, x, yy, z) = (y[0], y[1], y[2], y[3]);
    dy[0] = 0.5 * (-x * om.x - yy * om.y - z * om.z);
    dy[1] = 0.5 * (w * om.x + yy * om.z - z * om.y);
    dy[2] = 0.5 * (w * om.y + z * om.x - x * om.z);
    dy[3] = 0.5 * (w * om.z + x * om.y - yy * om.x);
}

struct Orbit(SpaceModel);
struct Torqued(SpaceModel);

impl ode_solvers::System<f64, SVector<f64, 13>> for Orbit {
    fn system(&self, _t: f64, y: &SVector<f64, 13>, dy: &mut SVector<f64, 13>) {
        let om = Vector3::new(y[4], y[5], y[6]);
        quaternion_rate(y.as_slice(), &om, dy.as_mut_slice());
        let r = quaternion_matrix(&y.as_slice()[..4]);
        let x = Vector3::new(y[7], y[8], y[9]);
        let (wd, xdd) = self.0.accelerations(&r, &om, &x);
        for i in 0..3 {
            dy[4 + i] = wd[i];
            dy[7 + i] = y[10 + i];
            dy[10 + i] = xdd[i];
        }
    }
}

impl ode_solvers::System<f64, SVector<f64, 7>> for Torqued {
    fn system(&self, _t: f64, y: &SVector<f64, 7>, dy: &mut SVector<f64, 7>) {
        let om = Vector3::new(y[4], y[5], y[6]);
        quaternion_rate(y.as_slice(), &om, dy.as_mut_slice());
        // Without gravity nothing depends on the attitude.
        let (wd, _) = self
            .0
            .accelerations(&Matrix3::identity(), &om, &Vector3::zeros());
        for i in 0..3 {
            dy[4 + i] = wd[i];
        }
    }
}

/// DOP853 from `state` over `[0, t_end]` with relative and absolute tolerance `tol`, on
/// `(q, Ω, x, ẋ)` (or `(q, Ω)` when `model.mu == 0`, the centre of mass then moving
/// uniformly); returns the final state and the number of right-hand-side evaluations.
///
/// # Errors
/// [`BaselineError::Dop853`] when the solver gives up.
pub fn dop853_in_space(
    model: &SpaceModel,
    state: &SpaceState,
    t_end: f64,
    tol: f64,
) -> Result<(SpaceState, u32), BaselineError> {
    let q = UnitQuaternion::from_matrix(&state.attitude);
    let w = state.omega;
    if model.mu == 0.0 {
        let y0 = SVector::<f64, 7>::from_row_slice(&[q.w, q.i, q.j, q.k, w.x, w.y, w.z]);
        let (y, evals) = solve(Torqued(*model), y0, t_end, tol)?;
        return Ok((
            SpaceState {
                attitude: quaternion_matrix(&y.as_slice()[..4]),
                omega: Vector3::new(y[4], y[5], y[6]),
                position: state.position + state.velocity * t_end,
                velocity: state.velocity,
            },
            evals,
        ));
    }
    let (x, v) = (state.position, state.velocity);
    let y0 = SVector::<f64, 13>::from_row_slice(&[
        q.w, q.i, q.j, q.k, w.x, w.y, w.z, x.x, x.y, x.z, v.x, v.y, v.z,
    ]);
    let (y, evals) = solve(Orbit(*model), y0, t_end, tol)?;
    Ok((
        SpaceState {
            attitude: quaternion_matrix(&y.as_slice()[..4]),
            omega: Vector3::new(y[4], y[5], y[6]),
            position: Vector3::new(y[7], y[8], y[9]),
            velocity: Vector3::new(y[10], y[11], y[12]),
        },
        evals,
    ))
}
