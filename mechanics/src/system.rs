//! Systems on any configuration group.
//!
//! - [`GroupLagrangian`]: what you implement for a system of your own, a reduced Lagrangian
//!   `ℓ(t, g, ξ)` written once, generically over the scalar, and a few optional facts about
//!   it (a symmetry, the velocity from the momentum in closed form, how fast it moves).
//! - [`System`]: what the integrator steps. Every [`GroupLagrangian`] is one; the built-in
//!   systems implement it directly with the closed forms of their derivatives and their
//!   own flow predictors. Its further methods are those fast paths: internal, and hidden
//!   from this documentation while their form may change.
//! - [`Forced`]: a system under a force ([`crate::forces`]).
//!
//! Forces are added with [`Forced`] (a [`crate::forces::Forcing`] beside a system) or as
//! the integrator's control input ([`crate::Integrator::set_input`]); [`crate::forces`]
//! says how they enter a step.

// The fast paths' types, public for System's hidden methods.
#[doc(hidden)]
pub use crate::flow::{FlowGuess, FlowStart, ForceAlongStep, ForceValueAlongStep};
use crate::forces::{ForceJet, Forcing};
use crate::group::{ConfigurationGroup, GroupChart, StepGroup};

#[doc(hidden)]
pub use crate::point::{ForceAtPoint, GaussPoints};
#[doc(hidden)]
pub use crate::point::{GaussPoint, PointForce, PointTransport};
use nalgebra::{RealField, SMatrix, SVector};

/// The element type of a system's group over the scalar `T`.
pub type ElementOf<S, const D: usize, T = f64> =
    <<S as System<D>>::Group as ConfigurationGroup<D>>::Element<T>;

/// What the integrator steps: a reduced, left-trivialised Lagrangian `ℓ(t, g, ξ)` on a
/// configuration group with algebra `ℝ^D` (`g` the configuration, `world_from_body`; `ξ`
/// the body velocity, `ġ = g ξ^`; body momentum `μ = ∂ℓ/∂ξ`, energy `⟨μ, ξ⟩ − ℓ`), its
/// force, and the closed forms the built-in systems give for speed.
///
/// Implement [`GroupLagrangian`] for a system of your own: every one is a `System`. The
/// built-in systems ([`crate::RigidBody`], [`crate::HeavyTop`], [`crate::FreeBody`],
/// [`crate::OrbitingBody`], the gyrostats, [`Forced`]) implement it directly; the methods
/// hidden from this documentation are their fast paths (closed-form derivatives at the
/// Gauss points, flow predictors), internal while their form may change. The visible
/// methods are [`GroupLagrangian`]'s, with the same meaning.
pub trait System<const D: usize> {
    /// The configuration group.
    type Group: StepGroup<D>;

    /// `ℓ(t, g, ξ)`.
    fn lagrangian<T: RealField + Copy>(
        &self,
        time: f64,
        configuration: &ElementOf<Self, D, T>,
        velocity: &SVector<T, D>,
    ) -> T;

    /// True when `ℓ` depends on neither `g` nor `t` (a free body): the exact momentum
    /// matching then has no configuration term. The default `false` is always correct.
    fn is_left_invariant(&self) -> bool {
        false
    }

    /// A generator `ζ` of a symmetry of `ℓ` (a one-parameter group acting on the left that
    /// leaves `ℓ` unchanged), so that Noether's theorem conserves the spatial momentum's
    /// component `⟨Ad*_{g⁻¹}μ, ζ⟩` when no force acts: on SO(3), an axis `d` with `d·Rμ`
    /// conserved (a heavy top's gravity direction). `None` (the default) claims no such
    /// symmetry; a left-invariant `ℓ` conserves all of the spatial momentum whatever this
    /// says.
    fn symmetry_generator(&self) -> Option<SVector<f64, D>> {
        None
    }

    /// How fast the motion from `(t, g, ξ)` is, in radians per unit time: a
    /// tolerance-driven run's first step is sized to turn about 3 rad at it
    /// ([`crate::tolerance::step_count`]). The default is the group's angular speed of `ξ`
    /// ([`ConfigurationGroup::angular_speed`]); a system with a faster natural motion adds
    /// it (a heavy top its pendulum frequency, an orbiting body its gravity-gradient
    /// libration, a gyrostat its fastest wheel).
    fn motion_rate(
        &self,
        time: f64,
        configuration: &ElementOf<Self, D>,
        velocity: &SVector<f64, D>,
    ) -> f64 {
        let _ = (time, configuration);
        <Self::Group as ConfigurationGroup<D>>::angular_speed(velocity)
    }

    /// `ξ` from `μ` in closed form where known; `None` (the default) makes the integrator
    /// solve `∂ℓ/∂ξ = μ` by Newton.
    fn velocity_from_momentum(
        &self,
        time: f64,
        configuration: &ElementOf<Self, D>,
        momentum: &SVector<f64, D>,
    ) -> Option<SVector<f64, D>> {
        let _ = (time, configuration, momentum);
        None
    }

    #[doc(hidden)]
    /// Whether the system has a generalised force ([`System::force`]); the
    /// default `false` skips it.
    fn is_forced(&self) -> bool {
        false
    }

    #[doc(hidden)]
    /// The left-trivialised generalised force `F(t, g, ξ)` (module documentation), generic
    /// over the scalar so that Newton gets its exact derivatives. Read only when
    /// [`System::is_forced`]; the default is zero.
    fn force<T: RealField + Copy>(
        &self,
        time: f64,
        configuration: &ElementOf<Self, D, T>,
        velocity: &SVector<T, D>,
    ) -> SVector<T, D> {
        let _ = (time, configuration, velocity);
        SVector::zeros()
    }

    #[doc(hidden)]
    /// [`System::force`] and its first derivatives at `(t, g, ξ)` ([`ForceJet`]).
    /// The default takes them by first-order dual numbers through `force` alone;
    /// [`Forced`] forwards to its force's closed form.
    fn force_jet(
        &self,
        time: f64,
        configuration: &ElementOf<Self, D>,
        velocity: &SVector<f64, D>,
    ) -> ForceJet<D>
    where
        Self: Sized,
    {
        ForceJet::by_dual_numbers(
            &SystemForce(self),
            time,
            configuration,
            velocity,
            !self.force_depends_on_configuration(),
        )
    }

    #[doc(hidden)]
    /// Whether [`System::force`] depends on the configuration (else the
    /// integrator need not form it at the Gauss points). The default `true` is always
    /// correct.
    fn force_depends_on_configuration(&self) -> bool {
        true
    }

    #[doc(hidden)]
    /// [`Forcing::rounding_scale`] of the system's force: the size of the terms it is
    /// formed from, which Newton's stopping test counts among the equations' terms. The
    /// default 0 suits a force whose rounding is relative to its value.
    fn force_rounding_scale(&self) -> f64 {
        0.0
    }

    #[doc(hidden)]
    /// `(∂²L/∂ξ∂η, ∂²L/∂ξ²)` of `L(η, ξ) = ℓ(t, g exp(η), ξ)` at `η = 0` (entry
    /// `(component of ξ, component of η or ξ)`): how the body momentum `μ = ∂ℓ/∂ξ` moves
    /// with the configuration (body frame) and with the velocity, which the linearisation
    /// of a step reads at both ends ([`crate::linearization::StepLinearization`]). `None` (the default)
    /// has them from [`System::local_derivatives`] or by dual numbers through
    /// `ℓ`; the built-in SO(3) systems give them from their closed forms.
    fn momentum_derivatives(
        &self,
        time: f64,
        configuration: &ElementOf<Self, D>,
        velocity: &SVector<f64, D>,
    ) -> Option<(SMatrix<f64, D, D>, SMatrix<f64, D, D>)> {
        let _ = (time, configuration, velocity);
        None
    }

    #[doc(hidden)]
    /// The first and second derivatives of `L(η, ξ) = ℓ(t, g exp(η), ξ)` at `η = 0`
    /// ([`LocalDerivatives`]), which the generic chain rule composes with the chart's
    /// derivatives; `None` (the default) has them taken by a second-order dual number over
    /// the `2D` variables `(η, ξ)` through `ℓ`. Only `L`'s derivatives at `η = 0` are read,
    /// so `exp(η)` may be taken to second order ([`ConfigurationGroup::exp_second_order`]).
    /// The mixed block `∂²L/∂η∂ξ` must be zero (a kinetic energy that does not depend on
    /// the configuration), as it is for the built-in SE(3) systems.
    fn local_derivatives(
        &self,
        time: f64,
        configuration: &ElementOf<Self, D>,
        velocity: &SVector<f64, D>,
        with_hessian: bool,
    ) -> Option<LocalDerivatives<D>> {
        let _ = (time, configuration, velocity, with_hessian);
        None
    }

    #[doc(hidden)]
    /// A closed-form path for one Gauss point's derivatives of
    /// `ℓ̃(x, v, ζ) = ℓ(t, base Φ(x) exp(ζ), A(x) v)` at the point `point` (see
    /// [`crate::group::PointJet`]), with the force terms of [`GaussPoint::force`] added
    /// when it is `Some` (its jet through the chart: [`crate::forces::ForceJet`]'s documentation):
    /// write them into `out` and return `true`, or return `false` (the default) to have
    /// them taken by the generic chain rule. The SO(3) systems use their chart's
    /// Rodrigues form, the built-in SE(3) systems the rotation–translation chart's 3 × 3
    /// blocks. An implementation that returns `true` must add the force.
    fn point_derivatives<C: GroupChart<Self::Group, D>>(
        &self,
        chart: &C,
        point: &GaussPoint<'_, Self::Group, D>,
        out: &mut <Self::Group as StepGroup<D>>::Jet,
    ) -> bool {
        let _ = (chart, point, out);
        false
    }

    #[doc(hidden)]
    /// [`System::point_derivatives`], handing back in `transport` the chart's
    /// `Ad_{Φ(x)⁻¹}ᵀ` and `A(x)` at the point ([`PointTransport`]) where the closed form
    /// formed them on its way and `point.with_configuration` asks for the configuration
    /// force: the exact matching then reads them instead of evaluating the chart at the
    /// point again. They must be [`GroupChart::transport_and_differential`]'s at `point.x`
    /// to rounding; `transport` is read only when this returns `true`, and the step passes
    /// it as `None` at every point of every assembly (an implementation that hands nothing
    /// back need not write it). The default calls
    /// `point_derivatives` and hands back nothing (`None`). The built-in SO(3) systems
    /// hand back the chart's terms where their `ℓ` reads the attitude.
    fn point_derivatives_and_transport<C: GroupChart<Self::Group, D>>(
        &self,
        chart: &C,
        point: &GaussPoint<'_, Self::Group, D>,
        out: &mut <Self::Group as StepGroup<D>>::Jet,
        transport: &mut Option<PointTransport<D>>,
    ) -> bool {
        *transport = None;
        self.point_derivatives(chart, point, out)
    }

    /// Every Gauss point of an assembly at once: point `j` written into `out[j]` and
    /// `transports[j]` as [`System::point_derivatives_and_transport`] would write
    /// them one by one, and the force's power `F·ξ` at it into `power[j]` (NaN unforced);
    /// `true` if written, `false` (the default, nothing written) to have the points taken
    /// one by one. The built-in SO(3) systems that are left-invariant or whose
    /// attitude term is linear in `R`, under a force that does not read the attitude,
    /// take four points at a time, the same bits as one by one. An internal fast path,
    /// hidden from the documentation while its form may change.
    #[doc(hidden)]
    fn points_in_lanes<C: GroupChart<Self::Group, D>>(
        &self,
        chart: &C,
        points: &GaussPoints<'_, Self::Group, D>,
        out: &mut [<Self::Group as StepGroup<D>>::Jet],
        transports: &mut [Option<PointTransport<D>>],
        power: &mut [f64],
    ) -> bool {
        let _ = (chart, points, out, transports, power);
        false
    }

    /// Why the state lies outside what the system models, if it does (an
    /// [`crate::OrbitingBody`] whose mass surrounds the attracting point, where its
    /// far-field potential does not hold): a sentence saying what to change. Read at each
    /// step's end, where a state it refuses is not taken
    /// ([`crate::MechanicsError::LeftModel`]), and at the start of a step that failed
    /// ([`crate::MechanicsError::OutsideModel`], with the failure as its source); keep it
    /// cheap. The default is `None`: the system models every state.
    fn model_breakdown(
        &self,
        time: f64,
        configuration: &ElementOf<Self, D>,
        velocity: &SVector<f64, D>,
    ) -> Option<String> {
        let _ = (time, configuration, velocity);
        None
    }

    /// The names of the physical parameters `p` of `ℓ` that a step can be differentiated
    /// by ([`crate::Integrator::linearize_with_parameters`]), in the order of
    /// [`System::parameter_lagrangian`]'s index. The default: none. The built-in
    /// bodies name the six entries of the inertia tensor
    /// ([`crate::inertia::INERTIA_PARAMETERS`]) and, where `ℓ` has one, the mass (the
    /// gyrostat its wheels' inertias, the orbiting body then its gravitational parameter). Forces do not depend on these parameters. A
    /// type that wraps other systems should forward it (and
    /// [`System::parameter_lagrangian`]).
    fn parameter_names(&self) -> Vec<String> {
        Vec::new()
    }

    /// `∂ℓ/∂p_k(t, g, ξ)`, the derivative of [`System::lagrangian`] in parameter
    /// `k` of [`System::parameter_names`] at the system's own parameters,
    /// generic over the scalar as `ℓ` is: a step's derivative in `p_k` is its residual
    /// with `ℓ` replaced by this (the residual is linear in `ℓ`; `docs/notes/linearization.md`
    /// §8). Must be exact: the linearisation is as accurate as it. Where
    /// [`System::is_left_invariant`] is true it must not depend on the
    /// configuration either (the step then takes no configuration derivatives of it). The
    /// default (no parameters) is zero.
    fn parameter_lagrangian<T: RealField + Copy>(
        &self,
        index: usize,
        time: f64,
        configuration: &ElementOf<Self, D, T>,
        velocity: &SVector<T, D>,
    ) -> T {
        let _ = (index, time, configuration, velocity);
        T::zero()
    }

    #[doc(hidden)]
    /// As [`System::point_derivatives`] for the Lagrangian
    /// [`System::parameter_lagrangian`] of parameter `index` (no force: the
    /// point's force is `None`): a faster path for the step's parameter columns, or
    /// `false` (the default) for the generic chain rule by dual numbers through `∂ℓ/∂p`
    /// (the chart's derivatives from [`GroupChart::with_derivatives`]). The built-in SE(3)
    /// bodies take the rotation–translation chart's 3 × 3 blocks with `∂ℓ/∂p`'s local
    /// derivatives in closed form (far cheaper than the generic rule's 6 × 6 products). On
    /// SO(3) the generic rule is faster than the Rodrigues form with `∂ℓ/∂p`'s derivatives
    /// by dual numbers, and is kept.
    fn parameter_point_derivatives<C: GroupChart<Self::Group, D>>(
        &self,
        index: usize,
        chart: &C,
        point: &GaussPoint<'_, Self::Group, D>,
        out: &mut <Self::Group as StepGroup<D>>::Jet,
    ) -> bool {
        let _ = (index, chart, point, out);
        false
    }

    #[doc(hidden)]
    /// A predictor from the system's own flow over the step from `start`: write the chart
    /// coordinates at `start.times` into `out` ([`FlowGuess::Written`], with the flow's end
    /// relative to its start, which the converged step is checked against), or report that
    /// the flow leaves the chart. [`FlowStart::force`] is the total force of the step (the
    /// system's and the control input), to be included in the flow. The default has none
    /// ([`FlowGuess::Unavailable`]): the integrator then continues the last step's curve.
    fn flow_guess<C: GroupChart<Self::Group, D>>(
        &self,
        chart: &C,
        start: &FlowStart<'_, Self::Group, D>,
        out: &mut [SVector<f64, D>],
    ) -> FlowGuess<ElementOf<Self, D>> {
        let _ = (chart, start, out);
        FlowGuess::Unavailable
    }
}

/// A system of your own: a reduced, left-trivialised Lagrangian `ℓ(t, g, ξ)` on a
/// configuration group with algebra `ℝ^D` (`g` the configuration, `world_from_body`; `ξ`
/// the body velocity, `ġ = g ξ^`). Body momentum `μ = ∂ℓ/∂ξ`, energy `⟨μ, ξ⟩ − ℓ`.
///
/// Write `ℓ` once, generically over the scalar: the integrator differentiates it by dual
/// numbers (its gradient and Hessian at the Gauss points, exactly). The other methods are
/// optional facts that make runs faster or their checks sharper. Forces are added with
/// [`Forced`] and a [`crate::forces::Forcing`], control inputs with
/// [`crate::Integrator::set_input`]. The groups: [`crate::group::Rotations`] (SO(3),
/// `D = 3`), [`crate::group::RigidMotions`] (SE(3), `D = 6`), the gyrostats' SO(3) × ℝᴷ, or
/// one of your own ([`crate::group`]). Every `GroupLagrangian` is a [`System`].
///
/// ```
/// use lgsvi_mechanics::group::RigidMotions;
/// use lgsvi_mechanics::lie::SE3;
/// use lgsvi_mechanics::prelude::*;
/// use nalgebra::RealField;
///
/// /// A unit sphere on a spring to the origin: ℓ = ½|ω|² + ½|v|² − ½k|x|².
/// struct Tethered { k: f64 }
/// impl GroupLagrangian<6> for Tethered {
///     type Group = RigidMotions;
///     fn lagrangian<T: RealField + Copy>(&self, _t: f64, g: &SE3<T>, xi: &SVector<T, 6>) -> T {
///         let half: T = nalgebra::convert(0.5);
///         let k: T = nalgebra::convert(self.k);
///         half * xi.dot(xi) - half * k * g.translation().norm_squared()
///     }
/// }
///
/// let xi = SVector::<f64, 6>::new(0.0, 0.0, 0.0, 0.0, 0.5, 0.0);
/// let mut it = Integrator::builder(Tethered { k: 4.0 })
///     .start(SE3::new(SO3::identity(), Vector3::new(1.0, 0.0, 0.0)), xi)
///     .step(0.1)
///     .nodes(8)
///     .build()?;
/// let e0 = it.state().energy(&Tethered { k: 4.0 });
/// it.run_until(10.0, 10)?;
/// // A variational integrator keeps the energy of this oscillator bounded.
/// assert!((it.state().energy(&Tethered { k: 4.0 }) - e0).abs() < 1e-12);
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
pub trait GroupLagrangian<const D: usize> {
    /// The configuration group.
    type Group: StepGroup<D>;

    /// `ℓ(t, g, ξ)`.
    fn lagrangian<T: RealField + Copy>(
        &self,
        time: f64,
        configuration: &<Self::Group as ConfigurationGroup<D>>::Element<T>,
        velocity: &SVector<T, D>,
    ) -> T;

    /// True when `ℓ` depends on neither `g` nor `t` (a free body): the exact momentum
    /// matching then has no configuration term. The default `false` is always correct.
    fn is_left_invariant(&self) -> bool {
        false
    }

    /// A generator `ζ` of a symmetry of `ℓ` (a one-parameter group acting on the left that
    /// leaves `ℓ` unchanged), so that Noether's theorem conserves the spatial momentum's
    /// component `⟨Ad*_{g⁻¹}μ, ζ⟩` when no force acts: on SO(3), an axis `d` with `d·Rμ`
    /// conserved. `None` (the default) claims no such symmetry; a left-invariant `ℓ`
    /// conserves all of the spatial momentum whatever this says.
    fn symmetry_generator(&self) -> Option<SVector<f64, D>> {
        None
    }

    /// `ξ` from `μ` in closed form where known; `None` (the default) makes the integrator
    /// solve `∂ℓ/∂ξ = μ` by Newton.
    fn velocity_from_momentum(
        &self,
        time: f64,
        configuration: &<Self::Group as ConfigurationGroup<D>>::Element<f64>,
        momentum: &SVector<f64, D>,
    ) -> Option<SVector<f64, D>> {
        let _ = (time, configuration, momentum);
        None
    }

    /// How fast the motion from `(t, g, ξ)` is, in radians per unit time: a
    /// tolerance-driven run's first step turns about 3 rad at it. The default is the
    /// group's angular speed of `ξ`; add the system's fastest natural motion (a pendulum's
    /// frequency) where it has one.
    fn motion_rate(
        &self,
        time: f64,
        configuration: &<Self::Group as ConfigurationGroup<D>>::Element<f64>,
        velocity: &SVector<f64, D>,
    ) -> f64 {
        let _ = (time, configuration);
        <Self::Group as ConfigurationGroup<D>>::angular_speed(velocity)
    }

    /// Why the state lies outside what the system models, if it does: a sentence saying
    /// what to change. Read at each step's end (a state it refuses is not taken:
    /// [`crate::MechanicsError::LeftModel`]) and where a step has failed
    /// ([`crate::MechanicsError::OutsideModel`]); the default `None` models every state.
    fn model_breakdown(
        &self,
        time: f64,
        configuration: &<Self::Group as ConfigurationGroup<D>>::Element<f64>,
        velocity: &SVector<f64, D>,
    ) -> Option<String> {
        let _ = (time, configuration, velocity);
        None
    }

    /// The names of physical parameters `p` of `ℓ` that a step can be differentiated by
    /// ([`crate::Integrator::linearize_with_parameters`]), in the order of
    /// [`GroupLagrangian::parameter_lagrangian`]'s index. The default: none.
    fn parameter_names(&self) -> Vec<String> {
        Vec::new()
    }

    /// `∂ℓ/∂p_k(t, g, ξ)` for parameter `k` of [`GroupLagrangian::parameter_names`],
    /// generic over the scalar as `ℓ` is, and exact. The default (no parameters) is zero.
    fn parameter_lagrangian<T: RealField + Copy>(
        &self,
        index: usize,
        time: f64,
        configuration: &<Self::Group as ConfigurationGroup<D>>::Element<T>,
        velocity: &SVector<T, D>,
    ) -> T {
        let _ = (index, time, configuration, velocity);
        T::zero()
    }
}

/// Every system of your own is a [`System`]: its derivatives by dual numbers, no flow
/// predictor (the integrator continues the last step's curve).
impl<L: GroupLagrangian<D>, const D: usize> System<D> for L {
    type Group = L::Group;

    fn lagrangian<T: RealField + Copy>(
        &self,
        time: f64,
        configuration: &ElementOf<Self, D, T>,
        velocity: &SVector<T, D>,
    ) -> T {
        GroupLagrangian::lagrangian(self, time, configuration, velocity)
    }
    fn is_left_invariant(&self) -> bool {
        GroupLagrangian::is_left_invariant(self)
    }
    fn symmetry_generator(&self) -> Option<SVector<f64, D>> {
        GroupLagrangian::symmetry_generator(self)
    }
    fn velocity_from_momentum(
        &self,
        time: f64,
        configuration: &ElementOf<Self, D>,
        momentum: &SVector<f64, D>,
    ) -> Option<SVector<f64, D>> {
        GroupLagrangian::velocity_from_momentum(self, time, configuration, momentum)
    }
    fn motion_rate(
        &self,
        time: f64,
        configuration: &ElementOf<Self, D>,
        velocity: &SVector<f64, D>,
    ) -> f64 {
        GroupLagrangian::motion_rate(self, time, configuration, velocity)
    }
    fn model_breakdown(
        &self,
        time: f64,
        configuration: &ElementOf<Self, D>,
        velocity: &SVector<f64, D>,
    ) -> Option<String> {
        GroupLagrangian::model_breakdown(self, time, configuration, velocity)
    }
    fn parameter_names(&self) -> Vec<String> {
        GroupLagrangian::parameter_names(self)
    }
    fn parameter_lagrangian<T: RealField + Copy>(
        &self,
        index: usize,
        time: f64,
        configuration: &ElementOf<Self, D, T>,
        velocity: &SVector<T, D>,
    ) -> T {
        GroupLagrangian::parameter_lagrangian(self, index, time, configuration, velocity)
    }
}

/// The derivatives of `L(η, ξ) = ℓ(t, g exp(η), ξ)` at `η = 0` for a Lagrangian whose
/// kinetic energy does not depend on the configuration (`∂²L/∂η∂ξ = 0`).
#[doc(hidden)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalDerivatives<const D: usize> {
    /// `p = ∂L/∂η`, the left-trivialised configuration force.
    pub configuration_gradient: SVector<f64, D>,
    /// `μ = ∂L/∂ξ`, the body momentum.
    pub momentum: SVector<f64, D>,
    /// `∂²L/∂η²` (zero when the Hessian was not asked for).
    pub configuration_hessian: SMatrix<f64, D, D>,
    /// `∂²L/∂ξ²` (zero when the Hessian was not asked for).
    pub velocity_hessian: SMatrix<f64, D, D>,
}

/// A system's own force as a [`Forcing`], for [`ForceJet::by_dual_numbers`].
struct SystemForce<'a, S>(&'a S);

impl<S: System<D>, const D: usize> Forcing<S::Group, D> for SystemForce<'_, S> {
    fn force<T: RealField + Copy>(
        &self,
        time: f64,
        configuration: &ElementOf<S, D, T>,
        velocity: &SVector<T, D>,
    ) -> SVector<T, D> {
        self.0.force(time, configuration, velocity)
    }
}

/// [`System`] for SO(3) systems that write `ℓ(R, Ω)` with their closed forms
/// ([`crate::lagrangian::Lagrangian`]): the Rodrigues chain rule at the Gauss points, four points at a time
/// where `ℓ` allows, and the flow predictor. `so3_system!(impl[generics] for Type; …)`.
macro_rules! so3_system {
    ($(impl[$($generics:tt)*] for $ty:ty;)*) => {$(
        impl<$($generics)*> $crate::system::System<3> for $ty {
            type Group = $crate::group::Rotations;

            fn lagrangian<T: ::nalgebra::RealField + Copy>(&self, _time: f64, g: &::lgsvi_lie::SO3<T>, w: &::nalgebra::Vector3<T>) -> T {
                $crate::lagrangian::Lagrangian::lagrangian(self, g.matrix(), w)
            }
            fn is_left_invariant(&self) -> bool {
                $crate::lagrangian::Lagrangian::is_left_invariant(self)
            }
            fn symmetry_generator(&self) -> Option<::nalgebra::Vector3<f64>> {
                $crate::lagrangian::Lagrangian::symmetry_axis(self)
            }
            fn velocity_from_momentum(
                &self,
                _time: f64,
                g: &::lgsvi_lie::SO3,
                mu: &::nalgebra::Vector3<f64>,
            ) -> Option<::nalgebra::Vector3<f64>> {
                $crate::lagrangian::Lagrangian::velocity_from_momentum(self, g.matrix(), mu)
            }
            /// `|Ω|` and the system's natural frequency (the `Lagrangian`'s natural frequency).
            fn motion_rate(&self, _time: f64, _g: &::lgsvi_lie::SO3, w: &::nalgebra::Vector3<f64>) -> f64 {
                w.norm() + $crate::lagrangian::Lagrangian::natural_frequency(self)
            }
            fn point_derivatives<C: $crate::group::GroupChart<$crate::group::Rotations, 3>>(
                &self,
                chart: &C,
                point: &$crate::point::GaussPoint<'_, $crate::group::Rotations, 3>,
                out: &mut $crate::group::Stacked<9>,
            ) -> bool {
                $crate::jet::point_derivatives(self, chart, point, out, &mut None)
            }
            fn point_derivatives_and_transport<C: $crate::group::GroupChart<$crate::group::Rotations, 3>>(
                &self,
                chart: &C,
                point: &$crate::point::GaussPoint<'_, $crate::group::Rotations, 3>,
                out: &mut $crate::group::Stacked<9>,
                transport: &mut Option<$crate::point::PointTransport<3>>,
            ) -> bool {
                $crate::jet::point_derivatives(self, chart, point, out, transport)
            }
            fn points_in_lanes<C: $crate::group::GroupChart<$crate::group::Rotations, 3>>(
                &self,
                chart: &C,
                points: &$crate::point::GaussPoints<'_, $crate::group::Rotations, 3>,
                out: &mut [$crate::group::Stacked<9>],
                transports: &mut [Option<$crate::point::PointTransport<3>>],
                power: &mut [f64],
            ) -> bool {
                crate::jet_lanes::points_in_lanes(self, chart, points, out, transports, power)
            }
            fn model_breakdown(&self, _time: f64, g: &::lgsvi_lie::SO3, w: &::nalgebra::Vector3<f64>) -> Option<String> {
                $crate::lagrangian::Lagrangian::model_breakdown(self, g.matrix(), w)
            }
            fn parameter_names(&self) -> Vec<String> {
                $crate::lagrangian::Lagrangian::parameter_names(self)
            }
            fn parameter_lagrangian<T: ::nalgebra::RealField + Copy>(
                &self,
                index: usize,
                _time: f64,
                g: &::lgsvi_lie::SO3<T>,
                w: &::nalgebra::Vector3<T>,
            ) -> T {
                $crate::lagrangian::Lagrangian::parameter_lagrangian(self, index, g.matrix(), w)
            }
            /// From the closed-form derivatives: `∂²L/∂Ω∂η_b = Σ_ij ∂²ℓ/∂R_ij∂Ω (R ê_b)_ij`.
            fn momentum_derivatives(
                &self,
                _time: f64,
                g: &::lgsvi_lie::SO3,
                w: &::nalgebra::Vector3<f64>,
            ) -> Option<(::nalgebra::Matrix3<f64>, ::nalgebra::Matrix3<f64>)> {
                let r = g.matrix();
                let l = $crate::lagrangian::Lagrangian::derivatives(self, r, w);
                let mut mixed = ::nalgebra::Matrix3::zeros();
                if let Some(h) = l.mixed_hessian {
                    for b in 0..3 {
                        let dr = r * lgsvi_lie::so3::hat(&::nalgebra::Vector3::ith(b, 1.0));
                        for c in 0..3 {
                            mixed[(c, b)] = (0..9).map(|k| h[(k, c)] * dr[(k / 3, k % 3)]).sum();
                        }
                    }
                }
                Some((mixed, l.velocity_hessian))
            }
            fn flow_guess<C: $crate::group::GroupChart<$crate::group::Rotations, 3>>(
                &self,
                chart: &C,
                start: &$crate::flow::FlowStart<'_, $crate::group::Rotations, 3>,
                out: &mut [::nalgebra::Vector3<f64>],
            ) -> $crate::flow::FlowGuess<::lgsvi_lie::SO3> {
                $crate::flow::flow_guess(self, chart, start, out)
            }
        }
    )*};
}
pub(crate) use so3_system;

#[cfg(test)]
mod tests {
    use crate::lagrangian::Lagrangian;
    use crate::{HeavyTop, Inertia, Integrator, StepSettings};
    use lgsvi_lie::{ChartKind, SO3};
    use nalgebra::{Matrix3, RealField, Vector3};

    /// A heavy top whose closed forms are hidden except `derivatives`: the integrator then
    /// forms `R` at every Gauss point and predictor stage, where with
    /// `Lagrangian::linear_attitude_term` it rotates `m g d` into the body instead.
    struct TopWithoutField(HeavyTop);
    so3_system! {
        impl[] for TopWithoutField;
    }
    impl Lagrangian for TopWithoutField {
        fn lagrangian<T: RealField + Copy>(&self, r: &Matrix3<T>, w: &Vector3<T>) -> T {
            self.0.lagrangian(r, w)
        }
        fn velocity_from_momentum(
            &self,
            r: &Matrix3<f64>,
            mu: &Vector3<f64>,
        ) -> Option<Vector3<f64>> {
            self.0.velocity_from_momentum(r, mu)
        }
        fn derivatives(
            &self,
            r: &Matrix3<f64>,
            w: &Vector3<f64>,
        ) -> crate::lagrangian::LagrangianDerivatives {
            self.0.derivatives(r, w)
        }
    }

    /// `linear_attitude_term` is a statement about `ℓ`: `ℓ(R, Ω) − ℓ(R', Ω) = aᵀ(R − R')b`
    /// at any attitudes; and a run that uses it (rotated vectors, never `R` at the points)
    /// takes the same steps as one that forms `R`, in every chart.
    #[test]
    fn a_linear_attitude_term_changes_how_not_what() {
        let inertia = Inertia::from_principal_moments([0.5, 0.9, 0.7]).unwrap();
        let top = HeavyTop::new(
            inertia,
            1.3,
            0.3,
            Vector3::new(0.1, -0.2, 0.8),
            Vector3::new(0.3, 0.1, -1.0),
        )
        .unwrap();
        let (a, b) = top.linear_attitude_term().unwrap();
        let w = Vector3::new(0.4, -1.1, 0.6);
        for (r1, r2) in [
            (SO3::exp(&Vector3::new(0.3, -0.7, 0.2)), SO3::about_z(2.0)),
            (SO3::exp(&Vector3::new(-2.1, 0.4, 1.0)), SO3::identity()),
        ] {
            let (r1, r2) = (r1.matrix(), r2.matrix());
            let difference = top.lagrangian(r1, &w) - top.lagrangian(r2, &w);
            // Two sums of order-10 terms: rounding of a few ulps of 10.
            assert!((difference - a.dot(&((r1 - r2) * b))).abs() <= 1e-13);
        }
        for chart in ChartKind::ALL {
            let settings = StepSettings::new(0.25, 8).unwrap();
            let start = SO3::exp(&Vector3::new(0.2, 0.1, -0.3));
            let mut fast = Integrator::with_chart(top, chart, settings, start, w).unwrap();
            let mut reference =
                Integrator::with_chart(TopWithoutField(top), chart, settings, start, w).unwrap();
            let mut largest: f64 = 0.0;
            for _ in 0..200 {
                fast.step().unwrap();
                reference.step().unwrap();
                let (x, y) = (fast.state(), reference.state());
                largest = largest
                    .max((x.configuration.matrix() - y.configuration.matrix()).amax())
                    .max((x.momentum - y.momentum).amax());
            }
            // The same equations solved to the same tolerance; only the rounding of the
            // rotated vectors differs: 2e-16 after the first step, which this asymmetric
            // top's motion amplifies (with g = 9.81 it is chaotic: ×10 every 10 steps, O(1)
            // after 200). At g = 0.3, 1.9e-13 … 1.4e-12 after 200 steps across the
            // charts; 1e-11 leaves that growth room (rotating by Φ instead of Φᵀ fails it
            // by 2.2×).
            let iterations = |s: &crate::integrator::Statistics| s.newton_iterations;
            let (i_fast, i_reference) = (
                iterations(fast.statistics()),
                iterations(reference.statistics()),
            );
            println!(
                "{chart}: largest difference {largest:.1e}, Newton iterations {i_fast} / {i_reference}"
            );
            assert!(largest <= 1e-11, "{chart}: {largest:e}");
            // The predictor rotates the same vector: its guesses, and so the iterations,
            // agree up to decisions at the rounding edge (589 against 591, exp chart); the
            // predictor's gravity torque with the wrong sign costs 12% (661) and fails it.
            assert!(i_fast.abs_diff(i_reference) * 50 <= i_reference, "{chart}");
        }
    }
}

so3_system! {
    impl[] for crate::lagrangian::RigidBody;
    impl[] for crate::lagrangian::HeavyTop;
    impl[V: crate::lagrangian::Potential] for crate::lagrangian::RigidBodyInPotential<V>;
}

/// A system with a generalised force added ([`Forcing`]): `Forced::new(body, BodyTorque(τ))`.
/// Everything else (the closed-form derivatives of `ℓ`, the flow predictor, which the
/// integrator hands the step's total force) is the inner system's; the force's own
/// derivatives come from [`Forcing::jet`] (closed form for the built-in forces). Under a
/// force that [`Forcing::is_zero`], the steps are the inner system's, bit for bit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Forced<S, F> {
    /// The unforced system.
    pub system: S,
    /// The force.
    pub forcing: F,
}

impl<S, F> Forced<S, F> {
    /// `system` under `forcing`.
    pub fn new(system: S, forcing: F) -> Self {
        Self { system, forcing }
    }
}

impl<S: System<D>, F: Forcing<S::Group, D>, const D: usize> System<D> for Forced<S, F> {
    type Group = S::Group;

    fn lagrangian<T: RealField + Copy>(
        &self,
        time: f64,
        g: &ElementOf<S, D, T>,
        xi: &SVector<T, D>,
    ) -> T {
        self.system.lagrangian(time, g, xi)
    }
    fn is_left_invariant(&self) -> bool {
        self.system.is_left_invariant()
    }
    fn symmetry_generator(&self) -> Option<SVector<f64, D>> {
        self.system.symmetry_generator()
    }
    fn velocity_from_momentum(
        &self,
        time: f64,
        g: &ElementOf<S, D>,
        mu: &SVector<f64, D>,
    ) -> Option<SVector<f64, D>> {
        self.system.velocity_from_momentum(time, g, mu)
    }
    fn motion_rate(&self, time: f64, g: &ElementOf<S, D>, xi: &SVector<f64, D>) -> f64 {
        self.system.motion_rate(time, g, xi)
    }
    fn is_forced(&self) -> bool {
        self.system.is_forced() || !self.forcing.is_zero()
    }
    fn force<T: RealField + Copy>(
        &self,
        time: f64,
        g: &ElementOf<S, D, T>,
        xi: &SVector<T, D>,
    ) -> SVector<T, D> {
        self.system.force(time, g, xi) + self.forcing.force(time, g, xi)
    }
    fn force_jet(&self, time: f64, g: &ElementOf<S, D>, xi: &SVector<f64, D>) -> ForceJet<D> {
        let own = self.forcing.jet(time, g, xi);
        if self.system.is_forced() {
            self.system.force_jet(time, g, xi) + own
        } else {
            own
        }
    }
    fn force_depends_on_configuration(&self) -> bool {
        (self.system.is_forced() && self.system.force_depends_on_configuration())
            || self.forcing.depends_on_configuration()
    }
    fn force_rounding_scale(&self) -> f64 {
        self.system
            .force_rounding_scale()
            .max(self.forcing.rounding_scale())
    }
    fn local_derivatives(
        &self,
        time: f64,
        g: &ElementOf<S, D>,
        xi: &SVector<f64, D>,
        with_hessian: bool,
    ) -> Option<LocalDerivatives<D>> {
        self.system.local_derivatives(time, g, xi, with_hessian)
    }
    fn momentum_derivatives(
        &self,
        time: f64,
        g: &ElementOf<S, D>,
        xi: &SVector<f64, D>,
    ) -> Option<(SMatrix<f64, D, D>, SMatrix<f64, D, D>)> {
        self.system.momentum_derivatives(time, g, xi)
    }
    fn point_derivatives<C: GroupChart<Self::Group, D>>(
        &self,
        chart: &C,
        point: &GaussPoint<'_, Self::Group, D>,
        out: &mut <Self::Group as StepGroup<D>>::Jet,
    ) -> bool {
        self.system.point_derivatives(chart, point, out)
    }
    fn point_derivatives_and_transport<C: GroupChart<Self::Group, D>>(
        &self,
        chart: &C,
        point: &GaussPoint<'_, Self::Group, D>,
        out: &mut <Self::Group as StepGroup<D>>::Jet,
        transport: &mut Option<PointTransport<D>>,
    ) -> bool {
        self.system
            .point_derivatives_and_transport(chart, point, out, transport)
    }
    fn points_in_lanes<C: GroupChart<Self::Group, D>>(
        &self,
        chart: &C,
        points: &GaussPoints<'_, Self::Group, D>,
        out: &mut [<Self::Group as StepGroup<D>>::Jet],
        transports: &mut [Option<PointTransport<D>>],
        power: &mut [f64],
    ) -> bool {
        // The step hands the force (this one's and the input) at every point itself.
        self.system
            .points_in_lanes(chart, points, out, transports, power)
    }
    fn model_breakdown(
        &self,
        time: f64,
        g: &ElementOf<S, D>,
        xi: &SVector<f64, D>,
    ) -> Option<String> {
        self.system.model_breakdown(time, g, xi)
    }
    fn parameter_names(&self) -> Vec<String> {
        self.system.parameter_names()
    }
    fn parameter_lagrangian<T: RealField + Copy>(
        &self,
        index: usize,
        time: f64,
        g: &ElementOf<S, D, T>,
        xi: &SVector<T, D>,
    ) -> T {
        self.system.parameter_lagrangian(index, time, g, xi)
    }
    fn parameter_point_derivatives<C: GroupChart<Self::Group, D>>(
        &self,
        index: usize,
        chart: &C,
        point: &GaussPoint<'_, Self::Group, D>,
        out: &mut <Self::Group as StepGroup<D>>::Jet,
    ) -> bool {
        self.system
            .parameter_point_derivatives(index, chart, point, out)
    }
    /// The inner system's flow, under the step's total force ([`FlowStart::force`]); none
    /// for a forced step whose force is not given.
    fn flow_guess<C: GroupChart<Self::Group, D>>(
        &self,
        chart: &C,
        start: &FlowStart<'_, Self::Group, D>,
        out: &mut [SVector<f64, D>],
    ) -> FlowGuess<ElementOf<S, D>> {
        if self.is_forced() && start.force.is_none() {
            return FlowGuess::Unavailable;
        }
        self.system.flow_guess(chart, start, out)
    }
}
