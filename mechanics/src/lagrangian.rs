//! Reduced, left-trivialised Lagrangians `ℓ(R, Ω)` on SO(3) and the built-in systems.

use crate::error::{check_finite, MechanicsError};
use crate::inertia::Inertia;
use nalgebra::{Matrix3, RealField, Vector3};

/// A reduced Lagrangian `ℓ(R, Ω)` with `R = world_from_body` and body angular velocity
/// `Ω` (`Ṙ = RΩ̂`).
///
/// Write `ℓ` once, generically over the scalar: the integrator differentiates it exactly
/// (gradients and Hessians by dual numbers), so no derivative is ever derived by hand.
/// Body momentum is `μ = ∂ℓ/∂Ω`, energy `⟨μ, Ω⟩ − ℓ`.
///
/// ```
/// use lgsvi_mechanics::Lagrangian;
/// use nalgebra::{Matrix3, RealField, Vector3};
///
/// /// A spherical body in a potential that pulls its body z axis towards world x.
/// struct Compass;
/// impl Lagrangian for Compass {
///     fn lagrangian<T: RealField + Copy>(&self, r: &Matrix3<T>, w: &Vector3<T>) -> T {
///         let half: T = nalgebra::convert(0.5);
///         half * w.dot(w) + r[(0, 2)] // ½|Ω|² − V(R), V = −(R e₃)·e₁
///     }
/// }
/// ```
pub trait Lagrangian {
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
}

/// The free rigid body, `ℓ = ½ΩᵀJΩ`.
///
/// ```
/// use lgsvi_mechanics::{Inertia, Lagrangian, RigidBody};
/// use nalgebra::{Matrix3, Vector3};
/// let body = RigidBody::new(Inertia::from_principal_moments([3.3, 2.5, 3.4])?);
/// let l = body.lagrangian(&Matrix3::identity(), &Vector3::new(1.0, 0.0, 0.0));
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

fn kinetic<T: RealField + Copy>(inertia: &Inertia, w: &Vector3<T>) -> T {
    let [a, b, c] = inertia.principal_moments();
    let half: T = nalgebra::convert(0.5);
    half * (w.x * w.x * nalgebra::convert(a)
        + w.y * w.y * nalgebra::convert(b)
        + w.z * w.z * nalgebra::convert(c))
}

impl Lagrangian for RigidBody {
    fn lagrangian<T: RealField + Copy>(&self, _r: &Matrix3<T>, w: &Vector3<T>) -> T {
        kinetic(&self.inertia, w)
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
        let norm = gravity_direction.norm();
        if norm == 0.0 {
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
            gravity_direction: gravity_direction / norm,
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
    fn is_left_invariant(&self) -> bool {
        self.mass * self.gravity == 0.0
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
    fn velocity_from_momentum(&self, _r: &Matrix3<f64>, mu: &Vector3<f64>) -> Option<Vector3<f64>> {
        Some(self.inertia.velocity(mu))
    }
}
