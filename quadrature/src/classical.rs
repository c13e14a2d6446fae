//! The classical Gauss rules besides Legendre's: Hermite, Laguerre, Jacobi and Chebyshev of
//! both kinds.
//!
//! Hermite, Laguerre and Jacobi from [`MARCH_FROM`] points on: the `O(m)` march along the
//! family's differential equation (`ode_march`), started at a point where one evaluation of
//! the three-term recurrence gives `p_m`, `p_m'` and the number of roots on either side
//! (symmetric weights start at 0 and mirror). Below: Golub–Welsch on the family's Jacobi
//! matrix for a first approximation, Newton on the three-term recurrence of the orthonormal
//! polynomials to polish each node, then one evaluation of the recurrence in double-double
//! (coefficients too) at the polished node: its residual gives the node's offset to the true
//! root below an ulp (Newton in double stops where `p_m`'s rounding hides the root: near 0
//! for Laguerre, whose recurrence cancels there, 70 ulps at m = 500), and the weight is the
//! Christoffel function `λ(x) = μ₀ / Σ_{k<m} p_k(x)²` (a sum of squares, in double-double)
//! taken at the true root to first order in that offset. Without the last step, weights
//! near a sensitive node were off by up to 3e-12 (Laguerre, m = 1000) and 8e-14 (Hermite,
//! m = 200). The recurrence is rescaled by powers of two as it runs, so that `p_k` neither
//! overflows nor underflows where the weight is tiny (Hermite and Laguerre nodes far out,
//! weights down to the smallest normal double). `O(m²)` operations, in double-double; the
//! same path finishes the Gauss–Kronrod rules. Chebyshev rules are closed forms.

use crate::double_double::DoubleDouble as Dd;
use crate::error::at_least;
use crate::golub_welsch::golub_welsch;
use crate::legendre::newton_polish;
use crate::ode_march::{march, weights, Ode, Point, Root};
use crate::rule::{Rule, RuleKind};
use crate::QuadratureError;

/// A rescaling step of the recurrence: `2^600` keeps `p_k²` and the sums finite.
const RESCALE_AT: f64 = 4.149515568880993e180; // 2^600
const RESCALE_BY: f64 = 2.409919865102884e-181; // 2^-600
const RESCALE_EXPONENT: i32 = 600;

/// The Jacobi matrix of an orthonormal family: `diagonal[k] = a_k`, `off[k] = √b_{k+1}`
/// (`m` of each: Golub–Welsch reads the first `m − 1` off-diagonal entries, the recurrence
/// the last too, for `p_m`), so that `off[k] p_{k+1} = (x − a_k) p_k − off[k−1] p_{k−1}`
/// with `p_0 = 1`.
struct Recurrence {
    diagonal: Vec<f64>,
    off: Vec<f64>,
    total_mass: f64,
    /// The same coefficients to about 32 digits, for the final evaluation at each node.
    diagonal_dd: Vec<Dd>,
    off_dd: Vec<Dd>,
}

/// At a node: `p_m` to about 32 digits, `p_m'`, `Σ_{k<m} p_k²` to about 32 digits and
/// `Σ_{k<m} p_k p_k'`, all up to the scale `2^exponent` (sums `2^(2·exponent)`).
struct EvaluationDd {
    p: Dd,
    dp: f64,
    sum: Dd,
    cross: f64,
    exponent: i32,
}

/// `(p_m, p_m')` up to a common power of two (Newton reads only their ratio).
struct Evaluation {
    p: f64,
    dp: f64,
}

impl Recurrence {
    fn evaluate(&self, x: f64) -> Evaluation {
        let m = self.diagonal.len();
        let (mut p_prev, mut p) = (0.0, 1.0);
        let (mut dp_prev, mut dp) = (0.0, 0.0);
        for k in 0..m {
            let back = if k > 0 { self.off[k - 1] } else { 0.0 };
            let shift = x - self.diagonal[k];
            let next = (shift * p - back * p_prev) / self.off[k];
            let dnext = (shift * dp + p - back * dp_prev) / self.off[k];
            (p_prev, p) = (p, next);
            (dp_prev, dp) = (dp, dnext);
            if p.abs().max(dp.abs()) > RESCALE_AT {
                p *= RESCALE_BY;
                p_prev *= RESCALE_BY;
                dp *= RESCALE_BY;
                dp_prev *= RESCALE_BY;
            }
        }
        Evaluation { p, dp }
    }

    fn from_dd(diagonal_dd: Vec<Dd>, off_dd: Vec<Dd>, total_mass: f64) -> Self {
        Self {
            diagonal: diagonal_dd.iter().map(|d| d.to_f64()).collect(),
            off: off_dd.iter().map(|d| d.to_f64()).collect(),
            total_mass,
            diagonal_dd,
            off_dd,
        }
    }

    /// The recurrence in double-double at a double `x` (the polished node).
    fn evaluate_dd(&self, x: f64) -> EvaluationDd {
        let m = self.diagonal.len();
        let x_dd = Dd::from_f64(x);
        let (mut p_prev, mut p) = (Dd::from_f64(0.0), Dd::from_f64(1.0));
        let (mut dp_prev, mut dp) = (0.0, 0.0);
        let (mut sum, mut cross) = (Dd::from_f64(0.0), 0.0);
        let mut exponent = 0;
        for k in 0..m {
            sum = sum.add(p.mul(p));
            cross += p.to_f64() * dp;
            let back = if k > 0 {
                self.off_dd[k - 1]
            } else {
                Dd::from_f64(0.0)
            };
            let shift = x_dd.sub(self.diagonal_dd[k]);
            let next = shift.mul(p).sub(back.mul(p_prev)).div(self.off_dd[k]);
            let pk = p.to_f64();
            let dnext = ((x - self.diagonal[k]) * dp + pk - back.to_f64() * dp_prev) / self.off[k];
            (p_prev, p) = (p, next);
            (dp_prev, dp) = (dp, dnext);
            if p.hi.abs().max(dp.abs()) > RESCALE_AT {
                p = p.scale(RESCALE_BY);
                p_prev = p_prev.scale(RESCALE_BY);
                dp *= RESCALE_BY;
                dp_prev *= RESCALE_BY;
                sum = sum.scale(RESCALE_BY * RESCALE_BY);
                cross *= RESCALE_BY * RESCALE_BY;
                exponent += RESCALE_EXPONENT;
            }
        }
        EvaluationDd {
            p,
            dp,
            sum,
            cross,
            exponent,
        }
    }

    /// Where the `O(m)` march starts: `p_m` and `p_m'` at `x` in double-double (up to a
    /// common power of two), how many roots of `p_m` lie above `x` (the sign changes of the
    /// Sturm sequence `p_0(x), …, p_m(x)`, whose leading coefficients are positive), and
    /// whether `x` is itself a root.
    fn start(&self, x: f64) -> (Point, usize, bool) {
        let m = self.diagonal.len();
        let x_dd = Dd::from_f64(x);
        let zero = Dd::from_f64(0.0);
        let (mut p_prev, mut p) = (zero, Dd::from_f64(1.0));
        let (mut dp_prev, mut dp) = (zero, zero);
        let mut exponent = 0;
        let (mut changes, mut sign) = (0, 1.0);
        for k in 0..m {
            let back = if k > 0 { self.off_dd[k - 1] } else { zero };
            let shift = x_dd.sub(self.diagonal_dd[k]);
            let next = shift.mul(p).sub(back.mul(p_prev)).div(self.off_dd[k]);
            let dnext = shift
                .mul(dp)
                .add(p)
                .sub(back.mul(dp_prev))
                .div(self.off_dd[k]);
            (p_prev, p) = (p, next);
            (dp_prev, dp) = (dp, dnext);
            // A zero is not a sign (p_m's: a root at x).
            if p.hi != 0.0 {
                if p.hi.signum() != sign {
                    changes += 1;
                }
                sign = p.hi.signum();
            }
            if p.hi.abs().max(dp.hi.abs()) > RESCALE_AT {
                p = p.scale(RESCALE_BY);
                p_prev = p_prev.scale(RESCALE_BY);
                dp = dp.scale(RESCALE_BY);
                dp_prev = dp_prev.scale(RESCALE_BY);
                exponent += RESCALE_EXPONENT;
            }
        }
        let point = Point {
            c: x,
            y: p,
            dy: dp,
            exponent,
        };
        (point, changes, p.hi == 0.0)
    }

    /// The rule: Golub–Welsch, Newton on `p_m`, Christoffel weights. With `symmetric`, the
    /// weight is even: the nodes are mirrored from the non-negative half (an odd rule's
    /// middle node is exactly 0).
    fn rule(&self, symmetric: bool) -> Result<(Vec<f64>, Vec<f64>), QuadratureError> {
        let m = self.diagonal.len();
        let (guesses, _) = golub_welsch(&self.diagonal, &self.off[..m - 1], self.total_mass)?;
        let mut nodes = Vec::with_capacity(m);
        let mut weights = Vec::with_capacity(m);
        for (i, &guess) in guesses.iter().enumerate() {
            if symmetric && i < m / 2 {
                // Filled from the mirror image below.
                nodes.push(0.0);
                weights.push(0.0);
                continue;
            }
            // An odd symmetric rule's middle node is 0 exactly.
            let centre = symmetric && m % 2 == 1 && i == m / 2;
            let x = if centre {
                0.0
            } else {
                newton_polish(guess, |x| {
                    let e = self.evaluate(x);
                    (e.p, e.dp)
                })
            };
            // The node's sub-ulp offset to the true root, from p_m in double-double
            // (Newton in double stops where p_m's rounding hides the root), and the
            // Christoffel function at the true root to first order in that offset:
            // λ(x + δ) = λ(x)(1 + δ d ln λ/dx), d ln λ/dx = −2 Σ p_k p_k' / Σ p_k².
            let mut x = x;
            let mut e = self.evaluate_dd(x);
            let mut delta = if e.dp != 0.0 && !centre {
                -e.p.to_f64() / e.dp
            } else {
                0.0
            };
            for _ in 0..3 {
                let moved = x + delta;
                if moved == x || !moved.is_finite() {
                    break;
                }
                x = moved;
                e = self.evaluate_dd(x);
                delta = if e.dp != 0.0 {
                    -e.p.to_f64() / e.dp
                } else {
                    0.0
                };
            }
            let sum = e.sum.to_f64();
            let slope = -2.0 * e.cross / sum;
            // λ = μ₀ / (sum · 2^(2 exponent)), the power applied in two halves so that
            // an intermediate does not underflow before the result does.
            let half = 2f64.powi(-e.exponent);
            nodes.push(x);
            weights.push(self.total_mass / sum * half * half * (1.0 + delta * slope));
        }
        if symmetric {
            for i in 0..m / 2 {
                nodes[i] = -nodes[m - 1 - i];
                weights[i] = weights[m - 1 - i];
            }
        }
        Ok((nodes, weights))
    }
}

/// From this many points on, the Hermite, Laguerre and Jacobi rules take the `O(m)` march
/// (`ode_march`); below, Golub–Welsch with the double-double polish.
pub(crate) const MARCH_FROM: usize = 100;

/// A classical family of degree `m`: its recurrence, its equation, whether its weight is
/// even, and where the march starts.
struct Family {
    recurrence: Recurrence,
    ode: Ode,
    symmetric: bool,
    start: f64,
}

impl Family {
    /// The rule: the march from [`MARCH_FROM`] points on (the polished path where it fails,
    /// which it has not been seen to), the polished path below.
    fn rule(&self) -> Result<(Vec<f64>, Vec<f64>), QuadratureError> {
        let m = self.recurrence.diagonal.len();
        match (m >= MARCH_FROM).then(|| self.marched()).flatten() {
            Some(rule) => Ok(rule),
            None => self.recurrence.rule(self.symmetric),
        }
    }

    /// The rule by the `O(m)` march from `start` (with `symmetric`, the weight is even and
    /// the march starts at 0, runs to the right only, and the rule is mirrored). `None`
    /// where the march failed.
    fn marched(&self) -> Option<(Vec<f64>, Vec<f64>)> {
        let m = self.recurrence.diagonal.len();
        let ode = &self.ode;
        let (point, above, at_root) = if self.symmetric {
            symmetric_start(m)
        } else {
            self.recurrence.start(self.start)
        };
        let x0 = point.c;
        let (p0, _, _) = ode.at(x0);
        // Half the local root spacing π/√(R/P) as the first reach.
        let spacing = 0.5 * std::f64::consts::PI / (ode.r.to_f64() / p0).sqrt();
        let below = m.checked_sub(above + usize::from(at_root))?;
        if self.symmetric && below != above {
            return None;
        }
        let right = march(ode, point, at_root, 1.0, above, spacing).ok()?;
        let left = if self.symmetric {
            Vec::new()
        } else {
            march(ode, point, at_root, -1.0, below, spacing).ok()?
        };
        let centre = at_root.then(|| {
            let (mantissa, exponent) = libm::frexp(point.dy.to_f64());
            Root {
                x: x0,
                rho: 1.0 / (p0 * mantissa * mantissa),
                exponent: exponent + point.exponent,
            }
        });
        let mut roots: Vec<Root> = Vec::with_capacity(m);
        if self.symmetric {
            roots.extend(right.iter().rev().map(|r| Root { x: -r.x, ..*r }));
        } else {
            roots.extend(left.into_iter().rev());
        }
        roots.extend(centre);
        roots.extend(right);
        if roots.len() != m || roots.windows(2).any(|w| w[0].x >= w[1].x) {
            return None;
        }
        let w = weights(&roots, self.recurrence.total_mass);
        Some((roots.iter().map(|r| r.x).collect(), w))
    }
}

/// `(y, y') = (1, 0)` at 0 for an even `m`, `(0, 1)` (a root) for an odd one: where a
/// symmetric family's march starts; above 0 lie `⌊m/2⌋` roots.
fn symmetric_start(m: usize) -> (Point, usize, bool) {
    let odd = m % 2 == 1;
    let (y, dy) = if odd { (0.0, 1.0) } else { (1.0, 0.0) };
    let point = Point {
        c: 0.0,
        y: Dd::from_f64(y),
        dy: Dd::from_f64(dy),
        exponent: 0,
    };
    (point, m / 2, odd)
}

/// The Gauss rule of a recurrence given in double-double (`diagonal` and `off` of length
/// `m`, `off[m − 1]` only scaling `p_m`): the same polish as the classical rules. Used by
/// the Gauss–Kronrod rules, whose Jacobi matrix Laurie's algorithm gives.
pub(crate) fn rule_from_recurrence(
    diagonal: Vec<Dd>,
    off: Vec<Dd>,
    total_mass: f64,
    symmetric: bool,
) -> Result<(Vec<f64>, Vec<f64>), QuadratureError> {
    Recurrence::from_dd(diagonal, off, total_mass).rule(symmetric)
}

fn zero() -> Dd {
    Dd::from_f64(0.0)
}

fn one() -> Dd {
    Dd::from_f64(1.0)
}

pub(crate) fn check_exponent(name: &'static str, value: f64) -> Result<(), QuadratureError> {
    if !(value.is_finite() && value > -1.0) {
        return Err(QuadratureError::InvalidExponent { name, value });
    }
    Ok(())
}

/// Hermite's recurrence and equation: `H'' − 2x H' + 2m H = 0`.
fn hermite(m: usize) -> Family {
    let recurrence = Recurrence::from_dd(
        vec![Dd::from_f64(0.0); m],
        (1..=m)
            .map(|k| Dd::from_f64(0.5 * k as f64).sqrt())
            .collect(),
        std::f64::consts::PI.sqrt(),
    );
    let ode = Ode {
        p: [one(), zero(), zero()],
        q: [zero(), Dd::from_f64(-2.0)],
        r: Dd::from_f64(2.0 * m as f64),
        lower: None,
        upper: None,
    };
    Family {
        recurrence,
        ode,
        symmetric: true,
        start: 0.0,
    }
}

/// Laguerre's: `x L'' + (α + 1 − x) L' + m L = 0`; the march starts amid the roots (they
/// lie in `(0, 4m + 2α + 2)`).
fn laguerre(m: usize, alpha: f64) -> Family {
    let alpha_dd = Dd::from_f64(alpha);
    let recurrence = Recurrence::from_dd(
        (0..m)
            .map(|k| Dd::from_f64(2.0 * k as f64 + 1.0).add(alpha_dd))
            .collect(),
        (1..=m)
            .map(|k| {
                let k = Dd::from_f64(k as f64);
                k.mul(k.add(alpha_dd)).sqrt()
            })
            .collect(),
        libm::tgamma(alpha + 1.0),
    );
    let ode = Ode {
        p: [zero(), one(), zero()],
        q: [one().add(alpha_dd), Dd::from_f64(-1.0)],
        r: Dd::from_f64(m as f64),
        lower: Some(0.0),
        upper: None,
    };
    Family {
        recurrence,
        ode,
        symmetric: false,
        start: 2.0 * m as f64 + alpha + 1.0,
    }
}

/// The `m`-point Gauss–Hermite rule: `∫_{−∞}^{∞} e^{−x²} f(x) dx ≈ Σ_i w_i f(x_i)`, exact for
/// polynomials `f` of degree `2m − 1`. Nodes ascending and symmetric about 0; weights
/// below the smallest normal double (the outer nodes of rules past `m ≈ 350`) are 0.
///
/// ```
/// use lgsvi_quadrature::gauss_hermite;
/// // ∫ e^{−x²} x⁴ dx = 3√π/4, exact with 3 points (degree 5).
/// let rule = gauss_hermite(3)?;
/// let moment = rule.integrate(|x| x.powi(4));
/// assert!((moment - 0.75 * std::f64::consts::PI.sqrt()).abs() < 1e-15);
/// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
/// ```
///
/// # Errors
/// [`QuadratureError::TooFewPoints`] for `m = 0`.
pub fn gauss_hermite(m: usize) -> Result<Rule, QuadratureError> {
    at_least("Gauss-Hermite", m, 1)?;
    let (nodes, weights) = hermite(m).rule()?;
    Ok(Rule::with_weight(
        RuleKind::GaussHermite,
        nodes,
        weights,
        (f64::NEG_INFINITY, f64::INFINITY),
        None,
    ))
}

/// The `m`-point generalised Gauss–Laguerre rule:
/// `∫_0^∞ x^α e^{−x} f(x) dx ≈ Σ_i w_i f(x_i)` (`α > −1`), exact for polynomials of degree
/// `2m − 1`. Weights below the smallest normal double are 0.
///
/// ```
/// use lgsvi_quadrature::gauss_laguerre;
/// // ∫_0^∞ √x e^{−x} x² dx = Γ(3.5) = 15√π/8.
/// let rule = gauss_laguerre(4, 0.5)?;
/// let value = rule.integrate(|x| x * x);
/// assert!((value - 15.0 * std::f64::consts::PI.sqrt() / 8.0).abs() < 1e-14);
/// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
/// ```
///
/// # Errors
/// [`QuadratureError::TooFewPoints`] for `m = 0`, [`QuadratureError::InvalidExponent`] for
/// `α ≤ −1` or not finite (the weight is not integrable at 0).
pub fn gauss_laguerre(m: usize, alpha: f64) -> Result<Rule, QuadratureError> {
    at_least("Gauss-Laguerre", m, 1)?;
    check_exponent("alpha", alpha)?;
    let (nodes, weights) = laguerre(m, alpha).rule()?;
    Ok(Rule::with_weight(
        RuleKind::GaussLaguerre,
        nodes,
        weights,
        (0.0, f64::INFINITY),
        Some((alpha, 0.0)),
    ))
}

/// The monic Jacobi recurrence `p_{k+1} = (x − a_k) p_k − b_k p_{k−1}` of the weight
/// `(1 − x)^α (1 + x)^β`, in double-double: `a_k` for `k < count`, and `b_1 … b_count`.
pub(crate) fn jacobi_coefficients(count: usize, alpha: f64, beta: f64) -> (Vec<Dd>, Vec<Dd>) {
    let (a, b) = (Dd::from_f64(alpha), Dd::from_f64(beta));
    let s = a.add(b);
    let (one, two, four) = (Dd::from_f64(1.0), Dd::from_f64(2.0), Dd::from_f64(4.0));
    let diagonal = (0..count)
        .map(|k| {
            if k == 0 {
                b.sub(a).div(s.add(two))
            } else {
                let c = Dd::from_f64(2.0 * k as f64).add(s);
                b.sub(a).mul(b.add(a)).div(c.mul(c.add(two)))
            }
        })
        .collect();
    let squares = (1..=count)
        .map(|k| {
            let kd = Dd::from_f64(k as f64);
            let c = Dd::from_f64(2.0 * k as f64).add(s);
            let c2 = c.mul(c);
            if k == 1 {
                // b₁ with the factor (1 + α + β) of numerator and denominator cancelled
                // (it vanishes for α + β = −1).
                four.mul(one.add(a)).mul(one.add(b)).div(c2.mul(c.add(one)))
            } else {
                four.mul(kd)
                    .mul(kd.add(a))
                    .mul(kd.add(b))
                    .mul(kd.add(s))
                    .div(c2.mul(c.add(one)).mul(c.sub(one)))
            }
        })
        .collect();
    (diagonal, squares)
}

/// `∫_{−1}^{1} (1 − x)^α (1 + x)^β dx = 2^{α+β+1} Γ(α+1) Γ(β+1) / Γ(α+β+2)`.
pub(crate) fn jacobi_mass(alpha: f64, beta: f64) -> f64 {
    2f64.powf(alpha + beta + 1.0) * libm::tgamma(alpha + 1.0) * libm::tgamma(beta + 1.0)
        / libm::tgamma(alpha + beta + 2.0)
}

/// Jacobi's: `(1 − x²) P'' + (β − α − (α + β + 2)x) P' + m(m + α + β + 1) P = 0`.
fn jacobi(m: usize, alpha: f64, beta: f64) -> Family {
    let (a, b) = (Dd::from_f64(alpha), Dd::from_f64(beta));
    let s = a.add(b);
    let (one, two) = (Dd::from_f64(1.0), Dd::from_f64(2.0));
    let (diagonal, squares) = jacobi_coefficients(m, alpha, beta);
    let off = squares.into_iter().map(Dd::sqrt).collect();
    let total_mass = jacobi_mass(alpha, beta);
    let recurrence = Recurrence::from_dd(diagonal, off, total_mass);
    let ode = Ode {
        p: [Dd::from_f64(1.0), zero(), Dd::from_f64(-1.0)],
        q: [b.sub(a), s.add(two).mul_f64(-1.0)],
        r: Dd::from_f64(m as f64).mul(Dd::from_f64(m as f64).add(s).add(one)),
        lower: Some(-1.0),
        upper: Some(1.0),
    };
    Family {
        recurrence,
        ode,
        symmetric: alpha == beta,
        start: 0.0,
    }
}

/// The `m`-point Gauss–Jacobi rule:
/// `∫_{−1}^{1} (1 − x)^α (1 + x)^β f(x) dx ≈ Σ_i w_i f(x_i)` (`α, β > −1`), exact for
/// polynomials of degree `2m − 1`. [`Rule::on`] maps it to `[a, b]` with the weight
/// `(b − x)^α (x − a)^β`: the weights scale by `((b − a)/2)^{α+β+1}`.
///
/// ```
/// use lgsvi_quadrature::gauss_jacobi;
/// // ∫_{−1}^{1} (1 − x)^{1/2} (1 + x)^{−1/2} dx = π.
/// let rule = gauss_jacobi(5, 0.5, -0.5)?;
/// assert!((rule.integrate(|_| 1.0) - std::f64::consts::PI).abs() < 1e-14);
/// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
/// ```
///
/// # Errors
/// [`QuadratureError::TooFewPoints`] for `m = 0`, [`QuadratureError::InvalidExponent`] for
/// `α` or `β` ≤ −1 or not finite.
pub fn gauss_jacobi(m: usize, alpha: f64, beta: f64) -> Result<Rule, QuadratureError> {
    at_least("Gauss-Jacobi", m, 1)?;
    check_exponent("alpha", alpha)?;
    check_exponent("beta", beta)?;
    let (nodes, weights) = jacobi(m, alpha, beta).rule()?;
    Ok(Rule::with_weight(
        RuleKind::GaussJacobi,
        nodes,
        weights,
        (-1.0, 1.0),
        Some((alpha, beta)),
    ))
}

/// `sin(π j / (2n))` for an integer `j` with `|j| ≤ n`: the argument formed exactly up to
/// one rounding, so that nodes near 0 keep their relative accuracy and mirror exactly.
fn sin_half_turn_fraction(j: i64, n: usize) -> f64 {
    (std::f64::consts::PI * j as f64 / (2 * n) as f64).sin()
}

/// The `m`-point Gauss–Chebyshev rule of the first kind:
/// `∫_{−1}^{1} f(x) / √(1 − x²) dx ≈ (π/m) Σ_i f(x_i)`, `x_i = cos((2i − 1)π/(2m))`, exact
/// for degree `2m − 1` (closed form).
///
/// ```
/// use lgsvi_quadrature::gauss_chebyshev_first;
/// // ∫ x² / √(1 − x²) dx = π/2.
/// let rule = gauss_chebyshev_first(2)?;
/// assert!((rule.integrate(|x| x * x) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
/// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
/// ```
///
/// # Errors
/// [`QuadratureError::TooFewPoints`] for `m = 0`.
pub fn gauss_chebyshev_first(m: usize) -> Result<Rule, QuadratureError> {
    at_least("Gauss-Chebyshev (first kind)", m, 1)?;
    // x_i = −cos((2i + 1)π/(2m)) = sin((2i + 1 − m)π/(2m)), i = 0…m−1 ascending.
    let nodes = (0..m)
        .map(|i| sin_half_turn_fraction(2 * i as i64 + 1 - m as i64, m))
        .collect();
    let weights = vec![std::f64::consts::PI / m as f64; m];
    Ok(Rule::with_weight(
        RuleKind::GaussChebyshevFirst,
        nodes,
        weights,
        (-1.0, 1.0),
        Some((-0.5, -0.5)),
    ))
}

/// The `m`-point Gauss–Chebyshev rule of the second kind:
/// `∫_{−1}^{1} √(1 − x²) f(x) dx ≈ Σ_i w_i f(x_i)`, `x_i = cos(iπ/(m + 1))`,
/// `w_i = π/(m + 1) sin²(iπ/(m + 1))`, exact for degree `2m − 1` (closed form).
///
/// ```
/// use lgsvi_quadrature::gauss_chebyshev_second;
/// // ∫ √(1 − x²) dx = π/2.
/// let rule = gauss_chebyshev_second(3)?;
/// assert!((rule.integrate(|_| 1.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
/// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
/// ```
///
/// # Errors
/// [`QuadratureError::TooFewPoints`] for `m = 0`.
pub fn gauss_chebyshev_second(m: usize) -> Result<Rule, QuadratureError> {
    at_least("Gauss-Chebyshev (second kind)", m, 1)?;
    let n = m + 1;
    // x_i = −cos((i + 1)π/n) = sin((2(i + 1) − n)π/(2n)); the weight's sin((i + 1)π/n)
    // from the nearer end (sin(kπ/n) = sin((n − k)π/n)), so that its argument is at most π/2
    // and the small weights near ±1 keep their relative accuracy.
    let (nodes, weights) = (0..m)
        .map(|i| {
            let j = 2 * (i as i64 + 1) - n as i64;
            let x = sin_half_turn_fraction(j, n);
            let k = (i + 1).min(n - i - 1);
            let s = (std::f64::consts::PI * k as f64 / n as f64).sin();
            (x, std::f64::consts::PI / n as f64 * s * s)
        })
        .unzip();
    Ok(Rule::with_weight(
        RuleKind::GaussChebyshevSecond,
        nodes,
        weights,
        (-1.0, 1.0),
        Some((0.5, 0.5)),
    ))
}

#[cfg(test)]
mod march_tests {
    use super::*;

    /// The march against the `O(m²)` polished path on the same recurrence (two independent
    /// routes to the same rule): the largest node difference in ulps of `max(|x|, 1)` and
    /// the largest relative weight difference in ε (weights above 1e-300).
    fn compare(family: Family) -> (f64, f64) {
        let m = family.recurrence.diagonal.len();
        let (xm, wm) = family.marched().expect("the march finds every root");
        let (xr, wr) = family.recurrence.rule(family.symmetric).unwrap();
        let mut node = 0.0f64;
        let mut weight = 0.0f64;
        for i in 0..m {
            node = node.max((xm[i] - xr[i]).abs() / (f64::EPSILON * xr[i].abs().max(1.0)));
            if wr[i] > 1e-300 {
                weight = weight.max((wm[i] - wr[i]).abs() / (f64::EPSILON * wr[i]));
            }
        }
        (node, weight)
    }

    /// Every node the same double and every weight within 8ε (each route is within about
    /// 3ε of the 60-digit references), for Hermite, six Laguerre and nine Jacobi weights
    /// (exponents near −1, large ones and strongly unsymmetric ones among them), even and
    /// odd `m`, small and large.
    #[test]
    fn the_march_and_the_polish_agree() {
        for m in [20usize, 21, 100, 201, 1000] {
            let mut families = vec![("hermite".to_string(), hermite(m))];
            for alpha in [0.0, 0.5, -0.5, 2.0, -0.9, 40.0] {
                families.push((format!("laguerre {alpha}"), laguerre(m, alpha)));
            }
            for (alpha, beta) in [
                (0.0, 0.0),
                (0.5, -0.5),
                (2.0, 1.0),
                (-0.7, 0.3),
                (1.5, 1.5),
                (-0.9, -0.9),
                (4.0, -0.5),
                (20.0, 0.5),
                (-0.99, 30.0),
            ] {
                families.push((format!("jacobi {alpha} {beta}"), jacobi(m, alpha, beta)));
            }
            for (name, family) in families {
                let (node, weight) = compare(family);
                assert!(
                    node <= 1.0,
                    "{name} m = {m}: nodes differ by {node:.2} ulps"
                );
                assert!(
                    weight <= 8.0,
                    "{name} m = {m}: weights differ by {weight:.2}ε"
                );
            }
        }
    }
}
