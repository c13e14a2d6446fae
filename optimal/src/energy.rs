//! The minimum-energy slew: Gauss–Newton SQP over the torques at a fixed final time.

use crate::shooting::{shoot, Shot};
use crate::tracking::{residuals, ByState, Residuals};
use crate::{qp, quadrature, Inputs, OptimalError, Slew, Solution, Statistics};
use clarabel::algebra::CscMatrix;
use lgsvi_mechanics::StepSettings;
use nalgebra::{DMatrix, DVector, SVector, Vector3};
use std::time::Instant;

/// Solves `slew` for the least `∫|u|² dt` (the crate documentation's iteration): with
/// constant torques `Σ_k h |u_k|²`, with polynomial ones the steps' quadrature
/// `Σ_k h Σ_j b_j |u_kj|²`; plus, where given, the tracking and terminal costs
/// (`crate::tracking`), whose residuals `r` and their Jacobian `G` add `|r|²` to the cost,
/// `2Gᵀr` to its gradient and `2GᵀG` to the Gauss–Newton Hessian `diag(2w)` (in the
/// banded subproblem, [`Banded`], each state's `2G_kᵀG_k`). Without a terminal cost the
/// terminal state is exact (the QP's six equality rows).
pub(crate) fn minimum_energy(
    slew: &Slew,
    settings: StepSettings,
    tolerance: f64,
) -> Result<Solution, OptimalError> {
    let clock = Instant::now();
    let (k_steps, h) = (slew.steps, settings.h());
    let body = slew.system()?;
    let (nodes, weights) = quadrature(slew, settings)?;
    let start = Start::of(
        slew.inputs,
        h,
        k_steps,
        &weights,
        slew.initial.as_deref(),
        slew.torque_max,
    );
    let per_step = start.step_weights.len();
    let shoot =
        |u: &[Vector3<f64>]| shoot(body, settings, slew.start, slew.target, u, per_step, false);
    let fit = |run: &Shot| residuals(slew, h, run);
    let problem = Problem {
        step_weights: &start.step_weights,
        bound: slew.torque_max,
        exact_target: slew.terminal_cost.is_none(),
        max_iterations: slew.max_iterations,
        shoot: &shoot,
        residuals: &fit,
        equilibrate: false,
        metric: None,
    };
    let solved = problem.solve(start.inputs, tolerance)?;
    // The subproblem's multipliers are those of the linearised rows `M δ = e`; the
    // optimal cost's sensitivity to the miss is their negative.
    let mut terminal = [0.0; 6];
    if problem.exact_target {
        terminal.copy_from_slice((-&solved.multipliers).as_slice());
    }
    let (means, at_points) = by_step(&solved.inputs, per_step, &weights);
    let mut statistics = solved.statistics;
    statistics.time_s = clock.elapsed().as_secs_f64();
    Ok(Solution {
        cost: solved.cost,
        states: solved.run.states,
        wheel_speeds: solved.run.wheel_speeds,
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

/// A minimum-energy problem over inputs of `M` entries, as the Gauss–Newton SQP sees it:
/// the cost `Σ_i w_i |u_i|²` plus the squared residuals where there are any, the terminal
/// state exact or not, each entry bounded or not.
pub(crate) struct Problem<'a, St, const M: usize> {
    /// The quadrature weight of each input of a step: `h` for a held input, `h b_j` at
    /// the Gauss points.
    pub step_weights: &'a [f64],
    /// The largest magnitude of each entry of an input.
    pub bound: Option<SVector<f64, M>>,
    /// Whether the terminal state is a constraint (else a cost among the residuals).
    pub exact_target: bool,
    /// The most iterations.
    pub max_iterations: usize,
    /// A run of the integrator under the inputs.
    pub shoot: &'a Shooter<'a, St, M>,
    /// The tracking and terminal residuals of a run and their Jacobian, if any.
    pub residuals: &'a dyn Fn(&Shot<St>) -> Option<Residuals>,
    /// Whether the subproblem sees its equality rows scaled to a largest entry of 1 (for
    /// rows of very different sizes, as a body in space's attitude and position).
    pub equilibrate: bool,
    /// A change of the subproblem's metric, where there is one: for each input `i` of
    /// step `k`, a map `C_i` (`M` rows; the step's start state's `2D` columns, then the
    /// step's inputs' `M` each) such that the step is measured as
    /// `δv_i = δu_i − C_i [δx_k; δu_k]`, the model's Hessian `diag(2w)` on `δv` in place of
    /// `δu` (a body in space's force measured in the world frame, `crate::motion`). The
    /// cost, the constraints and their linearisations are unchanged, so is every KKT
    /// point; only the path to one is. The subproblem is then the banded one
    /// ([`Banded`]), `δv` eliminated into its Hessian (a block over each step's start and
    /// inputs), so the bounds stay bounds on `u`.
    pub metric: Option<&'a Metric<'a, St, M>>,
}

/// The maps `C_i` of [`Problem::metric`] at a run and its inputs.
pub(crate) type Metric<'a, St, const M: usize> =
    dyn Fn(&Shot<St>, &[SVector<f64, M>]) -> Vec<DMatrix<f64>> + 'a;

/// A run of the integrator under inputs of `M` entries.
pub(crate) type Shooter<'a, St, const M: usize> =
    dyn Fn(&[SVector<f64, M>]) -> Result<Shot<St>, OptimalError> + 'a;

/// What [`Problem::solve`] found: the inputs, their run, the cost, the terminal
/// multipliers (empty without an exact target) and the record (its time not set).
pub(crate) struct Solved<St, const M: usize> {
    pub inputs: Vec<SVector<f64, M>>,
    pub run: Shot<St>,
    pub cost: f64,
    pub multipliers: DVector<f64>,
    pub statistics: Statistics,
}

impl<St, const M: usize> Problem<'_, St, M> {
    /// The cost of inputs and their residuals.
    fn cost(&self, u: &[SVector<f64, M>], r: Option<&Residuals>) -> f64 {
        let per_step = self.step_weights.len();
        u.iter()
            .enumerate()
            .map(|(i, u)| self.step_weights[i % per_step] * u.norm_squared())
            .sum::<f64>()
            + r.map_or(0.0, Residuals::squared)
    }

    /// The Gauss–Newton SQP from `inputs` (the crate documentation's iteration).
    pub(crate) fn solve(
        &self,
        mut inputs: Vec<SVector<f64, M>>,
        tolerance: f64,
    ) -> Result<Solved<St, M>, OptimalError> {
        let per_step = self.step_weights.len();
        let weight = |i: usize| self.step_weights[i % per_step];
        let exact_target = self.exact_target;
        let mut statistics = Statistics::default();
        let mut run = (self.shoot)(&inputs)?;
        let mut fit = (self.residuals)(&run);
        let rows_eq = if exact_target { run.miss.len() } else { 0 };
        let mut multipliers = DVector::<f64>::zeros(rows_eq);
        let n = M * inputs.len();
        let mut bound_duals = DVector::<f64>::zeros(n);
        let diagonal = energy_diagonal::<M>(self.step_weights, inputs.len());
        let (no_rows, no_miss) = (DMatrix::<f64>::zeros(0, n), DVector::<f64>::zeros(0));
        loop {
            let miss = run.miss.amax();
            // The energy's gradient, then the residuals' `2Gᵀr` (by the adjoint recursion).
            let energy_gradient = DVector::from_iterator(
                n,
                inputs
                    .iter()
                    .enumerate()
                    .flat_map(|(i, u)| (u * (2.0 * weight(i))).data.0[0]),
            );
            let model = fit.as_ref().map(|f| f.by_state(&run));
            let mut gradient = energy_gradient.clone();
            if let Some(model) = &model {
                gradient += run.input_gradient(&model.gradients);
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

            if statistics.iterations >= self.max_iterations {
                return Err(OptimalError::NotConverged {
                    iterations: statistics.iterations,
                    residual,
                    tolerance,
                });
            }
            statistics.iterations += 1;
            // ½ δᵀ H δ + gᵀ δ: the cost up to a constant (exact in δ for the energy, the
            // Gauss–Newton model of the residuals); the bounds |u + δu| ≤ u_max.
            let flat: Vec<f64> = inputs.iter().flat_map(|u| u.iter().copied()).collect();
            let (lower, upper): (Vec<f64>, Vec<f64>) = match self.bound {
                Some(bound) => (0..n)
                    .map(|j| (-bound[j % M] - flat[j], bound[j % M] - flat[j]))
                    .unzip(),
                None => (vec![f64::NEG_INFINITY; n], vec![f64::INFINITY; n]),
            };
            // With residuals or a metric, the banded subproblem (the states among its
            // variables), whose cost is linear in the step count; else the condensed one,
            // whose Hessian `diag(2w)` and six terminal rows are too.
            let maps = self.metric.map(|metric| metric(&run, &inputs));
            let found = if model.is_some() || maps.is_some() {
                Banded {
                    run: &run,
                    model: model.as_ref(),
                    metric: maps.as_deref(),
                    diagonal: &diagonal,
                    energy_gradient: &energy_gradient,
                    exact_target,
                    equilibrate: self.equilibrate,
                }
                .solve(&lower, &upper)?
            } else {
                let (scaled_rows, scaled_e, scale) = equilibrated(rows, e, self.equilibrate);
                let hessian = qp::diagonal(&diagonal);
                let mut found = qp::solve(
                    hessian,
                    gradient.as_slice(),
                    &scaled_rows,
                    &scaled_e,
                    &lower,
                    &upper,
                    1e-13,
                )?;
                if let Some(solution) = &mut found {
                    for (l, s) in solution.lambda.iter_mut().zip(&scale) {
                        *l *= s;
                    }
                }
                found
            };
            let solution = found.ok_or(OptimalError::Infeasible {
                residual: miss,
                bounded: self.bound.is_some(),
            })?;
            let (next_inputs, next_run, next_fit) =
                self.line_search(&inputs, &run, fit.as_ref(), &solution)?;
            inputs = next_inputs;
            run = next_run;
            fit = next_fit;
            multipliers = solution.lambda;
            bound_duals = solution.nu;
        }
        Ok(Solved {
            cost: self.cost(&inputs, fit.as_ref()),
            inputs,
            run,
            multipliers,
            statistics,
        })
    }
}

impl<St, const M: usize> Problem<'_, St, M> {
    /// The ℓ1 merit's backtracking along the subproblem's step: the next inputs, their run
    /// and residuals.
    #[allow(clippy::type_complexity)]
    fn line_search(
        &self,
        inputs: &[SVector<f64, M>],
        run: &Shot<St>,
        fit: Option<&Residuals>,
        solution: &qp::QpSolution,
    ) -> Result<(Vec<SVector<f64, M>>, Shot<St>, Option<Residuals>), OptimalError> {
        let exact_target = self.exact_target;
        let (step, lambda) = (&solution.step, &solution.lambda);
        // The merit J + ρ|e|₁ (ρ above the multipliers; the miss only where the target
        // is exact): halve the step until it falls.
        let rho = 2.0 * lambda.amax() + 1.0;
        let merit = |c: f64, e: &DVector<f64>| {
            c + if exact_target {
                rho * e.iter().map(|x| x.abs()).sum::<f64>()
            } else {
                0.0
            }
        };
        let before = merit(self.cost(inputs, fit), &run.miss);
        let mut alpha = 1.0;
        loop {
            let trial: Vec<SVector<f64, M>> = inputs
                .iter()
                .enumerate()
                .map(|(i, u)| u + alpha * step.fixed_rows::<M>(M * i))
                .collect();
            match (self.shoot)(&trial) {
                Ok(r) => {
                    let f = (self.residuals)(&r);
                    // A rise within the merit's rounding is no rise: near the solution the
                    // model's decrease falls below it, and halving a good step there only
                    // stalls the iteration. The rounding is the cost's and the miss's, each
                    // of whose rows rounds at `ε` of the state's size (order one) however
                    // small the miss (measured: rises of 2e-15 at a miss of 3e-16 and
                    // `ρ ≈ 1` held a 50-step tracking slew at a KKT residual of 6e-10).
                    let miss_rounding = if exact_target {
                        rho * run.miss.len() as f64
                    } else {
                        0.0
                    };
                    let rounding = 16.0 * f64::EPSILON * (before.abs() + miss_rounding);
                    let trial_merit = merit(self.cost(&trial, f.as_ref()), &r.miss);
                    if trial_merit <= before + rounding || alpha < 1e-3 {
                        return Ok((trial, r, f));
                    }
                    alpha *= 0.5;
                }
                Err(error) if alpha < 1e-3 => return Err(error),
                Err(_) => alpha *= 0.5,
            }
        }
    }
}

/// The Gauss–Newton subproblem with the states among its variables: the inputs' steps
/// `δu` (each step's `m` per input) and the states' `δx_k` (`k = 1 … K`, the plant's
/// linearisation coordinates), the steps' linearisations as equality rows
/// `δx_{k+1} − A_k δx_k − Σ_j B_kj δu_kj = 0` (`δx_0 = 0`), the terminal rows
/// `T δx_K = e` where the target is exact, and the cost
/// `Σ w |u + δu|² + Σ_b |r_b + G_b δx_k|²` up to a constant. Eliminating the states gives
/// back the condensed subproblem (the same step, the same terminal multipliers); kept,
/// they make its Hessian block diagonal and its rows banded, so that `clarabel`'s sparse
/// factorisation costs a fixed amount a step, where the condensed Hessian
/// `diag(2w) + 2GᵀG` is dense and costs the cube of the step count to form and factor.
///
/// With a metric ([`Problem::metric`]) the energy's model is `∇Jᵀδu + ½ δvᵀ diag(2w) δv`
/// with the measured step `δv_i = δu_i − C_i [δx_k; δu_k]`: its gradient term unchanged
/// (the cost is the same), its curvature measured in `δv`. Each `C_i` reads only its
/// step's start and inputs, so the Hessian `Σ_i L_iᵀ diag(2w_i) L_i` stays banded (a
/// block over each step's start and inputs), and a bound stays a bound on `u + δu`.
struct Banded<'a, St> {
    run: &'a Shot<St>,
    /// The residuals' Gauss–Newton terms at each state, where there are residuals.
    model: Option<&'a ByState>,
    /// Each input's `C_i`, where the step is measured in another metric.
    metric: Option<&'a [DMatrix<f64>]>,
    /// The energy's Hessian `2w`, one entry per input entry.
    diagonal: &'a [f64],
    /// The energy's gradient `2wu`.
    energy_gradient: &'a DVector<f64>,
    exact_target: bool,
    /// Whether the terminal rows are scaled to a largest entry of 1 ([`Problem`]).
    equilibrate: bool,
}

impl<St> Banded<'_, St> {
    /// The subproblem's step in the inputs, its terminal multipliers and the inputs' bound
    /// multipliers (as the condensed subproblem's); `None` where it is infeasible.
    fn solve(&self, lower: &[f64], upper: &[f64]) -> Result<Option<qp::QpSolution>, OptimalError> {
        let run = self.run;
        let (a, b) = (run.state_jacobians(), run.input_jacobians());
        let (k_steps, size, n) = (a.len(), run.state_size(), self.diagonal.len());
        let per_step = b.first().map_or(1, Vec::len);
        let width = n / (k_steps * per_step);
        // The variables: δu, then δx_1 … δx_K.
        let state_column = |k: usize| n + size * (k - 1);
        let total = n + size * k_steps;
        // Step k's own columns: its start state's (none at k = 0), then its inputs'.
        let own = |k: usize, c: usize| match c.checked_sub(size) {
            Some(input) => Some(width * per_step * k + input),
            None => (k > 0).then(|| state_column(k) + c),
        };
        // The Hessian's upper triangle, by columns, entries summed where they meet: the
        // energy's `2w` on δu, or with a metric `L_iᵀ diag(2w_i) L_i` on step k's own
        // columns (`L_i = [0 | I_i] − C_i`, so that `L_i [δx_k; δu_k] = δv_i`); each
        // state's block of the residuals.
        let mut hessian: Vec<Vec<(usize, f64)>> = vec![Vec::new(); total];
        let mut add = |i: usize, j: usize, value: f64| {
            if value != 0.0 {
                hessian[i.max(j)].push((i.min(j), value));
            }
        };
        match self.metric {
            None => {
                for (j, d) in self.diagonal.iter().enumerate() {
                    add(j, j, *d);
                }
            }
            Some(maps) => {
                // Summed over a step's inputs first, then entered once.
                let columns = size + width * per_step;
                for (k, step_maps) in maps.chunks(per_step).enumerate() {
                    let mut block = DMatrix::<f64>::zeros(columns, columns);
                    for (j, map) in step_maps.iter().enumerate() {
                        let i = per_step * k + j;
                        let mut l = -map.clone();
                        for r in 0..width {
                            l[(r, size + width * j + r)] += 1.0;
                            l.row_mut(r).scale_mut(self.diagonal[width * i + r].sqrt());
                        }
                        block += l.transpose() * &l;
                    }
                    for c in 0..columns {
                        for r in 0..=c {
                            if let (Some(row), Some(column)) = (own(k, r), own(k, c)) {
                                add(row, column, block[(r, c)]);
                            }
                        }
                    }
                }
            }
        }
        let mut q: Vec<f64> = self.energy_gradient.iter().copied().collect();
        q.resize(total, 0.0);
        for (k, (gradient, block)) in self
            .model
            .iter()
            .flat_map(|m| m.gradients.iter().zip(&m.hessians))
            .enumerate()
        {
            let at = state_column(k + 1);
            q[at..at + size].copy_from_slice(gradient.as_slice());
            for c in 0..size {
                for i in 0..=c {
                    add(at + i, at + c, block[(i, c)]);
                }
            }
        }
        let (mut colptr, mut rowval, mut nzval) = (vec![0], Vec::new(), Vec::new());
        for column in &mut hessian {
            sum_repeated(column);
            for &(i, value) in column.iter() {
                rowval.push(i);
                nzval.push(value);
            }
            colptr.push(rowval.len());
        }
        let p = CscMatrix::new(total, total, colptr, rowval, nzval);
        // The terminal rows, scaled where asked.
        let no_rows = (DMatrix::zeros(0, size), DVector::zeros(0));
        let (rows, e) = if self.exact_target {
            (&run.terminal, &run.miss)
        } else {
            (&no_rows.0, &no_rows.1)
        };
        let (terminal, e, scale) = equilibrated(rows, e, self.equilibrate);
        // The rows, by columns: step k's rows hold `δx_{k+1} − A_k δx_k − Σ_j B_kj δu_kj`,
        // the terminal rows `T δx_K`.
        let dynamics = size * k_steps;
        let mut columns: Vec<Vec<(usize, f64)>> = vec![Vec::new(); total];
        let mut put = |column: usize, row: usize, value: f64| {
            if value != 0.0 {
                columns[column].push((row, value));
            }
        };
        for k in 0..k_steps {
            for c in 0..size {
                put(state_column(k + 1) + c, size * k + c, 1.0);
                if let Some(at) = own(k, c) {
                    for r in 0..size {
                        put(at, size * k + r, -a[k][(r, c)]);
                    }
                }
            }
            for (j, bj) in b[k].iter().enumerate() {
                for c in 0..width {
                    for r in 0..size {
                        put(width * (per_step * k + j) + c, size * k + r, -bj[(r, c)]);
                    }
                }
            }
        }
        for c in 0..size {
            for r in 0..terminal.nrows() {
                put(state_column(k_steps) + c, dynamics + r, terminal[(r, c)]);
            }
        }
        for column in &mut columns {
            sum_repeated(column);
        }
        let mut rhs = DVector::<f64>::zeros(dynamics + e.len());
        rhs.rows_mut(dynamics, e.len()).copy_from(&e);
        let free = total - n;
        let lower: Vec<f64> = lower
            .iter()
            .copied()
            .chain(std::iter::repeat_n(f64::NEG_INFINITY, free))
            .collect();
        let upper: Vec<f64> = upper
            .iter()
            .copied()
            .chain(std::iter::repeat_n(f64::INFINITY, free))
            .collect();
        let found = qp::solve_sparse(
            p,
            &q,
            &columns,
            &rhs,
            &lower,
            &upper,
            1e-13,
            qp::Refinement::Full,
        )?;
        Ok(found.map(|s| qp::QpSolution {
            step: s.step.rows(0, n).into_owned(),
            lambda: DVector::from_iterator(
                e.len(),
                (0..e.len()).map(|i| s.lambda[dynamics + i] * scale[i]),
            ),
            nu: s.nu.rows(0, n).into_owned(),
        }))
    }
}

/// Equality rows and their right-hand side, each row scaled, where `equilibrate`, to a
/// largest entry of 1 (the same constraints, better conditioned for the subproblem), and
/// each row's factor, by which its multiplier is scaled back.
fn equilibrated(
    rows: &DMatrix<f64>,
    e: &DVector<f64>,
    equilibrate: bool,
) -> (DMatrix<f64>, DVector<f64>, Vec<f64>) {
    let scale: Vec<f64> = (0..rows.nrows())
        .map(|i| match rows.row(i).amax() {
            largest if equilibrate && largest > 0.0 => 1.0 / largest,
            _ => 1.0,
        })
        .collect();
    let scaled = DMatrix::from_fn(rows.nrows(), rows.ncols(), |i, j| rows[(i, j)] * scale[i]);
    let e = DVector::from_fn(e.len(), |i, _| e[i] * scale[i]);
    (scaled, e, scale)
}

/// A sparse column's entries by increasing row, those of a repeated row summed.
fn sum_repeated(column: &mut Vec<(usize, f64)>) {
    column.sort_by_key(|&(row, _)| row);
    column.dedup_by(|later, earlier| {
        let same = later.0 == earlier.0;
        if same {
            earlier.1 += later.1;
        }
        same
    });
}

/// The inputs a minimum-energy iteration starts from, with each input's quadrature
/// weight.
pub(crate) struct Start<const M: usize> {
    /// The quadrature weight of each input of a step: `h` for a held input, `h b_j` at
    /// the Gauss points.
    pub step_weights: Vec<f64>,
    /// The warm start (one per step spread over the points, or one per point), else rest,
    /// clamped to the bounds.
    pub inputs: Vec<SVector<f64, M>>,
}

impl<const M: usize> Start<M> {
    /// For `k_steps` steps of length `h` whose Gauss weights are `weights`.
    pub(crate) fn of(
        shape: Inputs,
        h: f64,
        k_steps: usize,
        weights: &[f64],
        initial: Option<&[SVector<f64, M>]>,
        bound: Option<SVector<f64, M>>,
    ) -> Self {
        let step_weights: Vec<f64> = match shape {
            Inputs::Constant => vec![h],
            _ => weights.iter().map(|b| h * b).collect(),
        };
        let per_step = step_weights.len();
        let mut inputs: Vec<SVector<f64, M>> = match initial {
            Some(initial) if initial.len() == k_steps * per_step => initial.to_vec(),
            Some(initial) => initial
                .iter()
                .flat_map(|u| std::iter::repeat_n(*u, per_step))
                .collect(),
            None => vec![SVector::zeros(); k_steps * per_step],
        };
        if let Some(bound) = bound {
            for u in &mut inputs {
                *u = u.zip_map(&bound, |x, b| x.clamp(-b, b));
            }
        }
        Self {
            step_weights,
            inputs,
        }
    }
}

/// Each step's torque (its mean `Σ_j b_j u_kj` at the Gauss points) and, with inputs at the
/// points, each step's values there.
#[allow(clippy::type_complexity)]
pub(crate) fn by_step<const M: usize>(
    inputs: &[SVector<f64, M>],
    per_step: usize,
    weights: &[f64],
) -> (Vec<SVector<f64, M>>, Vec<Vec<SVector<f64, M>>>) {
    if per_step == 1 {
        return (inputs.to_vec(), Vec::new());
    }
    let steps: Vec<Vec<SVector<f64, M>>> = inputs.chunks(per_step).map(|c| c.to_vec()).collect();
    let means = steps
        .iter()
        .map(|c| c.iter().zip(weights).map(|(u, b)| u * *b).sum())
        .collect();
    (means, steps)
}

/// `diag(2w)`, the energy's Hessian over `count` inputs of `M` entries: each entry
/// weighted by its input's quadrature weight (`step_weights`, one per input of a step).
fn energy_diagonal<const M: usize>(step_weights: &[f64], count: usize) -> Vec<f64> {
    let per_step = step_weights.len();
    (0..M * count)
        .map(|j| 2.0 * step_weights[(j / M) % per_step])
        .collect()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::shooting::{shoot, Shot};
    use crate::tracking::residuals;
    use crate::{Slew, Wheels};
    use lgsvi_mechanics::lie::SO3;
    use lgsvi_mechanics::Inertia;

    /// The banded subproblem against the condensed one it is the elimination of, at `run`
    /// with residuals `fit` and a metric's maps `metric` where given, `inputs` of
    /// quadrature weights `step_weights` (the energy's Hessian `diag(2w)` as the solver
    /// forms it), each entry bounded by `bound`, the terminal
    /// state exact or not, the banded side's terminal rows equilibrated or not (the
    /// condensed side's are not: scaling rows changes neither the step nor, scaled
    /// back, the multipliers); returns the bounds active and the largest entry of the
    /// condensed solution's `u + δu`. The same
    /// step, the same terminal and bound multipliers, and the adjoint gradient equal to
    /// `2Gᵀr` from the dense `G`. The condensed Hessian is
    /// `(I − Ĉ)ᵀ diag(2w) (I − Ĉ) + 2GᵀG`, `Ĉ` the maps chained through the states'
    /// sensitivities (`Ĉ_i = C_i [∂x_k/∂u; ∂u_k/∂u]`). Both are interior-point solutions
    /// to 1e-13; the condensed one forms its products in another order, so they agree to
    /// about 1e-9 of the step's size where bounds are active (the interior point's
    /// complementarity) and to rounding without.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn banded_matches_condensed<St, const M: usize>(
        run: &Shot<St>,
        fit: Option<&Residuals>,
        metric: Option<&[DMatrix<f64>]>,
        inputs: &[SVector<f64, M>],
        step_weights: &[f64],
        bound: f64,
        exact_target: bool,
        equilibrate: bool,
    ) -> (usize, f64) {
        let n = M * inputs.len();
        let u = &DVector::from_iterator(n, inputs.iter().flat_map(|u| u.iter().copied()));
        let diagonal = &energy_diagonal::<M>(step_weights, inputs.len());
        let (g, r) = match fit {
            Some(fit) => {
                let g = fit.dense(run);
                let dense_gradient = 2.0 * g.transpose() * &fit.values;
                let adjoint = fit.gradient(run);
                assert!(
                    (&adjoint - &dense_gradient).amax() <= 1e-13 * (1.0 + dense_gradient.amax()),
                    "adjoint gradient {:e} off",
                    (&adjoint - &dense_gradient).amax()
                );
                (g, fit.values.clone())
            }
            None => (DMatrix::zeros(0, n), DVector::zeros(0)),
        };
        let energy_gradient = DVector::from_fn(n, |j, _| diagonal[j] * u[j]);
        let lower: Vec<f64> = (0..n).map(|j| -bound - u[j]).collect();
        let upper: Vec<f64> = (0..n).map(|j| bound - u[j]).collect();
        // `δv = L δu`, `L = I − Ĉ`.
        let mut l = DMatrix::<f64>::identity(n, n);
        if let Some(maps) = metric {
            let sensitivities = run.full_state_sensitivities();
            let size = run.state_size();
            let per_step = run.input_jacobians()[0].len();
            let width = n / maps.len();
            for (i, map) in maps.iter().enumerate() {
                let k = i / per_step;
                let mut own = DMatrix::<f64>::zeros(map.ncols(), n);
                if k > 0 {
                    own.rows_mut(0, size).copy_from(&sensitivities[k - 1]);
                }
                for c in 0..width * per_step {
                    own[(size + c, width * per_step * k + c)] = 1.0;
                }
                let chained = map * own;
                for r in 0..width {
                    for c in 0..n {
                        l[(width * i + r, c)] -= chained[(r, c)];
                    }
                }
            }
        }
        let mut hessian =
            l.transpose() * DMatrix::from_diagonal(&DVector::from_column_slice(diagonal)) * &l;
        hessian += 2.0 * g.transpose() * &g;
        let q = &energy_gradient + 2.0 * g.transpose() * &r;
        let (rows, e) = if exact_target {
            (run.sensitivity.clone(), run.miss.clone())
        } else {
            (DMatrix::zeros(0, n), DVector::zeros(0))
        };
        let condensed = qp::solve(
            qp::upper_triangle(&hessian),
            q.as_slice(),
            &rows,
            &e,
            &lower,
            &upper,
            1e-13,
        )
        .unwrap()
        .unwrap();
        let model = fit.map(|f| f.by_state(run));
        let banded = Banded {
            run,
            model: model.as_ref(),
            metric,
            diagonal,
            energy_gradient: &energy_gradient,
            exact_target,
            equilibrate,
        }
        .solve(&lower, &upper)
        .unwrap()
        .unwrap();
        // An active bound's slack in an interior-point solution is about the gap over its
        // multiplier: each solution sits up to `1e-13 / ν` inside its bounds.
        let smallest = condensed
            .nu
            .iter()
            .map(|x| x.abs())
            .filter(|x| *x > 1e-8)
            .fold(f64::INFINITY, f64::min);
        let tolerance = 1e-11 + 10.0 * 1e-13 / smallest;
        let scale = 1.0 + condensed.step.amax();
        let off = (&banded.step - &condensed.step).amax() / scale;
        assert!(
            off <= tolerance,
            "steps differ by {off:e} (allowed {tolerance:e})"
        );
        // The multipliers follow from the step through `P δ + q + Mᵀλ + ν = 0`: their
        // difference is the steps' times the Hessian's size.
        let tolerance = tolerance * (1.0 + hessian.amax());
        let lambda = (&banded.lambda - &condensed.lambda).amax() / (1.0 + condensed.lambda.amax());
        assert!(
            lambda <= tolerance,
            "multipliers differ by {lambda:e} (allowed {tolerance:e})"
        );
        let nu = (&banded.nu - &condensed.nu).amax() / (1.0 + condensed.nu.amax());
        assert!(
            nu <= tolerance,
            "bound multipliers differ by {nu:e} (allowed {tolerance:e})"
        );
        let active = condensed.nu.iter().filter(|x| x.abs() > 1e-8).count();
        (active, (u + &condensed.step).amax())
    }

    /// A tracking slew of a rigid body and of a gyrostat (whose state has rows the
    /// residuals do not read), torques held and at the Gauss points, some on their bounds
    /// and none.
    #[test]
    fn the_banded_subproblem_is_the_condensed_one() {
        let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap();
        let (t_end, k_steps, nodes) = (20.0, 12usize, 6);
        let h = t_end / k_steps as f64;
        let axis = Vector3::new(1.0, 2.0, 2.0) / 3.0;
        let reference: Vec<_> = (1..=k_steps)
            .map(|k| (SO3::exp(&(axis * 0.05 * k as f64)), axis * 0.03))
            .collect();
        let wheels = Wheels {
            axes: [Vector3::x(), Vector3::y(), Vector3::new(0.0, 0.3, 1.0)],
            inertia: [0.05; 3],
            speeds: Vector3::new(3.0, -2.0, 1.0),
        };
        for with_wheels in [false, true] {
            let mut slew = Slew::new(inertia, t_end)
                .to(SO3::exp(&(axis * 0.6)), Vector3::zeros())
                .steps(k_steps)
                .nodes(nodes)
                .track(reference.clone(), [2.0, 0.5])
                .torque_max([0.05; 3]);
            if with_wheels {
                slew = slew.wheels(wheels);
            }
            let plant = slew.system().unwrap();
            let settings = StepSettings::new(h, nodes).unwrap();
            let weights = plant.quadrature(settings, slew.start).unwrap().1;
            for per_step in [1, weights.len()] {
                let inputs: Vec<Vector3<f64>> = (0..k_steps * per_step)
                    .map(|i| {
                        let t = i as f64 / per_step as f64;
                        Vector3::new(0.06 * (0.5 * t).cos(), -0.01, 0.04 * (0.3 * t).sin())
                    })
                    .collect();
                let run = shoot(
                    plant,
                    settings,
                    slew.start,
                    slew.target,
                    &inputs,
                    per_step,
                    false,
                )
                .unwrap();
                let fit = residuals(&slew, h, &run).unwrap();
                let step_weights: Vec<f64> = if per_step == 1 {
                    vec![h]
                } else {
                    weights.iter().map(|b| h * b).collect()
                };
                for exact_target in [true, false] {
                    let check = |bound: f64| {
                        banded_matches_condensed(
                            &run,
                            Some(&fit),
                            None,
                            &inputs,
                            &step_weights,
                            bound,
                            exact_target,
                            false,
                        )
                    };
                    // Unbounded, then bounded below the unbounded optimum's largest entry,
                    // so that a bound is active (the subproblem is convex).
                    let (_, peak) = check(f64::INFINITY);
                    let (active, _) = check(0.9 * peak);
                    assert!(active > 0, "no bound active");
                }
            }
        }
    }
}
