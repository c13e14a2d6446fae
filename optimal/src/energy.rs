//! The minimum-energy slew: Gauss–Newton SQP over the torques at a fixed final time.

use crate::shooting::shoot;
use crate::{qp, OptimalError, Slew, Solution, Statistics};
use lgsvi_mechanics::{RigidBody, StepSettings};
use nalgebra::{DVector, Vector3};
use std::time::Instant;

/// Solves `slew` for the least `Σ h |u_k|²` (the crate documentation's iteration).
pub(crate) fn minimum_energy(
    slew: &Slew,
    settings: StepSettings,
    tolerance: f64,
) -> Result<Solution, OptimalError> {
    let clock = Instant::now();
    let (k_steps, h) = (slew.steps, settings.h());
    let body = RigidBody::new(slew.inertia);
    let mut inputs = slew
        .initial
        .clone()
        .unwrap_or_else(|| vec![Vector3::zeros(); k_steps]);
    if let Some(bound) = slew.torque_max {
        for u in &mut inputs {
            *u = u.zip_map(&bound, |x, b| x.clamp(-b, b));
        }
    }
    let cost = |u: &[Vector3<f64>]| h * u.iter().map(|u| u.norm_squared()).sum::<f64>();
    let mut statistics = Statistics::default();
    let mut multipliers = DVector::<f64>::zeros(6);
    let mut bound_duals = DVector::<f64>::zeros(3 * k_steps);
    let shot = |u: &[Vector3<f64>]| shoot(body, settings, slew.start, slew.target, u);
    let mut run = shot(&inputs)?;
    loop {
        let miss = run.miss.amax();
        let gradient = DVector::from_iterator(
            3 * k_steps,
            inputs
                .iter()
                .flat_map(|u| [2.0 * h * u.x, 2.0 * h * u.y, 2.0 * h * u.z]),
        );
        let stationarity = (&gradient + run.sensitivity.transpose() * &multipliers + &bound_duals)
            .amax()
            / (1.0 + gradient.amax());
        let residual = stationarity.max(miss);
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
        // ½ δuᵀ (2h I) δu + (2h u)ᵀ δu: the cost Σ h |u + δu|² up to a constant; the
        // bounds |u + δu| ≤ u_max.
        let n = 3 * k_steps;
        let flat: Vec<f64> = inputs.iter().flat_map(|u| [u.x, u.y, u.z]).collect();
        let (lower, upper): (Vec<f64>, Vec<f64>) = match slew.torque_max {
            Some(bound) => (0..n)
                .map(|j| (-bound[j % 3] - flat[j], bound[j % 3] - flat[j]))
                .unzip(),
            None => (vec![f64::NEG_INFINITY; n], vec![f64::INFINITY; n]),
        };
        let solution = qp::solve(
            qp::diagonal(&vec![2.0 * h; n]),
            gradient.as_slice(),
            &run.sensitivity,
            &run.miss,
            &lower,
            &upper,
            1e-13,
        )?
        .ok_or(OptimalError::Infeasible {
            residual: miss,
            bounded: slew.torque_max.is_some(),
        })?;
        let (step, lambda) = (&solution.step, &solution.lambda);
        // The merit J + ρ|e|₁, ρ above the multipliers: halve the step until it falls.
        let rho = 2.0 * lambda.amax() + 1.0;
        let merit = |c: f64, e: &DVector<f64>| c + rho * e.iter().map(|x| x.abs()).sum::<f64>();
        let before = merit(cost(&inputs), &run.miss);
        let mut alpha = 1.0;
        let (next_inputs, next_run) = loop {
            let trial: Vec<Vector3<f64>> = inputs
                .iter()
                .enumerate()
                .map(|(k, u)| {
                    u + alpha * Vector3::new(step[3 * k], step[3 * k + 1], step[3 * k + 2])
                })
                .collect();
            match shot(&trial) {
                Ok(r) if merit(cost(&trial), &r.miss) <= before || alpha < 1e-3 => {
                    break (trial, r)
                }
                Err(error) if alpha < 1e-3 => return Err(error),
                _ => alpha *= 0.5,
            }
        };
        inputs = next_inputs;
        run = next_run;
        multipliers = solution.lambda;
        bound_duals = solution.nu;
    }
    statistics.time_s = clock.elapsed().as_secs_f64();
    let mut terminal = [0.0; 6];
    terminal.copy_from_slice(multipliers.as_slice());
    Ok(Solution {
        cost: cost(&inputs),
        states: run.states,
        inputs,
        multipliers: terminal,
        h,
        t_end: h * k_steps as f64,
        converged: true,
        statistics,
    })
}
