//! The Golub–Welsch algorithm: Gauss rules from the Jacobi matrix of a three-term recurrence.

use crate::error::at_least;
use crate::QuadratureError;

/// Sweeps allowed per eigenvalue before [`QuadratureError::EigenNotConverged`]. Implicit QL
/// with Wilkinson's shift converges cubically; two or three sweeps per eigenvalue are
/// typical, thirty is the classical generous bound.
const MAX_SWEEPS_PER_EIGENVALUE: usize = 30;

/// Nodes and weights of the Gauss rule of a weight function, from its Jacobi matrix.
///
/// The monic orthogonal polynomials of a weight `w(x) ≥ 0` satisfy
/// `p_{k+1}(x) = (x − α_k) p_k(x) − β_k p_{k−1}(x)`. The `m`-point Gauss rule's nodes are
/// the eigenvalues of the symmetric tridiagonal Jacobi matrix with diagonal `α_0..α_{m−1}`
/// and off-diagonal `√β_1..√β_{m−1}`, and its weights are `μ₀ v₀²`, where `v₀` is the
/// first component of the normalised eigenvector and `μ₀ = ∫ w(x) dx` (Golub & Welsch,
/// *Math. Comp.* 23, 1969).
///
/// The eigenproblem is solved by implicit QL with Wilkinson shifts directly on the
/// tridiagonal matrix, updating only the first row of the eigenvector matrix: `O(m²)`
/// operations and `O(m)` memory, against `O(m³)` and `O(m²)` for a dense symmetric
/// eigensolver that forms all eigenvectors. Nodes are accurate to about `m·ε·‖J‖` in
/// absolute terms and weights to a relative error that grows with `m`; for the Legendre
/// family the functions [`gauss_legendre`](crate::gauss_legendre) and friends polish both
/// to a few ulps.
///
/// Returns `(nodes, weights)`, nodes ascending.
///
/// # Errors
/// [`QuadratureError::TooFewPoints`] for an empty diagonal, [`QuadratureError::JacobiShape`]
/// when `off_diagonal.len() + 1 != diagonal.len()`, [`QuadratureError::NonFiniteJacobi`],
/// [`QuadratureError::InvalidMass`], and [`QuadratureError::EigenNotConverged`].
///
/// # Example
/// Three-point Gauss–Hermite (`w = e^{−x²}`: `α_k = 0`, `β_k = k/2`, `μ₀ = √π`),
/// whose nodes are `0, ±√(3/2)`:
/// ```
/// use lgsvi_quadrature::golub_welsch;
/// let off: Vec<f64> = (1..3).map(|k| (k as f64 / 2.0).sqrt()).collect();
/// let (nodes, weights) = golub_welsch(&[0.0; 3], &off, std::f64::consts::PI.sqrt())?;
/// assert!((nodes[2] - 1.5f64.sqrt()).abs() < 1e-14);
/// assert!((weights[1] - 2.0 * std::f64::consts::PI.sqrt() / 3.0).abs() < 1e-14);
/// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
/// ```
pub fn golub_welsch(
    diagonal: &[f64],
    off_diagonal: &[f64],
    total_mass: f64,
) -> Result<(Vec<f64>, Vec<f64>), QuadratureError> {
    let m = diagonal.len();
    at_least("a Gauss rule", m, 1)?;
    if off_diagonal.len() + 1 != m {
        return Err(QuadratureError::JacobiShape {
            diagonal: m,
            off_diagonal: off_diagonal.len(),
        });
    }
    if let Some(index) = diagonal.iter().position(|v| !v.is_finite()) {
        return Err(QuadratureError::NonFiniteJacobi {
            part: "diagonal",
            index,
        });
    }
    if let Some(index) = off_diagonal.iter().position(|v| !v.is_finite()) {
        return Err(QuadratureError::NonFiniteJacobi {
            part: "off-diagonal",
            index,
        });
    }
    if !(total_mass.is_finite() && total_mass > 0.0) {
        return Err(QuadratureError::InvalidMass { mass: total_mass });
    }

    let mut d = diagonal.to_vec();
    // e[i] couples rows i and i+1; e[m-1] = 0 is a sentinel.
    let mut e = off_diagonal.to_vec();
    e.push(0.0);
    // First row of the accumulated eigenvector matrix.
    let mut z = vec![0.0; m];
    z[0] = 1.0;
    implicit_ql(&mut d, &mut e, &mut z)?;

    let mut pairs: Vec<(f64, f64)> = d
        .into_iter()
        .zip(z)
        .map(|(x, v)| (x, total_mass * v * v))
        .collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(pairs.into_iter().unzip())
}

/// `√(f² + g²)`: directly where neither square can overflow or lose the result to
/// underflow, else by `hypot`. The direct form is within an ulp or two of `hypot`, and the
/// nodes are polished afterwards anyway; `hypot`, careful about overflow at every call, is
/// a large share of the time of building an integrator's small rules.
#[inline]
fn pythag(f: f64, g: f64) -> f64 {
    let big = f.abs().max(g.abs());
    if big > 1e-150 && big < 1e150 {
        (f * f + g * g).sqrt()
    } else {
        f.hypot(g)
    }
}

/// Implicit QL with Wilkinson shifts on the symmetric tridiagonal matrix `(d, e)`,
/// applying every Givens rotation to the row vector `z` only. On return `d` holds the
/// eigenvalues (unsorted) and `z[j]` the first component of the `j`-th eigenvector.
fn implicit_ql(d: &mut [f64], e: &mut [f64], z: &mut [f64]) -> Result<(), QuadratureError> {
    let n = d.len();
    for l in 0..n {
        let mut sweeps = 0;
        loop {
            // Find the first negligible off-diagonal element at or after l.
            let mut m = l;
            while m + 1 < n {
                let dd = d[m].abs() + d[m + 1].abs();
                if e[m].abs() <= f64::EPSILON * dd {
                    break;
                }
                m += 1;
            }
            if m == l {
                break;
            }
            sweeps += 1;
            if sweeps > MAX_SWEEPS_PER_EIGENVALUE {
                return Err(QuadratureError::EigenNotConverged {
                    index: l,
                    iterations: sweeps - 1,
                });
            }
            // Wilkinson shift from the leading 2×2 block.
            let mut g = (d[l + 1] - d[l]) / (2.0 * e[l]);
            let mut r = pythag(g, 1.0);
            g = d[m] - d[l] + e[l] / (g + r.copysign(g));
            let (mut s, mut c, mut p) = (1.0f64, 1.0f64, 0.0f64);
            let mut underflow = false;
            for i in (l..m).rev() {
                let f = s * e[i];
                let b = c * e[i];
                r = pythag(f, g);
                e[i + 1] = r;
                if r == 0.0 {
                    // Recover from underflow: deflate and restart the sweep.
                    d[i + 1] -= p;
                    e[m] = 0.0;
                    underflow = true;
                    break;
                }
                s = f / r;
                c = g / r;
                g = d[i + 1] - p;
                r = (d[i] - g) * s + 2.0 * c * b;
                p = s * r;
                d[i + 1] = g + p;
                g = c * r - b;
                let zi1 = z[i + 1];
                z[i + 1] = s * z[i] + c * zi1;
                z[i] = c * z[i] - s * zi1;
            }
            if underflow {
                continue;
            }
            d[l] -= p;
            e[l] = g;
            e[m] = 0.0;
        }
    }
    Ok(())
}
