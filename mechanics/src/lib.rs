//! Lie group spectral variational integrators (Hall & Leok) for rotating and moving
//! bodies: one core for any Lie group and chart ([`group`]), with systems on SO(3)
//! ([`RigidBody`], [`HeavyTop`], [`RigidBodyInPotential`]) and SE(3) ([`FreeBody`],
//! [`OrbitingBody`], [`BodyInField`]), forces and control inputs by the discrete
//! Lagrange–d'Alembert principle ([`Forced`], [`Integrator::set_input`]) and full inertia
//! tensors ([`Inertia::from_tensor`]).
//!
//! # The method (written here for SO(3); on any group `R` is `g`, `Ω` is `ξ`, and `Rμ`
//! is the coadjoint `Ad_{g⁻¹}ᵀ μ`)
//! A step from `(R_k, μ_k)` looks for a curve `R(t) = R_k Φ(ξ(t))` in a natural chart
//! (`Φ`: exp, Cayley, or the paper's unscaled Cayley), with `ξ(t)` a polynomial on `n`
//! Chebyshev–Lobatto nodes of `[0, h]` (`ξ¹ = 0`), that makes the discrete action
//! `S = Σ_j h b_j ℓ(R(c_j h), Ω(c_j h))` (`m` Gauss points) stationary with respect to the
//! interior nodes, and matches the incoming body momentum. Then `R_{k+1} = R_k Φ(ξⁿ)` and
//! `μ_{k+1} = A(ξⁿ)⁻ᵀ ∂S/∂ξⁿ` (taken in the form the matching equation makes it
//! equal to, `Φ(ξⁿ)ᵀ(μ_k + Σ_j h b_j Φ(x_j) p_j)` with `p_j` the configuration forces at the
//! Gauss points, zero for a free body: `R_{k+1} μ_{k+1}` then carries no Newton residual). The momentum matching is by default the **exact** derivative
//! of the discrete Lagrangian, so the map is exactly variational: spatial angular momentum
//! `Rμ` of a free body (and its vertical component for the heavy top) is conserved to
//! rounding and the energy error stays bounded. The paper's own recipe is available
//! ([`Matching::Paper`]) for reproducing its figures; it drifts.
//!
//! Newton uses the exact Jacobian: every Gauss point's gradient and Hessian of
//! `ℓ(R_k Φ(x), A(x) v)` come by the chain rule from the chart's derivatives (closed
//! forms from its Rodrigues coefficients) and `ℓ`'s own first and second derivatives in
//! `(R, Ω)`, which dual numbers (num-dual) take unless the system gives them in closed
//! form (the built-in ones do). So a system is defined by writing `ℓ` once
//! ([`GroupLagrangian`]), never its derivatives. The predictor integrates the
//! system's own equations of motion over the step (a few classical Runge–Kutta substeps
//! in the chart, when the system gives `Ω(μ)` in closed form; otherwise it continues the
//! last step's Galerkin curve), so that one Newton matrix per step is the rule: once it
//! is factored at a residual below 1e-4 of the equations' terms it is kept for chord
//! steps until their predicted remainder is below 1e-20, far below rounding (a remainder
//! at the floor would have a fixed sign along a trajectory and drift). Steps from the
//! quadratic regime are never backtracked. On the exp chart a step may rotate the body
//! past a half turn (up to about 5 rad per step on the paper's rigid body).
//!
//! # Validation
//! [`exact::FreeRigidBodyExact`] is the exact motion of the free rigid body (Jacobi
//! elliptic functions for `Ω(t)`, the precession angle in closed form for `R(t)`), in every
//! regime; the project measures every free-body error against it.
//!
//! # Conventions
//! `R = world_from_body`, `Ṙ = RΩ̂`, `μ = ∂ℓ/∂Ω` (body momentum), spatial momentum `Rμ`.
//! Inertia: the standard `J` or the paper's `J_d` ([`Inertia`]). `n` is the number of
//! nodes (degree `n − 1`), `m` the number of Gauss points (default `n`), `h` the step.
//!
//! # Example
//! ```
//! use lgsvi_mechanics::prelude::*;
//!
//! // The paper's 3D pendulum near its stable equilibrium, h = 0.5, 8 nodes.
//! let top = HeavyTop::paper(Inertia::from_paper_jd([1.0, 2.8, 2.0])?)?;
//! let mut integrator = Integrator::builder(top)
//!     .start(SO3::identity(), Vector3::new(0.5, -0.5, 0.4))
//!     .step(0.5)
//!     .nodes(8)
//!     .build()?;
//! let e0 = integrator.state().energy(&top);
//! integrator.run(20, 1)?;
//! assert!((integrator.state().energy(&top) - e0).abs() < 1e-8 * e0.abs());
//! # Ok::<(), lgsvi_mechanics::MechanicsError>(())
//! ```
//!
//! # Where things are
//! | module | what it holds |
//! |---|---|
//! | the crate root, [`prelude`] | the integrator and its builder, the built-in systems, settings, states, errors |
//! | [`stepper`] | the driving loop and its observers ([`Stepper`], [`stepper::Observer`], [`stepper::Recorder`]) |
//! | [`events`] | zero crossings of functions of the state, located on the steps and recorded or ending a run |
//! | [`tolerance`] | tolerance-driven and checked runs ([`tolerance::CheckedIntegrator`]) and their policy |
//! | [`forces`] | forces and control inputs by the Lagrange–d'Alembert principle |
//! | [`settings`] | step settings and their limits |
//! | [`integrator`] | the integrator's dense output and statistics |
//! | [`system`] | the systems' trait and the closed-form paths of the built-in ones |
//! | [`group`] | the configuration groups and charts the integrator is generic over (`lgsvi_lie`'s traits, re-exported), your own included, and its storage of their derivatives |
//! | [`control`], [`linearization`] | the exact linearisation of a step, discrete LQR, regulators |
//! | [`gyrostat`], [`exact`], [`ensemble`] | reaction wheels, the exact free rigid body, parallel ensembles |
//! | [`built_in`] | the built-in systems as one type per group, chosen at run time |
#![deny(missing_docs)]

mod builder;
pub mod built_in;
mod chart_flow;
pub mod control;
pub mod ensemble;
mod error;
pub mod events;
pub mod exact;
mod flow;

pub mod forces;
pub mod group;
pub mod gyrostat;
pub mod inertia;
pub mod integrator;
mod jet;
mod jet_lanes;
mod lagrangian;
pub mod linearization;
mod point;
pub mod prelude;
mod rigid_motion;
pub mod settings;
pub mod state;
mod step;
pub mod stepper;
pub mod system;
pub mod tolerance;

pub use builder::IntegratorBuilder;
pub use error::MechanicsError;
pub use inertia::Inertia;
pub use integrator::{Integrator, Trajectory};
pub use lagrangian::{HeavyTop, Potential, RigidBody, RigidBodyInPotential};
/// The geometry layer, re-exported so that users of this crate need no second import.
pub use lgsvi_lie as lie;
pub use rigid_motion::{BodyInField, FieldPotential, FreeBody, OrbitingBody};
pub use settings::{Matching, StepSettings};
pub use state::State;
pub use stepper::Stepper;
pub use system::{Forced, GroupLagrangian, System};

/// This crate's `README.md`, whose Rust example is compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
