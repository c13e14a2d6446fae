//! A force's value and first derivatives at one point, [`ForceJet`]: what Newton's exact
//! matrix needs of a force, in closed form for the built-in forces and by first-order
//! dual numbers on the force alone otherwise.
//!
//! With `F(t, g, ξ)` the left-trivialised force, the jet holds `F`, `F_ξ = ∂F/∂ξ` and
//! `F_η = ∂F(t, g exp(η), ξ)/∂η` at `η = 0`. At a Gauss point `g = g_k Φ(x)`,
//! `ξ = A(x) v`, so (a node variation moves `g` by `exp(A δx)` to first order)
//! `∂F/∂x = F_η A + F_ξ ∂(A v)/∂x` and `∂F/∂v = F_ξ A`: the chart's part comes from the
//! chart's own derivatives (the integrator's point derivatives), the force's from this jet.

use crate::group::ConfigurationGroup;
use crate::system::Forcing;
use lgsvi_lie::LieGroup;
use nalgebra::{SMatrix, SVector};
use num_dual::DualSVec64;

/// A left-trivialised force and its first derivatives at one point `(t, g, ξ)`.
///
/// ```
/// use lgsvi_mechanics::{AngularDamping, Forcing, ForceJet, Rotations};
/// use lgsvi_mechanics::lie::SO3;
/// use nalgebra::{Matrix3, Vector3};
/// let jet = Forcing::<Rotations, 3>::jet(&AngularDamping(0.5), 0.0, &SO3::identity(), &Vector3::new(1.0, 0.0, 0.0));
/// assert_eq!(jet.value, Vector3::new(-0.5, 0.0, 0.0));
/// assert_eq!(jet.velocity, Matrix3::identity() * -0.5);
/// assert_eq!(jet.configuration, Matrix3::zeros());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceJet<const D: usize> {
    /// `F(t, g, ξ)`.
    pub value: SVector<f64, D>,
    /// `∂F/∂ξ`, entry `(component of F, component of ξ)`.
    pub velocity: SMatrix<f64, D, D>,
    /// `∂F(t, g exp(η), ξ)/∂η` at `η = 0`, entry `(component of F, component of η)`.
    pub configuration: SMatrix<f64, D, D>,
}

impl<const D: usize> ForceJet<D> {
    /// A force that depends on neither the configuration nor the velocity.
    pub fn constant(value: SVector<f64, D>) -> Self {
        Self {
            value,
            velocity: SMatrix::zeros(),
            configuration: SMatrix::zeros(),
        }
    }

    /// The jet of `f` at `(t, g, ξ)` by first-order dual numbers (`D` directions, one
    /// pass for `ξ` and, unless `velocity_only`, one for `η`).
    pub(crate) fn by_dual_numbers<G: ConfigurationGroup<D>, F: Forcing<G, D>>(
        f: &F,
        time: f64,
        configuration: &G::Element<f64>,
        velocity: &SVector<f64, D>,
        velocity_only: bool,
    ) -> Self {
        let g = G::lift::<DualSVec64<D>>(configuration);
        let by_velocity = f.force(time, &g, &seeded(velocity));
        let value = by_velocity.map(|d| d.re);
        let velocity_jacobian = jacobian_of(&by_velocity);
        let configuration_jacobian = if velocity_only {
            SMatrix::zeros()
        } else {
            // g exp(η) to first order is all a first derivative reads.
            let moved = g.compose(&G::exp_second_order(&seeded(&SVector::zeros())));
            jacobian_of(&f.force(time, &moved, &velocity.map(nalgebra::convert)))
        };
        Self {
            value,
            velocity: velocity_jacobian,
            configuration: configuration_jacobian,
        }
    }
}

impl<const D: usize> std::ops::Add for ForceJet<D> {
    type Output = Self;
    fn add(self, other: Self) -> Self {
        Self {
            value: self.value + other.value,
            velocity: self.velocity + other.velocity,
            configuration: self.configuration + other.configuration,
        }
    }
}

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
