//! [`Chart`] for SO(3) and SE(3) from any [`So3Chart`].

use super::{Chart, So3Chart};
use crate::error::LieError;
use crate::se3::{blocks, join, split, SE3};
use crate::so3::{hat, SO3};
use nalgebra::{Matrix3, Matrix6, RealField, Vector3, Vector6};

impl<T: RealField + Copy, C: So3Chart> Chart<SO3<T>> for C {
    fn name(&self) -> &'static str {
        self.chart_name()
    }

    fn to_group(&self, xi: &Vector3<T>) -> SO3<T> {
        SO3::from_matrix_unchecked(self.rotation_matrix(xi))
    }

    fn to_algebra(&self, g: &SO3<T>) -> Result<Vector3<T>, LieError> {
        self.rotation_vector(g.matrix())
    }

    fn check_domain(&self, xi: &Vector3<T>) -> Result<(), LieError> {
        self.check_rotation_domain(xi)
    }

    fn left_differential(&self, xi: &Vector3<T>) -> Matrix3<T> {
        self.rotation_left_differential(xi)
    }

    fn left_differential_inverse(&self, xi: &Vector3<T>) -> Result<Matrix3<T>, LieError> {
        self.check_rotation_domain(xi)?;
        Ok(self.rotation_left_differential_inverse(xi))
    }

    fn right_differential(&self, xi: &Vector3<T>) -> Matrix3<T> {
        self.rotation_right_differential(xi)
    }

    fn right_differential_inverse(&self, xi: &Vector3<T>) -> Result<Matrix3<T>, LieError> {
        self.check_rotation_domain(xi)?;
        Ok(self.rotation_right_differential_inverse(xi))
    }
}

impl<T: RealField + Copy, C: So3Chart> Chart<SE3<T>> for C {
    fn name(&self) -> &'static str {
        self.chart_name()
    }

    /// `(Φ(ω), M(ω) v)`.
    fn to_group(&self, xi: &Vector6<T>) -> SE3<T> {
        let (w, v) = split(xi);
        SE3::new(
            SO3::from_matrix_unchecked(self.rotation_matrix(&w)),
            self.translation_map(&w) * v,
        )
    }

    /// `(Φ⁻¹(R), M(ω)⁻¹ x)`.
    fn to_algebra(&self, g: &SE3<T>) -> Result<Vector6<T>, LieError> {
        let w = self.rotation_vector(g.rotation().matrix())?;
        Ok(join(
            &w,
            &(self.translation_map_inverse(&w) * g.translation()),
        ))
    }

    fn check_domain(&self, xi: &Vector6<T>) -> Result<(), LieError> {
        let (w, v) = split(xi);
        self.check_rotation_domain(&w)?;
        if v.iter().all(|x| crate::scalar::real(*x).is_finite()) {
            Ok(())
        } else {
            Err(LieError::NonFinite {
                what: "chart coordinates",
            })
        }
    }

    /// `[[A_ω, 0], [RᵀN, RᵀM]]`.
    fn left_differential(&self, xi: &Vector6<T>) -> Matrix6<T> {
        let (w, v) = split(xi);
        let r_t = self.rotation_matrix(&w).transpose();
        blocks(
            &self.rotation_left_differential(&w),
            &Matrix3::zeros(),
            &(r_t * self.translation_map_derivative(&w, &v)),
            &(r_t * self.translation_map(&w)),
        )
    }

    /// `[[A_ω⁻¹, 0], [−M⁻¹N A_ω⁻¹, M⁻¹R]]`.
    fn left_differential_inverse(&self, xi: &Vector6<T>) -> Result<Matrix6<T>, LieError> {
        Chart::<SE3<T>>::check_domain(self, xi)?;
        let (w, v) = split(xi);
        let a_inv = self.rotation_left_differential_inverse(&w);
        let m_inv = self.translation_map_inverse(&w);
        Ok(blocks(
            &a_inv,
            &Matrix3::zeros(),
            &(-m_inv * self.translation_map_derivative(&w, &v) * a_inv),
            &(m_inv * self.rotation_matrix(&w)),
        ))
    }

    /// `[[B_ω, 0], [N + x̂B_ω, M]]` with `x = M v`.
    fn right_differential(&self, xi: &Vector6<T>) -> Matrix6<T> {
        let (w, v) = split(xi);
        let m = self.translation_map(&w);
        let b = self.rotation_right_differential(&w);
        blocks(
            &b,
            &Matrix3::zeros(),
            &(self.translation_map_derivative(&w, &v) + hat(&(m * v)) * b),
            &m,
        )
    }

    /// `[[B_ω⁻¹, 0], [−M⁻¹(N + x̂B_ω)B_ω⁻¹, M⁻¹]]`.
    fn right_differential_inverse(&self, xi: &Vector6<T>) -> Result<Matrix6<T>, LieError> {
        Chart::<SE3<T>>::check_domain(self, xi)?;
        let (w, v) = split(xi);
        let m = self.translation_map(&w);
        let m_inv = self.translation_map_inverse(&w);
        let b = self.rotation_right_differential(&w);
        let b_inv = self.rotation_right_differential_inverse(&w);
        let lower = self.translation_map_derivative(&w, &v) + hat(&(m * v)) * b;
        Ok(blocks(
            &b_inv,
            &Matrix3::zeros(),
            &(-m_inv * lower * b_inv),
            &m_inv,
        ))
    }
}
