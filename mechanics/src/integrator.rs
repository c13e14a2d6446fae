//! The integrator: initial state, stepping, control inputs, trajectories, invariants,
//! dense output — for any configuration group and chart.

use crate::error::{check_finite, MechanicsError};
use crate::flow::FlowGuess;
use crate::group::{ConfigurationGroup, GroupChart, Rotations};
use crate::linearization::StepLinearization;
use crate::settings::{StepSettings, MAX_NODES, ROUNDING_FLOOR};
use crate::state::{body_momentum, body_velocity, State};
use crate::step::assembly::{Workspace, WorkspaceOf};
use crate::step::points::StepForce;
use crate::step::tables::Discretisation;
use crate::step::{StepOutcome, Stepper};
use crate::system::{ElementOf, FlowStart, ForceAlongStep, GroupLagrangian, PointForce};
use lgsvi_lie::{ChartKind, LieGroup, SO3};
use nalgebra::{SMatrix, SVector};
use std::marker::PhantomData;
use std::sync::Arc;

/// A continued curve whose residual is below this fraction of the equations' terms is
/// taken without trying the velocity-corrected predictor (Newton then needs ~2 steps).
const PREDICTOR_GOOD_ENOUGH: f64 = 1e-3;

/// A continued curve whose relative residual is at or below this is taken instead of the
/// flow in the chart ([`crate::flow::chart_flow`]): the flow's guess is typically 1e-6 to
/// 1e-5 (measured on the orbiting body), so below it the continued curve needs no more
/// Newton work.
const CONTINUED_BEATS_FLOW: f64 = 1e-6;

/// While the flow in the chart wins, the continued curve is tried again every this many
/// steps (one assembly wasted when it loses: about 1.5% of the steps' work).
const PROBE_CONTINUED: usize = 16;

/// A converged step whose end attitude is further than this (radians) from the system's
/// own flow over the step is an aliased root. The flow's error is ~1e-5 of the step's
/// rotation (see [`crate::flow`]) and a converged step's local error far below 0.1 rad on
/// any step that converges to the motion, while an aliased root is off by an O(1) turn.
const ALIASED_DISTANCE: f64 = 0.5;

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
    /// Adaptive runs: solves whose error estimate was above the tolerance, redone with
    /// more nodes (their Newton iterations are counted above too).
    pub rejected_steps: usize,
}

/// A step's Galerkin curve: `g(t) = g_k Φ(ξ(t))`, `t ∈ [0, h]` from the step's start.
#[derive(Debug, Clone)]
pub struct GalerkinCurve<G: ConfigurationGroup<D> = Rotations, C = ChartKind, const D: usize = 3> {
    base: G::Element<f64>,
    nodes: Vec<SVector<f64, D>>,
    basis: lgsvi_spectral::Barycentric,
    chart: C,
    start: f64,
    group: PhantomData<G>,
}

impl<G: ConfigurationGroup<D>, C: GroupChart<G, D>, const D: usize> GalerkinCurve<G, C, D> {
    /// The step's start time.
    pub fn start(&self) -> f64 {
        self.start
    }

    /// The step length `h`.
    pub fn step(&self) -> f64 {
        *self.basis.nodes().last().unwrap_or(&0.0)
    }

    /// `(g(t), ξ(t))` at `t` seconds after the step's start, `0 ≤ t ≤ h` (up to a
    /// rounding slack of `1e-12 h` at either end).
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for a `t` outside the step (the polynomial
    /// describes the motion within its step only) or not finite.
    pub fn at(&self, t: f64) -> Result<(G::Element<f64>, SVector<f64, D>), MechanicsError> {
        let h = self.step();
        let slack = 1e-12 * h;
        if !(t >= -slack && t <= h + slack) {
            return Err(MechanicsError::InvalidSetting {
                name: "t",
                value: format!("{t:?}"),
                reason: "outside the step [0, h] the Galerkin curve is an extrapolation, not the \
                         motion: take the curve of the step that contains the time",
            });
        }
        let t = t.clamp(0.0, h);
        let n = self.nodes.len();
        let mut phi = vec![0.0; n];
        let mut dphi = vec![0.0; n];
        self.basis
            .basis_and_derivatives_into(t, &mut phi, &mut dphi)?;
        let mut xi = SVector::<f64, D>::zeros();
        let mut xi_dot = SVector::<f64, D>::zeros();
        for i in 0..n {
            xi += self.nodes[i] * phi[i];
            xi_dot += self.nodes[i] * dphi[i];
        }
        let g = self.base.compose(&self.chart.to_group(&xi));
        Ok((g, self.chart.left_differential(&xi) * xi_dot))
    }

    /// The chart coordinates `ξ¹ = 0, ξ², …, ξⁿ` of the nodes.
    pub fn nodes(&self) -> &[SVector<f64, D>] {
        &self.nodes
    }
}

/// A recorded trajectory (every `every`-th step, always the first and the last).
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory<E = SO3, const D: usize = 3> {
    /// States, in time order.
    pub states: Vec<State<E, D>>,
    /// Newton iterations of the step that produced each state (0 for the initial one).
    pub newton_iterations: Vec<usize>,
}

impl<E, const D: usize> Default for Trajectory<E, D> {
    fn default() -> Self {
        Self {
            states: Vec::new(),
            newton_iterations: Vec::new(),
        }
    }
}

/// After a step had to be solved again with more nodes, the nodes stay up for this many
/// steps before they may fall, twice as long after each fall that failed (up to
/// [`NODES_HOLD_MAX`]): where the error varies along the motion (the heavy top), lowering
/// them at once had every sixth step solved twice (measured, case B, h = 0.5, 6e-13 per
/// unit time: 321 of 2000 steps).
const NODES_HOLD: usize = 8;
const NODES_HOLD_MAX: usize = 1024;

/// The most times one step is halved when step changes are allowed.
const MAX_HALVINGS: usize = 30;

/// Adds `term` to `sum` with Kahan's compensation, `carry` holding what the last additions
/// lost: long runs add millions of terms (the work of the forces, the error estimates).
fn compensated_add(sum: &mut f64, carry: &mut f64, term: f64) {
    let term = term - *carry;
    let total = *sum + term;
    *carry = (total - *sum) - term;
    *sum = total;
}

/// A horizon `t_end` must be finite and non-negative.
fn check_horizon(t_end: f64) -> Result<(), MechanicsError> {
    if !(t_end.is_finite() && t_end >= 0.0) {
        return Err(MechanicsError::InvalidSetting {
            name: "t-end",
            value: t_end.to_string(),
            reason: "must be finite and non-negative",
        });
    }
    Ok(())
}

/// `n` zeros in a vector that can hold `capacity`.
fn with_length<const D: usize>(n: usize, capacity: usize) -> Vec<SVector<f64, D>> {
    let mut v = Vec::with_capacity(capacity);
    v.resize(n, SVector::zeros());
    v
}

/// The Lie group spectral variational integrator, for a system `S` on a group with
/// algebra `ℝ^D` in the chart `C`.
///
/// - `Integrator::new(system, settings, g₀, ξ₀)` takes the chart from the settings
///   ([`ChartKind`], chosen at run time); [`Integrator::with_chart`] takes a chart type
///   (`ExpChart`, `CayleyChart`, or your own), fixed at compile time.
/// - Driven from a control loop: [`Integrator::set_input`] (a piecewise-constant
///   generalised force for the next steps), [`Integrator::step`], [`Integrator::state`],
///   [`Integrator::reset`], [`Integrator::system_mut`] (change parameters between steps).
///   Nothing is rebuilt, and a step allocates nothing.
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
pub struct Integrator<S: GroupLagrangian<D>, C = ChartKind, const D: usize = 3> {
    system: S,
    chart: C,
    settings: StepSettings,
    discretisation: Arc<Discretisation>,
    work: WorkspaceOf<S, D>,
    state: State<ElementOf<S, D>, D>,
    /// Steps since the start (or the last reset).
    step_index: usize,
    /// The time of the start (or the last reset).
    origin: f64,
    /// The piecewise-constant generalised force added to the system's own.
    input: SVector<f64, D>,
    /// The velocity at the start of the last step taken; `None` before the first step
    /// (then there is no previous Galerkin curve either).
    previous_velocity: Option<SVector<f64, D>>,
    last_nodes: Vec<SVector<f64, D>>,
    /// Scratch for the predictor's comparison.
    extrapolated: Vec<SVector<f64, D>>,
    last_base: ElementOf<S, D>,
    /// The flow predictor's configuration at the end of the step being taken, relative to
    /// its start, when the flow could be integrated: the check against aliased roots.
    flow_end: Option<ElementOf<S, D>>,
    /// Whether the continued curve beat the flow in the chart at its last try.
    continued_wins: bool,
    statistics: Statistics,
    /// The work of the forces since the start (or the last reset), summed with Kahan's
    /// compensation (`work_carry`): a long forced run adds millions of terms.
    work_done: f64,
    work_carry: f64,
    /// The last step's estimated local error ([`Integrator::error_estimate`]).
    estimate: f64,
    /// The sum of the local estimates since the start (or the last reset), compensated.
    estimate_sum: f64,
    estimate_carry: f64,
    /// Steps taken with `n` nodes, at index `n` (length `MAX_NODES + 1`).
    nodes_used: Vec<usize>,
    /// Adaptive runs: the nodes the next step starts with, when they change.
    next_nodes: Option<usize>,
    /// Adaptive runs: steps left before the nodes may fall again after a step needed more,
    /// the current length of that wait, and whether the step being taken lowered them.
    hold_nodes: usize,
    hold_length: usize,
    lowered: bool,
    /// Adaptive runs: the last step's estimate, for the trend.
    previous_estimate: f64,
    /// Step changes: the step index at which `origin` was last set (times are counted
    /// from there in steps of the present `h`), the step the run started with (the
    /// largest it returns to), and the step the next step takes when it changes.
    origin_steps: usize,
    largest_step: f64,
    next_step: Option<f64>,
    /// Adaptive runs: the workspaces of the node counts not in use, kept for reuse.
    spare_work: Vec<WorkspaceOf<S, D>>,
    /// Adaptive runs: scratch for moving the last curve to other nodes.
    resampled: Vec<SVector<f64, D>>,
    basis_values: Vec<f64>,
}

impl<S: GroupLagrangian<D>, const D: usize> Integrator<S, ChartKind, D>
where
    ChartKind: GroupChart<S::Group, D>,
{
    /// Starts at configuration `g₀` with body velocity `ξ₀` (`μ₀ = ∂ℓ/∂ξ(0, g₀, ξ₀)`), in
    /// the chart the settings name.
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`] for a non-finite `ξ₀` or `g₀`;
    /// [`MechanicsError::NotOnGroup`] for a `g₀` off the group (an attitude that is not a
    /// rotation to `‖RᵀR − I‖_F ≤ 1e-9`, or a reflection); errors of the
    /// quadrature or basis construction (not expected for valid settings).
    pub fn new(
        system: S,
        settings: StepSettings,
        configuration: ElementOf<S, D>,
        velocity: SVector<f64, D>,
    ) -> Result<Self, MechanicsError> {
        Self::with_chart(system, settings.chart(), settings, configuration, velocity)
    }
}

impl<S: GroupLagrangian<D>, C: GroupChart<S::Group, D>, const D: usize> Integrator<S, C, D> {
    /// As [`Integrator::new`] in the chart `chart` (whatever `settings.chart()` says).
    ///
    /// ```
    /// use lgsvi_mechanics::{FreeBody, Inertia, Integrator, StepSettings};
    /// use lgsvi_mechanics::lie::{CayleyChart, SE3};
    /// use nalgebra::SVector;
    /// // A free rigid body drifting through space, in the Cayley chart of SE(3).
    /// let body = FreeBody::new(Inertia::from_principal_moments([1.0, 2.0, 2.5])?, 3.0)?;
    /// let xi = SVector::<f64, 6>::new(0.3, -0.2, 1.0, 0.5, 0.0, 0.0);
    /// let mut integrator = Integrator::with_chart(body, CayleyChart, StepSettings::new(0.2, 6)?, SE3::identity(), xi)?;
    /// integrator.run(10, 1)?;
    /// let e = integrator.state();
    /// // The centre of mass moves in a straight line at its initial velocity.
    /// assert!((e.position() - nalgebra::Vector3::new(1.0, 0.0, 0.0)).amax() < 1e-14);
    /// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
    /// ```
    ///
    /// # Errors
    /// As [`Integrator::new`].
    pub fn with_chart(
        system: S,
        chart: C,
        settings: StepSettings,
        configuration: ElementOf<S, D>,
        velocity: SVector<f64, D>,
    ) -> Result<Self, MechanicsError> {
        check_finite(
            <S::Group as ConfigurationGroup<D>>::INITIAL_VELOCITY,
            velocity.as_slice(),
        )?;
        if !<S::Group as ConfigurationGroup<D>>::is_finite(&configuration) {
            return Err(MechanicsError::NonFinite {
                what: "initial configuration",
                value: format!("{configuration:?}"),
            });
        }
        <S::Group as ConfigurationGroup<D>>::check_on_group(&configuration).map_err(|source| {
            MechanicsError::NotOnGroup {
                what: "initial configuration",
                source,
            }
        })?;
        let discretisation = Discretisation::shared(&settings)?;
        let work = Workspace::new(&discretisation);
        let momentum = body_momentum(&system, 0.0, &configuration, &velocity);
        let n = settings.nodes();
        // An adaptive run's buffers take its largest node count at once, so that a change
        // of nodes reallocates nothing.
        let capacity = settings.adaptive().map_or(n, |a| a.max_nodes.max(n));
        Ok(Self {
            system,
            chart,
            settings,
            discretisation,
            work,
            state: State {
                time: 0.0,
                configuration,
                momentum,
                velocity,
            },
            step_index: 0,
            origin: 0.0,
            input: SVector::zeros(),
            previous_velocity: None,
            last_nodes: with_length(n, capacity),
            extrapolated: with_length(n, capacity),
            last_base: configuration,
            flow_end: None,
            continued_wins: false,
            statistics: Statistics::default(),
            work_done: 0.0,
            work_carry: 0.0,
            estimate: 0.0,
            estimate_sum: 0.0,
            estimate_carry: 0.0,
            nodes_used: vec![0; MAX_NODES + 1],
            next_nodes: None,
            hold_nodes: 0,
            hold_length: NODES_HOLD,
            lowered: false,
            previous_estimate: 0.0,
            origin_steps: 0,
            largest_step: settings.step(),
            next_step: None,
            spare_work: Vec::with_capacity(capacity),
            resampled: Vec::with_capacity(capacity),
            basis_values: Vec::with_capacity(capacity),
        })
    }

    /// Sets the nodes of the following steps to `n` (a fixed run keeps them; an adaptive
    /// run starts its next step there and adapts from it). The tables for `n` are built
    /// once per process and shared; a node count used before allocates nothing.
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for `n` outside `2…MAX_NODES`, or outside an
    /// adaptive run's node range.
    pub fn set_nodes(&mut self, n: usize) -> Result<(), MechanicsError> {
        let (least, most) = self
            .settings
            .adaptive()
            .map_or((2, MAX_NODES), |a| (a.min_nodes, a.max_nodes));
        if !(least..=most).contains(&n) {
            return Err(MechanicsError::InvalidSetting {
                name: "nodes",
                value: n.to_string(),
                reason: "a step takes 2 to MAX_NODES nodes, and an adaptive run's within its \
                         node range",
            });
        }
        self.next_nodes = None;
        self.switch_nodes(n)
    }

    /// The current state.
    pub fn state(&self) -> &State<ElementOf<S, D>, D> {
        &self.state
    }

    /// The system.
    pub fn system(&self) -> &S {
        &self.system
    }

    /// The system, to change its parameters between steps (a new inertia, gain or
    /// target). The next step uses them; the state is kept as it is (its momentum is
    /// the old system's).
    pub fn system_mut(&mut self) -> &mut S {
        &mut self.system
    }

    /// The chart.
    pub fn chart(&self) -> &C {
        &self.chart
    }

    /// The settings.
    pub fn settings(&self) -> &StepSettings {
        &self.settings
    }

    /// Newton statistics so far.
    pub fn statistics(&self) -> &Statistics {
        &self.statistics
    }

    /// The work `W = ∫ ⟨F, ξ⟩ dt` done by the forces (the system's and the control
    /// input) since the start or the last [`Integrator::reset`], each step's integral
    /// taken by the step's own quadrature along its Galerkin curve: the discrete work of
    /// the Lagrange–d'Alembert step, so that `E(t) − E(0) = W(t)` holds to the method's
    /// accuracy (the energy balance). Zero for an unforced run.
    pub fn work_done(&self) -> f64 {
        self.work_done
    }

    /// The work of the forces over the step just solved (nodes in `work.xi`, from `base`
    /// at the step's start `time`), by the step's quadrature.
    fn step_work(&self, base: &ElementOf<S, D>, time: f64, input: &SVector<f64, D>) -> f64 {
        let d = &self.discretisation;
        let mut total = 0.0;
        for j in 0..d.m {
            let (values, slopes) = (d.values_at(j), d.slopes_at(j));
            let mut x = SVector::<f64, D>::zeros();
            let mut v = SVector::<f64, D>::zeros();
            for i in 1..d.n {
                x += self.work.xi[i] * values[i];
                v += self.work.xi[i] * slopes[i];
            }
            let velocity = self.chart.left_differential(&x) * v;
            let mut force = *input;
            if self.system.is_forced() {
                // Φ(x) only where the force reads the configuration.
                let g = if self.system.force_depends_on_configuration() {
                    base.compose(&self.chart.to_group(&x))
                } else {
                    *base
                };
                force += self.system.force(time + d.times[j], &g, &velocity);
            }
            total += d.weights[j] * force.dot(&velocity);
        }
        total
    }

    /// Sets the control input: a generalised force (for SO(3) a body torque; for SE(3)
    /// `(body torque, body force)`) held constant over the following steps until set
    /// again (zero-order hold), added to the system's own force through the discrete
    /// Lagrange–d'Alembert principle. Zero (the start) leaves the step unforced.
    ///
    /// ```
    /// use lgsvi_mechanics::{Inertia, Integrator, RigidBody, StepSettings};
    /// use lgsvi_lie::SO3;
    /// use nalgebra::Vector3;
    /// // A PD loop holding a body's spin at 1 rad/s about z against an initial wobble.
    /// let body = RigidBody::new(Inertia::from_principal_moments([2.0, 2.0, 3.0])?);
    /// let mut integrator = Integrator::new(body, StepSettings::new(0.1, 6)?, SO3::identity(), Vector3::new(0.2, 0.0, 0.5))?;
    /// for _ in 0..200 {
    ///     let w = integrator.state().velocity;
    ///     integrator.set_input((Vector3::new(0.0, 0.0, 1.0) - w) * 2.0)?;
    ///     integrator.step()?;
    /// }
    /// assert!((integrator.state().velocity - Vector3::new(0.0, 0.0, 1.0)).amax() < 1e-6);
    /// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
    /// ```
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`] for a non-finite input (the input is then unchanged).
    pub fn set_input(&mut self, input: SVector<f64, D>) -> Result<(), MechanicsError> {
        check_finite("control input", input.as_slice())?;
        self.input = input;
        Ok(())
    }

    /// The control input in force.
    pub fn input(&self) -> &SVector<f64, D> {
        &self.input
    }

    /// Restarts from `(t, g, ξ)`: the state is replaced (momentum from the Legendre
    /// transform), the predictor forgets the last step, and steps are counted from `t`.
    /// The tables, the workspace, the input and the statistics are kept.
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`] for a non-finite time, configuration or velocity,
    /// [`MechanicsError::NotOnGroup`] for a configuration off the group (the integrator
    /// is then unchanged).
    pub fn reset(
        &mut self,
        time: f64,
        configuration: ElementOf<S, D>,
        velocity: SVector<f64, D>,
    ) -> Result<(), MechanicsError> {
        check_finite("reset time", &[time])?;
        check_finite("reset velocity", velocity.as_slice())?;
        if !<S::Group as ConfigurationGroup<D>>::is_finite(&configuration) {
            return Err(MechanicsError::NonFinite {
                what: "reset configuration",
                value: format!("{configuration:?}"),
            });
        }
        <S::Group as ConfigurationGroup<D>>::check_on_group(&configuration).map_err(|source| {
            MechanicsError::NotOnGroup {
                what: "reset configuration",
                source,
            }
        })?;
        let momentum = body_momentum(&self.system, time, &configuration, &velocity);
        self.state = State {
            time,
            configuration,
            momentum,
            velocity,
        };
        self.origin = time;
        self.step_index = 0;
        self.origin_steps = 0;
        self.work_done = 0.0;
        self.work_carry = 0.0;
        self.estimate = 0.0;
        self.estimate_sum = 0.0;
        self.estimate_carry = 0.0;
        self.previous_velocity = None;
        self.last_base = configuration;
        self.flow_end = None;
        self.continued_wins = false;
        Ok(())
    }

    /// The Galerkin curve of the last step taken (dense output), if any.
    pub fn last_curve(&self) -> Option<GalerkinCurve<S::Group, C, D>> {
        self.previous_velocity.is_some().then(|| GalerkinCurve {
            base: self.last_base,
            nodes: self.last_nodes.clone(),
            basis: self.discretisation.basis.clone(),
            chart: self.chart,
            start: self.state.time - self.settings.step(),
            group: PhantomData,
        })
    }

    /// The last step's estimated local error, from the decay of the Chebyshev coefficients
    /// of its chart curve (0 before the first step): about the error of the step's end
    /// configuration and velocity (max norm, in the chart's coordinates: radians and
    /// radians per unit time on SO(3); SE(3) adds the units of the position). Calibrated on
    /// the free body and the heavy top: near the true local error on average, between 25×
    /// below and 30× above it on the steps measured (`docs/tolerance.md` §2), and never
    /// below the rounding of one step, [`crate::ROUNDING_FLOOR`] (`4ε`). Costs `4nD`
    /// multiplications per step.
    pub fn error_estimate(&self) -> f64 {
        self.estimate
    }

    /// The sum of the steps' local error estimates since the start (or the last reset):
    /// an estimate of the global error where local errors accumulate linearly (the
    /// reference cases: `docs/tolerance.md` says how well it predicted).
    pub fn estimated_global_error(&self) -> f64 {
        self.estimate_sum
    }

    /// How many steps took `n` nodes, at index `n` (adaptive runs change `n` per step;
    /// a fixed run has all its steps at one index).
    pub fn nodes_histogram(&self) -> &[usize] {
        &self.nodes_used
    }

    /// The node counts used so far with their steps, `(n, steps)` by increasing `n`: the
    /// non-zero entries of [`Integrator::nodes_histogram`].
    pub fn nodes_used(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.nodes_used
            .iter()
            .enumerate()
            .filter(|(_, &count)| count > 0)
            .map(|(n, &count)| (n, count))
    }

    /// Whether the next step is forced: the system has a force or the input is not zero.
    fn forcing(&self) -> Option<SVector<f64, D>> {
        (self.system.is_forced() || self.input.iter().any(|&u| u != 0.0)).then_some(self.input)
    }

    /// The predictor. When the system has a flow predictor (the SO(3) systems with `Ω(μ)`
    /// in closed form, under their forces and the control input): the system's own flow
    /// over the step
    /// ([`GroupLagrangian::flow_guess`]; measured relative residual 3e-6 at `h = 0.5`
    /// and 2e-5 at `h = 1` on the paper's rigid body, against 3e-4 and 0.1 for the
    /// continued curve). Otherwise, after the first step: the last step's Galerkin curve
    /// continued ([`Integrator::extrapolate`]); if its relative residual exceeds
    /// [`PREDICTOR_GOOD_ENOUGH`] (long steps), the better of it and the previous step's
    /// chart coordinates corrected by the change of velocity,
    /// `ξⁱ ← ξⁱ_prev + A(0)⁻¹ t_i (ξ_k − ξ_{k−1})` (second order in `h`). On the first
    /// step, or with `constant_velocity`, `ξⁱ = Φ⁻¹(exp(t_i ξ_k))`: first order, but robust
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
            let mut guess = self.predict_by_flow(false);
            if guess == FlowGuess::Unavailable
                && (!self.system.is_left_invariant() || self.forcing().is_some())
            {
                // Without a flow of its own, where forces act (a potential or a force): the
                // flow in the chart (measured on the orbiting body O1, h = 2, n = 8: 3.0
                // iterations and 1.0 Newton matrices per step against 4.0 and 2.0 for the
                // continued curve), unless the continued curve is already as good (a
                // uniformly accelerated body, where it is exact): it is tried first while
                // it wins, and every PROBE_CONTINUED steps while it does not. A free body
                // keeps the continued curve (2.0 iterations per step against the flow's
                // 3.0 at h = 0.5).
                if self.previous_velocity.is_some()
                    && (self.continued_wins || self.step_index.is_multiple_of(PROBE_CONTINUED))
                    && self.extrapolate()
                {
                    if self.predictor_residual() <= CONTINUED_BEATS_FLOW {
                        self.continued_wins = true;
                        return Ok(false);
                    }
                    self.continued_wins = false;
                }
                guess = self.predict_by_flow(true);
            }
            match guess {
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
                    let rotation =
                        <S::Group as ConfigurationGroup<D>>::angular_speed(&self.state.velocity)
                            * h;
                    let limit = self.chart.max_rotation_angle();
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
        MechanicsError::StepTooLong {
            step: self.step_index,
            time: self.state.time,
            chart: self.chart.name(),
            rotation,
            limit: self.chart.max_rotation_angle(),
            suggested,
            advice: self.chart.advice(),
        }
    }

    /// The error for a converged step `distance` rad away from the flow's end attitude.
    fn aliased_root(&self, distance: f64) -> MechanicsError {
        MechanicsError::AliasedRoot {
            step: self.step_index,
            time: self.state.time,
            chart: self.chart.name(),
            distance,
            advice: self.chart.advice(),
        }
    }

    /// The system's own flow over the step, when it has one (or, `in_chart`, the
    /// Euler–Poincaré flow in the step's chart, [`crate::flow::chart_flow`]), under the
    /// step's total force (the system's and the control input).
    fn predict_by_flow(&mut self, in_chart: bool) -> FlowGuess<ElementOf<S, D>> {
        self.work.guess_changed();
        let system = &self.system;
        let input = self.input;
        // The force the Gauss points see (the system's and the input), along the step.
        let at = |time: f64| StepForce {
            system,
            time,
            input: &input,
        };
        let total_force = |t: f64, g: &ElementOf<S, D>, xi: &SVector<f64, D>| at(t).jet(g, xi);
        let start = FlowStart {
            time: self.state.time,
            base: &self.state.configuration,
            momentum: &self.state.momentum,
            velocity: &self.state.velocity,
            h: self.settings.step(),
            times: self.discretisation.node_times(),
            force: self
                .forcing()
                .map(|_| &total_force as ForceAlongStep<'_, S::Group, D>),
            force_reads_configuration: at(self.state.time).depends_on_configuration(),
        };
        let done = if in_chart {
            crate::flow::chart_flow(system, &self.chart, &start, &mut self.work.xi)
        } else {
            system.flow_guess(&self.chart, &start, &mut self.work.xi)
        };
        self.work.xi[0] = SVector::zeros();
        done
    }

    /// The velocity-corrected (or, with `constant_velocity`, constant-velocity) predictor.
    fn predict_from_velocity(&mut self, constant_velocity: bool) {
        self.work.guess_changed();
        let chart = self.chart;
        let a0_inv = chart
            .left_differential_inverse(&SVector::zeros())
            .unwrap_or_else(|_| SMatrix::identity());
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
                    let moved = <S::Group as ConfigurationGroup<D>>::exp(&(omega * *t));
                    self.work.xi[i] = chart.to_algebra_near(&moved, &linear).unwrap_or(linear);
                }
            }
        }
        self.work.xi[0] = SVector::zeros();
    }

    /// The previous step's Galerkin curve continued over the next step, in the new
    /// step's chart: `ξⁱ = Φ⁻¹(Φ(ξⁿ_prev)⁻¹ Φ(ξ_prev(h + t_i)))`. False where a node
    /// leaves `Φ⁻¹`'s domain (the guess is then partly written: the caller replaces it).
    fn extrapolate(&mut self) -> bool {
        let chart = self.chart;
        let n = self.discretisation.n;
        self.work.xi[0] = SVector::zeros();
        let end = chart.to_group(&self.last_nodes[n - 1]).inverse();
        for i in 1..n {
            let row = &self.discretisation.extrapolation[i * n..(i + 1) * n];
            let continued = row
                .iter()
                .zip(&self.last_nodes)
                .fold(SVector::<f64, D>::zeros(), |acc, (e, xi)| acc + xi * *e);
            // Each node on the branch of the one before (ξ¹ = 0): the continued curve may
            // rotate past a half turn relative to the step's start.
            let near = self.work.xi[i - 1];
            match chart.to_algebra_near(&end.compose(&chart.to_group(&continued)), &near) {
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
    /// reach ([`GroupChart::max_rotation_angle`]) within the step, and
    /// [`MechanicsError::AliasedRoot`] where Newton converged to an attitude that is not
    /// the continuation of the motion (checked against the system's own flow, when it
    /// has one). The state is left unchanged. Where a step fails (any of these) because `ℓ` is not strictly convex in the velocity at the state (a zero or
    /// negative inertia or mass, after [`Integrator::system_mut`] for instance), the error
    /// is [`MechanicsError::DegenerateLagrangian`] instead, which no step or node count
    /// mends.
    pub fn step(&mut self) -> Result<usize, MechanicsError> {
        self.advance().map_err(|error| self.diagnose(error))
    }

    /// The cause of a failed solve, when it is the system's: `∂²ℓ/∂ξ²` at the state not
    /// positive definite (its eigenvalues are read only on this error path).
    fn diagnose(&self, error: MechanicsError) -> MechanicsError {
        if !matches!(
            error,
            MechanicsError::NewtonDiverged { .. }
                | MechanicsError::SingularJacobian { .. }
                | MechanicsError::InverseLegendre { .. }
                | MechanicsError::OutsideChart { .. }
                | MechanicsError::StepTooLong { .. }
                | MechanicsError::AliasedRoot { .. }
                | MechanicsError::NonFiniteStep { .. }
                | MechanicsError::ToleranceNotMet { .. }
        ) {
            return error;
        }
        let state = &self.state;
        let (_, hessian) = crate::state::legendre_blocks(
            &self.system,
            state.time,
            &state.configuration,
            &state.velocity,
        );
        let symmetric = (hessian + hessian.transpose()) * 0.5;
        if symmetric.iter().any(|x| !x.is_finite()) {
            return error;
        }
        // Dynamic storage: the fixed-size eigen decomposition needs bounds a const `D` lacks.
        let eigenvalues = nalgebra::DMatrix::from_iterator(D, D, symmetric.iter().copied())
            .symmetric_eigenvalues();
        let (least, most) = eigenvalues
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(l, m), &e| {
                (l.min(e), m.max(e.abs()))
            });
        if least > f64::EPSILON * D as f64 * most {
            return error;
        }
        MechanicsError::DegenerateLagrangian {
            step: self.step_index,
            time: state.time,
            least,
            most,
        }
    }

    fn advance(&mut self) -> Result<usize, MechanicsError> {
        let Some(adaptive) = self.settings.adaptive() else {
            let base = self.state.configuration;
            let outcome = self.attempt(&base)?;
            let (estimate, _) = self.discretisation.error_estimate(&self.work.xi);
            return self.commit(&base, outcome, estimate.max(ROUNDING_FLOOR));
        };
        if let Some(h) = self.next_step.take() {
            self.switch_step(h)?;
        }
        if let Some(n) = self.next_nodes.take() {
            self.switch_nodes(n)?;
        }
        let base = self.state.configuration;
        let mut halvings = 0;
        loop {
            let budget = adaptive.rate * self.settings.step();
            let outcome = match self.attempt(&base) {
                Ok(outcome) => outcome,
                // A step the chart cannot follow, or that Newton cannot solve, is tried
                // again at half the step when the step may change.
                Err(_) if adaptive.step_changes && halvings < MAX_HALVINGS => {
                    halvings += 1;
                    self.statistics.rejected_steps += 1;
                    self.switch_step(0.5 * self.settings.step())?;
                    continue;
                }
                Err(error) => return Err(error),
            };
            // Whether the step meets its share reads the estimate floored at the rounding
            // of a step (no nodes make it smaller); the choice of the next nodes and step
            // reads the spectral estimate itself.
            let (estimate, decay) = self.discretisation.error_estimate(&self.work.xi);
            let floored = estimate.max(ROUNDING_FLOOR);
            let n = self.discretisation.n;
            if floored > budget && n < adaptive.max_nodes {
                // A step that lowered its nodes and failed doubles the wait before the
                // next try (where the error varies along the motion, a fall that fails
                // once tends to fail again soon).
                self.hold_length = if self.lowered {
                    (2 * self.hold_length).min(NODES_HOLD_MAX)
                } else {
                    NODES_HOLD
                };
                self.hold_nodes = self.hold_length;
                self.lowered = false;
                // The estimate falls by about q² per node: add the nodes that bring it
                // under the budget (at least one, at most four at a time).
                let wanted = if decay < 1.0 && decay > 0.0 {
                    ((budget / estimate).ln() / (decay * decay).ln()).ceil()
                } else {
                    2.0
                };
                let more = (wanted as usize).clamp(1, 4);
                self.count_redone(&outcome);
                self.switch_nodes((n + more).min(adaptive.max_nodes))?;
                continue;
            }
            if floored > budget && adaptive.step_changes && halvings < MAX_HALVINGS {
                // The most nodes allowed do not reach the tolerance: half the step.
                halvings += 1;
                self.count_redone(&outcome);
                self.switch_step(0.5 * self.settings.step())?;
                continue;
            }
            if floored > budget {
                // Every remedy spent: accepting the step would miss the tolerance quietly.
                let (halved, advice) = if adaptive.step_changes {
                    (
                        format!(
                            ", after halving the step {halvings} times to {:e}",
                            self.settings.step()
                        ),
                        "the tolerance is below what this motion allows in double precision: \
                         raise it",
                    )
                } else {
                    (
                        String::new(),
                        "raise the tolerance, allow more nodes, shorten the step h, or let the \
                         step change",
                    )
                };
                return Err(MechanicsError::ToleranceNotMet {
                    step: self.step_index,
                    time: self.state.time,
                    estimate: floored,
                    budget,
                    nodes: n,
                    halved,
                    advice,
                });
            }
            let iterations = self.commit(&base, outcome, floored)?;
            if std::mem::take(&mut self.lowered) {
                // The fall held: the next wait starts short again.
                self.hold_length = NODES_HOLD;
            }
            // The next step's estimate, extrapolated from this one and the one before when
            // the error grows along the motion: where it would exceed the budget, the next
            // step takes one node more now rather than being solved twice.
            let growth = if self.previous_estimate > 0.0 && estimate > 1.5 * self.previous_estimate
            {
                (estimate / self.previous_estimate).min(1e3)
            } else {
                1.0
            };
            self.previous_estimate = estimate;
            let expected = estimate * growth;
            self.hold_nodes = self.hold_nodes.saturating_sub(1);
            if expected > budget && n < adaptive.max_nodes {
                self.next_nodes = Some(n + 1);
            } else if adaptive.falling_nodes
                && self.hold_nodes == 0
                && n > adaptive.min_nodes
                && decay > 0.0
                && decay < 1.0
                && expected > 0.0
            {
                // Each node fewer multiplies the estimate by about 1/q²: the next step
                // takes as few as keep it under half the budget (the margin keeps n from
                // going back and forth between neighbours).
                let fewer = ((0.5 * budget / expected).ln() / (decay * decay).recip().ln())
                    .floor()
                    .max(0.0) as usize;
                let next = n.saturating_sub(fewer.min(4)).max(adaptive.min_nodes);
                if next < n {
                    self.next_nodes = Some(next);
                    self.lowered = true;
                }
            }
            // With room below the budget, the step may grow back: doubling it multiplies
            // the local error by about 2^(2n−1) (order 2(n−1)) and the budget by 2; it
            // doubles where that stays under half the new budget.
            let h = self.settings.step();
            if adaptive.step_changes
                && self.next_nodes.is_none_or(|next| next <= n)
                && h < self.largest_step
                && expected * 2f64.powi(2 * n as i32 - 1) < budget
            {
                self.next_step = Some((2.0 * h).min(self.largest_step));
            }
            return Ok(iterations);
        }
    }

    /// The exact linearisation of the step from the current state with the current input
    /// ([`StepLinearization`]: `A = ∂x₊/∂x`, `B = ∂x₊/∂u`), without taking the step: the
    /// state, the step count and the statistics are unchanged. An adaptive run
    /// linearises the step at its present nodes and step.
    ///
    /// ```
    /// use lgsvi_mechanics::{Coordinates, Inertia, Integrator, RigidBody, StepSettings};
    /// use lgsvi_mechanics::lie::SO3;
    /// use nalgebra::Vector3;
    /// // A body at rest: the step is the exact zero-order hold of θ̈ = J⁻¹u.
    /// let body = RigidBody::new(Inertia::from_principal_moments([1.0, 2.0, 2.5])?);
    /// let h = 0.1;
    /// let mut integrator = Integrator::new(body, StepSettings::new(h, 4)?, SO3::identity(), Vector3::zeros())?;
    /// let step = integrator.linearize()?;
    /// let (a, b) = (step.a(Coordinates::Velocity), step.b(Coordinates::Velocity));
    /// assert!((a[(2, 5)] - h).abs() < 1e-15); // θ₊ = θ + hω + …
    /// assert!((b[(5, 2)] - h / 2.5).abs() < 1e-15); // ω₊ = ω + hJ⁻¹u
    /// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
    /// ```
    ///
    /// # Errors
    /// Those of [`Integrator::step`]; [`MechanicsError::InvalidSetting`] under the
    /// paper's matching (not variational: no linearisation is offered).
    pub fn linearize(&mut self) -> Result<StepLinearization<ElementOf<S, D>, D>, MechanicsError> {
        let start = self.state;
        let outcome = self.attempt(&start.configuration)?;
        let end = self.end_state(&outcome)?;
        self.linearization(start, end)
    }

    /// Takes one step (as [`Integrator::step`]) and returns its exact linearisation
    /// ([`StepLinearization`]), at the cost of one more Newton matrix and its
    /// factorisation, and a few back-substitutions.
    ///
    /// # Errors
    /// As [`Integrator::linearize`]; if only the linearisation fails, the step has been
    /// taken.
    pub fn step_linearized(
        &mut self,
    ) -> Result<StepLinearization<ElementOf<S, D>, D>, MechanicsError> {
        let start = self.state;
        self.step()?;
        let end = self.state;
        self.linearization(start, end)
    }

    /// The linearisation of the step just solved (its unknowns in the workspace) from
    /// `start` to `end`.
    fn linearization(
        &mut self,
        start: State<ElementOf<S, D>, D>,
        end: State<ElementOf<S, D>, D>,
    ) -> Result<StepLinearization<ElementOf<S, D>, D>, MechanicsError> {
        let stepper = Stepper {
            system: &self.system,
            chart: &self.chart,
            settings: &self.settings,
            d: &self.discretisation,
            time: start.time,
            forcing: self.forcing(),
        };
        let index = self.step_index;
        let jacobians =
            stepper.linearize(&start.configuration, &start.momentum, &mut self.work, index)?;
        StepLinearization::new(
            &self.system,
            &jacobians,
            start,
            end,
            self.input,
            (self.settings.step(), self.discretisation.n, index),
        )
    }

    /// Counts a solve that is thrown away and redone: its Newton work stays in the
    /// statistics.
    fn count_redone(&mut self, outcome: &StepOutcome<ElementOf<S, D>, D>) {
        let stats = &mut self.statistics;
        stats.rejected_steps += 1;
        stats.newton_iterations += outcome.iterations;
        stats.factorizations += outcome.factorizations;
    }

    /// Moves the integrator to the step `h` (same nodes, so the workspace stays): times
    /// are counted from the present state, and the last step's curve, made for the old
    /// step, no longer seeds the predictor.
    fn switch_step(&mut self, h: f64) -> Result<(), MechanicsError> {
        if h == self.settings.step() {
            return Ok(());
        }
        if !(h.is_finite() && h >= crate::settings::STEP_RANGE.0) {
            return Err(MechanicsError::InvalidSetting {
                name: "h",
                value: format!("{h:?}"),
                reason: "the step fell below 1e-280 while halving: the tolerance cannot be met",
            });
        }
        let settings = self.settings.with_step_unchecked(h);
        self.discretisation = Discretisation::shared(&settings)?;
        self.settings = settings;
        self.origin = self.state.time;
        self.origin_steps = self.step_index;
        self.previous_velocity = None;
        self.previous_estimate = 0.0;
        Ok(())
    }

    /// Moves the integrator to `n` nodes (tables, workspace, and the last step's curve
    /// resampled on the new nodes for the predictor). A workspace is built the first time
    /// a node count is used and kept for later.
    fn switch_nodes(&mut self, n: usize) -> Result<(), MechanicsError> {
        if n == self.discretisation.n {
            return Ok(());
        }
        let settings = self.settings.with_nodes(n);
        let tables = Discretisation::shared(&settings)?;
        let work = match self.spare_work.iter().position(|w| w.xi.len() == n) {
            Some(i) => self.spare_work.swap_remove(i),
            None => Workspace::new(&tables),
        };
        let previous = std::mem::replace(&mut self.work, work);
        self.spare_work.push(previous);
        // The last curve on the new nodes: exact when n grows (a polynomial of lower
        // degree), its interpolant when n shrinks (used only as the predictor's start).
        // The buffers hold `max_nodes` from the integrator's construction: no allocation.
        self.resampled.clear();
        self.basis_values.resize(self.discretisation.n, 0.0);
        for &t in tables.node_times() {
            self.discretisation
                .basis
                .basis_into(t, &mut self.basis_values)?;
            let value = self
                .basis_values
                .iter()
                .zip(&self.last_nodes)
                .fold(SVector::zeros(), |acc, (c, x)| acc + x * *c);
            self.resampled.push(value);
        }
        std::mem::swap(&mut self.last_nodes, &mut self.resampled);
        self.extrapolated.resize(n, SVector::zeros());
        self.discretisation = tables;
        self.settings = settings;
        Ok(())
    }

    /// Predicts and solves the step from `base` (the current state), without taking it.
    fn attempt(
        &mut self,
        base: &ElementOf<S, D>,
    ) -> Result<StepOutcome<ElementOf<S, D>, D>, MechanicsError> {
        let constant_velocity = self.predict(false)?;
        let first = self.solve(base);
        let outcome = match first {
            Ok(outcome) => outcome,
            // A poor guess (the velocity changed a lot over the last step, or the flow
            // guess led Newton astray): retry once from constant velocity before giving up.
            Err(_) if !constant_velocity => {
                self.predict(true)?;
                self.solve(base)?
            }
            Err(error) => return Err(error),
        };
        if let Some(end) = self.flow_end {
            let difference = end
                .inverse()
                .compose(&base.inverse())
                .compose(&outcome.configuration);
            let distance = <S::Group as ConfigurationGroup<D>>::rotation_angle(&difference);
            if distance.is_nan() || distance > ALIASED_DISTANCE {
                return Err(self.aliased_root(distance));
            }
        }
        Ok(outcome)
    }

    /// The state a solved step ends at: the configuration renormalised, the step's end
    /// time, the momentum and its velocity.
    ///
    /// # Errors
    /// [`MechanicsError::NonFiniteStep`] for a non-finite momentum; those of
    /// [`body_velocity`].
    fn end_state(
        &self,
        outcome: &StepOutcome<ElementOf<S, D>, D>,
    ) -> Result<State<ElementOf<S, D>, D>, MechanicsError> {
        // g_k Φ(ξⁿ) is on the group up to the rounding of the product, which would
        // accumulate over millions of steps (measured ‖RᵀR − I‖ 1e-12 after 10⁶ steps);
        // one polar Newton step R(I + ½(I − RᵀR)) squares that deviation away.
        let configuration =
            <S::Group as ConfigurationGroup<D>>::renormalise(&outcome.configuration);
        let since = self.step_index + 1 - self.origin_steps;
        let time = self.origin + since as f64 * self.settings.step();
        let velocity = body_velocity(
            &self.system,
            time,
            &outcome.configuration,
            &outcome.momentum,
            &self.state.velocity,
        )?;
        if !outcome.momentum.iter().all(|x| x.is_finite()) {
            return Err(MechanicsError::NonFiniteStep {
                step: self.step_index,
                time: self.state.time,
                what: "the momentum after the step",
                hint: if self.forcing().is_some() {
                    "the force (the system's or the input) or the Lagrangian gave a non-finite \
                     value within this step, or the inputs overflow double precision: check \
                     them at this time"
                } else {
                    "the Lagrangian or its derivatives gave a non-finite value within this \
                     step, or the inputs overflow double precision: check them at this state"
                },
            });
        }
        Ok(State {
            time,
            configuration,
            momentum: outcome.momentum,
            velocity,
        })
    }

    /// Takes the solved step: the new state, the work done, the statistics.
    fn commit(
        &mut self,
        base: &ElementOf<S, D>,
        outcome: StepOutcome<ElementOf<S, D>, D>,
        estimate: f64,
    ) -> Result<usize, MechanicsError> {
        let end = self.end_state(&outcome)?;
        if let Some(input) = self.forcing() {
            let work = self.step_work(base, self.state.time, &input);
            compensated_add(&mut self.work_done, &mut self.work_carry, work);
        }
        self.last_base = self.state.configuration;
        self.last_nodes.copy_from_slice(&self.work.xi);
        self.previous_velocity = Some(self.state.velocity);
        self.step_index += 1;
        self.state = end;
        let stats = &mut self.statistics;
        stats.steps += 1;
        stats.newton_iterations += outcome.iterations;
        stats.factorizations += outcome.factorizations;
        stats.max_newton_iterations = stats.max_newton_iterations.max(outcome.iterations);
        self.nodes_used[self.discretisation.n] += 1;
        self.estimate = estimate;
        compensated_add(&mut self.estimate_sum, &mut self.estimate_carry, estimate);
        Ok(outcome.iterations)
    }

    fn solve(
        &mut self,
        base: &ElementOf<S, D>,
    ) -> Result<StepOutcome<ElementOf<S, D>, D>, MechanicsError> {
        let (mu, step, time) = (self.state.momentum, self.step_index, self.state.time);
        let (stepper, work) = self.stepper();
        stepper.solve(base, &mu, work, step, time)
    }

    /// The relative residual of the guess in the workspace, from the current state.
    fn predictor_residual(&mut self) -> f64 {
        let (base, mu) = (self.state.configuration, self.state.momentum);
        let (stepper, work) = self.stepper();
        stepper.relative_residual(&base, &mu, work)
    }

    /// The step solver over this integrator's system and settings, beside its workspace.
    fn stepper(&mut self) -> (Stepper<'_, S, C, D>, &mut WorkspaceOf<S, D>) {
        let forcing = self.forcing();
        (
            Stepper {
                system: &self.system,
                chart: &self.chart,
                settings: &self.settings,
                d: &self.discretisation,
                time: self.state.time,
                forcing,
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
    pub fn run(
        &mut self,
        steps: usize,
        every: usize,
    ) -> Result<Trajectory<ElementOf<S, D>, D>, MechanicsError> {
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
    ) -> Result<Trajectory<ElementOf<S, D>, D>, MechanicsError> {
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

    /// The number of steps of length `h` from the current time to reach `t_end` or pass
    /// it by less than `h` ([`Integrator::run_until`] shortens the last one to land on
    /// `t_end`).
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for a non-finite or negative `t_end`, a `t_end`
    /// before the current time, more than 2⁵³ steps (beyond what the step count can hold
    /// exactly as a time), and a run whose step may change
    /// ([`StepSettings::with_step_changes`]): it has no fixed number of steps
    /// ([`Integrator::run_until`] takes it to `t_end`).
    pub fn steps_until(&self, t_end: f64) -> Result<usize, MechanicsError> {
        self.check_end(t_end)?;
        if self.settings.adaptive().is_some_and(|a| a.step_changes) {
            return Err(MechanicsError::InvalidSetting {
                name: "step changes",
                value: "on".into(),
                reason: "a run whose step may change has no fixed number of steps: use \
                         run_until, or step until state().time reaches the end",
            });
        }
        let remaining = (t_end - self.state.time).max(0.0);
        // A relative slack of 1e-9 steps keeps t_end = k·h from taking a (k+1)-th step
        // because of rounding in the division.
        let steps = (remaining / self.settings.step() - 1e-9).ceil().max(0.0);
        Self::check_step_count(t_end, steps)?;
        Ok(steps as usize)
    }

    /// A horizon must be finite, non-negative and not before the current time (within a
    /// billionth of a step: the rounding of the time's sums).
    fn check_end(&self, t_end: f64) -> Result<(), MechanicsError> {
        check_horizon(t_end)?;
        if t_end < self.state.time - 1e-9 * self.settings.step() {
            return Err(MechanicsError::InvalidSetting {
                name: "t-end",
                value: format!("{t_end:?}"),
                reason: "is before the current time (state().time): the integrator steps \
                         forward only; reset it to an earlier state to go back",
            });
        }
        Ok(())
    }

    /// At most 2⁵³ steps: the time `t₀ + k h` is formed from the step count `k`.
    fn check_step_count(t_end: f64, steps: f64) -> Result<(), MechanicsError> {
        if steps > 2f64.powi(53) {
            return Err(MechanicsError::InvalidSetting {
                name: "t-end",
                value: format!("{t_end:?}"),
                reason: "needs more than 2^53 steps of h from the current time: take a \
                         longer step or a nearer end",
            });
        }
        Ok(())
    }

    /// Steps until exactly `t_end`, recording as [`Integrator::run`]: steps of `h`, then
    /// one shorter step (itself a variational step, of its own length) where `t_end` is
    /// not a whole number of steps away; `h` is kept for the steps after. A run whose
    /// step may change ([`StepSettings::with_step_changes`]) likewise shortens its last
    /// step to end on `t_end`.
    ///
    /// # Errors
    /// As [`Integrator::run`]; as [`Integrator::steps_until`] for `t_end` (a `t_end`
    /// before the current time included).
    pub fn run_until(
        &mut self,
        t_end: f64,
        every: usize,
    ) -> Result<Trajectory<ElementOf<S, D>, D>, MechanicsError> {
        if !self.settings.adaptive().is_some_and(|a| a.step_changes) {
            self.check_end(t_end)?;
            let h = self.settings.step();
            let whole = ((t_end - self.state.time).max(0.0) / h + 1e-9).floor();
            Self::check_step_count(t_end, whole)?;
            let mut trajectory = self.run(whole as usize, every)?;
            let left = t_end - self.state.time;
            if left > 1e-9 * h {
                self.switch_step(left)?;
                let last = self.step();
                self.switch_step(h)?;
                let iterations = last?;
                trajectory.states.push(self.state);
                trajectory.newton_iterations.push(iterations);
            }
            return Ok(trajectory);
        }
        self.check_end(t_end)?;
        let every = every.max(1);
        let mut trajectory = Trajectory {
            states: vec![self.state],
            newton_iterations: vec![0],
        };
        let mut k = 0;
        // Within a billionth of a step of the end counts as there (rounding of the sums).
        while t_end - self.state.time > 1e-9 * self.settings.step() {
            let left = t_end - self.state.time;
            let h = self.next_step.unwrap_or(self.settings.step());
            if h > left {
                self.next_step = Some(left);
            }
            let iterations = self.step()?;
            k += 1;
            let done = t_end - self.state.time <= 1e-9 * self.settings.step();
            if k % every == 0 || done {
                trajectory.states.push(self.state);
                trajectory.newton_iterations.push(iterations);
            }
        }
        Ok(trajectory)
    }
}
