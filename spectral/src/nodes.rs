//! Chebyshev points on an interval, ascending.

use crate::SpectralError;
use std::f64::consts::PI;

pub(crate) fn check_interval(a: f64, b: f64) -> Result<(), SpectralError> {
    if !(a.is_finite() && b.is_finite()) {
        return Err(SpectralError::NonFiniteInterval { a, b });
    }
    if a >= b {
        return Err(SpectralError::EmptyInterval { a, b });
    }
    Ok(())
}

/// `t ∈ [−1, 1] ↦ a(1 − t)/2 + b(1 + t)/2`: sends `±1` exactly to `b` and `a`, and keeps
/// exactly symmetric reference points symmetric about the midpoint up to one rounding.
pub(crate) fn map_to(t: f64, a: f64, b: f64) -> f64 {
    a * (0.5 * (1.0 - t)) + b * (0.5 * (1.0 + t))
}

/// The `n` Chebyshev–Lobatto points (extrema of `T_{n−1}`, "Chebyshev points of the second
/// kind") on `[a, b]`, ascending: `x_j = a(1 − t_j)/2 + b(1 + t_j)/2` with
/// `t_j = −cos(πj/(n−1))`, `j = 0, …, n−1`. Both ends are nodes, exactly.
///
/// The reference points are computed as `sin(π(2j − n + 1)/(2(n − 1)))`, which is exactly
/// antisymmetric, so the points are symmetric about the midpoint and the middle point of
/// an odd set is the midpoint.
///
/// # Errors
/// [`SpectralError::TooFewNodes`] for `n < 2`; [`SpectralError::NonFiniteInterval`] and
/// [`SpectralError::EmptyInterval`] unless `a < b` are finite.
///
/// # Example
/// ```
/// use lgsvi_spectral::chebyshev_lobatto;
/// let x = chebyshev_lobatto(5, 0.0, 2.0)?;
/// assert_eq!((x[0], x[2], x[4]), (0.0, 1.0, 2.0));
/// assert!((x[1] - (1.0 - 0.5f64.sqrt())).abs() < 1e-15);
/// # Ok::<(), lgsvi_spectral::SpectralError>(())
/// ```
pub fn chebyshev_lobatto(n: usize, a: f64, b: f64) -> Result<Vec<f64>, SpectralError> {
    if n < 2 {
        return Err(SpectralError::TooFewNodes {
            kind: "Chebyshev-Lobatto",
            n,
            min: 2,
        });
    }
    check_interval(a, b)?;
    let denominator = 2.0 * (n - 1) as f64;
    Ok((0..n)
        .map(|j| {
            let numerator = 2.0 * j as f64 - (n - 1) as f64;
            let t = (PI * numerator / denominator).sin();
            map_to(t, a, b)
        })
        .collect())
}

/// The `n` Chebyshev points of the first kind (roots of `T_n`) on `[a, b]`, ascending:
/// `t_j = −cos(π(2j + 1)/(2n))`, `j = 0, …, n−1`, mapped as in [`chebyshev_lobatto`].
/// No end is a node.
///
/// # Errors
/// [`SpectralError::TooFewNodes`] for `n = 0`; interval errors as for
/// [`chebyshev_lobatto`].
///
/// # Example
/// ```
/// use lgsvi_spectral::chebyshev_first_kind;
/// let x = chebyshev_first_kind(2, -1.0, 1.0)?;
/// assert!((x[1] - 0.5f64.sqrt()).abs() <= 2.0 * f64::EPSILON && x[0] == -x[1]);
/// # Ok::<(), lgsvi_spectral::SpectralError>(())
/// ```
pub fn chebyshev_first_kind(n: usize, a: f64, b: f64) -> Result<Vec<f64>, SpectralError> {
    if n == 0 {
        return Err(SpectralError::TooFewNodes {
            kind: "Chebyshev (first kind)",
            n,
            min: 1,
        });
    }
    check_interval(a, b)?;
    let denominator = 2.0 * n as f64;
    Ok((0..n)
        .map(|j| {
            let numerator = (2 * j + 1) as f64 - n as f64;
            map_to((PI * numerator / denominator).sin(), a, b)
        })
        .collect())
}
