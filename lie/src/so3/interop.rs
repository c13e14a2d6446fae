//! Conversions of [`SO3`] to and from nalgebra (always), glam (feature `glam`) and serde
//! (feature `serde`), and the `approx` comparison traits.

use super::{quaternion, SO3};
use crate::error::LieError;
use approx::{AbsDiffEq, RelativeEq, UlpsEq};
use nalgebra::{Quaternion, RealField, Rotation3, UnitQuaternion, Vector3};

impl<T: RealField + Copy> From<Rotation3<T>> for SO3<T> {
    /// nalgebra's `Rotation3` is already a rotation: no check.
    fn from(r: Rotation3<T>) -> Self {
        SO3::from_matrix_unchecked(r.into_inner())
    }
}

impl<T: RealField + Copy> From<SO3<T>> for Rotation3<T> {
    fn from(r: SO3<T>) -> Self {
        Rotation3::from_matrix_unchecked(*r.matrix())
    }
}

impl<T: RealField + Copy> From<UnitQuaternion<T>> for SO3<T> {
    fn from(q: UnitQuaternion<T>) -> Self {
        SO3::from_matrix_unchecked(quaternion::to_matrix(q.w, &q.imag()))
    }
}

impl<T: RealField + Copy> From<SO3<T>> for UnitQuaternion<T> {
    /// Shepperd's method, scalar part `w ≥ 0`.
    fn from(r: SO3<T>) -> Self {
        let (w, v) = quaternion::from_matrix(r.matrix());
        UnitQuaternion::new_unchecked(Quaternion::from_parts(w, Vector3::new(v.x, v.y, v.z)))
    }
}

impl<T: RealField + Copy> AbsDiffEq for SO3<T> {
    type Epsilon = T;
    fn default_epsilon() -> T {
        T::default_epsilon()
    }
    fn abs_diff_eq(&self, other: &Self, epsilon: T) -> bool {
        self.matrix().abs_diff_eq(other.matrix(), epsilon)
    }
}

impl<T: RealField + Copy> RelativeEq for SO3<T> {
    fn default_max_relative() -> T {
        T::default_max_relative()
    }
    fn relative_eq(&self, other: &Self, epsilon: T, max_relative: T) -> bool {
        self.matrix()
            .relative_eq(other.matrix(), epsilon, max_relative)
    }
}

impl<T: RealField + Copy> UlpsEq for SO3<T> {
    fn default_max_ulps() -> u32 {
        T::default_max_ulps()
    }
    fn ulps_eq(&self, other: &Self, epsilon: T, max_ulps: u32) -> bool {
        self.matrix().ulps_eq(other.matrix(), epsilon, max_ulps)
    }
}

impl SO3<f64> {
    /// The matrix as 9 numbers, row-major (the crate's printed and serialised form).
    pub fn to_row_major(&self) -> [f64; 9] {
        let m = self.matrix();
        std::array::from_fn(|k| m[(k / 3, k % 3)])
    }

    /// A checked rotation from 9 numbers, row-major.
    ///
    /// # Errors
    /// As [`SO3::try_from_matrix`].
    ///
    /// ```
    /// use lgsvi_lie::SO3;
    /// let r = SO3::try_from_row_major([0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0])?;
    /// assert_eq!(r.to_row_major()[1], -1.0);
    /// # Ok::<(), lgsvi_lie::LieError>(())
    /// ```
    pub fn try_from_row_major(values: [f64; 9]) -> Result<Self, LieError> {
        SO3::try_from_matrix(nalgebra::Matrix3::from_row_slice(&values))
    }
}

#[cfg(feature = "glam")]
mod glam_interop {
    use super::SO3;
    use crate::error::LieError;
    use glam::{DMat3, DQuat, DVec3};
    use nalgebra::Matrix3;

    impl From<SO3<f64>> for DMat3 {
        fn from(r: SO3<f64>) -> DMat3 {
            let m = r.matrix();
            DMat3::from_cols(
                DVec3::new(m[(0, 0)], m[(1, 0)], m[(2, 0)]),
                DVec3::new(m[(0, 1)], m[(1, 1)], m[(2, 1)]),
                DVec3::new(m[(0, 2)], m[(1, 2)], m[(2, 2)]),
            )
        }
    }

    impl TryFrom<DMat3> for SO3<f64> {
        type Error = LieError;
        /// Checked as [`SO3::try_from_matrix`].
        fn try_from(m: DMat3) -> Result<Self, LieError> {
            SO3::try_from_matrix(Matrix3::from_column_slice(&m.to_cols_array()))
        }
    }

    impl From<SO3<f64>> for DQuat {
        fn from(r: SO3<f64>) -> DQuat {
            let [w, x, y, z] = r.quaternion_wxyz();
            DQuat::from_xyzw(x, y, z, w)
        }
    }

    impl TryFrom<DQuat> for SO3<f64> {
        type Error = LieError;
        /// Normalised first; a zero or non-finite quaternion is an error.
        fn try_from(q: DQuat) -> Result<Self, LieError> {
            SO3::try_from_quaternion_wxyz([q.w, q.x, q.y, q.z])
        }
    }
}

#[cfg(feature = "serde")]
mod serde_interop {
    use super::SO3;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    impl Serialize for SO3<f64> {
        /// As 9 numbers, row-major.
        fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
            self.to_row_major().serialize(serializer)
        }
    }

    impl<'de> Deserialize<'de> for SO3<f64> {
        /// From 9 numbers, row-major, checked as [`SO3::try_from_matrix`].
        fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
            let values = <[f64; 9]>::deserialize(deserializer)?;
            SO3::try_from_row_major(values).map_err(serde::de::Error::custom)
        }
    }
}
