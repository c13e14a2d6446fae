//! The exponential map as a chart.

use super::{RodriguesCoefficients, So3Chart};
use crate::error::LieError;
use crate::scalar::constant;
use crate::series::{
    exp_and_right_jacobian_coefficients, one_minus_cos_and_theta_minus_sin, one_minus_cos_over_sq,
    one_minus_cos_over_sq_derivative, sinc_and_one_minus_cos_over_sq, theta_minus_sin_over_cube,
    theta_minus_sin_over_cube_derivative,
};
use crate::so3::exp::{
    check_exp_domain, exp_matrix, log_and_half_turn, right_jacobian_inverse_unchecked,
};
use crate::so3::{hat, left_jacobian, right_jacobian};
use nalgebra::{Matrix3, RealField, Vector3};
use std::f64::consts::PI;

/// The exponential map `Φ(ξ) = exp(ξ̂)`: `A = J_r`, `B = J_l`.
///
/// A local diffeomorphism for `|ω| < 2π`, so a step may rotate by more than a half turn;
/// `Φ⁻¹ = log` for rotation angles below `π`, and
/// [`So3Chart::rotation_vector_near`] picks the branch beyond it.
/// On SE(3) it is the usual SE(3) exponential, `(exp ω, J_l(ω) v)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct ExpChart;

impl So3Chart for ExpChart {
    fn chart_name(&self) -> &'static str {
        "exp"
    }

    fn rotation_matrix<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        exp_matrix(w)
    }

    fn rotation_vector<T: RealField + Copy>(&self, r: &Matrix3<T>) -> Result<Vector3<T>, LieError> {
        let (w, half_turn) = log_and_half_turn(r);
        if half_turn {
            return Err(LieError::OutsideChart {
                chart: "exponential",
                angle: PI,
                limit: PI,
                hint: "a rotation by exactly π has two logarithms: keep the rotation below π (a \
                       shorter step) or centre the chart elsewhere",
            });
        }
        Ok(w)
    }

    /// The principal logarithm `θa` (`θ ≤ π`) or the other branch inside the domain,
    /// `(θ − 2π)a`, whichever is nearer `near`; at a half turn, `±πa`.
    fn rotation_vector_near<T: RealField + Copy>(
        &self,
        r: &Matrix3<T>,
        near: &Vector3<T>,
    ) -> Result<Vector3<T>, LieError> {
        let (w, _) = log_and_half_turn(r);
        let angle = w.norm();
        // Below this angle the axis is rounding noise and the other branch, of angle
        // 2π − θ, sits at the edge of the domain: the principal branch is the only one.
        if angle <= constant(1e-6) {
            return Ok(w);
        }
        let other = w * (T::one() - T::two_pi() / angle);
        Ok(
            if (other - near).norm_squared() < (w - near).norm_squared() {
                other
            } else {
                w
            },
        )
    }

    /// `2π`: `exp` is a local diffeomorphism for `|ω| < 2π`.
    fn max_rotation_angle(&self) -> f64 {
        std::f64::consts::TAU
    }
    fn check_rotation_domain<T: RealField + Copy>(&self, w: &Vector3<T>) -> Result<(), LieError> {
        check_exp_domain(w)
    }

    fn rotation_left_differential<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        right_jacobian(w)
    }

    /// `exp(ω̂) = I + (sin θ/θ) ω̂ + ((1 − cos θ)/θ²) ω̂²`.
    fn rotation_matrix_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<RodriguesCoefficients<T>> {
        let (a, b) = sinc_and_one_minus_cos_over_sq(s);
        Some(RodriguesCoefficients {
            identity: T::one(),
            hat: a,
            hat_squared: b,
        })
    }

    /// `J_r(ω) = I − ((1 − cos θ)/θ²) ω̂ + ((θ − sin θ)/θ³) ω̂²`.
    fn rotation_left_differential_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<RodriguesCoefficients<T>> {
        let (b, c) = one_minus_cos_and_theta_minus_sin(s);
        Some(RodriguesCoefficients {
            identity: T::one(),
            hat: -b,
            hat_squared: c,
        })
    }

    /// Both from one `sin_cos(θ/2)` (or one series): `Φ`'s `ω̂²` coefficient is `−A`'s
    /// `ω̂` coefficient, and below the series threshold `sin θ/θ = 1 − θ²·(θ − sin θ)/θ³`
    /// (at most 0.55 subtracted from 1 there: no cancellation).
    fn rotation_and_left_differential_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<(RodriguesCoefficients<T>, RodriguesCoefficients<T>)> {
        let (sinc, b, c) = exp_and_right_jacobian_coefficients(s);
        Some((
            RodriguesCoefficients {
                identity: T::one(),
                hat: sinc,
                hat_squared: b,
            },
            RodriguesCoefficients {
                identity: T::one(),
                hat: -b,
                hat_squared: c,
            },
        ))
    }

    fn rotation_left_differential_inverse<T: RealField + Copy>(
        &self,
        w: &Vector3<T>,
    ) -> Matrix3<T> {
        right_jacobian_inverse_unchecked(w)
    }

    fn rotation_right_differential<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        left_jacobian(w)
    }

    fn rotation_right_differential_inverse<T: RealField + Copy>(
        &self,
        w: &Vector3<T>,
    ) -> Matrix3<T> {
        right_jacobian_inverse_unchecked(&(-w))
    }

    fn translation_map<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        left_jacobian(w)
    }

    fn translation_map_inverse<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
        right_jacobian_inverse_unchecked(&(-w))
    }

    /// `∂(J_l(ω) v)/∂ω` for `J_l = I + b ω̂ + c ω̂²`, `b, c` functions of `s = |ω|²`:
    /// `−b v̂ + 2b'(ω×v)ωᵀ + c((ω·v)I + ωvᵀ − 2vωᵀ) + 2c'(ω×(ω×v))ωᵀ`.
    fn translation_map_derivative<T: RealField + Copy>(
        &self,
        w: &Vector3<T>,
        v: &Vector3<T>,
    ) -> Matrix3<T> {
        let s = w.norm_squared();
        let (b, c) = (one_minus_cos_over_sq(s), theta_minus_sin_over_cube(s));
        let (db, dc) = (
            one_minus_cos_over_sq_derivative(s),
            theta_minus_sin_over_cube_derivative(s),
        );
        let two = constant::<T>(2.0);
        let w_cross_v = w.cross(v);
        let w_cross_w_cross_v = w.cross(&w_cross_v);
        -hat(v) * b
            + w_cross_v * w.transpose() * (two * db)
            + (Matrix3::identity() * w.dot(v) + w * v.transpose() - v * w.transpose() * two) * c
            + w_cross_w_cross_v * w.transpose() * (two * dc)
    }
}
