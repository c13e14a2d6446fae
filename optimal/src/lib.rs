//! Optimal control on the group with lgsvi's variational step as the constraint: the
//! minimum-energy slew of a rigid body, from a start `(R₀, Ω₀)` to a target `(R_f, Ω_f)` in
//! a fixed time, the torques bounded per axis.
//!
//! # The problem
//!
//! `K` steps of `h = T/K`, each one of lgsvi's steps (`n` nodes, exp chart, exact
//! matching), the body torque `u_k` held over step `k` (the integrator's input):
//!
//! ```text
//! minimise   Σ_k h |u_k|²                       (= ∫ |u|² dt, no ½)
//! subject to x_{k+1} = step(x_k, u_k),  x_0 = (R₀, Ω₀),  x_K = (R_f, Ω_f),
//!            |u_k,i| ≤ u_max,i
//! ```
//!
//! The states are the step's own, so the solution replays exactly: an [`Integrator`]
//! driven with the optimal torques lands on the target (to the solver's tolerance).
//!
//! # The solver
//!
//! Sequential quadratic programming over the torques (single shooting: each iterate's
//! states come from a run of the integrator, so every iterate is a motion). Each iteration
//! linearises every step exactly ([`Integrator::step_linearized`]: `A_k = ∂x_{k+1}/∂x_k`,
//! `B_k = ∂x_{k+1}/∂u_k` in the body-frame coordinates `(θ, ω)` of
//! `docs/linearization.md`), chains them into the terminal state's sensitivity
//! `M = ∂x_K/∂u`, and solves the QP
//!
//! ```text
//! minimise  Σ h |u_k + δu_k|²  subject to  M δu = e,  |u + δu| ≤ u_max
//! ```
//!
//! (`e = (log(R_Kᵀ R_f), Ω_f − Ω_K)`, the terminal state's miss) with `clarabel`. Its
//! Hessian is the cost's, exact; the constraint's curvature (the step's second
//! derivatives, which lgsvi does not form) is left out: a Gauss–Newton SQP, converging
//! linearly at a rate set by the multipliers times that curvature, quadratically for a
//! motion that is linear in the torques. A step that does not lower the merit
//! `J + ρ |e|₁` is halved. The iteration ends when the scaled KKT residual
//! (stationarity over `1 + |∇J|`, and the terminal miss) is at most the tolerance.
//!
//! The torque is constant over each step: the optimal cost of the discrete problem
//! converges to the continuous one at second order in `h`, whatever the integrator's
//! order (measured in `optimal/tests/slews.rs` and `docs/optimal.md`); inputs polynomial
//! within a step, which would follow the integrator's order, are not built yet.
//!
//! ```
//! use lgsvi_mechanics::lie::{LieGroup, SO3};
//! use lgsvi_mechanics::Inertia;
//! use lgsvi_optimal::Slew;
//! use nalgebra::Vector3;
//!
//! // A 90° rest-to-rest slew about an oblique axis in 20 s, at most 0.05 N·m per axis.
//! let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.0])?;
//! let target = SO3::exp(&(Vector3::new(1.0, 1.0, 0.0).normalize() * std::f64::consts::FRAC_PI_2));
//! let solution = Slew::new(inertia, 20.0)
//!     .to(target, Vector3::zeros())
//!     .steps(40)
//!     .torque_max([0.05; 3])
//!     .solve()?;
//! assert!(solution.converged);
//! assert!(solution.inputs.iter().all(|u| u.amax() <= 0.05 + 1e-9));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus,
    SupportedConeT, ZeroConeT,
};
use lgsvi_mechanics::lie::{LieGroup, SO3};
use lgsvi_mechanics::linearization::Coordinates;
use lgsvi_mechanics::{Inertia, Integrator, MechanicsError, RigidBody, State, StepSettings};
use nalgebra::{DMatrix, DVector, Vector3};
use std::time::Instant;

/// Why a slew was not solved.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OptimalError {
    /// A setting out of range.
    #[error("invalid {name} = {value}: {reason}")]
    InvalidSetting {
        /// The setting.
        name: &'static str,
        /// Its value, as given.
        value: String,
        /// Why, and what to give.
        reason: String,
    },
    /// No torques (within the bounds, where there are any) reach the target in the time.
    #[error(
        "infeasible: {} (the closest iterate misses it by {residual:.3e}): {}",
        if *bounded { "no torques within the bounds reach the target in the time" }
        else { "the QP finds no torques that reach the target" },
        if *bounded { "raise the torque bound or the final time" }
        else { "the problem's numbers are too far apart for the QP (give the time, inertia \
               and torques units that make them comparable) or too few steps" }
    )]
    Infeasible {
        /// The terminal miss of the last iterate.
        residual: f64,
        /// Whether the torques were bounded (the bounds are then the likely cause).
        bounded: bool,
    },
    /// The iteration did not reach the tolerance.
    #[error(
        "not converged after {iterations} iterations: scaled KKT residual {residual:.3e} \
         against {tolerance:e}; allow more iterations, loosen the tolerance, or give more \
         steps or time"
    )]
    NotConverged {
        /// Iterations taken.
        iterations: usize,
        /// The scaled KKT residual reached.
        residual: f64,
        /// The tolerance asked for.
        tolerance: f64,
    },
    /// A step of the integrator failed.
    #[error("a step failed: {0}")]
    Mechanics(#[from] MechanicsError),
    /// The QP subproblem solver failed.
    #[error(
        "the QP subproblem: {0}; the problem's numbers may be too far apart for it: give the \
         time, inertia and torques units that make them comparable"
    )]
    Subproblem(String),
}

/// A minimum-energy slew of a rigid body (module documentation): built, then
/// [`Slew::solve`]d.
#[derive(Debug, Clone)]
pub struct Slew {
    inertia: Inertia,
    t_end: f64,
    start: (SO3, Vector3<f64>),
    target: (SO3, Vector3<f64>),
    steps: usize,
    nodes: usize,
    torque_max: Option<Vector3<f64>>,
    tolerance: f64,
    max_iterations: usize,
    initial: Option<Vec<Vector3<f64>>>,
}

/// The solver's record of a solve.
#[derive(Debug, Clone, PartialEq)]
pub struct Statistics {
    /// SQP iterations.
    pub iterations: usize,
    /// The scaled KKT residual at each iterate.
    pub kkt_residuals: Vec<f64>,
    /// The terminal miss at each iterate.
    pub terminal_misses: Vec<f64>,
    /// Wall time (s).
    pub time_s: f64,
}

/// A solved slew.
#[derive(Debug, Clone)]
pub struct Solution {
    /// The states at the step boundaries, `x_0 … x_K`.
    pub states: Vec<State>,
    /// The torque of each step, `u_0 … u_{K−1}` (body frame, N·m).
    pub inputs: Vec<Vector3<f64>>,
    /// `Σ h |u_k|²`.
    pub cost: f64,
    /// The terminal constraint's multipliers (`∂J*/∂e`, in `(θ, ω)` at the target).
    pub multipliers: [f64; 6],
    /// The step `h = T/K`.
    pub h: f64,
    /// Whether the scaled KKT residual reached the tolerance.
    pub converged: bool,
    /// The solver's record.
    pub statistics: Statistics,
}

impl Slew {
    /// A slew of the body of `inertia` in time `t_end`, by default rest to rest from the
    /// identity to the identity, 20 steps of 10 nodes, no torque bound, tolerance 1e-10,
    /// at most 100 iterations, from rest.
    pub fn new(inertia: Inertia, t_end: f64) -> Self {
        Self {
            inertia,
            t_end,
            start: (SO3::identity(), Vector3::zeros()),
            target: (SO3::identity(), Vector3::zeros()),
            steps: 20,
            nodes: 10,
            torque_max: None,
            tolerance: 1e-10,
            max_iterations: 100,
            initial: None,
        }
    }

    /// The start `(R₀, Ω₀)` (body to world; body rates).
    pub fn from(mut self, attitude: SO3, omega: Vector3<f64>) -> Self {
        self.start = (attitude, omega);
        self
    }

    /// The target `(R_f, Ω_f)`.
    pub fn to(mut self, attitude: SO3, omega: Vector3<f64>) -> Self {
        self.target = (attitude, omega);
        self
    }

    /// `K` steps.
    pub fn steps(mut self, steps: usize) -> Self {
        self.steps = steps;
        self
    }

    /// `n` nodes per step.
    pub fn nodes(mut self, nodes: usize) -> Self {
        self.nodes = nodes;
        self
    }

    /// The largest torque per body axis.
    pub fn torque_max(mut self, bound: [f64; 3]) -> Self {
        self.torque_max = Some(Vector3::from(bound));
        self
    }

    /// The scaled KKT residual to reach.
    pub fn tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }

    /// The most SQP iterations.
    pub fn max_iterations(mut self, iterations: usize) -> Self {
        self.max_iterations = iterations;
        self
    }

    /// Start the iteration from these torques (a warm start: one per step) instead of
    /// rest.
    pub fn warm_start(mut self, inputs: Vec<Vector3<f64>>) -> Self {
        self.initial = Some(inputs);
        self
    }

    fn check(&self) -> Result<StepSettings, OptimalError> {
        let invalid = |name, value: String, reason: &str| OptimalError::InvalidSetting {
            name,
            value,
            reason: reason.into(),
        };
        if !(self.t_end.is_finite() && self.t_end > 0.0) {
            return Err(invalid(
                "t_end",
                format!("{:?}", self.t_end),
                "the final time is positive and finite",
            ));
        }
        if self.steps < 2 || self.steps > 100_000 {
            return Err(invalid(
                "steps",
                self.steps.to_string(),
                "from 2 to 100000 steps (the terminal attitude and rates are six conditions; \
                 one step has three torques)",
            ));
        }
        if let Some(bound) = self.torque_max {
            if bound.iter().any(|b| !(b.is_finite() && *b > 0.0)) {
                return Err(invalid(
                    "torque_max",
                    format!("{:?}", bound.as_slice()),
                    "each axis's bound is positive and finite",
                ));
            }
        }
        if !(self.tolerance.is_finite() && self.tolerance >= 1e-14 && self.tolerance < 1.0) {
            return Err(invalid(
                "tolerance",
                format!("{:?}", self.tolerance),
                "a scaled KKT residual from 1e-14 to below 1",
            ));
        }
        for (name, (r, w)) in [("start", self.start), ("target", self.target)] {
            if !(r.matrix().iter().all(|x| x.is_finite()) && w.iter().all(|x| x.is_finite())) {
                return Err(invalid(
                    name,
                    format!("{:?}, {:?}", r.matrix().as_slice(), w.as_slice()),
                    "not finite",
                ));
            }
        }
        if let Some(initial) = &self.initial {
            if initial.len() != self.steps {
                return Err(invalid(
                    "warm_start",
                    format!("{} torques", initial.len()),
                    "one torque per step",
                ));
            }
        }
        Ok(StepSettings::new(
            self.t_end / self.steps as f64,
            self.nodes,
        )?)
    }

    /// Solves the slew (module documentation).
    ///
    /// # Errors
    /// [`OptimalError::InvalidSetting`] for a setting out of range;
    /// [`OptimalError::Infeasible`] when the bounds leave the target out of reach;
    /// [`OptimalError::NotConverged`] when the iterations run out;
    /// [`OptimalError::Mechanics`] for a step that fails (a slew too fast for its steps:
    /// give more steps).
    pub fn solve(&self) -> Result<Solution, OptimalError> {
        let settings = self.check()?;
        let clock = Instant::now();
        let (k_steps, h) = (self.steps, settings.h());
        let body = RigidBody::new(self.inertia);
        let mut inputs = self
            .initial
            .clone()
            .unwrap_or_else(|| vec![Vector3::zeros(); k_steps]);
        if let Some(bound) = self.torque_max {
            for u in &mut inputs {
                *u = u.zip_map(&bound, |x, b| x.clamp(-b, b));
            }
        }
        let cost = |u: &[Vector3<f64>]| h * u.iter().map(|u| u.norm_squared()).sum::<f64>();
        let mut statistics = Statistics {
            iterations: 0,
            kkt_residuals: Vec::new(),
            terminal_misses: Vec::new(),
            time_s: 0.0,
        };
        let mut multipliers = DVector::<f64>::zeros(6);
        let mut bound_duals = DVector::<f64>::zeros(3 * k_steps);
        let mut run = self.shoot(body, settings, &inputs)?;
        loop {
            let miss = run.miss.amax();
            let gradient = DVector::from_iterator(
                3 * k_steps,
                inputs
                    .iter()
                    .flat_map(|u| (2.0 * h * u).into_iter().copied().collect::<Vec<_>>()),
            );
            let stationarity =
                (&gradient + run.sensitivity.transpose() * &multipliers + &bound_duals).amax()
                    / (1.0 + gradient.amax());
            let residual = stationarity.max(miss);
            statistics.kkt_residuals.push(residual);
            statistics.terminal_misses.push(miss);
            if residual <= self.tolerance && statistics.iterations > 0 {
                break;
            }
            if statistics.iterations >= self.max_iterations {
                return Err(OptimalError::NotConverged {
                    iterations: statistics.iterations,
                    residual,
                    tolerance: self.tolerance,
                });
            }
            statistics.iterations += 1;
            let qp = self.subproblem(h, &inputs, &run)?;
            let (step, lambda, nu) = match qp {
                Some(qp) => qp,
                None => {
                    return Err(OptimalError::Infeasible {
                        residual: miss,
                        bounded: self.torque_max.is_some(),
                    })
                }
            };
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
                let trial_run = self.shoot(body, settings, &trial);
                match trial_run {
                    Ok(r) if merit(cost(&trial), &r.miss) <= before || alpha < 1e-3 => {
                        break (trial, r)
                    }
                    Err(error) if alpha < 1e-3 => return Err(error),
                    _ => alpha *= 0.5,
                }
            };
            inputs = next_inputs;
            run = next_run;
            multipliers = lambda;
            bound_duals = nu;
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
            converged: true,
            statistics,
        })
    }

    /// The run from the start with `inputs`, its terminal miss and the terminal state's
    /// sensitivity to every torque.
    fn shoot(
        &self,
        body: RigidBody,
        settings: StepSettings,
        inputs: &[Vector3<f64>],
    ) -> Result<Shot, OptimalError> {
        let mut it = Integrator::new(body, settings, self.start.0, self.start.1)?;
        let mut states = vec![*it.state()];
        let mut a = Vec::with_capacity(inputs.len());
        let mut b = Vec::with_capacity(inputs.len());
        for u in inputs {
            it.set_input(*u)?;
            let step = it.step_linearized()?;
            a.push(step.a(Coordinates::Velocity).clone());
            b.push(step.b(Coordinates::Velocity).clone());
            states.push(*it.state());
        }
        // M = ∂x_K/∂u: M_k = A_{K−1} ⋯ A_{k+1} B_k, chained backwards.
        let k_steps = inputs.len();
        let mut sensitivity = DMatrix::<f64>::zeros(6, 3 * k_steps);
        let mut chain = DMatrix::<f64>::identity(6, 6);
        for k in (0..k_steps).rev() {
            sensitivity
                .view_mut((0, 3 * k), (6, 3))
                .copy_from(&(&chain * &b[k]));
            chain = &chain * &a[k];
        }
        let last = states[k_steps];
        let rotation = last.configuration.inverse().compose(&self.target.0).log();
        let rates = self.target.1 - last.velocity;
        let miss = DVector::from_iterator(6, rotation.iter().chain(rates.iter()).copied());
        Ok(Shot {
            states,
            sensitivity,
            miss,
        })
    }

    /// The QP of one iteration: the step in the torques, the terminal multipliers and
    /// the bounds' (upper minus lower); `None` where the QP is infeasible.
    #[allow(clippy::type_complexity)]
    fn subproblem(
        &self,
        h: f64,
        inputs: &[Vector3<f64>],
        run: &Shot,
    ) -> Result<Option<(DVector<f64>, DVector<f64>, DVector<f64>)>, OptimalError> {
        let n = 3 * inputs.len();
        // ½ δuᵀ (2h I) δu + (2h u)ᵀ δu: the cost Σ h |u + δu|² up to a constant.
        let p = CscMatrix::new(n, n, (0..=n).collect(), (0..n).collect(), vec![2.0 * h; n]);
        let q: Vec<f64> = inputs
            .iter()
            .flat_map(|u| [2.0 * h * u.x, 2.0 * h * u.y, 2.0 * h * u.z])
            .collect();
        // Rows: M δu = e (6), then δu ≤ u_max − u and −δu ≤ u_max + u.
        let bounded = self.torque_max.is_some();
        let rows = 6 + if bounded { 2 * n } else { 0 };
        let mut colptr = vec![0];
        let (mut rowval, mut nzval) = (Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..6 {
                rowval.push(i);
                nzval.push(run.sensitivity[(i, j)]);
            }
            if bounded {
                rowval.extend([6 + j, 6 + n + j]);
                nzval.extend([1.0, -1.0]);
            }
            colptr.push(rowval.len());
        }
        let a = CscMatrix::new(rows, n, colptr, rowval, nzval);
        let mut b: Vec<f64> = run.miss.iter().copied().collect();
        let mut cones: Vec<SupportedConeT<f64>> = vec![ZeroConeT(6)];
        if let Some(bound) = self.torque_max {
            let flat: Vec<f64> = inputs.iter().flat_map(|u| [u.x, u.y, u.z]).collect();
            b.extend((0..n).map(|j| bound[j % 3] - flat[j]));
            b.extend((0..n).map(|j| bound[j % 3] + flat[j]));
            cones.push(NonnegativeConeT(2 * n));
        }
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .tol_gap_abs(1e-13)
            .tol_gap_rel(1e-13)
            .tol_feas(1e-13)
            .build()
            .map_err(|e| OptimalError::Subproblem(format!("{e:?}")))?;
        let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings)
            .map_err(|e| OptimalError::Subproblem(format!("{e:?}")))?;
        solver.solve();
        match solver.solution.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => {
                let z = &solver.solution.z;
                let lambda = DVector::from_column_slice(&z[..6]);
                let nu = if bounded {
                    DVector::from_iterator(n, (0..n).map(|j| z[6 + j] - z[6 + n + j]))
                } else {
                    DVector::zeros(n)
                };
                Ok(Some((
                    DVector::from_column_slice(&solver.solution.x),
                    lambda,
                    nu,
                )))
            }
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => Ok(None),
            other => Err(OptimalError::Subproblem(format!(
                "clarabel stopped with status {other:?}"
            ))),
        }
    }
}

/// One run of the torques: its states, the terminal state's sensitivity and miss.
struct Shot {
    states: Vec<State>,
    sensitivity: DMatrix<f64>,
    miss: DVector<f64>,
}

/// The page `docs/optimal.md`, whose Rust example is compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../../docs/optimal.md")]
pub struct DocsPage;
