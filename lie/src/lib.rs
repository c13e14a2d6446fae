//! SO(3) and SE(3) with the exponential and Cayley natural charts.
//!
//! # What it provides
//! - [`SO3`] and [`SE3`] (rotation matrix storage; conversions to and from nalgebra's
//!   `Rotation3`, `UnitQuaternion`, `Isometry3`, glam's `DMat3`, `DQuat`, `DAffine3`
//!   behind the `glam` feature, serde behind `serde`; `approx` comparisons), under one
//!   [`LieGroup`] trait: composition, inverse, action on points, `hat`/`vee`, `Ad`, `ad`,
//!   the coadjoint action.
//! - One trait family for any Lie group, these and yours: [`LieGroup`] (an element type at
//!   one scalar) with [`ExponentialMap`]; [`ConfigurationGroup`] (a group over every scalar
//!   at once, a marker type whose `Element<T>` is a [`LieGroup`]: [`Rotations`],
//!   [`RigidMotions`], [`product::BodyAndWheels`] for SO(3) × ℝᴷ) and [`GroupChart`] (its
//!   chart over every scalar, with [`ChartDerivatives`], the derivatives of its
//!   differential, in closed form ([`jet`]) or by dual numbers): what lgsvi's integrator,
//!   linearisation and optimiser are generic over.
//! - The group and chart laws ([`laws`]), written once, for any group and chart of your
//!   own to run with its own examples.
//! - Charts `Φ: 𝔤 → G` ([`Chart`]): [`ExpChart`], [`CayleyChart`] and the
//!   [`UnscaledCayleyChart`] of Hall and Leok, each with `Φ`, `Φ⁻¹`, the left- and
//!   right-trivialised differentials and their inverses in closed form, on SO(3) and on
//!   SE(3); the natural chart at a point ([`NaturalChart`]); the right and left Jacobians
//!   of SO(3) ([`so3::right_jacobian`], ...).
//!
//! # Conventions
//! - `R ∈ SO(3)` is `world_from_body`: it maps body coordinates to world coordinates;
//!   compose frames as `a_from_c = a_from_b * b_from_c`.
//! - Body angular velocity `Ω`: `Ṙ = R Ω̂`, with
//!   `hat(a, b, c) = [[0, −c, b], [c, 0, −a], [−b, a, 0]]`; [`so3::vee`] inverts it.
//! - SE(3) tangent vectors are ordered **`(ω, v)`**, rotation first; `ẋ = R v`.
//! - Left-trivialised differential `A(ξ)`: `Φ(ξ)⁻¹ DΦ(ξ)[v] = (A(ξ) v)^`;
//!   right-trivialised `B(ξ)`: `DΦ(ξ)[v] Φ(ξ)⁻¹ = (B(ξ) v)^`. For exp, `A = J_r`, `B = J_l`.
//! - Quaternions are Hamilton's, `(w, x, y, z)` with the scalar first where this crate
//!   spells them out; the quaternion returned for a rotation has `w ≥ 0`.
//! - Matrices are printed and serialised row-major.
//! - Domains: Cayley charts are singular at rotation angle `π`; `exp` is a local
//!   diffeomorphism for `|ξ| < 2π` and `log` is defined for angles below `π`. Leaving a
//!   domain is a [`LieError::OutsideChart`], never a NaN.
//!
//! # Automatic differentiation
//! Everything is generic over the scalar `T: nalgebra::RealField + Copy`, so dual
//! numbers (e.g. `num_dual::Dual64`, `Dual2Vec64`) pass through `Φ`, the differentials
//! and the group operations, and exact derivatives of anything built from them come by
//! changing the scalar type. The small-angle branches are Taylor series in `θ²`, smooth at
//! `0`, so derivatives stay exact there. The tests check the closed-form differentials
//! against automatic differentiation and central differences.
//!
//! # Example
//! ```
//! use lgsvi_lie::{Chart, ExpChart, LieGroup, NaturalChart, SO3};
//! use nalgebra::Vector3;
//!
//! // A body turning at Ω = (0, 0, 1) rad/s for 0.5 s, in the natural chart at its attitude.
//! let world_from_body = SO3::about_x(0.3);
//! let chart = NaturalChart::new(world_from_body, ExpChart);
//! let later = chart.to_group(&Vector3::new(0.0, 0.0, 0.5));
//! let body_rotation = world_from_body.inverse() * later;
//! assert!((body_rotation.log() - Vector3::new(0.0, 0.0, 0.5)).norm() < 1e-15);
//! ```
#![deny(missing_docs)]

mod chart;
mod configuration;
mod error;
mod group;
mod group_chart;
pub mod jet;
pub mod laws;
pub mod product;
mod scalar;
pub mod se3;
mod series;
pub mod so3;

pub use chart::{
    CayleyChart, Chart, ChartKind, ExpChart, NaturalChart, ParseChartError, RodriguesCoefficients,
    So3Chart, UnscaledCayleyChart,
};
pub use configuration::{coadjoint_generator_of, ConfigurationGroup, RigidMotions, Rotations};
pub use error::LieError;
pub use group::{ExponentialMap, LieGroup};
#[doc(hidden)]
pub use group_chart::RotationTranslationDerivatives;
pub use group_chart::{dual_number_derivatives, ChartDerivatives, GroupChart, Screw};
pub use se3::SE3;
pub use so3::SO3;

/// This crate's `README.md`, whose Rust example is compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
