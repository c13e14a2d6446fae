//! The Gauss rule and the Chebyshev–Lobatto basis together, as a Galerkin step uses them on
//! `[0, h]`: laws of the evaluation matrix `B[j][i] = φ_i(c_j)` and derivative matrix
//! `D[j][i] = φ_i'(c_j)` integrated with the weights `b_j`.

use lgsvi_quadrature::{gauss_legendre, gauss_lobatto};
use lgsvi_spectral::Barycentric;

const EPS: f64 = f64::EPSILON;

/// `∫_0^h φ_i'(t) dt = φ_i(h) − φ_i(0) = δ_{i,n−1} − δ_{i,0}` (fundamental theorem of
/// calculus; exact for any m with 2m − 1 ≥ n − 2), and `Σ_i ∫ φ_i = h` (partition of unity).
/// Entries of D are ≤ 2n²/h, so sums of m of them carry ~ m·n²·ε/h·h = m n² ε.
#[test]
fn integrals_of_basis_functions_and_derivatives() {
    for h in [0.1, 0.5, 1.5] {
        for n in [2usize, 3, 5, 8, 12, 20] {
            let m = n.div_ceil(2).max(1);
            let rule = gauss_legendre(m).unwrap().on(0.0, h).unwrap();
            let basis = Barycentric::chebyshev_lobatto(n, 0.0, h).unwrap();
            let (b, d) = basis
                .evaluation_and_derivative_matrices(rule.nodes())
                .unwrap();
            for i in 0..n {
                let integral: f64 = (0..m).map(|j| rule.weights()[j] * d[(j, i)]).sum();
                let expected = if i == n - 1 {
                    1.0
                } else if i == 0 {
                    -1.0
                } else {
                    0.0
                };
                assert!(
                    (integral - expected).abs() <= 8.0 * (m * n * n) as f64 * EPS,
                    "h {h} n {n} i {i}: {integral}"
                );
            }
            let total: f64 = (0..m)
                .map(|j| rule.weights()[j] * b.row(j).iter().sum::<f64>())
                .sum();
            assert!((total - h).abs() <= 4.0 * (m + n) as f64 * EPS * h);
        }
    }
}

/// The mass matrix `M_ik = ∫ φ_i φ_k` (degree 2n − 2) computed with two different exact
/// rules — n Gauss points and n + 1 Lobatto points — agrees to rounding, and is symmetric
/// positive: `Σ_ik M_ik = h`.
#[test]
fn mass_matrix_is_rule_independent_once_exact() {
    let h = 0.5;
    for n in [2usize, 4, 7, 12] {
        let basis = Barycentric::chebyshev_lobatto(n, 0.0, h).unwrap();
        let mass = |nodes: &[f64], weights: &[f64]| -> Vec<f64> {
            let b = basis.evaluation_matrix(nodes).unwrap();
            let mut m = vec![0.0; n * n];
            for (j, w) in weights.iter().enumerate() {
                for i in 0..n {
                    for k in 0..n {
                        m[i * n + k] += w * b[(j, i)] * b[(j, k)];
                    }
                }
            }
            m
        };
        let g = gauss_legendre(n).unwrap().on(0.0, h).unwrap();
        let l = gauss_lobatto(n + 1).unwrap().on(0.0, h).unwrap();
        let (mg, ml) = (mass(g.nodes(), g.weights()), mass(l.nodes(), l.weights()));
        // |φ_i| ≤ Λ_n ≤ 3 for these n: each entry sums ≤ n + 1 terms of size ≤ 9·h/n.
        for (a, c) in mg.iter().zip(&ml) {
            assert!((a - c).abs() <= 64.0 * (n + 1) as f64 * EPS * h, "n {n}");
        }
        assert!((mg.iter().sum::<f64>() - h).abs() <= 16.0 * (n * n) as f64 * EPS * h);
    }
}
