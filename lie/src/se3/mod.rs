//! The rigid motions SE(3) = SO(3) ⋉ ℝ³.
//!
//! # Overview
//! | | |
//! |---|---|
//! | tangent space | `ξ = (ω, v) ∈ ℝ⁶`, **rotation first**: body angular velocity `ω`, body linear velocity `v` |
//! | internal parameters | rotation `R` (3×3) and translation `x` (3) |
//! | action space | `ℝ³`, `p ↦ Rp + x` |
//! | matrix size | 4 × 4 homogeneous, `[[R, x], [0, 1]]` |
//!
//! `(R, x) = world_from_body`; a motion with body velocity `(ω, v)` has `Ṙ = R ω̂`,
//! `ẋ = R v`; `ξ^ = [[ω̂, v], [0, 0]]`.
//!
//! # Group structure
//! `(R₁, x₁)(R₂, x₂) = (R₁R₂, R₁x₂ + x₁)`, `(R, x)⁻¹ = (Rᵀ, −Rᵀx)`,
//! `Ad = [[R, 0], [x̂R, R]]`, `ad_(ω,v) = [[ω̂, 0], [v̂, ω̂]]`.

mod interop;

use crate::error::LieError;
use crate::group::{ExponentialMap, LieGroup};
use crate::so3::{hat, vee, SO3};
use nalgebra::{Matrix3, Matrix4, Matrix6, RealField, Vector3, Vector6};
use std::ops::Mul;

/// A rigid motion `(R, x) = world_from_body`, tangent ordered `(ω, v)`.
///
/// ```
/// use lgsvi_lie::{LieGroup, SE3, SO3};
/// use nalgebra::Vector3;
/// let world_from_body = SE3::new(SO3::about_z(std::f64::consts::FRAC_PI_2), Vector3::new(1.0, 0.0, 0.0));
/// let p = world_from_body.act(&Vector3::new(1.0, 0.0, 0.0));
/// assert!((p - Vector3::new(1.0, 1.0, 0.0)).norm() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SE3<T: RealField + Copy = f64> {
    rotation: SO3<T>,
    translation: Vector3<T>,
}

impl<T: RealField + Copy> SE3<T> {
    /// The identity motion (also [`LieGroup::identity`]).
    pub fn identity() -> Self {
        Self::new(SO3::identity(), Vector3::zeros())
    }

    /// The motion with rotation `R` and translation `x`.
    pub fn new(rotation: SO3<T>, translation: Vector3<T>) -> Self {
        Self {
            rotation,
            translation,
        }
    }

    /// A checked motion from a homogeneous 4×4 matrix: the rotation block as
    /// [`SO3::try_from_matrix`], the last row exactly `(0, 0, 0, 1)`.
    ///
    /// # Errors
    /// [`LieError::NonFinite`], [`LieError::NotOrthogonal`] (also for a wrong last row),
    /// [`LieError::NotProperRotation`].
    pub fn try_from_matrix(m: Matrix4<T>) -> Result<Self, LieError> {
        if m.iter().any(|x| !crate::scalar::real(*x).is_finite()) {
            return Err(LieError::NonFinite {
                what: "homogeneous matrix",
            });
        }
        let last = [m[(3, 0)], m[(3, 1)], m[(3, 2)], m[(3, 3)] - T::one()];
        let deviation = last
            .iter()
            .map(|x| crate::scalar::real(*x).abs())
            .fold(0.0, f64::max);
        if deviation != 0.0 {
            return Err(LieError::NotOrthogonal {
                deviation,
                tolerance: 0.0,
            });
        }
        let rotation = SO3::try_from_matrix(m.fixed_view::<3, 3>(0, 0).into_owned())?;
        Ok(Self::new(rotation, m.fixed_view::<3, 1>(0, 3).into_owned()))
    }

    /// The rotation part.
    pub fn rotation(&self) -> &SO3<T> {
        &self.rotation
    }

    /// The translation part.
    pub fn translation(&self) -> &Vector3<T> {
        &self.translation
    }

    /// The exponential map: `exp(ω, v) = (exp ω, J_l(ω) v)` (the `ExpChart` on SE(3)).
    pub fn exp(xi: &Vector6<T>) -> Self {
        let (w, v) = split(xi);
        Self::new(SO3::exp(&w), crate::so3::left_jacobian(&w) * v)
    }

    /// The logarithm `(ω, J_l(ω)⁻¹ x)` with `ω = log R`, `|ω| ≤ π`. At a rotation angle of
    /// exactly `π` the sign of `ω` is arbitrary (see [`SO3::log`]).
    pub fn log(&self) -> Vector6<T> {
        let w = self.rotation.log();
        // |ω| ≤ π < 2π: J_l(ω) = J_r(−ω) is invertible.
        let v = crate::so3::exp::right_jacobian_inverse_unchecked(&(-w)) * self.translation;
        join(&w, &v)
    }
}

/// Splits a tangent `(ω, v)` into its rotational and translational parts.
///
/// ```
/// use lgsvi_lie::se3::{join, split};
/// use nalgebra::{Vector3, Vector6};
/// let xi = Vector6::new(1.0, 2.0, 3.0, 4.0, 5.0, 6.0);
/// let (w, v) = split(&xi);
/// assert_eq!((w, v), (Vector3::new(1.0, 2.0, 3.0), Vector3::new(4.0, 5.0, 6.0)));
/// assert_eq!(join(&w, &v), xi);
/// ```
pub fn split<T: RealField + Copy>(xi: &Vector6<T>) -> (Vector3<T>, Vector3<T>) {
    (
        xi.fixed_rows::<3>(0).into_owned(),
        xi.fixed_rows::<3>(3).into_owned(),
    )
}

/// Builds a tangent `(ω, v)` from its parts ([`split`] inverts it).
pub fn join<T: RealField + Copy>(w: &Vector3<T>, v: &Vector3<T>) -> Vector6<T> {
    Vector6::new(w.x, w.y, w.z, v.x, v.y, v.z)
}

/// The 6×6 block matrix `[[a, b], [c, d]]` of four 3×3 blocks (rows and columns ordered
/// `(ω, v)`, as the tangent).
///
/// ```
/// use lgsvi_lie::se3::blocks;
/// use nalgebra::Matrix3;
/// let (i, z) = (Matrix3::<f64>::identity(), Matrix3::zeros());
/// let m = blocks(&i, &z, &(i * 2.0), &i);
/// assert_eq!((m[(0, 0)], m[(3, 0)], m[(0, 3)]), (1.0, 2.0, 0.0));
/// ```
pub fn blocks<T: RealField + Copy>(
    a: &Matrix3<T>,
    b: &Matrix3<T>,
    c: &Matrix3<T>,
    d: &Matrix3<T>,
) -> Matrix6<T> {
    let mut m = Matrix6::zeros();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(a);
    m.fixed_view_mut::<3, 3>(0, 3).copy_from(b);
    m.fixed_view_mut::<3, 3>(3, 0).copy_from(c);
    m.fixed_view_mut::<3, 3>(3, 3).copy_from(d);
    m
}

impl<T: RealField + Copy> ExponentialMap for SE3<T> {
    fn exp(xi: &Self::Tangent) -> Self {
        SE3::exp(xi)
    }
    fn log(&self) -> Self::Tangent {
        SE3::log(self)
    }
}

impl<T: RealField + Copy> LieGroup for SE3<T> {
    type Scalar = T;
    type Tangent = Vector6<T>;
    type Jacobian = Matrix6<T>;
    type Point = Vector3<T>;
    type Matrix = Matrix4<T>;
    const DOF: usize = 6;
    const NAME: &'static str = "SE(3)";

    fn identity() -> Self {
        SE3::identity()
    }

    fn compose(&self, other: &Self) -> Self {
        Self::new(
            self.rotation.compose(&other.rotation),
            self.rotation.act(&other.translation) + self.translation,
        )
    }

    fn inverse(&self) -> Self {
        let r_inv = self.rotation.inverse();
        Self::new(r_inv, -r_inv.act(&self.translation))
    }

    fn act(&self, point: &Vector3<T>) -> Vector3<T> {
        self.rotation.act(point) + self.translation
    }

    fn to_matrix(&self) -> Matrix4<T> {
        let mut m = Matrix4::identity();
        m.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(self.rotation.matrix());
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&self.translation);
        m
    }

    fn hat(xi: &Vector6<T>) -> Matrix4<T> {
        let (w, v) = split(xi);
        let mut m = Matrix4::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&hat(&w));
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&v);
        m
    }

    fn vee(matrix: &Matrix4<T>) -> Vector6<T> {
        let w = vee(&matrix.fixed_view::<3, 3>(0, 0).into_owned());
        let v = matrix.fixed_view::<3, 1>(0, 3).into_owned();
        join(&w, &v)
    }

    fn adjoint(&self) -> Matrix6<T> {
        let r = *self.rotation.matrix();
        blocks(&r, &Matrix3::zeros(), &(hat(&self.translation) * r), &r)
    }

    fn small_adjoint(xi: &Vector6<T>) -> Matrix6<T> {
        let (w, v) = split(xi);
        let w_hat = hat(&w);
        blocks(&w_hat, &Matrix3::zeros(), &hat(&v), &w_hat)
    }

    fn coadjoint_action(&self, mu: &Vector6<T>) -> Vector6<T> {
        self.inverse().adjoint().transpose() * mu
    }
}

impl<T: RealField + Copy> Mul for SE3<T> {
    type Output = Self;
    fn mul(self, rhs: Self) -> Self {
        self.compose(&rhs)
    }
}

impl<T: RealField + Copy> Mul<&SE3<T>> for &SE3<T> {
    type Output = SE3<T>;
    fn mul(self, rhs: &SE3<T>) -> SE3<T> {
        self.compose(rhs)
    }
}

impl<T: RealField + Copy> Mul<Vector3<T>> for SE3<T> {
    type Output = Vector3<T>;
    fn mul(self, rhs: Vector3<T>) -> Vector3<T> {
        self.act(&rhs)
    }
}

impl<T: RealField + Copy> Default for SE3<T> {
    fn default() -> Self {
        Self::identity()
    }
}
