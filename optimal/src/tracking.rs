//! The residuals of the tracking cost and of a terminal cost in place of the exact
//! terminal condition: they make the minimum-energy slew a nonlinear least-squares
//! problem, which `crate::energy` solves by Gauss–Newton SQP with their exact Jacobians.

use crate::shooting::Shot;
use crate::{Slew, Target};
use lgsvi_mechanics::lie::{ExpChart, LieGroup, So3Chart};
use nalgebra::{DMatrix, DVector};

/// The weighted residuals of a shot and their Jacobian in the inputs: each tracked state
/// contributes `√(h q_θ) log(R_refᵀ R_k)` and `√(h q_ω) (Ω_k − Ω_ref)`, the soft target
/// `√q_θ log(R_fᵀ R_K)` and `√q_ω (Ω_K − Ω_f)`. A perturbation `R_k exp(δθ)` moves
/// `log(R_refᵀ R_k)` by `J_r(e)⁻¹ δθ` (the inverse right Jacobian at the error `e`).
/// `None` where the slew has neither cost (the states' sensitivities are then not formed).
pub(crate) fn residuals(slew: &Slew, h: f64, shot: &Shot) -> Option<Residuals> {
    if slew.tracking.is_none() && slew.terminal_cost.is_none() {
        return None;
    }
    let sensitivities = shot.state_sensitivities();
    let columns = shot.sensitivity.ncols();
    let mut terms: Vec<(usize, Target, [f64; 2])> = Vec::new();
    if let Some((reference, [q_theta, q_omega])) = &slew.tracking {
        for (k, state) in reference.iter().enumerate() {
            terms.push((k + 1, *state, [h * q_theta, h * q_omega]));
        }
    }
    if let Some(weights) = slew.terminal_cost {
        terms.push((shot.states.len() - 1, slew.target, weights));
    }
    let mut r = DVector::<f64>::zeros(6 * terms.len());
    let mut g = DMatrix::<f64>::zeros(6 * terms.len(), columns);
    for (row, (k, (attitude, omega), [q_theta, q_omega])) in terms.into_iter().enumerate() {
        let state = &shot.states[k];
        let e = attitude.inverse().compose(&state.configuration).log();
        let jacobian = ExpChart.rotation_left_differential_inverse(&e);
        let (wt, ww) = (q_theta.sqrt(), q_omega.sqrt());
        let s = &sensitivities[k - 1];
        let theta_rows = jacobian * s.rows(0, 3) * wt;
        let omega_rows = s.rows(3, 3) * ww;
        g.view_mut((6 * row, 0), (3, columns))
            .copy_from(&theta_rows);
        g.view_mut((6 * row + 3, 0), (3, columns))
            .copy_from(&omega_rows);
        r.rows_mut(6 * row, 3).copy_from(&(e * wt));
        r.rows_mut(6 * row + 3, 3)
            .copy_from(&((state.velocity - omega) * ww));
    }
    Some((r, g))
}

/// The weighted residuals and their Jacobian in the inputs.
pub(crate) type Residuals = (DVector<f64>, DMatrix<f64>);
