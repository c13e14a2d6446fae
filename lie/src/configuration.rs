//! [`ConfigurationGroup`]: a Lie group over every scalar at once, with algebra `ℝ^D`, as
//! integrators and optimisers that differentiate through it use it; [`Rotations`] (SO(3))
//! and [`RigidMotions`] (SE(3)) implement it.

use crate::error::LieError;
use crate::group::LieGroup;
use crate::se3::{blocks, split, SE3};
use crate::so3::SO3;
use nalgebra::{Matrix3, RealField, SMatrix, SVector, Vector3};
use std::fmt::Debug;

/// A Lie group with algebra `ℝ^D`, over every scalar at once: a marker type whose
/// [`ConfigurationGroup::Element`] is the group's [`LieGroup`] over `f64` or a dual number.
/// It is what lgsvi's integrator (and anything that differentiates through a group by
/// changing the scalar) is generic over. Implemented by [`Rotations`] (SO(3)) and
/// [`RigidMotions`] (SE(3)); for a group of your own, implement it with its elements and a
/// [`GroupChart`](crate::GroupChart), and run [`crate::laws`] on both with your examples.
///
/// ```
/// use lgsvi_lie::{ConfigurationGroup, LieGroup, Rotations, SO3};
/// use nalgebra::Vector3;
///
/// let g = SO3::about_z(0.4);
/// // The same element over a dual number, and the exponential over any scalar.
/// let lifted = <Rotations as ConfigurationGroup<3>>::lift::<num_dual::Dual64>(&g);
/// assert_eq!(lifted.matrix()[(0, 0)].re, g.matrix()[(0, 0)]);
/// let turn = <Rotations as ConfigurationGroup<3>>::exp(&Vector3::new(0.0, 0.0, 0.4));
/// assert!((turn.matrix() - g.matrix()).amax() < 1e-15);
/// let angle = <Rotations as ConfigurationGroup<3>>::rotation_angle(&g.compose(&g));
/// assert!((angle - 0.8).abs() < 1e-15);
/// ```
pub trait ConfigurationGroup<const D: usize>:
    Copy + Debug + Default + Send + Sync + 'static
{
    /// The group element over a scalar (`f64`, or a dual number).
    type Element<T: RealField + Copy>: LieGroup<Scalar = T, Tangent = SVector<T, D>, Jacobian = SMatrix<T, D, D>>
        + Copy
        + Send
        + Sync;
    /// Name, for messages.
    const NAME: &'static str;
    /// What the initial body velocity `ξ₀` is called in messages ("initial angular
    /// velocity" on SO(3)).
    const INITIAL_VELOCITY: &'static str = "initial velocity";

    /// `g` over another scalar.
    fn lift<T: RealField + Copy>(g: &Self::Element<f64>) -> Self::Element<T>;
    /// The exponential map, for configuration variations `g exp(ζ)` (only its first two
    /// orders at `ζ = 0` matter).
    fn exp<T: RealField + Copy>(zeta: &SVector<T, D>) -> Self::Element<T>;
    /// `exp(ζ)` to second order, `I + ζ^ + ½(ζ^)²` in the matrix representation (not on
    /// the group beyond second order): what the derivatives of `ℓ(g exp(η), ξ)` at
    /// `η = 0` need, without the exponential's trigonometry. Defaults to
    /// [`ConfigurationGroup::exp`].
    fn exp_second_order<T: RealField + Copy>(zeta: &SVector<T, D>) -> Self::Element<T> {
        Self::exp(zeta)
    }
    /// The rotation angle of `g`'s rotational part (for the checks that a step stays in
    /// its chart). The default, `0`, is a group without one: no step is then refused for
    /// turning too far.
    fn rotation_angle(g: &Self::Element<f64>) -> f64 {
        let _ = g;
        0.0
    }
    /// The angular speed `|Ω|` of a body velocity (its rotational part), which bounds
    /// how far a step turns the body. The default, `0`, is a group without rotation.
    fn angular_speed(xi: &SVector<f64, D>) -> f64 {
        let _ = xi;
        0.0
    }
    /// `g` with the rounding of its products removed (one polar Newton step on a rotation
    /// block), so that millions of steps do not drift off the group. The default keeps `g`:
    /// a group whose elements cannot drift off it (angles, translations).
    fn renormalise(g: &Self::Element<f64>) -> Self::Element<f64> {
        *g
    }
    /// Whether every entry of `g` is finite.
    fn is_finite(g: &Self::Element<f64>) -> bool;
    /// Checks that `g` lies on the group to the group's tolerance (a starting state that
    /// does not would have its error dropped silently by the first step's
    /// renormalisation). The default accepts every element: a group whose elements
    /// cannot leave it.
    ///
    /// # Errors
    /// Why `g` is not on the group (for SO(3): [`LieError::NotOrthogonal`] beyond
    /// `‖RᵀR − I‖_F ≤ 1e-9`, [`LieError::NotProperRotation`] for a reflection).
    fn check_on_group(g: &Self::Element<f64>) -> Result<(), LieError> {
        let _ = g;
        Ok(())
    }
    /// The matrix of `η ↦ ad_ηᵀ p`: the coadjoint term of the Euler–Poincaré equations
    /// (`μ̇ = ad_ξᵀ μ + p`) and of the derivative of `Ad_{Φ(x)⁻¹}ᵀ p` in `x`. The default
    /// builds it from the element's [`LieGroup::small_adjoint`], one basis vector a column
    /// ([`coadjoint_generator_of`]); the built-in groups give it in closed form.
    fn coadjoint_generator(p: &SVector<f64, D>) -> SMatrix<f64, D, D> {
        coadjoint_generator_of::<Self::Element<f64>, D>(p)
    }
}

/// The matrix of `η ↦ ad_ηᵀ p` from a group's small adjoint: column `i` is
/// `ad_{e_i}ᵀ p` ([`ConfigurationGroup::coadjoint_generator`]'s default).
pub fn coadjoint_generator_of<E, const D: usize>(p: &SVector<f64, D>) -> SMatrix<f64, D, D>
where
    E: LieGroup<Scalar = f64, Tangent = SVector<f64, D>, Jacobian = SMatrix<f64, D, D>>,
{
    SMatrix::<f64, D, D>::from_fn(|row, column| {
        let basis = SVector::<f64, D>::from_fn(|i, _| if i == column { 1.0 } else { 0.0 });
        (E::small_adjoint(&basis).transpose() * p)[row]
    })
}

/// SO(3), `D = 3`, elements [`SO3`]: the rigid body's attitude.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Rotations;

/// SE(3), `D = 6`, elements [`SE3`] `(R, x)` with body velocities `(Ω, v)`, `ẋ = R v`:
/// a rigid body that rotates and translates.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RigidMotions;

/// `I + ω̂ + ½ω̂²`.
fn quadratic_rotation<T: RealField + Copy>(w: &Vector3<T>) -> Matrix3<T> {
    let half: T = nalgebra::convert(0.5);
    let w_hat = crate::so3::hat(w);
    Matrix3::identity() + w_hat + w_hat * w_hat * half
}

/// One polar Newton step `R(I + ½(I − RᵀR))`: squares the deviation from orthogonality.
fn polar_step(r: &Matrix3<f64>) -> Matrix3<f64> {
    let deviation = Matrix3::identity() - r.transpose() * r;
    r + r * deviation * 0.5
}

impl ConfigurationGroup<3> for Rotations {
    type Element<T: RealField + Copy> = SO3<T>;
    const NAME: &'static str = "SO(3)";
    const INITIAL_VELOCITY: &'static str = "initial angular velocity";

    fn lift<T: RealField + Copy>(g: &SO3) -> SO3<T> {
        SO3::from_matrix_unchecked(g.matrix().map(nalgebra::convert))
    }
    fn exp<T: RealField + Copy>(zeta: &Vector3<T>) -> SO3<T> {
        SO3::exp(zeta)
    }
    fn exp_second_order<T: RealField + Copy>(zeta: &Vector3<T>) -> SO3<T> {
        SO3::from_matrix_unchecked(quadratic_rotation(zeta))
    }
    fn rotation_angle(g: &SO3) -> f64 {
        g.angle()
    }
    fn angular_speed(xi: &Vector3<f64>) -> f64 {
        xi.norm()
    }
    fn renormalise(g: &SO3) -> SO3 {
        SO3::from_matrix_unchecked(polar_step(g.matrix()))
    }
    fn is_finite(g: &SO3) -> bool {
        g.matrix().iter().all(|x| x.is_finite())
    }
    fn check_on_group(g: &SO3) -> Result<(), LieError> {
        SO3::try_from_matrix(*g.matrix()).map(|_| ())
    }
    fn coadjoint_generator(p: &Vector3<f64>) -> Matrix3<f64> {
        crate::so3::hat(p)
    }
}

impl ConfigurationGroup<6> for RigidMotions {
    type Element<T: RealField + Copy> = SE3<T>;
    const NAME: &'static str = "SE(3)";
    const INITIAL_VELOCITY: &'static str = "initial velocity (Ω, v)";

    fn lift<T: RealField + Copy>(g: &SE3) -> SE3<T> {
        SE3::new(
            Rotations::lift(g.rotation()),
            g.translation().map(nalgebra::convert),
        )
    }
    fn exp<T: RealField + Copy>(zeta: &SVector<T, 6>) -> SE3<T> {
        SE3::exp(zeta)
    }
    /// `[[I + ω̂ + ½ω̂², (I + ½ω̂)u], [0, 1]]`.
    fn exp_second_order<T: RealField + Copy>(zeta: &SVector<T, 6>) -> SE3<T> {
        let w = Vector3::new(zeta[0], zeta[1], zeta[2]);
        let u = Vector3::new(zeta[3], zeta[4], zeta[5]);
        let half: T = nalgebra::convert(0.5);
        SE3::new(
            SO3::from_matrix_unchecked(quadratic_rotation(&w)),
            u + w.cross(&u) * half,
        )
    }
    fn rotation_angle(g: &SE3) -> f64 {
        g.rotation().angle()
    }
    fn angular_speed(xi: &SVector<f64, 6>) -> f64 {
        xi.fixed_rows::<3>(0).norm()
    }
    fn renormalise(g: &SE3) -> SE3 {
        SE3::new(Rotations::renormalise(g.rotation()), *g.translation())
    }
    fn is_finite(g: &SE3) -> bool {
        Rotations::is_finite(g.rotation()) && g.translation().iter().all(|x| x.is_finite())
    }
    fn check_on_group(g: &SE3) -> Result<(), LieError> {
        Rotations::check_on_group(g.rotation())
    }
    /// With `p = (p_ω, p_v)`: `ad_(ω,v)ᵀ p = (−ω̂ p_ω − v̂ p_v, −ω̂ p_v)`, i.e.
    /// `[[p̂_ω, p̂_v], [p̂_v, 0]]` applied to `(ω, v)`.
    fn coadjoint_generator(p: &SVector<f64, 6>) -> SMatrix<f64, 6, 6> {
        let (pw, pv) = split(p);
        let (pw, pv) = (crate::so3::hat(&pw), crate::so3::hat(&pv));
        blocks(&pw, &pv, &pv, &Matrix3::zeros())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default coadjoint generator, built from the small adjoint, is the closed form
    /// SO(3) and SE(3) give (`p̂`, and SE(3)'s blocks): exactly, the columns being sums of
    /// one or two products of `p`'s entries with ±1.
    #[test]
    fn the_default_coadjoint_generator_is_the_closed_form() {
        let p3 = Vector3::new(0.3, -1.7, 2.2);
        assert_eq!(
            coadjoint_generator_of::<SO3, 3>(&p3),
            Rotations::coadjoint_generator(&p3)
        );
        let p6 = SVector::<f64, 6>::new(0.3, -1.7, 2.2, -0.4, 0.9, 1.3);
        assert_eq!(
            coadjoint_generator_of::<SE3, 6>(&p6),
            RigidMotions::coadjoint_generator(&p6)
        );
    }
}
