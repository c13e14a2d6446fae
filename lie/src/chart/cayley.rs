//! The Cayley transforms as charts.

use super::{RodriguesCoefficients, So3Chart};
use crate::error::LieError;
use crate::scalar::{constant, real};
use crate::so3::{hat, quaternion, rodrigues_form};
use nalgebra::{Matrix3, RealField, Vector3};
use std::f64::consts::PI;

/// The quaternion `(w, v)` of `R`, refusing a rotation by `π` (`w = 0`), where both
/// Cayley maps are singular.
fn quaternion_below_pi<T: RealField + Copy>(
    r: &Matrix3<T>,
    chart: &'static str,
) -> Result<(T, Vector3<T>), LieError> {
    let (w, v) = quaternion::from_matrix(r);
    if real(w) <= 0.0 || real(w).is_nan() {
        return Err(LieError::OutsideChart {
            chart,
            angle: PI,
            limit: PI,
            hint: "the Cayley transform is singular at a rotation by π: keep each step's rotation \
                   below π (a shorter step) or take the exp chart, which reaches 2π",
        });
    }
    Ok((w, v))
}

fn check_finite<T: RealField + Copy>(w: &Vector3<T>) -> Result<(), LieError> {
    if w.iter().all(|x| real(*x).is_finite()) {
        Ok(())
    } else {
        Err(LieError::NonFinite {
            what: "chart coordinates",
        })
    }
}

/// The standard Cayley transform `Φ(ξ) = (I − ξ̂/2)⁻¹(I + ξ̂/2)`, which agrees with `exp`
/// to second order: a rotation by `2 atan(|ξ|/2)` about `ξ`.
///
/// `Φ(ξ) = I + (4/(4 + |ξ|²))(ξ̂ + ξ̂²/2)`; `A(ξ) = (I − ξ̂/2)/(1 + |ξ|²/4)`,
/// `A⁻¹ = I + ξ̂/2 + ξξᵀ/4`; `B(ξ) = (I + ξ̂/2)/(1 + |ξ|²/4)`, `B⁻¹ = I − ξ̂/2 + ξξᵀ/4`;
/// `Φ⁻¹(R) = 2 q_v/q_w` from the unit quaternion. A diffeomorphism from ℝ³ onto the
/// rotations by less than `π`. On SE(3), `M(ω) = (I − ω̂/2)⁻¹`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct CayleyChart;

impl So3Chart for CayleyChart {
    fn chart_name(&self) -> &'static str {
        "cayley"
    }

    fn rotation_matrix<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        let scale = constant::<T>(4.0) / (constant::<T>(4.0) + w.norm_squared());
        rodrigues_form(w, scale, scale * constant::<T>(0.5))
    }

    fn rotation_vector<T: RealField + Copy>(&self, r: &Matrix3<T>) -> Result<Vector3<T>, LieError> {
        let (qw, qv) = quaternion_below_pi(r, "cayley")?;
        Ok(qv * (constant::<T>(2.0) / qw))
    }

    fn check_rotation_domain<T: RealField + Copy>(&self, w: &Vector3<T>) -> Result<(), LieError> {
        check_finite(w)
    }

    fn rotation_left_differential<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        let half = constant::<T>(0.5);
        (Matrix3::identity() - hat(w) * half) / (T::one() + w.norm_squared() * constant(0.25))
    }

    /// `Φ = I + (4/(4 + s)) ξ̂ + (2/(4 + s)) ξ̂²`.
    fn rotation_matrix_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<RodriguesCoefficients<T>> {
        let scale = constant::<T>(4.0) / (constant::<T>(4.0) + s);
        Some(RodriguesCoefficients {
            identity: T::one(),
            hat: scale,
            hat_squared: scale * constant::<T>(0.5),
        })
    }

    /// `A = (I − ξ̂/2)/(1 + s/4)`.
    fn rotation_left_differential_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<RodriguesCoefficients<T>> {
        let scale = T::one() / (T::one() + s * constant::<T>(0.25));
        Some(RodriguesCoefficients {
            identity: scale,
            hat: scale * constant::<T>(-0.5),
            hat_squared: T::zero(),
        })
    }

    fn rotation_left_differential_inverse<T: RealField + Copy>(
        &self,
        w: &Vector3<T>,
    ) -> Matrix3<T> {
        Matrix3::identity() + hat(w) * constant::<T>(0.5) + w * w.transpose() * constant::<T>(0.25)
    }

    fn rotation_right_differential<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        let half = constant::<T>(0.5);
        (Matrix3::identity() + hat(w) * half) / (T::one() + w.norm_squared() * constant(0.25))
    }

    fn rotation_right_differential_inverse<T: RealField + Copy>(
        &self,
        w: &Vector3<T>,
    ) -> Matrix3<T> {
        Matrix3::identity() - hat(w) * constant::<T>(0.5) + w * w.transpose() * constant::<T>(0.25)
    }

    /// `(I − ω̂/2)⁻¹ = I + (ω̂/2 + ω̂²/4)/(1 + |ω|²/4)`.
    fn translation_map<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        let w_hat = hat(w);
        Matrix3::identity()
            + (w_hat * constant::<T>(0.5) + w_hat * w_hat * constant::<T>(0.25))
                / (T::one() + w.norm_squared() * constant(0.25))
    }

    fn translation_map_inverse<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        Matrix3::identity() - hat(w) * constant::<T>(0.5)
    }

    /// `d(M v) = M (dω̂/2) M v`, so `N = −½ M (Mv)^`.
    fn translation_map_derivative<T: RealField + Copy>(
        &self,
        w: &Vector3<T>,
        v: &Vector3<T>,
    ) -> Matrix3<T> {
        let m = self.translation_map(w);
        -m * hat(&(m * v)) * constant::<T>(0.5)
    }
}

/// The paper's unscaled Cayley transform `Φ(q) = (I − q̂)(I + q̂)⁻¹`, its own inverse as a
/// matrix map: a rotation by `−2 atan|q|` about `q` (that is, `CayleyChart` at `−2q`).
///
/// `Φ(q) = I + 2(q̂² − q̂)/(1 + |q|²)`; `A(q) = −2(I + q̂)/(1 + |q|²)`,
/// `A⁻¹ = −½(I + qqᵀ − q̂)`; `B(q) = −2(I − q̂)/(1 + |q|²)`, `B⁻¹ = −½(I + qqᵀ + q̂)`;
/// `Φ⁻¹(R) = −q_v/q_w`. Well conditioned for `|q| < 1` (rotations below `π/2`); singular
/// at a rotation by `π`. On SE(3), `M(q) = −2(I + q̂)⁻¹` (the 4×4 transform).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct UnscaledCayleyChart;

impl So3Chart for UnscaledCayleyChart {
    fn chart_name(&self) -> &'static str {
        "cayley-unscaled"
    }

    fn rotation_matrix<T: RealField + Copy>(&self, q: &Vector3<T>) -> Matrix3<T> {
        let scale = constant::<T>(2.0) / (T::one() + q.norm_squared());
        rodrigues_form(q, -scale, scale)
    }

    fn rotation_vector<T: RealField + Copy>(&self, r: &Matrix3<T>) -> Result<Vector3<T>, LieError> {
        let (qw, qv) = quaternion_below_pi(r, "cayley-unscaled")?;
        Ok(-qv / qw)
    }

    fn check_rotation_domain<T: RealField + Copy>(&self, q: &Vector3<T>) -> Result<(), LieError> {
        check_finite(q)
    }

    fn rotation_left_differential<T: RealField + Copy>(&self, q: &Vector3<T>) -> Matrix3<T> {
        (Matrix3::identity() + hat(q)) * (constant::<T>(-2.0) / (T::one() + q.norm_squared()))
    }

    /// `Φ = I − (2/(1 + s)) q̂ + (2/(1 + s)) q̂²`.
    fn rotation_matrix_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<RodriguesCoefficients<T>> {
        let scale = constant::<T>(2.0) / (T::one() + s);
        Some(RodriguesCoefficients {
            identity: T::one(),
            hat: -scale,
            hat_squared: scale,
        })
    }

    /// `A = −2(I + q̂)/(1 + s)`.
    fn rotation_left_differential_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<RodriguesCoefficients<T>> {
        let scale = constant::<T>(-2.0) / (T::one() + s);
        Some(RodriguesCoefficients {
            identity: scale,
            hat: scale,
            hat_squared: T::zero(),
        })
    }

    fn rotation_left_differential_inverse<T: RealField + Copy>(
        &self,
        q: &Vector3<T>,
    ) -> Matrix3<T> {
        (Matrix3::identity() + q * q.transpose() - hat(q)) * constant::<T>(-0.5)
    }

    fn rotation_right_differential<T: RealField + Copy>(&self, q: &Vector3<T>) -> Matrix3<T> {
        (Matrix3::identity() - hat(q)) * (constant::<T>(-2.0) / (T::one() + q.norm_squared()))
    }

    fn rotation_right_differential_inverse<T: RealField + Copy>(
        &self,
        q: &Vector3<T>,
    ) -> Matrix3<T> {
        (Matrix3::identity() + q * q.transpose() + hat(q)) * constant::<T>(-0.5)
    }

    /// `−2(I + q̂)⁻¹ = −2(I + (q̂² − q̂)/(1 + |q|²))`.
    fn translation_map<T: RealField + Copy>(&self, q: &Vector3<T>) -> Matrix3<T> {
        let q_hat = hat(q);
        (Matrix3::identity() + (q_hat * q_hat - q_hat) / (T::one() + q.norm_squared()))
            * constant::<T>(-2.0)
    }

    fn translation_map_inverse<T: RealField + Copy>(&self, q: &Vector3<T>) -> Matrix3<T> {
        (Matrix3::identity() + hat(q)) * constant::<T>(-0.5)
    }

    /// `d(M v) = 2(I + q̂)⁻¹ dq̂ (I + q̂)⁻¹ v`, so `N = −½ M (Mv)^`.
    fn translation_map_derivative<T: RealField + Copy>(
        &self,
        q: &Vector3<T>,
        v: &Vector3<T>,
    ) -> Matrix3<T> {
        let m = self.translation_map(q);
        -m * hat(&(m * v)) * constant::<T>(0.5)
    }
}
