//! Gauss–Kronrod rules: the `2n + 1`-point extension of the `n`-point Gauss–Legendre rule
//! that keeps its nodes, and with it an error estimate from one set of function values.

use crate::classical::rule_from_recurrence;
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
    half_length: f64,
}

impl GaussKronrod {
    /// The pair on `[a, b]` (as [`Rule::on`]: `a > b` integrates backwards).
    ///
    /// # Errors
    /// As [`Rule::on`].
    pub fn on(&self, a: f64, b: f64) -> Result<Self, QuadratureError> {
        let kronrod = self.kronrod.on(a, b)?;
        let half_length = 0.5 * (b - a);
        let gauss_weights = self
            .gauss_weights
            .iter()
            .map(|w| w / self.half_length * half_length)
            .collect();
        Ok(Self {
            kronrod,
            gauss_weights,
            half_length,
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
    let (alpha, beta) = laurie(n);
    // √β_1 … √β_{2n}, and 1 to scale the last step of the recurrence (only p_m's zeros
    // matter there).
    let off: Vec<Dd> = beta[1..]
        .iter()
        .map(|b| b.sqrt())
        .chain([Dd::from_f64(1.0)])
        .collect();
    let (mut nodes, weights) = rule_from_recurrence(alpha, off, 2.0, true)?;
    let m = 2 * n + 1;
    let gauss = gauss_legendre(n)?;
    let mut gauss_weights = vec![0.0; m];
    for (i, (&x, &w)) in gauss.nodes().iter().zip(gauss.weights()).enumerate() {
        nodes[2 * i + 1] = x;
        gauss_weights[2 * i + 1] = w;
    }
    Ok(GaussKronrod {
        kronrod: Rule::with_weight(RuleKind::GaussKronrod, nodes, weights, (-1.0, 1.0), None),
        gauss_weights,
        half_length: 1.0,
    })
}

/// Laurie's algorithm: the recurrence coefficients `(α_k, β_k)`, `k < 2n + 1`, of the
/// Kronrod rule extending the `n`-point Gauss–Legendre rule (`β_0 = 2`, the mass), in
/// double-double (in double, the rounding of its recurrences left Kronrod weights 115ε off
/// at n = 25). A transcription of `r_kronrod` (Laurie 1997; Gautschi's OPQ), indices from 0.
fn laurie(n: usize) -> (Vec<Dd>, Vec<Dd>) {
    let len = 2 * n + 1;
    let zero = Dd::from_f64(0.0);
    let (mut a, mut b) = (vec![zero; len], vec![zero; len]);
    // Legendre: α_k = 0, β_0 = 2, β_k = k²/(4k² − 1), needed up to ⌈3n/2⌉.
    for (k, bk) in b.iter_mut().enumerate().take((3 * n).div_ceil(2) + 1) {
        *bk = if k == 0 {
            Dd::from_f64(2.0)
        } else {
            let k2 = (k * k) as f64;
            Dd::from_f64(k2).div(Dd::from_f64(4.0 * k2 - 1.0))
        };
    }
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
