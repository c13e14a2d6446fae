//! What most programs that use this crate need, in one import:
//! `use lgsvi_mechanics::prelude::*;`.
//!
//! The integrator and its builder, the [`Stepper`] trait that gives them `run`,
//! `run_until` and `drive`, the built-in systems and forces, settings and states, the
//! error type, the groups SO(3) and SE(3) with the chart kinds, and nalgebra's vectors and
//! matrices of the sizes the systems use.

pub use crate::forces::{
    AngularDamping, AttitudeSpring, BodyTorque, ForceOfTime, Forcing, SpaceForce,
};
pub use crate::gyrostat::Gyrostat;
pub use crate::lie::{ChartKind, SE3, SO3};
pub use crate::tolerance::CheckedIntegrator;
pub use crate::{
    Forced, FreeBody, GroupLagrangian, HeavyTop, Inertia, Integrator, Matching, MechanicsError,
    OrbitingBody, RigidBody, State, StepSettings, Stepper, System, Trajectory,
};
pub use nalgebra::{Matrix3, SVector, Vector3};
