//! Legendre polynomials by their three-term recurrence, in double and in double-double
//! precision, and the Newton polish shared by the Legendre-family rules.

use crate::double_double::DoubleDouble;

/// `P_n`, `P_{n−1}` and derivatives at one point.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Legendre {
    /// `P_n(x)`.
    pub p: f64,
    /// `P_{n−1}(x)` (0 for `n = 0`).
    pub p_prev: f64,
    /// `P_n'(x)`.
    pub dp: f64,
    /// `P_{n−1}'(x)`.
    pub dp_prev: f64,
    /// `P_n''(x)`.
    pub d2p: f64,
}

/// Values and derivatives by `(k+1)P_{k+1} = (2k+1)xP_k − kP_{k−1}` and the same recurrence
/// differentiated once and twice; no division by `1 − x²`, so it is exact at `x = ±1`.
pub(crate) fn legendre(n: usize, x: f64) -> Legendre {
    let (mut p0, mut d0, mut s0) = (1.0, 0.0, 0.0);
    if n == 0 {
        return Legendre {
            p: 1.0,
            p_prev: 0.0,
            dp: 0.0,
            dp_prev: 0.0,
            d2p: 0.0,
        };
    }
    let (mut p1, mut d1, mut s1) = (x, 1.0, 0.0);
    for k in 1..n {
        let (a, b, c) = ((2 * k + 1) as f64, k as f64, (k + 1) as f64);
        let p2 = (a * x * p1 - b * p0) / c;
        let d2 = (a * (p1 + x * d1) - b * d0) / c;
        let s2 = (a * (2.0 * d1 + x * s1) - b * s0) / c;
        (p0, p1, d0, d1, s0, s1) = (p1, p2, d1, d2, s1, s2);
    }
    Legendre {
        p: p1,
        p_prev: p0,
        dp: d1,
        dp_prev: d0,
        d2p: s1,
    }
}

/// `P_n`, `P_{n−1}`, `P_n'`, `P_{n−1}'` at a double `x`, in double-double arithmetic.
///
/// Used once per node after Newton has converged in double: it gives the residual of the
/// rounded node to ~30 digits, hence the node's sub-ulp offset from the true root, which
/// the weight formulas need near `x = ±1` where a weight is very sensitive to its node.
pub(crate) struct LegendreDd {
    pub p: DoubleDouble,
    pub p_prev: DoubleDouble,
    pub dp: DoubleDouble,
    pub dp_prev: DoubleDouble,
}

pub(crate) fn legendre_dd(n: usize, x: f64) -> LegendreDd {
    let zero = DoubleDouble::from_f64(0.0);
    let one = DoubleDouble::from_f64(1.0);
    if n == 0 {
        return LegendreDd {
            p: one,
            p_prev: zero,
            dp: zero,
            dp_prev: zero,
        };
    }
    let (mut p0, mut p1, mut d0, mut d1) = (one, DoubleDouble::from_f64(x), zero, one);
    for k in 1..n {
        let (a, b, c) = ((2 * k + 1) as f64, k as f64, (k + 1) as f64);
        let p2 = p1.mul_f64(x).mul_f64(a).sub(p0.mul_f64(b)).div_f64(c);
        let d2 = p1
            .add(d1.mul_f64(x))
            .mul_f64(a)
            .sub(d0.mul_f64(b))
            .div_f64(c);
        (p0, p1, d0, d1) = (p1, p2, d1, d2);
    }
    LegendreDd {
        p: p1,
        p_prev: p0,
        dp: d1,
        dp_prev: d0,
    }
}

/// Newton iterations allowed when polishing a Golub–Welsch eigenvalue. The eigenvalue is
/// already within `O(m ε)` of the root, so Newton converges in one to three steps; the
/// bound only stops a cycle between two neighbouring doubles.
const MAX_NEWTON_STEPS: usize = 12;

/// Polishes `x` towards a simple root of `f` by Newton steps in double precision; stops
/// when a step no longer moves `x` by more than an ulp.
pub(crate) fn newton_polish(mut x: f64, f_and_derivative: impl Fn(f64) -> (f64, f64)) -> f64 {
    for _ in 0..MAX_NEWTON_STEPS {
        let (f, df) = f_and_derivative(x);
        if f == 0.0 || df == 0.0 || !df.is_finite() {
            break;
        }
        let step = f / df;
        let next = x - step;
        let moved_at_most_an_ulp =
            (next - x).abs() <= f64::EPSILON * x.abs().max(f64::MIN_POSITIVE);
        x = next;
        if moved_at_most_an_ulp {
            break;
        }
    }
    x
}

/// Exact-in-floating-point `1 − x²` up to one rounding of each factor: `(1 − x)(1 + x)`,
/// where the factor near zero is computed without cancellation (Sterbenz).
pub(crate) fn one_minus_square(x: f64) -> f64 {
    (1.0 - x) * (1.0 + x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_forms_of_low_degree() {
        // P_3 = (5x³ − 3x)/2, P_3' = (15x² − 3)/2, P_3'' = 15x.
        for &x in &[-1.0, -0.3, 0.0, 0.25, 1.0] {
            let l = legendre(3, x);
            let tol = 4.0 * f64::EPSILON * 8.0;
            assert!((l.p - (5.0 * x * x * x - 3.0 * x) / 2.0).abs() < tol);
            assert!((l.p_prev - (3.0 * x * x - 1.0) / 2.0).abs() < tol);
            assert!((l.dp - (15.0 * x * x - 3.0) / 2.0).abs() < tol);
            assert!((l.dp_prev - 3.0 * x).abs() < tol);
            assert!((l.d2p - 15.0 * x).abs() < tol * 4.0);
            let dd = legendre_dd(3, x);
            assert!((dd.p.to_f64() - l.p).abs() < tol);
            assert!((dd.dp.to_f64() - l.dp).abs() < tol);
        }
    }

    #[test]
    fn double_double_resolves_below_an_ulp() {
        // (1 + 2^-60) represented as hi + lo survives a multiply and divide by 3.
        let x = DoubleDouble {
            hi: 1.0,
            lo: 2f64.powi(-60),
        };
        let y = x.mul_f64(3.0).div_f64(3.0).sub(DoubleDouble::from_f64(1.0));
        assert_eq!(y.to_f64(), 2f64.powi(-60));
    }
}
