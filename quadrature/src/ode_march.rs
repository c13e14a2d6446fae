//! Classical Gauss rules of any size in `O(m)`: the roots of `p_m` found one after the other
//! along the line from the differential equation `p_m` solves (the idea of Glaser, Liu and
//! Rokhlin, SIAM J. Sci. Comput. 29, 2007).
//!
//! Every classical family's `p_m` solves `P(x) y'' + Q(x) y' + R y = 0` with `P` of degree
//! at most 2, `Q` of degree at most 1 and `R` constant:
//!
//! | family | `P` | `Q` | `R` |
//! |---|---|---|---|
//! | Hermite | `1` | `−2x` | `2m` |
//! | Laguerre `α` | `x` | `α + 1 − x` | `m` |
//! | Jacobi `α, β` | `1 − x²` | `β − α − (α + β + 2)x` | `m(m + α + β + 1)` |
//!
//! Differentiating the equation `j` times gives the Taylor coefficients of `y` about any
//! point from `y` and `y'` there (a two-term recurrence, `O(1)` per coefficient), so from
//! one point where `(y, y')` is known the march finds the next root by scanning the local
//! series for a sign change and refining by Newton's method on it, carries `(y, y')` to the
//! root, and goes on: `O(1)` work per root. Where the march starts, `(y, y')` and the number
//! of roots on either side come from one evaluation of the three-term recurrence (its Sturm
//! sequence's sign changes count the roots above the point), `O(m)` once.
//!
//! Accuracy. The series and the carried `(y, y')` are in double-double, so that nothing
//! accumulates over the `m` roots: each node is the double nearest the root of the local
//! series (one double-double Newton correction after Newton in double), and each weight is
//! `w_k ∝ 1 / (P(x_k) y'(x_k)²)` (the same closed form for every family) taken at the true
//! root to first order in the node's sub-ulp offset and normalised by the total mass
//! `Σ w_k = μ₀`. The carried `y` is kept as a double-double mantissa and a power of two
//! (exact rescaling), so no weight overflows or underflows before the last multiplication.
//! A Taylor series about `x` converges within the distance to the nearest zero of `P` (an
//! end of the interval); the march never uses one beyond half that distance, re-expanding
//! on the way where a root near an end needs it.

use crate::double_double::DoubleDouble as Dd;

/// The most Taylor coefficients of one local series. With the reach at most half the
/// distance to a singular point and about two root spacings, the terms fall below 1e-34 of
/// the largest within about 130; more means the march left its assumptions.
const MAX_TERMS: usize = 600;
/// The most re-expansions without a root before the march gives up.
const MAX_SUBSTEPS: usize = 4000;
/// Scan points per local series.
const SCAN: usize = 8;

/// `P(x) y'' + Q(x) y' + R y = 0` with `P = p₀ + p₁x + p₂x²`, `Q = q₀ + q₁x`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Ode {
    pub(crate) p: [Dd; 3],
    pub(crate) q: [Dd; 2],
    pub(crate) r: Dd,
    /// The zeros of `P` below and above the roots (the interval's finite ends).
    pub(crate) lower: Option<f64>,
    pub(crate) upper: Option<f64>,
}

/// The coefficients of the `j`-times differentiated equation at a point `c`:
/// `P y⁽ʲ⁺²⁾ + (Q + jP') y⁽ʲ⁺¹⁾ + (R + jQ' + j(j−1)p₂) y⁽ʲ⁾ = 0`.
#[derive(Clone, Copy)]
struct Local {
    inv_p: Dd,
    q: Dd,
    dp: Dd,
    r: Dd,
    dq: Dd,
    p2: Dd,
}

impl Ode {
    fn local(&self, c: f64) -> Local {
        let x = Dd::from_f64(c);
        let [_, p1, p2] = self.p;
        let p = self.p_at(x);
        Local {
            inv_p: Dd::from_f64(1.0).div(p),
            q: self.q[0].add(x.mul(self.q[1])),
            dp: p1.add(x.mul(p2).scale(2.0)),
            r: self.r,
            dq: self.q[1],
            p2,
        }
    }

    /// `P(x) = p₀ + x(p₁ + x p₂)` in double-double at a double-double `x`.
    fn p_at(&self, x: Dd) -> Dd {
        let [p0, p1, p2] = self.p;
        p0.add(x.mul(p1.add(x.mul(p2))))
    }

    /// `P(x)`, `P'(x)`, `Q(x)`, formed in double-double and rounded: `1 − x²` near `±1`
    /// keeps its relative accuracy (in double it would lose `1/(1 − x²)` ulps).
    pub(crate) fn at(&self, x: f64) -> (f64, f64, f64) {
        let xd = Dd::from_f64(x);
        let [_, p1, p2] = self.p;
        let p = self.p_at(xd);
        let dp = p1.add(xd.mul(p2).scale(2.0));
        let q = self.q[0].add(xd.mul(self.q[1]));
        (p.to_f64(), dp.to_f64(), q.to_f64())
    }

    /// How far from `c` in direction `d` the nearest singular point lies.
    fn distance(&self, c: f64, d: f64) -> f64 {
        let end = if d > 0.0 { self.upper } else { self.lower };
        end.map_or(f64::INFINITY, |e| (e - c).abs())
    }
}

/// `y` and `y'` at the double `c`, both times `2^exponent`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Point {
    pub(crate) c: f64,
    pub(crate) y: Dd,
    pub(crate) dy: Dd,
    pub(crate) exponent: i32,
}

impl Point {
    /// The same point with `y'` scaled into `[1, 2)` by a power of two (exact).
    fn rescaled(mut self) -> Self {
        let magnitude = self.dy.hi.abs().max(self.y.hi.abs());
        if magnitude == 0.0 || !magnitude.is_finite() {
            return self;
        }
        let (_, k) = libm::frexp(magnitude);
        let k = k - 1;
        let factor = libm::ldexp(1.0, -k);
        self.y = self.y.scale(factor);
        self.dy = self.dy.scale(factor);
        self.exponent += k;
        self
    }
}

/// A root found by the march: the node, and `ρ 2^(−2·exponent)` proportional to its weight.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Root {
    pub(crate) x: f64,
    pub(crate) rho: f64,
    pub(crate) exponent: i32,
}

/// The Taylor coefficients `a_j = y⁽ʲ⁾(c) σʲ / j!` in double, up to where they stop mattering.
fn series_f64(local: &Local, sigma: f64, y: f64, dy: f64, out: &mut Vec<f64>) -> bool {
    let (inv_p, q, dp) = (local.inv_p.to_f64(), local.q.to_f64(), local.dp.to_f64());
    let (r, dq, p2) = (local.r.to_f64(), local.dq.to_f64(), local.p2.to_f64());
    out.clear();
    out.push(y);
    out.push(dy * sigma);
    let mut largest = y.abs().max(out[1].abs());
    let sigma2 = sigma * sigma;
    for j in 0..MAX_TERMS {
        let jf = j as f64;
        let next = -((q + jf * dp) * (jf + 1.0) * sigma * out[j + 1]
            + (r + jf * dq + jf * (jf - 1.0) * p2) * sigma2 * out[j])
            * inv_p
            / ((jf + 1.0) * (jf + 2.0));
        out.push(next);
        largest = largest.max(next.abs());
        if j > 2 && next.abs() + out[j + 1].abs() <= 1e-20 * largest {
            return true;
        }
        if !next.is_finite() {
            return false;
        }
    }
    false
}

/// The same coefficients in double-double, as far as they matter at `|t| ≤ reach` (≤ 1):
/// until two consecutive terms `a_j tʲ` fall below 1e-34 of the largest.
fn series_dd(local: &Local, sigma: f64, y: Dd, dy: Dd, reach: f64, out: &mut Vec<Dd>) -> bool {
    out.clear();
    out.push(y);
    out.push(dy.mul_f64(sigma));
    // The equation's coefficients scaled by σ and σ² once; per term only products with
    // small integers (exact in a double) and three double-double products.
    let sigma2 = Dd::from_f64(sigma).mul_f64(sigma);
    let (qs, dps) = (local.q.mul_f64(sigma), local.dp.mul_f64(sigma));
    let (rs, dqs, p2s) = (
        local.r.mul(sigma2),
        local.dq.mul(sigma2),
        local.p2.mul(sigma2),
    );
    let mut power = reach;
    let mut largest = y.hi.abs().max(out[1].hi.abs() * power);
    let mut previous = out[1].hi.abs() * power;
    for j in 0..MAX_TERMS {
        let jf = j as f64;
        let first = qs.add(dps.mul_f64(jf)).mul_f64(jf + 1.0).mul(out[j + 1]);
        let second = rs
            .add(dqs.mul_f64(jf))
            .add(p2s.mul_f64(jf * (jf - 1.0)))
            .mul(out[j]);
        let next = first
            .add(second)
            .mul(local.inv_p)
            .div_f64(-((jf + 1.0) * (jf + 2.0)));
        out.push(next);
        power *= reach;
        let term = next.hi.abs() * power;
        largest = largest.max(term);
        if j > 2 && term + previous <= 1e-34 * largest {
            return true;
        }
        previous = term;
        if !next.hi.is_finite() {
            return false;
        }
    }
    false
}

/// `(Σ a_j tʲ, Σ j a_j tʲ⁻¹)`.
fn horner(a: &[f64], t: f64) -> (f64, f64) {
    let (mut v, mut d) = (0.0, 0.0);
    for &c in a.iter().rev() {
        d = d * t + v;
        v = v * t + c;
    }
    (v, d)
}

fn horner_dd(a: &[Dd], t: Dd) -> (Dd, Dd) {
    let zero = Dd::from_f64(0.0);
    let (mut v, mut d) = (zero, zero);
    for &c in a.iter().rev() {
        d = d.mul(t).add(v);
        v = v.mul(t).add(c);
    }
    (v, d)
}

/// Why the march stopped short (a defect of this module if it ever happens: the callers
/// fall back to the `O(m²)` path).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct MarchFailed;

/// Marches from `start` in direction `d` (±1) and returns the next `count` roots in the
/// order met. `at_root`: `start` is itself a root (not returned). `spacing`: an estimate of
/// the distance to the next root (a smaller one costs only time).
pub(crate) fn march(
    ode: &Ode,
    start: Point,
    at_root: bool,
    d: f64,
    count: usize,
    spacing: f64,
) -> Result<Vec<Root>, MarchFailed> {
    let mut roots = Vec::with_capacity(count);
    let (mut point, mut at_root, mut spacing) = (start.rescaled(), at_root, spacing);
    let mut last_root = at_root.then_some(point.c);
    let (mut a, mut a_dd) = (Vec::with_capacity(64), Vec::with_capacity(64));
    let mut a_short = Vec::with_capacity(16);
    let mut substeps = 0;
    while roots.len() < count {
        let reach = (2.0 * spacing).min(0.5 * ode.distance(point.c, d));
        if !(reach > 0.0 && reach.is_finite()) {
            return Err(MarchFailed);
        }
        let sigma = d * reach;
        let local = ode.local(point.c);
        if !series_f64(&local, sigma, point.y.to_f64(), point.dy.to_f64(), &mut a) {
            return Err(MarchFailed);
        }
        // The sign just past the start: y's own there, or y' σ's at a root (where y is
        // only the rounding of the root).
        let reference = if at_root { a[1] } else { a[0] };
        let mut bracket = None;
        let mut previous = 0.0;
        for i in 1..=SCAN {
            let t = i as f64 / SCAN as f64;
            let (v, _) = horner(&a, t);
            if v == 0.0 || v.signum() != reference.signum() {
                bracket = Some((previous, t));
                break;
            }
            previous = t;
        }
        let Some((mut lo, mut hi)) = bracket else {
            // No root within this series' reach: carry (y, y') to its end and expand again.
            let next = point.c + sigma;
            point = carry(&local, sigma, &point, next, &mut a_dd)?.rescaled();
            at_root = false;
            substeps += 1;
            if substeps > MAX_SUBSTEPS {
                return Err(MarchFailed);
            }
            continue;
        };
        if at_root && lo == 0.0 {
            // Never back onto the root we stand on.
            lo = hi / 64.0;
        }
        // Newton on the series, kept inside the bracket by bisection.
        let sign_lo = horner(&a, lo).0.signum();
        let mut t = 0.5 * (lo + hi);
        for _ in 0..100 {
            let (v, dv) = horner(&a, t);
            if v == 0.0 {
                break;
            }
            if v.signum() == sign_lo {
                lo = t;
            } else {
                hi = t;
            }
            let newton = t - v / dv;
            let next = if newton > lo && newton < hi && dv != 0.0 {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if (next - t).abs() <= 2.0 * f64::EPSILON * t.abs() {
                t = next;
                break;
            }
            t = next;
        }
        let mut x = point.c + sigma * t;
        // The root to below an ulp: Newton in double-double on the same series.
        // Evaluated at the root, t ≈ the double Newton's (a little past it for the
        // corrections).
        let at_most = (1.01 * t + 1e-3).min(1.0);
        if !series_dd(&local, sigma, point.y, point.dy, at_most, &mut a_dd) {
            return Err(MarchFailed);
        }
        let mut at = evaluate(&a_dd, sigma, point.c, x);
        for _ in 0..3 {
            let delta = -at.0.to_f64() / at.1.to_f64();
            let moved = x + delta;
            if moved == x || !moved.is_finite() {
                break;
            }
            // (y, y') at the moved node from a short series about x (the move is an ulp or
            // two: a handful of terms), not the long one about the centre again.
            let here = Point {
                c: x,
                y: at.0,
                dy: at.1,
                exponent: 0,
            };
            let step = moved - x;
            at = match carry(&ode.local(x), step, &here, moved, &mut a_short) {
                Ok(p) => (p.y, p.dy),
                Err(e) => return Err(e),
            };
            x = moved;
        }
        let (y, dy) = at;
        let next = Point {
            c: x,
            y,
            dy,
            exponent: point.exponent,
        }
        .rescaled();
        // The weight at the true root x* = x + δ (δ = −y/y' in double-double: the node's
        // sub-ulp offset), from the long series about the centre: near an end of a Jacobi
        // or Laguerre interval ln ρ changes by 1/(1 ∓ x) per unit of x (8e9 at the end
        // roots of 10⁵ points), so neither the rounded node nor a first-order correction
        // would do.
        // δ to second order: y + y'δ + y''δ²/2 = 0, y'' = −(Q y' + R y)/P. Near an end
        // y''/y' ~ 1/(1 ∓ x) makes the second-order term 4e-8 of δ at 10⁵ points (16ε
        // in the weight), the third 1e-15 of that.
        let first = y.div(dy).mul_f64(-1.0);
        let (p_x, _, q_x) = ode.at(x);
        let curvature = -(q_x + ode.r.to_f64() * (y.to_f64() / dy.to_f64())) / p_x;
        let d1 = first.to_f64();
        let delta = first.add(Dd::from_f64(-0.5 * curvature * d1 * d1));
        let x_true = Dd::from_f64(x).add(delta);
        let t_true = x_true.sub(Dd::from_f64(point.c)).div(Dd::from_f64(sigma));
        let (_, slope) = horner_dd(&a_dd, t_true);
        let p_true = ode.p_at(x_true);
        let (mantissa, k) = libm::frexp(slope.div_f64(sigma).to_f64());
        let rho = 1.0 / (p_true.to_f64() * mantissa * mantissa);
        if !(rho.is_finite() && rho > 0.0) {
            return Err(MarchFailed);
        }
        roots.push(Root {
            x,
            rho,
            exponent: point.exponent + k,
        });
        if let Some(previous_root) = last_root {
            spacing = (x - previous_root).abs();
        }
        last_root = Some(x);
        point = next;
        at_root = true;
        substeps = 0;
    }
    Ok(roots)
}

/// `(y, y')` at the double `x` from the double-double series about `c` with scale `σ`.
fn evaluate(a: &[Dd], sigma: f64, c: f64, x: f64) -> (Dd, Dd) {
    // t = (x − c)/σ: the difference of two doubles is exact in double-double.
    let t = Dd::from_f64(x)
        .sub(Dd::from_f64(c))
        .div(Dd::from_f64(sigma));
    let (v, d) = horner_dd(a, t);
    (v, d.div_f64(sigma))
}

/// The point `next` from the series about `point`.
fn carry(
    local: &Local,
    sigma: f64,
    point: &Point,
    next: f64,
    a_dd: &mut Vec<Dd>,
) -> Result<Point, MarchFailed> {
    if !series_dd(local, sigma, point.y, point.dy, 1.0, a_dd) {
        return Err(MarchFailed);
    }
    let (y, dy) = evaluate(a_dd, sigma, point.c, next);
    Ok(Point {
        c: next,
        y,
        dy,
        exponent: point.exponent,
    })
}

/// The weights `μ₀ ρ_k 2^(−2e_k) / Σ_j ρ_j 2^(−2e_j)` of the roots of a whole rule.
/// Weights below the smallest normal double are 0.
pub(crate) fn weights(roots: &[Root], mass: f64) -> Vec<f64> {
    let least = roots.iter().map(|r| r.exponent).min().unwrap_or(0);
    let relative: Vec<f64> = roots
        .iter()
        .map(|r| libm::ldexp(r.rho, -2 * (r.exponent - least)))
        .collect();
    let mut sum = Dd::from_f64(0.0);
    for &v in &relative {
        sum = sum.add(Dd::from_f64(v));
    }
    let scale = Dd::from_f64(mass).div(sum);
    // The scale before the power of two, so that a weight loses no digits to a subnormal
    // intermediate: only the final ldexp can underflow.
    roots
        .iter()
        .map(|r| {
            let w = libm::ldexp(scale.mul_f64(r.rho).to_f64(), -2 * (r.exponent - least));
            if w < f64::MIN_POSITIVE {
                0.0
            } else {
                w
            }
        })
        .collect()
}
