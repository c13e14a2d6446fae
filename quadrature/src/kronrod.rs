//! Gauss–Kronrod rules: the `2n + 1`-point extension of the `n`-point Gauss–Legendre rule
//! that keeps its nodes, and with it an error estimate from one set of function values.

use crate::classical::{
    check_exponent, gauss_jacobi, jacobi_coefficients, jacobi_mass, rule_from_recurrence,
};
use crate::double_double::DoubleDouble as Dd;
use crate::error::at_least;
use crate::rule::{Rule, RuleKind};
use crate::rules::gauss_legendre;
use crate::QuadratureError;

/// A Gauss–Kronrod pair on one interval: the `2n + 1`-point Kronrod rule and the weights of
/// the embedded `n`-point Gauss rule at the same nodes (zero at the `n + 1` added ones).
///
/// [`GaussKronrod::integrate`] evaluates `f` once per Kronrod node and returns the Kronrod
/// value with `|K − G|`, the classical (conservative) estimate of the Gauss value's error —
/// the Kronrod value itself is far more accurate (exact for degree `3n + 1`, `3n + 2` for odd
/// `n`, against the Gauss rule's `2n − 1`).
///
/// ```
/// use lgsvi_quadrature::gauss_kronrod;
/// // G7–K15 on [0, 1]: ∫ eˣ dx = e − 1.
/// let pair = gauss_kronrod(7)?.on(0.0, 1.0)?;
/// let (value, estimate) = pair.integrate(f64::exp);
/// assert!((value - (1f64.exp() - 1.0)).abs() < 4.0 * f64::EPSILON);
/// assert!(estimate < 1e-13); // |K − G|: the 7-point Gauss rule's error is ~1e-17 here
/// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct GaussKronrod {
    kronrod: Rule,
    gauss_weights: Vec<f64>,
    /// The Gauss weights on the reference interval `[−1, 1]`, mapped afresh by `on`.
    reference_gauss_weights: Vec<f64>,
}

impl GaussKronrod {
    /// The pair on `[a, b]` (as [`Rule::on`]: `a > b` integrates backwards).
    ///
    /// # Errors
    /// As [`Rule::on`].
    pub fn on(&self, a: f64, b: f64) -> Result<Self, QuadratureError> {
        let kronrod = self.kronrod.on(a, b)?;
        // The Kronrod rule's own scale: (b − a)/2, or its power α + β + 1 for a weight.
        let half_length = 0.5 * (b - a);
        let scale = match self.kronrod.weight_exponents() {
            None => half_length,
            Some((alpha, beta)) => half_length.powf(alpha + beta + 1.0),
        };
        let gauss_weights = self
            .reference_gauss_weights
            .iter()
            .map(|w| w * scale)
            .collect();
        Ok(Self {
            kronrod,
            gauss_weights,
            reference_gauss_weights: self.reference_gauss_weights.clone(),
        })
    }

    /// The `2n + 1`-point Kronrod rule.
    pub fn kronrod(&self) -> &Rule {
        &self.kronrod
    }

    /// The embedded Gauss rule's weights, in the order of the Kronrod nodes (zero at the
    /// nodes the Kronrod rule adds: every other node, from the first).
    pub fn gauss_weights(&self) -> &[f64] {
        &self.gauss_weights
    }

    /// `(K, |K − G|)`: the Kronrod value and the difference from the embedded Gauss value,
    /// from one evaluation of `f` per Kronrod node.
    pub fn integrate(&self, mut f: impl FnMut(f64) -> f64) -> (f64, f64) {
        let (mut k, mut g) = (0.0, 0.0);
        for ((x, w), wg) in self.kronrod.iter().zip(&self.gauss_weights) {
            let y = f(x);
            k += w * y;
            g += wg * y;
        }
        (k, (k - g).abs())
    }
}

/// The Gauss–Kronrod pair of `n` Gauss–Legendre points extended to `2n + 1` (G7–K15 is
/// `gauss_kronrod(7)`), on `[−1, 1]`.
///
/// How: Laurie's algorithm (*Math. Comp.* 66, 1997) gives the Jacobi matrix of the Kronrod
/// rule from the Legendre recurrence; its Gauss rule is then computed as the classical rules
/// are (Golub–Welsch, Newton, one double-double evaluation per node, Christoffel weights,
/// symmetric by construction), and the Gauss nodes among its nodes are [`gauss_legendre`]'s
/// exactly, so that the pair shares its function values. Against a committed 150-digit mpmath reference
/// (`tests/data/generate_kronrod.py`, from the Stieltjes polynomial's definition) for
/// `n ≤ 30`: every node the double nearest the reference, Kronrod weights within `1.2ε`
/// and Gauss weights within `2ε` relative (the tests hold them to `4ε`, `4ε`, `8ε`; `cargo
/// test --test kronrod -- --nocapture` prints them). The QUADPACK G7–K15 constants agree with
/// the reference to their 33 digits (its node `0.5860872354676911302941448382587…`).
///
/// # Errors
/// [`QuadratureError::TooFewPoints`] for `n = 0`; those of Golub–Welsch (not expected).
pub fn gauss_kronrod(n: usize) -> Result<GaussKronrod, QuadratureError> {
    at_least("Gauss-Kronrod (Gauss points)", n, 1)?;
    // Legendre: α_k = 0, β_0 = 2, β_k = k²/(4k² − 1).
    let (a, b) = monic(n, |count| {
        let squares = (1..=count)
            .map(|k| {
                let k2 = (k * k) as f64;
                Dd::from_f64(k2).div(Dd::from_f64(4.0 * k2 - 1.0))
            })
            .collect();
        (vec![Dd::from_f64(0.0); count], squares)
    });
    let gauss = gauss_legendre(n)?;
    let (nodes, weights, gauss_weights) = extension(n, a, b, 2.0, true, &gauss)
        .expect("the Gauss-Legendre rule has a Kronrod extension for every n");
    Ok(GaussKronrod {
        kronrod: Rule::with_weight(RuleKind::GaussKronrod, nodes, weights, (-1.0, 1.0), None),
        reference_gauss_weights: gauss_weights.clone(),
        gauss_weights,
    })
}

/// The Gauss–Kronrod pair extending the `n`-point Gauss–Jacobi rule
/// ([`gauss_jacobi`](crate::gauss_jacobi)) of the weight `(1 − x)^α (1 + x)^β` to `2n + 1`
/// points, where that extension has real nodes inside `(−1, 1)` and positive weights; its
/// weighted [`GaussKronrod::integrate`] gives the Kronrod value of
/// `∫ (1 − x)^α (1 + x)^β f(x) dx` and `|K − G|`. The Gegenbauer weights `α = β ∈ (−½, 3/2]`
/// have one for every `n` (Gautschi & Notaris 1988; the Chebyshev weight of the second kind
/// among them; the first kind's puts nodes on `±1`, refused here); other
/// exponents for some `n` or none (checked against the reference: `(2, 1)` and `(3, 3)`
/// up to `n = 20`; `(½, −½)` puts a node on an end for every `n`). Laguerre and Hermite
/// weights have none for most `n`, which is why this crate offers none.
///
/// Same method as [`gauss_kronrod`]: Laurie's algorithm on the Jacobi recurrence in
/// double-double, the rule of the resulting Jacobi matrix, the embedded Gauss nodes and
/// weights exactly [`gauss_jacobi`](crate::gauss_jacobi)'s.
///
/// ```
/// use lgsvi_quadrature::gauss_kronrod_jacobi;
/// // ∫ √(1 − x²) eˣ dx = π I₁(1) = 1.7754996892121809…, with 7 Gauss and 15 Kronrod points.
/// let pair = gauss_kronrod_jacobi(7, 0.5, 0.5)?;
/// let (value, estimate) = pair.integrate(f64::exp);
/// assert!((value - 1.775_499_689_212_180_9).abs() < 1e-15);
/// assert!(estimate < 1e-12);
/// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
/// ```
///
/// # Errors
/// [`QuadratureError::TooFewPoints`] for `n = 0`; [`QuadratureError::InvalidExponent`] for
/// `α` or `β` ≤ −1 or not finite; [`QuadratureError::NoKronrodExtension`] where the
/// extension has complex nodes, nodes outside `(−1, 1)` or a weight that is not positive.
pub fn gauss_kronrod_jacobi(
    n: usize,
    alpha: f64,
    beta: f64,
) -> Result<GaussKronrod, QuadratureError> {
    at_least("Gauss-Kronrod-Jacobi (Gauss points)", n, 1)?;
    check_exponent("alpha", alpha)?;
    check_exponent("beta", beta)?;
    let mass = jacobi_mass(alpha, beta);
    let (a, mut b) = monic(n, |count| jacobi_coefficients(count, alpha, beta));
    b[0] = Dd::from_f64(mass);
    let gauss = gauss_jacobi(n, alpha, beta)?;
    let (nodes, weights, gauss_weights) = extension(n, a, b, mass, alpha == beta, &gauss).ok_or(
        QuadratureError::NoKronrodExtension {
            points: n,
            alpha,
            beta,
        },
    )?;
    Ok(GaussKronrod {
        kronrod: Rule::with_weight(
            RuleKind::GaussKronrodJacobi,
            nodes,
            weights,
            (-1.0, 1.0),
            Some((alpha, beta)),
        ),
        reference_gauss_weights: gauss_weights.clone(),
        gauss_weights,
    })
}

/// The monic recurrence `(a_k, b_k)`, `k < 2n + 1`, with the first `⌊3n/2⌋ + 1` entries
/// filled from `coefficients(count) → (a_0 … a_{count−1}, b_1 … b_count)` (`b_0` left for
/// the caller: the mass), the rest zero, as Laurie's algorithm takes them.
fn monic(n: usize, coefficients: impl FnOnce(usize) -> (Vec<Dd>, Vec<Dd>)) -> (Vec<Dd>, Vec<Dd>) {
    let len = 2 * n + 1;
    let count = (3 * n).div_ceil(2) + 1;
    let (diagonal, squares) = coefficients(count);
    let zero = Dd::from_f64(0.0);
    let mut a = vec![zero; len];
    let mut b = vec![zero; len];
    for k in 0..count.min(len) {
        a[k] = diagonal[k];
        b[k] = if k == 0 {
            Dd::from_f64(2.0)
        } else {
            squares[k - 1]
        };
    }
    (a, b)
}

/// The Kronrod rule of the recurrence `(a, b)` (Laurie's algorithm, then the rule of its
/// Jacobi matrix) with the Gauss rule's nodes in it exactly: `(nodes, Kronrod weights, Gauss
/// weights in the Kronrod nodes' order)`, or `None` where the extension is not real with
/// nodes inside `(−1, 1)` and positive weights.
fn extension(
    n: usize,
    a: Vec<Dd>,
    b: Vec<Dd>,
    mass: f64,
    symmetric: bool,
    gauss: &Rule,
) -> Option<(Vec<f64>, Vec<f64>, Vec<f64>)> {
    let (alpha, beta) = laurie(n, a, b);
    // A Kronrod matrix with a non-positive β_k has complex nodes (Laurie 1997).
    if !beta[1..].iter().all(|b| b.hi > 0.0 && b.hi.is_finite()) {
        return None;
    }
    // √β_1 … √β_{2n}, and 1 to scale the last step of the recurrence (only p_m's zeros
    // matter there).
    let off: Vec<Dd> = beta[1..]
        .iter()
        .map(|b| b.sqrt())
        .chain([Dd::from_f64(1.0)])
        .collect();
    let (mut nodes, weights) = rule_from_recurrence(alpha, off, mass, symmetric).ok()?;
    let m = 2 * n + 1;
    let inside = nodes.iter().all(|&x| x > -1.0 && x < 1.0);
    let positive = weights.iter().all(|&w| w > 0.0 && w.is_finite());
    if nodes.len() != m || !inside || !positive {
        return None;
    }
    let mut gauss_weights = vec![0.0; m];
    for (i, (&x, &w)) in gauss.nodes().iter().zip(gauss.weights()).enumerate() {
        // The Kronrod nodes interlace with the Gauss nodes, which they contain.
        if (nodes[2 * i + 1] - x).abs() > 1e-10 {
            return None;
        }
        nodes[2 * i + 1] = x;
        gauss_weights[2 * i + 1] = w;
    }
    Some((nodes, weights, gauss_weights))
}

/// Laurie's algorithm: the recurrence coefficients `(α_k, β_k)`, `k < 2n + 1`, of the
/// Kronrod rule extending the `n`-point Gauss rule of the monic recurrence `(a, b)` (given
/// for `k ≤ ⌈3n/2⌉`, `b_0` the mass), in double-double (in double, the rounding of its
/// recurrences left Kronrod weights 115ε off at n = 25). A transcription of `r_kronrod`
/// (Laurie 1997; Gautschi's OPQ), indices from 0.
fn laurie(n: usize, mut a: Vec<Dd>, mut b: Vec<Dd>) -> (Vec<Dd>, Vec<Dd>) {
    let zero = Dd::from_f64(0.0);
    let half = n / 2 + 2;
    let (mut s, mut t) = (vec![zero; half], vec![zero; half]);
    t[1] = b[n + 1];
    for m in 0..n.saturating_sub(1) {
        let mut u = zero;
        let mut k = m.div_ceil(2);
        loop {
            let l = m - k;
            u = u
                .add(a[k + n + 1].sub(a[l]).mul(t[k + 1]))
                .add(b[k + n + 1].mul(s[k]))
                .sub(b[l].mul(s[k + 1]));
            s[k + 1] = u;
            if k == 0 {
                break;
            }
            k -= 1;
        }
        std::mem::swap(&mut s, &mut t);
    }
    for j in (0..=n / 2).rev() {
        s[j + 1] = s[j];
    }
    for m in n - 1..2 * n - 2 {
        let mut u = zero;
        let mut j = 0;
        for k in (m + 1 - n)..=((m - 1) / 2) {
            let l = m - k;
            j = n - 1 - l;
            u = u
                .sub(a[k + n + 1].sub(a[l]).mul(t[j + 1]))
                .sub(b[k + n + 1].mul(s[j + 1]))
                .add(b[l].mul(s[j + 2]));
            s[j + 1] = u;
        }
        if m % 2 == 0 {
            let k = m / 2;
            a[k + n + 1] = a[k].add(s[j + 1].sub(b[k + n + 1].mul(s[j + 2])).div(t[j + 2]));
        } else {
            let k = m.div_ceil(2);
            b[k + n + 1] = s[j + 1].div(s[j + 2]);
        }
        std::mem::swap(&mut s, &mut t);
    }
    a[2 * n] = a[n - 1].sub(b[2 * n].mul(s[1]).div(t[1]));
    (a, b)
}
