//! A force's value and first derivatives at one point, [`ForceJet`]: what Newton's exact
//! matrix needs of a force, in closed form for the built-in forces and by first-order
//! dual numbers on the force alone otherwise.
//!
//! With `F(t, g, ξ)` the left-trivialised force, the jet holds `F`, `F_ξ = ∂F/∂ξ` and
//! `F_η = ∂F(t, g exp(η), ξ)/∂η` at `η = 0`. At a Gauss point `g = g_k Φ(x)`,
//! `ξ = A(x) v`, so (a node variation moves `g` by `exp(A δx)` to first order)
//! `∂F/∂x = F_η A + F_ξ ∂(A v)/∂x` and `∂F/∂v = F_ξ A`: the chart's part comes from the
//! chart's own derivatives (the integrator's point derivatives), the force's from this jet.

use crate::dual::{jacobian_of, seeded};
use crate::group::ConfigurationGroup;
use lgsvi_lie::LieGroup;
use nalgebra::{RealField, SMatrix, SVector};
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

/// A generalised force on a group (`crate::system`'s documentation): for SO(3) a body torque, for
/// SE(3) `(body torque, body force)`. Generic over the scalar, so Newton differentiates it
/// exactly; combine two with a tuple `(a, b)` (their sum).
pub trait Forcing<G: ConfigurationGroup<D>, const D: usize> {
    /// `F(t, g, ξ)`.
    fn force<T: RealField + Copy>(
        &self,
        time: f64,
        configuration: &G::Element<T>,
        velocity: &SVector<T, D>,
    ) -> SVector<T, D>;

    /// Whether the force is identically zero (then the step is the unforced one, bit for
    /// bit). The default `false` is always correct.
    fn is_zero(&self) -> bool {
        false
    }

    /// The force and its first derivatives at `(t, g, ξ)` ([`ForceJet`]), which Newton's
    /// exact matrix is built from. The default takes them by first-order dual numbers
    /// through [`Forcing::force`] alone (exact); the built-in forces give them in closed
    /// form.
    fn jet(
        &self,
        time: f64,
        configuration: &G::Element<f64>,
        velocity: &SVector<f64, D>,
    ) -> ForceJet<D>
    where
        Self: Sized,
    {
        ForceJet::by_dual_numbers(
            self,
            time,
            configuration,
            velocity,
            !self.depends_on_configuration(),
        )
    }

    /// Whether the force depends on the configuration `g`. The default `true` is always
    /// correct; `false` spares the integrator forming `g` at every Gauss point.
    fn depends_on_configuration(&self) -> bool {
        true
    }
}

impl<G: ConfigurationGroup<D>, A: Forcing<G, D>, B: Forcing<G, D>, const D: usize> Forcing<G, D>
    for (A, B)
{
    fn force<T: RealField + Copy>(
        &self,
        time: f64,
        g: &G::Element<T>,
        xi: &SVector<T, D>,
    ) -> SVector<T, D> {
        self.0.force(time, g, xi) + self.1.force(time, g, xi)
    }
    fn is_zero(&self) -> bool {
        self.0.is_zero() && self.1.is_zero()
    }
    fn jet(&self, time: f64, g: &G::Element<f64>, xi: &SVector<f64, D>) -> ForceJet<D> {
        self.0.jet(time, g, xi) + self.1.jet(time, g, xi)
    }
    fn depends_on_configuration(&self) -> bool {
        self.0.depends_on_configuration() || self.1.depends_on_configuration()
    }
}
