//! What the slew tests share: the exact optimum of the discrete single-axis problem.

use nalgebra::{Matrix2, Vector2};

/// The exact optimum of the discrete problem for a spherical body `J = jI` turning by `θ`
/// about a fixed axis, rest to rest in `K` steps of `h`, the torque `u_k` held over step
/// `k`: `φ_K = Σ_k (h²/2 + (K−1−k) h²) u_k / j`, `ω_K = Σ_k h u_k / j`; the least `Σ h u_k²`
/// meeting `(φ_K, ω_K) = (θ, 0)` is `h |u*|²` with `u* = Gᵀ (G Gᵀ)⁻¹ (θ, 0)`.
pub fn discrete_optimum(j: f64, theta: f64, t_end: f64, k: usize) -> f64 {
    let h = t_end / k as f64;
    let rows: Vec<(f64, f64)> = (0..k)
        .map(|i| ((0.5 + (k - 1 - i) as f64) * h * h / j, h / j))
        .collect();
    let mut ggt = Matrix2::zeros();
    for &(a, b) in &rows {
        ggt += Matrix2::new(a * a, a * b, a * b, b * b);
    }
    let y = ggt.try_inverse().unwrap() * Vector2::new(theta, 0.0);
    h * rows
        .iter()
        .map(|&(a, b)| (a * y.x + b * y.y).powi(2))
        .sum::<f64>()
}
