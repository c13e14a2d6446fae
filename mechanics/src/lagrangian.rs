//! Reduced, left-trivialised Lagrangians `ℓ(R, Ω)` on SO(3) and the built-in systems.

use crate::error::{check_finite, MechanicsError};
use crate::inertia::Inertia;
use nalgebra::{Matrix3, RealField, SMatrix, SVector, Vector3};
use num_dual::Dual2SVec64;

/// First and second derivatives of `ℓ(R, Ω)` at one point, with `R`'s nine entries taken
/// as independent variables (flattened row-major: index `3a + b` is `R_ab`).
///
/// The integrator assembles its exact Newton matrices from these and the chart's own
/// derivatives. [`Lagrangian::derivatives`] computes them by dual numbers; the built-in
/// systems give them in closed form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LagrangianDerivatives {
    /// `∂ℓ/∂R_ab`.
    pub attitude_gradient: Matrix3<f64>,
    /// `∂ℓ/∂Ω`, the body momentum `μ`.
    pub velocity_gradient: Vector3<f64>,
    /// `∂²ℓ/∂Ω²`.
    pub velocity_hessian: Matrix3<f64>,
    /// `∂²ℓ/∂R_ab ∂R_cd` at `(3a + b, 3c + d)`; `None` when it is zero.
    pub attitude_hessian: Option<SMatrix<f64, 9, 9>>,
    /// `∂²ℓ/∂R_ab ∂Ω_c` at `(3a + b, c)`; `None` when it is zero.
    pub mixed_hessian: Option<SMatrix<f64, 9, 3>>,
}

impl LagrangianDerivatives {
    /// The derivatives by dual numbers (second order, in the 3 entries of `Ω`, or in the 12
    /// of `(R, Ω)` unless `attitude_free`).
    pub fn by_dual_numbers<L: Lagrangian + ?Sized>(
        system: &L,
        world_from_body: &Matrix3<f64>,
        omega: &Vector3<f64>,
        attitude_free: bool,
    ) -> Self {
        if attitude_free {
            let r: Matrix3<Dual2SVec64<3>> = world_from_body.map(nalgebra::convert);
            let (_, gradient, hessian) = num_dual::hessian(
                |w: SVector<Dual2SVec64<3>, 3>| system.lagrangian(&r, &w),
                omega,
            );
            return Self {
                attitude_gradient: Matrix3::zeros(),
                velocity_gradient: gradient,
                velocity_hessian: hessian,
                attitude_hessian: None,
                mixed_hessian: None,
            };
        }
        let mut y = SVector::<f64, 12>::zeros();
        for a in 0..3 {
            for b in 0..3 {
                y[3 * a + b] = world_from_body[(a, b)];
            }
            y[9 + a] = omega[a];
        }
        let (_, gradient, hessian) = num_dual::hessian(
            |y: SVector<Dual2SVec64<12>, 12>| {
                let r = Matrix3::from_fn(|a, b| y[3 * a + b]);
                let w = Vector3::new(y[9], y[10], y[11]);
                system.lagrangian(&r, &w)
            },
            &y,
        );
        Self {
            attitude_gradient: Matrix3::from_fn(|a, b| gradient[3 * a + b]),
            velocity_gradient: gradient.fixed_rows::<3>(9).into_owned(),
            velocity_hessian: hessian.fixed_view::<3, 3>(9, 9).into_owned(),
            attitude_hessian: Some(hessian.fixed_view::<9, 9>(0, 0).into_owned()),
            mixed_hessian: Some(hessian.fixed_view::<9, 3>(0, 9).into_owned()),
        }
    }
}

/// The built-in SO(3) systems' reduced Lagrangian `ℓ(R, Ω)` (`R = world_from_body`, body
/// angular velocity `Ω`, `Ṙ = RΩ̂`) with the closed forms of its derivatives and the facts
/// the SO(3) fast paths read ([`crate::System`] for them comes from `so3_system!`). Body
/// momentum is `μ = ∂ℓ/∂Ω`, energy `⟨μ, Ω⟩ − ℓ`. A system of your own implements
/// [`crate::GroupLagrangian`] instead.
pub(crate) trait Lagrangian {
    /// `ℓ(R, Ω)`.
    fn lagrangian<T: RealField + Copy>(
        &self,
        world_from_body: &Matrix3<T>,
        omega: &Vector3<T>,
    ) -> T;

    /// True when `ℓ` does not depend on `R` (the free rigid body): then the exact
    /// momentum matching has no base-point term and the integrator skips computing it.
    /// The default `false` is always correct.
    fn is_left_invariant(&self) -> bool {
        false
    }

    /// A spatial direction `d` about which `ℓ` is symmetric (`ℓ(exp(θd̂)R, Ω) = ℓ(R, Ω)`),
    /// so that Noether's theorem conserves `d·Rμ` when no force acts: a heavy top's gravity
    /// direction. `None` (the default) claims no such symmetry; a left-invariant `ℓ`
    /// ([`Lagrangian::is_left_invariant`]) conserves all of `Rμ` whatever this says.
    fn symmetry_axis(&self) -> Option<Vector3<f64>> {
        None
    }

    /// `(a, b)` when `R` enters `ℓ` only through the single term `aᵀ R b`, i.e.
    /// `ℓ(R, Ω) = k(Ω) + aᵀRb`: a uniform field `a` (world frame) acting on a body-fixed
    /// vector `b`, as gravity on a top (`a = m g d`, `b = ρ`) or a uniform magnetic field
    /// on a dipole. Then `∂ℓ/∂R = a bᵀ` at every `(R, Ω)`, the attitude Hessians vanish
    /// and the integrator needs only `Rᵀa`, a rotated vector, where it would otherwise
    /// form `R` at every Gauss point and predictor stage; [`Lagrangian::derivatives`] and
    /// [`Lagrangian::velocity_from_momentum`] may then be called with any `R`. `None`
    /// (the default) is always correct.
    fn linear_attitude_term(&self) -> Option<(Vector3<f64>, Vector3<f64>)> {
        None
    }

    /// The fastest natural motion besides the spin, rad per unit time (a heavy top's
    /// pendulum frequency): with `|Ω|`, the rate a tolerance-driven run's step is sized
    /// for ([`crate::System::motion_rate`]). The default: 0.
    fn natural_frequency(&self) -> f64 {
        0.0
    }

    /// `Ω` from `μ` in closed form where known (`J⁻¹μ` for `ℓ = ½ΩᵀJΩ − V(R)`);
    /// `None` (the default) makes the integrator solve `∂ℓ/∂Ω(R, Ω) = μ` by Newton.
    fn velocity_from_momentum(
        &self,
        world_from_body: &Matrix3<f64>,
        momentum: &Vector3<f64>,
    ) -> Option<Vector3<f64>> {
        let _ = (world_from_body, momentum);
        None
    }

    /// Why the state `(R, Ω)` lies outside what `ℓ` models, if it does: a sentence saying
    /// what to change. Read at each step's end and where a step has failed, as
    /// [`crate::System::model_breakdown`] (which the SO(3) systems take from
    /// here): the step's error is then [`crate::MechanicsError::LeftModel`] or
    /// [`crate::MechanicsError::OutsideModel`]. `None`
    /// (the default): `ℓ` models every state. A type that wraps other Lagrangians should
    /// forward it.
    fn model_breakdown(
        &self,
        world_from_body: &Matrix3<f64>,
        omega: &Vector3<f64>,
    ) -> Option<String> {
        let _ = (world_from_body, omega);
        None
    }

    /// The names of the physical parameters `p` of `ℓ` that a step can be differentiated
    /// by ([`crate::Integrator::linearize_with_parameters`]), in the order of
    /// [`Lagrangian::parameter_lagrangian`]'s index. The default: none. The built-in
    /// bodies name the six entries of the inertia tensor ([`crate::inertia::INERTIA_PARAMETERS`]) and,
    /// where `ℓ` has one, the mass. A type that wraps other Lagrangians should forward it
    /// (and [`Lagrangian::parameter_lagrangian`]).
    fn parameter_names(&self) -> Vec<String> {
        Vec::new()
    }

    /// `∂ℓ/∂p_k(R, Ω)`, the derivative of [`Lagrangian::lagrangian`] in parameter `k` of
    /// [`Lagrangian::parameter_names`] at the system's own parameters, generic over the
    /// scalar as `ℓ` is (the step's derivative in `p_k` is the step's residual with `ℓ`
    /// replaced by this, `docs/notes/linearization.md` §8). Must be exact: the linearisation
    /// is as accurate as it. Where [`Lagrangian::is_left_invariant`] is true it must not
    /// depend on `R` either. The default (no parameters) is zero.
    fn parameter_lagrangian<T: RealField + Copy>(
        &self,
        index: usize,
        world_from_body: &Matrix3<T>,
        omega: &Vector3<T>,
    ) -> T {
        let _ = (index, world_from_body, omega);
        T::zero()
    }

    /// First and second derivatives of `ℓ` at `(R, Ω)`, which the Newton matrices are
    /// built from. The default takes them by dual numbers (exact); override it only to go
    /// faster, with a closed form (the built-in systems do). A type that wraps other
    /// Lagrangians (an enum of systems, say) should forward this method too (and
    /// [`Lagrangian::linear_attitude_term`]): the default is exact but about ten times
    /// slower per step than the built-ins' closed forms.
    fn derivatives(
        &self,
        world_from_body: &Matrix3<f64>,
        omega: &Vector3<f64>,
    ) -> LagrangianDerivatives {
        LagrangianDerivatives::by_dual_numbers(
            self,
            world_from_body,
            omega,
            self.is_left_invariant(),
        )
    }
}

/// Closed-form derivatives of `½ΩᵀJΩ + ⟨G, R⟩` (a potential linear in `R`).
fn quadratic_kinetic_derivatives(
    inertia: &Inertia,
    omega: &Vector3<f64>,
    attitude_gradient: Matrix3<f64>,
) -> LagrangianDerivatives {
    LagrangianDerivatives {
        attitude_gradient,
        velocity_gradient: inertia.momentum(omega),
        velocity_hessian: inertia.matrix(),
        attitude_hessian: None,
        mixed_hessian: None,
    }
}

/// The free rigid body, `ℓ = ½ΩᵀJΩ`.
///
/// ```
/// use lgsvi_mechanics::lie::SO3;
/// use lgsvi_mechanics::{Inertia, RigidBody, System};
/// use nalgebra::Vector3;
/// let body = RigidBody::new(Inertia::from_principal_moments([3.3, 2.5, 3.4])?);
/// let l = body.lagrangian(0.0, &SO3::identity(), &Vector3::new(1.0, 0.0, 0.0));
/// assert_eq!(l, 1.65);
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidBody {
    inertia: Inertia,
}

impl RigidBody {
    /// A free rigid body of the given inertia.
    pub fn new(inertia: Inertia) -> Self {
        Self { inertia }
    }

    /// Its inertia.
    pub fn inertia(&self) -> &Inertia {
        &self.inertia
    }
}

/// `½ΩᵀJΩ` (for a diagonal `J`, the three products written out, as they always were).
pub(crate) fn kinetic<T: RealField + Copy>(inertia: &Inertia, w: &Vector3<T>) -> T {
    let half: T = nalgebra::convert(0.5);
    if !inertia.is_diagonal() {
        let j: Matrix3<T> = inertia.matrix().map(nalgebra::convert);
        return half * w.dot(&(j * w));
    }
    let [a, b, c] = inertia.principal_moments();
    half * (w.x * w.x * nalgebra::convert(a)
        + w.y * w.y * nalgebra::convert(b)
        + w.z * w.z * nalgebra::convert(c))
}

/// `½ΩᵀEΩ` with `E = ∂J/∂p` of inertia parameter `index` ([`Inertia::parameter_direction`]):
/// the kinetic energy's derivative in that entry; zero past the sixth.
pub(crate) fn kinetic_parameter<T: RealField + Copy>(index: usize, w: &Vector3<T>) -> T {
    match Inertia::parameter_direction(index) {
        Some(direction) => {
            let e: Matrix3<T> = direction.map(nalgebra::convert);
            w.dot(&(e * w)) * nalgebra::convert::<f64, T>(0.5)
        }
        None => T::zero(),
    }
}

/// [`INERTIA_PARAMETERS`](crate::inertia::INERTIA_PARAMETERS) followed by `extra`.
pub(crate) fn inertia_parameter_names(extra: &[&str]) -> Vec<String> {
    crate::inertia::INERTIA_PARAMETERS
        .iter()
        .chain(extra)
        .map(|name| name.to_string())
        .collect()
}

impl Lagrangian for RigidBody {
    fn lagrangian<T: RealField + Copy>(&self, _r: &Matrix3<T>, w: &Vector3<T>) -> T {
        kinetic(&self.inertia, w)
    }
    /// The inertia tensor's six entries.
    fn parameter_names(&self) -> Vec<String> {
        inertia_parameter_names(&[])
    }
    fn parameter_lagrangian<T: RealField + Copy>(
        &self,
        index: usize,
        _r: &Matrix3<T>,
        w: &Vector3<T>,
    ) -> T {
        kinetic_parameter(index, w)
    }
    fn derivatives(&self, _r: &Matrix3<f64>, w: &Vector3<f64>) -> LagrangianDerivatives {
        quadratic_kinetic_derivatives(&self.inertia, w, Matrix3::zeros())
    }
    fn is_left_invariant(&self) -> bool {
        true
    }
    fn velocity_from_momentum(&self, _r: &Matrix3<f64>, mu: &Vector3<f64>) -> Option<Vector3<f64>> {
        Some(self.inertia.velocity(mu))
    }
}

/// The heavy top / 3D pendulum: `ℓ = ½ΩᵀJΩ + m g dᵀ R ρ`, with `ρ` the centre of mass in
/// the body frame (from the pivot) and `d` the unit direction gravity pulls in (world
/// frame). With the paper's `d = e₃`, `ρ = (0, 0, 1)`: `R = I` is the stable equilibrium
/// and `R = diag(−1, 1, −1)` the unstable one. Energy `½ΩᵀJΩ − m g dᵀRρ`; the momentum
/// about the vertical, `dᵀRμ`, is conserved.
///
/// ```
/// use lgsvi_mechanics::{HeavyTop, Inertia};
/// let top = HeavyTop::paper(Inertia::from_paper_jd([1.0, 2.8, 2.0])?)?; // m = 1, g = 9.81
/// assert_eq!(top.mass_times_gravity(), 9.81);
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeavyTop {
    inertia: Inertia,
    mass: f64,
    gravity: f64,
    center_of_mass: Vector3<f64>,
    gravity_direction: Vector3<f64>,
}

impl HeavyTop {
    /// A heavy top with mass `m ≥ 0`, gravitational acceleration `g ≥ 0`, centre of mass
    /// `ρ` (body frame) and gravity pulling along `gravity_direction` (world frame,
    /// normalised here).
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`]; [`MechanicsError::InvalidSetting`] for a negative
    /// mass or gravity or a zero direction.
    pub fn new(
        inertia: Inertia,
        mass: f64,
        gravity: f64,
        center_of_mass: Vector3<f64>,
        gravity_direction: Vector3<f64>,
    ) -> Result<Self, MechanicsError> {
        check_finite("mass", &[mass])?;
        check_finite("gravity", &[gravity])?;
        check_finite("centre of mass", center_of_mass.as_slice())?;
        check_finite("gravity direction", gravity_direction.as_slice())?;
        if mass < 0.0 {
            return Err(MechanicsError::InvalidSetting {
                name: "mass",
                value: mass.to_string(),
                reason: "must be non-negative",
            });
        }
        if gravity < 0.0 {
            return Err(MechanicsError::InvalidSetting {
                name: "gravity",
                value: gravity.to_string(),
                reason: "must be non-negative (set the direction with gravity_direction)",
            });
        }
        // Scaled by its largest component first: the norm of a direction like 1e200·e₃
        // would overflow (and the direction become zero).
        let largest = gravity_direction.amax();
        if largest == 0.0 {
            return Err(MechanicsError::InvalidSetting {
                name: "gravity direction",
                value: format!("{:?}", gravity_direction.as_slice()),
                reason: "must be a non-zero vector",
            });
        }
        Ok(Self {
            inertia,
            mass,
            gravity,
            center_of_mass,
            gravity_direction: (gravity_direction / largest).normalize(),
        })
    }

    /// The paper's 3D pendulum: `m = 1`, `g = 9.81`, `ρ = (0, 0, 1)`, `d = e₃`.
    ///
    /// # Errors
    /// None in practice (the parameters are valid); kept fallible like [`HeavyTop::new`].
    pub fn paper(inertia: Inertia) -> Result<Self, MechanicsError> {
        Self::new(inertia, 1.0, 9.81, Vector3::z(), Vector3::z())
    }

    /// Its inertia.
    pub fn inertia(&self) -> &Inertia {
        &self.inertia
    }

    /// `m g`.
    pub fn mass_times_gravity(&self) -> f64 {
        self.mass * self.gravity
    }

    /// The mass `m`.
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// The gravitational acceleration `g`.
    pub fn gravity(&self) -> f64 {
        self.gravity
    }

    /// `ρ`.
    pub fn center_of_mass(&self) -> &Vector3<f64> {
        &self.center_of_mass
    }

    /// `d`.
    pub fn gravity_direction(&self) -> &Vector3<f64> {
        &self.gravity_direction
    }
}

impl Lagrangian for HeavyTop {
    fn lagrangian<T: RealField + Copy>(&self, r: &Matrix3<T>, w: &Vector3<T>) -> T {
        let rho: Vector3<T> = self.center_of_mass.map(nalgebra::convert);
        let d: Vector3<T> = self.gravity_direction.map(nalgebra::convert);
        let mg: T = nalgebra::convert(self.mass * self.gravity);
        kinetic(&self.inertia, w) + mg * d.dot(&(r * rho))
    }
    /// The inertia tensor's six entries and the mass (`∂ℓ/∂m = g d·Rρ`).
    fn parameter_names(&self) -> Vec<String> {
        inertia_parameter_names(&["mass"])
    }
    fn parameter_lagrangian<T: RealField + Copy>(
        &self,
        index: usize,
        r: &Matrix3<T>,
        w: &Vector3<T>,
    ) -> T {
        if index == 6 {
            let rho: Vector3<T> = self.center_of_mass.map(nalgebra::convert);
            let d: Vector3<T> = self.gravity_direction.map(nalgebra::convert);
            let g: T = nalgebra::convert(self.gravity);
            g * d.dot(&(r * rho))
        } else {
            kinetic_parameter(index, w)
        }
    }
    /// `∂ℓ/∂R = m g d ρᵀ`; the Hessians in `R` vanish.
    fn derivatives(&self, _r: &Matrix3<f64>, w: &Vector3<f64>) -> LagrangianDerivatives {
        let gradient =
            self.gravity_direction * self.center_of_mass.transpose() * (self.mass * self.gravity);
        quadratic_kinetic_derivatives(&self.inertia, w, gradient)
    }
    fn is_left_invariant(&self) -> bool {
        self.mass * self.gravity == 0.0
    }
    /// The gravity direction `d`: `d·Rμ` is conserved.
    fn symmetry_axis(&self) -> Option<Vector3<f64>> {
        Some(self.gravity_direction)
    }
    /// The small-oscillation frequency `√(m g |ρ| / J_min)` about the least principal
    /// moment.
    fn natural_frequency(&self) -> f64 {
        let lever = self.mass * self.gravity * self.center_of_mass.norm();
        let least = self
            .inertia
            .principal_moments()
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        (lever / least).sqrt()
    }
    /// `a = m g d`, `b = ρ`.
    fn linear_attitude_term(&self) -> Option<(Vector3<f64>, Vector3<f64>)> {
        Some((
            self.gravity_direction * (self.mass * self.gravity),
            self.center_of_mass,
        ))
    }
    fn velocity_from_momentum(&self, _r: &Matrix3<f64>, mu: &Vector3<f64>) -> Option<Vector3<f64>> {
        Some(self.inertia.velocity(mu))
    }
}

/// A potential energy `V(R)`, written once generically over the scalar.
pub trait Potential {
    /// `V(R)`, `R = world_from_body`.
    fn potential<T: RealField + Copy>(&self, world_from_body: &Matrix3<T>) -> T;
}

/// A rigid body in a potential of your own: `ℓ = ½ΩᵀJΩ − V(R)`.
///
/// ```
/// use lgsvi_mechanics::{Inertia, Potential, RigidBodyInPotential};
/// use nalgebra::{Matrix3, RealField};
/// /// A magnetic dipole along body x in a field along world z: V = −(R e₁)·e₃.
/// struct Dipole;
/// impl Potential for Dipole {
///     fn potential<T: RealField + Copy>(&self, r: &Matrix3<T>) -> T { -r[(2, 0)] }
/// }
/// let body = RigidBodyInPotential::new(Inertia::from_principal_moments([1.0, 2.0, 2.5])?, Dipole);
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
#[derive(Debug, Clone)]
pub struct RigidBodyInPotential<V> {
    inertia: Inertia,
    potential: V,
}

impl<V: Potential> RigidBodyInPotential<V> {
    /// A body of inertia `J` in the potential `V`.
    pub fn new(inertia: Inertia, potential: V) -> Self {
        Self { inertia, potential }
    }
}

impl<V: Potential> Lagrangian for RigidBodyInPotential<V> {
    fn lagrangian<T: RealField + Copy>(&self, r: &Matrix3<T>, w: &Vector3<T>) -> T {
        kinetic(&self.inertia, w) - self.potential.potential(r)
    }
    /// The inertia tensor's six entries (the potential's own constants are held).
    fn parameter_names(&self) -> Vec<String> {
        inertia_parameter_names(&[])
    }
    fn parameter_lagrangian<T: RealField + Copy>(
        &self,
        index: usize,
        _r: &Matrix3<T>,
        w: &Vector3<T>,
    ) -> T {
        kinetic_parameter(index, w)
    }
    /// The kinetic part in closed form, `V`'s by dual numbers in `R`'s nine entries.
    fn derivatives(&self, r: &Matrix3<f64>, w: &Vector3<f64>) -> LagrangianDerivatives {
        let mut y = SVector::<f64, 9>::zeros();
        for a in 0..3 {
            for b in 0..3 {
                y[3 * a + b] = r[(a, b)];
            }
        }
        let (_, gradient, hessian) = num_dual::hessian(
            |y: SVector<Dual2SVec64<9>, 9>| {
                -self
                    .potential
                    .potential(&Matrix3::from_fn(|a, b| y[3 * a + b]))
            },
            &y,
        );
        let mut d = quadratic_kinetic_derivatives(
            &self.inertia,
            w,
            Matrix3::from_fn(|a, b| gradient[3 * a + b]),
        );
        d.attitude_hessian = Some(hessian);
        d
    }
    fn velocity_from_momentum(&self, _r: &Matrix3<f64>, mu: &Vector3<f64>) -> Option<Vector3<f64>> {
        Some(self.inertia.velocity(mu))
    }
}
