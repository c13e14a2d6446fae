//! Yardsticks for lgsvi: the integrators a user would pick instead for a rotating body.
//!
//! - [`Lgvi2`]: the second-order Lie group variational integrator of Lee, Leok and
//!   McClamroch (trapezoidal form), `h·hat(Π_k + h/2 M_k) = F J_d − J_d Fᵀ`,
//!   `R_{k+1} = R_k F`, `Π_{k+1} = Fᵀ(Π_k + h/2 M_k) + h/2 M_{k+1}`, with `F` by Newton on
//!   its Cayley vector and the exact 3×3 Jacobian.
//! - [`Splitting`]: the symmetric rotation splitting of the free body
//!   `T1(h/2) T2(h/2) T3(h) T2(h/2) T1(h/2)` (each an exact rotation about a body axis),
//!   between potential kicks `V(h/2)` for the heavy top.
//! - [`Yoshida4`]: the fourth-order triple-jump composition of either.
//! - [`dop853`]: DOP853 (the `ode_solvers` crate) on the unit-quaternion state or the
//!   `(R, Ω)` state, sparse output only; [`dop853_in_space`] on a body in space
//!   (`(q, Ω, x, ẋ)`, MacCullagh's gravity, a body torque).
//!
//! The system is a rigid body with `ℓ = ½ΩᵀJΩ + m g e₃ᵀRρ` ([`Model`]; `m g = 0` is the
//! free body), `Π = JΩ`, `J Ω̇ = (JΩ) × Ω + m g ρ × Rᵀe₃`. [`so3_problem`] and
//! [`space_problem`] build a model and its start from a named case of `lgsvi_cases`.

#![warn(missing_docs)]

use nalgebra::{Matrix3, Vector3};

mod cases;
mod dop;
mod space;
pub use cases::{so3_problem, space_problem};
pub use dop::{dop853, Dop853State};
pub use space::{dop853_in_space, SpaceModel, SpaceState};

/// Why a baseline failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BaselineError {
    /// Newton for `F` did not converge.
    #[error(
        "LGVI: Newton for the Cayley vector did not converge (residual {0:e}); take a smaller step"
    )]
    Newton(f64),
    /// From DOP853.
    #[error("DOP853: {0}")]
    Dop853(String),
}

/// A rigid body with `ℓ = ½ΩᵀJΩ + m g e₃ᵀRρ` (principal axes along the body axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Model {
    /// Standard principal moments `J`.
    pub inertia: [f64; 3],
    /// `m g` (0 for the free body).
    pub mg: f64,
    /// Centre of mass in the body frame.
    pub rho: Vector3<f64>,
}

impl Model {
    /// The free body.
    pub fn free(inertia: [f64; 3]) -> Self {
        Self {
            inertia,
            mg: 0.0,
            rho: Vector3::z(),
        }
    }

    /// `M(R) = m g ρ × Rᵀe₃`.
    pub fn torque(&self, r: &Matrix3<f64>) -> Vector3<f64> {
        if self.mg == 0.0 {
            return Vector3::zeros();
        }
        self.mg * self.rho.cross(&(r.transpose() * Vector3::z()))
    }

    /// `Ω = J⁻¹Π`.
    pub fn velocity(&self, p: &Vector3<f64>) -> Vector3<f64> {
        Vector3::new(
            p.x / self.inertia[0],
            p.y / self.inertia[1],
            p.z / self.inertia[2],
        )
    }

    /// `½ΩᵀJΩ − m g e₃ᵀRρ`.
    pub fn energy(&self, s: &State) -> f64 {
        0.5 * s.momentum.dot(&self.velocity(&s.momentum)) - self.mg * (s.attitude * self.rho).z
    }
}

/// Attitude `R = world_from_body` and body momentum `Π = JΩ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    /// `R`.
    pub attitude: Matrix3<f64>,
    /// `Π`.
    pub momentum: Vector3<f64>,
}

/// A one-step method.
pub trait OneStep {
    /// Its order.
    fn order(&self) -> u32;
    /// Advances `state` by `h`.
    ///
    /// # Errors
    /// When an implicit stage does not converge.
    fn step(&self, model: &Model, state: &mut State, h: f64) -> Result<(), BaselineError>;
    /// `steps` steps of `h`.
    ///
    /// # Errors
    /// As [`OneStep::step`].
    fn run(
        &self,
        model: &Model,
        state: &mut State,
        h: f64,
        steps: usize,
    ) -> Result<(), BaselineError> {
        for _ in 0..steps {
            self.step(model, state, h)?;
        }
        Ok(())
    }
}

fn hat(w: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -w.z, w.y, w.z, 0.0, -w.x, -w.y, w.x, 0.0)
}

/// The Cayley map `(I + f̂)(I − f̂)⁻¹ = I + 2(f̂ + f̂²)/(1 + |f|²)`.
pub fn cayley(f: &Vector3<f64>) -> Matrix3<f64> {
    let fh = hat(f);
    Matrix3::identity() + (fh + fh * fh) * (2.0 / (1.0 + f.norm_squared()))
}

/// The second-order Lie group variational integrator of Lee, Leok and McClamroch.
#[derive(Debug, Clone, Copy, Default)]
pub struct Lgvi2;

impl OneStep for Lgvi2 {
    fn order(&self) -> u32 {
        2
    }

    fn step(&self, model: &Model, s: &mut State, h: f64) -> Result<(), BaselineError> {
        let a = s.momentum + 0.5 * h * model.torque(&s.attitude);
        let ha = h * a;
        let j = Matrix3::from_diagonal(&Vector3::from(model.inertia));
        // vee(F J_d − J_d Fᵀ) = 2(Jf + f × Jf)/(1 + |f|²) for F = cay(f), so F solves
        // G(f) = 2(Jf + f × Jf) − (1 + |f|²) h a = 0; Newton with the exact Jacobian
        // G'(f) = 2(J + f̂J − (Jf)^) − 2 h a fᵀ, from f = J⁻¹ha/2 (first order).
        let mut f = model.velocity(&ha) * 0.5;
        let scale = ha.norm().max(f64::MIN_POSITIVE);
        let mut residual = f64::INFINITY;
        for _ in 0..50 {
            let jf = j * f;
            let g = 2.0 * (jf + f.cross(&jf)) - (1.0 + f.norm_squared()) * ha;
            residual = g.norm();
            if residual <= 4.0 * f64::EPSILON * scale {
                break;
            }
            let jac = 2.0 * (j + hat(&f) * j - hat(&jf)) - 2.0 * ha * f.transpose();
            let Some(delta) = jac.lu().solve(&g) else {
                return Err(BaselineError::Newton(residual));
            };
            f -= delta;
            if delta.norm() <= f64::EPSILON * f.norm() {
                residual = 0.0;
                break;
            }
        }
        if residual > 1e3 * f64::EPSILON * scale {
            return Err(BaselineError::Newton(residual));
        }
        let big_f = cayley(&f);
        s.attitude *= big_f;
        s.momentum = big_f.transpose() * a + 0.5 * h * model.torque(&s.attitude);
        Ok(())
    }
}

/// Rotation by `angle` about body axis `axis`.
fn axis_rotation(axis: usize, angle: f64) -> Matrix3<f64> {
    let (s, c) = angle.sin_cos();
    let mut m = Matrix3::identity();
    let (i, k) = ((axis + 1) % 3, (axis + 2) % 3);
    m[(i, i)] = c;
    m[(k, k)] = c;
    m[(i, k)] = -s;
    m[(k, i)] = s;
    m
}

/// The symmetric rotation splitting: free flow `T1(h/2) T2(h/2) T3(h) T2(h/2) T1(h/2)`,
/// each `T_i` the exact flow of `Π_i²/(2J_i)` (a rotation about body axis `i`), inside
/// potential kicks `V(h/2)` for the heavy top. Second order, symplectic, exact `|Π|`
/// and (free body) `RΠ`.
#[derive(Debug, Clone, Copy, Default)]
pub struct Splitting;

impl Splitting {
    fn axis_flow(model: &Model, s: &mut State, axis: usize, h: f64) {
        let angle = h * s.momentum[axis] / model.inertia[axis];
        let rot = axis_rotation(axis, angle);
        s.attitude *= rot;
        s.momentum = rot.transpose() * s.momentum;
    }
}

impl OneStep for Splitting {
    fn order(&self) -> u32 {
        2
    }

    fn step(&self, model: &Model, s: &mut State, h: f64) -> Result<(), BaselineError> {
        s.momentum += 0.5 * h * model.torque(&s.attitude);
        Self::axis_flow(model, s, 0, 0.5 * h);
        Self::axis_flow(model, s, 1, 0.5 * h);
        Self::axis_flow(model, s, 2, h);
        Self::axis_flow(model, s, 1, 0.5 * h);
        Self::axis_flow(model, s, 0, 0.5 * h);
        s.momentum += 0.5 * h * model.torque(&s.attitude);
        Ok(())
    }
}

/// Yoshida's fourth-order triple jump `Φ(γ₁h) Φ(γ₂h) Φ(γ₁h)` of a symmetric second-order
/// method, `γ₁ = 1/(2 − 2^{1/3})`, `γ₂ = 1 − 2γ₁`.
#[derive(Debug, Clone, Copy, Default)]
pub struct Yoshida4<M>(pub M);

impl<M: OneStep> OneStep for Yoshida4<M> {
    fn order(&self) -> u32 {
        4
    }

    fn step(&self, model: &Model, s: &mut State, h: f64) -> Result<(), BaselineError> {
        let g1 = 1.0 / (2.0 - 2f64.cbrt());
        let g2 = 1.0 - 2.0 * g1;
        self.0.step(model, s, g1 * h)?;
        self.0.step(model, s, g2 * h)?;
        self.0.step(model, s, g1 * h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cayley_identity_behind_the_lgvi_newton() {
        // vee(F J_d − J_d Fᵀ) = 2(Jf + f × Jf)/(1 + |f|²), J_d = ½ tr(J) I − J.
        let j = [3.3, 2.5, 3.4];
        let jm = Matrix3::from_diagonal(&Vector3::from(j));
        let jd = Matrix3::identity() * (0.5 * jm.trace()) - jm;
        for f in [Vector3::new(0.3, -0.2, 0.7), Vector3::new(-1.5, 0.4, 2.0)] {
            let big = cayley(&f);
            let m = big * jd - jd * big.transpose();
            let vee = Vector3::new(m[(2, 1)], m[(0, 2)], m[(1, 0)]);
            let jf = jm * f;
            let closed = 2.0 * (jf + f.cross(&jf)) / (1.0 + f.norm_squared());
            assert!((vee - closed).norm() < 1e-14, "{vee} {closed}");
            assert!((big.transpose() * big - Matrix3::identity()).norm() < 1e-15);
        }
    }
}
