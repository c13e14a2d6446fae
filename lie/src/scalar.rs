//! Small helpers for code generic over the scalar type (`f64` or a dual number).

use nalgebra::RealField;

/// The scalar `x` as a `T` (a dual number gets zero derivative parts).
#[inline(always)]
pub(crate) fn constant<T: RealField + Copy>(x: f64) -> T {
    nalgebra::convert(x)
}

/// The real part of `x` as an `f64`: used for branch decisions (small-angle series,
/// domain checks) and error messages, never for values.
#[inline(always)]
pub(crate) fn real<T: RealField + Copy>(x: T) -> f64 {
    x.to_subset_unchecked()
}
