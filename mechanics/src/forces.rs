//! Forces and control inputs, by the discrete Lagrange–d'Alembert principle.
//!
//! A left-trivialised generalised force `F(t, g, ξ) ∈ ℝ^D` (for SO(3) a body-frame torque;
//! for SE(3) a body-frame torque and a body-frame force, `(τ, Rᵀf)`) enters a step through
//! the virtual work of the variation `δg = g η^`, integrated by the step's own quadrature:
//! `δS + Σ_j h b_j ⟨F_j, η_j⟩ = 0`. On the curve `g(t) = g_k Φ(ξ(t))` a node variation
//! gives `η_j = A(x_j) δx_j`, so each Gauss point adds `A(x_j)ᵀ F_j` to the `x`-gradient of
//! its term, and moving the base point (the exact momentum matching) adds `F_j` to the
//! configuration force `p_j`: `μ_{k+1} = Ad_{Φ(ξⁿ)}ᵀ (μ_k + Σ_j h b_j Ad_{Φ(x_j)⁻¹}ᵀ (p_j + F_j))`.
//! These are the discrete forces `F_d^±` of Marsden and West's forced discrete
//! Euler–Lagrange equations for this discrete Lagrangian, so the energy balance
//! `E(T) − E(0) = ∫ ⟨F, ξ⟩ dt` holds to the method's order. With no force the step is the
//! unforced one, bit for bit (the force terms are skipped, not added as zeros).
//!
//! A force is added to a system with [`crate::Forced`]`::new(system, force)`: the built-in
//! ones ([`BodyTorque`], [`AngularDamping`], [`SpaceForce`], [`ForceOfTime`]), a tuple of two
//! (their sum), or a [`Forcing`] of your own, written once generically over the scalar so
//! that Newton differentiates it exactly. A control input set between steps
//! ([`crate::Integrator::set_input`]) is a force held over the step.
//!
//! Newton's exact matrix needs a force's value and first derivatives at each Gauss point,
//! its [`ForceJet`]: in closed form for the built-in forces and by first-order dual
//! numbers on the force alone otherwise. With `F(t, g, ξ)` the left-trivialised force, the
//! jet holds `F`, `F_ξ = ∂F/∂ξ` and `F_η = ∂F(t, g exp(η), ξ)/∂η` at `η = 0`. At a Gauss
//! point `g = g_k Φ(x)`, `ξ = A(x) v`, so (a node variation moves `g` by `exp(A δx)` to
//! first order) `∂F/∂x = F_η A + F_ξ ∂(A v)/∂x` and `∂F/∂v = F_ξ A`: the chart's part comes
//! from the chart's own derivatives (the integrator's point derivatives), the force's from
//! this jet.

use crate::error::MechanicsError;
use crate::group::{RigidMotions, Rotations, StepGroup};
use lgsvi_lie::jet::{jacobian_of, seeded};
use lgsvi_lie::se3::{blocks, join, split};
use lgsvi_lie::{LieGroup, SE3, SO3};
use nalgebra::{Matrix3, RealField, SMatrix, SVector, Vector3};
use num_dual::DualSVec64;

/// A left-trivialised force and its first derivatives at one point `(t, g, ξ)`.
///
/// ```
/// use lgsvi_mechanics::forces::{AngularDamping, Forcing};
/// use lgsvi_mechanics::group::Rotations;
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
    pub(crate) fn by_dual_numbers<G: StepGroup<D>, F: Forcing<G, D>>(
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

/// A generalised force on a group (module documentation): for SO(3) a body torque, for
/// SE(3) `(body torque, body force)`. Generic over the scalar, so Newton differentiates it
/// exactly; combine two with a tuple `(a, b)` (their sum).
pub trait Forcing<G: StepGroup<D>, const D: usize> {
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

    /// The size of the terms the force is formed from, where they can be far larger than
    /// the force: a force formed as a small difference of order-one quantities (a spring's
    /// `θ = log(R_targetᵀ R)` near its target) carries their rounding, about `ε` times this,
    /// whatever its own size. The step's tests of its residual (Newton's stopping test,
    /// the predictor's, the reuse of factored matrices) count it among the equations'
    /// terms, so that a step at rest on the target is accepted at that rounding floor. The
    /// default 0 suits a force whose rounding is relative to its value.
    fn rounding_scale(&self) -> f64 {
        0.0
    }
}

impl<G: StepGroup<D>, A: Forcing<G, D>, B: Forcing<G, D>, const D: usize> Forcing<G, D> for (A, B) {
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
    /// The sum of the two jets; a part that [`Forcing::is_zero`] is skipped (a drive with
    /// its damping but not its spring pays for the damping alone).
    fn jet(&self, time: f64, g: &G::Element<f64>, xi: &SVector<f64, D>) -> ForceJet<D> {
        match (self.0.is_zero(), self.1.is_zero()) {
            (false, true) => self.0.jet(time, g, xi),
            (true, false) => self.1.jet(time, g, xi),
            _ => self.0.jet(time, g, xi) + self.1.jet(time, g, xi),
        }
    }
    fn depends_on_configuration(&self) -> bool {
        self.0.depends_on_configuration() || self.1.depends_on_configuration()
    }
    fn rounding_scale(&self) -> f64 {
        self.0.rounding_scale().max(self.1.rounding_scale())
    }
}

/// A generalised force given as a closure of time alone, `t ↦ F(t)` (for SO(3) a body
/// torque, for SE(3) `(body torque, body force)`), on any group: a feed-forward profile or
/// a disturbance. Exact in Newton (it does not depend on the state); for a force that
/// depends on the state, implement [`Forcing`] (generic over the scalar) instead.
///
/// ```
/// use lgsvi_mechanics::Stepper;
/// use lgsvi_mechanics::{Forced, Inertia, Integrator, RigidBody, StepSettings};
/// use lgsvi_mechanics::forces::ForceOfTime;
/// use lgsvi_mechanics::lie::SO3;
/// use nalgebra::Vector3;
/// // A torque pulse about z for the first second spins a sphere up to Ω_z = τ t / J.
/// let pulse = ForceOfTime(|t: f64| Vector3::new(0.0, 0.0, if t < 1.0 { 0.2 } else { 0.0 }));
/// let body = RigidBody::new(Inertia::from_principal_moments([2.0, 2.0, 2.0])?);
/// let mut it = Integrator::new(Forced::new(body, pulse), StepSettings::new(0.25, 6)?, SO3::identity(), Vector3::zeros())?;
/// it.run(8, 1)?;
/// assert!((it.state().velocity.z - 0.1).abs() < 1e-14);
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub struct ForceOfTime<F>(pub F);

impl<G: StepGroup<D>, F: Fn(f64) -> SVector<f64, D>, const D: usize> Forcing<G, D>
    for ForceOfTime<F>
{
    fn force<T: RealField + Copy>(
        &self,
        time: f64,
        _g: &G::Element<T>,
        _xi: &SVector<T, D>,
    ) -> SVector<T, D> {
        (self.0)(time).map(nalgebra::convert)
    }
    fn jet(&self, time: f64, _g: &G::Element<f64>, _xi: &SVector<f64, D>) -> ForceJet<D> {
        ForceJet::constant((self.0)(time))
    }
    fn depends_on_configuration(&self) -> bool {
        false
    }
}

/// A constant body-frame torque `τ` (N·m), on SO(3) and SE(3).
///
/// ```
/// use lgsvi_mechanics::Stepper;
/// use lgsvi_mechanics::{Forced, Inertia, Integrator, RigidBody, StepSettings};
/// use lgsvi_mechanics::forces::BodyTorque;
/// use lgsvi_mechanics::lie::SO3;
/// use nalgebra::Vector3;
/// // A body at rest spun up about its z axis by τ = 0.1 for 1 s: Ω_z = τ/J_z t.
/// let body = Forced::new(
///     RigidBody::new(Inertia::from_principal_moments([1.0, 1.0, 2.0])?),
///     BodyTorque(Vector3::new(0.0, 0.0, 0.1)),
/// );
/// let mut integrator = Integrator::new(body, StepSettings::new(0.25, 6)?, SO3::identity(), Vector3::zeros())?;
/// integrator.run(4, 1)?;
/// assert!((integrator.state().velocity.z - 0.05).abs() < 1e-14);
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyTorque(pub Vector3<f64>);

/// Damping `τ = −c Ω` of the angular velocity (`c ≥ 0`, N·m·s), on SO(3) and SE(3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AngularDamping(pub f64);

/// A torsion spring toward a target attitude: the body torque `τ = −k θ`, `θ =
/// log(R_targetᵀ R)` the rotation vector (body frame) that turns the target into the body
/// (N·m per radian, `k ≥ 0`), on SO(3) and SE(3). It is conservative: `τ` is minus the
/// left-trivialised gradient of `V(R) = ½ k |θ|²` (the gradient is `J_r(θ)⁻ᵀ k θ = k θ`,
/// as `θ̂ θ = 0`), so `E + V` is conserved on its own.
///
/// With [`AngularDamping`] `c` beside it, `−k θ − c Ω` is the proportional–derivative
/// attitude law (rotation-vector feedback) of a regulator holding the target: a
/// continuous law, integrated to the method's order, not a sampled one. `|θ| ≤ π`; the law
/// jumps where the body is turned by π from the target (either sign of `θ`), so start a
/// run within a half-turn of the target.
///
/// ```
/// use lgsvi_mechanics::prelude::*;
/// use lgsvi_mechanics::forces::AttitudeSpring;
/// // A sphere turned 0.5 rad about x from the target, at rest: with k = 2, c = 1 and
/// // J = 1 its angle obeys θ'' + θ' + 2θ = 0, θ(t) = 0.5 e^(−t/2) (cos βt + sin βt/(2β)),
/// // β = √7/2.
/// let spring = AttitudeSpring::new(SO3::identity(), 2.0)?;
/// let body = Forced::new(RigidBody::new(Inertia::from_principal_moments([1.0, 1.0, 1.0])?),
///                        (spring, AngularDamping(1.0)));
/// let start = SO3::exp(&Vector3::new(0.5, 0.0, 0.0));
/// let mut it = Integrator::new(body, StepSettings::new(0.25, 12)?, start, Vector3::zeros())?;
/// it.run(16, 1)?;
/// let b = 7f64.sqrt() / 2.0;
/// let exact = 0.5 * (-2.0f64).exp() * ((4.0 * b).cos() + (4.0 * b).sin() / (2.0 * b));
/// assert!((it.state().attitude().log().x - exact).abs() < 1e-12);
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AttitudeSpring {
    target: SO3,
    stiffness: f64,
}

impl AttitudeSpring {
    /// The spring of stiffness `k` toward `target` (`R_target`, world from body).
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for a stiffness that is negative or not finite;
    /// [`MechanicsError::NonFinite`] for a target with an entry that is not finite.
    pub fn new(target: SO3, stiffness: f64) -> Result<Self, MechanicsError> {
        if !(stiffness.is_finite() && stiffness >= 0.0) {
            return Err(MechanicsError::InvalidSetting {
                name: "stiffness",
                value: format!("{stiffness:?}"),
                reason: "a spring's stiffness (the proportional gain) is finite and \
                         non-negative",
            });
        }
        if target.matrix().iter().any(|x| !x.is_finite()) {
            return Err(MechanicsError::NonFinite {
                what: "target attitude",
                value: format!("{:?}", target.matrix().as_slice()),
            });
        }
        Ok(Self { target, stiffness })
    }

    /// No spring: stiffness 0 toward the identity (the unforced step, bit for bit).
    pub fn none() -> Self {
        Self {
            target: SO3::identity(),
            stiffness: 0.0,
        }
    }

    /// The target attitude.
    pub fn target(&self) -> &SO3 {
        &self.target
    }

    /// The stiffness `k`.
    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// `θ = log(R_targetᵀ R)`, the rotation vector from the target to `attitude` (generic
    /// over the scalar, as the torque is formed).
    pub fn error<T: RealField + Copy>(&self, attitude: &SO3<T>) -> Vector3<T> {
        let target = self.target.matrix().map(nalgebra::convert::<f64, T>);
        SO3::from_matrix_unchecked(target.transpose() * attitude.matrix()).log()
    }

    /// The spring's potential energy `½ k |θ|²` at `attitude`.
    pub fn potential(&self, attitude: &SO3) -> f64 {
        0.5 * self.stiffness * self.error(attitude).norm_squared()
    }

    /// `−k θ` at `g`, generic over the scalar (out of line: the zero spring's test in
    /// [`Forcing::force`] is all a drive without a spring pays at each evaluation).
    #[inline(never)]
    pub(crate) fn torque<T: RealField + Copy>(&self, g: &SO3<T>) -> Vector3<T> {
        self.error(g) * nalgebra::convert::<f64, T>(-self.stiffness)
    }

    /// [`Forcing::jet`] of a spring of non-zero stiffness: `θ(R exp(η)) = θ + J_r(θ)⁻¹ η +
    /// O(η²)`, so the configuration derivative is `−k J_r(θ)⁻¹` (`|θ| ≤ π`, inside `J_r`'s
    /// domain).
    #[inline(never)]
    fn spring_jet(&self, g: &SO3) -> ForceJet<3> {
        let theta = self.error(g);
        let inverse = lgsvi_lie::so3::right_jacobian_inverse(&theta)
            .unwrap_or_else(|_| Matrix3::from_element(f64::NAN));
        ForceJet {
            value: theta * -self.stiffness,
            velocity: Matrix3::zeros(),
            configuration: inverse * -self.stiffness,
        }
    }
}

impl Forcing<Rotations, 3> for AttitudeSpring {
    #[inline]
    fn force<T: RealField + Copy>(&self, _t: f64, g: &SO3<T>, _w: &Vector3<T>) -> Vector3<T> {
        if self.stiffness == 0.0 {
            return Vector3::zeros();
        }
        self.torque(g)
    }
    fn is_zero(&self) -> bool {
        self.stiffness == 0.0
    }
    /// `−k θ` with the configuration derivative `−k J_r(θ)⁻¹`, in closed form; zero for
    /// stiffness 0.
    #[inline]
    fn jet(&self, _t: f64, g: &SO3, _w: &Vector3<f64>) -> ForceJet<3> {
        if self.stiffness == 0.0 {
            return ForceJet::constant(Vector3::zeros());
        }
        self.spring_jet(g)
    }
    /// A spring of stiffness 0 (beside a damping, say) spares the integrator forming the
    /// configuration at every Gauss point.
    fn depends_on_configuration(&self) -> bool {
        self.stiffness != 0.0
    }
    /// `k` (N·m per radian times one radian): `θ` comes from the entries of `R_targetᵀ R`,
    /// of order one, with their rounding, so `−k θ` carries `~ε k` at any `|θ|`.
    fn rounding_scale(&self) -> f64 {
        self.stiffness
    }
}

/// A constant space-frame force `f` (N) on an SE(3) body's centre of mass: body force
/// `Rᵀ f`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpaceForce(pub Vector3<f64>);

fn convert3<T: RealField + Copy>(v: &Vector3<f64>) -> Vector3<T> {
    v.map(nalgebra::convert)
}

impl Forcing<Rotations, 3> for BodyTorque {
    fn force<T: RealField + Copy>(&self, _t: f64, _g: &SO3<T>, _w: &Vector3<T>) -> Vector3<T> {
        convert3(&self.0)
    }
    fn is_zero(&self) -> bool {
        self.0 == Vector3::zeros()
    }
    fn jet(&self, _t: f64, _g: &SO3, _w: &Vector3<f64>) -> ForceJet<3> {
        ForceJet::constant(self.0)
    }
    fn depends_on_configuration(&self) -> bool {
        false
    }
}

impl Forcing<Rotations, 3> for AngularDamping {
    fn force<T: RealField + Copy>(&self, _t: f64, _g: &SO3<T>, w: &Vector3<T>) -> Vector3<T> {
        w * nalgebra::convert::<f64, T>(-self.0)
    }
    fn is_zero(&self) -> bool {
        self.0 == 0.0
    }
    fn jet(&self, _t: f64, _g: &SO3, w: &Vector3<f64>) -> ForceJet<3> {
        ForceJet {
            value: w * -self.0,
            velocity: Matrix3::identity() * -self.0,
            configuration: Matrix3::zeros(),
        }
    }
    fn depends_on_configuration(&self) -> bool {
        false
    }
}

/// A torque acting on the rotation of an SE(3) body: the SO(3) force `F(t, R, Ω)` as
/// `(F, 0)`, so that each torque is written once, for SO(3).
fn on_rotation<F: Forcing<Rotations, 3>, T: RealField + Copy>(
    forcing: &F,
    time: f64,
    g: &SE3<T>,
    xi: &SVector<T, 6>,
) -> SVector<T, 6> {
    let omega = Vector3::new(xi[0], xi[1], xi[2]);
    let torque = forcing.force(time, g.rotation(), &omega);
    SVector::<T, 6>::new(
        torque.x,
        torque.y,
        torque.z,
        T::zero(),
        T::zero(),
        T::zero(),
    )
}

/// The jet of [`on_rotation`]: the SO(3) jet in the rotational rows and columns (a
/// torque that depends on `R` and `Ω` alone).
fn jet_on_rotation<F: Forcing<Rotations, 3>>(
    forcing: &F,
    time: f64,
    g: &SE3,
    xi: &SVector<f64, 6>,
) -> ForceJet<6> {
    let (omega, _) = split(xi);
    let jet = forcing.jet(time, g.rotation(), &omega);
    let zero = Matrix3::zeros();
    ForceJet {
        value: join(&jet.value, &Vector3::zeros()),
        velocity: blocks(&jet.velocity, &zero, &zero, &zero),
        configuration: blocks(&jet.configuration, &zero, &zero, &zero),
    }
}

/// The SE(3) impl of a torque written once for SO(3): it acts on the body's rotation
/// ([`on_rotation`], [`jet_on_rotation`]).
macro_rules! torque_on_se3 {
    ($($torque:ty),*) => {$(
        impl Forcing<RigidMotions, 6> for $torque {
            fn force<T: RealField + Copy>(
                &self,
                t: f64,
                g: &SE3<T>,
                xi: &SVector<T, 6>,
            ) -> SVector<T, 6> {
                on_rotation(self, t, g, xi)
            }
            fn is_zero(&self) -> bool {
                Forcing::<Rotations, 3>::is_zero(self)
            }
            fn jet(&self, t: f64, g: &SE3, xi: &SVector<f64, 6>) -> ForceJet<6> {
                jet_on_rotation(self, t, g, xi)
            }
            fn depends_on_configuration(&self) -> bool {
                Forcing::<Rotations, 3>::depends_on_configuration(self)
            }
            fn rounding_scale(&self) -> f64 {
                Forcing::<Rotations, 3>::rounding_scale(self)
            }
        }
    )*};
}

torque_on_se3!(BodyTorque, AngularDamping, AttitudeSpring);

impl Forcing<RigidMotions, 6> for SpaceForce {
    fn force<T: RealField + Copy>(
        &self,
        _t: f64,
        g: &SE3<T>,
        _xi: &SVector<T, 6>,
    ) -> SVector<T, 6> {
        let body = g.rotation().inverse().act(&convert3::<T>(&self.0));
        SVector::<T, 6>::new(T::zero(), T::zero(), T::zero(), body.x, body.y, body.z)
    }
    fn is_zero(&self) -> bool {
        self.0 == Vector3::zeros()
    }
    /// `b = Rᵀf`; under `R ↦ R exp(ω̂)`, `b ↦ exp(−ω̂) b = b + b̂ ω + O(ω²)`: the
    /// configuration derivative is `b̂` in the force rows and rotation columns.
    fn jet(&self, _t: f64, g: &SE3, _xi: &SVector<f64, 6>) -> ForceJet<6> {
        let body = g.rotation().matrix().transpose() * self.0;
        let zero = Matrix3::zeros();
        ForceJet {
            value: join(&Vector3::zeros(), &body),
            velocity: SMatrix::zeros(),
            configuration: blocks(&zero, &zero, &lgsvi_lie::so3::hat(&body), &zero),
        }
    }
}
