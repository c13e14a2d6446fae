//! One driving loop for runs of many steps: [`Integrator::drive`] steps and tells an
//! [`Observer`] after every step. Recording ([`Recorder`]), progress, checks, conserved
//! quantities and curve sampling are observers, so every loop over steps — `run`,
//! `run_until`, a study's, a user's — is this one.

use super::*;

/// What the loop does after an observer has seen a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    /// Take the next step.
    Continue,
    /// Stop here: [`Integrator::drive`] returns the steps taken so far.
    Stop,
}

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

/// Watches a driven run: told of every step with the integrator after it (state, last
/// Galerkin curve, statistics, estimates), it records, checks, reports progress, or stops
/// the run.
///
/// A closure `FnMut(&Integrator, StepInfo) -> Result<Flow, E>` becomes one through [`each`];
/// `(A, B)` pairs and `&mut` references of observers are observers too:
///
/// ```
/// use lgsvi_mechanics::{each, Flow, Inertia, Integrator, Recorder, RigidBody, StepSettings};
/// use lgsvi_lie::SO3;
/// use nalgebra::Vector3;
///
/// let body = RigidBody::new(Inertia::from_paper_jd([1.3, 2.1, 1.2])?);
/// let mut integrator =
///     Integrator::new(body, StepSettings::new(0.5, 8)?, SO3::identity(), Vector3::new(-2.0, 1.9, -1.0))?;
/// let mut recorder = Recorder::new(integrator.state(), 5, 20);
/// let mut largest_energy_change = 0.0f64;
/// let e0 = integrator.state().energy(&body);
/// let energy = each(|it: &Integrator<RigidBody>, _step| {
///     largest_energy_change = largest_energy_change.max((it.state().energy(&body) - e0).abs());
///     Ok::<_, lgsvi_mechanics::MechanicsError>(Flow::Continue)
/// });
/// let taken = integrator.drive(20, &mut (&mut recorder, energy))?;
/// assert_eq!(taken, 20);
/// assert_eq!(recorder.trajectory().states.len(), 5); // t = 0, 2.5, 5, 7.5, 10
/// assert!(largest_energy_change < 1e-6);
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
pub trait Observer<S: GroupLagrangian<D>, C: GroupChart<S::Group, D>, const D: usize> {
    /// The observer's error; a failed step becomes one through `From`.
    type Error: From<MechanicsError>;

    /// After a step.
    ///
    /// # Errors
    /// Whatever the observer finds wrong; the run stops with it.
    fn after_step(
        &mut self,
        integrator: &Integrator<S, C, D>,
        step: StepInfo,
    ) -> Result<Flow, Self::Error>;
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
    S: GroupLagrangian<D>,
    C: GroupChart<S::Group, D>,
    F: FnMut(&Integrator<S, C, D>, StepInfo) -> Result<Flow, E>,
    E: From<MechanicsError>,
{
    type Error = E;
    fn after_step(&mut self, integrator: &Integrator<S, C, D>, step: StepInfo) -> Result<Flow, E> {
        (self.0)(integrator, step)
    }
}

/// Both observers, in order; the run stops if either says so.
impl<S, C, const D: usize, A, B> Observer<S, C, D> for (A, B)
where
    S: GroupLagrangian<D>,
    C: GroupChart<S::Group, D>,
    A: Observer<S, C, D>,
    B: Observer<S, C, D, Error = A::Error>,
{
    type Error = A::Error;
    fn after_step(
        &mut self,
        integrator: &Integrator<S, C, D>,
        step: StepInfo,
    ) -> Result<Flow, A::Error> {
        let first = self.0.after_step(integrator, step)?;
        let second = self.1.after_step(integrator, step)?;
        Ok(if first == Flow::Stop || second == Flow::Stop {
            Flow::Stop
        } else {
            Flow::Continue
        })
    }
}

/// Records the initial state, every `every`-th state and the last one of a driven run,
/// with each recorded step's Newton iterations: what [`Integrator::run`] returns.
#[derive(Debug, Clone)]
pub struct Recorder<E, const D: usize> {
    every: usize,
    trajectory: Trajectory<E, D>,
}

impl<E: Copy, const D: usize> Recorder<E, D> {
    /// From the run's initial state, recording every `every`-th step (at least 1), with
    /// room for a run of `steps` steps.
    pub fn new(start: &State<E, D>, every: usize, steps: usize) -> Self {
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
    pub(super) fn push(&mut self, state: State<E, D>, iterations: usize) {
        self.trajectory.states.push(state);
        self.trajectory.newton_iterations.push(iterations);
    }
}

impl<S, C, const D: usize> Observer<S, C, D> for Recorder<ElementOf<S, D>, D>
where
    S: GroupLagrangian<D>,
    C: GroupChart<S::Group, D>,
{
    type Error = MechanicsError;
    fn after_step(
        &mut self,
        integrator: &Integrator<S, C, D>,
        step: StepInfo,
    ) -> Result<Flow, MechanicsError> {
        if step.index.is_multiple_of(self.every) || step.last {
            self.push(*integrator.state(), step.iterations);
        }
        Ok(Flow::Continue)
    }
}

impl<S, C, const D: usize, O> Observer<S, C, D> for &mut O
where
    S: GroupLagrangian<D>,
    C: GroupChart<S::Group, D>,
    O: Observer<S, C, D> + ?Sized,
{
    type Error = O::Error;
    fn after_step(
        &mut self,
        integrator: &Integrator<S, C, D>,
        step: StepInfo,
    ) -> Result<Flow, O::Error> {
        (**self).after_step(integrator, step)
    }
}

impl<S: GroupLagrangian<D>, C: GroupChart<S::Group, D>, const D: usize> Integrator<S, C, D> {
    /// Takes up to `steps` steps, telling `observer` after each; returns the steps taken
    /// (fewer when the observer stopped the run).
    ///
    /// # Errors
    /// A failed step ([`Integrator::step`]'s errors, through the observer's error type) or
    /// the observer's own; the integrator keeps the last good state.
    pub fn drive<O: Observer<S, C, D>>(
        &mut self,
        steps: usize,
        observer: &mut O,
    ) -> Result<usize, O::Error> {
        drive_by(self, steps, observer, Integrator::step, |it| it)
    }
}

/// The driving loop over anything that steps (`step`) and shows an integrator (`view`):
/// [`Integrator::drive`], and [`crate::Checked::drive`] with its primary run.
pub(crate) fn drive_by<T, S, C, O, const D: usize>(
    target: &mut T,
    steps: usize,
    observer: &mut O,
    step: fn(&mut T) -> Result<usize, MechanicsError>,
    view: fn(&T) -> &Integrator<S, C, D>,
) -> Result<usize, O::Error>
where
    S: GroupLagrangian<D>,
    C: GroupChart<S::Group, D>,
    O: Observer<S, C, D>,
{
    for index in 1..=steps {
        let iterations = step(target)?;
        let info = StepInfo {
            index,
            iterations,
            last: index == steps,
        };
        if observer.after_step(view(target), info)? == Flow::Stop {
            return Ok(index);
        }
    }
    Ok(steps)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Inertia, RigidBody};
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
                Flow::Stop
            } else {
                Flow::Continue
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
        let mut recorder = Recorder::new(b.state(), 3, 7);
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
                Ok(Flow::Continue)
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
        let mut quiet = each(|_: &Integrator<RigidBody>, _| Ok::<_, Mine>(Flow::Continue));
        assert!(matches!(it.drive(5, &mut quiet), Err(Mine::Mechanics)));
        assert_eq!(it.state().time, 0.0);
    }
}
