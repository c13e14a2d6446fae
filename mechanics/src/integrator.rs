//! The integrator: initial state, stepping, trajectories, invariants, dense output.

use crate::error::{check_finite, MechanicsError};
use crate::flow::FlowGuess;
use crate::galerkin::{Discretisation, Stepper, Workspace};
use crate::lagrangian::Lagrangian;
use crate::settings::StepSettings;
use lgsvi_lie::{ChartKind, So3Chart, SO3};
use nalgebra::{Matrix3, SVector, Vector3};
use num_dual::{Dual2SVec64, DualSVec64};

/// A continued curve whose residual is below this fraction of the equations' terms is
/// taken without trying the velocity-corrected predictor (Newton then needs ~2 steps).
const PREDICTOR_GOOD_ENOUGH: f64 = 1e-3;

/// A converged step whose end attitude is further than this (radians) from the system's
/// own flow over the step is an aliased root. The flow's error is ~1e-5 of the step's
/// rotation (see [`crate::flow`]) and a converged step's local error far below 0.1 rad on
/// any step that converges to the motion, while an aliased root is off by an O(1) turn.
const ALIASED_DISTANCE: f64 = 0.5;

/// What to suggest besides a smaller step when a step outruns `chart`.
fn chart_advice(chart: ChartKind) -> &'static str {
    match chart {
        ChartKind::Exp => "",
        ChartKind::Cayley | ChartKind::CayleyUnscaled => {
            " or the exp chart (--chart exp), which follows up to 2π per step"
        }
    }
}

/// `μ = ∂ℓ/∂Ω(R, Ω)` (the Legendre transform), by dual numbers.
pub fn body_momentum<L: Lagrangian>(
    system: &L,
    attitude: &Matrix3<f64>,
    omega: &Vector3<f64>,
) -> Vector3<f64> {
    let (_, gradient) = num_dual::gradient(
        |w: SVector<DualSVec64<3>, 3>| {
            let r: Matrix3<DualSVec64<3>> = attitude.map(nalgebra::convert);
            system.lagrangian(&r, &w)
        },
        omega,
    );
    gradient
}

/// `Ω` with `∂ℓ/∂Ω(R, Ω) = μ`: the closed form when the system has one, else Newton
/// with the exact Hessian `∂²ℓ/∂Ω²` from `guess`.
///
/// # Errors
/// [`MechanicsError::InverseLegendre`] if Newton does not converge (a Lagrangian not
/// strictly convex in `Ω`).
pub fn body_velocity<L: Lagrangian>(
    system: &L,
    attitude: &Matrix3<f64>,
    momentum: &Vector3<f64>,
    guess: &Vector3<f64>,
) -> Result<Vector3<f64>, MechanicsError> {
    if let Some(omega) = system.velocity_from_momentum(attitude, momentum) {
        return Ok(omega);
    }
    let mut omega = *guess;
    let mut residual_norm = f64::INFINITY;
    for iteration in 0..50 {
        let (_, gradient, hessian) = num_dual::hessian(
            |w: SVector<Dual2SVec64<3>, 3>| {
                let r: Matrix3<Dual2SVec64<3>> = attitude.map(nalgebra::convert);
                system.lagrangian(&r, &w)
            },
            &omega,
        );
        let residual = gradient - momentum;
        residual_norm = residual.amax();
        if residual_norm <= 16.0 * f64::EPSILON * momentum.amax().max(1.0) {
            return Ok(omega);
        }
        let Some(delta) = hessian.lu().solve(&residual) else {
            break;
        };
        omega -= delta;
        if !omega.iter().all(|w| w.is_finite()) {
            break;
        }
        if iteration > 0 && delta.amax() <= 4.0 * f64::EPSILON * omega.amax() {
            return Ok(omega);
        }
    }
    Err(MechanicsError::InverseLegendre {
        residual: residual_norm,
    })
}

/// The state at a step: time, attitude, body momentum and velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    /// Time.
    pub time: f64,
    /// `R = world_from_body`.
    pub attitude: SO3,
    /// Body momentum `μ`.
    pub momentum: Vector3<f64>,
    /// Body angular velocity `Ω` with `∂ℓ/∂Ω(R, Ω) = μ` (for `½ΩᵀJΩ − V`: `J⁻¹μ`).
    pub velocity: Vector3<f64>,
}

impl State {
    /// Spatial (world-frame) angular momentum `Rμ`: conserved by every left-invariant
    /// system, and its component along gravity by the heavy top.
    pub fn spatial_momentum(&self) -> Vector3<f64> {
        self.attitude.matrix() * self.momentum
    }

    /// `|μ|²`, the Casimir: conserved by the free rigid body.
    pub fn casimir(&self) -> f64 {
        self.momentum.norm_squared()
    }

    /// Energy `⟨μ, Ω⟩ − ℓ(R, Ω)`.
    pub fn energy<L: Lagrangian>(&self, system: &L) -> f64 {
        self.momentum.dot(&self.velocity)
            - system.lagrangian(self.attitude.matrix(), &self.velocity)
    }
}

/// Newton statistics of the run so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Statistics {
    /// Steps taken.
    pub steps: usize,
    /// Newton iterations, summed over the steps.
    pub newton_iterations: usize,
    /// The most Newton iterations one step took.
    pub max_newton_iterations: usize,
    /// Newton matrices assembled and factored, summed over the steps: the iterations
    /// beyond these were chord steps, which reuse the step's last factored matrix.
    pub factorizations: usize,
}

/// A step's Galerkin curve: `g(t) = g_k Φ(ξ(t))`, `t ∈ [0, h]` from the step's start.
#[derive(Debug, Clone)]
pub struct GalerkinCurve {
    base: SO3,
    nodes: Vec<Vector3<f64>>,
    basis: lgsvi_spectral::Barycentric,
    chart: ChartKind,
    start: f64,
}

impl GalerkinCurve {
    /// The step's start time.
    pub fn start(&self) -> f64 {
        self.start
    }

    /// The step length `h`.
    pub fn step(&self) -> f64 {
        *self.basis.nodes().last().unwrap_or(&0.0)
    }

    /// `(g(t), Ω(t))` at `t` seconds after the step's start (`0 ≤ t ≤ h`; outside,
    /// the polynomial is extrapolated).
    ///
    /// # Errors
    /// [`MechanicsError::Spectral`] for a non-finite `t`.
    pub fn at(&self, t: f64) -> Result<(SO3, Vector3<f64>), MechanicsError> {
        let n = self.nodes.len();
        let mut phi = vec![0.0; n];
        let mut dphi = vec![0.0; n];
        self.basis
            .basis_and_derivatives_into(t, &mut phi, &mut dphi)?;
        let mut xi = Vector3::zeros();
        let mut xi_dot = Vector3::zeros();
        for i in 0..n {
            xi += self.nodes[i] * phi[i];
            xi_dot += self.nodes[i] * dphi[i];
        }
        let g = self.base * SO3::from_matrix_unchecked(self.chart.rotation_matrix(&xi));
        Ok((g, self.chart.rotation_left_differential(&xi) * xi_dot))
    }

    /// The chart coordinates `ξ¹ = 0, ξ², …, ξⁿ` of the nodes.
    pub fn nodes(&self) -> &[Vector3<f64>] {
        &self.nodes
    }
}

/// A recorded trajectory (every `every`-th step, always the first and the last).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Trajectory {
    /// States, in time order.
    pub states: Vec<State>,
    /// Newton iterations of the step that produced each state (0 for the initial one).
    pub newton_iterations: Vec<usize>,
}

/// The Lie group spectral variational integrator for a system on SO(3).
///
/// ```
/// use lgsvi_mechanics::{Inertia, Integrator, RigidBody, StepSettings};
/// use lgsvi_lie::SO3;
/// use nalgebra::Vector3;
///
/// // The paper's rigid body, 20 steps of h = 0.5 with 10 nodes (exp chart, exact matching).
/// let body = RigidBody::new(Inertia::from_paper_jd([1.3, 2.1, 1.2])?);
/// let settings = StepSettings::new(0.5, 10)?;
/// let mut integrator = Integrator::new(body, settings, SO3::identity(), Vector3::new(-2.0, 1.9, -1.0))?;
/// let start = *integrator.state();
/// let trajectory = integrator.run(20, 1)?;
/// let end = trajectory.states.last().unwrap();
/// // Spatial angular momentum and |μ|² are conserved to rounding.
/// assert!((end.spatial_momentum() - start.spatial_momentum()).amax() < 1e-12);
/// assert!((end.casimir() - start.casimir()).abs() < 1e-11);
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
pub struct Integrator<L: Lagrangian> {
    system: L,
    settings: StepSettings,
    discretisation: Discretisation,
    work: Workspace,
    state: State,
    step_index: usize,
    /// The velocity at the start of the last step taken; `None` before the first step
    /// (then there is no previous Galerkin curve either).
    previous_velocity: Option<Vector3<f64>>,
    last_nodes: Vec<Vector3<f64>>,
    /// Scratch for the predictor's comparison.
    extrapolated: Vec<Vector3<f64>>,
    last_base: SO3,
    /// The flow predictor's attitude at the end of the step being taken, relative to its
    /// start, when the flow could be integrated: the check against aliased roots.
    flow_end: Option<Matrix3<f64>>,
    statistics: Statistics,
}

impl<L: Lagrangian> Integrator<L> {
    /// Starts at attitude `R₀` with body angular velocity `Ω₀` (`μ₀ = ∂ℓ/∂Ω(R₀, Ω₀)`).
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`] for non-finite `Ω₀` or attitude; errors of the
    /// quadrature or basis construction (not expected for valid settings).
    pub fn new(
        system: L,
        settings: StepSettings,
        attitude: SO3,
        omega: Vector3<f64>,
    ) -> Result<Self, MechanicsError> {
        check_finite("initial angular velocity", omega.as_slice())?;
        check_finite("initial attitude", attitude.matrix().as_slice())?;
        let discretisation = Discretisation::new(&settings)?;
        let work = Workspace::new(&discretisation);
        let momentum = body_momentum(&system, attitude.matrix(), &omega);
        let n = settings.nodes();
        Ok(Self {
            system,
            settings,
            discretisation,
            work,
            state: State {
                time: 0.0,
                attitude,
                momentum,
                velocity: omega,
            },
            step_index: 0,
            previous_velocity: None,
            last_nodes: vec![Vector3::zeros(); n],
            extrapolated: vec![Vector3::zeros(); n],
            last_base: attitude,
            flow_end: None,
            statistics: Statistics::default(),
        })
    }

    /// The current state.
    pub fn state(&self) -> &State {
        &self.state
    }

    /// The system.
    pub fn system(&self) -> &L {
        &self.system
    }

    /// The settings.
    pub fn settings(&self) -> &StepSettings {
        &self.settings
    }

    /// Newton statistics so far.
    pub fn statistics(&self) -> &Statistics {
        &self.statistics
    }

    /// The Galerkin curve of the last step taken (dense output), if any.
    pub fn last_curve(&self) -> Option<GalerkinCurve> {
        self.previous_velocity.is_some().then(|| GalerkinCurve {
            base: self.last_base,
            nodes: self.last_nodes.clone(),
            basis: self.discretisation.basis.clone(),
            chart: self.settings.chart(),
            start: self.state.time - self.settings.step(),
        })
    }

    /// The predictor. When the system gives `Ω(μ)` in closed form (the built-in ones do):
    /// the system's own flow over the step by a few Runge–Kutta substeps
    /// ([`Integrator::predict_by_flow`]; measured relative residual 3e-6 at `h = 0.5`
    /// and 2e-5 at `h = 1` on the paper's rigid body, against 3e-4 and 0.1 for the
    /// continued curve). Otherwise, after the first step: the last step's Galerkin curve
    /// continued ([`Integrator::extrapolate`]); if its relative residual exceeds
    /// [`PREDICTOR_GOOD_ENOUGH`] (long steps), the better of it and the previous step's
    /// chart coordinates corrected by the change of velocity,
    /// `ξⁱ ← ξⁱ_prev + A(0)⁻¹ t_i (Ω_k − Ω_{k−1})` (second order in `h`). On the first
    /// step, or with `constant_velocity`, `ξⁱ = Φ⁻¹(exp(t_i Ω_k))`: first order, but robust
    /// when the velocity changes a lot within a step (the fallback when Newton fails).
    ///
    /// Returns whether the guess is the constant-velocity one (nothing left to retry).
    ///
    /// # Errors
    /// [`MechanicsError::StepTooLong`] where the flow (or, without one, the present
    /// angular speed) turns the body past the chart's reach within the step.
    fn predict(&mut self, constant_velocity: bool) -> Result<bool, MechanicsError> {
        self.work.guess_changed();
        if !constant_velocity {
            self.flow_end = None;
            match self.predict_by_flow() {
                FlowGuess::Written(end) => {
                    self.flow_end = Some(end);
                    return Ok(false);
                }
                FlowGuess::LeavesChart { time, angle } => {
                    return Err(self.step_too_long(angle, time));
                }
                FlowGuess::Unavailable => {
                    // Without the flow, the present angular speed bounds what a step
                    // must be able to turn.
                    let h = self.settings.step();
                    let rotation = self.state.velocity.norm() * h;
                    let limit = self.settings.chart().max_rotation_angle();
                    if rotation >= limit {
                        return Err(self.step_too_long(rotation, h * limit / rotation));
                    }
                }
            }
        }
        if !constant_velocity && self.previous_velocity.is_some() && self.extrapolate() {
            // On long steps the continuation can be worse than the velocity correction
            // below: when its residual is not small, keep the better of the two.
            let continued = self.predictor_residual();
            if continued <= PREDICTOR_GOOD_ENOUGH {
                return Ok(false);
            }
            self.extrapolated.copy_from_slice(&self.work.xi);
            self.predict_from_velocity(false);
            let corrected = self.predictor_residual();
            if continued <= corrected {
                self.work.xi.copy_from_slice(&self.extrapolated);
                self.work.guess_changed();
            }
            return Ok(false);
        }
        self.predict_from_velocity(constant_velocity);
        Ok(constant_velocity || self.previous_velocity.is_none())
    }

    /// The error for a step that turns the body `rotation` rad, reaching the chart's
    /// limit `suggested` seconds into the step.
    fn step_too_long(&self, rotation: f64, suggested: f64) -> MechanicsError {
        let chart = self.settings.chart();
        MechanicsError::StepTooLong {
            step: self.step_index,
            time: self.state.time,
            chart: chart.chart_name(),
            rotation,
            limit: chart.max_rotation_angle(),
            suggested,
            advice: chart_advice(chart),
        }
    }

    /// The error for a converged step `distance` rad away from the flow's end attitude.
    fn aliased_root(&self, distance: f64) -> MechanicsError {
        let chart = self.settings.chart();
        MechanicsError::AliasedRoot {
            step: self.step_index,
            time: self.state.time,
            chart: chart.chart_name(),
            distance,
            advice: chart_advice(chart),
        }
    }

    /// The system's own flow over the step (classical RK4 on a quaternion, see
    /// [`crate::flow`]), when the system gives `Ω(μ)` in closed form: the guess is written
    /// ([`FlowGuess::Written`]), the flow turns past the chart's reach
    /// ([`FlowGuess::LeavesChart`]), or there is no flow to follow
    /// ([`FlowGuess::Unavailable`]; the guess then comes from the other predictors).
    fn predict_by_flow(&mut self) -> FlowGuess {
        let base = *self.state.attitude.matrix();
        let done = crate::flow::flow_guess(
            &self.system,
            self.settings.chart(),
            &base,
            &self.state.momentum,
            &self.state.velocity,
            self.settings.step(),
            self.discretisation.node_times(),
            &mut self.work.xi,
        );
        self.work.xi[0] = Vector3::zeros();
        done
    }

    /// The velocity-corrected (or, with `constant_velocity`, constant-velocity) predictor.
    fn predict_from_velocity(&mut self, constant_velocity: bool) {
        self.work.guess_changed();
        let chart = self.settings.chart();
        let a0_inv = chart.rotation_left_differential_inverse(&Vector3::zeros());
        let omega = self.state.velocity;
        let times = self.discretisation.node_times();
        match self.previous_velocity {
            Some(previous) if !constant_velocity => {
                let change = a0_inv * (omega - previous);
                for (i, t) in times.iter().enumerate() {
                    self.work.xi[i] = self.last_nodes[i] + change * *t;
                }
            }
            _ => {
                for (i, t) in times.iter().enumerate() {
                    // On the branch of the linear guess: past a half turn per step, the
                    // principal logarithm would jump to the other side of the exp chart.
                    let linear = a0_inv * (omega * *t);
                    let rotation = SO3::exp(&(omega * *t));
                    self.work.xi[i] = chart
                        .rotation_vector_near(rotation.matrix(), &linear)
                        .unwrap_or(linear);
                }
            }
        }
        self.work.xi[0] = Vector3::zeros();
    }

    /// The previous step's Galerkin curve continued over the next step, in the new
    /// step's chart: `ξⁱ = Φ⁻¹(Φ(ξⁿ_prev)⁻¹ Φ(ξ_prev(h + t_i)))`. False where a node
    /// leaves `Φ⁻¹`'s domain (the guess is then partly written: the caller replaces it).
    fn extrapolate(&mut self) -> bool {
        let chart = self.settings.chart();
        let n = self.discretisation.n;
        self.work.xi[0] = Vector3::zeros();
        let end = chart.rotation_matrix(&self.last_nodes[n - 1]).transpose();
        for i in 1..n {
            let row = &self.discretisation.extrapolation[i * n..(i + 1) * n];
            let continued = row
                .iter()
                .zip(&self.last_nodes)
                .fold(Vector3::zeros(), |acc, (e, xi)| acc + xi * *e);
            // Each node on the branch of the one before (ξ¹ = 0): the continued curve may
            // rotate past a half turn relative to the step's start.
            let near = self.work.xi[i - 1];
            match chart.rotation_vector_near(&(end * chart.rotation_matrix(&continued)), &near) {
                Ok(xi) if xi.iter().all(|x| x.is_finite()) => self.work.xi[i] = xi,
                _ => return false,
            }
        }
        true
    }

    /// Advances one step; returns the Newton iterations it took.
    ///
    /// # Errors
    /// [`MechanicsError::NewtonDiverged`], [`MechanicsError::SingularJacobian`] or
    /// [`MechanicsError::OutsideChart`], naming the step;
    /// [`MechanicsError::StepTooLong`] where the motion turns the body past the chart's
    /// reach ([`lgsvi_lie::So3Chart::max_rotation_angle`]) within the step, and
    /// [`MechanicsError::AliasedRoot`] where Newton converged to an attitude that is not
    /// the continuation of the motion (checked against the system's own flow, when it
    /// has a closed-form `Ω(μ)`). The state is left unchanged.
    pub fn step(&mut self) -> Result<usize, MechanicsError> {
        let constant_velocity = self.predict(false)?;
        let base = *self.state.attitude.matrix();
        let first = self.solve(&base);
        let outcome = match first {
            Ok(outcome) => outcome,
            // A poor guess (the velocity changed a lot over the last step, or the flow
            // guess led Newton astray): retry once from constant velocity before giving up.
            Err(_) if !constant_velocity => {
                self.predict(true)?;
                self.solve(&base)?
            }
            Err(error) => return Err(error),
        };
        if let Some(end) = self.flow_end {
            let difference = end.transpose() * base.transpose() * outcome.attitude;
            let distance = SO3::from_matrix_unchecked(difference).angle();
            if distance.is_nan() || distance > ALIASED_DISTANCE {
                return Err(self.aliased_root(distance));
            }
        }
        // R_k Φ(ξⁿ) is a rotation up to the rounding of the product, which would
        // accumulate over millions of steps (measured ‖RᵀR − I‖ 1e-12 after 10⁶ steps);
        // one polar Newton step R(I + ½(I − RᵀR)) squares that deviation away.
        let r = outcome.attitude;
        let deviation = Matrix3::identity() - r.transpose() * r;
        let attitude = SO3::from_matrix_unchecked(r + r * deviation * 0.5);
        let velocity = body_velocity(
            &self.system,
            &outcome.attitude,
            &outcome.momentum,
            &self.state.velocity,
        )?;
        check_finite("momentum after the step", outcome.momentum.as_slice())?;
        self.last_base = self.state.attitude;
        self.last_nodes.copy_from_slice(&self.work.xi);
        self.previous_velocity = Some(self.state.velocity);
        self.step_index += 1;
        self.state = State {
            time: self.step_index as f64 * self.settings.step(),
            attitude,
            momentum: outcome.momentum,
            velocity,
        };
        let stats = &mut self.statistics;
        stats.steps += 1;
        stats.newton_iterations += outcome.iterations;
        stats.factorizations += outcome.factorizations;
        stats.max_newton_iterations = stats.max_newton_iterations.max(outcome.iterations);
        Ok(outcome.iterations)
    }

    fn solve(
        &mut self,
        base: &Matrix3<f64>,
    ) -> Result<crate::galerkin::StepOutcome, MechanicsError> {
        let (mu, step, time) = (self.state.momentum, self.step_index, self.state.time);
        let (stepper, work) = self.stepper();
        stepper.solve(base, &mu, work, step, time)
    }

    /// The relative residual of the guess in the workspace, from the current state.
    fn predictor_residual(&mut self) -> f64 {
        let (base, mu) = (*self.state.attitude.matrix(), self.state.momentum);
        let (stepper, work) = self.stepper();
        stepper.relative_residual(&base, &mu, work)
    }

    /// The step solver over this integrator's system and settings, beside its workspace.
    fn stepper(&mut self) -> (Stepper<'_, L>, &mut Workspace) {
        (
            Stepper {
                system: &self.system,
                settings: &self.settings,
                d: &self.discretisation,
            },
            &mut self.work,
        )
    }

    /// Takes `steps` steps, recording the initial state, every `every`-th state and the
    /// last one.
    ///
    /// # Errors
    /// As [`Integrator::step`]; the states recorded so far are lost with the error, the
    /// integrator keeps the last good state.
    pub fn run(&mut self, steps: usize, every: usize) -> Result<Trajectory, MechanicsError> {
        self.run_with_progress(steps, every, |_| {})
    }

    /// As [`Integrator::run`], calling `progress(k)` after step `k` (for a progress bar).
    ///
    /// # Errors
    /// As [`Integrator::run`].
    pub fn run_with_progress(
        &mut self,
        steps: usize,
        every: usize,
        mut progress: impl FnMut(usize),
    ) -> Result<Trajectory, MechanicsError> {
        let every = every.max(1);
        let mut trajectory = Trajectory {
            states: vec![self.state],
            newton_iterations: vec![0],
        };
        for k in 1..=steps {
            let iterations = self.step()?;
            if k % every == 0 || k == steps {
                trajectory.states.push(self.state);
                trajectory.newton_iterations.push(iterations);
            }
            progress(k);
        }
        Ok(trajectory)
    }

    /// The number of steps from the current time to reach `t_end` (the last one may
    /// overshoot by less than `h`: the method has a fixed step).
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for a non-finite or negative `t_end`.
    pub fn steps_until(&self, t_end: f64) -> Result<usize, MechanicsError> {
        if !(t_end.is_finite() && t_end >= 0.0) {
            return Err(MechanicsError::InvalidSetting {
                name: "t-end",
                value: t_end.to_string(),
                reason: "must be finite and non-negative",
            });
        }
        let remaining = (t_end - self.state.time).max(0.0);
        // A relative slack of 1e-9 steps keeps t_end = k·h from taking a (k+1)-th step
        // because of rounding in the division.
        Ok((remaining / self.settings.step() - 1e-9).ceil().max(0.0) as usize)
    }

    /// Steps until `t_end` (the last step may overshoot by less than `h`: the method has
    /// a fixed step), recording as [`Integrator::run`].
    ///
    /// # Errors
    /// As [`Integrator::run`]; [`MechanicsError::InvalidSetting`] for a non-finite or
    /// negative `t_end`.
    pub fn run_until(&mut self, t_end: f64, every: usize) -> Result<Trajectory, MechanicsError> {
        let steps = self.steps_until(t_end)?;
        self.run(steps, every)
    }
}
