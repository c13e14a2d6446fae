//! Gauss–Legendre, Gauss–Lobatto and Gauss–Radau rules: Golub–Welsch for a first
//! approximation, Newton on the Legendre recurrence to polish each node, and weights from
//! closed forms evaluated in double-double at the polished node.
//!
//! Why double-double: near `x = ±1` a weight is sensitive to its node, with relative
//! derivative up to `2/(1 − x²) ≈ 2m²/j²` for the `j`-th node from the end. Rounding the
//! node to a double moves it by up to half an ulp, which would cost `~10⁴ ε` in the weight
//! at `m = 500`. Evaluating the recurrence once in double-double at the rounded node gives
//! the sub-ulp offset `δ` to the true root, and the weight is taken at the true root by a
//! first-order correction `w(x + δ) ≈ w(x)(1 + δ · d ln w/dx)`.

use crate::error::at_least;
use crate::golub_welsch::golub_welsch;
use crate::legendre::{legendre, legendre_dd, newton_polish, one_minus_square};
use crate::legendre_asymptotic::{gauss_legendre_asymptotic, ASYMPTOTIC_FROM};
use crate::rule::{Rule, RuleKind};
use crate::symmetric::{symmetric, Polished};
use crate::QuadratureError;

/// Given the node `x` after Newton, its sub-ulp offset `delta` to the true root, the weight
/// formula's value `w` at `x` and its logarithmic derivative, the node and weight at the
/// true root.
fn at_true_root(x: f64, delta: f64, w: f64, dlnw_dx: f64) -> Polished {
    Polished {
        node: x + delta,
        weight: w * (1.0 + delta * dlnw_dx),
    }
}

pub(crate) fn gauss_legendre_node(m: usize, guess: f64) -> Polished {
    let x = newton_polish(guess, |x| {
        let l = legendre(m, x);
        (l.p, l.dp)
    });
    let l = legendre(m, x);
    let dd = legendre_dd(m, x);
    let dp = dd.dp.to_f64();
    let delta = -dd.p.to_f64() / dp;
    let one_minus_x2 = one_minus_square(x);
    // w = 2 / ((1 − x²) P_m'(x)²);  d ln w/dx = 2x/(1 − x²) − 2 P_m''/P_m'.
    let w = 2.0 / (one_minus_x2 * dp * dp);
    let dlnw = 2.0 * x / one_minus_x2 - 2.0 * l.d2p / dp;
    at_true_root(x, delta, w, dlnw)
}

/// The `m`-point Gauss–Legendre rule on `[−1, 1]` (weight function 1): exact for
/// polynomials of degree `2m − 1`. Nodes ascending, exactly symmetric; `0` is a node
/// exactly when `m` is odd.
///
/// Below 100 points, Golub–Welsch on the Legendre Jacobi matrix (`β_k = k²/(4k² − 1)`)
/// gives first approximations; each node is polished by Newton on `P_m` and its weight
/// `2/((1 − x²) P_m'(x)²)` is evaluated in double-double at the true root (see the module
/// notes), in `O(m²)`. From 100 points on, the asymptotic expansions of the nodes and
/// weights in `θ = arccos x` (Hale and Townsend's, every term kept) give them directly in
/// `O(m)`, a million points included. Node errors at most `4ε` (absolute), relative
/// weight errors at most `8ε`, measured against 60-digit mpmath references for `m` up to
/// 500 and at the largest nodes of `m = 10⁶`, against the polished rules up to `m = 4000`
/// and at sampled nodes up to `m = 10⁶` (the crate's tests pin all of them).
///
/// # Errors
/// [`QuadratureError::TooFewPoints`] for `m = 0`.
///
/// # Example
/// ```
/// use lgsvi_quadrature::gauss_legendre;
/// let rule = gauss_legendre(2)?;
/// let x = 1.0 / 3f64.sqrt();
/// assert!((rule.nodes()[1] - x).abs() <= f64::EPSILON);
/// // Weights 1 and 1, to within the documented 8ε.
/// assert!(rule.weights().iter().all(|w| (w - 1.0).abs() <= 8.0 * f64::EPSILON));
/// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
/// ```
pub fn gauss_legendre(m: usize) -> Result<Rule, QuadratureError> {
    if m >= ASYMPTOTIC_FROM {
        let (nodes, weights) = gauss_legendre_asymptotic(m);
        return Ok(Rule::reference(RuleKind::GaussLegendre, nodes, weights));
    }
    gauss_legendre_golub_welsch(m)
}

/// [`gauss_legendre`] by Golub–Welsch, Newton and double-double polish at every `m`.
pub(crate) fn gauss_legendre_golub_welsch(m: usize) -> Result<Rule, QuadratureError> {
    at_least("Gauss-Legendre", m, 1)?;
    let off: Vec<f64> = (1..m)
        .map(|k| {
            let k = k as f64;
            k / (4.0 * k * k - 1.0).sqrt()
        })
        .collect();
    let (guesses, _) = golub_welsch(&vec![0.0; m], &off, 2.0)?;
    let (nodes, weights) = symmetric(m, |i| {
        if 2 * i + 1 == m {
            // The middle node of an odd rule is 0 exactly (P_m is odd).
            let dp = legendre_dd(m, 0.0).dp.to_f64();
            Polished {
                node: 0.0,
                weight: 2.0 / (dp * dp),
            }
        } else {
            gauss_legendre_node(m, guesses[m - 1 - i])
        }
    });
    Ok(Rule::reference(RuleKind::GaussLegendre, nodes, weights))
}

/// The `m`-point Gauss–Lobatto (Legendre) rule on `[−1, 1]`: nodes `±1` and the roots of
/// `P_{m−1}'`, weights `2/(m(m−1) P_{m−1}(x)²)`; exact for degree `2m − 3`.
///
/// Golub–Welsch on the Jacobi matrix of the Jacobi polynomials `P^{(1,1)}` (whose roots
/// are those of `P_{m−1}'`) gives first approximations; Newton on `P_{m−1}'` and a
/// double-double evaluation polish them.
///
/// # Errors
/// [`QuadratureError::TooFewPoints`] for `m < 2`.
///
/// # Example
/// ```
/// use lgsvi_quadrature::gauss_lobatto;
/// // Simpson's rule is the 3-point Lobatto rule.
/// let rule = gauss_lobatto(3)?;
/// assert_eq!(rule.nodes(), &[-1.0, 0.0, 1.0]);
/// assert!((rule.weights()[1] - 4.0 / 3.0).abs() <= f64::EPSILON);
/// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
/// ```
pub fn gauss_lobatto(m: usize) -> Result<Rule, QuadratureError> {
    at_least("Gauss-Lobatto", m, 2)?;
    let n = m - 1;
    let end_weight = 2.0 / (m * n) as f64;
    let interior = m - 2;
    let guesses = if interior > 0 {
        // P^{(1,1)}: β_k = k(k+2)/((2k+1)(2k+3)), μ₀ = ∫(1 − x²) dx = 4/3.
        let off: Vec<f64> = (1..interior)
            .map(|k| {
                let k = k as f64;
                (k * (k + 2.0) / ((2.0 * k + 1.0) * (2.0 * k + 3.0))).sqrt()
            })
            .collect();
        golub_welsch(&vec![0.0; interior], &off, 4.0 / 3.0)?.0
    } else {
        Vec::new()
    };
    let (nodes, weights) = symmetric(m, |i| {
        if i == 0 {
            return Polished {
                node: 1.0,
                weight: end_weight,
            };
        }
        let scale = (m * n) as f64;
        if 2 * i + 1 == m {
            // Odd m: the middle node is 0 exactly (P_{m−1}' is odd).
            let p = legendre_dd(n, 0.0).p.to_f64();
            return Polished {
                node: 0.0,
                weight: 2.0 / (scale * p * p),
            };
        }
        let x = newton_polish(guesses[interior - i], |x| {
            let l = legendre(n, x);
            (l.dp, l.d2p)
        });
        let l = legendre(n, x);
        let dd = legendre_dd(n, x);
        let p = dd.p.to_f64();
        let delta = -dd.dp.to_f64() / l.d2p;
        // w = 2/(m(m−1) P_n²); d ln w/dx = −2 P_n'/P_n (zero at the root: w is stationary).
        at_true_root(x, delta, 2.0 / (scale * p * p), -2.0 * l.dp / p)
    });
    Ok(Rule::reference(RuleKind::GaussLobatto, nodes, weights))
}

/// The `m`-point Gauss–Radau rule on `[−1, 1]` with the left end `−1` as a node: the
/// other nodes are the roots of `(P_{m−1} + P_m)/(1 + x)`, weights `2/m²` at `−1` and
/// `(1 − x)/(m² P_{m−1}(x)²)` elsewhere; exact for degree `2m − 2`.
///
/// # Errors
/// [`QuadratureError::TooFewPoints`] for `m = 0`.
///
/// # Example
/// ```
/// use lgsvi_quadrature::gauss_radau_left;
/// let rule = gauss_radau_left(2)?;
/// assert_eq!(rule.nodes()[0], -1.0);
/// assert!((rule.nodes()[1] - 1.0 / 3.0).abs() <= f64::EPSILON);
/// assert!((rule.weights()[1] - 1.5).abs() <= 2.0 * f64::EPSILON);
/// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
/// ```
pub fn gauss_radau_left(m: usize) -> Result<Rule, QuadratureError> {
    at_least("Gauss-Radau", m, 1)?;
    let interior = m - 1;
    let mut nodes = Vec::with_capacity(m);
    let mut weights = Vec::with_capacity(m);
    let m2 = (m * m) as f64;
    nodes.push(-1.0);
    weights.push(2.0 / m2);
    if interior > 0 {
        // P^{(0,1)} (weight 1 + x): α_k = 1/((2k+1)(2k+3)), β_k = k(k+1)/(2k+1)², μ₀ = 2.
        let diag: Vec<f64> = (0..interior)
            .map(|k| {
                let k = k as f64;
                1.0 / ((2.0 * k + 1.0) * (2.0 * k + 3.0))
            })
            .collect();
        let off: Vec<f64> = (1..interior)
            .map(|k| {
                let k = k as f64;
                (k * (k + 1.0)).sqrt() / (2.0 * k + 1.0)
            })
            .collect();
        let (guesses, _) = golub_welsch(&diag, &off, 2.0)?;
        for guess in guesses {
            let x = newton_polish(guess, |x| {
                let l = legendre(m, x);
                (l.p + l.p_prev, l.dp + l.dp_prev)
            });
            let l = legendre(m, x);
            let dd = legendre_dd(m, x);
            let f = dd.p.add(dd.p_prev).to_f64();
            let delta = -f / (l.dp + l.dp_prev);
            let p_prev = dd.p_prev.to_f64();
            // w = (1 − x)/(m² P_{m−1}²); d ln w/dx = −1/(1 − x) − 2 P_{m−1}'/P_{m−1}.
            let w = (1.0 - x) / (m2 * p_prev * p_prev);
            let dlnw = -1.0 / (1.0 - x) - 2.0 * dd.dp_prev.to_f64() / p_prev;
            let p = at_true_root(x, delta, w, dlnw);
            nodes.push(p.node);
            weights.push(p.weight);
        }
    }
    Ok(Rule::reference(RuleKind::GaussRadauLeft, nodes, weights))
}

/// The `m`-point Gauss–Radau rule on `[−1, 1]` with the right end `+1` as a node: the
/// mirror image of [`gauss_radau_left`].
///
/// # Errors
/// [`QuadratureError::TooFewPoints`] for `m = 0`.
///
/// ```
/// use lgsvi_quadrature::gauss_radau_right;
/// let rule = gauss_radau_right(3)?;
/// assert_eq!(*rule.nodes().last().unwrap(), 1.0);
/// // Exact for degree 2m − 2 = 4: ∫ x⁴ = 2/5.
/// assert!((rule.integrate(|x| x.powi(4)) - 0.4).abs() < 1e-15);
/// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
/// ```
pub fn gauss_radau_right(m: usize) -> Result<Rule, QuadratureError> {
    let left = gauss_radau_left(m)?;
    let nodes = left.nodes().iter().rev().map(|x| -x).collect();
    let weights = left.weights().iter().rev().copied().collect();
    Ok(Rule::reference(RuleKind::GaussRadauRight, nodes, weights))
}
