//! Numerical experiments on Lie group spectral variational integrators, as a library.
//!
//! The studies the `lgsvi` command line runs (`lgsvi converge`, the paper's figures in
//! `lgsvi reproduce`, the comparisons of `lgsvi bench`) are functions here that return data — no files, no strings to
//! parse — so that a library user runs them on their own systems:
//!
//! - [`convergence`]: n-refinement (nodes at a fixed step) and h-refinement (steps at a
//!   fixed node count) against the closed-form free rigid body or a high-accuracy run,
//!   with the global error at the final time, along the Galerkin curves inside the steps,
//!   energy and momentum drifts, Newton iterations and wall time per run;
//! - [`fit`]: the geometric factor of an n-refinement series and the algebraic order of
//!   an h-refinement series, fitted on the asymptotic points only (above the rounding
//!   floor, below saturation);
//! - [`tolerance`]: the calibration of the steps' error estimates against their true local
//!   errors, and tolerance-driven runs beside the fastest fixed `(h, n)` as accurate, for
//!   any group;
//! - [`work_precision`]: work-precision points, the fastest run at an error target, the most
//!   accurate run, and the median timing they share;
//! - [`paper`]: the measurements behind the figures of Hall and Leok's paper (n- and
//!   h-refinement, long runs, momenta on the sphere, the unstable pendulum), as data;
//! - [`record`]: a run to its horizon, every state checked and every `every`-th recorded
//!   with its energy, work, translation or wheels and the integrator's statistics (what
//!   `lgsvi simulate` writes), for SO(3), SE(3) and the gyrostats;
//! - [`scenario`]: the built-in systems (free body, heavy top, body in space, orbiting body,
//!   gyrostat) built from plain parameters and run as one type, whatever their group;
//! - [`conserved`]: how far energy, the Casimir `|μ|²` and the spatial momentum `Rμ` (or
//!   its conserved component) have moved from their initial values.
//!
//! A study runs a [`Subject`]: a system, its start and its settings. [`Body`] is the
//! ready-made one; [`scenario::Scenario`] is the built-in systems' (what the command line
//! runs).
//!
//! ```
//! use lgsvi_experiments::convergence::{study, Reference, Refinement};
//! use lgsvi_experiments::Body;
//! use lgsvi_mechanics::lie::SO3;
//! use lgsvi_mechanics::{Inertia, RigidBody, StepSettings};
//! use nalgebra::Vector3;
//!
//! # fn main() -> Result<(), lgsvi_experiments::ExperimentError> {
//! let inertia = Inertia::from_principal_moments([3.3, 2.5, 3.4])?;
//! let body = Body::new(
//!     RigidBody::new(inertia),
//!     SO3::identity(),
//!     Vector3::new(-2.0, 1.9, -1.0),
//!     StepSettings::new(0.5, 4)?,
//! )
//! .with_exact_solution(inertia);
//! let t_end = 2.0;
//! let reference = Reference::for_subject(&body, t_end)?;
//! let refinement = Refinement {
//!     h: 0.5,
//!     nodes: vec![4, 6, 8],
//!     steps: vec![0.5, 0.25],
//!     step_nodes: vec![3],
//!     t_end,
//!     curve_samples: 4,
//! };
//! let result = study(&body, &reference, &refinement, || {})?;
//! // Geometric convergence in n: each node added divides the error.
//! let errors: Vec<f64> = result.nodes_refinement.iter().map(|m| m.error_r).collect();
//! assert!(errors[2] < errors[1] && errors[1] < errors[0]);
//! assert!(result.geometric_factors[0].3.unwrap() > 5.0);
//! # Ok(())
//! # }
//! ```

#![warn(missing_docs)]

pub mod conserved;
pub mod control;
pub mod convergence;
mod error;
pub mod fit;
pub mod paper;
pub mod record;
pub mod scenario;
pub mod stop;
mod subject;
pub mod tolerance;
pub mod work_precision;

pub use conserved::{Drift, Symmetry, Tracker};
pub use error::ExperimentError;
pub use subject::{Body, Subject};

#[doc(hidden)]
pub use lgsvi_mechanics::gyrostat as __gyrostat;

/// This crate's `README.md`, whose Rust example is compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
