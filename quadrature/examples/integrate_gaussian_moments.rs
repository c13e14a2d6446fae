//! Expectations under the normal, gamma and beta distributions by the classical Gauss rules,
//! against their closed forms.
//!
//! `E[g(X)]` for `X ~ N(μ, σ²)` is `∫ e^{−t²} g(μ + √2 σ t) dt / √π`: a Gauss–Hermite rule
//! with the nodes shifted and scaled. For `X ~ Gamma(k, 1)`, `E[g(X)] = ∫ x^{k−1} e^{−x} g(x) dx
//! / Γ(k)`: Gauss–Laguerre with `α = k − 1`. For `X ~ Beta(a, b)` on `[0, 1]`, Gauss–Jacobi
//! mapped to `[0, 1]` with `α = b − 1`, `β = a − 1`. Each rule of `m` points is exact for
//! polynomial `g` of degree `2m − 1`, and converges geometrically for smooth `g`.
//!
//! Run: `cargo run --release -p lgsvi-quadrature --example integrate_gaussian_moments`

use lgsvi_quadrature::{gauss_hermite, gauss_jacobi, gauss_laguerre, QuadratureError};
use std::f64::consts::PI;

fn main() -> Result<(), QuadratureError> {
    // The normal distribution: moments and E[cos X] = cos(μ) e^{−σ²/2}.
    let (mu, sigma) = (0.3, 1.7);
    let hermite = gauss_hermite(20)?;
    let normal =
        |g: &dyn Fn(f64) -> f64| hermite.integrate(|t| g(mu + 2f64.sqrt() * sigma * t)) / PI.sqrt();
    let fourth = normal(&|x| (x - mu).powi(4));
    let cosine = normal(&|x| x.cos());
    println!("N({mu}, {sigma}²), 20 Hermite points:");
    println!(
        "  E[(X − μ)⁴] = {fourth:.16}  (3σ⁴ = {:.16})",
        3.0 * sigma.powi(4)
    );
    println!(
        "  E[cos X]    = {cosine:.16}  (cos μ e^(−σ²/2) = {:.16})",
        mu.cos() * (-sigma * sigma / 2.0).exp()
    );
    assert!((fourth - 3.0 * sigma.powi(4)).abs() < 1e-13);
    assert!((cosine - mu.cos() * (-sigma * sigma / 2.0).exp()).abs() < 1e-15);

    // The gamma distribution Gamma(k = 2.5, 1): E[X] = k, E[X²] = k(k + 1), E[e^{−X}] = 2^{−k}.
    let k = 2.5;
    let laguerre = gauss_laguerre(30, k - 1.0)?;
    let mass = laguerre.integrate(|_| 1.0); // Γ(k)
    let mean = laguerre.integrate(|x| x) / mass;
    let second = laguerre.integrate(|x| x * x) / mass;
    let laplace = laguerre.integrate(|x| (-x).exp()) / mass;
    println!("Gamma({k}, 1), 30 Laguerre points:");
    println!(
        "  E[X] = {mean:.16}, E[X²] = {second:.16}, E[e^(−X)] = {laplace:.16} (2^(−k) = {:.16})",
        2f64.powf(-k)
    );
    assert!((mean - k).abs() < 1e-14 && (second - k * (k + 1.0)).abs() < 1e-13);
    assert!((laplace - 2f64.powf(-k)).abs() < 1e-14);

    // The beta distribution Beta(a = 2, b = 3.5) on [0, 1]: weight x^{a−1}(1 − x)^{b−1}.
    let (a, b) = (2.0, 3.5);
    let jacobi = gauss_jacobi(10, b - 1.0, a - 1.0)?.on(0.0, 1.0)?;
    let norm = jacobi.integrate(|_| 1.0); // B(a, b)
    let mean = jacobi.integrate(|x| x) / norm;
    let variance = jacobi.integrate(|x| (x - mean).powi(2)) / norm;
    let exact_variance = a * b / ((a + b).powi(2) * (a + b + 1.0));
    println!("Beta({a}, {b}), 10 Jacobi points on [0, 1]:");
    println!(
        "  mean = {mean:.16} (a/(a+b) = {:.16}), variance = {variance:.16} ({exact_variance:.16})",
        a / (a + b)
    );
    assert!((mean - a / (a + b)).abs() < 1e-15 && (variance - exact_variance).abs() < 1e-15);
    Ok(())
}
