//! Conversions of [`SE3`] to and from nalgebra (always), glam (feature `glam`) and serde
//! (feature `serde`), and the `approx` comparison traits.

use super::SE3;
use crate::so3::SO3;
use approx::{AbsDiffEq, RelativeEq, UlpsEq};
use nalgebra::{Isometry3, RealField, Translation3, UnitQuaternion};

impl<T: RealField + Copy> From<Isometry3<T>> for SE3<T> {
    fn from(iso: Isometry3<T>) -> Self {
        SE3::new(SO3::from(iso.rotation), iso.translation.vector)
    }
}

impl<T: RealField + Copy> From<SE3<T>> for Isometry3<T> {
    fn from(g: SE3<T>) -> Self {
        Isometry3::from_parts(
            Translation3::from(*g.translation()),
            UnitQuaternion::from(*g.rotation()),
        )
    }
}

impl<T: RealField + Copy> AbsDiffEq for SE3<T> {
    type Epsilon = T;
    fn default_epsilon() -> T {
        T::default_epsilon()
    }
    fn abs_diff_eq(&self, other: &Self, epsilon: T) -> bool {
        self.rotation().abs_diff_eq(other.rotation(), epsilon)
            && self.translation().abs_diff_eq(other.translation(), epsilon)
    }
}

impl<T: RealField + Copy> RelativeEq for SE3<T> {
    fn default_max_relative() -> T {
        T::default_max_relative()
    }
    fn relative_eq(&self, other: &Self, epsilon: T, max_relative: T) -> bool {
        self.rotation()
            .relative_eq(other.rotation(), epsilon, max_relative)
            && self
                .translation()
                .relative_eq(other.translation(), epsilon, max_relative)
    }
}

impl<T: RealField + Copy> UlpsEq for SE3<T> {
    fn default_max_ulps() -> u32 {
        T::default_max_ulps()
    }
    fn ulps_eq(&self, other: &Self, epsilon: T, max_ulps: u32) -> bool {
        self.rotation().ulps_eq(other.rotation(), epsilon, max_ulps)
            && self
                .translation()
                .ulps_eq(other.translation(), epsilon, max_ulps)
    }
}

#[cfg(feature = "glam")]
mod glam_interop {
    use super::SE3;
    use crate::error::LieError;
    use crate::so3::SO3;
    use glam::{DAffine3, DMat3};
    use nalgebra::Vector3;

    impl From<SE3<f64>> for DAffine3 {
        fn from(g: SE3<f64>) -> DAffine3 {
            let t = g.translation();
            DAffine3::from_mat3_translation(
                DMat3::from(*g.rotation()),
                glam::DVec3::new(t.x, t.y, t.z),
            )
        }
    }

    impl TryFrom<DAffine3> for SE3<f64> {
        type Error = LieError;
        /// The linear part must be a rotation (checked as [`SO3::try_from_matrix`]): an
        /// affine map with scale or shear is refused.
        fn try_from(a: DAffine3) -> Result<Self, LieError> {
            let rotation = SO3::try_from(a.matrix3)?;
            let t = a.translation;
            if !(t.x.is_finite() && t.y.is_finite() && t.z.is_finite()) {
                return Err(LieError::NonFinite {
                    what: "translation",
                });
            }
            Ok(SE3::new(rotation, Vector3::new(t.x, t.y, t.z)))
        }
    }
}

#[cfg(feature = "serde")]
mod serde_interop {
    use super::SE3;
    use crate::so3::SO3;
    use nalgebra::Vector3;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Repr {
        /// Row-major rotation matrix.
        rotation: SO3<f64>,
        translation: [f64; 3],
    }

    impl Serialize for SE3<f64> {
        /// As `{"rotation": [9 numbers, row-major], "translation": [x, y, z]}`.
        fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
            let t = self.translation();
            Repr {
                rotation: *self.rotation(),
                translation: [t.x, t.y, t.z],
            }
            .serialize(serializer)
        }
    }

    impl<'de> Deserialize<'de> for SE3<f64> {
        /// The rotation is checked as [`SO3::try_from_matrix`].
        fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
            let repr = Repr::deserialize(deserializer)?;
            if repr.translation.iter().any(|x| !x.is_finite()) {
                return Err(serde::de::Error::custom(
                    "translation holds a non-finite number",
                ));
            }
            Ok(SE3::new(repr.rotation, Vector3::from(repr.translation)))
        }
    }
}
