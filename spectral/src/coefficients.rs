//! Chebyshev coefficients of the interpolant through values at Chebyshev–Lobatto nodes.
//!
//! With `N = n − 1` and the ascending nodes `t_j = −cos(πj/N)` of [`chebyshev_lobatto`]
//! (mapped to any `[a, b]`), the interpolant is `p(t) = Σ_{k=0}^{N} c_k T_k(t)` with the
//! discrete cosine transform of type I
//!
//! ```text
//! c_k = (2 / (N γ_k)) Σ''_j f_j T_k(t_j),   T_k(t_j) = (−1)^k cos(πjk/N),
//! ```
//!
//! where `Σ''` halves the terms `j = 0` and `j = N`, and `γ_0 = γ_N = 2`, `γ_k = 1`
//! otherwise. The decay of `|c_k|` is what a spectral method reads its own accuracy from:
//! for a function analytic in the Bernstein ellipse `E_ρ`, `|c_k| = O(ρ^{−k})`.
//!
//! [`chebyshev_lobatto`]: crate::chebyshev_lobatto

use crate::error::SpectralError;
use crate::matrix::Matrix;
use std::f64::consts::PI;

/// The `n × n` matrix `C` with `c_k = Σ_j C[k][j] f_j`: the Chebyshev coefficients of the
/// interpolant through values `f_j` at the `n` Chebyshev–Lobatto nodes, in the ascending
/// order of [`chebyshev_lobatto`](crate::chebyshev_lobatto). Row `k` is contiguous, so a
/// caller who needs only the last coefficients (an error estimate) keeps those rows.
///
/// # Errors
/// [`SpectralError::TooFewNodes`] for `n < 2`.
///
/// # Example
/// ```
/// use lgsvi_spectral::{chebyshev_coefficient_matrix, chebyshev_lobatto};
/// // T_2(t) = 2t² − 1 on 5 nodes of [−1, 1]: the coefficients are (0, 0, 1, 0, 0).
/// let t = chebyshev_lobatto(5, -1.0, 1.0)?;
/// let f: Vec<f64> = t.iter().map(|t| 2.0 * t * t - 1.0).collect();
/// let c = chebyshev_coefficient_matrix(5)?.mul_vec(&f).unwrap();
/// assert!((c[2] - 1.0).abs() < 1e-15);
/// assert!(c.iter().enumerate().all(|(k, c)| k == 2 || c.abs() < 1e-15));
/// # Ok::<(), lgsvi_spectral::SpectralError>(())
/// ```
pub fn chebyshev_coefficient_matrix(n: usize) -> Result<Matrix, SpectralError> {
    if n < 2 {
        return Err(SpectralError::TooFewNodes {
            kind: "Chebyshev-Lobatto",
            n,
            min: 2,
        });
    }
    let last = n - 1;
    let mut matrix = Matrix::zeros(n, n);
    for k in 0..n {
        let gamma = if k == 0 || k == last { 2.0 } else { 1.0 };
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        let row = matrix.row_mut(k);
        for (j, entry) in row.iter_mut().enumerate() {
            let halve = if j == 0 || j == last { 0.5 } else { 1.0 };
            // cos(πjk/N) with jk reduced mod 2N: the argument stays in [0, 2π), so the
            // rounding of the cosine does not grow with j·k.
            let phase = (j * k) % (2 * last);
            let cosine = (PI * phase as f64 / last as f64).cos();
            *entry = 2.0 / (last as f64 * gamma) * halve * sign * cosine;
        }
    }
    Ok(matrix)
}

/// From this many values on, the transforms go through the FFT (`O(n log n)`); below, the
/// cosine sums directly (faster there, and bit for bit what earlier versions computed).
pub const FFT_FROM: usize = 65;

/// The Chebyshev coefficients `c_0, …, c_{n−1}` of the interpolant through `values` at the
/// `n = values.len()` Chebyshev–Lobatto nodes (ascending), as
/// [`chebyshev_coefficient_matrix`] defines them: the cosine sums directly below
/// [`FFT_FROM`] values, from there a real-to-real DCT-I through a complex FFT of the even
/// extension (length `2(n − 1)`, `O(n log n)`).
///
/// # Errors
/// [`SpectralError::TooFewNodes`] for fewer than two values.
///
/// # Example
/// ```
/// use lgsvi_spectral::{chebyshev_coefficients, chebyshev_lobatto};
/// // exp on [−1, 1]: c_k = 2 I_k(1) for k ≥ 1 (modified Bessel functions), c_0 = I_0(1).
/// let t = chebyshev_lobatto(20, -1.0, 1.0)?;
/// let f: Vec<f64> = t.iter().map(|t| t.exp()).collect();
/// let c = chebyshev_coefficients(&f)?;
/// assert!((c[0] - 1.266_065_877_752_008_4).abs() < 1e-15);
/// assert!((c[1] - 2.0 * 0.565_159_103_992_485_0).abs() < 1e-15);
/// assert!(c[19].abs() < 1e-15); // 2 I_19(1) = 3e-23: only rounding is left
/// # Ok::<(), lgsvi_spectral::SpectralError>(())
/// ```
pub fn chebyshev_coefficients(values: &[f64]) -> Result<Vec<f64>, SpectralError> {
    let n = values.len();
    if n < FFT_FROM {
        let matrix = chebyshev_coefficient_matrix(n)?;
        return Ok(matrix
            .mul_vec(values)
            .expect("the matrix has one column per value"));
    }
    // G_k = Σ_j g_j e^{−iπjk/N} over the even extension g = (f_0 … f_N, f_{N−1} … f_1)
    // is 2 Σ''_j f_j cos(πjk/N), so c_k = (−1)^k G_k / (N γ_k).
    let last = n - 1;
    let g = dct1(values);
    Ok(g.iter()
        .enumerate()
        .map(|(k, &gk)| {
            let gamma = if k == 0 || k == last { 2.0 } else { 1.0 };
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            sign * gk / (last as f64 * gamma)
        })
        .collect())
}

/// The values `p(t_j)` at the `n = coefficients.len()` Chebyshev–Lobatto nodes (ascending)
/// of the series `p = Σ_k c_k T_k`: the inverse of [`chebyshev_coefficients`], by the same
/// DCT-I (`O(n log n)` from [`FFT_FROM`] coefficients; Clenshaw's sums below).
///
/// # Errors
/// [`SpectralError::TooFewNodes`] for fewer than two coefficients.
///
/// # Example
/// ```
/// use lgsvi_spectral::{chebyshev_coefficients, chebyshev_values};
/// let values: Vec<f64> = (0..100).map(|j| (j as f64 * 0.1).sin()).collect();
/// let back = chebyshev_values(&chebyshev_coefficients(&values)?)?;
/// assert!(values.iter().zip(&back).all(|(a, b)| (a - b).abs() < 1e-14));
/// # Ok::<(), lgsvi_spectral::SpectralError>(())
/// ```
pub fn chebyshev_values(coefficients: &[f64]) -> Result<Vec<f64>, SpectralError> {
    let n = coefficients.len();
    if n < 2 {
        return Err(SpectralError::TooFewNodes {
            kind: "Chebyshev-Lobatto",
            n,
            min: 2,
        });
    }
    let last = n - 1;
    // p(t_j) = Σ_k c_k (−1)^k cos(πjk/N) = ½ G_j of e_k = (−1)^k c_k γ_k.
    let e: Vec<f64> = coefficients
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            let gamma = if k == 0 || k == last { 2.0 } else { 1.0 };
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            sign * gamma * c
        })
        .collect();
    if n < FFT_FROM {
        return Ok((0..n)
            .map(|j| {
                (0..n)
                    .map(|k| {
                        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
                        let phase = (j * k) % (2 * last);
                        sign * coefficients[k] * (PI * phase as f64 / last as f64).cos()
                    })
                    .sum::<f64>()
            })
            .collect());
    }
    Ok(dct1(&e).into_iter().map(|g| 0.5 * g).collect())
}

/// `G_k = 2 Σ''_j f_j cos(πjk/N)`, `k = 0 … N` (the unnormalised DCT-I), from one complex
/// FFT of length `2N` of the even extension of `f`.
fn dct1(f: &[f64]) -> Vec<f64> {
    use rustfft::num_complex::Complex;
    let last = f.len() - 1;
    let len = 2 * last;
    let mut buffer: Vec<Complex<f64>> = (0..len)
        .map(|j| Complex::new(if j <= last { f[j] } else { f[len - j] }, 0.0))
        .collect();
    let mut planner = rustfft::FftPlanner::new();
    planner.plan_fft_forward(len).process(&mut buffer);
    buffer[..=last].iter().map(|z| z.re).collect()
}
