//! The minimum-energy slew: Gauss–Newton SQP over the torques at a fixed final time.

use crate::shooting::shoot;
use crate::tracking::{residuals, Residuals};
use crate::{qp, quadrature, Inputs, OptimalError, Slew, Solution, Statistics};
use lgsvi_mechanics::StepSettings;
use nalgebra::{DMatrix, DVector, Vector3};
use std::time::Instant;

/// Solves `slew` for the least `∫|u|² dt` (the crate documentation's iteration): with
/// constant torques `Σ_k h |u_k|²`, with polynomial ones the steps' quadrature
/// `Σ_k h Σ_j b_j |u_kj|²`; plus, where given, the tracking and terminal costs
/// (`crate::tracking`), whose residuals `r` and their Jacobian `G` add `|r|²` to the cost,
/// `2Gᵀr` to its gradient and `2GᵀG` to the Gauss–Newton Hessian `diag(2w)`. Without a
/// terminal cost the terminal state is exact (the QP's six equality rows).
pub(crate) fn minimum_energy(
    slew: &Slew,
    settings: StepSettings,
    tolerance: f64,
) -> Result<Solution, OptimalError> {
    let clock = Instant::now();
    let (k_steps, h) = (slew.steps, settings.h());
    let body = slew.system()?;
    let Start {
        nodes,
        weights,
        step_weights,
        mut inputs,
    } = Start::of(slew, settings)?;
    let per_step = step_weights.len();
    let exact_target = slew.terminal_cost.is_none();
    let weight = |i: usize| step_weights[i % per_step];
    let cost = |u: &[Vector3<f64>], r: Option<&Residuals>| {
        u.iter()
            .enumerate()
            .map(|(i, u)| weight(i) * u.norm_squared())
            .sum::<f64>()
            + r.map_or(0.0, |(r, _)| r.norm_squared())
    };
    let mut statistics = Statistics::default();
    let mut multipliers = DVector::<f64>::zeros(if exact_target { 6 } else { 0 });
    let n = 3 * inputs.len();
    let mut bound_duals = DVector::<f64>::zeros(n);
    let shot =
        |u: &[Vector3<f64>]| shoot(body, settings, slew.start, slew.target, u, per_step, false);
    let mut run = shot(&inputs)?;
    let mut fit = residuals(slew, h, &run);
    let diagonal: Vec<f64> = (0..n).map(|j| 2.0 * weight(j / 3)).collect();
    let (no_rows, no_miss) = (DMatrix::<f64>::zeros(0, n), DVector::<f64>::zeros(0));
    loop {
        let miss = run.miss.amax();
        let mut gradient = DVector::from_iterator(
            n,
            inputs.iter().enumerate().flat_map(|(i, u)| {
                let w = 2.0 * weight(i);
                [w * u.x, w * u.y, w * u.z]
            }),
        );
        if let Some((r, g)) = &fit {
            gradient += 2.0 * g.transpose() * r;
        }
        let (rows, e) = if exact_target {
            (&run.sensitivity, &run.miss)
        } else {
            (&no_rows, &no_miss)
        };
        let stationarity = (&gradient + rows.transpose() * &multipliers + &bound_duals).amax()
            / (1.0 + gradient.amax());
        let residual = if exact_target {
            stationarity.max(miss)
        } else {
            stationarity
        };
        statistics.kkt_residuals.push(residual);
        statistics.terminal_misses.push(miss);
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
        // ½ δᵀ H δ + gᵀ δ: the cost up to a constant (exact in δ for the energy, the
        // Gauss–Newton model of the residuals); the bounds |u + δu| ≤ u_max.
        let hessian = match &fit {
            None => qp::diagonal(&diagonal),
            Some((_, g)) => {
                let mut dense = 2.0 * g.transpose() * g;
                for (j, d) in diagonal.iter().enumerate() {
                    dense[(j, j)] += d;
                }
                qp::upper_triangle(&dense)
            }
        };
        let flat: Vec<f64> = inputs.iter().flat_map(|u| [u.x, u.y, u.z]).collect();
        let (lower, upper): (Vec<f64>, Vec<f64>) = match slew.torque_max {
            Some(bound) => (0..n)
                .map(|j| (-bound[j % 3] - flat[j], bound[j % 3] - flat[j]))
                .unzip(),
            None => (vec![f64::NEG_INFINITY; n], vec![f64::INFINITY; n]),
        };
        let solution = qp::solve(hessian, gradient.as_slice(), rows, e, &lower, &upper, 1e-13)?
            .ok_or(OptimalError::Infeasible {
                residual: miss,
                bounded: slew.torque_max.is_some(),
            })?;
        let (step, lambda) = (&solution.step, &solution.lambda);
        // The merit J + ρ|e|₁ (ρ above the multipliers; the miss only where the target is
        // exact): halve the step until it falls.
        let rho = 2.0 * lambda.amax() + 1.0;
        let merit = |c: f64, e: &DVector<f64>| {
            c + if exact_target {
                rho * e.iter().map(|x| x.abs()).sum::<f64>()
            } else {
                0.0
            }
        };
        let before = merit(cost(&inputs, fit.as_ref()), &run.miss);
        let mut alpha = 1.0;
        let (next_inputs, next_run, next_fit) = loop {
            let trial: Vec<Vector3<f64>> = inputs
                .iter()
                .enumerate()
                .map(|(i, u)| {
                    u + alpha * Vector3::new(step[3 * i], step[3 * i + 1], step[3 * i + 2])
                })
                .collect();
            match shot(&trial) {
                Ok(r) => {
                    let f = residuals(slew, h, &r);
                    if merit(cost(&trial, f.as_ref()), &r.miss) <= before || alpha < 1e-3 {
                        break (trial, r, f);
                    }
                    alpha *= 0.5;
                }
                Err(error) if alpha < 1e-3 => return Err(error),
                Err(_) => alpha *= 0.5,
            }
        };
        inputs = next_inputs;
        run = next_run;
        fit = next_fit;
        multipliers = solution.lambda;
        bound_duals = solution.nu;
    }
    statistics.time_s = clock.elapsed().as_secs_f64();
    let mut terminal = [0.0; 6];
    if exact_target {
        terminal.copy_from_slice(multipliers.as_slice());
    }
    let (means, at_points) = by_step(&inputs, per_step, &weights);
    Ok(Solution {
        cost: cost(&inputs, fit.as_ref()),
        states: run.states,
        wheel_speeds: run.wheel_speeds,
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

/// The torques a minimum-energy iteration starts from, with the step's quadrature.
pub(crate) struct Start {
    /// The Gauss points as fractions of a step.
    pub nodes: Vec<f64>,
    /// Their weights `b_j`.
    pub weights: Vec<f64>,
    /// The quadrature weight of each input of a step: `h` for a held torque, `h b_j` at
    /// the Gauss points.
    pub step_weights: Vec<f64>,
    /// The warm start (one per step spread over the points, or one per point), else rest,
    /// clamped to the bounds.
    pub inputs: Vec<Vector3<f64>>,
}

impl Start {
    pub(crate) fn of(slew: &Slew, settings: StepSettings) -> Result<Self, OptimalError> {
        let (k_steps, h) = (slew.steps, settings.h());
        let (nodes, weights) = quadrature(slew, settings)?;
        let step_weights: Vec<f64> = match slew.inputs {
            Inputs::Constant => vec![h],
            _ => weights.iter().map(|b| h * b).collect(),
        };
        let per_step = step_weights.len();
        let mut inputs: Vec<Vector3<f64>> = match &slew.initial {
            Some(initial) if initial.len() == k_steps * per_step => initial.clone(),
            Some(initial) => initial
                .iter()
                .flat_map(|u| std::iter::repeat_n(*u, per_step))
                .collect(),
            None => vec![Vector3::zeros(); k_steps * per_step],
        };
        if let Some(bound) = slew.torque_max {
            for u in &mut inputs {
                *u = u.zip_map(&bound, |x, b| x.clamp(-b, b));
            }
        }
        Ok(Self {
            nodes,
            weights,
            step_weights,
            inputs,
        })
    }
}

/// Each step's torque (its mean `Σ_j b_j u_kj` at the Gauss points) and, with inputs at the
/// points, each step's values there.
#[allow(clippy::type_complexity)]
pub(crate) fn by_step(
    inputs: &[Vector3<f64>],
    per_step: usize,
    weights: &[f64],
) -> (Vec<Vector3<f64>>, Vec<Vec<Vector3<f64>>>) {
    if per_step == 1 {
        return (inputs.to_vec(), Vec::new());
    }
    let steps: Vec<Vec<Vector3<f64>>> = inputs.chunks(per_step).map(|c| c.to_vec()).collect();
    let means = steps
        .iter()
        .map(|c| c.iter().zip(weights).map(|(u, b)| u * *b).sum())
        .collect();
    (means, steps)
}
