//! Runs of many steps, written once: anything that takes a step ([`Stepper`]: an
//! [`Integrator`], a [`CheckedIntegrator`] beside its companion) gets the driving loop
//! [`Stepper::drive`], which tells an [`Observer`] after every step, and the runs built on
//! it ([`Stepper::run`], [`Stepper::run_until`]). Recording ([`Recorder`]), progress,
//! checks, conserved quantities and curve sampling are observers, so every loop over
//! steps — a run's, a study's, a user's — is this one.
//!
//! An observer answers with [`std::ops::ControlFlow`]: `Continue(())` takes the next step,
//! `Break(())` stops the run there. Before a step it may also set the control input
//! ([`Observer::input`]): a controller that samples the state and holds its output
//! between samples (a [`crate::control::PdLaw`] read every period) is an observer too.
//!
//! ```
//! use lgsvi_mechanics::prelude::*;
//! use lgsvi_mechanics::stepper::{each, Recorder};
//! use std::ops::ControlFlow;
//!
//! let body = RigidBody::new(Inertia::from_paper_jd([1.3, 2.1, 1.2])?);
//! let mut integrator =
//!     Integrator::new(body, StepSettings::new(0.5, 8)?, SO3::identity(), Vector3::new(-2.0, 1.9, -1.0))?;
//! let mut recorder = Recorder::new(integrator.state(), 20, 5);
//! let mut largest_energy_change = 0.0f64;
//! let e0 = integrator.state().energy(&body);
//! let energy = each(|it: &Integrator<RigidBody>, _step| {
//!     largest_energy_change = largest_energy_change.max((it.state().energy(&body) - e0).abs());
//!     Ok::<_, MechanicsError>(ControlFlow::Continue(()))
//! });
//! let taken = integrator.drive(20, &mut (&mut recorder, energy))?;
//! assert_eq!(taken, 20);
//! assert_eq!(recorder.trajectory().states.len(), 5); // t = 0, 2.5, 5, 7.5, 10
//! assert!(largest_energy_change < 1e-6);
//! # Ok::<(), lgsvi_mechanics::MechanicsError>(())
//! ```
//!
//! [`CheckedIntegrator`]: crate::tolerance::CheckedIntegrator

use crate::error::MechanicsError;
use crate::group::GroupChart;
use crate::integrator::{Integrator, Trajectory};
use crate::state::State;
use crate::system::{ElementOf, System};
use nalgebra::SVector;
use std::ops::ControlFlow;

/// A step of a driven run, as its observers see it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StepInfo {
    /// The step's number in the run, from 1.
    pub index: usize,
    /// Its Newton iterations.
    pub iterations: usize,
    /// Whether it is the run's last planned step.
    pub last: bool,
}

/// Anything that advances an [`Integrator`] step by step: the integrator itself, or a
/// [`crate::tolerance::CheckedIntegrator`] that takes every step again beside a companion.
/// The loops over many steps are its provided methods, written once.
///
/// Implement [`Stepper::step`], [`Stepper::step_by`] and [`Stepper::integrator`]; the
/// runs come with them.
pub trait Stepper<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> {
    /// Advances one step of the settings' length; returns its Newton iterations.
    ///
    /// # Errors
    /// The step's failure ([`Integrator::step`]); the state is then unchanged.
    fn step(&mut self) -> Result<usize, MechanicsError>;

    /// Advances one step of length `h` (a shorter last step to land on a horizon), then
    /// returns to the settings' step; returns its Newton iterations.
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for an `h` that is not finite or lies outside
    /// [`crate::settings::STEP_RANGE`]; the step's failure, as [`Stepper::step`].
    fn step_by(&mut self, h: f64) -> Result<usize, MechanicsError>;

    /// The integrator being advanced (for a checked run, the run being checked).
    fn integrator(&self) -> &Integrator<S, C, D>;

    /// Sets the control input of the steps to come ([`Integrator::set_input`]; a checked
    /// run's companion takes it too).
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`] for an input with an entry that is not finite.
    fn set_input(&mut self, input: SVector<f64, D>) -> Result<(), MechanicsError>;

    /// The run's error as the stepper knows it: a checked run's measured difference from
    /// its companion ([`CheckReport::difference`]), else the sum of the steps' local
    /// estimates ([`Integrator::estimated_global_error`]), which is a model of the error,
    /// not a bound (the user guide's page on tolerance-driven runs).
    fn estimated_error(&self) -> f64 {
        self.integrator().estimated_global_error()
    }

    /// What a checked run's companion measured; `None` for a run that is not checked.
    fn check_report(&self) -> Option<CheckReport> {
        None
    }

    /// Takes up to `steps` steps, telling `observer` after each; returns the steps taken
    /// (fewer when the observer stopped the run).
    ///
    /// # Errors
    /// A failed step (its error through the observer's error type) or the observer's own;
    /// the integrator keeps the last good state.
    fn drive<O: Observer<S, C, D>>(
        &mut self,
        steps: usize,
        observer: &mut O,
    ) -> Result<usize, O::Error>
    where
        Self: Sized,
    {
        for index in 1..=steps {
            before_step(self, observer)?;
            let iterations = self.step()?;
            let info = StepInfo {
                index,
                iterations,
                last: index == steps,
            };
            if observer.after_step(self.integrator(), info)?.is_break() {
                return Ok(index);
            }
        }
        Ok(steps)
    }

    /// Takes `steps` steps, recording the initial state, every `every`-th state (at least
    /// 1) and the last one.
    ///
    /// # Errors
    /// As [`Stepper::step`]; the states recorded so far are lost with the error, the
    /// integrator keeps the last good state.
    fn run(
        &mut self,
        steps: usize,
        every: usize,
    ) -> Result<Trajectory<ElementOf<S, D>, D>, MechanicsError>
    where
        Self: Sized,
    {
        let mut recorder = Recorder::new(self.integrator().state(), steps, every);
        self.drive(steps, &mut recorder)?;
        Ok(recorder.into_trajectory())
    }

    /// Drives the run to exactly `t_end`, telling `observer` after every step: steps of
    /// `h`, then one shorter step (itself a variational step, of its own length,
    /// [`Stepper::step_by`]) where `t_end` is not a whole number of steps away; the last
    /// step's [`StepInfo::last`] is set. Returns the steps taken (fewer when the observer
    /// stopped the run).
    ///
    /// # Errors
    /// As [`Stepper::drive`]; [`MechanicsError::InvalidSetting`] for a `t_end` that is not
    /// finite, lies before the present time, or needs more than 2⁵³ steps.
    fn drive_until<O: Observer<S, C, D>>(
        &mut self,
        t_end: f64,
        observer: &mut O,
    ) -> Result<usize, O::Error>
    where
        Self: Sized,
    {
        let integrator = self.integrator();
        integrator.check_end(t_end)?;
        let h = integrator.settings().h();
        let start = integrator.state().time;
        let whole = ((t_end - start).max(0.0) / h + 1e-9).floor();
        Integrator::<S, C, D>::check_step_count(t_end, whole)?;
        let whole = whole as usize;
        // The step at which the run ends: the shortened one, if there is one.
        let short = t_end - (start + whole as f64 * h) > 1e-9 * h;
        for index in 1..=whole {
            before_step(self, observer)?;
            let iterations = self.step()?;
            let info = StepInfo {
                index,
                iterations,
                last: index == whole && !short,
            };
            if observer.after_step(self.integrator(), info)?.is_break() {
                return Ok(index);
            }
        }
        let left = t_end - self.integrator().state().time;
        if short && left > 1e-9 * h {
            before_step(self, observer)?;
            let iterations = self.step_by(left)?;
            let info = StepInfo {
                index: whole + 1,
                iterations,
                last: true,
            };
            // The run ends here, whatever the observer answers.
            let _ = observer.after_step(self.integrator(), info)?;
            return Ok(whole + 1);
        }
        Ok(whole)
    }

    /// Steps until exactly `t_end` ([`Stepper::drive_until`]), recording as
    /// [`Stepper::run`]: the initial state, every `every`-th state and the last.
    ///
    /// # Errors
    /// As [`Stepper::drive_until`].
    fn run_until(
        &mut self,
        t_end: f64,
        every: usize,
    ) -> Result<Trajectory<ElementOf<S, D>, D>, MechanicsError>
    where
        Self: Sized,
    {
        run_until_by_steps(self, t_end, every)
    }
}

/// [`Stepper::run_until`]'s loop, for the implementations that add to it.
pub(crate) fn run_until_by_steps<T, S, C, const D: usize>(
    stepper: &mut T,
    t_end: f64,
    every: usize,
) -> Result<Trajectory<ElementOf<S, D>, D>, MechanicsError>
where
    T: Stepper<S, C, D>,
    S: System<D>,
    C: GroupChart<S::Group, D>,
{
    let mut recorder = Recorder::new(stepper.integrator().state(), 0, every);
    stepper.drive_until(t_end, &mut recorder)?;
    Ok(recorder.into_trajectory())
}

/// The largest difference of a checked run and where it was measured.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Difference {
    /// The largest entry of `(θ, δξ)`: the configurations' difference in the algebra and
    /// the body velocities' ([`crate::tolerance`]).
    pub value: f64,
    /// The step after which it was measured (1-based: the state after step `step`).
    pub step: usize,
    /// The time of that state.
    pub time: f64,
}

/// What a checked run's companion measured ([`Stepper::check_report`],
/// [`crate::tolerance::CheckedIntegrator`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckReport {
    /// The difference of the two runs after the last step: the run's measured error now.
    pub difference: f64,
    /// The largest difference along the run, its time and step.
    pub largest: Difference,
    /// The sum of the run's local error estimates (the unchecked model), for comparison.
    pub local_sum: f64,
    /// Runs taken: the first, and each with a tightened share per step.
    pub attempts: usize,
    /// The present run's share per step against the first's (1 for the first).
    pub tightened: f64,
}

/// Before a step of `stepper`: `observer`'s input, where it sets one, then its
/// [`Observer::before_step`] (which sees the step's start with that input).
fn before_step<S, C, T, O, const D: usize>(
    stepper: &mut T,
    observer: &mut O,
) -> Result<(), O::Error>
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    T: Stepper<S, C, D> + ?Sized,
    O: Observer<S, C, D>,
{
    if let Some(input) = observer.input(stepper.integrator()) {
        stepper.set_input(input)?;
    }
    observer.before_step(stepper.integrator());
    Ok(())
}

/// Watches a driven run: told of every step with the integrator after it (state, last
/// Galerkin curve, statistics, estimates), it records, checks, reports progress, or stops
/// the run.
///
/// A closure `FnMut(&Integrator, StepInfo) -> Result<ControlFlow<()>, E>` becomes one
/// through [`each`]; `(A, B)` pairs, `Option`s and `&mut` references of observers are
/// observers too (module documentation).
pub trait Observer<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> {
    /// The observer's error; a failed step becomes one through `From`.
    type Error: From<MechanicsError>;

    /// After a step: `Continue(())` takes the next, `Break(())` stops the run.
    ///
    /// # Errors
    /// Whatever the observer finds wrong; the run stops with it.
    fn after_step(
        &mut self,
        integrator: &Integrator<S, C, D>,
        step: StepInfo,
    ) -> Result<ControlFlow<()>, Self::Error>;

    /// Before a step, with the integrator at the step's start (nothing by default; the
    /// events observer keeps the start to take shorter steps from it).
    fn before_step(&mut self, integrator: &Integrator<S, C, D>) {
        let _ = integrator;
    }

    /// Before a step (and before [`Observer::before_step`]), with the integrator at the
    /// step's start: a control input to set for this step and the ones after it
    /// ([`Stepper::set_input`]), or `None` to keep the one in force (the default). A
    /// sampled controller answers at its sampling instants.
    fn input(&mut self, integrator: &Integrator<S, C, D>) -> Option<SVector<f64, D>> {
        let _ = integrator;
        None
    }
}

/// A closure as an observer ([`each`]).
#[derive(Debug, Clone, Copy)]
pub struct Each<F>(pub F);

/// The observer that calls `f(integrator, step)` after every step.
pub fn each<F>(f: F) -> Each<F> {
    Each(f)
}

impl<S, C, const D: usize, F, E> Observer<S, C, D> for Each<F>
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    F: FnMut(&Integrator<S, C, D>, StepInfo) -> Result<ControlFlow<()>, E>,
    E: From<MechanicsError>,
{
    type Error = E;
    fn after_step(
        &mut self,
        integrator: &Integrator<S, C, D>,
        step: StepInfo,
    ) -> Result<ControlFlow<()>, E> {
        (self.0)(integrator, step)
    }
}

/// Both observers, in order; the run stops if either says so. The second's errors become
/// the first's (a library error into an application's, for instance).
impl<S, C, const D: usize, A, B> Observer<S, C, D> for (A, B)
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    A: Observer<S, C, D>,
    B: Observer<S, C, D>,
    A::Error: From<B::Error>,
{
    type Error = A::Error;
    fn before_step(&mut self, integrator: &Integrator<S, C, D>) {
        self.0.before_step(integrator);
        self.1.before_step(integrator);
    }
    /// The first's input where it gives one, else the second's (both are asked).
    fn input(&mut self, integrator: &Integrator<S, C, D>) -> Option<SVector<f64, D>> {
        let first = self.0.input(integrator);
        let second = self.1.input(integrator);
        first.or(second)
    }
    fn after_step(
        &mut self,
        integrator: &Integrator<S, C, D>,
        step: StepInfo,
    ) -> Result<ControlFlow<()>, A::Error> {
        let first = self.0.after_step(integrator, step)?;
        let second = self.1.after_step(integrator, step)?;
        Ok(if first.is_break() || second.is_break() {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        })
    }
}

/// An observer that may be absent: `None` watches nothing and sets no input.
impl<S, C, const D: usize, O> Observer<S, C, D> for Option<O>
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    O: Observer<S, C, D>,
{
    type Error = O::Error;
    fn after_step(
        &mut self,
        integrator: &Integrator<S, C, D>,
        step: StepInfo,
    ) -> Result<ControlFlow<()>, O::Error> {
        match self {
            Some(observer) => observer.after_step(integrator, step),
            None => Ok(ControlFlow::Continue(())),
        }
    }
    fn before_step(&mut self, integrator: &Integrator<S, C, D>) {
        if let Some(observer) = self {
            observer.before_step(integrator);
        }
    }
    fn input(&mut self, integrator: &Integrator<S, C, D>) -> Option<SVector<f64, D>> {
        self.as_mut()?.input(integrator)
    }
}

impl<S, C, const D: usize, O> Observer<S, C, D> for &mut O
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    O: Observer<S, C, D> + ?Sized,
{
    type Error = O::Error;
    fn after_step(
        &mut self,
        integrator: &Integrator<S, C, D>,
        step: StepInfo,
    ) -> Result<ControlFlow<()>, O::Error> {
        (**self).after_step(integrator, step)
    }
    fn before_step(&mut self, integrator: &Integrator<S, C, D>) {
        (**self).before_step(integrator);
    }
    fn input(&mut self, integrator: &Integrator<S, C, D>) -> Option<SVector<f64, D>> {
        (**self).input(integrator)
    }
}

/// Records the initial state, every `every`-th state and the last one of a driven run,
/// with each recorded step's Newton iterations: what [`Stepper::run`] returns.
#[derive(Debug, Clone)]
pub struct Recorder<E, const D: usize> {
    every: usize,
    trajectory: Trajectory<E, D>,
}

impl<E: Copy, const D: usize> Recorder<E, D> {
    /// From the run's initial state, with room for a run of `steps` steps, recording every
    /// `every`-th step (at least 1): the arguments of [`Stepper::run`], in its order.
    pub fn new(start: &State<E, D>, steps: usize, every: usize) -> Self {
        let every = every.max(1);
        let mut states = Vec::with_capacity(steps / every + 2);
        let mut newton_iterations = Vec::with_capacity(steps / every + 2);
        states.push(*start);
        newton_iterations.push(0);
        Self {
            every,
            trajectory: Trajectory {
                states,
                newton_iterations,
            },
        }
    }

    /// What has been recorded.
    pub fn trajectory(&self) -> &Trajectory<E, D> {
        &self.trajectory
    }

    /// The recorded trajectory.
    pub fn into_trajectory(self) -> Trajectory<E, D> {
        self.trajectory
    }

    /// Records `state` from a step of `iterations` Newton iterations.
    pub(crate) fn push(&mut self, state: State<E, D>, iterations: usize) {
        self.trajectory.states.push(state);
        self.trajectory.newton_iterations.push(iterations);
    }
}

impl<S, C, const D: usize> Observer<S, C, D> for Recorder<ElementOf<S, D>, D>
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
{
    type Error = MechanicsError;
    fn after_step(
        &mut self,
        integrator: &Integrator<S, C, D>,
        step: StepInfo,
    ) -> Result<ControlFlow<()>, MechanicsError> {
        if step.index.is_multiple_of(self.every) || step.last {
            self.push(*integrator.state(), step.iterations);
        }
        Ok(ControlFlow::Continue(()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Inertia, RigidBody, StepSettings};
    use lgsvi_lie::SO3;
    use nalgebra::Vector3;

    fn integrator() -> Integrator<RigidBody> {
        let body = RigidBody::new(Inertia::from_paper_jd([1.3, 2.1, 1.2]).unwrap());
        let settings = StepSettings::new(0.5, 6).unwrap();
        Integrator::new(
            body,
            settings,
            SO3::identity(),
            Vector3::new(-2.0, 1.9, -1.0),
        )
        .unwrap()
    }

    #[test]
    fn an_observer_sees_every_step_and_can_stop_the_run() {
        let mut it = integrator();
        let mut seen = Vec::new();
        let mut stop_at_three = each(|it: &Integrator<RigidBody>, step: StepInfo| {
            seen.push((step.index, step.last, it.state().time));
            Ok::<_, MechanicsError>(if step.index == 3 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            })
        });
        assert_eq!(it.drive(10, &mut stop_at_three).unwrap(), 3);
        assert_eq!(
            seen,
            vec![(1, false, 0.5), (2, false, 1.0), (3, false, 1.5)]
        );
        assert_eq!(it.state().time, 1.5);
    }

    #[test]
    fn a_recorder_keeps_what_run_returns() {
        let (mut a, mut b) = (integrator(), integrator());
        let expected = a.run(7, 3).unwrap();
        let mut recorder = Recorder::new(b.state(), 7, 3);
        assert_eq!(b.drive(7, &mut recorder).unwrap(), 7);
        // The initial state, steps 3 and 6, and the last (7): bit for bit as `run`.
        assert_eq!(recorder.trajectory(), &expected);
        assert_eq!(expected.states.len(), 4);
    }

    #[test]
    fn an_observers_error_stops_the_run_with_it() {
        #[derive(Debug)]
        enum Mine {
            Step,
            Mechanics,
        }
        impl From<MechanicsError> for Mine {
            fn from(_: MechanicsError) -> Self {
                Mine::Mechanics
            }
        }
        let mut it = integrator();
        let mut failing = each(|_: &Integrator<RigidBody>, step: StepInfo| {
            if step.index == 2 {
                Err(Mine::Step)
            } else {
                Ok(ControlFlow::Continue(()))
            }
        });
        assert!(matches!(it.drive(5, &mut failing), Err(Mine::Step)));
        assert_eq!(it.state().time, 1.0);
        // A step that fails (one Newton iteration cannot converge from the predictor's
        // guess) comes through the observer's error type.
        let body = RigidBody::new(Inertia::from_paper_jd([1.3, 2.1, 1.2]).unwrap());
        let settings = StepSettings::new(0.5, 6)
            .unwrap()
            .with_max_newton_iterations(1);
        let mut it = Integrator::new(
            body,
            settings,
            SO3::identity(),
            Vector3::new(-2.0, 1.9, -1.0),
        )
        .unwrap();
        let mut quiet =
            each(|_: &Integrator<RigidBody>, _| Ok::<_, Mine>(ControlFlow::Continue(())));
        assert!(matches!(it.drive(5, &mut quiet), Err(Mine::Mechanics)));
        assert_eq!(it.state().time, 0.0);
    }

    /// A run to a horizon that is not a whole number of steps away ends on it with one
    /// shorter step, and the step after is the settings' again.
    #[test]
    fn run_until_lands_on_the_horizon_with_a_shorter_step() {
        let mut it = integrator();
        let trajectory = it.run_until(1.2, 1).unwrap();
        let times: Vec<f64> = trajectory.states.iter().map(|s| s.time).collect();
        assert_eq!(times, vec![0.0, 0.5, 1.0, 1.2]);
        it.step().unwrap();
        assert!((it.state().time - 1.7).abs() < 1e-15);
        // A step of a length outside the step range is refused, naming h.
        for h in [f64::NAN, 0.0, -0.5, f64::INFINITY] {
            match it.step_by(h) {
                Err(MechanicsError::InvalidSetting { name: "h", .. }) => {}
                other => panic!("h = {h}: {other:?}"),
            }
        }
    }
}
