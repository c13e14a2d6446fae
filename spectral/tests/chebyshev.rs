//! The Chebyshev series type against closed forms: a fit to machine precision, the roots
//! of a cosine, an integral, derivatives and integrals of the series, products, the
//! refusals.

use lgsvi_spectral::{Chebyshev, SpectralError};
use std::f64::consts::PI;

fn grid(a: f64, b: f64, n: usize) -> impl Iterator<Item = f64> {
    (0..=n).map(move |i| a + (b - a) * i as f64 / n as f64)
}

/// The check: sin(5x)/(1 + x²) on [−2, 3] within 1e-14 of the function at 2001
/// points (the function's own rounding is ~2e-16; Clenshaw's on ~60 terms a few ε).
#[test]
fn a_smooth_function_is_fitted_to_machine_precision() {
    let f = |x: f64| (5.0 * x).sin() / (1.0 + x * x);
    let fit = Chebyshev::fit(f, -2.0, 3.0).unwrap();
    let worst = grid(-2.0, 3.0, 2000)
        .map(|x| (fit.evaluate(x).unwrap() - f(x)).abs())
        .fold(0.0f64, f64::max);
    println!("{} coefficients, worst error {worst:e}", fit.len());
    assert!(worst < 1e-14, "worst error {worst:e}");
    // A looser tolerance keeps fewer coefficients and meets it.
    let loose = Chebyshev::fit_with_tolerance(f, -2.0, 3.0, 1e-8).unwrap();
    assert!(loose.len() < fit.len());
    let worst = grid(-2.0, 3.0, 2000)
        .map(|x| (loose.evaluate(x).unwrap() - f(x)).abs())
        .fold(0.0f64, f64::max);
    assert!(worst < 1e-7, "tolerance 1e-8: worst error {worst:e}");
}

/// The roots of cos(10x) on [0, 3] are (2k + 1)π/20, k = 0..9, within 1e-14.
#[test]
fn the_roots_of_a_cosine_are_found() {
    let roots = Chebyshev::fit(|x| (10.0 * x).cos(), 0.0, 3.0)
        .unwrap()
        .roots();
    assert_eq!(roots.len(), 10, "{roots:?}");
    for (k, r) in roots.iter().enumerate() {
        let exact = (2 * k + 1) as f64 * PI / 20.0;
        assert!((r - exact).abs() < 1e-14, "root {k}: {r} vs {exact}");
    }
    // A linear series and a series without roots in its interval.
    let linear = Chebyshev::fit(|x| x - 0.25, 0.0, 1.0).unwrap().roots();
    assert!(
        linear.len() == 1 && (linear[0] - 0.25).abs() < 1e-16,
        "{linear:?}"
    );
    assert!(Chebyshev::fit(|x| 2.0 + x.sin(), 0.0, 3.0)
        .unwrap()
        .roots()
        .is_empty());
}

/// ∫₀³ eˣ sin x dx = (e³(sin 3 − cos 3) + 1)/2 within 1e-14 relative; the indefinite
/// integral and the derivative against their closed forms.
#[test]
fn integrals_and_derivatives_match_closed_forms() {
    let f = Chebyshev::fit(|x| x.exp() * x.sin(), 0.0, 3.0).unwrap();
    let exact = (3f64.exp() * (3f64.sin() - 3f64.cos()) + 1.0) / 2.0;
    let value = f.definite_integral();
    assert!(
        (value - exact).abs() < 1e-14 * exact.abs(),
        "{value} vs {exact}"
    );
    let big = f.integral();
    let primitive = |x: f64| (x.exp() * (x.sin() - x.cos()) + 1.0) / 2.0;
    for x in grid(0.0, 3.0, 300) {
        // Values up to 12: a few ε relative.
        assert!(
            (big.evaluate(x).unwrap() - primitive(x)).abs() < 1e-13,
            "F({x})"
        );
    }
    let slope = f.derivative();
    for x in grid(0.0, 3.0, 300) {
        let exact = x.exp() * (x.sin() + x.cos());
        // Differentiation amplifies the fit's rounding by ~N²: 1e-12 on values up to 20.
        assert!(
            (slope.evaluate(x).unwrap() - exact).abs() < 1e-12,
            "f'({x})"
        );
    }
}

/// Polynomials are held exactly (their trailing coefficients chopped); sums, products and
/// the values ↔ coefficients round trip.
#[test]
fn polynomials_sums_and_products_are_exact() {
    let cubic = Chebyshev::fit(|x| x * x * x - 2.0 * x, -1.0, 1.0).unwrap();
    // x³ − 2x = ¼T₃ + ¾T₁ − 2T₁.
    assert_eq!(cubic.len(), 4);
    let c = cubic.coefficients();
    assert!((c[1] + 1.25).abs() < 1e-15 && (c[3] - 0.25).abs() < 1e-15 && c[0].abs() < 1e-15);
    let sine = Chebyshev::fit(f64::sin, 0.0, 2.0).unwrap();
    let cosine = Chebyshev::fit(f64::cos, 0.0, 2.0).unwrap();
    let product = sine.mul(&cosine).unwrap();
    let sum = sine.add(&cosine).unwrap();
    for x in grid(0.0, 2.0, 200) {
        assert!((product.evaluate(x).unwrap() - 0.5 * (2.0 * x).sin()).abs() < 1e-15 * 4.0);
        assert!((sum.evaluate(x).unwrap() - (x.sin() + x.cos())).abs() < 1e-15 * 4.0);
    }
    let again = Chebyshev::from_values(&sine.values(), 0.0, 2.0).unwrap();
    let difference = again
        .coefficients()
        .iter()
        .zip(sine.coefficients())
        .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
    assert!(difference < 1e-15 * 4.0, "round trip {difference:e}");
}

#[test]
fn what_a_series_cannot_say_is_refused() {
    let f = Chebyshev::fit(|x| (5.0 * x).sin() / (1.0 + x * x), -2.0, 3.0).unwrap();
    // Outside its interval a fit says nothing (an interpolant there is ~1e11 at x = 10).
    assert!(matches!(
        f.evaluate(10.0),
        Err(SpectralError::OutsideInterval { .. })
    ));
    assert!(matches!(
        f.evaluate(-2.000001),
        Err(SpectralError::OutsideInterval { .. })
    ));
    // The ends themselves, and a rounding error beyond them, are in.
    assert!(f.evaluate(3.0).is_ok() && f.evaluate(3.0 + 2.0 * f64::EPSILON).is_ok());
    assert!(matches!(
        f.evaluate(f64::NAN),
        Err(SpectralError::NonFinitePoint { .. })
    ));
    // |x| has coefficients decaying like k⁻²: not resolved to ε by 4097 points.
    assert!(matches!(
        Chebyshev::fit(f64::abs, -1.0, 2.0),
        Err(SpectralError::NotResolved { .. })
    ));
    assert!(matches!(
        Chebyshev::fit(|x| 1.0 / x, -1.0, 1.0),
        Err(SpectralError::NonFiniteValue { .. })
    ));
    assert!(matches!(
        Chebyshev::fit_with_tolerance(f64::sin, 0.0, 1.0, 1e-20),
        Err(SpectralError::InvalidTolerance { .. })
    ));
    assert!(matches!(
        Chebyshev::fit(f64::sin, 1.0, 0.0),
        Err(SpectralError::EmptyInterval { .. })
    ));
    let other = Chebyshev::fit(f64::sin, 0.0, 1.0).unwrap();
    assert!(matches!(
        f.add(&other),
        Err(SpectralError::IntervalMismatch { .. })
    ));
}

/// The fast transform (DCT-I by FFT from `FFT_FROM` values on) against exact laws and the
/// direct cosine sums: `T_k` sampled at the nodes has the coefficients `δ_k`; values →
/// coefficients → values returns the values; and on random values the FFT and the
/// `O(n²)` matrix agree. Tolerances: either transform sums `n` terms of size at most
/// `2 max|f| / (n − 1)`, so its rounding is at most about `2nε max|f|` (worst case;
/// typically `√n ε`): 1e-12 covers `n = 4097`, a wrong transform is off by O(1).
#[test]
fn the_fast_transform_is_the_cosine_transform() {
    use lgsvi_spectral::{
        chebyshev_coefficient_matrix, chebyshev_coefficients, chebyshev_lobatto, chebyshev_values,
        FFT_FROM,
    };
    assert_eq!(FFT_FROM, 65);
    for n in [64usize, 65, 66, 129, 1000, 1025, 4097] {
        let t = chebyshev_lobatto(n, -1.0, 1.0).unwrap();
        for k in [0, 1, 7, n / 2, n - 2, n - 1] {
            // T_k(t) = cos(k arccos t), exact at the nodes up to rounding.
            let values: Vec<f64> = t.iter().map(|&t| (k as f64 * t.acos()).cos()).collect();
            let c = chebyshev_coefficients(&values).unwrap();
            for (j, &cj) in c.iter().enumerate() {
                let expect = if j == k { 1.0 } else { 0.0 };
                assert!((cj - expect).abs() < 1e-12, "n {n} k {k} j {j}: {cj}");
            }
        }
        // A pseudo-random vector (a fixed linear congruential sequence).
        let mut state = 12345u64;
        let values: Vec<f64> = (0..n)
            .map(|_| {
                state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
                (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .collect();
        let fast = chebyshev_coefficients(&values).unwrap();
        let direct = chebyshev_coefficient_matrix(n)
            .unwrap()
            .mul_vec(&values)
            .unwrap();
        let worst = fast
            .iter()
            .zip(&direct)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f64, f64::max);
        assert!(
            worst < 1e-12,
            "n {n}: FFT and cosine sums differ by {worst:e}"
        );
        let back = chebyshev_values(&fast).unwrap();
        let worst = values
            .iter()
            .zip(&back)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f64, f64::max);
        assert!(worst < 1e-12, "n {n}: round trip off by {worst:e}");
    }
}

/// A function that needs the FFT's sizes: sin(40x)·e^x on [−1, 2] (about 150 coefficients)
/// within 5e-13 of the function: its slope reaches 40e² ≈ 300, so the rounding of x alone
/// (an ulp of 2 is 4.4e-16) moves f by 1.3e-13, in the fit's samples as in the check's
/// values; `values()` agrees with `evaluate` at the nodes.
#[test]
fn a_fast_oscillation_is_fitted_through_the_fft() {
    let f = |x: f64| (40.0 * x).sin() * x.exp();
    let fit = Chebyshev::fit(f, -1.0, 2.0).unwrap();
    assert!(fit.len() > 100, "{} coefficients", fit.len());
    let worst = grid(-1.0, 2.0, 3000)
        .map(|x| (fit.evaluate(x).unwrap() - f(x)).abs())
        .fold(0.0f64, f64::max);
    assert!(worst < 5e-13, "worst error {worst:e}");
    let nodes = lgsvi_spectral::chebyshev_lobatto(fit.len(), -1.0, 2.0).unwrap();
    for (x, v) in nodes.iter().zip(fit.values()) {
        assert!((fit.evaluate(*x).unwrap() - v).abs() < 1e-13);
    }
}

/// Composition and range against closed forms: e^{cos x} on [−1, 2]; (x²)∘ of sin(3y);
/// the range of sin on [0, 3] is [0, 1] (its maximum at π/2); a composition whose inner
/// range leaves the outer interval is refused.
#[test]
fn compositions_and_ranges_match_closed_forms() {
    let cos = Chebyshev::fit(f64::cos, -1.0, 2.0).unwrap();
    let h = cos.compose(f64::exp).unwrap();
    let worst = grid(-1.0, 2.0, 1000)
        .map(|x| (h.evaluate(x).unwrap() - x.cos().exp()).abs())
        .fold(0.0f64, f64::max);
    assert!(worst < 1e-14, "e^cos: {worst:e}");
    let (low, high) = Chebyshev::fit(f64::sin, 0.0, 3.0).unwrap().range();
    assert!(
        low.abs() < 1e-15 && (high - 1.0).abs() < 1e-15,
        "{low} {high}"
    );
    let square = Chebyshev::fit(|x| x * x, -1.0, 1.0).unwrap();
    let outer = Chebyshev::fit(|y| (3.0 * y).sin(), 0.0, 1.0).unwrap();
    let h = square.compose_with(&outer).unwrap();
    let worst = grid(-1.0, 1.0, 1000)
        .map(|x| (h.evaluate(x).unwrap() - (3.0 * x * x).sin()).abs())
        .fold(0.0f64, f64::max);
    assert!(worst < 1e-14, "sin(3x²): {worst:e}");
    let narrow = Chebyshev::fit(|y| y, 0.0, 0.5).unwrap();
    assert!(matches!(
        square.compose_with(&narrow),
        Err(SpectralError::OutsideInterval { .. })
    ));
}

/// Every root `roots` returns is a zero of the series: sin(5x)/(1 + x²) on [−2, 3] has eight
/// (kπ/5 in the interval); a spurious real eigenvalue of the colleague matrix at the end
/// x = 3 (where f = 0.065), which Newton clamps there, is not one of them.
#[test]
fn roots_are_zeros_of_the_series() {
    let f = |x: f64| (5.0 * x).sin() / (1.0 + x * x);
    let roots = Chebyshev::fit(f, -2.0, 3.0).unwrap().roots();
    assert_eq!(roots.len(), 8, "{roots:?}");
    for (k, r) in roots.iter().enumerate() {
        let exact = (k as f64 - 3.0) * PI / 5.0;
        assert!((r - exact).abs() < 1e-14, "root {k}: {r} vs {exact}");
    }
}
