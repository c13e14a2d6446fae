//! The rotation group SO(3).
//!
//! # Overview
//! | | |
//! |---|---|
//! | tangent space | `ω ∈ ℝ³` (body angular velocity / rotation vector), `ω̂ ∈ so(3)` |
//! | internal parameters | a 3×3 rotation matrix `R` (row-major when printed) |
//! | action space | `ℝ³`, `p ↦ Rp` |
//! | matrix size | 3 × 3 |
//!
//! `R = world_from_body` maps body coordinates to world coordinates; body angular velocity
//! `Ω` satisfies `Ṙ = R Ω̂` with `hat(a, b, c) = [[0, −c, b], [c, 0, −a], [−b, a, 0]]`.
//!
//! # Group structure
//! Product and inverse are the matrix product and transpose; `Ad_R = R`; `ad_ω = ω̂`; the
//! coadjoint action sends body momentum `μ` to spatial momentum `Rμ`.

pub(crate) mod exp;
mod interop;
pub(crate) mod quaternion;

pub use exp::{left_jacobian, left_jacobian_inverse, right_jacobian, right_jacobian_inverse};

use crate::error::LieError;
use crate::group::{ExponentialMap, LieGroup};
use crate::scalar::real;
use nalgebra::{Matrix3, RealField, Unit, Vector3};
use std::ops::Mul;

/// Default tolerance of [`SO3::try_from_matrix`] on `‖RᵀR − I‖_F`: loose enough for
/// matrices printed with ten significant digits, tight enough to catch a wrong matrix.
pub const ORTHOGONALITY_TOLERANCE: f64 = 1e-9;

/// `ω ↦ ω̂`, the skew-symmetric matrix with `ω̂ v = ω × v`.
///
/// ```
/// use lgsvi_lie::so3::{hat, vee};
/// use nalgebra::Vector3;
/// let w = Vector3::new(1.0, 2.0, 3.0);
/// assert_eq!(hat(&w) * Vector3::new(4.0, 5.0, 6.0), w.cross(&Vector3::new(4.0, 5.0, 6.0)));
/// assert_eq!(vee(&hat(&w)), w);
/// ```
pub fn hat<T: RealField + Copy>(w: &Vector3<T>) -> Matrix3<T> {
    let z = T::zero();
    Matrix3::new(z, -w.z, w.y, w.z, z, -w.x, -w.y, w.x, z)
}

/// `I + α ω̂ + β ω̂²`, entry by entry (no matrix product): with `ω̂² = ωωᵀ − |ω|²I`, the
/// diagonal is `1 − β(ω_j² + ω_k²)`, free of cancellation. Every SO(3) map of this crate
/// (exp, the Cayley transforms, `J_r`, `J_l` and their inverses) has this form.
pub(crate) fn rodrigues_form<T: RealField + Copy>(w: &Vector3<T>, alpha: T, beta: T) -> Matrix3<T> {
    let one = T::one();
    let (x, y, z) = (w.x, w.y, w.z);
    let (xx, yy, zz) = (x * x, y * y, z * z);
    let (bxy, bxz, byz) = (beta * x * y, beta * x * z, beta * y * z);
    let (ax, ay, az) = (alpha * x, alpha * y, alpha * z);
    Matrix3::new(
        one - beta * (yy + zz),
        bxy - az,
        bxz + ay,
        bxy + az,
        one - beta * (xx + zz),
        byz - ax,
        bxz - ay,
        byz + ax,
        one - beta * (xx + yy),
    )
}

/// `ω̂ ↦ ω`, reading the entries below the diagonal (`(2,1), (0,2), (1,0)`).
pub fn vee<T: RealField + Copy>(m: &Matrix3<T>) -> Vector3<T> {
    Vector3::new(m[(2, 1)], m[(0, 2)], m[(1, 0)])
}

/// A rotation of ℝ³, stored as its 3×3 matrix `R = world_from_body`.
///
/// Generic over the scalar so that dual numbers (automatic differentiation) pass through;
/// `SO3` alone means `SO3<f64>`.
///
/// ```
/// use lgsvi_lie::{LieGroup, SO3};
/// use nalgebra::Vector3;
/// let world_from_body = SO3::exp(&Vector3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2));
/// let p_world = world_from_body.act(&Vector3::new(1.0, 0.0, 0.0));
/// assert!((p_world - Vector3::new(0.0, 1.0, 0.0)).norm() < 1e-15);
/// assert!((world_from_body.log().z - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SO3<T: RealField + Copy = f64> {
    matrix: Matrix3<T>,
}

impl<T: RealField + Copy> SO3<T> {
    /// The identity rotation (also [`LieGroup::identity`]).
    pub fn identity() -> Self {
        Self {
            matrix: Matrix3::identity(),
        }
    }

    /// Wraps a matrix the caller guarantees to be a rotation (orthogonal, determinant
    /// +1, to rounding). Nothing is checked; for user data use [`SO3::try_from_matrix`].
    pub fn from_matrix_unchecked(matrix: Matrix3<T>) -> Self {
        Self { matrix }
    }

    /// A rotation from a matrix, checked: finite, `‖RᵀR − I‖_F ≤`
    /// [`ORTHOGONALITY_TOLERANCE`], determinant positive.
    ///
    /// # Errors
    /// [`LieError::NonFinite`], [`LieError::NotOrthogonal`], [`LieError::NotProperRotation`].
    ///
    /// ```
    /// use lgsvi_lie::{LieError, SO3};
    /// use nalgebra::Matrix3;
    /// assert!(SO3::try_from_matrix(Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0)).is_ok());
    /// let reflection = Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, 1.0, -1.0));
    /// assert!(matches!(SO3::try_from_matrix(reflection), Err(LieError::NotProperRotation { .. })));
    /// assert!(matches!(SO3::try_from_matrix(Matrix3::identity() * 1.1), Err(LieError::NotOrthogonal { .. })));
    /// ```
    pub fn try_from_matrix(matrix: Matrix3<T>) -> Result<Self, LieError> {
        Self::try_from_matrix_with_tolerance(matrix, ORTHOGONALITY_TOLERANCE)
    }

    /// As [`SO3::try_from_matrix`] with a tolerance of your own on `‖RᵀR − I‖_F`.
    ///
    /// # Errors
    /// As [`SO3::try_from_matrix`].
    pub fn try_from_matrix_with_tolerance(
        matrix: Matrix3<T>,
        tolerance: f64,
    ) -> Result<Self, LieError> {
        if matrix.iter().any(|x| !real(*x).is_finite()) {
            return Err(LieError::NonFinite {
                what: "rotation matrix",
            });
        }
        let deviation = real((matrix.transpose() * matrix - Matrix3::identity()).norm());
        if deviation > tolerance {
            return Err(LieError::NotOrthogonal {
                deviation,
                tolerance,
            });
        }
        let determinant = real(matrix.determinant());
        if determinant <= 0.0 {
            return Err(LieError::NotProperRotation { determinant });
        }
        Ok(Self { matrix })
    }

    /// The rotation nearest (in the Frobenius norm) to a matrix that is only nearly one:
    /// the orthogonal factor `U Vᵀ` of its polar decomposition, from the SVD.
    ///
    /// # Errors
    /// [`LieError::NonFinite`]; [`LieError::NotProperRotation`] for a non-positive
    /// determinant (a reflection is not "nearly a rotation"); [`LieError::Degenerate`] when
    /// the second singular value vanishes (no unique nearest rotation).
    ///
    /// ```
    /// use lgsvi_lie::SO3;
    /// use nalgebra::Matrix3;
    /// let noisy = Matrix3::new(1.0, 1e-4, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.9999);
    /// let r = SO3::from_matrix_orthonormalized(noisy)?;
    /// assert!(r.orthogonality_error() < 1e-15);
    /// # Ok::<(), lgsvi_lie::LieError>(())
    /// ```
    pub fn from_matrix_orthonormalized(matrix: Matrix3<T>) -> Result<Self, LieError> {
        if matrix.iter().any(|x| !real(*x).is_finite()) {
            return Err(LieError::NonFinite {
                what: "rotation matrix",
            });
        }
        let determinant = real(matrix.determinant());
        if determinant <= 0.0 {
            return Err(LieError::NotProperRotation { determinant });
        }
        let svd = matrix.svd(true, true);
        let s = svd.singular_values;
        let mut sorted = [real(s[0]), real(s[1]), real(s[2])];
        sorted.sort_by(|a, b| b.total_cmp(a));
        if sorted[1] <= f64::EPSILON * sorted[0] {
            return Err(LieError::Degenerate {
                singular_values: sorted,
            });
        }
        let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
            return Err(LieError::Degenerate {
                singular_values: sorted,
            });
        };
        Ok(Self { matrix: u * v_t })
    }

    /// The exponential map (Rodrigues' formula): rotation by `|ω|` about `ω/|ω|`.
    /// Smooth at `ω = 0` (Taylor branch), valid for every `ω`.
    pub fn exp(w: &Vector3<T>) -> Self {
        Self {
            matrix: exp::exp_matrix(w),
        }
    }

    /// The logarithm: the rotation vector `ω` with `|ω| ∈ [0, π]` and `exp(ω) = self`.
    /// Computed through the unit quaternion (Shepperd's method), so it is accurate near
    /// `π`; at exactly `π` the sign of `ω` is not determined by the rotation and either is
    /// returned. The natural chart of the exponential map refuses that case
    /// ([`crate::ExpChart`]).
    pub fn log(&self) -> Vector3<T> {
        exp::log_matrix(&self.matrix)
    }

    /// Rotation by `angle` (radians, right-handed) about a unit `axis`.
    pub fn from_axis_angle(axis: &Unit<Vector3<T>>, angle: T) -> Self {
        Self::exp(&(axis.into_inner() * angle))
    }

    /// Rotation about the x axis.
    pub fn about_x(angle: T) -> Self {
        Self::exp(&Vector3::new(angle, T::zero(), T::zero()))
    }

    /// Rotation about the y axis.
    pub fn about_y(angle: T) -> Self {
        Self::exp(&Vector3::new(T::zero(), angle, T::zero()))
    }

    /// Rotation about the z axis.
    pub fn about_z(angle: T) -> Self {
        Self::exp(&Vector3::new(T::zero(), T::zero(), angle))
    }

    /// The rotation matrix.
    pub fn matrix(&self) -> &Matrix3<T> {
        &self.matrix
    }

    /// The rotation angle in `[0, π]`.
    pub fn angle(&self) -> T {
        self.log().norm()
    }

    /// `‖RᵀR − I‖_F`: how far the stored matrix has drifted from orthogonality (0 up to
    /// rounding for anything this crate builds).
    pub fn orthogonality_error(&self) -> T {
        (self.matrix.transpose() * self.matrix - Matrix3::identity()).norm()
    }

    /// The unit quaternion `(w, x, y, z)` (Hamilton convention, `w ≥ 0`) of the rotation,
    /// by Shepperd's method.
    pub fn quaternion_wxyz(&self) -> [T; 4] {
        let (w, v) = quaternion::from_matrix(&self.matrix);
        [w, v.x, v.y, v.z]
    }

    /// The rotation of a unit quaternion `(w, x, y, z)` (Hamilton convention), normalised
    /// first.
    ///
    /// # Errors
    /// [`LieError::NonFinite`] or [`LieError::ZeroQuaternion`].
    ///
    /// ```
    /// use lgsvi_lie::SO3;
    /// let half = std::f64::consts::FRAC_1_SQRT_2;
    /// let r = SO3::try_from_quaternion_wxyz([half, 0.0, 0.0, half])?; // 90° about z
    /// assert!((r.matrix()[(1, 0)] - 1.0).abs() < 1e-15);
    /// assert!(SO3::<f64>::try_from_quaternion_wxyz([0.0; 4]).is_err());
    /// // Scale does not matter, however large or small.
    /// let big = SO3::try_from_quaternion_wxyz([1e155, 0.0, 0.0, 1e155])?;
    /// let tiny = SO3::try_from_quaternion_wxyz([1e-170, 0.0, 0.0, 1e-170])?;
    /// assert!((big.matrix() - r.matrix()).norm() < 1e-15);
    /// assert!((tiny.matrix() - r.matrix()).norm() < 1e-15);
    /// # Ok::<(), lgsvi_lie::LieError>(())
    /// ```
    pub fn try_from_quaternion_wxyz(q: [T; 4]) -> Result<Self, LieError> {
        if q.iter().any(|x| !real(*x).is_finite()) {
            return Err(LieError::NonFinite { what: "quaternion" });
        }
        // Scaled by the largest component first, so that the sum of squares can neither
        // overflow (|q| ~ 1e155) nor underflow (|q| ~ 1e-160): any non-zero quaternion
        // gives its rotation.
        let largest = q.iter().fold(T::zero(), |m, x| m.max(x.abs()));
        if largest == T::zero() {
            return Err(LieError::ZeroQuaternion { norm: 0.0 });
        }
        let q = q.map(|x| x / largest);
        let norm = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
        let (w, v) = (q[0] / norm, Vector3::new(q[1], q[2], q[3]) / norm);
        Ok(Self {
            matrix: quaternion::to_matrix(w, &v),
        })
    }
}

impl<T: RealField + Copy> ExponentialMap for SO3<T> {
    fn exp(xi: &Self::Tangent) -> Self {
        SO3::exp(xi)
    }
    fn log(&self) -> Self::Tangent {
        SO3::log(self)
    }
}

impl<T: RealField + Copy> LieGroup for SO3<T> {
    type Scalar = T;
    type Tangent = Vector3<T>;
    type Jacobian = Matrix3<T>;
    type Point = Vector3<T>;
    type Matrix = Matrix3<T>;
    const DOF: usize = 3;
    const NAME: &'static str = "SO(3)";

    fn identity() -> Self {
        SO3::identity()
    }

    fn compose(&self, other: &Self) -> Self {
        Self {
            matrix: self.matrix * other.matrix,
        }
    }

    fn inverse(&self) -> Self {
        Self {
            matrix: self.matrix.transpose(),
        }
    }

    fn act(&self, point: &Vector3<T>) -> Vector3<T> {
        self.matrix * point
    }

    fn to_matrix(&self) -> Matrix3<T> {
        self.matrix
    }

    fn hat(xi: &Vector3<T>) -> Matrix3<T> {
        hat(xi)
    }

    fn vee(matrix: &Matrix3<T>) -> Vector3<T> {
        vee(matrix)
    }

    fn adjoint(&self) -> Matrix3<T> {
        self.matrix
    }

    fn small_adjoint(xi: &Vector3<T>) -> Matrix3<T> {
        hat(xi)
    }

    fn coadjoint_action(&self, mu: &Vector3<T>) -> Vector3<T> {
        self.matrix * mu
    }
}

impl<T: RealField + Copy> Mul for SO3<T> {
    type Output = Self;
    fn mul(self, rhs: Self) -> Self {
        self.compose(&rhs)
    }
}

impl<T: RealField + Copy> Mul<&SO3<T>> for &SO3<T> {
    type Output = SO3<T>;
    fn mul(self, rhs: &SO3<T>) -> SO3<T> {
        self.compose(rhs)
    }
}

impl<T: RealField + Copy> Mul<Vector3<T>> for SO3<T> {
    type Output = Vector3<T>;
    fn mul(self, rhs: Vector3<T>) -> Vector3<T> {
        self.matrix * rhs
    }
}

impl<T: RealField + Copy> Default for SO3<T> {
    fn default() -> Self {
        Self::identity()
    }
}
