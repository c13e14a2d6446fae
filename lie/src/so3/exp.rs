//! Exponential, logarithm and the Jacobians of SO(3).

use super::{quaternion, rodrigues_form};
use crate::error::LieError;
use crate::scalar::real;
use crate::series::{
    jr_inverse_coefficient, one_minus_cos_and_theta_minus_sin, sinc_and_one_minus_cos_over_sq,
    theta_over_sin,
};
use nalgebra::{Matrix3, RealField, Vector3};
use std::f64::consts::TAU;

/// `exp(ω̂) = I + (sin θ/θ) ω̂ + ((1 − cos θ)/θ²) ω̂²`.
pub(crate) fn exp_matrix<T: RealField + Copy>(w: &Vector3<T>) -> Matrix3<T> {
    let (a, b) = sinc_and_one_minus_cos_over_sq(w.norm_squared());
    rodrigues_form(w, a, b)
}

/// `cos θ` below which [`log_matrix`] goes through the quaternion (`θ > 2π/3`).
const LOG_QUATERNION_BELOW_COS: f64 = -0.5;

/// The logarithm, and whether the rotation is by exactly `π` (where its sign is arbitrary).
///
/// For `θ ≤ 2π/3` (`cos θ ≥ −½`): `u = vee(R − Rᵀ)/2 = sin θ · n` is accurate to ε
/// relative there (its entries dominate the symmetric part's), and `ω = (θ/sin θ) u` with
/// `θ = asin|u|` while `cos θ > 0.7` and `θ = acos(cos θ)` below (each where its
/// derivative is ≤ 1.5, and both cheaper than `atan2`). Beyond, where `u` shrinks towards 0
/// and loses its direction, through the unit quaternion `(q_w, q_v)` of Shepperd's
/// method: `ω = 2 acos(q_w) q_v/|q_v|`.
pub(crate) fn log_and_half_turn<T: RealField + Copy>(r: &Matrix3<T>) -> (Vector3<T>, bool) {
    let half: T = nalgebra::convert(0.5);
    let cos = (r[(0, 0)] + r[(1, 1)] + r[(2, 2)] - T::one()) * half;
    if real(cos) >= LOG_QUATERNION_BELOW_COS {
        let u = Vector3::new(
            r[(2, 1)] - r[(1, 2)],
            r[(0, 2)] - r[(2, 0)],
            r[(1, 0)] - r[(0, 1)],
        ) * half;
        (u * theta_over_sin(u.norm_squared(), cos), false)
    } else {
        // θ > 2π/3: q_w = cos(θ/2) < ½ and |q_v| > 0.86, so θ/2 = acos(q_w) is well
        // conditioned (derivative ≤ 1.2) and nothing is divided by a small number.
        let (w, v) = quaternion::from_matrix(r);
        let two: T = nalgebra::convert(2.0);
        (
            v * (two * w.acos() / v.norm()),
            real(w) <= 0.0 || real(w).is_nan(),
        )
    }
}

/// The logarithm, `|ω| ≤ π`.
pub(crate) fn log_matrix<T: RealField + Copy>(r: &Matrix3<T>) -> Vector3<T> {
    log_and_half_turn(r).0
}

/// The right Jacobian `J_r(ω) = I − ((1 − cos θ)/θ²) ω̂ + ((θ − sin θ)/θ³) ω̂²`, the
/// left-trivialised differential of `exp`: `exp(ω)⁻¹ d exp(ω)[v] = (J_r(ω) v)^`.
///
/// ```
/// use lgsvi_lie::so3::right_jacobian;
/// use nalgebra::{Matrix3, Vector3};
/// assert_eq!(right_jacobian(&Vector3::<f64>::zeros()), Matrix3::identity());
/// ```
pub fn right_jacobian<T: RealField + Copy>(w: &Vector3<T>) -> Matrix3<T> {
    let (b, c) = one_minus_cos_and_theta_minus_sin(w.norm_squared());
    rodrigues_form(w, -b, c)
}

/// The left Jacobian `J_l(ω) = J_r(−ω) = R J_r(ω)`, the right-trivialised differential
/// of `exp`: `d exp(ω)[v] exp(ω)⁻¹ = (J_l(ω) v)^`.
pub fn left_jacobian<T: RealField + Copy>(w: &Vector3<T>) -> Matrix3<T> {
    right_jacobian(&(-w))
}

pub(crate) fn check_exp_domain<T: RealField + Copy>(w: &Vector3<T>) -> Result<(), LieError> {
    let angle = real(w.norm());
    if !angle.is_finite() {
        return Err(LieError::NonFinite {
            what: "rotation vector",
        });
    }
    if angle >= TAU {
        return Err(LieError::OutsideChart {
            chart: "exponential",
            angle,
            limit: TAU,
            hint: "the differential of exp is singular at 2π; take a shorter step",
        });
    }
    Ok(())
}

/// `J_r(ω)⁻¹ = I + ½ ω̂ + (1/θ² − cot(θ/2)/(2θ)) ω̂²`, for `|ω| < 2π`.
///
/// # Errors
/// [`LieError::OutsideChart`] for `|ω| ≥ 2π`, where `J_r` is singular;
/// [`LieError::NonFinite`] for a non-finite `ω`.
///
/// ```
/// use lgsvi_lie::so3::{right_jacobian, right_jacobian_inverse};
/// use nalgebra::{Matrix3, Vector3};
/// let w = Vector3::new(0.3, -1.2, 2.0);
/// let product = right_jacobian(&w) * right_jacobian_inverse(&w)?;
/// assert!((product - Matrix3::identity()).norm() < 1e-14);
/// assert!(right_jacobian_inverse(&Vector3::new(7.0, 0.0, 0.0)).is_err());
/// # Ok::<(), lgsvi_lie::LieError>(())
/// ```
pub fn right_jacobian_inverse<T: RealField + Copy>(w: &Vector3<T>) -> Result<Matrix3<T>, LieError> {
    check_exp_domain(w)?;
    Ok(right_jacobian_inverse_unchecked(w))
}

/// `J_r(ω)⁻¹` without the domain check (for callers that have made it).
pub(crate) fn right_jacobian_inverse_unchecked<T: RealField + Copy>(w: &Vector3<T>) -> Matrix3<T> {
    rodrigues_form(
        w,
        nalgebra::convert(0.5),
        jr_inverse_coefficient(w.norm_squared()),
    )
}

/// `J_l(ω)⁻¹ = J_r(−ω)⁻¹`, for `|ω| < 2π`.
///
/// # Errors
/// As [`right_jacobian_inverse`].
pub fn left_jacobian_inverse<T: RealField + Copy>(w: &Vector3<T>) -> Result<Matrix3<T>, LieError> {
    right_jacobian_inverse(&(-w))
}
