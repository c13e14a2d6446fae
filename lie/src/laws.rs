//! The group and chart laws, written once for any group: run them on your own group and
//! chart with your own examples, as this crate's tests run them on SO(3), SE(3), SO(3) × ℝᴷ
//! and every chart of theirs.
//!
//! [`group_laws`] checks, on the elements and algebra vectors you give, the axioms
//! (identity, inverse, associativity), the exponential map (`log ∘ exp`, one-parameter
//! subgroups), the adjoint (a homomorphism, conjugation `g exp(ξ) g⁻¹ = exp(Ad_g ξ)`, the
//! coadjoint pairing), and the algebra (`vee ∘ hat`, `ad` antisymmetric, the Jacobi
//! identity, `ad` as the derivative of `Ad` by central differences). [`chart_laws`] checks a
//! chart: `Φ(0) = e`, `Φ⁻¹ ∘ Φ`, the trivialised differentials against central differences
//! of `Φ`, and their inverses. Each returns the largest error of every law, or the first
//! law that fails, with its size. [`configuration_group_laws`] checks what a
//! [`ConfigurationGroup`] gives besides its elements (the lift to other scalars, `exp` to
//! second order, the coadjoint generator, the checks that an element is on the group), and
//! [`group_chart_laws`] checks a
//! [`GroupChart`], the chart of a [`ConfigurationGroup`] over every scalar that an integrator
//! reads: the chart laws through it, and that what it gives in closed form (the chart
//! velocity, the transport of covectors, the derivatives of `A`) agrees with what it must
//! give.
//!
//! Errors are measured as distances in the algebra, `|log(a⁻¹ b)|∞` between elements and
//! the largest entry between vectors and matrices, against `tolerance` times the scale of
//! the examples (at least 1); the laws that differentiate numerically (`ad` from `Ad`, the
//! differentials) are held to `max(tolerance, 1e-6)` times that scale instead, the accuracy
//! of a central difference at a step of 1e-5. (The consistency laws of
//! [`group_chart_laws`] are relative; its documentation says how.)
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

use crate::chart::Chart;
use crate::configuration::{coadjoint_generator_of, ConfigurationGroup};
use crate::error::LieError;
use crate::group::{ExponentialMap, LieGroup};
use crate::group_chart::{dual_number_derivatives, ChartDerivatives, GroupChart};
use nalgebra::{SMatrix, SVector};

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
            // A NaN error, or any error against a NaN allowance, is not within it.
            let within = matches!(
                error.partial_cmp(&allowed),
                Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal)
            );
            if !within {
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

/// The largest of `errors`, NaN if any is (`f64::max` drops a NaN).
fn worst(errors: impl IntoIterator<Item = f64>) -> f64 {
    errors.into_iter().fold(0.0f64, |a, e| {
        if a.is_nan() || e.is_nan() {
            f64::NAN
        } else {
            a.max(e)
        }
    })
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
            .map(|a| worst([distance(&a.compose(&e), a), distance(&e.compose(a), a)])),
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
                (Ok(left), Ok(right)) => worst([
                    largest(&(chart.left_differential(xi) * left - identity)),
                    largest(&(chart.right_differential(xi) * right - identity)),
                ]),
                _ => f64::NAN,
            }
        }),
        exact * 16.0,
    )?;
    Ok(laws.report)
}

/// A [`GroupChart`] read as a [`Chart`] of its elements over `f64`, for [`chart_laws`]:
/// `Φ⁻¹` is `to_algebra_near` the origin, and the right-trivialised differential is
/// `B(ξ) = Ad_{Φ(ξ)} A(ξ)` (from `DΦ Φ⁻¹ = Φ (Φ⁻¹ DΦ) Φ⁻¹`), with inverse `A⁻¹ Ad_{Φ⁻¹}`.
struct AsChart<'a, G, C, const D: usize> {
    chart: &'a C,
    group: std::marker::PhantomData<G>,
}

impl<G, C, const D: usize> Chart<G::Element<f64>> for AsChart<'_, G, C, D>
where
    G: ConfigurationGroup<D>,
    C: GroupChart<G, D>,
{
    fn name(&self) -> &'static str {
        self.chart.name()
    }
    fn to_group(&self, xi: &SVector<f64, D>) -> G::Element<f64> {
        self.chart.to_group(xi)
    }
    fn to_algebra(&self, g: &G::Element<f64>) -> Result<SVector<f64, D>, LieError> {
        self.chart.to_algebra_near(g, &SVector::zeros())
    }
    fn check_domain(&self, xi: &SVector<f64, D>) -> Result<(), LieError> {
        self.chart.check_domain(xi)
    }
    fn left_differential(&self, xi: &SVector<f64, D>) -> SMatrix<f64, D, D> {
        self.chart.left_differential(xi)
    }
    fn left_differential_inverse(
        &self,
        xi: &SVector<f64, D>,
    ) -> Result<SMatrix<f64, D, D>, LieError> {
        self.chart.left_differential_inverse(xi)
    }
    fn right_differential(&self, xi: &SVector<f64, D>) -> SMatrix<f64, D, D> {
        self.chart.to_group(xi).adjoint() * self.chart.left_differential(xi)
    }
    fn right_differential_inverse(
        &self,
        xi: &SVector<f64, D>,
    ) -> Result<SMatrix<f64, D, D>, LieError> {
        Ok(self.chart.left_differential_inverse(xi)? * self.chart.to_group(xi).inverse().adjoint())
    }
}

/// Checks a [`GroupChart`] of a [`ConfigurationGroup`] (the chart an integrator reads) on
/// `tangents`: the laws of [`chart_laws`], read through it (`Φ⁻¹` near the origin, the
/// right differential `Ad_Φ A`), and the consistency of what a chart may give in closed
/// form with what it must give:
/// - "chart velocity": [`GroupChart::chart_velocity`] is `A(ξ)⁻¹ η`;
/// - "transport": [`GroupChart::coadjoint_to_start`] and
///   [`GroupChart::transport_and_differential`] are `Ad_{Φ(ξ)⁻¹}ᵀ` and `A(ξ)`;
/// - "chart derivatives": [`GroupChart::with_derivatives`] (a closed form, where the chart
///   overrides it) against [`dual_number_derivatives`]:
///   `A`, `∂(Aη)/∂ξ`, `∂(Aᵀη)/∂ξ` and `∇²(μᵀAη)`, with `η`, `μ` the next examples in turn.
///
/// `Φ⁻¹` is read on the branch nearest the origin, so the examples should be there too
/// (rotations below a half turn). The derivatives are compared with second derivatives
/// asked for and without (the first-order route), and, where a chart gives SE(3)'s block
/// form ([`ChartDerivatives::rotation_translation`]), that form too. The consistency laws
/// compare two exact routes: each error is taken relative to the larger of 1 and the
/// reference's largest entry, and held to `64 × tolerance` (the routes sum the same
/// products in different orders). Give at least three examples: the contractions take the
/// next two examples as their vectors.
///
/// ```
/// use lgsvi_lie::laws::group_chart_laws;
/// use lgsvi_lie::{ExpChart, RigidMotions, Rotations};
/// use nalgebra::{SVector, Vector3};
///
/// let w = [Vector3::new(0.1, 0.2, -0.3), Vector3::new(-1.0, 0.4, 0.9)];
/// group_chart_laws::<Rotations, _, 3>(&ExpChart, &w, 1e-13)?;
/// let xi = [SVector::<f64, 6>::new(0.1, 0.2, -0.3, 1.0, -2.0, 0.5)];
/// group_chart_laws::<RigidMotions, _, 6>(&ExpChart, &xi, 1e-13)?;
/// # Ok::<(), lgsvi_lie::laws::LawViolation>(())
/// ```
///
/// # Errors
/// The first law that fails, with its size ([`LawViolation`]).
pub fn group_chart_laws<G, C, const D: usize>(
    chart: &C,
    tangents: &[SVector<f64, D>],
    tolerance: f64,
) -> Result<LawReport, LawViolation>
where
    G: ConfigurationGroup<D>,
    G::Element<f64>: ExponentialMap,
    C: GroupChart<G, D>,
{
    let mut report = chart_laws::<G::Element<f64>, _, D>(
        &AsChart::<G, C, D> {
            chart,
            group: std::marker::PhantomData,
        },
        tangents,
        tolerance,
    )?;
    // Two exact routes agree to rounding relative to the quantity compared.
    let relative =
        |a: &SMatrix<f64, D, D>, b: &SMatrix<f64, D, D>| largest(&(a - b)) / largest(b).max(1.0);
    let consistent = 64.0 * tolerance;
    let mut laws = Laws { report: Vec::new() };
    let next = |i: usize, k: usize| tangents[(i + k) % tangents.len()];
    laws.check(
        "chart velocity",
        tangents.iter().enumerate().map(|(i, xi)| {
            let eta = next(i, 1);
            match (
                chart.left_differential_inverse(xi),
                chart.chart_velocity(xi, &chart.to_group(xi), &eta),
            ) {
                (Ok(inverse), Ok(velocity)) => {
                    let formed = inverse * eta;
                    largest(&(formed - velocity)) / largest(&formed).max(1.0)
                }
                _ => f64::NAN,
            }
        }),
        consistent,
    )?;
    laws.check(
        "transport",
        tangents.iter().enumerate().map(|(i, xi)| {
            let p = next(i, 1);
            let transport = chart.to_group(xi).inverse().adjoint().transpose();
            let (together, a) = chart.transport_and_differential(xi);
            let moved = transport * p;
            worst([
                largest(&(moved - chart.coadjoint_to_start(xi, &p))) / largest(&moved).max(1.0),
                relative(&together, &transport),
                relative(&a, &chart.left_differential(xi)),
            ])
        }),
        consistent,
    )?;
    laws.check(
        "chart derivatives",
        tangents.iter().enumerate().map(|(i, xi)| {
            let (eta, mu) = (next(i, 1), next(i, 2));
            let read = |d: &dyn ChartDerivatives<D>| {
                // `None` inside: block derivatives of SE(3) on a group of another dimension.
                let blocks = d.rotation_translation().map(|r| {
                    let six =
                        |v: &SVector<f64, D>| SVector::<f64, 6>::from_iterator(v.iter().copied());
                    (D == 6).then(|| {
                        let (eta, mu) = (six(&eta), six(&mu));
                        [
                            r.differential(),
                            r.differential_times(&eta),
                            r.transpose_times(&eta),
                            r.second(&mu, &eta),
                        ]
                    })
                });
                (
                    [
                        d.differential(),
                        d.differential_times(&eta),
                        d.transpose_times(&eta),
                        d.second(&mu, &eta),
                    ],
                    blocks,
                )
            };
            let (dual, _) = dual_number_derivatives::<G, C, _, D>(chart, xi, read);
            let (closed, closed_blocks) = chart.with_derivatives(xi, true, read);
            // The first-order derivatives (no second derivatives asked for) are the same.
            let (first, first_blocks) = chart.with_derivatives(xi, false, read);
            let mut errors: Vec<f64> = closed
                .iter()
                .zip(&dual)
                .map(|(a, b)| relative(a, b))
                .collect();
            errors.extend(first.iter().zip(&dual).take(3).map(|(a, b)| relative(a, b)));
            // SE(3)'s block form, where a chart gives it, against the same references (in
            // `D = 6` coordinates: the blocks' derivatives are of the whole chart).
            for (blocks, count) in [(closed_blocks, 4), (first_blocks, 3)] {
                match blocks {
                    None => {}
                    Some(None) => errors.push(f64::NAN),
                    Some(Some(blocks)) => {
                        errors.extend(blocks.iter().zip(&dual).take(count).map(|(a, b)| {
                            relative(&SMatrix::<f64, D, D>::from_iterator(a.iter().copied()), b)
                        }))
                    }
                }
            }
            worst(errors)
        }),
        consistent,
    )?;
    report.append(&mut laws.report);
    Ok(report)
}

/// Checks what a [`ConfigurationGroup`] gives besides its elements' [`LieGroup`], on
/// `elements` (on the group) and `tangents`:
/// - "lift": `lift::<f64>(g) = g`;
/// - "exp to second order", "second-order exp": [`ConfigurationGroup::exp`] and
///   [`ConfigurationGroup::exp_second_order`] agree with the elements' [`ExponentialMap`]
///   to second order at the identity (what configuration variations `g exp(ζ)` read): at
///   `tξ` with `t|ξ| = 10⁻³` their matrices' entries that `vee` reads and their adjoints
///   differ by at most `10⁻⁹` (the third order is below `|tξ|³/6`) plus the exact
///   allowance, where an error in the second order would give about `10⁻⁶`;
/// - "coadjoint generator": [`ConfigurationGroup::coadjoint_generator`] against its
///   definition from the small adjoint ([`coadjoint_generator_of`]);
/// - "on the group": each element is finite, passes
///   [`ConfigurationGroup::check_on_group`], and is kept by
///   [`ConfigurationGroup::renormalise`].
///
/// Errors are measured as in [`group_laws`], against `tolerance` times the scale of the
/// examples (at least 1).
///
/// ```
/// use lgsvi_lie::laws::configuration_group_laws;
/// use lgsvi_lie::{RigidMotions, SE3, SO3};
/// use nalgebra::{SVector, Vector3};
///
/// let g = [SE3::new(SO3::about_y(0.7), Vector3::new(1.0, -2.0, 0.5)), SE3::identity()];
/// let xi = [SVector::<f64, 6>::new(0.1, 0.2, -0.3, 1.0, -2.0, 0.5)];
/// configuration_group_laws::<RigidMotions, 6>(&g, &xi, 1e-13)?;
/// # Ok::<(), lgsvi_lie::laws::LawViolation>(())
/// ```
///
/// # Errors
/// The first law that fails, with its size ([`LawViolation`]).
pub fn configuration_group_laws<G, const D: usize>(
    elements: &[G::Element<f64>],
    tangents: &[SVector<f64, D>],
    tolerance: f64,
) -> Result<LawReport, LawViolation>
where
    G: ConfigurationGroup<D>,
    G::Element<f64>: ExponentialMap,
{
    let scale = tangents
        .iter()
        .map(largest)
        .chain(elements.iter().map(|g| largest(&g.log())))
        .fold(1.0f64, f64::max);
    let exact = tolerance * scale;
    let mut laws = Laws { report: Vec::new() };
    laws.check(
        "lift",
        elements.iter().map(|g| distance(&G::lift::<f64>(g), g)),
        exact,
    )?;
    let small = |xi: &SVector<f64, D>| xi * (1e-3 / xi.norm().max(f64::MIN_POSITIVE));
    // A second-order `exp` need not be on the group, where `log` does not apply: it is
    // compared by the matrix entries that `vee` reads and by its adjoint, both of which
    // see the second order (on SO(3), `I + ζ̂` alone misses `½ζ̂²` in both).
    let apart = |a: &G::Element<f64>, b: &G::Element<f64>| {
        worst([
            largest(
                &(G::Element::<f64>::vee(&a.to_matrix()) - G::Element::<f64>::vee(&b.to_matrix())),
            ),
            largest(&(a.adjoint() - b.adjoint())),
        ])
    };
    let third_order = 1e-9 + exact;
    laws.check(
        "exp to second order",
        tangents.iter().map(|xi| {
            let zeta = small(xi);
            apart(&G::exp::<f64>(&zeta), &ExponentialMap::exp(&zeta))
        }),
        third_order,
    )?;
    laws.check(
        "second-order exp",
        tangents.iter().map(|xi| {
            let zeta = small(xi);
            apart(
                &G::exp_second_order::<f64>(&zeta),
                &ExponentialMap::exp(&zeta),
            )
        }),
        third_order,
    )?;
    laws.check(
        "coadjoint generator",
        tangents.iter().map(|p| {
            largest(&(G::coadjoint_generator(p) - coadjoint_generator_of::<G::Element<f64>, D>(p)))
        }),
        exact,
    )?;
    laws.check(
        "on the group",
        elements.iter().map(|g| {
            if G::is_finite(g) && G::check_on_group(g).is_ok() {
                distance(&G::renormalise(g), g)
            } else {
                f64::NAN
            }
        }),
        exact,
    )?;
    Ok(laws.report)
}
