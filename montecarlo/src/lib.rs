//! Monte Carlo dispersion analysis for lgsvi: thousands of runs of a rigid body or
//! spacecraft whose parameters and start are dispersed about a nominal, each member
//! reproducible from `(seed, member)` alone.
//!
//! - [`dispersion`] draws the members: a [`Plan`] checks the dispersions against the
//!   nominal body up front (no member can be non-physical) and gives member `i` the same
//!   draws on any machine, thread count or order.
//! - [`statistics`] summarises them with bounded memory: percentiles over the members
//!   ([`statistics::Quantiles`], within 0.55% of the exact sample percentiles, merged
//!   exactly in any order) per output and sample time ([`statistics::Envelope`]).
//!
//! ```
//! use lgsvi_mechanics::lie::SO3;
//! use lgsvi_mechanics::Inertia;
//! use lgsvi_montecarlo::{Body, Dispersion, Dispersions, Plan};
//! use nalgebra::Vector3;
//!
//! let inertia = Inertia::from_principal_moments([3.3, 2.5, 3.4])?;
//! let nominal = Body::new(inertia, SO3::identity(), Vector3::new(0.1, 0.0, 0.0));
//! let dispersions = Dispersions {
//!     omega: Some(Dispersion::Normal { sigma: 0.01 }),
//!     inertia: Some(Dispersion::TruncatedNormal { sigma: 0.02, bound: 0.06 }),
//!     attitude: Some(Dispersion::Uniform { half_width: 0.05 }),
//!     ..Dispersions::default()
//! };
//! let plan = Plan::new(nominal, dispersions, 42)?;
//! let member = plan.member(7)?;
//! assert_eq!(member, plan.member(7)?); // (seed, index) alone
//! assert!((member.body.omega.x - 0.1).abs() < 0.1);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

pub mod dispersion;
pub mod statistics;

pub use dispersion::{Body, Dispersion, DispersionError, Dispersions, Member, Plan};

/// The user guide's page (`docs/guide/montecarlo.md`), whose Rust example is compiled and
/// run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../../docs/guide/montecarlo.md")]
pub struct GuidePage;

/// This crate's `README.md`, whose Rust example is compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
