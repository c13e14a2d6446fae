//! Many initial conditions, integrated in parallel (rayon).
//!
//! Each member gets its own [`Integrator`] (its own workspace), so the members share
//! nothing but the system and the settings, and the result of each is bit-for-bit the one
//! a sequential run gives. The work runs on rayon's current thread pool: wrap the call in
//! `rayon::ThreadPool::install` to choose the number of threads.

use crate::error::MechanicsError;
use crate::integrator::{Integrator, Statistics};
use crate::lagrangian::Lagrangian;
use crate::settings::StepSettings;
use crate::state::State;
use lgsvi_lie::SO3;
use nalgebra::Vector3;
use rayon::prelude::*;

/// One member's initial condition: attitude and body angular velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialCondition {
    /// `R(0) = world_from_body`.
    pub attitude: SO3,
    /// `Ω(0)`, body frame.
    pub velocity: Vector3<f64>,
}

/// What one member of an ensemble ends with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnsembleMember {
    /// The state after the last step.
    pub state: State,
    /// Its Newton statistics.
    pub statistics: Statistics,
}

/// Integrates `steps` steps from every initial condition in parallel and returns, in the
/// order of `initial`, each member's final state or the error that stopped it (a member's
/// failure does not stop the others).
///
/// ```
/// use lgsvi_mechanics::ensemble::{run_ensemble, InitialCondition};
/// use lgsvi_mechanics::lie::SO3;
/// use lgsvi_mechanics::{Inertia, RigidBody, StepSettings};
/// use nalgebra::Vector3;
///
/// let body = RigidBody::new(Inertia::from_principal_moments([1.0, 2.0, 3.0])?);
/// let initial: Vec<InitialCondition> = (0..8)
///     .map(|k| InitialCondition {
///         attitude: SO3::identity(),
///         velocity: Vector3::new(1.0, 0.1 * k as f64, 0.5),
///     })
///     .collect();
/// let results = run_ensemble(&body, &StepSettings::new(0.5, 8)?, &initial, 10);
/// assert_eq!(results.len(), 8);
/// for member in results {
///     assert!((member?.state.time - 5.0).abs() < 1e-12);
/// }
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
pub fn run_ensemble<L>(
    system: &L,
    settings: &StepSettings,
    initial: &[InitialCondition],
    steps: usize,
) -> Vec<Result<EnsembleMember, MechanicsError>>
where
    L: Lagrangian + Clone + Send + Sync,
{
    initial
        .par_iter()
        .map(|start| {
            let mut integrator =
                Integrator::new(system.clone(), *settings, start.attitude, start.velocity)?;
            for _ in 0..steps {
                integrator.step()?;
            }
            Ok(EnsembleMember {
                state: *integrator.state(),
                statistics: *integrator.statistics(),
            })
        })
        .collect()
}
