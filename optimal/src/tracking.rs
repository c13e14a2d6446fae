//! The residuals of the tracking cost and of a terminal cost in place of the exact
//! terminal condition: they make the minimum-energy slew a nonlinear least-squares
//! problem, which `crate::energy` solves by Gauss–Newton SQP with their exact Jacobians.
//!
//! Each block of residuals reads one state, so its Jacobian is kept in that state's own
//! coordinates (`2D` columns), not chained to the inputs: the gradient `2Gᵀr` follows by
//! the adjoint recursion ([`Shot::input_gradient`]) and the subproblem sees the banded
//! structure of the steps ([`crate::energy`]), both linear in the step count. The dense
//! Jacobian in the inputs, `G = [G_b ∂x_k/∂u]`, is formed only by the tests, for the
//! condensed subproblem they check the banded one against.

use crate::shooting::Shot;
use crate::{Slew, Target};
use lgsvi_mechanics::lie::{ExpChart, LieGroup, So3Chart};
use nalgebra::{DMatrix, DVector, Matrix3};

/// The weighted residuals of a run, in blocks of rows that each read one state.
pub(crate) struct Residuals {
    /// The residuals `r`.
    pub values: DVector<f64>,
    /// Each block: the state `k ≥ 1` it reads, its first row in `values`, and its
    /// Jacobian `G_b` in that state's linearisation coordinates (the block's rows, `2D`
    /// columns).
    pub blocks: Vec<(usize, usize, DMatrix<f64>)>,
}

impl Residuals {
    /// `|r|²`.
    pub fn squared(&self) -> f64 {
        self.values.norm_squared()
    }

    /// The Gauss–Newton model's terms at each state `k = 1 … K` of `shot`: the gradients
    /// `2 Σ_b G_bᵀ r_b` and the Hessians `2 Σ_b G_bᵀ G_b` of the blocks that read it.
    pub fn by_state<St>(&self, shot: &Shot<St>) -> ByState {
        let (states, size) = (shot.states.len() - 1, shot.state_size());
        let mut gradients = vec![DVector::zeros(size); states];
        let mut hessians = vec![DMatrix::zeros(size, size); states];
        for (k, at, g) in &self.blocks {
            let r = self.values.rows(*at, g.nrows());
            gradients[k - 1] += 2.0 * g.transpose() * r;
            hessians[k - 1] += 2.0 * g.transpose() * g;
        }
        ByState {
            gradients,
            hessians,
        }
    }

    /// `2Gᵀr`, the gradient of `|r|²` in the inputs, by the adjoint recursion; the tests'
    /// (the solver forms [`Residuals::by_state`] once an iteration and chains it itself).
    #[cfg(test)]
    pub fn gradient<St>(&self, shot: &Shot<St>) -> DVector<f64> {
        shot.input_gradient(&self.by_state(shot).gradients)
    }

    /// The Jacobian `G` in the inputs, dense (rows of `r`, the run's input columns):
    /// quadratic in the step count; the tests' condensed reference.
    #[cfg(test)]
    pub fn dense<St>(&self, shot: &Shot<St>) -> DMatrix<f64> {
        let sensitivities = shot.full_state_sensitivities();
        let mut g = DMatrix::<f64>::zeros(self.values.len(), shot.sensitivity.ncols());
        for (k, at, block) in &self.blocks {
            g.rows_mut(*at, block.nrows())
                .copy_from(&(block * &sensitivities[k - 1]));
        }
        g
    }
}

/// [`Residuals::by_state`]: the Gauss–Newton model's gradient and Hessian at each state
/// `k = 1 … K` (`[k − 1]`), in the plant's linearisation coordinates.
pub(crate) struct ByState {
    pub gradients: Vec<DVector<f64>>,
    pub hessians: Vec<DMatrix<f64>>,
}

/// The weighted residuals of a shot and their Jacobians in the states they read: each
/// tracked state contributes `√(h q_θ) log(R_refᵀ R_k)` and `√(h q_ω) (Ω_k − Ω_ref)`, the
/// soft target `√q_θ log(R_fᵀ R_K)` and `√q_ω (Ω_K − Ω_f)`. A perturbation `R_k exp(δθ)`
/// moves `log(R_refᵀ R_k)` by `J_r(e)⁻¹ δθ` (the inverse right Jacobian at the error `e`).
/// `None` where the slew has neither cost.
pub(crate) fn residuals(slew: &Slew, h: f64, shot: &Shot) -> Option<Residuals> {
    if slew.tracking.is_none() && slew.terminal_cost.is_none() {
        return None;
    }
    let observation = shot.observation();
    let mut terms: Vec<(usize, Target, [f64; 2])> = Vec::new();
    if let Some((reference, [q_theta, q_omega])) = &slew.tracking {
        for (k, state) in reference.iter().enumerate() {
            terms.push((k + 1, *state, [h * q_theta, h * q_omega]));
        }
    }
    if let Some(weights) = slew.terminal_cost {
        terms.push((shot.states.len() - 1, slew.target, weights));
    }
    let mut values = DVector::<f64>::zeros(6 * terms.len());
    let mut blocks = Vec::with_capacity(terms.len());
    for (row, (k, (attitude, omega), [q_theta, q_omega])) in terms.into_iter().enumerate() {
        let state = &shot.states[k];
        let e = attitude.inverse().compose(&state.configuration).log();
        let (wt, ww) = (q_theta.sqrt(), q_omega.sqrt());
        // The observed rows (θ, ω) to the weighted residual's rows.
        let mut local = DMatrix::<f64>::zeros(6, 6);
        local
            .view_mut((0, 0), (3, 3))
            .copy_from(&(ExpChart.rotation_left_differential_inverse(&e) * wt));
        local
            .view_mut((3, 3), (3, 3))
            .copy_from(&(Matrix3::identity() * ww));
        blocks.push((k, 6 * row, local * &observation));
        values.rows_mut(6 * row, 3).copy_from(&(e * wt));
        values
            .rows_mut(6 * row + 3, 3)
            .copy_from(&((state.velocity - omega) * ww));
    }
    Some(Residuals { values, blocks })
}
