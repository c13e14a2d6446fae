//! Laws every rule must satisfy, independent of any reference table: polynomial exactness
//! up to the rule's degree, symmetry, weights summing to the interval's length, positive
//! weights, ascending nodes inside the interval, and typed errors on bad input.

use lgsvi_quadrature::{
    gauss_legendre, gauss_lobatto, gauss_radau_left, gauss_radau_right, golub_welsch,
    QuadratureError, Rule,
};
use proptest::prelude::*;

const EPS: f64 = f64::EPSILON;
const ORDERS: [usize; 14] = [1, 2, 3, 4, 5, 6, 7, 8, 13, 21, 50, 100, 500, 1000];

/// A rule family: its name, the least number of points it allows, its constructor.
type Family = (
    &'static str,
    usize,
    fn(usize) -> Result<Rule, QuadratureError>,
);

fn families() -> Vec<Family> {
    vec![
        ("gauss-legendre", 1, gauss_legendre),
        ("gauss-lobatto", 2, gauss_lobatto),
        ("gauss-radau-left", 1, gauss_radau_left),
        ("gauss-radau-right", 1, gauss_radau_right),
    ]
}

/// `∫_{−1}^{1} x^k dx`.
fn monomial_integral(k: usize) -> f64 {
    if k % 2 == 1 {
        0.0
    } else {
        2.0 / (k as f64 + 1.0)
    }
}

/// Bound on `|Σ w_i x_i^k − ∫ x^k|` for a rule whose nodes are within 4ε and weights within
/// 8ε (relative) of exact, summed naively: the weight errors contribute `8ε Σ w|x|^k`, the
/// node errors `4ε Σ w k|x|^{k−1} ≤ 8kε`, `powi` (binary powering, ≤ 2 log₂k + 1 roundings)
/// and the product `(2 log₂k + 2) ε Σ w|x|^k`, and the sum of m terms `m ε Σ w|x|^k`.
fn exactness_bound(rule: &Rule, k: usize) -> f64 {
    let abs_sum: f64 = rule.iter().map(|(x, w)| w * x.abs().powi(k as i32)).sum();
    let log2k = (k.max(1) as f64).log2().ceil();
    let m = rule.num_points() as f64;
    EPS * ((8.0 + 2.0 * log2k + 2.0 + m) * abs_sum + 8.0 * k as f64)
}

#[test]
fn exact_for_every_monomial_up_to_the_degree() {
    for (name, min, build) in families() {
        for &m in ORDERS.iter().filter(|&&m| m >= min) {
            let rule = build(m).unwrap();
            for k in 0..=rule.degree_of_exactness() {
                let got = rule.integrate(|x| x.powi(k as i32));
                let err = (got - monomial_integral(k)).abs();
                assert!(
                    err <= exactness_bound(&rule, k),
                    "{name} m = {m}, x^{k}: error {err:e} > {:e}",
                    exactness_bound(&rule, k)
                );
            }
        }
    }
}

#[test]
fn not_exact_one_degree_higher() {
    // The degree is sharp: x^(d+1) is integrated with a visible error. For Gauss the
    // error is 2^{2m}(m!)^4/((2m+1)((2m)!)^2) ≈ 2e-5 at m = 8, and it falls like 4^{-m}:
    // beyond m ≈ 20 it nears rounding, so the check stops at m = 8.
    for (name, min, build) in families() {
        for &m in ORDERS.iter().filter(|&&m| m >= min && m <= 8) {
            let rule = build(m).unwrap();
            let k = rule.degree_of_exactness() + 1;
            let err = (rule.integrate(|x| x.powi(k as i32)) - monomial_integral(k)).abs();
            assert!(
                err > 1e3 * exactness_bound(&rule, k),
                "{name} m = {m}: x^{k}"
            );
        }
    }
}

#[test]
fn nodes_ascending_inside_weights_positive_and_summing_to_length() {
    for (name, min, build) in families() {
        for &m in ORDERS.iter().filter(|&&m| m >= min) {
            let rule = build(m).unwrap();
            assert_eq!(rule.num_points(), m);
            assert!(rule.nodes().windows(2).all(|w| w[0] < w[1]), "{name} {m}");
            assert!(rule.nodes().iter().all(|x| (-1.0..=1.0).contains(x)));
            assert!(rule.weights().iter().all(|&w| w > 0.0));
            // Each weight is within 8ε of exact; summing m of them adds m ε·2.
            let sum: f64 = rule.weights().iter().sum();
            assert!(
                (sum - 2.0).abs() <= (8.0 + m as f64) * 2.0 * EPS,
                "{name} {m}: {sum}"
            );
        }
    }
}

#[test]
fn symmetric_rules_are_exactly_symmetric() {
    for build in [gauss_legendre, gauss_lobatto] {
        for m in 2..=60 {
            let rule = build(m).unwrap();
            let (x, w) = (rule.nodes(), rule.weights());
            for i in 0..m {
                assert_eq!(x[i], -x[m - 1 - i]);
                assert_eq!(w[i], w[m - 1 - i]);
            }
            if m % 2 == 1 {
                assert_eq!(x[m / 2], 0.0);
            }
        }
    }
}

#[test]
fn endpoints_are_nodes_exactly() {
    for m in 2..=40 {
        let lob = gauss_lobatto(m).unwrap().on(0.3, 7.0).unwrap();
        assert_eq!((lob.nodes()[0], lob.nodes()[m - 1]), (0.3, 7.0));
        let left = gauss_radau_left(m).unwrap().on(-2.0, 5.0).unwrap();
        assert_eq!(left.nodes()[0], -2.0);
        let right = gauss_radau_right(m).unwrap().on(-2.0, 5.0).unwrap();
        assert_eq!(right.nodes()[m - 1], 5.0);
    }
}

#[test]
fn small_rules_in_closed_form() {
    // Gauss 3: 0, ±√(3/5); weights 8/9, 5/9.
    let g = gauss_legendre(3).unwrap();
    assert_eq!(g.nodes()[1], 0.0);
    assert!((g.nodes()[2] - 0.6f64.sqrt()).abs() <= EPS);
    assert!((g.weights()[1] - 8.0 / 9.0).abs() <= EPS);
    assert!((g.weights()[0] - 5.0 / 9.0).abs() <= EPS);
    // Lobatto 4: ±1, ±1/√5; weights 1/6, 5/6.
    let l = gauss_lobatto(4).unwrap();
    assert!((l.nodes()[2] - 0.2f64.sqrt()).abs() <= EPS);
    assert!((l.weights()[0] - 1.0 / 6.0).abs() <= EPS);
    assert!((l.weights()[1] - 5.0 / 6.0).abs() <= EPS);
    // Radau 3: −1, (1 ∓ √6)/5; weights 2/9, (16 ± √6)/18.
    let r = gauss_radau_left(3).unwrap();
    let s6 = 6f64.sqrt();
    assert!((r.nodes()[1] - (1.0 - s6) / 5.0).abs() <= EPS);
    assert!((r.nodes()[2] - (1.0 + s6) / 5.0).abs() <= EPS);
    assert!((r.weights()[0] - 2.0 / 9.0).abs() <= EPS);
    assert!((r.weights()[1] - (16.0 + s6) / 18.0).abs() <= 2.0 * EPS);
    assert!((r.weights()[2] - (16.0 - s6) / 18.0).abs() <= 2.0 * EPS);
}

#[test]
fn bad_input_is_a_typed_error() {
    assert!(matches!(
        gauss_legendre(0),
        Err(QuadratureError::TooFewPoints {
            points: 0,
            min: 1,
            ..
        })
    ));
    assert!(matches!(
        gauss_lobatto(1),
        Err(QuadratureError::TooFewPoints {
            points: 1,
            min: 2,
            ..
        })
    ));
    assert!(gauss_radau_left(0).is_err() && gauss_radau_right(0).is_err());
    let rule = gauss_legendre(4).unwrap();
    for (a, b) in [(1.0, 1.0), (-3.5, -3.5)] {
        assert!(matches!(
            rule.on(a, b),
            Err(QuadratureError::EmptyInterval { .. })
        ));
    }
    for (a, b) in [
        (f64::NAN, 1.0),
        (0.0, f64::INFINITY),
        (f64::NEG_INFINITY, 0.0),
    ] {
        assert!(matches!(
            rule.on(a, b),
            Err(QuadratureError::NonFiniteInterval { .. })
        ));
    }
    assert!(matches!(
        golub_welsch(&[0.0, 0.0], &[], 1.0),
        Err(QuadratureError::JacobiShape {
            diagonal: 2,
            off_diagonal: 0
        })
    ));
    assert!(matches!(
        golub_welsch(&[0.0, f64::NAN], &[1.0], 1.0),
        Err(QuadratureError::NonFiniteJacobi { index: 1, .. })
    ));
    assert!(matches!(
        golub_welsch(&[0.0], &[], -1.0),
        Err(QuadratureError::InvalidMass { .. })
    ));
    assert!(golub_welsch(&[], &[], 1.0).is_err());
    // Messages say what to change.
    let msg = rule.on(2.0, 2.0).unwrap_err().to_string();
    assert!(msg.contains("a ≠ b"), "{msg}");
}

/// A reversed interval integrates backwards, `∫_b^a f = −∫_a^b f`. For the symmetric
/// rules (Legendre, Lobatto) the backward rule is the forward one's nodes in the opposite
/// order with negated weights, bit for bit. For every family (the one-sided Radau rule
/// too, whose backward rule puts its fixed node at `b`) both integrate a polynomial they
/// are exact for to the rounding of the sum (8 ulps of the sum of |terms|), with opposite
/// signs.
#[test]
fn a_reversed_interval_integrates_backwards() {
    let (a, b) = (-0.7, 2.3);
    for m in [2usize, 3, 7, 20, 64] {
        for (rule, symmetric) in [
            (gauss_legendre(m).unwrap(), true),
            (gauss_lobatto(m).unwrap(), true),
            (gauss_radau_left(m).unwrap(), false),
        ] {
            let forward = rule.on(a, b).unwrap();
            let backward = rule.on(b, a).unwrap();
            assert_eq!(backward.interval(), (b, a));
            let n = forward.num_points();
            if symmetric {
                for i in 0..n {
                    assert_eq!(backward.nodes()[i], forward.nodes()[n - 1 - i]);
                    assert_eq!(backward.weights()[i], -forward.weights()[n - 1 - i]);
                }
            }
            // A polynomial of degree 1 (every rule here with m ≥ 2 integrates it exactly).
            let f = |x: f64| 0.4 - 1.7 * x;
            let size: f64 = forward.iter().map(|(x, w)| (w * f(x)).abs()).sum();
            let exact = 0.4 * (b - a) - 0.85 * (b * b - a * a);
            let (there, back) = (forward.integrate(f), backward.integrate(f));
            assert!(
                (there - exact).abs() <= 8.0 * f64::EPSILON * size,
                "m = {m}"
            );
            assert!((back + exact).abs() <= 8.0 * f64::EPSILON * size, "m = {m}");
        }
    }
}

#[test]
fn golub_welsch_agrees_with_a_dense_symmetric_eigensolver() {
    // An independent eigensolver (nalgebra's dense symmetric QR) on a non-symmetric family
    // (Laguerre: α_k = 2k+1, β_k = k², μ₀ = 1). Eigenvalues up to ~4m: tolerance m·ε·‖J‖.
    for m in [1, 2, 5, 17, 40] {
        let diag: Vec<f64> = (0..m).map(|k| 2.0 * k as f64 + 1.0).collect();
        let off: Vec<f64> = (1..m).map(|k| k as f64).collect();
        let (nodes, weights) = golub_welsch(&diag, &off, 1.0).unwrap();
        let jacobi = nalgebra::DMatrix::from_fn(m, m, |i, j| {
            if i == j {
                diag[i]
            } else if i.abs_diff(j) == 1 {
                off[i.min(j)]
            } else {
                0.0
            }
        });
        let eig = nalgebra::SymmetricEigen::new(jacobi);
        let mut pairs: Vec<(f64, f64)> = (0..m)
            .map(|j| (eig.eigenvalues[j], eig.eigenvectors[(0, j)].powi(2)))
            .collect();
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let norm = 4.0 * m as f64;
        for (j, (x, w)) in pairs.into_iter().enumerate() {
            assert!(
                (nodes[j] - x).abs() <= 16.0 * m as f64 * EPS * norm,
                "m {m} node {j}"
            );
            // Weights of Laguerre decay like e^{-x}; compare absolutely against the sum 1.
            assert!(
                (weights[j] - w).abs() <= 16.0 * m as f64 * EPS,
                "m {m} weight {j}"
            );
        }
    }
}

proptest! {
    /// On any interval, a random polynomial of the rule's degree integrates exactly
    /// (against its antiderivative in closed form). Tolerance: the coefficients are O(1)
    /// and the interval length ≤ 20 with |x| ≤ 20, so terms are ≤ 20^d; 64·(m + d)·ε
    /// times the sum of |terms| covers the mapping, the rule's own errors and the sum.
    #[test]
    fn mapped_rules_integrate_random_polynomials(
        m in 1usize..8,
        a in -10.0f64..10.0,
        len in 0.01f64..10.0,
        coeffs in proptest::collection::vec(-1.0f64..1.0, 16),
        family in 0usize..4,
    ) {
        let (_, min, build) = families()[family];
        prop_assume!(m >= min);
        let b = a + len;
        let rule = build(m).unwrap().on(a, b).unwrap();
        let d = rule.degree_of_exactness();
        let c = &coeffs[..=d];
        let poly = |x: f64| c.iter().rev().fold(0.0, |acc, ci| acc * x + ci);
        let anti = |x: f64| c.iter().enumerate().rev()
            .fold(0.0, |acc, (k, ci)| acc * x + ci / (k as f64 + 1.0)) * x;
        let exact = anti(b) - anti(a);
        let got = rule.integrate(poly);
        let scale: f64 = rule.iter().map(|(x, w)| w * c.iter().enumerate()
            .map(|(k, ci)| (ci * x.powi(k as i32)).abs()).sum::<f64>()).sum::<f64>()
            + anti(b).abs() + anti(a).abs();
        prop_assert!((got - exact).abs() <= 64.0 * (m + d) as f64 * EPS * scale,
            "m {} [{}, {}] got {} exact {}", m, a, b, got, exact);
    }
}

/// A vector integrand's components are the scalar integrals, bit for bit (the same sums in
/// the same order), on every family.
#[test]
fn vector_integrands_sum_as_scalar_ones() {
    use lgsvi_quadrature::{gauss_hermite, gauss_jacobi, gauss_legendre};
    let rules = [
        gauss_legendre(7).unwrap().on(-0.3, 2.0).unwrap(),
        gauss_hermite(9).unwrap(),
        gauss_jacobi(6, 0.4, -0.2).unwrap().on(1.0, 3.0).unwrap(),
    ];
    for rule in &rules {
        let mut out = [f64::NAN; 3];
        rule.integrate_into(
            |x, v| v.copy_from_slice(&[x.sin(), x * x, (-x * x).exp()]),
            &mut out,
        );
        assert_eq!(out[0], rule.integrate(f64::sin));
        assert_eq!(out[1], rule.integrate(|x| x * x));
        assert_eq!(out[2], rule.integrate(|x| (-x * x).exp()));
    }
}

/// The maps to infinite intervals: exact for the rational functions they are made for,
/// refused for rules with end nodes or weights and for scales that are not positive.
#[test]
fn half_and_whole_line_maps() {
    use lgsvi_quadrature::{gauss_hermite, gauss_legendre, gauss_lobatto, QuadratureError};
    // ∫_a^∞ (x − a + s)^{−k} dx = s^{1−k}/(k − 1): a polynomial of degree k − 2 in t times
    // the map's derivative, exact for k ≤ 2m + 1.
    let (a, s, m) = (-2.0, 3.0, 5);
    let rule = gauss_legendre(m).unwrap().on_half_line(a, s).unwrap();
    assert_eq!(rule.interval(), (a, f64::INFINITY));
    assert!(rule.nodes().iter().all(|&x| x > a));
    for k in 2..=(2 * m + 1) as i32 {
        let exact = s.powi(1 - k) / (k - 1) as f64;
        let value = rule.integrate(|x| (x - a + s).powi(-k));
        assert!(
            (value - exact).abs() <= 1e-14 * exact,
            "k {k}: {value} {exact}"
        );
    }
    // ∫ dx/(1 + x²) = π; ∫ e^{−x²} dx = √π, through the whole-line map.
    let line = gauss_legendre(160).unwrap().on_real_line(0.0, 1.0).unwrap();
    assert_eq!(line.interval(), (f64::NEG_INFINITY, f64::INFINITY));
    assert!((line.integrate(|x| 1.0 / (1.0 + x * x)) - std::f64::consts::PI).abs() < 1e-14);
    assert!((line.integrate(|x| (-x * x).exp()) - std::f64::consts::PI.sqrt()).abs() < 1e-14);
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            gauss_legendre(4).unwrap().on_half_line(0.0, bad),
            Err(QuadratureError::NonFiniteInterval { .. })
        ));
    }
    for rule in [gauss_lobatto(4).unwrap(), gauss_hermite(4).unwrap()] {
        assert!(matches!(
            rule.on_half_line(0.0, 1.0),
            Err(QuadratureError::UnboundedRule { .. })
        ));
        assert!(matches!(
            rule.on_real_line(0.0, 1.0),
            Err(QuadratureError::UnboundedRule { .. })
        ));
    }
}
