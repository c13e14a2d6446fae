//! Gauss quadrature rules, accurate to a few ulps for thousands of points.
//!
//! # What it computes
//! Rules `∫_a^b f(x) dx ≈ Σ_i w_i f(x_i)` of the Legendre family (weight function 1):
//!
//! | function | nodes | exact for degree |
//! |---|---|---|
//! | [`gauss_legendre`]`(m)` | roots of `P_m` | `2m − 1` |
//! | [`gauss_lobatto`]`(m)` | `±1` and the roots of `P_{m−1}'` | `2m − 3` |
//! | [`gauss_radau_left`]`(m)` / [`gauss_radau_right`]`(m)` | one end and the roots of `(P_{m−1} ± P_m)/(1 ± x)` | `2m − 2` |
//!
//! the classical weighted families (every one exact for degree `2m − 1`):
//!
//! | function | `∫ w(x) f(x) dx` with `w(x) =` | on |
//! |---|---|---|
//! | [`gauss_hermite`]`(m)` | `e^{−x²}` | the real line |
//! | [`gauss_laguerre`]`(m, α)` | `x^α e^{−x}` | `[0, ∞)` |
//! | [`gauss_jacobi`]`(m, α, β)` | `(1 − x)^α (1 + x)^β` | `[−1, 1]` (any `[a, b]` by [`Rule::on`]) |
//! | [`gauss_chebyshev_first`]`(m)` / [`gauss_chebyshev_second`]`(m)` | `1/√(1 − x²)` / `√(1 − x²)` | `[−1, 1]` |
//!
//! and, for any other weight function whose three-term recurrence you know, the raw
//! [`golub_welsch`] algorithm. [`gauss_kronrod`]`(n)` extends the `n`-point Gauss–Legendre
//! rule to `2n + 1` points with an error estimate ([`GaussKronrod`]), and
//! [`gauss_kronrod_jacobi`]`(n, α, β)` the Gauss–Jacobi rule where such an extension exists.
//! Infinite intervals without a weight: a Gauss–Legendre rule through an algebraic map,
//! [`Rule::on_half_line`] (`[a, ∞)`) and [`Rule::on_real_line`]; vector- and
//! matrix-valued integrands: [`Rule::integrate_into`].
//!
//! # Conventions
//! - Rules are built on the reference interval `[−1, 1]` and mapped to `[a, b]` by
//!   [`Rule::on`]; nodes are **ascending**; weights include the factor `(b − a)/2`.
//! - `m` is always the number of points.
//!
//! # How, and how accurate
//! Golub–Welsch (eigenvalues of the Jacobi matrix by implicit QL, `O(m²)`) gives nodes to
//! about `m ε`; Newton on the Legendre three-term recurrence polishes each to the nearest
//! doubles; the weights come from closed forms evaluated once in double-double precision
//! at the polished node, corrected to the true root. Against a committed 60-digit mpmath
//! reference (`tests/data/generate_reference.py`), for `m` from 1 to 500: node errors at
//! most `4ε` and relative weight errors at most `8ε` (pinned by the tests). Hermite,
//! Laguerre and Jacobi rules below 100 points take the same path on their own recurrences,
//! with the weights from the Christoffel function in double-double (`O(m²)`); from 100
//! points on they are `O(m)`: the roots are found one after the other along the line from
//! the differential equation `P y'' + Q y' + R y = 0` every classical polynomial solves
//! (Glaser, Liu & Rokhlin), by local Taylor series carried in double-double, each weight
//! `∝ 1/(P(x_k) y'(x_k)²)` normalised by the total mass. Against
//! `tests/data/generate_classical.py` (m from 1 to 1000, 10 weight functions) every node is
//! the double nearest the reference root (Chebyshev's closed forms within half an ulp) and
//! every weight above 1e-300 within `2.9ε` relative, and against
//! `tests/data/generate_classical_large.py` (m = 10⁴ and 10⁵, sampled indices, 6 weight
//! functions) within the same bounds; the tests hold them to `4ε` of `max(|x|, 1)` and
//! `16ε` (at most `2.9ε` in the weights, every node exact). Building a rule by the march
//! takes time linear in `m`, which makes rules of 10⁴ to 10⁶ points practical, far beyond
//! the sizes the `O(m²)` path builds in reasonable time.
//! Gauss–Legendre from 100 points on is `O(m)`: the asymptotic expansions in
//! `θ = arccos x` (Hale–Townsend, every term kept, no iteration), within `2.2ε` in the
//! nodes and `1.9ε` in the weights of the 60-digit reference at `m = 100` and `500`, and
//! within the same `4ε` and `8ε` at a million points (sampled nodes, and the extreme ones
//! against mpmath).
//!
//! # Example
//! ```
//! use lgsvi_quadrature::gauss_legendre;
//!
//! // ∫_0^π sin x dx = 2 with 10 Gauss points (error ~ 1e-20 in exact arithmetic).
//! let rule = gauss_legendre(10)?.on(0.0, std::f64::consts::PI)?;
//! let integral = rule.integrate(f64::sin);
//! assert!((integral - 2.0).abs() < 4.0 * f64::EPSILON);
//! # Ok::<(), lgsvi_quadrature::QuadratureError>(())
//! ```
#![deny(missing_docs)]

mod classical;
mod double_double;
mod error;
mod golub_welsch;
mod kronrod;
mod legendre;
mod legendre_asymptotic;
mod ode_march;
mod rule;
mod rules;
mod symmetric;

pub use classical::{
    gauss_chebyshev_first, gauss_chebyshev_second, gauss_hermite, gauss_jacobi, gauss_laguerre,
};
pub use error::QuadratureError;
pub use golub_welsch::golub_welsch;
pub use kronrod::{gauss_kronrod, gauss_kronrod_jacobi, GaussKronrod};
pub use rule::{Rule, RuleKind};
pub use rules::{gauss_legendre, gauss_lobatto, gauss_radau_left, gauss_radau_right};

/// This crate's `README.md`, whose Rust example is compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
