//! Rotation matrix ↔ unit quaternion, Hamilton convention, scalar first.

use crate::scalar::constant;
use nalgebra::{Matrix3, RealField, Vector3};

/// Shepperd's method: take the square root of the largest of `4w², 4x², 4y², 4z²` (read
/// off the trace and the diagonal) and the other components from sums and differences of
/// off-diagonal pairs, so nothing is divided by a small number at any angle. Returns
/// `(w, (x, y, z))` with `w ≥ 0`.
pub(crate) fn from_matrix<T: RealField + Copy>(r: &Matrix3<T>) -> (T, Vector3<T>) {
    let (r00, r11, r22) = (r[(0, 0)], r[(1, 1)], r[(2, 2)]);
    let trace = r00 + r11 + r22;
    let one = T::one();
    let quarter = constant::<T>(0.25);
    // With the largest component c = √(1 ± r00 ± r11 ± r22)/2 ≥ ½, the others are
    // (sums or differences of off-diagonal pairs)/(4c).
    let (w, x, y, z);
    if trace >= r00 && trace >= r11 && trace >= r22 {
        let root = (one + trace).sqrt();
        let inv = quarter * constant::<T>(2.0) / root; // 1/(4w)
        w = root * constant::<T>(0.5);
        x = (r[(2, 1)] - r[(1, 2)]) * inv;
        y = (r[(0, 2)] - r[(2, 0)]) * inv;
        z = (r[(1, 0)] - r[(0, 1)]) * inv;
    } else if r00 >= r11 && r00 >= r22 {
        let root = (one + r00 - r11 - r22).sqrt();
        let inv = quarter * constant::<T>(2.0) / root; // 1/(4x)
        x = root * constant::<T>(0.5);
        w = (r[(2, 1)] - r[(1, 2)]) * inv;
        y = (r[(0, 1)] + r[(1, 0)]) * inv;
        z = (r[(0, 2)] + r[(2, 0)]) * inv;
    } else if r11 >= r22 {
        let root = (one - r00 + r11 - r22).sqrt();
        let inv = quarter * constant::<T>(2.0) / root; // 1/(4y)
        y = root * constant::<T>(0.5);
        w = (r[(0, 2)] - r[(2, 0)]) * inv;
        x = (r[(0, 1)] + r[(1, 0)]) * inv;
        z = (r[(1, 2)] + r[(2, 1)]) * inv;
    } else {
        let root = (one - r00 - r11 + r22).sqrt();
        let inv = quarter * constant::<T>(2.0) / root; // 1/(4z)
        z = root * constant::<T>(0.5);
        w = (r[(1, 0)] - r[(0, 1)]) * inv;
        x = (r[(0, 2)] + r[(2, 0)]) * inv;
        y = (r[(1, 2)] + r[(2, 1)]) * inv;
    }
    let v = Vector3::new(x, y, z);
    if w < T::zero() {
        (-w, -v)
    } else {
        (w, v)
    }
}

/// The rotation matrix of the unit quaternion `(w, v)`.
pub(crate) fn to_matrix<T: RealField + Copy>(w: T, v: &Vector3<T>) -> Matrix3<T> {
    // R = (w² − |v|²) I + 2 v vᵀ + 2 w v̂
    let two = constant::<T>(2.0);
    Matrix3::identity() * (w * w - v.norm_squared())
        + v * v.transpose() * two
        + super::hat(v) * (two * w)
}
