//! Many initial conditions, integrated in parallel (rayon), for any system on any group.
//!
//! Each member gets its own [`Integrator`] (its own workspace), so the members share
//! nothing but the system and the settings, and the result of each is bit-for-bit the one
//! a sequential run gives. The work runs on rayon's current thread pool: wrap the call in
//! `rayon::ThreadPool::install` to choose the number of threads.

use crate::error::MechanicsError;
use crate::group::GroupChart;
use crate::integrator::{Integrator, Statistics};
use crate::settings::StepSettings;
use crate::state::State;
use crate::stepper::{each, Stepper};
use crate::system::{ElementOf, System};
use lgsvi_lie::{ChartKind, SO3};
use nalgebra::SVector;
use rayon::prelude::*;
use std::ops::ControlFlow;

/// One member's initial condition: the configuration `g(0)` and the body velocity `ξ(0)`,
/// on any group (SO(3) by default: attitude `R(0) = world_from_body` and `Ω(0)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialCondition<E = SO3, const D: usize = 3> {
    /// `g(0)`: on SO(3), the attitude `R(0) = world_from_body`.
    pub configuration: E,
    /// `ξ(0)`, body frame: on SO(3), `Ω(0)`.
    pub velocity: SVector<f64, D>,
}

/// What one member of an ensemble ends with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnsembleMember<E = SO3, const D: usize = 3> {
    /// The state after the last step.
    pub state: State<E, D>,
    /// Its Newton statistics.
    pub statistics: Statistics,
}

/// Integrates `steps` steps from every initial condition in parallel and returns, in the
/// order of `initial`, each member's final state or the error that stopped it (a member's
/// failure does not stop the others). Any system on any group: an SO(3) body, a body in
/// space on SE(3), a gyrostat.
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
///         configuration: SO3::identity(),
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
pub fn run_ensemble<S, const D: usize>(
    system: &S,
    settings: &StepSettings,
    initial: &[InitialCondition<ElementOf<S, D>, D>],
    steps: usize,
) -> Vec<Result<EnsembleMember<ElementOf<S, D>, D>, MechanicsError>>
where
    S: System<D> + Clone + Send + Sync,
    ElementOf<S, D>: Send + Sync,
    ChartKind: GroupChart<S::Group, D>,
{
    each_member(system, settings, initial, |integrator| {
        for _ in 0..steps {
            integrator.step()?;
        }
        Ok(())
    })
}

/// As [`run_ensemble`], each member run to exactly `t_end` ([`crate::Stepper::run_until`]'s
/// steps: steps of `h`, the last shortened to land on `t_end`).
///
/// ```
/// use lgsvi_mechanics::ensemble::{run_ensemble_until, InitialCondition};
/// use lgsvi_mechanics::prelude::*;
///
/// let body = RigidBody::new(Inertia::from_principal_moments([1.0, 2.0, 3.0])?);
/// let initial = [InitialCondition { configuration: SO3::identity(), velocity: Vector3::new(1.0, 0.2, 0.5) }];
/// let results = run_ensemble_until(&body, &StepSettings::new(0.5, 8)?, &initial, 1.2);
/// assert_eq!(results[0].as_ref().unwrap().state.time, 1.2);
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
pub fn run_ensemble_until<S, const D: usize>(
    system: &S,
    settings: &StepSettings,
    initial: &[InitialCondition<ElementOf<S, D>, D>],
    t_end: f64,
) -> Vec<Result<EnsembleMember<ElementOf<S, D>, D>, MechanicsError>>
where
    S: System<D> + Clone + Send + Sync,
    ElementOf<S, D>: Send + Sync,
    ChartKind: GroupChart<S::Group, D>,
{
    each_member(system, settings, initial, |integrator| {
        let mut quiet = each(|_: &Integrator<S, ChartKind, D>, _| {
            Ok::<_, MechanicsError>(ControlFlow::Continue(()))
        });
        integrator.drive_until(t_end, &mut quiet).map(|_| ())
    })
}

/// Every member's integrator from its start, advanced by `advance`, in parallel; each
/// member's final state and statistics or the error that stopped it.
fn each_member<S, const D: usize>(
    system: &S,
    settings: &StepSettings,
    initial: &[InitialCondition<ElementOf<S, D>, D>],
    advance: impl Fn(&mut Integrator<S, ChartKind, D>) -> Result<(), MechanicsError> + Sync,
) -> Vec<Result<EnsembleMember<ElementOf<S, D>, D>, MechanicsError>>
where
    S: System<D> + Clone + Send + Sync,
    ElementOf<S, D>: Send + Sync,
    ChartKind: GroupChart<S::Group, D>,
{
    initial
        .par_iter()
        .map(|start| {
            let mut integrator = Integrator::new(
                system.clone(),
                *settings,
                start.configuration,
                start.velocity,
            )?;
            advance(&mut integrator)?;
            Ok(EnsembleMember {
                state: *integrator.state(),
                statistics: *integrator.statistics(),
            })
        })
        .collect()
}
