//! Systems on any configuration group: the generic reduced Lagrangian, a system under a
//! force, and the bridge from the SO(3) [`Lagrangian`].
//!
//! Forces are added with [`Forced`] (a [`crate::forces::Forcing`] beside a system) or as
//! the integrator's control input ([`crate::Integrator::set_input`]); [`crate::forces`]
//! says how they enter a step.

pub use crate::flow::FlowGuess;
pub use crate::flow::{FlowStart, ForceAlongStep, ForceValueAlongStep};
use crate::forces::{ForceJet, Forcing};
use crate::group::{ConfigurationGroup, GroupChart, Rotations, Stacked};
use crate::lagrangian::Lagrangian;
pub use crate::lagrangian::LagrangianDerivatives;
#[doc(hidden)]
pub use crate::point::{ForceAtPoint, GaussPoints};
pub use crate::point::{GaussPoint, PointForce, PointTransport};
use lgsvi_lie::SO3;
use nalgebra::{Matrix3, RealField, SMatrix, SVector, Vector3};

/// The element type of a system's group over the scalar `T`.
pub type ElementOf<S, const D: usize, T = f64> =
    <<S as GroupLagrangian<D>>::Group as ConfigurationGroup<D>>::Element<T>;

/// A reduced, left-trivialised Lagrangian `ℓ(t, g, ξ)` on a configuration group with
/// algebra `ℝ^D`: `g` the configuration (`world_from_body`), `ξ` the body velocity
/// (`ġ = g ξ^`). Body momentum `μ = ∂ℓ/∂ξ`, energy `⟨μ, ξ⟩ − ℓ`.
///
/// Every SO(3) [`Lagrangian`] is one (`D = 3`, [`Rotations`]), with its closed-form
/// derivatives and flow predictor; the SE(3) systems ([`crate::FreeBody`],
/// [`crate::OrbitingBody`], [`crate::BodyInField`]) have `D = 6`. Write `ℓ` once,
/// generically over the scalar: the integrator differentiates it by dual numbers.
///
/// ```
/// use lgsvi_mechanics::GroupLagrangian;
/// use lgsvi_mechanics::group::RigidMotions;
/// use lgsvi_mechanics::lie::SE3;
/// use nalgebra::{RealField, SVector};
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
/// ```
pub trait GroupLagrangian<const D: usize> {
    /// The configuration group.
    type Group: ConfigurationGroup<D>;

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

    /// Whether the system has a generalised force ([`GroupLagrangian::force`]); the
    /// default `false` skips it.
    fn is_forced(&self) -> bool {
        false
    }

    /// The left-trivialised generalised force `F(t, g, ξ)` (module documentation), generic
    /// over the scalar so that Newton gets its exact derivatives. Read only when
    /// [`GroupLagrangian::is_forced`]; the default is zero.
    fn force<T: RealField + Copy>(
        &self,
        time: f64,
        configuration: &ElementOf<Self, D, T>,
        velocity: &SVector<T, D>,
    ) -> SVector<T, D> {
        let _ = (time, configuration, velocity);
        SVector::zeros()
    }

    /// [`GroupLagrangian::force`] and its first derivatives at `(t, g, ξ)` ([`ForceJet`]).
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

    /// Whether [`GroupLagrangian::force`] depends on the configuration (else the
    /// integrator need not form it at the Gauss points). The default `true` is always
    /// correct.
    fn force_depends_on_configuration(&self) -> bool {
        true
    }

    /// `(∂²L/∂ξ∂η, ∂²L/∂ξ²)` of `L(η, ξ) = ℓ(t, g exp(η), ξ)` at `η = 0` (entry
    /// `(component of ξ, component of η or ξ)`): how the body momentum `μ = ∂ℓ/∂ξ` moves
    /// with the configuration (body frame) and with the velocity, which the linearisation
    /// of a step reads at both ends ([`crate::linearization::StepLinearization`]). `None` (the default)
    /// has them from [`GroupLagrangian::local_derivatives`] or by dual numbers through
    /// `ℓ`; the SO(3) systems of [`Lagrangian`] give them from
    /// [`Lagrangian::derivatives`].
    fn momentum_derivatives(
        &self,
        time: f64,
        configuration: &ElementOf<Self, D>,
        velocity: &SVector<f64, D>,
    ) -> Option<(SMatrix<f64, D, D>, SMatrix<f64, D, D>)> {
        let _ = (time, configuration, velocity);
        None
    }

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
        out: &mut <Self::Group as ConfigurationGroup<D>>::Jet,
    ) -> bool {
        let _ = (chart, point, out);
        false
    }

    /// [`GroupLagrangian::point_derivatives`], handing back in `transport` the chart's
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
        out: &mut <Self::Group as ConfigurationGroup<D>>::Jet,
        transport: &mut Option<PointTransport<D>>,
    ) -> bool {
        *transport = None;
        self.point_derivatives(chart, point, out)
    }

    /// Every Gauss point of an assembly at once: point `j` written into `out[j]` and
    /// `transports[j]` as [`GroupLagrangian::point_derivatives_and_transport`] would write
    /// them one by one, and the force's power `F·ξ` at it into `power[j]` (NaN unforced);
    /// `true` if written, `false` (the default, nothing written) to have the points taken
    /// one by one. SO(3) Lagrangians ([`Lagrangian`]) that are left-invariant or whose
    /// attitude term is linear in `R`, under a force that does not read the attitude,
    /// take four points at a time, the same bits as one by one. An internal fast path,
    /// hidden from the documentation while its form may change.
    #[doc(hidden)]
    fn points_in_lanes<C: GroupChart<Self::Group, D>>(
        &self,
        chart: &C,
        points: &GaussPoints<'_, Self::Group, D>,
        out: &mut [<Self::Group as ConfigurationGroup<D>>::Jet],
        transports: &mut [Option<PointTransport<D>>],
        power: &mut [f64],
    ) -> bool {
        let _ = (chart, points, out, transports, power);
        false
    }

    /// Why the state lies outside what the system models, if it does (an
    /// [`crate::OrbitingBody`] whose mass surrounds the attracting point, where its
    /// far-field potential does not hold): a sentence saying what to change. Read only when a step has failed
    /// ([`crate::Integrator::step`] then returns [`crate::MechanicsError::OutsideModel`] with the
    /// failure as its source), so it costs nothing on the steps that succeed. The default
    /// is `None`: the system models every state.
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
    /// [`GroupLagrangian::parameter_lagrangian`]'s index. The default: none. The built-in
    /// bodies name the six entries of the inertia tensor
    /// ([`crate::inertia::INERTIA_PARAMETERS`]) and, where `ℓ` has one, the mass (and
    /// the gyrostat its wheels' inertias). Forces do not depend on these parameters. A
    /// type that wraps other systems should forward it (and
    /// [`GroupLagrangian::parameter_lagrangian`]).
    fn parameter_names(&self) -> Vec<String> {
        Vec::new()
    }

    /// `∂ℓ/∂p_k(t, g, ξ)`, the derivative of [`GroupLagrangian::lagrangian`] in parameter
    /// `k` of [`GroupLagrangian::parameter_names`] at the system's own parameters,
    /// generic over the scalar as `ℓ` is: a step's derivative in `p_k` is its residual
    /// with `ℓ` replaced by this (the residual is linear in `ℓ`; `docs/linearization.md`
    /// §8). Must be exact: the linearisation is as accurate as it. Where
    /// [`GroupLagrangian::is_left_invariant`] is true it must not depend on the
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

    /// As [`GroupLagrangian::point_derivatives`] for the Lagrangian
    /// [`GroupLagrangian::parameter_lagrangian`] of parameter `index` (no force: the
    /// point's force is `None`): a faster path for the step's parameter columns, or
    /// `false` (the default) for the generic chain rule by dual numbers through `∂ℓ/∂p`
    /// (the chart's derivatives from [`GroupChart::with_derivatives`]). The built-in SE(3) bodies take the rotation–translation chart's
    /// 3 × 3 blocks with `∂ℓ/∂p`'s local derivatives in closed form (five times faster
    /// on the orbiting body; `docs/linearization.md` §8). On SO(3) the generic rule was
    /// measured faster than the Rodrigues form with `∂ℓ/∂p`'s derivatives by dual
    /// numbers, and is kept.
    fn parameter_point_derivatives<C: GroupChart<Self::Group, D>>(
        &self,
        index: usize,
        chart: &C,
        point: &GaussPoint<'_, Self::Group, D>,
        out: &mut <Self::Group as ConfigurationGroup<D>>::Jet,
    ) -> bool {
        let _ = (index, chart, point, out);
        false
    }

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

/// The derivatives of `L(η, ξ) = ℓ(t, g exp(η), ξ)` at `η = 0` for a Lagrangian whose
/// kinetic energy does not depend on the configuration (`∂²L/∂η∂ξ = 0`).
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

impl<S: GroupLagrangian<D>, const D: usize> Forcing<S::Group, D> for SystemForce<'_, S> {
    fn force<T: RealField + Copy>(
        &self,
        time: f64,
        configuration: &ElementOf<S, D, T>,
        velocity: &SVector<T, D>,
    ) -> SVector<T, D> {
        self.0.force(time, configuration, velocity)
    }
}

impl<L: Lagrangian> GroupLagrangian<3> for L {
    type Group = Rotations;

    fn lagrangian<T: RealField + Copy>(&self, _time: f64, g: &SO3<T>, w: &Vector3<T>) -> T {
        Lagrangian::lagrangian(self, g.matrix(), w)
    }
    fn is_left_invariant(&self) -> bool {
        Lagrangian::is_left_invariant(self)
    }
    fn symmetry_generator(&self) -> Option<Vector3<f64>> {
        Lagrangian::symmetry_axis(self)
    }
    fn velocity_from_momentum(
        &self,
        _time: f64,
        g: &SO3,
        mu: &Vector3<f64>,
    ) -> Option<Vector3<f64>> {
        Lagrangian::velocity_from_momentum(self, g.matrix(), mu)
    }
    /// `|Ω|` and the system's natural frequency ([`Lagrangian::natural_frequency`]).
    fn motion_rate(&self, _time: f64, _g: &SO3, w: &Vector3<f64>) -> f64 {
        w.norm() + Lagrangian::natural_frequency(self)
    }
    fn point_derivatives<C: GroupChart<Rotations, 3>>(
        &self,
        chart: &C,
        point: &GaussPoint<'_, Rotations, 3>,
        out: &mut Stacked<9>,
    ) -> bool {
        crate::jet::point_derivatives(self, chart, point, out, &mut None)
    }
    fn point_derivatives_and_transport<C: GroupChart<Rotations, 3>>(
        &self,
        chart: &C,
        point: &GaussPoint<'_, Rotations, 3>,
        out: &mut Stacked<9>,
        transport: &mut Option<PointTransport<3>>,
    ) -> bool {
        crate::jet::point_derivatives(self, chart, point, out, transport)
    }
    fn points_in_lanes<C: GroupChart<Rotations, 3>>(
        &self,
        chart: &C,
        points: &GaussPoints<'_, Rotations, 3>,
        out: &mut [Stacked<9>],
        transports: &mut [Option<PointTransport<3>>],
        power: &mut [f64],
    ) -> bool {
        crate::jet_lanes::points_in_lanes(self, chart, points, out, transports, power)
    }
    fn model_breakdown(&self, _time: f64, g: &SO3, w: &Vector3<f64>) -> Option<String> {
        Lagrangian::model_breakdown(self, g.matrix(), w)
    }
    fn parameter_names(&self) -> Vec<String> {
        Lagrangian::parameter_names(self)
    }
    fn parameter_lagrangian<T: RealField + Copy>(
        &self,
        index: usize,
        _time: f64,
        g: &SO3<T>,
        w: &Vector3<T>,
    ) -> T {
        Lagrangian::parameter_lagrangian(self, index, g.matrix(), w)
    }
    /// From [`Lagrangian::derivatives`]: `∂²L/∂Ω∂η_b = Σ_ij ∂²ℓ/∂R_ij∂Ω (R ê_b)_ij`.
    fn momentum_derivatives(
        &self,
        _time: f64,
        g: &SO3,
        w: &Vector3<f64>,
    ) -> Option<(Matrix3<f64>, Matrix3<f64>)> {
        let r = g.matrix();
        let l = Lagrangian::derivatives(self, r, w);
        let mut mixed = Matrix3::zeros();
        if let Some(h) = l.mixed_hessian {
            for b in 0..3 {
                let dr = r * lgsvi_lie::so3::hat(&Vector3::ith(b, 1.0));
                for c in 0..3 {
                    mixed[(c, b)] = (0..9).map(|k| h[(k, c)] * dr[(k / 3, k % 3)]).sum();
                }
            }
        }
        Some((mixed, l.velocity_hessian))
    }
    fn flow_guess<C: GroupChart<Rotations, 3>>(
        &self,
        chart: &C,
        start: &FlowStart<'_, Rotations, 3>,
        out: &mut [Vector3<f64>],
    ) -> FlowGuess<SO3> {
        crate::flow::flow_guess(self, chart, start, out)
    }
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

impl<S: GroupLagrangian<D>, F: Forcing<S::Group, D>, const D: usize> GroupLagrangian<D>
    for Forced<S, F>
{
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
        out: &mut <Self::Group as ConfigurationGroup<D>>::Jet,
    ) -> bool {
        self.system.point_derivatives(chart, point, out)
    }
    fn point_derivatives_and_transport<C: GroupChart<Self::Group, D>>(
        &self,
        chart: &C,
        point: &GaussPoint<'_, Self::Group, D>,
        out: &mut <Self::Group as ConfigurationGroup<D>>::Jet,
        transport: &mut Option<PointTransport<D>>,
    ) -> bool {
        self.system
            .point_derivatives_and_transport(chart, point, out, transport)
    }
    fn points_in_lanes<C: GroupChart<Self::Group, D>>(
        &self,
        chart: &C,
        points: &GaussPoints<'_, Self::Group, D>,
        out: &mut [<Self::Group as ConfigurationGroup<D>>::Jet],
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
        out: &mut <Self::Group as ConfigurationGroup<D>>::Jet,
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
