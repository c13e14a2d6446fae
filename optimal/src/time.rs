//! The least time of a slew or a manoeuvre: SQP over the inputs and the common step
//! length, the Lagrangian's Hessian by differences of its exact gradient on the free
//! variables.

use crate::energy::minimum_energy;
use crate::qp::QpSolution;
use crate::shooting::{shoot, Shot};
use crate::{qp, Cost, OptimalError, Slew, Solution, Statistics};
use lgsvi_mechanics::StepSettings;
use nalgebra::{DMatrix, DVector, SVector, Vector3};
use std::ops::Range;
use std::time::Instant;

/// The largest relative change of the step length in one iteration (a trust region on
/// the one variable the problem is not bounded in).
const TIME_TRUST: f64 = 0.3;

/// The subproblem's tolerance: two orders below the default KKT tolerance, since at a
/// degenerate vertex (fewer free torques than terminal conditions: a switch on a step's
/// boundary) the refitted multipliers are not unique and the subproblem's own carry the
/// residual (at 1e-10, 7 of 84 slews swept stalled just above 1e-10; at 1e-12 none).
const QP_TOLERANCE: f64 = 1e-12;

/// Solves `slew` for the least final time (the crate documentation's iteration): from
/// the coarsest of a ladder of step counts (halving `K` while at least `2 ×`
/// [`COARSEST`]) up to `K`, each level started from the one below (its torques sampled
/// at the finer steps' midpoints).
///
/// A heavy top without a warm start is started from the same slew without gravity (its
/// least time and torques): gravity does not scale with the time, so the rest-to-rest
/// start of [`feasible_start`] does not hold for it, and the bounded minimum-energy start
/// it falls back on can lead to a worse local minimum. Where that continuation fails, the
/// fallback is taken.
pub(crate) fn minimum_time(slew: &Slew, tolerance: f64) -> Result<Solution, OptimalError> {
    let mut continuation = None;
    if slew.gravity.is_some() && slew.initial.is_none() {
        let free = Slew {
            gravity: None,
            ..slew.clone()
        };
        if let Ok(weightless) = minimum_time(&free, tolerance) {
            // The two stages share the iteration budget; the statistics cover both.
            let used = weightless.statistics.iterations;
            let continued = Slew {
                t_end: weightless.t_end,
                initial: Some(weightless.inputs),
                max_iterations: slew.max_iterations.saturating_sub(used),
                ..slew.clone()
            };
            match minimum_time(&continued, tolerance) {
                Ok(mut solution) => {
                    let (first, then) = (weightless.statistics, &mut solution.statistics);
                    then.iterations += first.iterations;
                    then.time_s += first.time_s;
                    then.kkt_residuals.splice(0..0, first.kkt_residuals);
                    then.terminal_misses.splice(0..0, first.terminal_misses);
                    return Ok(solution);
                }
                Err(error) => continuation = Some(error),
            }
        }
    }
    // Where the continuation failed and so does this, its error is the one to report (the
    // fallback's own start works to a looser tolerance than the one asked for).
    fallback(slew, tolerance).map_err(|error| continuation.unwrap_or(error))
}

/// What the least time asks of a problem with inputs of `W` entries: a slew (three
/// torques, [`Slew`]) or a manoeuvre in space (a wrench, [`crate::Manoeuvre`]).
pub(crate) trait Timed<const W: usize> {
    /// The state recorded at each step boundary.
    type State;
    /// Each input entry's bound, all finite (the least time needs them: without a bound
    /// any time is reachable).
    fn bound(&self) -> Result<SVector<f64, W>, OptimalError>;
    /// The step count, nodes, iteration limit and warm start asked for.
    fn settings(&self) -> TimeSettings;
    /// The run of `inputs` (one held over each step of `settings`) with `∂x_K/∂h`: the
    /// miss and its sensitivities in the rows the tolerance measures.
    fn shoot(
        &self,
        settings: StepSettings,
        inputs: &[SVector<f64, W>],
    ) -> Result<Shot<Self::State>, OptimalError>;
    /// The rows of the miss that are rates (the body rates, and a body in space's velocity),
    /// scaled by `T_ref`: the body rates then in radians, commensurate with the attitude's.
    fn rate_rows(&self) -> Range<usize>;
    /// Inputs for `k_steps` steps and a final time that reach the target
    /// ([`feasible_start`] for a slew).
    fn feasible_start(&self, k_steps: usize) -> Result<(Vec<SVector<f64, W>>, f64), OptimalError>;
}

/// What a least-time problem asks for beside its inputs and targets.
pub(crate) struct TimeSettings {
    /// The step count `K`.
    pub steps: usize,
    /// Nodes a step.
    pub nodes: usize,
    /// The most SQP iterations.
    pub max_iterations: usize,
    /// Whether the iteration starts from the user's inputs (no ladder, no perturbation).
    pub warm: bool,
}

impl Timed<3> for Slew {
    type State = lgsvi_mechanics::State;
    fn bound(&self) -> Result<Vector3<f64>, OptimalError> {
        self.torque_max.ok_or_else(|| OptimalError::InvalidSetting {
            name: "torque_max",
            value: "(none)".into(),
            reason: "a minimum-time slew needs a torque bound (without one, any time is reachable)"
                .into(),
        })
    }
    fn settings(&self) -> TimeSettings {
        TimeSettings {
            steps: self.steps,
            nodes: self.nodes,
            max_iterations: self.max_iterations,
            warm: self.initial.is_some(),
        }
    }
    fn shoot(&self, settings: StepSettings, inputs: &[Vector3<f64>]) -> Result<Shot, OptimalError> {
        shoot(
            self.system()?,
            settings,
            self.start,
            self.target,
            inputs,
            1,
            true,
        )
    }
    fn rate_rows(&self) -> Range<usize> {
        3..6
    }
    fn feasible_start(&self, k_steps: usize) -> Result<(Vec<Vector3<f64>>, f64), OptimalError> {
        feasible_start(&Slew {
            steps: k_steps,
            ..self.clone()
        })
    }
}

/// [`minimum_time`] from the ladder's own start.
fn fallback(slew: &Slew, tolerance: f64) -> Result<Solution, OptimalError> {
    let found = least_time(slew, tolerance)?;
    let settings = StepSettings::new(found.h, slew.nodes)?;
    let mut multipliers = [0.0; 6];
    multipliers.copy_from_slice(&found.multipliers);
    Ok(Solution {
        cost: found.t_end,
        states: found.shot.states,
        wheel_speeds: found.shot.wheel_speeds,
        inputs: found.inputs,
        inputs_at_points: Vec::new(),
        quadrature_nodes: crate::quadrature(slew, settings)?.0,
        multipliers,
        h: found.h,
        t_end: found.t_end,
        converged: true,
        statistics: found.statistics,
    })
}

/// A problem solved for the least time.
pub(crate) struct Fastest<St, const W: usize> {
    /// The inputs, one a step.
    pub inputs: Vec<SVector<f64, W>>,
    /// Their run.
    pub shot: Shot<St>,
    /// The step length and the final time.
    pub h: f64,
    pub t_end: f64,
    /// The terminal constraint's multipliers `∂T*/∂e`, in the rows of [`Timed::shoot`]'s
    /// miss.
    pub multipliers: Vec<f64>,
    /// The solver's record.
    pub statistics: Statistics,
}

/// The least time of `problem` (the crate documentation's iteration): from the coarsest
/// of a ladder of step counts (halving `K` while at least `2 ×` [`COARSEST`]) up to `K`,
/// each level started from the one below (its inputs sampled at the finer steps'
/// midpoints).
pub(crate) fn least_time<P: Timed<W>, const W: usize>(
    problem: &P,
    tolerance: f64,
) -> Result<Fastest<P::State, W>, OptimalError> {
    let clock = Instant::now();
    let bound = problem.bound()?;
    let mut ladder = vec![problem.settings().steps];
    while !problem.settings().warm && ladder[ladder.len() - 1] >= 2 * COARSEST {
        ladder.push(ladder[ladder.len() - 1].div_ceil(2));
    }
    let mut statistics = Statistics::default();
    let climbed = climb(problem, bound, &ladder, tolerance, &mut statistics);
    let (inputs, last) = match climbed {
        Ok(found) => found,
        // A lower level that does not converge (too few steps for the body, a start far
        // off) leaves the problem to the full step count from the start: its error, if
        // any, is then about the tolerance asked for.
        Err(_) if ladder.len() > 1 => {
            statistics = Statistics::default();
            climb(problem, bound, &ladder[..1], tolerance, &mut statistics)?
        }
        Err(error) => return Err(error),
    };
    statistics.time_s = clock.elapsed().as_secs_f64();
    // The multipliers in the unscaled miss, as the energy's are: the scaled objective
    // is T/T_ref and the scaled rates rows ω·T_ref; those that fit best ([`best_fit`]).
    let mut gradient = DVector::<f64>::zeros(last.z.len());
    gradient[last.z.len() - 1] = 1.0;
    let lambda = match &last.multipliers {
        Some(subproblem) => best_fit(&last.z, &last.jacobian, &gradient, subproblem).0,
        None => least_squares_multipliers(&last.jacobian, &gradient, &last.z),
    };
    let rates = problem.rate_rows();
    // `∂T*/∂e` is the negative of the rows `M δ = e`'s multipliers.
    let multipliers = lambda
        .iter()
        .enumerate()
        .map(|(i, l)| -l * last.t_ref * if rates.contains(&i) { last.t_ref } else { 1.0 })
        .collect();
    let t_end = last.h * last.k_steps as f64;
    Ok(Fastest {
        inputs,
        h: last.h,
        t_end,
        shot: last.shot,
        multipliers,
        statistics,
    })
}

/// The ladder's levels from the coarsest (last) to `ladder[0]`: the last level's inputs
/// and shot.
#[allow(clippy::type_complexity)]
fn climb<P: Timed<W>, const W: usize>(
    timed: &P,
    bound: SVector<f64, W>,
    ladder: &[usize],
    tolerance: f64,
    statistics: &mut Statistics,
) -> Result<(Vec<SVector<f64, W>>, Scaled<P::State>), OptimalError> {
    let mut solved: Option<(Vec<SVector<f64, W>>, Scaled<P::State>)> = None;
    for (level, &k_steps) in ladder.iter().enumerate().rev() {
        let problem = Problem {
            timed,
            bound,
            k_steps,
        };
        let level_tolerance = if level == 0 {
            tolerance
        } else {
            LADDER_TOLERANCE
        };
        let found = match solved.take() {
            None => problem.coarsest(level_tolerance, statistics)?,
            Some((coarse, below)) => {
                let fine: Vec<SVector<f64, W>> = (0..k_steps)
                    .map(|k| {
                        coarse[((2 * k + 1) * coarse.len() / (2 * k_steps)).min(coarse.len() - 1)]
                    })
                    .collect();
                let t_coarse = below.h * below.k_steps as f64;
                let z0 = problem.scaled(&fine, 0.0);
                problem.sqp(z0, t_coarse, level_tolerance, statistics)?
            }
        };
        solved = Some((problem.inputs(&found.z), found));
    }
    Ok(solved.expect("the ladder has at least one level"))
}

/// The step counts below which the ladder stops halving.
const COARSEST: usize = 20;

/// The KKT tolerance of the ladder's lower levels (their solutions only start the next).
const LADDER_TOLERANCE: f64 = 1e-6;

/// The size of the perturbation of the coarsest level's first start, in units of the
/// bound.
const PERTURBATION: f64 = 0.2;

/// One level of the ladder.
struct Problem<'a, P, const W: usize> {
    timed: &'a P,
    bound: SVector<f64, W>,
    k_steps: usize,
}

impl<P: Timed<W>, const W: usize> Problem<'_, P, W> {
    /// The coarsest level, from the warm start if one is given, else from the
    /// minimum-energy motion perturbed by [`PERTURBATION`] (a rest-to-rest turn about a
    /// principal axis is a symmetric stationary point of the time, a saddle, which an
    /// unperturbed start can stall on), and unperturbed if that fails.
    fn coarsest(
        &self,
        tolerance: f64,
        statistics: &mut Statistics,
    ) -> Result<Scaled<P::State>, OptimalError> {
        let (inputs, t_start) = self.timed.feasible_start(self.k_steps)?;
        if self.timed.settings().warm {
            return self.sqp(self.scaled(&inputs, 0.0), t_start, tolerance, statistics);
        }
        match self.sqp(
            self.scaled(&inputs, PERTURBATION),
            t_start,
            tolerance,
            statistics,
        ) {
            Ok(found) => Ok(found),
            Err(first) => self
                .sqp(self.scaled(&inputs, 0.0), t_start, tolerance, statistics)
                .map_err(|_| first),
        }
    }

    /// The scaled variables of `inputs` (inputs over their bounds, the step length 1 in
    /// units of `T_ref/K`), with a perturbation `size · sin((i+1)πt/T)` on entry `i`.
    fn scaled(&self, inputs: &[SVector<f64, W>], size: f64) -> DVector<f64> {
        let n = W * self.k_steps + 1;
        let mut z = DVector::<f64>::zeros(n);
        for (k, u) in inputs.iter().enumerate() {
            let t = (k as f64 + 0.5) / self.k_steps as f64;
            for i in 0..W {
                let wave = size * ((i + 1) as f64 * std::f64::consts::PI * t).sin();
                z[W * k + i] = (u[i] / self.bound[i] + wave).clamp(-1.0, 1.0);
            }
        }
        z[n - 1] = 1.0;
        z
    }

    /// The inputs of scaled variables.
    fn inputs(&self, z: &DVector<f64>) -> Vec<SVector<f64, W>> {
        (0..self.k_steps)
            .map(|k| SVector::from_fn(|i, _| z[W * k + i] * self.bound[i]))
            .collect()
    }

    /// The shot of scaled variables, `T_ref` the time of `σ = 1`.
    fn run(&self, z: &DVector<f64>, t_ref: f64) -> Result<Scaled<P::State>, OptimalError> {
        let h_ref = t_ref / self.k_steps as f64;
        let settings = StepSettings::new(z[z.len() - 1] * h_ref, self.timed.settings().nodes)?;
        let shot = self.timed.shoot(settings, &self.inputs(z))?;
        Ok(Scaled::of(
            shot,
            z.clone(),
            self.bound.as_slice(),
            self.timed.rate_rows(),
            (h_ref, t_ref),
            self.k_steps,
        ))
    }
    /// The SQP from `z` with `σ = 1` meaning the final time `t_ref`: the solution's shot.
    fn sqp(
        &self,
        mut z: DVector<f64>,
        t_ref: f64,
        tolerance: f64,
        statistics: &mut Statistics,
    ) -> Result<Scaled<P::State>, OptimalError> {
        let n = z.len();
        let run = |z: &DVector<f64>| self.run(z, t_ref);
        let mut current = run(&z)?;
        let mut gradient = DVector::<f64>::zeros(n);
        gradient[n - 1] = 1.0;
        let mut multipliers = least_squares_multipliers(&current.jacobian, &gradient, &z);
        let mut iterations = 0;
        let mut mirrored = false;
        loop {
            let miss = current.miss.amax();
            let stationarity = stationarity(&z, &current.jacobian, &gradient, &multipliers);
            let residual = stationarity.max(miss);
            statistics.kkt_residuals.push(residual);
            statistics.terminal_misses.push(current.shot.miss.amax());
            if residual <= tolerance && iterations > 0 {
                current.multipliers = Some(multipliers);
                return Ok(current);
            }
            if statistics.iterations >= self.timed.settings().max_iterations {
                return Err(OptimalError::NotConverged {
                    iterations: statistics.iterations,
                    residual,
                    tolerance,
                });
            }
            statistics.iterations += 1;
            iterations += 1;
            let hessians = lagrangian_hessian(&z, &multipliers, &current, &run)?;
            let (mut lower, mut upper): (Vec<f64>, Vec<f64>) =
                (0..n - 1).map(|j| (-1.0 - z[j], 1.0 - z[j])).unzip();
            lower.push(-TIME_TRUST * z[n - 1]);
            upper.push(TIME_TRUST * z[n - 1]);
            let solve = |hessian: &DMatrix<f64>,
                         e: &DVector<f64>|
             -> Result<Option<QpSolution>, OptimalError> {
                Ok(qp::solve(
                    qp::upper_triangle(hessian),
                    gradient.as_slice(),
                    &current.jacobian,
                    e,
                    &lower,
                    &upper,
                    QP_TOLERANCE,
                )?
                .map(|found| {
                    polish(
                        hessian,
                        &gradient,
                        &current.jacobian,
                        e,
                        &z,
                        &lower,
                        &upper,
                        &found,
                        tolerance,
                    )
                    .unwrap_or_else(|| project(&current.jacobian, e, &z, &lower, &upper, found))
                }))
            };
            let primary = if mirrored {
                &hessians.mirrored
            } else {
                &hessians.floored
            };
            let solution = solve(primary, &current.miss)?.ok_or(OptimalError::Infeasible {
                residual: current.shot.miss.amax(),
                bounded: true,
            })?;
            // The merit σ + ρ|e|₁ with ρ above the subproblem's multipliers, at each
            // iteration (`MERIT_MARGIN`).
            let rho = 2.0 * solution.lambda.amax() + MERIT_MARGIN;
            let merit = |z: &DVector<f64>, e: &DVector<f64>| z[n - 1] + rho * e.abs().sum();
            let before = merit(&z, &current.miss);
            let accepts = |z: &DVector<f64>, r: &Scaled<P::State>| {
                merit(z, &r.miss) <= before + ROUNDING * (1.0 + before.abs())
            };
            let full = snap(&z + &solution.step, &solution.nu);
            let first = run(&full);
            let (next_z, next, lambda) = match first {
                Ok(r) if accepts(&full, &r) => (full, r, solution.lambda),
                _ => {
                    // A second-order correction (the full step's miss against its
                    // linearisation, put back into the subproblem) before backtracking:
                    // the ℓ1 merit otherwise refuses steps along the constraints'
                    // curvature.
                    let corrected = match &first {
                        Ok(r) => {
                            let e = &r.miss + &current.jacobian * &solution.step;
                            solve(primary, &e)?.and_then(|c| {
                                let trial = snap(&z + &c.step, &c.nu);
                                let r = run(&trial).ok()?;
                                accepts(&trial, &r).then_some((trial, r, solution.lambda.clone()))
                            })
                        }
                        Err(_) => None,
                    };
                    // Then the mirrored model's full step (`Hessians::mirrored`, where it
                    // differs), the model of every later iteration once taken. A
                    // subproblem that fails here leaves the step to the backtracking.
                    let corrected = match corrected {
                        Some(accepted) => Some(accepted),
                        None if mirrored || !hessians.differ => None,
                        None => solve(&hessians.mirrored, &current.miss)
                            .ok()
                            .flatten()
                            .and_then(|c| {
                                let trial = snap(&z + &c.step, &c.nu);
                                let r = run(&trial).ok()?;
                                accepts(&trial, &r).then_some((trial, r, c.lambda))
                            })
                            .inspect(|_| mirrored = true),
                    };
                    match corrected {
                        Some(accepted) => accepted,
                        None => {
                            let mut alpha = 1.0;
                            loop {
                                alpha *= 0.5;
                                let trial = snap(&z + alpha * &solution.step, &solution.nu);
                                match run(&trial) {
                                    Ok(r) if accepts(&trial, &r) || alpha < 1e-3 => {
                                        break (trial, r, solution.lambda.clone())
                                    }
                                    Err(error) if alpha < 1e-3 => return Err(error),
                                    _ => {}
                                }
                            }
                        }
                    }
                }
            };
            z = next_z;
            current = next;
            multipliers = lambda;
        }
    }
}

/// A shot in the scaled variables.
struct Scaled<St> {
    shot: Shot<St>,
    /// The scaled variables.
    z: DVector<f64>,
    /// The time of `σ = 1`.
    t_ref: f64,
    /// The step length and count.
    h: f64,
    k_steps: usize,
    /// `∂e/∂z` up to sign (`m × (WK+1)`), rates rows times `T_ref`.
    jacobian: DMatrix<f64>,
    /// The miss, rates rows times `T_ref`.
    miss: DVector<f64>,
    /// The multipliers of the last subproblem that led here (scaled rows), where one did.
    multipliers: Option<DVector<f64>>,
}

impl<St> Scaled<St> {
    /// `shot` of the scaled variables `z` (inputs over `bound`, the step length over
    /// `h_ref`), its `rates` rows scaled by `t_ref`.
    fn of(
        shot: Shot<St>,
        z: DVector<f64>,
        bound: &[f64],
        rates: Range<usize>,
        (h_ref, t_ref): (f64, f64),
        k_steps: usize,
    ) -> Self {
        let h = z[z.len() - 1] * h_ref;
        let (rows, columns) = shot.sensitivity.shape();
        let mut jacobian = DMatrix::<f64>::zeros(rows, columns + 1);
        for j in 0..columns {
            jacobian
                .column_mut(j)
                .copy_from(&(shot.sensitivity.column(j) * bound[j % bound.len()]));
        }
        jacobian
            .column_mut(columns)
            .copy_from(&(&shot.time_sensitivity * h_ref));
        let mut miss = shot.miss.clone();
        for i in rates {
            jacobian.row_mut(i).scale_mut(t_ref);
            miss[i] *= t_ref;
        }
        Self {
            shot,
            z,
            t_ref,
            h,
            k_steps,
            jacobian,
            miss,
            multipliers: None,
        }
    }
}

/// Torques and a final time that reach the target: the warm start if given; for a
/// rest-to-rest slew, the unbounded minimum-energy slew at the given time rescaled in
/// time until its largest torque meets its bound (the time scaling of
/// [`crate::shooting::shoot`] is exact for the step, and leaves rest at rest: the
/// rescaled torques reach the target whatever the first guess); else (and under gravity or
/// a disturbance) the bounded minimum-energy slew at the given time, half as long again
/// until one exists.
fn feasible_start(slew: &Slew) -> Result<(Vec<Vector3<f64>>, f64), OptimalError> {
    if let Some(initial) = &slew.initial {
        return Ok((initial.clone(), slew.t_end));
    }
    let settings = |t_end: f64| StepSettings::new(t_end / slew.steps as f64, slew.nodes);
    let bound = slew
        .torque_max
        .unwrap_or_else(|| Vector3::repeat(f64::INFINITY));
    // Rest to rest (the wheels too: their rates would scale with the time), and without
    // gravity or a disturbance (which do not scale with it).
    let wheels_at_rest = slew.wheels.is_none_or(|w| w.speeds == Vector3::zeros());
    if slew.start.1 == Vector3::zeros()
        && slew.target.1 == Vector3::zeros()
        && wheels_at_rest
        && slew.gravity.is_none()
        && slew.disturbance_torque() == Vector3::zeros()
    {
        let free = Slew {
            cost: Cost::Energy,
            torque_max: None,
            ..slew.clone()
        };
        let solution = minimum_energy(&free, settings(slew.t_end)?, START_TOLERANCE)?;
        if let Some(start) = rescaled_to_bound(&solution.inputs, &bound, slew.t_end) {
            return Ok(start);
        }
    }
    let attempt = |t_end: f64| {
        let energy = Slew {
            t_end,
            cost: Cost::Energy,
            ..slew.clone()
        };
        Ok(minimum_energy(&energy, settings(t_end)?, START_TOLERANCE)?.inputs)
    };
    bracket(slew.t_end, attempt)
}

/// Unbounded inputs over `t_end`, rest to rest, rescaled in time until their largest entry
/// meets its bound: `u(t)` over `T` becomes `u(t/c)/c²` over `cT`, the same path (the time
/// scaling of a body without a potential), and the peak meets the bound at `c = √peak`.
/// `None` for inputs that are all zero or not finite.
pub(crate) fn rescaled_to_bound<const W: usize>(
    inputs: &[SVector<f64, W>],
    bound: &SVector<f64, W>,
    t_end: f64,
) -> Option<(Vec<SVector<f64, W>>, f64)> {
    let peak = inputs
        .iter()
        .map(|u| u.component_div(bound).amax())
        .fold(0.0, f64::max);
    (peak > 0.0 && peak.is_finite()).then(|| {
        let c = peak.sqrt();
        (inputs.iter().map(|u| u / (c * c)).collect(), t_end * c)
    })
}

/// The inputs of `attempt` (a bounded minimum-energy motion in the time given) at a time
/// near the least for which it finds one: half as long again from `t_end` until it finds
/// one, then shorter by 30% while it does, so that the start is within 30% of that time.
/// An attempt's error other than "infeasible" or "not converged" ends the search.
pub(crate) fn bracket<U>(
    t_end: f64,
    attempt: impl Fn(f64) -> Result<Vec<U>, OptimalError>,
) -> Result<(Vec<U>, f64), OptimalError> {
    let mut t_end = t_end;
    let mut found = None;
    let mut last = None;
    for _ in 0..GUESSES {
        match attempt(t_end) {
            Ok(inputs) => {
                found = Some((inputs, t_end));
                break;
            }
            Err(error @ (OptimalError::Infeasible { .. } | OptimalError::NotConverged { .. })) => {
                last = Some(error);
                t_end *= 1.5;
            }
            Err(error) => return Err(error),
        }
    }
    let Some(mut found) = found else {
        return Err(last.expect("every attempt an error"));
    };
    if last.is_none() {
        for _ in 0..GUESSES {
            match attempt(0.7 * found.1) {
                Ok(inputs) => found = (inputs, 0.7 * found.1),
                Err(OptimalError::Infeasible { .. } | OptimalError::NotConverged { .. }) => break,
                Err(error) => return Err(error),
            }
        }
    }
    Ok(found)
}

/// The most lengthenings (and shortenings) of the first guess of the time.
const GUESSES: usize = 8;

/// The KKT tolerance of the minimum-energy slew that starts a minimum-time one.
pub(crate) const START_TOLERANCE: f64 = 1e-8;

/// The variables off their bounds (the step length always).
fn free_set(z: &DVector<f64>) -> Vec<usize> {
    let n = z.len();
    (0..n).filter(|&j| j == n - 1 || z[j].abs() < 1.0).collect()
}

/// `z` with the torques the subproblem holds on a bound put on it: the interior-point
/// subproblem lands near its active bounds, not on them, and the active set is read
/// from which torques are on their bounds ([`held`]).
fn snap(mut z: DVector<f64>, nu: &DVector<f64>) -> DVector<f64> {
    let n = z.len();
    for (x, m) in z.iter_mut().zip(nu.iter()).take(n - 1) {
        if let Some(side) = held(*x, *m) {
            *x = side;
        }
    }
    z
}

/// The bound (±1) that holds a scaled torque at `x` with the subproblem's bound
/// multiplier `nu` (upper minus lower): the one it is within [`NEAR`] of, if the
/// multiplier pushes outwards and exceeds the gap (complementarity: an active bound's
/// gap is about the interior-point tolerance over its multiplier, an inactive one's
/// multiplier the tolerance over its gap).
fn held(x: f64, nu: f64) -> Option<f64> {
    let gap = 1.0 - x.abs();
    (gap < NEAR && nu * x.signum() > gap.max(0.0)).then(|| x.signum())
}

/// How near its bound (in units of the bound) an active torque is put on it.
const NEAR: f64 = 1e-3;

/// The multipliers that best make the free variables stationary (least squares): the
/// first iterate's estimate.
fn least_squares_multipliers(
    jacobian: &DMatrix<f64>,
    gradient: &DVector<f64>,
    z: &DVector<f64>,
) -> DVector<f64> {
    let free = free_set(z);
    let m = jacobian.select_columns(&free);
    let g = gradient.select_rows(&free);
    (&m * m.transpose())
        .lu()
        .solve(&(-(&m * g)))
        .filter(|l| l.iter().all(|x| x.is_finite()))
        .unwrap_or_else(|| DVector::zeros(jacobian.nrows()))
}

/// The QP's Hessian: the Lagrangian's, `Σ λ_i ∂²e_i/∂z²`, on the free variables by
/// forward differences of its exact gradient `Mᵀλ` (one run of the integrator per free
/// variable), made positive definite on the constraints' null space by adding
/// `c MᵀM` (which leaves the subproblem's solution unchanged: `M δ` is fixed there) and
/// positive definite outright by raising eigenvalues below a floor; the variables on
/// their bounds get a unit diagonal. Two such matrices: [`Hessians::floored`] and
/// [`Hessians::mirrored`].
fn lagrangian_hessian<St>(
    z: &DVector<f64>,
    lambda: &DVector<f64>,
    current: &Scaled<St>,
    run: &impl Fn(&DVector<f64>) -> Result<Scaled<St>, OptimalError>,
) -> Result<Hessians, OptimalError> {
    let n = z.len();
    let free = free_set(z);
    let f = free.len();
    let mut block = DMatrix::<f64>::zeros(f, f);
    for (c, &j) in free.iter().enumerate() {
        // Towards the interior, so that the shifted torque stays within its bound.
        let mut shifted = z.clone();
        let delta = if j + 1 < n && z[j] > 0.0 {
            -DIFFERENCE
        } else {
            DIFFERENCE
        };
        shifted[j] += delta;
        let column = (run(&shifted)?.jacobian - &current.jacobian).transpose() * lambda / delta;
        for (r, &i) in free.iter().enumerate() {
            block[(r, c)] = column[i];
        }
    }
    let jacobian = current.jacobian.select_columns(&free);
    let symmetric = 0.5 * (&block + block.transpose());
    let scale = symmetric.amax().max(1.0);
    let weight = scale / jacobian.amax().powi(2).max(f64::MIN_POSITIVE);
    let convexified = &symmetric + weight * jacobian.transpose() * &jacobian;
    let eigen = convexified.symmetric_eigen();
    let floor = 1e-8 * eigen.eigenvalues.amax().max(1.0);
    let with = |value: &dyn Fn(f64) -> f64| {
        let values = eigen.eigenvalues.map(value);
        let positive =
            &eigen.eigenvectors * DMatrix::from_diagonal(&values) * eigen.eigenvectors.transpose();
        let mut hessian = DMatrix::<f64>::identity(n, n);
        for (r, &i) in free.iter().enumerate() {
            for (c, &j) in free.iter().enumerate() {
                hessian[(i, j)] = positive[(r, c)];
            }
        }
        hessian
    };
    Ok(Hessians {
        floored: with(&|v| v.max(floor)),
        mirrored: with(&|v| v.abs().max(floor)),
        differ: eigen.eigenvalues.iter().any(|&v| v < -floor),
    })
}

/// The QP's Hessian made positive definite in two ways.
struct Hessians {
    /// Eigenvalues below the floor raised to it: the model is flat along the Lagrangian's
    /// negative curvature, so that the step follows it (what lets a slew leave a saddle of
    /// the time for the lower minimum).
    floored: DMatrix<f64>,
    /// Eigenvalues replaced by their size: a step that the negative curvature would
    /// otherwise send to the bounds is kept short (the fallback where the floored model's
    /// step is refused: a manoeuvre whose body-frame force bound turns with the attitude
    /// crawls along the constraints' curvature without it).
    mirrored: DMatrix<f64>,
    /// Whether the two differ (an eigenvalue below minus the floor).
    differ: bool,
}

/// The forward difference's step in the scaled variables (`O(1)`): its truncation error
/// `~ε` and rounding `~10⁻¹⁶/ε` both near 1e-8 relative, which slows Newton's quadratic
/// convergence only below that (the KKT residual itself is exact).
const DIFFERENCE: f64 = 1e-8;

/// What the merit's weight on the miss exceeds twice the subproblem's largest multiplier
/// by. The weight is set afresh at each iteration, not only raised: an early overestimate
/// of the multipliers, kept, makes the merit refuse the steps along the constraints'
/// curvature near the solution (`docs/notes/optimal.md`, "Minimum time in space").
const MERIT_MARGIN: f64 = 1e-3;

/// The merit's rounding: a full step that changes it by less is taken (the last steps
/// move the variables by ~1e-9, below what the ℓ1 merit resolves).
const ROUNDING: f64 = 1e-14;

/// The KKT residual's stationarity part with the multipliers that fit it best
/// ([`best_fit`]), over `1 + |∇f|`.
fn stationarity(
    z: &DVector<f64>,
    jacobian: &DMatrix<f64>,
    gradient: &DVector<f64>,
    subproblem: &DVector<f64>,
) -> f64 {
    best_fit(z, jacobian, gradient, subproblem).1 / (1.0 + gradient.amax())
}

/// Of the multipliers refitted by least squares on the free variables and the
/// subproblem's, those that make the Lagrangian the more stationary
/// ([`stationarity_with`]), and that residual: where fewer variables are free than there
/// are terminal conditions (a switch on a step's boundary, a turn driven only by torques
/// on their bounds), the refit is not unique and the subproblem's multipliers, which carry
/// the bounds' share, are the ones that fit.
fn best_fit(
    z: &DVector<f64>,
    jacobian: &DMatrix<f64>,
    gradient: &DVector<f64>,
    subproblem: &DVector<f64>,
) -> (DVector<f64>, f64) {
    let refit = least_squares_multipliers(jacobian, gradient, z);
    let (by_refit, by_subproblem) = (
        stationarity_with(z, jacobian, gradient, &refit),
        stationarity_with(z, jacobian, gradient, subproblem),
    );
    if by_subproblem < by_refit {
        (subproblem.clone(), by_subproblem)
    } else {
        (refit, by_refit)
    }
}

/// The Lagrangian's gradient `∇f + Mᵀλ` with the multipliers `lambda`: its size on the free
/// variables, and on a variable at a bound its part of the wrong sign (a bound holds the
/// variable only against a gradient that pushes it outwards).
fn stationarity_with(
    z: &DVector<f64>,
    jacobian: &DMatrix<f64>,
    gradient: &DVector<f64>,
    lambda: &DVector<f64>,
) -> f64 {
    let free = free_set(z);
    let lagrangian = gradient + jacobian.transpose() * lambda;
    (0..z.len())
        .map(|j| {
            let g = lagrangian[j];
            if free.binary_search(&j).is_ok() {
                g.abs()
            } else if z[j] > 0.0 {
                // At the upper bound: ∇L = −ν ≤ 0.
                g.max(0.0)
            } else {
                (-g).max(0.0)
            }
        })
        .fold(0.0, f64::max)
}

/// The subproblem's solution made exact on its active set: the torques whose bounds hold
/// ([`held`]) put on them, and the equality-constrained
/// quadratic on the rest,
///
/// ```text
/// minimise ½ δ_Fᵀ P_FF δ_F + (q_F + P_FA δ_A)ᵀ δ_F   subject to   M_F δ_F = e − M_A δ_A,
/// ```
///
/// solved by the null-space method (the least-norm solution of the equality rows, from
/// an SVD, plus the reduced Hessian's step in their null space): the rows are then met to
/// rounding even where the reduced Hessian is nearly singular (a torque with a singular
/// arc, intermediate over a stretch of steps), where a KKT matrix solve loses them. A
/// torque within [`NEAR`] of a bound that this pushes past it is held on it,
/// a bound whose multiplier then comes out of the wrong sign released and the system
/// solved again (a few rounds at most). Where the free variables cannot move every row
/// (a part of the motion that only inputs held on their bounds drive: a bang-bang turn
/// beside a force left free), the rows must already be consistent to [`CONSISTENT`], as
/// they are at a vertex of the solution, and are met by least squares. `None` when the
/// step leaves a bound or the system is singular or inconsistent (the interior-point
/// solution is then used as it is). The interior-point
/// method meets the equality rows and the active bounds only to its tolerance, and near
/// the solution its multipliers cannot tell a weakly active bound from an inactive one;
/// this is what lets the KKT residual fall to rounding instead of stalling there.
#[allow(clippy::too_many_arguments)]
fn polish(
    hessian: &DMatrix<f64>,
    gradient: &DVector<f64>,
    jacobian: &DMatrix<f64>,
    e: &DVector<f64>,
    z: &DVector<f64>,
    lower: &[f64],
    upper: &[f64],
    found: &QpSolution,
    tolerance: f64,
) -> Option<QpSolution> {
    let n = z.len();
    let mut active: Vec<Option<f64>> = (0..n)
        .map(|j| {
            if j + 1 < n {
                held(z[j] + found.step[j], found.nu[j])
            } else {
                None
            }
        })
        .collect();
    for _ in 0..POLISH_ROUNDS {
        let fixed = DVector::from_fn(n, |j, _| active[j].map_or(0.0, |b| b - z[j]));
        let free: Vec<usize> = (0..n).filter(|&j| active[j].is_none()).collect();
        let m = e.len();
        let mf = jacobian.select_columns(&free);
        let pushed = hessian * &fixed;
        let moved = jacobian * &fixed;
        let hff = hessian.select_rows(&free).select_columns(&free);
        let gf = DVector::from_iterator(free.len(), free.iter().map(|&i| gradient[i] + pushed[i]));
        // Null-space method: the equality rows met to rounding by the least-norm part,
        // the reduced Hessian (which the weight c MᵀM does not enter) solved on the rest.
        let svd = mf.clone().svd(true, true);
        let largest = svd.singular_values.max();
        let floor = 1e-12 * largest;
        let spanning: Vec<usize> = (0..svd.singular_values.len())
            .filter(|&i| svd.singular_values[i] > floor)
            .collect();
        if largest == 0.0 {
            return None;
        }
        let particular = svd.solve(&(e - &moved), floor).ok()?;
        if spanning.len() < m {
            let unmet = (&mf * &particular - (e - &moved)).amax();
            if unmet > CONSISTENT.min(0.1 * tolerance) * (1.0 + e.amax()) {
                return None;
            }
        }
        let v_t = svd.v_t.as_ref()?;
        let range = v_t.select_rows(&spanning).transpose();
        let projector =
            DMatrix::<f64>::identity(free.len(), free.len()) - &range * range.transpose();
        let eigen = projector.symmetric_eigen();
        let columns: Vec<usize> = (0..free.len())
            .filter(|&i| eigen.eigenvalues[i] > 0.5)
            .collect();
        let solution = if columns.is_empty() {
            // The free variables' step lies in the rows' span: the rows alone fix it.
            particular
        } else {
            let basis = eigen.eigenvectors.select_columns(&columns);
            let reduced = basis.transpose() * &hff * &basis;
            let right = -(basis.transpose() * (&gf + &hff * &particular));
            &particular + &basis * reduced.lu().solve(&right)?
        };
        // The multipliers by least squares on the free rows, M_Fᵀ λ = −(q_F + P_F· δ), the
        // nearest to the subproblem's own: where the free rows leave some undetermined (a
        // part of the motion that only bounded inputs drive, such as a bang-bang turn
        // beside a force left free), those keep the subproblem's values, whose signs hold
        // the bounds, rather than the least-norm zero, which would release them.
        let rows = mf.transpose();
        let target = -(&gf + &hff * &solution) - &rows * &found.lambda;
        let lambda = &found.lambda + rows.svd(true, true).solve(&target, floor).ok()?;
        let mut step = fixed;
        let mut held = Vec::new();
        for (r, &j) in free.iter().enumerate() {
            let x = solution[r];
            if !x.is_finite() {
                return None;
            }
            if x < lower[j] || x > upper[j] {
                // A torque within NEAR of the bound it is pushed past is held on it (a
                // singular arc's flat directions push such torques far); any other
                // excursion leaves the subproblem's own solution in place.
                let side = if x > upper[j] { 1.0 } else { -1.0 };
                if j + 1 == n || (side - z[j]).abs() > NEAR {
                    return None;
                }
                held.push((j, side));
            }
            step[j] = x;
        }
        if !held.is_empty() {
            for (j, side) in held {
                active[j] = Some(side);
            }
            continue;
        }
        // The bounds' multipliers from stationarity, P δ + q + Mᵀλ + ν = 0: an upper
        // bound holds with ν ≥ 0, a lower one with ν ≤ 0.
        let residual = hessian * &step + gradient + jacobian.transpose() * &lambda;
        let nu = DVector::from_fn(n, |j, _| {
            if active[j].is_some() {
                -residual[j]
            } else {
                0.0
            }
        });
        let wrong: Vec<usize> = (0..n)
            .filter(|&j| active[j].is_some_and(|b| b * nu[j] < 0.0))
            .collect();
        if wrong.is_empty() {
            return Some(QpSolution { step, lambda, nu });
        }
        for j in wrong {
            active[j] = None;
        }
    }
    None
}

/// How nearly (relative to `1 + |e|`, and at most a tenth of the KKT tolerance)
/// [`polish`]'s least-squares step must meet rows that its free variables cannot all move:
/// far below the misses of an iteration still on its way (which the interior-point step
/// then takes), above the rounding of one at a vertex (`docs/notes/optimal.md`).
const CONSISTENT: f64 = 1e-8;

/// The most rounds of releasing wrongly held bounds in [`polish`].
const POLISH_ROUNDS: usize = 8;

/// The subproblem's own solution with the torques it holds on a bound put on it
/// ([`held`]) and then its equality rows met to rounding: the least-norm correction
/// `M_F⁺ (e − M δ)` on the variables off their bounds. The interior-point method lands
/// near its active bounds, not on them; putting them on the bounds moves the terminal
/// state by `M` times those gaps, which the correction takes back. Left as it is if the
/// correction would leave a bound.
fn project(
    jacobian: &DMatrix<f64>,
    e: &DVector<f64>,
    z: &DVector<f64>,
    lower: &[f64],
    upper: &[f64],
    mut found: QpSolution,
) -> QpSolution {
    let n = z.len();
    let mut step = found.step.clone();
    let mut on_bound = vec![false; n];
    for j in 0..n - 1 {
        if let Some(side) = held(z[j] + step[j], found.nu[j]) {
            step[j] = side - z[j];
            on_bound[j] = true;
        }
    }
    let free: Vec<usize> = (0..n)
        .filter(|&j| {
            j + 1 == n
                || (!on_bound[j]
                    && step[j] > lower[j] + PROJECTION_MARGIN
                    && step[j] < upper[j] - PROJECTION_MARGIN)
        })
        .collect();
    let miss = e - jacobian * &step;
    let Ok(correction) = jacobian
        .select_columns(&free)
        .svd(true, true)
        .solve(&miss, 0.0)
    else {
        return found;
    };
    for (r, &j) in free.iter().enumerate() {
        step[j] += correction[r];
        if !(step[j] >= lower[j] && step[j] <= upper[j]) {
            return found;
        }
    }
    found.step = step;
    found
}

/// How far inside its bounds (scaled) a variable must lie to take part in [`project`]'s
/// correction.
const PROJECTION_MARGIN: f64 = 1e-9;
