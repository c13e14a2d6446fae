//! First-order dual numbers seeded along every coordinate, and the Jacobian read back:
//! the dual-number routes that stay as references beside the closed forms.

use nalgebra::{SMatrix, SVector};
use num_dual::DualSVec64;

/// `x` as `D` first-order dual numbers, one direction each.
pub(crate) fn seeded<const D: usize>(x: &SVector<f64, D>) -> SVector<DualSVec64<D>, D> {
    SVector::from_fn(|i, _| {
        DualSVec64::<D>::new(
            x[i],
            num_dual::Derivative::some(SVector::from_fn(|j, _| if i == j { 1.0 } else { 0.0 })),
        )
    })
}

/// The `D × D` matrix `∂y_r/∂x_a` of first-order dual numbers `y` seeded by [`seeded`].
pub(crate) fn jacobian_of<const D: usize>(y: &SVector<DualSVec64<D>, D>) -> SMatrix<f64, D, D> {
    SMatrix::from_fn(|r, a| {
        y[r].eps
            .unwrap_generic(nalgebra::Const::<D>, nalgebra::Const::<1>)[a]
    })
}
