//! A function as its Chebyshev series: fit, roots, extrema, an integral.
//!
//! Fits `f(x) = sin(5x)/(1 + x²)` on [−2, 3] to machine precision, finds its roots (the
//! colleague matrix's eigenvalues, polished by Newton), its extrema (the roots of the
//! derivative series) and its integral, and checks the roots of cos(10x) on [0, 3]
//! against (2k + 1)π/20.
//!
//! Run: `cargo run --release -p lgsvi-spectral --example chebyshev_roots`

use lgsvi_spectral::Chebyshev;
use std::f64::consts::PI;

fn main() -> Result<(), lgsvi_spectral::SpectralError> {
    let f = |x: f64| (5.0 * x).sin() / (1.0 + x * x);
    let fit = Chebyshev::fit(f, -2.0, 3.0)?;
    let worst = (0..=2000)
        .map(|i| -2.0 + 5.0 * i as f64 / 2000.0)
        .map(|x| Ok((fit.evaluate(x)? - f(x)).abs()))
        .collect::<Result<Vec<f64>, _>>()?
        .into_iter()
        .fold(0.0f64, f64::max);
    println!(
        "sin(5x)/(1+x²) on [−2, 3]: {} coefficients, largest error on 2001 points {worst:.1e}",
        fit.len()
    );
    assert!(worst < 1e-14);
    let roots = fit.roots();
    println!("roots ({}): {:.6?}", roots.len(), roots);
    for r in &roots {
        assert!(f(*r).abs() < 1e-14, "f({r}) = {}", f(*r));
    }
    let extrema = fit.derivative().roots();
    let highest = extrema
        .iter()
        .map(|&x| (x, f(x)))
        .fold(
            (0.0, f64::NEG_INFINITY),
            |m, p| if p.1 > m.1 { p } else { m },
        );
    println!(
        "{} extrema; the maximum f({:.12}) = {:.12}",
        extrema.len(),
        highest.0,
        highest.1
    );
    println!("∫ f over [−2, 3] = {:.15}", fit.definite_integral());

    let cosine = Chebyshev::fit(|x| (10.0 * x).cos(), 0.0, 3.0)?;
    let roots = cosine.roots();
    let error = roots
        .iter()
        .enumerate()
        .map(|(k, r)| (r - (2 * k + 1) as f64 * PI / 20.0).abs())
        .fold(0.0f64, f64::max);
    println!(
        "cos(10x) on [0, 3]: {} roots, largest error against (2k + 1)π/20: {error:.1e}",
        roots.len()
    );
    assert!(roots.len() == 10 && error < 1e-14);
    Ok(())
}
