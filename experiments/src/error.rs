//! What can go wrong in an experiment.

use lgsvi_mechanics::MechanicsError;

/// An experiment's failure: a run that could not be built or did not finish, or a reference
/// asked outside what it covers.
#[derive(Debug, thiserror::Error)]
pub enum ExperimentError {
    /// From the integrator, a system or a setting (its message says what to change).
    #[error(transparent)]
    Mechanics(#[from] MechanicsError),
    /// A failure inside a named run (the reference run, for example).
    #[error("{context}: {source}")]
    Run {
        /// Which run.
        context: String,
        /// What failed.
        source: MechanicsError,
    },
    /// A recorded state or invariant overflowed ([`crate::record`]).
    #[error(
        "step {step} (t = {time}): the {quantity} is not finite ({values}): a quantity of the run \
         left double precision's range, from inputs of very different sizes (an inertia, mass, \
         gravity, distance or velocity far above or below the others): express them in units \
         that make them comparable"
    )]
    Overflow {
        /// The step.
        step: usize,
        /// Its time.
        time: f64,
        /// Which quantity.
        quantity: &'static str,
        /// Its values.
        values: String,
    },
    /// A system's parameter that its constructor refused.
    #[error("{parameter}: {source}")]
    Parameter {
        /// The parameter(s), as the model's fields name them (`mass`, `mass/mu`,
        /// `axes/inertia`, `speeds0/torque`, `drive`).
        parameter: &'static str,
        /// Why.
        source: MechanicsError,
    },
    /// A start the system cannot take (the orbiting body at its attracting centre).
    #[error("invalid start {value}: {reason}")]
    InvalidStart {
        /// The start, as given.
        value: String,
        /// Why, and what to change.
        reason: String,
    },
    /// A stop condition the run cannot watch.
    #[error("stop condition {condition}: {reason}")]
    Stop {
        /// The condition, as given.
        condition: String,
        /// Why, and what to give.
        reason: String,
    },
    /// The reference run has no Galerkin curve at this time (it ended before it).
    #[error(
        "the reference has no curve at t = {0}: its run ended before that time; build the \
         reference to a horizon at or past the study's"
    )]
    NoReferenceCurve(f64),
}
