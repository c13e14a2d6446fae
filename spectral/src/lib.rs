//! Chebyshev points and barycentric Lagrange bases.
//!
//! # What it computes
//! - Nodes on any interval `[a, b]`, **ascending**: [`chebyshev_lobatto`] (the `n`
//!   extrema of `T_{n−1}`, both ends included — "second kind") and [`chebyshev_first_kind`]
//!   (the `n` roots of `T_n`).
//! - [`Barycentric`]: the Lagrange basis `φ_0, …, φ_{n−1}` of any distinct nodes
//!   (`φ_i(x_k) = δ_ik`, polynomials of degree `n − 1`), evaluated by the barycentric
//!   formula of Berrut & Trefethen: interpolants and their derivatives at any point,
//!   all `n` basis functions and first derivatives at once (no allocation), evaluation
//!   and derivative matrices at a set of points (`B[j][i] = φ_i(c_j)`,
//!   `D[j][i] = φ_i'(c_j)`, row-major [`Matrix`]), and the differentiation matrix on the
//!   nodes.
//! - Chebyshev coefficients of the interpolant through Chebyshev–Lobatto values and back
//!   ([`chebyshev_coefficients`], [`chebyshev_values`]: the DCT-I, by an FFT from
//!   [`FFT_FROM`] points on; [`chebyshev_coefficient_matrix`]): the decay a spectral method
//!   reads its own error from.
//! - [`Chebyshev`]: a function held as its Chebyshev series, fitted adaptively to machine
//!   precision (chebfun's plateau and chop rule), with Clenshaw evaluation that refuses
//!   points outside its interval, derivative, indefinite and definite integrals, roots
//!   (colleague-matrix eigenvalues), range, sums, products and composition.
//!
//! # Conventions
//! - `n` is the number of nodes; the degree is `n − 1`.
//! - The map from the reference interval is `x = a(1 − t)/2 + b(1 + t)/2`, which puts the
//!   Chebyshev–Lobatto ends exactly on `a` and `b`.
//! - Evaluation exactly at a node returns the Kronecker delta and the exact row of the
//!   differentiation matrix; a point one ulp away is just as accurate (no 0/0).
//!
//! # Example
//! ```
//! use lgsvi_spectral::Barycentric;
//!
//! // Runge's function on 100 Chebyshev–Lobatto points: error ~ ρ^{-n}, ρ = 0.2 + √1.04.
//! let runge = |x: f64| 1.0 / (1.0 + 25.0 * x * x);
//! let basis = Barycentric::chebyshev_lobatto(100, -1.0, 1.0)?;
//! let values: Vec<f64> = basis.nodes().iter().map(|&x| runge(x)).collect();
//! let x = 0.123;
//! assert!((basis.interpolate(&values, x)? - runge(x)).abs() < 1e-8);
//! # Ok::<(), lgsvi_spectral::SpectralError>(())
//! ```
#![deny(missing_docs)]

mod barycentric;
mod chebyshev;
mod coefficients;
mod error;
mod matrix;
mod nodes;

pub use barycentric::Barycentric;
pub use chebyshev::{Chebyshev, MAX_FIT_POINTS};
pub use coefficients::{
    chebyshev_coefficient_matrix, chebyshev_coefficients, chebyshev_values, FFT_FROM,
};
pub use error::SpectralError;
pub use matrix::Matrix;
pub use nodes::{chebyshev_first_kind, chebyshev_lobatto};

/// This crate's `README.md`, whose Rust example is compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
