//! One run of the integrator under given torques: its states, the terminal miss, and the
//! terminal state's exact sensitivity to every torque and to the common step length.

use crate::OptimalError;
use lgsvi_mechanics::built_in::BuiltInSo3;
use lgsvi_mechanics::lie::{LieGroup, SO3};
use lgsvi_mechanics::linearization::Coordinates;
use lgsvi_mechanics::{Integrator, State, StepSettings};
use nalgebra::{DMatrix, DVector, Vector3};

/// One run of the torques: its states, the terminal state's sensitivity and miss.
pub(crate) struct Shot {
    /// `x_0 … x_K`.
    pub states: Vec<State>,
    /// `M = ∂x_K/∂u` (`6 × 3K` per input of a step) in the body-frame coordinates `(θ, ω)`.
    pub sensitivity: DMatrix<f64>,
    /// `∂x_K/∂h` (6), the step length shared by every step.
    pub time_sensitivity: DVector<f64>,
    /// `e = (log(R_Kᵀ R_f), Ω_f − Ω_K)`.
    pub miss: DVector<f64>,
    /// Each step's `A_k` and input Jacobians `B_kj` (velocity coordinates).
    a: Vec<DMatrix<f64>>,
    b: Vec<Vec<DMatrix<f64>>>,
}

impl Shot {
    /// `∂x_k/∂u` for `k = 1 … K` (`6 × n` each), chained forwards:
    /// `S_{k+1} = A_k S_k + [B_kj in step k's columns]`.
    pub fn state_sensitivities(&self) -> Vec<DMatrix<f64>> {
        let columns = self.sensitivity.ncols();
        let per_step = columns / self.a.len().max(1);
        let mut out = Vec::with_capacity(self.a.len());
        let mut s = DMatrix::<f64>::zeros(6, columns);
        for (k, (a, b)) in self.a.iter().zip(&self.b).enumerate() {
            s = a * &s;
            for (j, bj) in b.iter().enumerate() {
                s.view_mut((0, per_step * k + 3 * j), (6, 3)).copy_from(bj);
            }
            out.push(s.clone());
        }
        out
    }
}

/// The run from `start` under `inputs`, `per_step` of them per step of `settings` (one:
/// held over the step; the step's Gauss-point count: its values at the points,
/// [`Integrator::set_input_at_points`]), against `target`.
///
/// Each step is linearised exactly ([`Integrator::step_linearized`]: `A_k` and the input
/// Jacobians `B_kj`), and its derivative in the step length follows from the same `A_k`
/// and `B_kj` by the rigid body's time scaling: a step of length `ch` from `(R, Ω)` under
/// `u(t)` is the step of length `h` from `(R, cΩ)` under `c² u(ct)` with its end rates
/// divided by `c` (the Euler equations, and lgsvi's discrete action term by term, are
/// invariant under `t ↦ ct`, `Ω ↦ Ω/c`, `u ↦ u/c²`; the inputs at the points keep their
/// fractions of the step). Differentiating at `c = 1`:
///
/// ```text
/// h ∂x₊/∂h = A_ω Ω + 2 Σ_j B_j u_j − (0, Ω₊)
/// ```
///
/// with `A_ω` the columns of `A` in the start's rates; `optimal/tests/free_time.rs`
/// checks both the scaling and this derivative against finite differences. The law is the
/// free body's: for a heavy top (gravity does not scale so) `∂x_K/∂h` is not meaningful,
/// and no minimum-time slew of one is solved.
pub(crate) fn shoot(
    body: BuiltInSo3,
    settings: StepSettings,
    start: (SO3, Vector3<f64>),
    target: (SO3, Vector3<f64>),
    inputs: &[Vector3<f64>],
    per_step: usize,
) -> Result<Shot, OptimalError> {
    let h = settings.h();
    let mut it = Integrator::new(body, settings, start.0, start.1)?;
    let mut states = vec![*it.state()];
    let k_steps = inputs.len() / per_step;
    let mut a = Vec::with_capacity(k_steps);
    let mut b = Vec::with_capacity(k_steps);
    let mut d = Vec::with_capacity(k_steps);
    for step_inputs in inputs.chunks(per_step) {
        let omega = it.state().velocity;
        if per_step == 1 {
            it.set_input(step_inputs[0])?;
        } else {
            it.set_input_at_points(step_inputs)?;
        }
        let step = it.step_linearized()?;
        let ak = step.a(Coordinates::Velocity).clone();
        let bk: Vec<DMatrix<f64>> = match step.b_points(Coordinates::Velocity) {
            Some(points) => points.to_vec(),
            None => vec![step.b(Coordinates::Velocity).clone()],
        };
        let end = it.state().velocity;
        let mut dk = ak.view((0, 3), (6, 3)) * omega;
        for (bj, u) in bk.iter().zip(step_inputs) {
            dk += 2.0 * (bj * u);
        }
        for i in 0..3 {
            dk[3 + i] -= end[i];
        }
        d.push(dk / h);
        a.push(ak);
        b.push(bk);
        states.push(*it.state());
    }
    // M_kj = A_{K−1} ⋯ A_{k+1} B_kj and ∂x_K/∂h = Σ_k A_{K−1} ⋯ A_{k+1} d_k, chained
    // backwards.
    let columns = 3 * per_step;
    let mut sensitivity = DMatrix::<f64>::zeros(6, columns * k_steps);
    let mut time_sensitivity = DVector::<f64>::zeros(6);
    let mut chain = DMatrix::<f64>::identity(6, 6);
    for k in (0..k_steps).rev() {
        for (j, bj) in b[k].iter().enumerate() {
            sensitivity
                .view_mut((0, columns * k + 3 * j), (6, 3))
                .copy_from(&(&chain * bj));
        }
        time_sensitivity += &chain * &d[k];
        chain = &chain * &a[k];
    }
    let last = states[k_steps];
    let rotation = last.configuration.inverse().compose(&target.0).log();
    let rates = target.1 - last.velocity;
    let miss = DVector::from_iterator(6, rotation.iter().chain(rates.iter()).copied());
    Ok(Shot {
        states,
        sensitivity,
        time_sensitivity,
        miss,
        a,
        b,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use lgsvi_mechanics::Inertia;

    /// `∂x_K/∂h` from the time scaling against central differences of whole runs, with
    /// torques held over each step and with torques at the Gauss points: with
    /// `δ = 1e-4 h` the difference's truncation error is `~δ² |x‴| ≈ 1e-8` relative and
    /// its rounding `~1e-16/δ·|x| ≈ 1e-11`, so they agree to about 1e-7 relative.
    #[test]
    fn the_time_derivative_matches_central_differences() {
        let body = BuiltInSo3::Free(lgsvi_mechanics::RigidBody::new(
            Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap(),
        ));
        let start = (
            SO3::exp(&Vector3::new(0.2, -0.4, 0.1)),
            Vector3::new(0.3, -0.2, 0.5),
        );
        let target = (SO3::identity(), Vector3::zeros());
        let h = 0.4;
        let points = Integrator::new(body, StepSettings::new(h, 8).unwrap(), start.0, start.1)
            .unwrap()
            .quadrature_nodes()
            .len();
        for per_step in [1, points] {
            let inputs: Vec<Vector3<f64>> = (0..6 * per_step)
                .map(|k| {
                    let t = k as f64 / per_step as f64;
                    Vector3::new(0.1 * t, -0.2, 0.05 * t.sin())
                })
                .collect();
            let at = |h: f64| {
                shoot(
                    body,
                    StepSettings::new(h, 8).unwrap(),
                    start,
                    target,
                    &inputs,
                    per_step,
                )
                .unwrap()
            };
            let shot = at(h);
            let delta = 1e-4 * h;
            let (plus, minus) = (at(h + delta), at(h - delta));
            let (p, m) = (plus.states[6], minus.states[6]);
            let theta = m.configuration.inverse().compose(&p.configuration).log() / (2.0 * delta);
            let omega = (p.velocity - m.velocity) / (2.0 * delta);
            let difference = DVector::from_iterator(6, theta.iter().chain(omega.iter()).copied());
            let error = (&shot.time_sensitivity - &difference).amax() / difference.amax();
            assert!(error < 1e-7, "{per_step} inputs a step: {error:e}");
        }
    }
}
