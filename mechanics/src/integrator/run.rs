//! Driving the integrator to a horizon: the step count to it, and the integrator's
//! [`Stepper`] implementation (the shortened last step, and the run to a horizon of a run
//! whose step may change).

use super::*;
use crate::stepper::{run_until_by_steps, Recorder, Stepper};

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

impl<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> Integrator<S, C, D> {
    /// The number of steps of length `h` from the current time to reach `t_end` or pass
    /// it by less than `h` ([`crate::Stepper::run_until`] shortens the last one to land on
    /// `t_end`).
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for a non-finite or negative `t_end`, a `t_end`
    /// before the current time, more than 2⁵³ steps (beyond what the step count can hold
    /// exactly as a time), and a run whose step may change
    /// ([`StepSettings::with_step_changes`]): it has no fixed number of steps
    /// ([`crate::Stepper::run_until`] takes it to `t_end`).
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
        let steps = (remaining / self.settings.h() - 1e-9).ceil().max(0.0);
        Self::check_step_count(t_end, steps)?;
        Ok(steps as usize)
    }

    /// A horizon must be finite, non-negative and not before the current time (within a
    /// billionth of a step: the rounding of the time's sums).
    pub(crate) fn check_end(&self, t_end: f64) -> Result<(), MechanicsError> {
        check_horizon(t_end)?;
        if t_end < self.state.time - 1e-9 * self.settings.h() {
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
    pub(crate) fn check_step_count(t_end: f64, steps: f64) -> Result<(), MechanicsError> {
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
}

impl<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> Stepper<S, C, D>
    for Integrator<S, C, D>
{
    fn step(&mut self) -> Result<usize, MechanicsError> {
        Integrator::step(self)
    }

    /// A step of length `h`, the settings' step kept for the steps after; a run whose step
    /// may change takes it as its next step.
    fn step_by(&mut self, h: f64) -> Result<usize, MechanicsError> {
        let (least, most) = crate::settings::STEP_RANGE;
        if !(h.is_finite() && (least..=most).contains(&h)) {
            return Err(MechanicsError::InvalidSetting {
                name: "h",
                value: format!("{h:?}"),
                reason: "a step's length lies within 1e-280 to 1e280",
            });
        }
        if self.settings.adaptive().is_some_and(|a| a.step_changes) {
            self.control.next_step = Some(h);
            return Integrator::step(self);
        }
        let step = self.settings.h();
        self.switch_step(h)?;
        let last = Integrator::step(self);
        let curve = if last.is_ok() && h != step {
            self.last_curve()
        } else {
            None
        };
        self.switch_step(step)?;
        self.other_length_curve = curve;
        last
    }

    fn integrator(&self) -> &Integrator<S, C, D> {
        self
    }

    fn set_input(&mut self, input: SVector<f64, D>) -> Result<(), MechanicsError> {
        Integrator::set_input(self, input)
    }

    /// As [`Stepper::run_until`]; a run whose step may change
    /// ([`StepSettings::with_step_changes`]) likewise shortens its last step to end on
    /// `t_end`.
    fn run_until(
        &mut self,
        t_end: f64,
        every: usize,
    ) -> Result<Trajectory<ElementOf<S, D>, D>, MechanicsError> {
        if !self.settings.adaptive().is_some_and(|a| a.step_changes) {
            return run_until_by_steps(self, t_end, every);
        }
        self.check_end(t_end)?;
        let every = every.max(1);
        let mut recorder = Recorder::new(&self.state, 0, every);
        let mut k = 0;
        // Within a billionth of a step of the end counts as there (rounding of the sums).
        while t_end - self.state.time > 1e-9 * self.settings.h() {
            let left = t_end - self.state.time;
            let h = self.control.next_step.unwrap_or(self.settings.h());
            if h > left {
                self.control.next_step = Some(left);
            }
            let iterations = Integrator::step(self)?;
            k += 1;
            let done = t_end - self.state.time <= 1e-9 * self.settings.h();
            if k % every == 0 || done {
                recorder.push(self.state, iterations);
            }
        }
        Ok(recorder.into_trajectory())
    }
}
