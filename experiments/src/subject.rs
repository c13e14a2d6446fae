//! What a study runs: a system on SO(3), its start, its settings, and what it conserves.

use crate::conserved::{Symmetry, Tracker};
use lgsvi_mechanics::exact::FreeRigidBodyExact;
use lgsvi_mechanics::group::Rotations;
use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::{Inertia, Integrator, MechanicsError, State, StepSettings, System};
use nalgebra::Vector3;

/// A problem on SO(3) that the studies of this crate run: the system, its initial state
/// and the settings whose chart, matching and Newton Jacobian every run of a study keeps
/// (the studies vary the step and the node count).
pub trait Subject {
    /// The system: any SO(3) system, forced or not.
    type System: System<3, Group = Rotations>;

    /// The system, for energies.
    fn system(&self) -> &Self::System;

    /// The base settings of every run.
    fn settings(&self) -> StepSettings;

    /// An integrator from the initial state with `settings`.
    fn integrator(
        &self,
        settings: StepSettings,
    ) -> Result<Integrator<Self::System>, MechanicsError>;

    /// What the run conserves: by default what the system says it conserves
    /// ([`Symmetry::of`]: all of `Rμ` for a free, unforced body, `d·Rμ` for a heavy top's
    /// gravity direction `d`, nothing under a torque or damping).
    fn symmetry(&self) -> Symmetry {
        Symmetry::of(self.system())
    }

    /// The conservation tracker from the run's initial `state`, with [`Subject::symmetry`].
    fn tracker(&self, state: &State) -> Tracker {
        Tracker::with_symmetry(
            state.energy(self.system()),
            state.attitude().matrix(),
            &state.momentum,
            self.symmetry(),
        )
    }

    /// Whether the system is free and unforced (left invariant, no force): it then
    /// conserves `|μ|²` and all of `Rμ`.
    fn is_free(&self) -> bool {
        self.system().is_left_invariant() && !self.system().is_forced()
    }

    /// The closed-form solution, where one is known (a free rigid body); `None` otherwise,
    /// and then a study measures against a high-accuracy run.
    fn exact(&self) -> Option<Result<FreeRigidBodyExact, MechanicsError>>;
}

/// A ready-made [`Subject`]: a system, its initial attitude and body angular velocity,
/// and the base settings.
#[derive(Debug, Clone)]
pub struct Body<S> {
    system: S,
    attitude0: SO3,
    omega0: Vector3<f64>,
    settings: StepSettings,
    exact: Option<Inertia>,
    axis: Option<Vector3<f64>>,
}

impl<S: System<3, Group = Rotations> + Clone> Body<S> {
    /// `system` from `(attitude0, omega0)`, every run with `settings`' chart, matching and
    /// Newton Jacobian. Conservation is tracked for what the system says it conserves
    /// ([`Symmetry::of`]: all of `Rμ` for a free, unforced body, `d·Rμ` for a heavy top's
    /// gravity direction `d`), unless [`Body::with_conserved_axis`] names another axis.
    pub fn new(system: S, attitude0: SO3, omega0: Vector3<f64>, settings: StepSettings) -> Self {
        Self {
            system,
            attitude0,
            omega0,
            settings,
            exact: None,
            axis: None,
        }
    }

    /// Measure against the closed-form free rigid body of this inertia (the caller states
    /// that `system` is that free body; `Body` cannot look inside a generic system).
    pub fn with_exact_solution(mut self, inertia: Inertia) -> Self {
        self.exact = Some(inertia);
        self
    }

    /// The spatial direction about which the system is symmetric (a heavy top's gravity
    /// direction): only `d·Rμ` is then tracked as conserved.
    pub fn with_conserved_axis(mut self, axis: Vector3<f64>) -> Self {
        self.axis = Some(axis);
        self
    }
}

impl<S: System<3, Group = Rotations> + Clone> Subject for Body<S> {
    type System = S;
    fn system(&self) -> &S {
        &self.system
    }
    fn settings(&self) -> StepSettings {
        self.settings
    }
    fn integrator(&self, settings: StepSettings) -> Result<Integrator<S>, MechanicsError> {
        Integrator::new(self.system.clone(), settings, self.attitude0, self.omega0)
    }
    fn symmetry(&self) -> Symmetry {
        self.axis.map_or(Symmetry::of(&self.system), Symmetry::Axis)
    }
    fn exact(&self) -> Option<Result<FreeRigidBodyExact, MechanicsError>> {
        self.exact
            .map(|inertia| FreeRigidBodyExact::new(inertia, self.attitude0, self.omega0))
    }
}
