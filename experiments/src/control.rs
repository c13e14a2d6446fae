//! A sampled controller in the loop: the PD law of [`PdLaw`] (with its torque limit)
//! evaluated every `period` from the run's start and held until the next sample
//! (zero-order hold), as a flight computer runs it. [`crate::record::record_until`] and
//! [`crate::scenario::Scenario::record`] take one beside the run's own drive.
//!
//! The sampling instants fall on steps' starts (the period a whole number of steps,
//! [`SampledLaw::check_step`]; the sampler counts steps), so each step's input is constant
//! and the step keeps its accuracy; an event located inside a step (a stop or settling
//! condition) is refined with the input of the step that holds it.

use crate::error::ExperimentError;
use crate::record::Columns;
use lgsvi_mechanics::control::PdLaw;
use lgsvi_mechanics::group::GroupChart;
use lgsvi_mechanics::stepper::{Observer, StepInfo};
use lgsvi_mechanics::system::{ElementOf, System};
use lgsvi_mechanics::{Integrator, MechanicsError};
use nalgebra::SVector;
use std::ops::ControlFlow;

/// How far from a whole number of steps a period may be and still be one (relative): the
/// rounding of a period and a step given as decimals (`0.7 / 0.1`).
const WHOLE: f64 = 1e-9;

/// A [`PdLaw`] sampled every `period` (seconds) and held between samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampledLaw {
    law: PdLaw,
    period: f64,
}

fn refused(value: String, reason: &'static str) -> ExperimentError {
    ExperimentError::Parameter {
        parameter: "control",
        source: MechanicsError::InvalidSetting {
            name: "sample period",
            value,
            reason,
        },
    }
}

/// The refusal of a sampled law on a gyrostat, whose input is its wheels' motor torques.
pub(crate) fn on_a_gyrostat() -> ExperimentError {
    ExperimentError::Parameter {
        parameter: "control",
        source: MechanicsError::InvalidSetting {
            name: "sampled attitude law",
            value: "on a gyrostat".into(),
            reason: "a gyrostat turns by its wheels' motor torques (Wheels::torque), not by a \
                     body torque",
        },
    }
}

impl SampledLaw {
    /// `law` sampled every `period`.
    ///
    /// # Errors
    /// [`ExperimentError::Parameter`] for a period that is not positive and finite.
    pub fn new(law: PdLaw, period: f64) -> Result<Self, ExperimentError> {
        if !(period.is_finite() && period > 0.0) {
            return Err(refused(
                format!("{period:?}"),
                "the controller's sample period must be positive and finite",
            ));
        }
        Ok(Self { law, period })
    }

    /// The law.
    pub fn law(&self) -> &PdLaw {
        &self.law
    }

    /// The sample period.
    pub fn period(&self) -> f64 {
        self.period
    }

    /// Refuses a step `h` that does not divide the period into a whole number of steps
    /// (the held torque would change inside a step, where the step assumes it constant).
    ///
    /// # Errors
    /// [`ExperimentError::Parameter`] naming the step and the period.
    pub fn check_step(&self, h: f64) -> Result<(), ExperimentError> {
        self.steps(h).map(|_| ())
    }

    /// The steps of `h` in a period, where they are a whole number.
    fn steps(&self, h: f64) -> Result<u64, ExperimentError> {
        let steps = self.period / h;
        if !(steps.is_finite() && steps.round() >= 1.0)
            || (steps - steps.round()).abs() > WHOLE * steps
        {
            return Err(refused(
                format!("{} with steps of {h}", self.period),
                "the sample period must be a whole number of steps: take the step h as the \
                 period divided by a whole number",
            ));
        }
        Ok(steps.round() as u64)
    }

    /// The observer that sets the law's torque at the start of a run of steps `h` and
    /// every period after it ([`Observer::input`]), for a run of fixed steps.
    ///
    /// # Errors
    /// As [`SampledLaw::check_step`].
    pub fn observer(&self, h: f64) -> Result<Sampler, ExperimentError> {
        Ok(Sampler {
            law: self.law,
            every: self.steps(h)?,
            taken: 0,
        })
    }
}

/// The observer of [`SampledLaw::observer`]: before the first step and every `T/h` steps
/// after it, the law's torque from that step's start state, held by the steps after it
/// until the next sample.
#[derive(Debug, Clone, Copy)]
pub struct Sampler {
    law: PdLaw,
    every: u64,
    taken: u64,
}

impl<S, C, const D: usize> Observer<S, C, D> for Sampler
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: Columns<D>,
{
    type Error = ExperimentError;

    fn after_step(
        &mut self,
        _integrator: &Integrator<S, C, D>,
        _step: StepInfo,
    ) -> Result<ControlFlow<()>, ExperimentError> {
        Ok(ControlFlow::Continue(()))
    }

    fn input(&mut self, integrator: &Integrator<S, C, D>) -> Option<SVector<f64, D>> {
        let at_sample = self.taken.is_multiple_of(self.every);
        self.taken += 1;
        if !at_sample {
            return None;
        }
        let (rotation, _, _) = ElementOf::<S, D>::columns(integrator.state());
        let torque = self.law.torque(&rotation.configuration, &rotation.velocity);
        // The torque in the input's rotational entries: a rigid body's three, a body in
        // space's first three of (torque, force).
        Some(SVector::<f64, D>::from_fn(|i, _| {
            if i < 3 {
                torque[i]
            } else {
                0.0
            }
        }))
    }
}
