//! What can stop a measurement.

use lgsvi_baselines::BaselineError;
use lgsvi_mechanics::MechanicsError;

/// A measurement's failure (a failed run inside a sweep is a data point, not an error).
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// From lgsvi: a setting or a run.
    #[error(transparent)]
    Mechanics(#[from] MechanicsError),
    /// From a baseline integrator.
    #[error(transparent)]
    Baseline(#[from] BaselineError),
    /// A failure inside a named run.
    #[error("{context}: {source}")]
    Run {
        /// Which run.
        context: String,
        /// What failed.
        source: MechanicsError,
    },
    /// The thread pool of an ensemble could not be built.
    #[error("thread pool: {0}")]
    ThreadPool(#[from] rayon::ThreadPoolBuildError),
    /// A measurement that could not be set up (its members' draws, no setting that reaches
    /// its accuracy).
    #[error("{0}")]
    Setup(String),
}
