//! The integrator: initial state, stepping, control inputs, trajectories, invariants,
//! dense output — for any configuration group and chart.
//!
//! By concern: this file holds the integrator's fields, construction, accessors, inputs
//! and reset; `parts` the state beside the motion's, by concern (the clock that counts
//! steps, the predictor's memory of the last step, the node and step controller, the
//! ledger of statistics and compensated sums); `predictor` the first guess of each step and the checks that a converged
//! step is the motion's; `advance` a step's attempt, node and step control and commit;
//! `linearize` the exact linearisation of a step; `run` the step count to a horizon
//! and the integrator's [`crate::stepper::Stepper`] implementation;
//! `curve` the statistics, dense output and trajectories a run returns.

use crate::error::{check_finite, MechanicsError};
use crate::flow::FlowGuess;
use crate::group::{ConfigurationGroup, GroupChart, Rotations, StepGroup};
use crate::linearization::StepLinearization;
use crate::settings::{StepSettings, MAX_NODES, ROUNDING_FLOOR};
use crate::state::{body_momentum, body_velocity, State};
use crate::step::assembly::{Workspace, WorkspaceOf};
use crate::step::points::StepForce;
use crate::step::tables::Discretisation;
use crate::step::{StepOutcome, StepSolver};
use crate::system::{
    ElementOf, FlowStart, ForceAlongStep, ForceValueAlongStep, PointForce, System,
};
use lgsvi_lie::{ChartKind, LieGroup, SO3};
use nalgebra::{SMatrix, SVector};
use std::marker::PhantomData;
use std::sync::Arc;

mod advance;
mod curve;
mod linearize;
mod parts;
mod predictor;
mod run;

pub use curve::{GalerkinCurve, Statistics, Trajectory};
use parts::{Clock, Controller, Ledger, Predictor};

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
/// use lgsvi_mechanics::Stepper;
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
pub struct Integrator<S: System<D>, C = ChartKind, const D: usize = 3> {
    system: S,
    chart: C,
    settings: StepSettings,
    discretisation: Arc<Discretisation>,
    work: WorkspaceOf<S, D>,
    /// Adaptive runs: the workspaces of the node counts not in use, kept for reuse.
    spare_work: Vec<WorkspaceOf<S, D>>,
    state: State<ElementOf<S, D>, D>,
    /// The piecewise-constant generalised force added to the system's own.
    input: SVector<f64, D>,
    /// The input at each Gauss point of a step (in place of `input`'s constant value),
    /// when set by [`Integrator::set_input_at_points`].
    point_inputs: Option<Vec<SVector<f64, D>>>,
    /// Whether the step being solved is to be linearised ([`Integrator::step_linearized`],
    /// [`Integrator::linearize`]): its Newton loop then asks its last assembly for
    /// Hessians, which the linearisation reuses when it got them.
    linearizing: bool,
    clock: Clock,
    predictor: Predictor<ElementOf<S, D>, D>,
    control: Controller,
    ledger: Ledger,
    /// The curve of a step of another length ([`Stepper::step_by`]) taken last: kept
    /// because returning to the settings' step forgets the predictor's curve.
    other_length_curve: Option<GalerkinCurve<S::Group, C, D>>,
}

impl<S: System<D>, const D: usize> Integrator<S, ChartKind, D>
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

impl<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> Integrator<S, C, D> {
    /// As [`Integrator::new`] in the chart `chart` (whatever `settings.chart()` says).
    ///
    /// ```
    /// use lgsvi_mechanics::Stepper;
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
            spare_work: Vec::with_capacity(capacity),
            state: State {
                time: 0.0,
                configuration,
                momentum,
                velocity,
            },
            input: SVector::zeros(),
            point_inputs: None,
            linearizing: false,
            clock: Clock::default(),
            predictor: Predictor {
                previous_velocity: None,
                last_nodes: with_length(n, capacity),
                last_base: configuration,
                flow_end: None,
                continued_wins: false,
                extrapolated: with_length(n, capacity),
                resampled: Vec::with_capacity(capacity),
                basis_values: Vec::with_capacity(capacity),
            },
            control: Controller::new(settings.h()),
            ledger: Ledger::new(MAX_NODES),
            other_length_curve: None,
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
        self.control.next_nodes = None;
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
        // A changed system has another Newton matrix: the next step forms its own.
        self.work.forget_factors();
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
        &self.ledger.statistics
    }

    /// The work `W = ∫ ⟨F, ξ⟩ dt` done by the forces (the system's and the control
    /// input) since the start or the last [`Integrator::reset`], each step's integral
    /// taken by the step's own quadrature along its Galerkin curve: the discrete work of
    /// the Lagrange–d'Alembert step, so that `E(t) − E(0) = W(t)` holds to the method's
    /// accuracy (the energy balance). Zero for an unforced run.
    pub fn work_done(&self) -> f64 {
        self.ledger.work.value()
    }

    /// The work of the forces over the step just solved (nodes in `work.xi`, from `base`
    /// at the step's start `time`), by the step's quadrature.
    fn step_work(&self, base: &ElementOf<S, D>, time: f64, input: &SVector<f64, D>) -> f64 {
        let d = &self.discretisation;
        // The Gauss points of the step's last assembly had the force and the velocity:
        // their powers give the work of the accepted curve (or, after a last chord step,
        // of a curve within rounding of it). Only a system whose own point derivatives
        // left the force's jet unasked has it evaluated again here.
        let power = &self.work.power;
        if power.len() == d.m && power.iter().all(|p| p.is_finite()) {
            return d.weights.iter().zip(power).map(|(w, p)| w * p).sum();
        }
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
            let mut force = self.point_inputs.as_ref().map_or(*input, |p| p[j]);
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
        self.point_inputs = None;
        Ok(())
    }

    /// The control input in force (with inputs at the Gauss points, their weighted
    /// mean: the constant input of the same impulse).
    pub fn input(&self) -> &SVector<f64, D> {
        &self.input
    }

    /// The Gauss points of a step as fractions of its length, `c_j ∈ (0, 1)`: where the
    /// inputs of [`Integrator::set_input_at_points`] act, and with
    /// [`Integrator::quadrature_weights`] the step's quadrature `∫ f dt ≈ h Σ_j b_j f(c_j h)`.
    pub fn quadrature_nodes(&self) -> Vec<f64> {
        let h = self.settings.h();
        self.discretisation.times.iter().map(|t| t / h).collect()
    }

    /// The weights `b_j` of the step's quadrature (summing to 1), beside
    /// [`Integrator::quadrature_nodes`].
    pub fn quadrature_weights(&self) -> Vec<f64> {
        let h = self.settings.h();
        self.discretisation.weights.iter().map(|w| w / h).collect()
    }

    /// Sets the control input at each Gauss point of the following steps (until set
    /// again, or [`Integrator::set_input`] holds a constant): an input that varies
    /// within a step, such as a polynomial given by its values at the points
    /// ([`Integrator::quadrature_nodes`]). The discrete Lagrange–d'Alembert principle
    /// sees the force only at those points, so a polynomial input of degree below the
    /// number of points acts exactly as its values there; and its linearisation
    /// ([`Integrator::step_linearized`]) then carries one input Jacobian per point
    /// ([`StepLinearization::b_points`](crate::linearization::StepLinearization::b_points)).
    ///
    /// ```
    /// use lgsvi_mechanics::{Inertia, Integrator, RigidBody, StepSettings};
    /// use lgsvi_lie::SO3;
    /// use nalgebra::Vector3;
    /// // A torque rising linearly over a step, u(t) = (0, 0, t/h), on a body at rest.
    /// let body = RigidBody::new(Inertia::from_principal_moments([2.0, 2.0, 2.0])?);
    /// let mut integrator = Integrator::new(body, StepSettings::new(0.5, 6)?, SO3::identity(), Vector3::zeros())?;
    /// let inputs: Vec<Vector3<f64>> =
    ///     integrator.quadrature_nodes().iter().map(|c| Vector3::new(0.0, 0.0, *c)).collect();
    /// integrator.set_input_at_points(&inputs)?;
    /// integrator.step()?;
    /// // The impulse ∫ u dt = h/2 about z: Ω_z = (h/2)/J = 0.125.
    /// assert!((integrator.state().velocity.z - 0.125).abs() < 1e-14);
    /// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
    /// ```
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for a number of inputs other than the number of
    /// Gauss points; [`MechanicsError::NonFinite`] for a non-finite input (the inputs are
    /// then unchanged).
    pub fn set_input_at_points(
        &mut self,
        inputs: &[SVector<f64, D>],
    ) -> Result<(), MechanicsError> {
        let m = self.discretisation.m;
        if inputs.len() != m {
            return Err(MechanicsError::InvalidSetting {
                name: "input_at_points",
                value: format!(
                    "{} inputs for {m} Gauss points ({} nodes)",
                    inputs.len(),
                    self.discretisation.n
                ),
                reason: "one input per Gauss point of the step (quadrature_nodes)",
            });
        }
        for input in inputs {
            check_finite("control input", input.as_slice())?;
        }
        let h = self.settings.h();
        self.input = inputs
            .iter()
            .zip(&self.discretisation.weights)
            .map(|(u, w)| u * (w / h))
            .sum();
        self.point_inputs = Some(inputs.to_vec());
        Ok(())
    }

    /// The inputs at the Gauss points set by [`Integrator::set_input_at_points`], if any.
    pub fn inputs_at_points(&self) -> Option<&[SVector<f64, D>]> {
        self.point_inputs.as_deref()
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
        self.clock = Clock {
            step_index: 0,
            origin: time,
            origin_steps: 0,
        };
        self.ledger.restart();
        self.other_length_curve = None;
        self.predictor.previous_velocity = None;
        self.predictor.last_base = configuration;
        self.predictor.flow_end = None;
        self.work.forget_factors();
        self.predictor.continued_wins = false;
        Ok(())
    }

    /// The Galerkin curve of the last step taken (dense output), if any: a step of the
    /// settings' length or one of another length ([`crate::Stepper::step_by`], the shortened last
    /// step of [`crate::Stepper::drive_until`]).
    pub fn last_curve(&self) -> Option<GalerkinCurve<S::Group, C, D>> {
        if self.predictor.previous_velocity.is_none() {
            // Only while that step is still the last one taken: it ends where the state is.
            return self
                .other_length_curve
                .as_ref()
                .filter(|c| (c.start() + c.step() - self.state.time).abs() <= 1e-9 * c.step())
                .cloned();
        }
        self.predictor
            .previous_velocity
            .is_some()
            .then(|| GalerkinCurve {
                base: self.predictor.last_base,
                nodes: self.predictor.last_nodes.clone(),
                basis: self.discretisation.basis.clone(),
                chart: self.chart,
                start: self.state.time - self.settings.h(),
                group: PhantomData,
            })
    }

    /// The last step's estimated local error, from the decay of the Chebyshev coefficients
    /// of its chart curve (0 before the first step): about the error of the step's end
    /// configuration and velocity (max norm, in the chart's coordinates: radians and
    /// radians per unit time on SO(3); SE(3) adds the units of the position). Calibrated on
    /// the free body and the heavy top to lie near the true local error on average (within
    /// a factor 30 either way on single steps), and never below the rounding of one step,
    /// [`crate::settings::ROUNDING_FLOOR`] (`4ε`). Costs `4nD` multiplications per step.
    pub fn error_estimate(&self) -> f64 {
        self.ledger.estimate
    }

    /// The sum of the steps' local error estimates since the start (or the last reset):
    /// an estimate of the global error where local errors accumulate linearly. It is a
    /// model, not a bound: errors that grow along the motion escape it, which a checked run
    /// measures instead (the user guide's page on tolerance-driven runs).
    pub fn estimated_global_error(&self) -> f64 {
        self.ledger.estimates.value()
    }

    /// How many steps took `n` nodes, at index `n` (adaptive runs change `n` per step;
    /// a fixed run has all its steps at one index).
    pub fn nodes_histogram(&self) -> &[usize] {
        &self.ledger.nodes_used
    }

    /// The node counts used so far with their steps, `(n, steps)` by increasing `n`: the
    /// non-zero entries of [`Integrator::nodes_histogram`].
    pub fn nodes_used(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.ledger
            .nodes_used
            .iter()
            .enumerate()
            .filter(|(_, &count)| count > 0)
            .map(|(n, &count)| (n, count))
    }
}
