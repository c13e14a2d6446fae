//! Driving the integrator over many steps: fixed step counts, to a horizon, with progress
//! (each through [`Integrator::drive`] and a [`Recorder`], or, for a run whose step
//! changes, the same recorder on its own loop).

use super::drive::{each, Flow, Recorder, StepInfo};
use super::*;

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

impl<S: GroupLagrangian<D>, C: GroupChart<S::Group, D>, const D: usize> Integrator<S, C, D> {
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
        let mut recorder = Recorder::new(&self.state, every, steps);
        let report = each(|_: &Self, step: StepInfo| {
            progress(step.index);
            Ok::<_, MechanicsError>(Flow::Continue)
        });
        self.drive(steps, &mut (&mut recorder, report))?;
        Ok(recorder.into_trajectory())
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
    pub(super) fn check_end(&self, t_end: f64) -> Result<(), MechanicsError> {
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
    pub(super) fn check_step_count(t_end: f64, steps: f64) -> Result<(), MechanicsError> {
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
        let mut recorder = Recorder::new(&self.state, every, 0);
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
                recorder.push(self.state, iterations);
            }
        }
        Ok(recorder.into_trajectory())
    }
}
