//! The group and chart laws, written once for any group: run them on your own group and
//! chart with your own examples, as this crate's tests run them on SO(3) and SE(3).
//!
//! [`group_laws`] checks, on the elements and algebra vectors you give, the axioms
//! (identity, inverse, associativity), the exponential map (`log ∘ exp`, one-parameter
//! subgroups), the adjoint (a homomorphism, conjugation `g exp(ξ) g⁻¹ = exp(Ad_g ξ)`, the
//! coadjoint pairing), and the algebra (`vee ∘ hat`, `ad` antisymmetric, the Jacobi
//! identity, `ad` as the derivative of `Ad` by central differences). [`chart_laws`] checks a
//! chart: `Φ(0) = e`, `Φ⁻¹ ∘ Φ`, the trivialised differentials against central differences
//! of `Φ`, and their inverses. Each returns the largest error of every law, or the first
//! law that fails, with its size.
//!
//! Errors are measured as distances in the algebra, `|log(a⁻¹ b)|∞` between elements and
//! the largest entry between vectors and matrices, against `tolerance` times the scale of
//! the examples (at least 1); the laws that differentiate numerically (`ad` from `Ad`, the
//! differentials) are held to `max(tolerance, 1e-6)` times that scale instead, the accuracy
//! of a central difference at a step of 1e-5.
//!
//! ```
//! use lgsvi_lie::laws::{chart_laws, group_laws};
//! use lgsvi_lie::{CayleyChart, SO3};
//! use nalgebra::Vector3;
//!
//! let elements = [SO3::about_x(0.3), SO3::exp(&Vector3::new(0.5, -1.0, 2.0)), SO3::identity()];
//! let tangents = [Vector3::new(0.1, 0.2, -0.3), Vector3::new(-1.0, 0.4, 0.9)];
//! let report = group_laws(&elements, &tangents, 1e-13)?;
//! assert!(report.iter().any(|(law, _)| *law == "associativity"));
//! chart_laws::<SO3, _, 3>(&CayleyChart, &tangents, 1e-13)?;
//! # Ok::<(), lgsvi_lie::laws::LawViolation>(())
//! ```

use crate::{Chart, LieGroup, SE3, SO3};
use nalgebra::{RealField, SMatrix, SVector};

/// The exponential map and its inverse near the identity, which the laws read.
pub trait ExponentialMap: LieGroup {
    /// `exp(ξ)`.
    fn exp(xi: &Self::Tangent) -> Self;
    /// `log(g)`, the inverse of `exp` near the identity.
    fn log(&self) -> Self::Tangent;
}

impl<T: RealField + Copy> ExponentialMap for SO3<T> {
    fn exp(xi: &Self::Tangent) -> Self {
        SO3::exp(xi)
    }
    fn log(&self) -> Self::Tangent {
        SO3::log(self)
    }
}

impl<T: RealField + Copy> ExponentialMap for SE3<T> {
    fn exp(xi: &Self::Tangent) -> Self {
        SE3::exp(xi)
    }
    fn log(&self) -> Self::Tangent {
        SE3::log(self)
    }
}

/// A law that does not hold on the examples: which, where and by how much.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("the law \"{law}\" fails by {error:e} (allowed {allowed:e}) at example {example}")]
pub struct LawViolation {
    /// The law.
    pub law: &'static str,
    /// Its largest error on the examples.
    pub error: f64,
    /// What it was allowed.
    pub allowed: f64,
    /// The example (element or vector index) where it failed.
    pub example: usize,
}

/// Every law checked, with its largest error on the examples.
pub type LawReport = Vec<(&'static str, f64)>;

/// Collects each law's largest error and stops at the first that exceeds its allowance.
struct Laws {
    report: LawReport,
}

impl Laws {
    fn check(
        &mut self,
        law: &'static str,
        errors: impl IntoIterator<Item = f64>,
        allowed: f64,
    ) -> Result<(), LawViolation> {
        let mut largest = 0.0f64;
        for (example, error) in errors.into_iter().enumerate() {
            if error.is_nan() || error > allowed {
                return Err(LawViolation {
                    law,
                    error,
                    allowed,
                    example,
                });
            }
            largest = largest.max(error);
        }
        self.report.push((law, largest));
        Ok(())
    }
}

fn largest<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> f64 {
    m.iter().fold(0.0f64, |a, x| {
        if x.is_nan() || a.is_nan() {
            f64::NAN
        } else {
            a.max(x.abs())
        }
    })
}

/// The distance of two elements in the algebra, `|log(a⁻¹ b)|∞`.
fn distance<G, const N: usize>(a: &G, b: &G) -> f64
where
    G: ExponentialMap<Scalar = f64, Tangent = SVector<f64, N>>,
{
    largest(&a.inverse().compose(b).log())
}

/// The finite-difference step of the differentiating laws.
const STEP: f64 = 1e-5;

/// Checks the group laws on `elements` and `tangents` (module documentation): all pairs and
/// triples of the examples. The elements should lie within the logarithm's domain of each
/// other's products (rotations below a half turn apart, say).
///
/// # Errors
/// The first law that fails, with its size ([`LawViolation`]).
pub fn group_laws<G, const N: usize>(
    elements: &[G],
    tangents: &[SVector<f64, N>],
    tolerance: f64,
) -> Result<LawReport, LawViolation>
where
    G: ExponentialMap<Scalar = f64, Tangent = SVector<f64, N>, Jacobian = SMatrix<f64, N, N>>,
{
    let scale = tangents
        .iter()
        .map(largest)
        .chain(elements.iter().map(|g| largest(&g.log())))
        .fold(1.0f64, f64::max);
    let exact = tolerance * scale;
    let differenced = tolerance.max(1e-6) * scale * scale;
    let e = G::identity();
    let mut laws = Laws { report: Vec::new() };
    laws.check(
        "identity",
        elements
            .iter()
            .map(|a| distance(&a.compose(&e), a).max(distance(&e.compose(a), a))),
        exact,
    )?;
    laws.check(
        "inverse",
        elements
            .iter()
            .map(|a| distance(&a.compose(&a.inverse()), &e)),
        exact,
    )?;
    let triples = elements.iter().flat_map(|a| {
        elements
            .iter()
            .flat_map(move |b| elements.iter().map(move |c| (a, b, c)))
    });
    laws.check(
        "associativity",
        triples.map(|(a, b, c)| distance(&a.compose(b).compose(c), &a.compose(&b.compose(c)))),
        exact,
    )?;
    laws.check(
        "log ∘ exp",
        tangents.iter().map(|xi| largest(&(G::exp(xi).log() - xi))),
        exact,
    )?;
    laws.check(
        "one-parameter subgroup",
        tangents.iter().map(|xi| {
            distance(
                &G::exp(&(xi * 0.3)).compose(&G::exp(&(xi * 0.5))),
                &G::exp(&(xi * 0.8)),
            )
        }),
        exact,
    )?;
    laws.check(
        "vee ∘ hat",
        tangents
            .iter()
            .map(|xi| largest(&(G::vee(&G::hat(xi)) - xi))),
        exact,
    )?;
    let pairs = elements
        .iter()
        .flat_map(|a| elements.iter().map(move |b| (a, b)));
    laws.check(
        "adjoint homomorphism",
        pairs.map(|(a, b)| largest(&(a.compose(b).adjoint() - a.adjoint() * b.adjoint()))),
        exact,
    )?;
    let conjugations = elements
        .iter()
        .flat_map(|a| tangents.iter().map(move |xi| (a, xi)));
    laws.check(
        "conjugation",
        conjugations.map(|(a, xi)| {
            distance(
                &a.compose(&G::exp(xi)).compose(&a.inverse()),
                &G::exp(&(a.adjoint() * xi)),
            )
        }),
        exact,
    )?;
    let pairings = elements.iter().flat_map(|a| {
        tangents
            .iter()
            .flat_map(move |mu| tangents.iter().map(move |xi| (a, mu, xi)))
    });
    laws.check(
        "coadjoint pairing",
        pairings.map(|(a, mu, xi)| {
            (a.coadjoint_action(mu).dot(&(a.adjoint() * xi)) - mu.dot(xi)).abs()
        }),
        exact,
    )?;
    let brackets = tangents
        .iter()
        .flat_map(|xi| tangents.iter().map(move |eta| (xi, eta)));
    laws.check(
        "ad antisymmetric",
        brackets
            .clone()
            .map(|(xi, eta)| largest(&(G::small_adjoint(xi) * eta + G::small_adjoint(eta) * xi))),
        exact,
    )?;
    laws.check(
        "Jacobi identity",
        tangents.iter().flat_map(|z| {
            brackets.clone().map(move |(x, y)| {
                let ad = |a: &SVector<f64, N>, b: &SVector<f64, N>| G::small_adjoint(a) * b;
                largest(&(ad(x, &ad(y, z)) + ad(y, &ad(z, x)) + ad(z, &ad(x, y))))
            })
        }),
        exact * scale,
    )?;
    laws.check(
        "ad the derivative of Ad",
        brackets.map(|(xi, eta)| {
            let plus = G::exp(&(xi * STEP)).adjoint() * eta;
            let minus = G::exp(&(xi * -STEP)).adjoint() * eta;
            largest(&((plus - minus) / (2.0 * STEP) - G::small_adjoint(xi) * eta))
        }),
        differenced,
    )?;
    Ok(laws.report)
}

/// Checks the chart laws of `chart` at the algebra vectors `tangents` (within its domain):
/// `Φ(0) = e`, `Φ⁻¹(Φ(ξ)) = ξ`, the left- and right-trivialised differentials against
/// central differences of `Φ` (`Φ(ξ)⁻¹ Φ(ξ + εv) ≈ exp(ε A(ξ) v)`,
/// `Φ(ξ + εv) Φ(ξ)⁻¹ ≈ exp(ε B(ξ) v)`), and their inverses.
///
/// # Errors
/// The first law that fails, with its size ([`LawViolation`]); a chart operation that
/// refuses a vector counts as a failure of its law.
pub fn chart_laws<G, C, const N: usize>(
    chart: &C,
    tangents: &[SVector<f64, N>],
    tolerance: f64,
) -> Result<LawReport, LawViolation>
where
    G: ExponentialMap<Scalar = f64, Tangent = SVector<f64, N>, Jacobian = SMatrix<f64, N, N>>,
    C: Chart<G>,
{
    let scale = tangents.iter().map(largest).fold(1.0f64, f64::max);
    let exact = tolerance * scale;
    let differenced = tolerance.max(1e-6) * scale;
    let mut laws = Laws { report: Vec::new() };
    laws.check(
        "Φ(0) = e",
        [distance(&chart.to_group(&SVector::zeros()), &G::identity())],
        exact,
    )?;
    laws.check(
        "Φ⁻¹ ∘ Φ",
        tangents
            .iter()
            .map(|xi| match chart.to_algebra(&chart.to_group(xi)) {
                Ok(back) => largest(&(back - xi)),
                Err(_) => f64::NAN,
            }),
        exact,
    )?;
    let basis = |k: usize| SVector::<f64, N>::from_fn(|i, _| if i == k { 1.0 } else { 0.0 });
    let columns = |xi: &SVector<f64, N>, left: bool| {
        SMatrix::<f64, N, N>::from_fn(|i, k| {
            let g = chart.to_group(xi);
            let plus = chart.to_group(&(xi + basis(k) * STEP));
            let minus = chart.to_group(&(xi - basis(k) * STEP));
            let (p, m) = if left {
                (g.inverse().compose(&plus), g.inverse().compose(&minus))
            } else {
                (plus.compose(&g.inverse()), minus.compose(&g.inverse()))
            };
            ((p.log() - m.log()) / (2.0 * STEP))[i]
        })
    };
    laws.check(
        "left differential",
        tangents
            .iter()
            .map(|xi| largest(&(columns(xi, true) - chart.left_differential(xi)))),
        differenced,
    )?;
    laws.check(
        "right differential",
        tangents
            .iter()
            .map(|xi| largest(&(columns(xi, false) - chart.right_differential(xi)))),
        differenced,
    )?;
    let identity = SMatrix::<f64, N, N>::identity();
    laws.check(
        "differential inverses",
        tangents.iter().map(|xi| {
            match (
                chart.left_differential_inverse(xi),
                chart.right_differential_inverse(xi),
            ) {
                (Ok(left), Ok(right)) => largest(&(chart.left_differential(xi) * left - identity))
                    .max(largest(&(chart.right_differential(xi) * right - identity))),
                _ => f64::NAN,
            }
        }),
        exact * 16.0,
    )?;
    Ok(laws.report)
}
