//! The minimum-energy slew with a tracking cost and/or a terminal cost in place of the
//! exact terminal condition: a nonlinear least-squares problem, solved by Gauss–Newton
//! SQP with the residuals' exact Jacobians.

use crate::energy::{by_step, Start};
use crate::shooting::{shoot, Shot};
use crate::{qp, OptimalError, Slew, Solution, Statistics, Target};
use lgsvi_mechanics::lie::{ExpChart, LieGroup, So3Chart};
use lgsvi_mechanics::{RigidBody, StepSettings};
use nalgebra::{DMatrix, DVector, Vector3};
use std::time::Instant;

/// The weighted residuals of a shot and their Jacobian in the inputs: each tracked state
/// contributes `√(h q_θ) log(R_refᵀ R_k)` and `√(h q_ω) (Ω_k − Ω_ref)`, the soft target
/// `√q_θ log(R_fᵀ R_K)` and `√q_ω (Ω_K − Ω_f)`. A perturbation `R_k exp(δθ)` moves
/// `log(R_refᵀ R_k)` by `J_r(e)⁻¹ δθ` (the inverse right Jacobian at the error `e`).
fn residuals(slew: &Slew, h: f64, shot: &Shot) -> (DVector<f64>, DMatrix<f64>) {
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
    (r, g)
}

/// Solves `slew` with its tracking and/or terminal cost (the crate documentation's
/// iteration, the Gauss–Newton Hessian `diag(2w) + 2 GᵀG` of the least squares).
pub(crate) fn least_squares(
    slew: &Slew,
    settings: StepSettings,
    tolerance: f64,
) -> Result<Solution, OptimalError> {
    let clock = Instant::now();
    let (k_steps, h) = (slew.steps, settings.h());
    let body = RigidBody::new(slew.inertia);
    let Start {
        nodes,
        weights,
        step_weights,
        mut inputs,
    } = Start::of(slew, settings)?;
    let per_step = step_weights.len();
    let exact_target = slew.terminal_cost.is_none();
    let n = 3 * inputs.len();
    let weight = |j: usize| step_weights[(j / 3) % per_step];
    let flat =
        |u: &[Vector3<f64>]| DVector::from_iterator(n, u.iter().flat_map(|v| [v.x, v.y, v.z]));
    let cost = |u: &DVector<f64>, r: &DVector<f64>| {
        u.iter()
            .enumerate()
            .map(|(j, x)| weight(j) * x * x)
            .sum::<f64>()
            + r.norm_squared()
    };
    let shot = |u: &[Vector3<f64>]| shoot(body, settings, slew.start, slew.target, u, per_step);
    let mut run = shot(&inputs)?;
    let (mut r, mut g) = residuals(slew, h, &run);
    let mut statistics = Statistics::default();
    let equality_rows = if exact_target { 6 } else { 0 };
    let mut multipliers = DVector::<f64>::zeros(equality_rows);
    let mut bound_duals = DVector::<f64>::zeros(n);
    let no_rows = DMatrix::<f64>::zeros(0, n);
    let no_miss = DVector::<f64>::zeros(0);
    loop {
        let u = flat(&inputs);
        let gradient =
            DVector::from_fn(n, |j, _| 2.0 * weight(j) * u[j]) + 2.0 * g.transpose() * &r;
        let miss = if exact_target { run.miss.amax() } else { 0.0 };
        let constraint = if exact_target {
            run.sensitivity.transpose() * &multipliers
        } else {
            DVector::zeros(n)
        };
        let stationarity = (&gradient + constraint + &bound_duals).amax() / (1.0 + gradient.amax());
        let residual = stationarity.max(miss);
        statistics.kkt_residuals.push(residual);
        statistics.terminal_misses.push(run.miss.amax());
        if residual <= tolerance && statistics.iterations > 0 {
            break;
        }
        if statistics.iterations >= slew.max_iterations {
            return Err(OptimalError::NotConverged {
                iterations: statistics.iterations,
                residual,
                tolerance,
            });
        }
        statistics.iterations += 1;
        let mut hessian = 2.0 * g.transpose() * &g;
        for j in 0..n {
            hessian[(j, j)] += 2.0 * weight(j);
        }
        let (lower, upper): (Vec<f64>, Vec<f64>) = match slew.torque_max {
            Some(bound) => (0..n)
                .map(|j| (-bound[j % 3] - u[j], bound[j % 3] - u[j]))
                .unzip(),
            None => (vec![f64::NEG_INFINITY; n], vec![f64::INFINITY; n]),
        };
        let (rows, e) = if exact_target {
            (&run.sensitivity, &run.miss)
        } else {
            (&no_rows, &no_miss)
        };
        let solution = qp::solve(
            qp::upper_triangle(&hessian),
            gradient.as_slice(),
            rows,
            e,
            &lower,
            &upper,
            1e-13,
        )?
        .ok_or(OptimalError::Infeasible {
            residual: miss,
            bounded: slew.torque_max.is_some(),
        })?;
        // The merit J + ρ|e|₁ (ρ above the multipliers where the target is exact): halve
        // the step until it falls.
        let rho = 2.0 * solution.lambda.amax() + 1.0;
        let merit = |u: &DVector<f64>, r: &DVector<f64>, run: &Shot| {
            cost(u, r)
                + if exact_target {
                    rho * run.miss.abs().sum()
                } else {
                    0.0
                }
        };
        let before = merit(&u, &r, &run);
        let mut alpha = 1.0;
        loop {
            let trial = &u + alpha * &solution.step;
            let trial_inputs: Vec<Vector3<f64>> = (0..inputs.len())
                .map(|i| Vector3::new(trial[3 * i], trial[3 * i + 1], trial[3 * i + 2]))
                .collect();
            match shot(&trial_inputs) {
                Ok(next) => {
                    let (next_r, next_g) = residuals(slew, h, &next);
                    if merit(&trial, &next_r, &next) <= before || alpha < 1e-3 {
                        inputs = trial_inputs;
                        run = next;
                        (r, g) = (next_r, next_g);
                        break;
                    }
                }
                Err(error) if alpha < 1e-3 => return Err(error),
                Err(_) => {}
            }
            alpha *= 0.5;
        }
        multipliers = solution.lambda;
        bound_duals = solution.nu;
    }
    statistics.time_s = clock.elapsed().as_secs_f64();
    let mut terminal = [0.0; 6];
    if exact_target {
        terminal.copy_from_slice(multipliers.as_slice());
    }
    let u = flat(&inputs);
    let total = cost(&u, &r);
    let (means, at_points) = by_step(&inputs, per_step, &weights);
    Ok(Solution {
        cost: total,
        states: run.states,
        inputs: means,
        inputs_at_points: at_points,
        quadrature_nodes: nodes,
        multipliers: terminal,
        h,
        t_end: h * k_steps as f64,
        converged: true,
        statistics,
    })
}
