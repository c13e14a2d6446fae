//! Tolerance-driven runs and runs that check themselves.
//!
//! - **The policy of a tolerance-driven run** ([`step_count`], [`first_nodes`],
//!   [`STEP_ROTATION`]): the step from the initial motion's rate, the first step's nodes
//!   from the tolerance, the nodes per step from each step's own spectral estimate
//!   ([`StepSettings::with_tolerance`]). [`crate::IntegratorBuilder`] applies it.
//! - **Checked runs** ([`CheckedIntegrator`]): a companion integrator takes every step
//!   again with more nodes, and the difference between the two is the run's measured
//!   error; with a tolerance ([`CheckedIntegrator::with_tolerance`]) a run that misses is
//!   taken again with a tightened share per step ([`ToleranceCheck`]).
//!
//! A tolerance-driven run ([`StepSettings::with_tolerance`]) chooses each step's nodes from
//! that step's own spectral estimate, and the sum of those estimates
//! ([`Integrator::estimated_global_error`]) is the run's model of its error. The model
//! fails where the motion amplifies the errors of earlier steps (a fast spin near the
//! intermediate axis, an unstable equilibrium, the phase of an orbit) or where the estimate's
//! calibration does not reach (spins far faster than the reference cases): there the error
//! at the end can be hundreds of times the sum of the local estimates.
//!
//! [`CheckedIntegrator`] measures instead of modelling. Beside the run (the *primary*) a companion
//! integrator starts from the same state and takes the same steps, each with
//! [`CHECK_EXTRA_NODES`] more nodes than the primary took (same step, chart, matching,
//! input). The method converges geometrically in the nodes (on the reference cases about
//! 30× per node at steps of 3 rad), so the companion is about a thousand times more
//! accurate, and the difference of the two states is the primary's error to a few per cent,
//! whatever made it: the local errors, their growth along the motion, or rounding (both runs
//! round; their difference is then the rounding's size). Both runs see the same motion, so
//! an amplification of errors is measured, not assumed away.
//!
//! The difference of two states is the largest entry of `(θ, δξ)`: `θ = log(ḡ⁻¹g)` the
//! configurations' difference in the algebra (radians on SO(3); SE(3) adds the position's
//! units) and `δξ` the body velocities' difference, as in [`crate::control::error_state`].
//!
//! It costs the companion: about 1.2–1.4 times the primary's time again at the node counts of
//! tolerance-driven runs (more nodes per step, the same steps).
//!
//! ```
//! use lgsvi_mechanics::prelude::*;
//! use lgsvi_mechanics::exact::FreeRigidBodyExact;
//! use lgsvi_mechanics::tolerance::CheckedIntegrator;
//! // A fast spin near the intermediate axis: the errors of early steps grow along the motion.
//! let inertia = Inertia::from_principal_moments([3.3, 2.5, 3.4])?;
//! let omega = Vector3::new(20.0, 0.1, 0.1);
//! let settings = StepSettings::new(0.15, 9)?;
//! let mut run = CheckedIntegrator::new(Integrator::new(RigidBody::new(inertia), settings, SO3::identity(), omega)?)?;
//! for _ in 0..20 {
//!     run.step()?;
//! }
//! // The measured difference against the exact motion's error.
//! let exact = FreeRigidBodyExact::new(inertia, SO3::identity(), omega)?.state(run.integrator().state().time)?;
//! let state = run.integrator().state();
//! let truth = (state.attitude().matrix() - exact.attitude().matrix()).amax()
//!     .max((state.velocity - exact.velocity).amax());
//! let measured = run.largest_difference().value;
//! assert!(measured > truth / 3.0 && measured < 3.0 * truth);
//! # Ok::<(), lgsvi_mechanics::MechanicsError>(())
//! ```

use crate::control::GroupLog;
use crate::error::MechanicsError;
use crate::group::GroupChart;
use crate::integrator::{Integrator, Trajectory};
use crate::settings::{StepSettings, DEFAULT_ADAPTIVE_NODES, MAX_NODES, ROUNDING_FLOOR};
use crate::state::State;
use crate::stepper::{run_until_by_steps, CheckReport, Difference, Stepper};
use crate::system::{ElementOf, System};
use nalgebra::SVector;

/// The companion's nodes beyond the primary's, per step: two nodes make it about a
/// thousand times more accurate at the steps of a tolerance-driven run (30× per node at
/// 3 rad per step), so its difference from the primary is the primary's error to about
/// 0.1%; where the method converges more slowly per node (shorter steps converge faster,
/// so that is a long step near the chart's reach) still to within a factor 2 from 2.5× per
/// node on.
pub const CHECK_EXTRA_NODES: usize = 2;

/// A checked run accepts its tolerance when its largest measured difference is at most
/// this many times the tolerance: the difference is the error to a few per cent, so the run
/// ends within this factor (at most the 10 promised) of the truth.
pub const CHECK_ACCEPTS: f64 = 3.0;

/// How many runs a checked tolerance-driven run may take (the first and two with a
/// tightened rate, [`tightened_rate`]) before it fails.
pub const CHECK_ATTEMPTS: usize = 3;

/// The rotation per step a tolerance-driven run's step is sized for: the smaller of
/// `0.5 ×` the chart's reach and 3 rad. On the reference cases the fastest fixed `(h, n)`
/// for errors 1e-6 … 1e-13 turn the body 2.5–4 rad per step, and a longer step also makes
/// each node count a smaller change in the error (about 30× per node at 3 rad, 100× at
/// 1.5 rad), so the tolerance is met more closely.
pub const STEP_ROTATION: (f64, f64) = (0.5, 3.0);

/// The nodes a tolerance-driven run's first step takes: `3 + ⌈−log₁₀(tol)/2⌉` within
/// [`DEFAULT_ADAPTIVE_NODES`], the fewest the reference cases settle on at steps of about
/// 3 rad (6 at 1e-6, 10 at 1e-13); the nodes only rise from there, as far as the estimates
/// ask. A first guess too low costs the first step a second solve; one too high would keep
/// the whole run more accurate (and slower) than asked.
///
/// ```
/// use lgsvi_mechanics::tolerance::first_nodes;
/// assert_eq!(first_nodes(1e-6), 6);
/// assert_eq!(first_nodes(1e-13), 10);
/// ```
pub fn first_nodes(tol: f64) -> usize {
    let (least, most) = DEFAULT_ADAPTIVE_NODES;
    (3.0 + (-tol.log10() / 2.0).ceil()).clamp(least as f64, most as f64) as usize
}

/// The number of steps of a tolerance-driven run over `[0, t_end]` at the motion's rate
/// `rate` (rad per unit time, [`System::motion_rate`]) in a chart that reaches
/// `max_rotation` rad per step: the fewest whole steps that each turn [`STEP_ROTATION`] or
/// less (at least one); the step is `t_end` over it.
///
/// ```
/// use lgsvi_mechanics::tolerance::step_count;
/// // Case A turns at |Ω₀| ≈ 2.93 rad/s: 98 steps of about 3 rad over T = 100 in the exp chart.
/// assert_eq!(step_count(100.0, 2.93, std::f64::consts::PI * 2.0), 98.0);
/// ```
pub fn step_count(t_end: f64, rate: f64, max_rotation: f64) -> f64 {
    let rotation = (STEP_ROTATION.0 * max_rotation).min(STEP_ROTATION.1);
    (t_end * rate / rotation).ceil().max(1.0)
}

/// A run and its companion, stepped together (module docs); with a tolerance, also the
/// policy that takes the run again when it misses.
///
/// Build one with [`crate::IntegratorBuilder::build_checked`], or around an integrator
/// with [`CheckedIntegrator::new`].
pub struct CheckedIntegrator<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> {
    primary: Integrator<S, C, D>,
    companion: Integrator<S, C, D>,
    extra: usize,
    steps: usize,
    now: f64,
    largest: Difference,
    /// The state and input the run started from, where a run that missed starts again.
    start: State<ElementOf<S, D>, D>,
    start_input: SVector<f64, D>,
    policy: Option<ToleranceCheck>,
}

impl<S, C, const D: usize> CheckedIntegrator<S, C, D>
where
    S: System<D> + Clone,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: GroupLog<D>,
{
    /// Checks `primary` from its present state on, with [`CHECK_EXTRA_NODES`] more nodes.
    ///
    /// # Errors
    /// As [`CheckedIntegrator::with_extra_nodes`].
    pub fn new(primary: Integrator<S, C, D>) -> Result<Self, MechanicsError> {
        Self::with_extra_nodes(primary, CHECK_EXTRA_NODES)
    }

    /// Checks `primary` with `extra` more nodes per step (1 to 8).
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for `extra` outside 1…8, for a primary whose step
    /// may change ([`crate::StepSettings::with_step_changes`]: the companion takes the
    /// primary's steps, and a step that changes would take its times apart), or whose
    /// nodes leave no room for `extra` more below [`MAX_NODES`]; the companion's
    /// construction errors (not expected for a primary that was built).
    pub fn with_extra_nodes(
        primary: Integrator<S, C, D>,
        extra: usize,
    ) -> Result<Self, MechanicsError> {
        if !(1..=8).contains(&extra) {
            return Err(MechanicsError::InvalidSetting {
                name: "extra nodes",
                value: extra.to_string(),
                reason: "the companion of a checked run takes 1 to 8 more nodes per step",
            });
        }
        let settings = *primary.settings();
        if settings.adaptive().is_some_and(|a| a.step_changes) {
            return Err(MechanicsError::InvalidSetting {
                name: "step changes",
                value: "true".into(),
                reason: "a checked run takes the primary's steps: let the nodes adapt, not the \
                         step",
            });
        }
        let most = settings
            .adaptive()
            .map_or(settings.nodes(), |a| a.max_nodes.max(settings.nodes()));
        if most + extra > MAX_NODES {
            return Err(MechanicsError::InvalidSetting {
                name: "nodes",
                value: most.to_string(),
                reason: "a checked run's companion takes more nodes than the primary's most, \
                         which must leave room below MAX_NODES",
            });
        }
        let state = *primary.state();
        let mut companion = Integrator::with_chart(
            primary.system().clone(),
            *primary.chart(),
            settings.fixed_with_nodes(settings.nodes() + extra),
            state.configuration,
            state.velocity,
        )?;
        companion.reset(state.time, state.configuration, state.velocity)?;
        companion.set_input(*primary.input())?;
        Ok(Self {
            start: state,
            start_input: *primary.input(),
            primary,
            companion,
            extra,
            steps: 0,
            now: 0.0,
            largest: Difference::default(),
            policy: None,
        })
    }

    /// This checked run held to `tolerance` at its end ([`ToleranceCheck`]): the primary's
    /// settings must be tolerance-driven ([`StepSettings::with_tolerance`], as the builder
    /// makes them). [`Stepper::run_until`] then judges the run by its largest measured
    /// difference and, where it exceeds [`CHECK_ACCEPTS`]` · tolerance`, takes it again
    /// from its start with a tightened share per step, up to [`CHECK_ATTEMPTS`] runs;
    /// [`CheckedIntegrator::judge`] does the same for a run driven by hand.
    ///
    /// # Errors
    /// As [`ToleranceCheck::new`].
    pub fn with_tolerance(mut self, tolerance: f64) -> Result<Self, MechanicsError> {
        self.policy = Some(ToleranceCheck::new(*self.primary.settings(), tolerance)?);
        Ok(self)
    }

    /// Judges the run so far by its largest measured difference ([`ToleranceCheck`]):
    /// `Ok(true)` accepts it (always, without a tolerance); `Ok(false)` has restarted the
    /// run from its start with a tightened share per step, to be taken again.
    ///
    /// # Errors
    /// [`MechanicsError::ToleranceNotChecked`] after the last run allowed, or where the
    /// share per step has reached the rounding of a step; a restart's construction errors
    /// (not expected: the run was built from the same state).
    pub fn judge(&mut self) -> Result<bool, MechanicsError> {
        let Some(policy) = self.policy.as_mut() else {
            return Ok(true);
        };
        if policy.judge(self.largest)? {
            return Ok(true);
        }
        let settings = policy.settings();
        let start = self.start;
        let mut primary = Integrator::with_chart(
            self.primary.system().clone(),
            *self.primary.chart(),
            settings,
            start.configuration,
            start.velocity,
        )?;
        if start.time != 0.0 {
            primary.reset(start.time, start.configuration, start.velocity)?;
        }
        primary.set_input(self.start_input)?;
        let policy = self.policy.take();
        *self = Self::with_extra_nodes(primary, self.extra)?;
        self.policy = policy;
        Ok(false)
    }

    /// Sets the control input of both runs ([`Integrator::set_input`]).
    ///
    /// # Errors
    /// As [`Integrator::set_input`].
    pub fn set_input(&mut self, input: SVector<f64, D>) -> Result<(), MechanicsError> {
        self.primary.set_input(input)?;
        self.companion.set_input(input)
    }

    /// The run being checked, the companion dropped.
    pub fn into_integrator(self) -> Integrator<S, C, D> {
        self.primary
    }

    /// The present state of the run being checked.
    pub fn state(&self) -> &State<ElementOf<S, D>, D> {
        self.primary.state()
    }

    /// The companion's present state (the same time as the primary's).
    pub fn companion_state(&self) -> &State<ElementOf<S, D>, D> {
        self.companion.state()
    }

    /// The difference of the two runs after the last step (0 before the first).
    pub fn difference(&self) -> f64 {
        self.now
    }

    /// The largest difference since the check began, and where (a NaN difference counts
    /// as the largest).
    pub fn largest_difference(&self) -> Difference {
        self.largest
    }

    /// The tolerance policy, for a run with a tolerance.
    pub fn policy(&self) -> Option<&ToleranceCheck> {
        self.policy.as_ref()
    }

    /// One step of the primary, then the same step of the companion with `extra` more
    /// nodes (of length `h`, or the primary's own when `None`).
    fn step_both(&mut self, h: Option<f64>) -> Result<usize, MechanicsError> {
        let iterations = match h {
            Some(h) => self.primary.step_by(h)?,
            None => self.primary.step()?,
        };
        let nodes = self.primary.settings().nodes() + self.extra;
        let time = self.primary.state().time;
        let failed = |source| MechanicsError::CheckFailed {
            step: self.steps,
            time,
            source: Box::new(source),
        };
        self.companion.set_nodes(nodes).map_err(failed)?;
        self.companion
            .set_input(*self.primary.input())
            .map_err(failed)?;
        match h {
            Some(h) => self.companion.step_by(h).map_err(failed)?,
            None => self.companion.step().map_err(failed)?,
        };
        self.steps += 1;
        self.now = difference(self.primary.state(), self.companion.state());
        // A NaN difference is kept as the largest once seen.
        let larger = self.now.is_nan() || self.now > self.largest.value;
        if larger && !self.largest.value.is_nan() {
            self.largest = Difference {
                value: self.now,
                step: self.steps,
                time,
            };
        }
        Ok(iterations)
    }
}

impl<S, C, const D: usize> Stepper<S, C, D> for CheckedIntegrator<S, C, D>
where
    S: System<D> + Clone,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: GroupLog<D>,
{
    /// One step of the primary, then the same step of the companion with `extra` more
    /// nodes; returns the primary's Newton iterations.
    ///
    /// # Errors
    /// The primary's errors, as [`Integrator::step`]; [`MechanicsError::CheckFailed`]
    /// where the companion's step fails after the primary's succeeded (the primary has
    /// then taken the step; the check cannot go on).
    fn step(&mut self) -> Result<usize, MechanicsError> {
        self.step_both(None)
    }

    fn step_by(&mut self, h: f64) -> Result<usize, MechanicsError> {
        self.step_both(Some(h))
    }

    fn integrator(&self) -> &Integrator<S, C, D> {
        &self.primary
    }

    fn set_input(&mut self, input: SVector<f64, D>) -> Result<(), MechanicsError> {
        CheckedIntegrator::set_input(self, input)
    }

    /// As [`Stepper::run_until`]; a run with a tolerance is then judged
    /// ([`CheckedIntegrator::judge`]) and, where it missed, taken again from its start:
    /// the trajectory returned is the accepted run's, from its start.
    ///
    /// # Errors
    /// As [`Stepper::run_until`]; [`MechanicsError::ToleranceNotChecked`] where no run
    /// allowed met the tolerance.
    fn run_until(
        &mut self,
        t_end: f64,
        every: usize,
    ) -> Result<Trajectory<ElementOf<S, D>, D>, MechanicsError> {
        loop {
            let trajectory = run_until_by_steps(self, t_end, every)?;
            if self.judge()? {
                return Ok(trajectory);
            }
        }
    }

    /// The measured difference at the last step.
    fn estimated_error(&self) -> f64 {
        self.now
    }

    fn check_report(&self) -> Option<CheckReport> {
        Some(CheckReport {
            difference: self.now,
            largest: self.largest,
            local_sum: self.primary.estimated_global_error(),
            attempts: self.policy.map_or(1, |p| p.attempt()),
            tightened: self.policy.map_or(1.0, |p| p.tightened()),
        })
    }
}

/// The largest entry of `(log(b⁻¹a), ξ_a − ξ_b)`.
fn difference<E: GroupLog<D>, const D: usize>(a: &State<E, D>, b: &State<E, D>) -> f64 {
    let theta = a.configuration.log_from(&b.configuration);
    let mut largest = 0.0f64;
    for x in theta.iter().chain((a.velocity - b.velocity).iter()) {
        if x.is_nan() {
            return f64::NAN;
        }
        largest = largest.max(x.abs());
    }
    largest
}

/// The first step `h` of a tolerance-driven run over `[t₀, t₀ + t_end]` of `system` from
/// `(g, ξ)` in `chart`: `t_end` over [`step_count`] at the motion's rate
/// ([`System::motion_rate`]); `None` for a horizon that is not positive.
pub(crate) fn tolerance_step<S: System<D>, C: GroupChart<S::Group, D>, const D: usize>(
    system: &S,
    chart: &C,
    t_end: f64,
    configuration: &ElementOf<S, D>,
    velocity: &SVector<f64, D>,
) -> Option<f64> {
    (t_end > 0.0).then(|| {
        let rate = system.motion_rate(0.0, configuration, velocity);
        t_end / step_count(t_end, rate, chart.max_rotation_angle())
    })
}

/// The error per unit time a tolerance-driven run takes again after a checked run of
/// rate `rate` measured `measured` against the tolerance `tolerance`: the rate times
/// `tolerance / (10 · measured)`, and at most a tenth of it. The target a tenth below the
/// tolerance leaves room for the growth of errors that made the first run miss (the error
/// falls by about 30× per node, so a tenfold margin costs about one node).
pub fn tightened_rate(rate: f64, measured: f64, tolerance: f64) -> f64 {
    let factor = if measured > 0.0 && measured.is_finite() {
        (tolerance / (10.0 * measured)).min(0.1)
    } else {
        0.1
    };
    rate * factor
}

/// The policy of a checked tolerance-driven run: which settings each run takes, and whether
/// a run's largest difference ([`CheckedIntegrator::largest_difference`]) accepts the
/// tolerance, asks for another run, or ends in [`MechanicsError::ToleranceNotChecked`].
/// [`CheckedIntegrator::with_tolerance`] applies it; this is the policy alone, for runs
/// of your own.
///
/// A run is accepted when its largest difference is at most [`CHECK_ACCEPTS`]` · tolerance`;
/// otherwise the next run takes the share per step [`tightened_rate`] gives (never below the
/// rounding of a step), up to [`CHECK_ATTEMPTS`] runs. Where the share has reached the
/// rounding of a step, the error says so, with the closest run's difference as what the
/// motion allows.
///
/// ```
/// use lgsvi_mechanics::prelude::*;
/// use lgsvi_mechanics::tolerance::{CheckedIntegrator, ToleranceCheck};
/// let (t_end, tolerance) = (10.0, 1e-8);
/// let body = RigidBody::new(Inertia::from_principal_moments([3.3, 2.5, 3.4])?);
/// let omega = Vector3::new(20.0, 0.1, 0.1);
/// let first = StepSettings::new(t_end / 67.0, 7)?.with_tolerance(tolerance / t_end)?;
/// let mut policy = ToleranceCheck::new(first, tolerance)?;
/// let run = loop {
///     let integrator = Integrator::new(body, policy.settings(), SO3::identity(), omega)?;
///     let mut run = CheckedIntegrator::new(integrator)?;
///     for _ in 0..67 {
///         run.step()?;
///     }
///     if policy.judge(run.largest_difference())? {
///         break run;
///     }
/// };
/// assert!(run.largest_difference().value <= 3.0 * tolerance);
/// assert_eq!(policy.attempt(), 2); // the first run missed: the errors grow along this spin
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToleranceCheck {
    tolerance: f64,
    first_rate: f64,
    settings: StepSettings,
    attempt: usize,
    best: f64,
}

impl ToleranceCheck {
    /// The policy for a run of `settings` (with a tolerance:
    /// [`StepSettings::with_tolerance`]) that must end within `tolerance`.
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for settings without a tolerance, or a tolerance
    /// that is not positive and finite.
    pub fn new(settings: StepSettings, tolerance: f64) -> Result<Self, MechanicsError> {
        let Some(adaptive) = settings.adaptive() else {
            return Err(MechanicsError::InvalidSetting {
                name: "tolerance",
                value: "none".into(),
                reason: "a checked tolerance run needs settings with a tolerance \
                         (StepSettings::with_tolerance)",
            });
        };
        if !(tolerance.is_finite() && tolerance > 0.0) {
            return Err(MechanicsError::InvalidSetting {
                name: "tolerance",
                value: tolerance.to_string(),
                reason: "must be positive and finite",
            });
        }
        Ok(Self {
            tolerance,
            first_rate: adaptive.rate,
            settings,
            attempt: 1,
            best: f64::INFINITY,
        })
    }

    /// The settings of the present run.
    pub fn settings(&self) -> StepSettings {
        self.settings
    }

    /// The present run, from 1.
    pub fn attempt(&self) -> usize {
        self.attempt
    }

    /// How far the present run's share per step lies below the first run's (1 for the
    /// first).
    pub fn tightened(&self) -> f64 {
        self.first_rate / self.rate()
    }

    fn rate(&self) -> f64 {
        self.settings.adaptive().map_or(self.first_rate, |a| a.rate)
    }

    /// Judges a run by its largest difference: `Ok(true)` accepts it; `Ok(false)` asks for
    /// another run with [`ToleranceCheck::settings`] (now tightened).
    ///
    /// # Errors
    /// [`MechanicsError::ToleranceNotChecked`] after the last run allowed, or where the
    /// share per step has reached the rounding of a step.
    pub fn judge(&mut self, largest: Difference) -> Result<bool, MechanicsError> {
        self.best = self.best.min(largest.value);
        if largest.value <= CHECK_ACCEPTS * self.tolerance {
            return Ok(true);
        }
        let rate = self.rate();
        let floor = ROUNDING_FLOOR / self.settings.h() * (1.0 + 1e-9);
        let at_floor = rate <= floor;
        if self.attempt >= CHECK_ATTEMPTS || at_floor {
            return Err(MechanicsError::ToleranceNotChecked {
                tolerance: self.tolerance,
                attempts: self.attempt,
                tightened: self.tightened(),
                measured: largest.value,
                time: largest.time,
                step: largest.step,
                at_floor,
                best: self.best,
            });
        }
        self.settings = self
            .settings
            .with_tolerance(tightened_rate(rate, largest.value, self.tolerance).max(floor))?;
        self.attempt += 1;
        Ok(false)
    }
}
