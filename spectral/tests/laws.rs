//! Laws and closed forms for nodes and barycentric bases. References come from outside the
//! code under test: Chebyshev series evaluated by Clenshaw's recurrence, Trefethen's
//! closed-form differentiation matrix, the Runge function's known convergence rate.

use lgsvi_spectral::{chebyshev_first_kind, chebyshev_lobatto, Barycentric, SpectralError};
use proptest::prelude::*;
use std::f64::consts::PI;

const EPS: f64 = f64::EPSILON;

/// A Chebyshev series `Σ c_k T_k(t)` on `[a, b]` (`t` the reference variable), value and
/// derivative by Clenshaw's recurrence for `T_k` and for `T_k' = k U_{k−1}`.
struct ChebSeries {
    c: Vec<f64>,
    a: f64,
    b: f64,
}

impl ChebSeries {
    fn t(&self, x: f64) -> f64 {
        (2.0 * x - self.a - self.b) / (self.b - self.a)
    }
    fn value(&self, x: f64) -> f64 {
        let t = self.t(x);
        let (mut b1, mut b2) = (0.0, 0.0);
        for &ck in self.c.iter().skip(1).rev() {
            (b1, b2) = (2.0 * t * b1 - b2 + ck, b1);
        }
        t * b1 - b2 + self.c[0]
    }
    fn derivative(&self, x: f64) -> f64 {
        // d/dt Σ c_k T_k = Σ k c_k U_{k−1}(t), U by Clenshaw; times dt/dx = 2/(b − a).
        let t = self.t(x);
        let (mut b1, mut b2) = (0.0, 0.0);
        for k in (1..self.c.len()).rev() {
            (b1, b2) = (2.0 * t * b1 - b2 + k as f64 * self.c[k], b1);
        }
        b1 * 2.0 / (self.b - self.a)
    }
    /// Σ|c_k| bounds |p| on the interval; Σ k²|c_k| bounds |dp/dt| (Markov).
    fn bounds(&self) -> (f64, f64) {
        let v = self.c.iter().map(|c| c.abs()).sum();
        let d = self
            .c
            .iter()
            .enumerate()
            .map(|(k, c)| (k * k) as f64 * c.abs())
            .sum::<f64>()
            * 2.0
            / (self.b - self.a);
        (v, d)
    }
}

/// Deterministic pseudo-random coefficients in [−1, 1] (xorshift), so the test is seeded.
fn coefficients(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        })
        .collect()
}

fn sample_points(a: f64, b: f64, nodes: &[f64]) -> Vec<f64> {
    let mut pts: Vec<f64> = (0..=200).map(|k| a + (b - a) * k as f64 / 200.0).collect();
    for &x in nodes {
        pts.extend([x, x.next_up(), x.next_down()]);
    }
    pts
}

#[test]
fn reproduces_every_polynomial_of_degree_below_n() {
    // Bounds: the second barycentric form is forward stable on Chebyshev-like nodes with
    // error ≤ (3n + 4) ε Λ_n Σ|c_k| (Higham 2004), Λ_n ≤ 1 + (2/π) ln n < 4 here; for the
    // derivative each φ_i' carries n relative roundings and |φ_i'| ≤ ‖D‖_∞ ~ n², so we
    // allow 8 n ε times the Markov bound Σ k²|c_k| · 2/(b − a).
    for &(a, b) in &[(-1.0, 1.0), (0.0, 0.5), (3.0, 10.0)] {
        for &n in &[2usize, 3, 4, 5, 8, 13, 17, 32, 64] {
            let bases = [
                Barycentric::chebyshev_lobatto(n, a, b).unwrap(),
                Barycentric::chebyshev_first_kind(n, a, b).unwrap(),
                Barycentric::new(chebyshev_first_kind(n, a, b).unwrap()).unwrap(),
            ];
            for (family, basis) in bases.iter().enumerate() {
                let p = ChebSeries {
                    c: coefficients(n, (n * 31 + family) as u64),
                    a,
                    b,
                };
                let (vbound, dbound) = p.bounds();
                let values: Vec<f64> = basis.nodes().iter().map(|&x| p.value(x)).collect();
                let (mut phi, mut dphi) = (vec![0.0; n], vec![0.0; n]);
                for x in sample_points(a, b, basis.nodes()) {
                    let v = basis.interpolate(&values, x).unwrap();
                    let tol_v = (3 * n + 4) as f64 * 4.0 * EPS * vbound;
                    assert!((v - p.value(x)).abs() <= tol_v, "value n {n} x {x}");
                    basis
                        .basis_and_derivatives_into(x, &mut phi, &mut dphi)
                        .unwrap();
                    let d: f64 = dphi.iter().zip(&values).map(|(d, f)| d * f).sum();
                    let tol_d = 8.0 * n as f64 * EPS * dbound.max(1.0) + tol_v;
                    assert!(
                        (d - p.derivative(x)).abs() <= tol_d,
                        "derivative n {n} family {family} x {x}: {} vs {}",
                        d,
                        p.derivative(x)
                    );
                }
            }
        }
    }
}

fn runge(x: f64) -> f64 {
    1.0 / (1.0 + 25.0 * x * x)
}

/// Max interpolation error of Runge's function on a grid of 4001 points plus the midpoints
/// of the nodes (where the error peaks).
fn runge_error(n: usize) -> f64 {
    let basis = Barycentric::chebyshev_lobatto(n, -1.0, 1.0).unwrap();
    let values: Vec<f64> = basis.nodes().iter().map(|&x| runge(x)).collect();
    let mut pts: Vec<f64> = (0..=4000).map(|k| -1.0 + k as f64 / 2000.0).collect();
    pts.extend(basis.nodes().windows(2).map(|w| 0.5 * (w[0] + w[1])));
    pts.iter()
        .map(|&x| (basis.interpolate(&values, x).unwrap() - runge(x)).abs())
        .fold(0.0, f64::max)
}

#[test]
fn runge_function_converges_geometrically_at_the_predicted_rate() {
    // The poles ±i/5 lie on the Bernstein ellipse of parameter ρ = 0.2 + √1.04, so the
    // error behaves like C ρ^{−n}. Fit ln(error) against n by least squares over n =
    // 20..=120 (well above rounding) and compare the slope with −ln ρ. The prefactor
    // varies slowly with n (and with the parity of n), so allow 3% on the rate.
    let rho = 0.2 + 1.04f64.sqrt();
    let ns: Vec<f64> = (20..=120).step_by(4).map(|n| n as f64).collect();
    let logs: Vec<f64> = ns.iter().map(|&n| runge_error(n as usize).ln()).collect();
    let k = ns.len() as f64;
    let (mx, my) = (ns.iter().sum::<f64>() / k, logs.iter().sum::<f64>() / k);
    let slope = ns
        .iter()
        .zip(&logs)
        .map(|(x, y)| (x - mx) * (y - my))
        .sum::<f64>()
        / ns.iter().map(|x| (x - mx).powi(2)).sum::<f64>();
    let measured = (-slope).exp();
    println!("Runge: fitted factor per node {measured:.5}, predicted ρ = {rho:.5}");
    assert!(
        ((-slope) / rho.ln() - 1.0).abs() < 0.03,
        "fitted {measured}, predicted {rho}"
    );
}

#[test]
fn runge_function_reaches_rounding_and_stays_there() {
    // ρ^{−200} ≈ 6e−18: at n = 200 only rounding is left, ≤ (3n+4) ε Λ_n max|f| ≈ 1e−13 as
    // a bound, 1e−14 demanded by the issue (measured values printed with --nocapture).
    for n in [50, 100, 200, 2000] {
        let err = runge_error(n);
        println!("Runge n = {n:>4}: max error {err:.3e}");
        if n >= 200 {
            assert!(err <= 1e-14, "n = {n}: {err:e}");
        }
    }
}

#[test]
fn derivatives_of_a_smooth_function_converge_geometrically() {
    // f = e^x sin 5x is entire: the error of the interpolant's derivative falls faster
    // than any geometric rate until it meets rounding, ~ n² ε max|f| (‖D‖ ~ n²).
    let f = |x: f64| x.exp() * (5.0 * x).sin();
    let df = |x: f64| x.exp() * ((5.0 * x).sin() + 5.0 * (5.0 * x).cos());
    let mut previous = f64::INFINITY;
    for n in [8, 12, 16, 20, 24, 28, 32] {
        let basis = Barycentric::chebyshev_lobatto(n, -1.0, 1.0).unwrap();
        let values: Vec<f64> = basis.nodes().iter().map(|&x| f(x)).collect();
        let err = (0..=500)
            .map(|k| -1.0 + k as f64 / 250.0)
            .map(|x| (basis.interpolate_derivative(&values, x).unwrap() - df(x)).abs())
            .fold(0.0, f64::max);
        println!("e^x sin 5x, n = {n}: max derivative error {err:.3e}");
        if n <= 24 {
            assert!(err < previous / 10.0, "n = {n}: {err:e} after {previous:e}");
        }
        previous = err;
    }
    assert!(previous < 1e-11, "{previous:e}");
}

#[test]
fn exact_at_nodes_and_accurate_one_ulp_away() {
    for n in [2usize, 3, 5, 9, 16, 33] {
        let basis = Barycentric::chebyshev_lobatto(n, 0.0, 0.7).unwrap();
        let dmat = basis.differentiation_matrix();
        let (mut phi, mut dphi) = (vec![0.0; n], vec![0.0; n]);
        for p in 0..n {
            let xp = basis.nodes()[p];
            basis
                .basis_and_derivatives_into(xp, &mut phi, &mut dphi)
                .unwrap();
            for i in 0..n {
                assert_eq!(phi[i], if i == p { 1.0 } else { 0.0 });
                assert_eq!(dphi[i], dmat[(p, i)]);
            }
            // One ulp away the basis moves by |φ_i'| · ulp and the derivative by |φ_i''| ·
            // ulp ≤ n⁴ ulp/(b−a)²; rounding adds n ε |D|. 64 n² ε |D|_max covers both.
            let dmax = dmat.as_slice().iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for x in [xp.next_up(), xp.next_down()] {
                basis
                    .basis_and_derivatives_into(x, &mut phi, &mut dphi)
                    .unwrap();
                assert!(phi.iter().chain(&dphi).all(|v| v.is_finite()));
                for i in 0..n {
                    let delta = if i == p { 1.0 } else { 0.0 };
                    assert!((phi[i] - delta).abs() <= 4.0 * dmax * EPS);
                    assert!(
                        (dphi[i] - dmat[(p, i)]).abs() <= 64.0 * (n * n) as f64 * EPS * dmax,
                        "n {n} p {p} i {i}: {} vs {}",
                        dphi[i],
                        dmat[(p, i)]
                    );
                }
            }
        }
    }
}

#[test]
fn middle_gauss_point_on_the_middle_lobatto_node() {
    // With n and the number of Gauss points m both odd, the middle Gauss point on [0, h]
    // is h/2, which is also the middle Chebyshev–Lobatto node: a naive barycentric
    // formula divides 0 by 0 there.
    for n in [3usize, 5, 7, 9] {
        let h = 0.5;
        let basis = Barycentric::chebyshev_lobatto(n, 0.0, h).unwrap();
        let mid = n / 2;
        assert_eq!(basis.nodes()[mid], h / 2.0);
        let (b, d) = basis
            .evaluation_and_derivative_matrices(&[h / 2.0])
            .unwrap();
        let dmat = basis.differentiation_matrix();
        for i in 0..n {
            assert_eq!(b[(0, i)], if i == mid { 1.0 } else { 0.0 });
            assert_eq!(d[(0, i)], dmat[(mid, i)]);
        }
    }
}

#[test]
fn differentiation_matrix_matches_trefethens_closed_form() {
    // cheb.m (Trefethen, Spectral Methods in MATLAB): x_j = cos(jπ/N), D_00 = (2N²+1)/6,
    // D_jj = −x_j/(2(1 − x_j²)), D_ij = (c_i/c_j)(−1)^{i+j}/(x_i − x_j), c = 2 at the ends.
    // Our nodes ascend, so index j here is N − j there. Entries are O(N²); the closed-form
    // diagonal itself loses digits (x_j² near 1), so compare to 4 N² ε max|D| rather than ε.
    for n in [2usize, 3, 4, 8, 16, 32] {
        let big_n = n - 1;
        let x: Vec<f64> = (0..n)
            .map(|j| (j as f64 * PI / big_n as f64).cos())
            .collect();
        let c = |j: usize| if j == 0 || j == big_n { 2.0 } else { 1.0 };
        let closed = |i: usize, j: usize| -> f64 {
            if i != j {
                let sign = if (i + j).is_multiple_of(2) { 1.0 } else { -1.0 };
                c(i) / c(j) * sign / (x[i] - x[j])
            } else if i == 0 {
                (2.0 * (big_n * big_n) as f64 + 1.0) / 6.0
            } else if i == big_n {
                -(2.0 * (big_n * big_n) as f64 + 1.0) / 6.0
            } else {
                -x[i] / (2.0 * (1.0 - x[i] * x[i]))
            }
        };
        let d = Barycentric::chebyshev_lobatto(n, -1.0, 1.0)
            .unwrap()
            .differentiation_matrix();
        let scale = (2.0 * (big_n * big_n) as f64 + 1.0) / 6.0;
        for j in 0..n {
            for i in 0..n {
                let expected = closed(big_n - j, big_n - i);
                assert!(
                    (d[(j, i)] - expected).abs() <= 4.0 * (n * n) as f64 * EPS * scale,
                    "n {n} ({j},{i}): {} vs {expected}",
                    d[(j, i)]
                );
            }
        }
    }
}

#[test]
fn general_weights_agree_with_the_closed_forms() {
    for n in [2usize, 3, 7, 30, 200] {
        for (closed, nodes) in [
            (
                Barycentric::chebyshev_lobatto(n, -2.0, 3.0).unwrap(),
                chebyshev_lobatto(n, -2.0, 3.0).unwrap(),
            ),
            (
                Barycentric::chebyshev_first_kind(n, -2.0, 3.0).unwrap(),
                chebyshev_first_kind(n, -2.0, 3.0).unwrap(),
            ),
        ] {
            let general = Barycentric::new(nodes).unwrap();
            // Weights are defined up to a common factor; compare after normalising by the
            // first. Each general weight sums n logarithms: relative error ~ n ε · ln-scale.
            let r = general.weights()[0] / closed.weights()[0];
            for (g, c) in general.weights().iter().zip(closed.weights()) {
                assert!(
                    (g / r - c).abs() <= 64.0 * n as f64 * EPS * c.abs(),
                    "n {n}"
                );
            }
        }
    }
}

#[test]
fn nodes_are_ascending_symmetric_and_hit_the_ends() {
    for n in 2..=64 {
        let x = chebyshev_lobatto(n, -1.0, 1.0).unwrap();
        assert_eq!((x[0], x[n - 1]), (-1.0, 1.0));
        assert!(x.windows(2).all(|w| w[0] < w[1]));
        for j in 0..n {
            assert_eq!(x[j], -x[n - 1 - j]);
            // Against the textbook formula −cos(πj/(n−1)), within an ulp or two.
            assert!((x[j] + (PI * j as f64 / (n - 1) as f64).cos()).abs() <= 2.0 * EPS);
        }
        let h = chebyshev_lobatto(n, 0.0, 0.5).unwrap();
        assert_eq!((h[0], h[n - 1]), (0.0, 0.5));
        let f = chebyshev_first_kind(n, -1.0, 1.0).unwrap();
        assert!(f.windows(2).all(|w| w[0] < w[1]));
        for (j, fj) in f.iter().enumerate() {
            assert!((fj + (PI * (2 * j + 1) as f64 / (2 * n) as f64).cos()).abs() <= 2.0 * EPS);
        }
    }
}

#[test]
fn bad_input_is_a_typed_error() {
    use SpectralError::*;
    assert!(matches!(
        chebyshev_lobatto(1, 0.0, 1.0),
        Err(TooFewNodes { n: 1, min: 2, .. })
    ));
    assert!(matches!(
        chebyshev_first_kind(0, 0.0, 1.0),
        Err(TooFewNodes { .. })
    ));
    assert!(matches!(
        chebyshev_lobatto(4, 1.0, 1.0),
        Err(EmptyInterval { .. })
    ));
    assert!(matches!(
        chebyshev_lobatto(4, 0.0, f64::NAN),
        Err(NonFiniteInterval { .. })
    ));
    assert!(matches!(Barycentric::new(vec![]), Err(TooFewNodes { .. })));
    assert!(matches!(
        Barycentric::new(vec![0.0, f64::INFINITY]),
        Err(NonFiniteNode { index: 1, .. })
    ));
    assert!(matches!(
        Barycentric::new(vec![0.0, 2.0, 1.0, 2.0]),
        Err(DuplicateNode {
            first: 1,
            second: 3,
            ..
        })
    ));
    // 1200 equispaced nodes: weights span 2^1200, beyond double precision.
    let equi: Vec<f64> = (0..1200).map(|k| k as f64 / 1199.0).collect();
    assert!(matches!(
        Barycentric::new(equi),
        Err(WeightUnderflow { .. })
    ));
    let basis = Barycentric::chebyshev_lobatto(4, 0.0, 1.0).unwrap();
    assert!(matches!(
        basis.interpolate(&[1.0, 2.0], 0.5),
        Err(LengthMismatch {
            expected: 4,
            got: 2,
            ..
        })
    ));
    assert!(matches!(
        basis.interpolate(&[0.0; 4], f64::NAN),
        Err(NonFinitePoint { .. })
    ));
    let mut short = [0.0; 3];
    let mut ok = [0.0; 4];
    assert!(basis
        .basis_and_derivatives_into(0.5, &mut ok, &mut short)
        .is_err());
    assert!(basis.evaluation_matrix(&[0.1, f64::INFINITY]).is_err());
    let msg = Barycentric::new(vec![1.0, 1.0]).unwrap_err().to_string();
    assert!(msg.contains("distinct"), "{msg}");
}

#[test]
fn matrices_agree_with_pointwise_evaluation() {
    let basis = Barycentric::chebyshev_lobatto(9, 0.0, 0.5).unwrap();
    let pts = [0.0, 0.01, 0.25, 0.3, 0.5];
    let (b, d) = basis.evaluation_and_derivative_matrices(&pts).unwrap();
    assert_eq!(b, basis.evaluation_matrix(&pts).unwrap());
    let (mut phi, mut dphi) = ([0.0; 9], [0.0; 9]);
    for (j, &x) in pts.iter().enumerate() {
        basis
            .basis_and_derivatives_into(x, &mut phi, &mut dphi)
            .unwrap();
        assert_eq!(b.row(j), &phi);
        assert_eq!(d.row(j), &dphi);
    }
    let f: Vec<f64> = basis.nodes().iter().map(|x| x * x).collect();
    let df = d.mul_vec(&f).unwrap();
    for (j, &x) in pts.iter().enumerate() {
        assert!((df[j] - 2.0 * x).abs() < 1e-13);
    }
    assert!(matches!(
        d.mul_vec(&[1.0]),
        Err(lgsvi_spectral::SpectralError::LengthMismatch { got: 1, .. })
    ));
}

proptest! {
    /// Arbitrary distinct nodes (sorted, spacing ≥ 1e-2) reproduce a random polynomial of
    /// degree n − 1 at points inside their hull (outside, the error of extrapolation grows
    /// like (distance/spread)^n and no fixed bound applies). Such nodes can have Lebesgue
    /// constants in the thousands, hence the looser 1e-9 relative bound.
    #[test]
    fn arbitrary_nodes_reproduce_polynomials(
        gaps in proptest::collection::vec(0.01f64..0.3, 1..8),
        coeffs in proptest::collection::vec(-1.0f64..1.0, 8),
        fraction in 0.0f64..1.0,
    ) {
        let mut nodes = vec![-1.0];
        for g in &gaps { nodes.push(nodes.last().unwrap() + g); }
        let n = nodes.len();
        let x = nodes[0] + fraction * (nodes[n - 1] - nodes[0]);
        let c = &coeffs[..n];
        let poly = |x: f64| c.iter().rev().fold(0.0, |acc, ci| acc * x + ci);
        let dpoly = |x: f64| c.iter().enumerate().skip(1).rev()
            .fold(0.0, |acc, (k, ci)| acc * x + k as f64 * ci);
        let basis = Barycentric::new(nodes.clone()).unwrap();
        let values: Vec<f64> = nodes.iter().map(|&t| poly(t)).collect();
        let scale = 1.0 + nodes.last().unwrap().abs().powi(n as i32);
        prop_assert!((basis.interpolate(&values, x).unwrap() - poly(x)).abs() <= 1e-9 * scale);
        prop_assert!(
            (basis.interpolate_derivative(&values, x).unwrap() - dpoly(x)).abs()
                <= 1e-7 * scale * n as f64
        );
    }
}

/// The coefficient transform inverts Clenshaw's summation: a series of degree `n − 1`
/// sampled at the `n` Lobatto nodes (by Clenshaw, not by the code under test) gives its
/// coefficients back. Each coefficient is a sum of `n` terms of size ≤ `2 max|f| / N`,
/// and `max|f| ≤ Σ|c_k|`, so the error is ≤ ~`4 n ε Σ|c_k|`.
#[test]
fn coefficients_of_a_sampled_series_are_its_coefficients() {
    for n in [2usize, 3, 4, 7, 12, 25, 64] {
        for seed in 0..3 {
            let c = coefficients(n, seed);
            let series = ChebSeries {
                c: c.clone(),
                a: -0.3,
                b: 2.1,
            };
            let nodes = chebyshev_lobatto(n, -0.3, 2.1).unwrap();
            let f: Vec<f64> = nodes.iter().map(|&x| series.value(x)).collect();
            let back = lgsvi_spectral::chebyshev_coefficients(&f).unwrap();
            let size: f64 = c.iter().map(|c| c.abs()).sum();
            for (k, (got, want)) in back.iter().zip(&c).enumerate() {
                assert!(
                    (got - want).abs() <= 4.0 * n as f64 * EPS * size,
                    "n {n} k {k}: {got} vs {want}"
                );
            }
        }
    }
}

/// Aliasing on the Lobatto grid of `N + 1` points: `T_{2N−k}(t_j) = T_k(t_j)`, so the
/// samples of `T_{2N−k}` (`0 < k < N`) have the single coefficient `c_k = 1`.
#[test]
fn lobatto_samples_alias_t_2n_minus_k_onto_t_k() {
    for n in [3usize, 6, 11] {
        let big_n = n - 1;
        let nodes = chebyshev_lobatto(n, -1.0, 1.0).unwrap();
        for k in 1..big_n {
            let degree = 2 * big_n - k;
            let f: Vec<f64> = nodes
                .iter()
                .map(|&t| (degree as f64 * t.clamp(-1.0, 1.0).acos()).cos())
                .collect();
            let c = lgsvi_spectral::chebyshev_coefficients(&f).unwrap();
            for (i, ci) in c.iter().enumerate() {
                let want = if i == k { 1.0 } else { 0.0 };
                assert!(
                    (ci - want).abs() <= 8.0 * n as f64 * EPS,
                    "n {n} k {k} i {i}: {ci}"
                );
            }
        }
    }
}

#[test]
fn coefficients_need_two_values() {
    assert!(matches!(
        lgsvi_spectral::chebyshev_coefficients(&[1.0]),
        Err(SpectralError::TooFewNodes { n: 1, min: 2, .. })
    ));
    assert!(lgsvi_spectral::chebyshev_coefficient_matrix(0).is_err());
}
