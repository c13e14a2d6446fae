//! Rigid bodies on SE(3): rotation and translation together.
//!
//! The configuration is `g = (R, x)` (`world_from_body`, `x` the centre of mass in the
//! world frame), the body velocity `ξ = (Ω, v)` with `ẋ = R v`; users read `ẋ` from
//! [`crate::State::linear_velocity`]. With the centre of mass as the body origin the
//! kinetic energy splits, `ℓ = ½ΩᵀJΩ + ½m|v|² − V(R, x)` (`|v| = |ẋ|`). The body momentum
//! is `μ = (JΩ, m v)`; the spatial momentum `Ad_{g⁻¹}ᵀ μ = (RJΩ + x × mẋ, mẋ)` is the
//! angular momentum about the world origin and the linear momentum.

use crate::error::{check_finite, MechanicsError};
use crate::group::RigidMotions;
use crate::inertia::Inertia;
use crate::lagrangian::kinetic;
use crate::system::GroupLagrangian;
use lgsvi_lie::SE3;
use nalgebra::{Matrix3, RealField, SVector, Vector3};

fn check_mass(mass: f64) -> Result<(), MechanicsError> {
    check_finite("mass", &[mass])?;
    if mass > 0.0 {
        Ok(())
    } else {
        Err(MechanicsError::InvalidSetting {
            name: "mass",
            value: mass.to_string(),
            reason: "must be positive",
        })
    }
}

/// `½ΩᵀJΩ + ½m|v|²`.
fn kinetic6<T: RealField + Copy>(inertia: &Inertia, mass: f64, xi: &SVector<T, 6>) -> T {
    let w = Vector3::new(xi[0], xi[1], xi[2]);
    let v = Vector3::new(xi[3], xi[4], xi[5]);
    let half_mass: T = nalgebra::convert(0.5 * mass);
    kinetic(inertia, &w) + half_mass * v.dot(&v)
}

/// `(J⁻¹μ_ω, μ_v/m)`.
fn velocity6(inertia: &Inertia, mass: f64, mu: &SVector<f64, 6>) -> SVector<f64, 6> {
    let w = inertia.velocity(&mu.fixed_rows::<3>(0).into_owned());
    let v = mu.fixed_rows::<3>(3) / mass;
    SVector::<f64, 6>::new(w.x, w.y, w.z, v.x, v.y, v.z)
}

/// A free rigid body in space: `ℓ = ½ΩᵀJΩ + ½m|v|²`. The rotation is the free rigid
/// body's; the centre of mass moves in a straight line. Energy and the spatial momentum
/// `(RJΩ + x × mẋ, mẋ)` are conserved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreeBody {
    inertia: Inertia,
    mass: f64,
}

impl FreeBody {
    /// A body of inertia `J` (about its centre of mass) and mass `m > 0`.
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`] or [`MechanicsError::InvalidSetting`] for the mass.
    pub fn new(inertia: Inertia, mass: f64) -> Result<Self, MechanicsError> {
        check_mass(mass)?;
        Ok(Self { inertia, mass })
    }

    /// Its inertia.
    pub fn inertia(&self) -> &Inertia {
        &self.inertia
    }

    /// Its mass.
    pub fn mass(&self) -> f64 {
        self.mass
    }
}

impl GroupLagrangian<6> for FreeBody {
    type Group = RigidMotions;
    fn lagrangian<T: RealField + Copy>(&self, _t: f64, _g: &SE3<T>, xi: &SVector<T, 6>) -> T {
        kinetic6(&self.inertia, self.mass, xi)
    }
    fn is_left_invariant(&self) -> bool {
        true
    }
    fn velocity_from_momentum(
        &self,
        _t: f64,
        _g: &SE3,
        mu: &SVector<f64, 6>,
    ) -> Option<SVector<f64, 6>> {
        Some(velocity6(&self.inertia, self.mass, mu))
    }
}

/// A potential `V(t, R, x)` on SE(3), written once generically over the scalar.
pub trait FieldPotential {
    /// `V` at time `t`, attitude `R` (`world_from_body`) and centre of mass `x` (world).
    fn potential<T: RealField + Copy>(
        &self,
        time: f64,
        attitude: &Matrix3<T>,
        position: &Vector3<T>,
    ) -> T;
}

/// A rigid body in a potential of your own: `ℓ = ½ΩᵀJΩ + ½m|v|² − V(t, R, x)`.
///
/// ```
/// use lgsvi_mechanics::{BodyInField, FieldPotential, Inertia, Integrator, StepSettings};
/// use lgsvi_mechanics::lie::{SE3, SO3};
/// use nalgebra::{Matrix3, RealField, SVector, Vector3};
/// /// Uniform gravity g along −z on a body of mass 2: V = m g x_z.
/// struct Gravity;
/// impl FieldPotential for Gravity {
///     fn potential<T: RealField + Copy>(&self, _t: f64, _r: &Matrix3<T>, x: &Vector3<T>) -> T {
///         x.z * nalgebra::convert::<f64, T>(2.0 * 9.81)
///     }
/// }
/// let body = BodyInField::new(Inertia::from_principal_moments([1.0, 1.0, 1.5])?, 2.0, Gravity)?;
/// let mut it = Integrator::new(body, StepSettings::new(0.1, 5)?, SE3::identity(), SVector::<f64, 6>::zeros())?;
/// it.run(10, 1)?;
/// // Free fall: x_z = −g t²/2 at t = 1.
/// assert!((it.state().position().z + 0.5 * 9.81).abs() < 1e-12);
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyInField<V> {
    inertia: Inertia,
    mass: f64,
    potential: V,
}

impl<V: FieldPotential> BodyInField<V> {
    /// A body of inertia `J`, mass `m > 0`, in the potential `V`.
    ///
    /// # Errors
    /// As [`FreeBody::new`].
    pub fn new(inertia: Inertia, mass: f64, potential: V) -> Result<Self, MechanicsError> {
        check_mass(mass)?;
        Ok(Self {
            inertia,
            mass,
            potential,
        })
    }

    /// The potential.
    pub fn potential(&self) -> &V {
        &self.potential
    }

    /// The potential, to change between steps.
    pub fn potential_mut(&mut self) -> &mut V {
        &mut self.potential
    }
}

impl<V: FieldPotential> GroupLagrangian<6> for BodyInField<V> {
    type Group = RigidMotions;
    fn lagrangian<T: RealField + Copy>(&self, t: f64, g: &SE3<T>, xi: &SVector<T, 6>) -> T {
        kinetic6(&self.inertia, self.mass, xi)
            - self
                .potential
                .potential(t, g.rotation().matrix(), g.translation())
    }
    fn velocity_from_momentum(
        &self,
        _t: f64,
        _g: &SE3,
        mu: &SVector<f64, 6>,
    ) -> Option<SVector<f64, 6>> {
        Some(velocity6(&self.inertia, self.mass, mu))
    }
}

/// A rigid body orbiting a fixed point mass (the full body problem about a fixed centre),
/// with MacCullagh's second-order potential
/// `V = −μm/r − (μ/(2r³))(tr J − 3 x̂ᵀRJRᵀx̂)`, `r = |x|`, `x̂ = x/r`, `μ = GM`: the
/// gravity-gradient torque couples the attitude and the orbit. Energy and the total
/// angular momentum `m x × ẋ + RJΩ` are conserved.
///
/// ```
/// use lgsvi_mechanics::{Inertia, Integrator, OrbitingBody, StepSettings};
/// use lgsvi_mechanics::lie::{SE3, SO3};
/// use nalgebra::{SVector, Vector3};
/// let body = OrbitingBody::new(Inertia::from_principal_moments([0.3, 0.2, 0.4])?, 1.0, 1.0)?;
/// let start = SE3::new(SO3::identity(), Vector3::new(3.0, 0.0, 0.0));
/// let xi = SVector::<f64, 6>::new(0.2, -0.3, 0.5, 0.0, 0.55, 0.05);
/// let mut it = Integrator::new(body, StepSettings::new(0.5, 8)?, start, xi)?;
/// let (e0, l0) = (it.state().energy(&body), it.state().spatial_momentum());
/// it.run(40, 1)?;
/// assert!((it.state().energy(&body) - e0).abs() < 1e-9);
/// assert!((it.state().spatial_momentum() - l0).fixed_rows::<3>(0).amax() < 1e-13);
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitingBody {
    inertia: Inertia,
    mass: f64,
    gravitational_parameter: f64,
}

impl OrbitingBody {
    /// A body of inertia `J` and mass `m > 0` about a point mass of gravitational
    /// parameter `μ = GM ≥ 0` at the origin.
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`]; [`MechanicsError::InvalidSetting`] for `m ≤ 0` or
    /// `μ < 0`.
    pub fn new(
        inertia: Inertia,
        mass: f64,
        gravitational_parameter: f64,
    ) -> Result<Self, MechanicsError> {
        check_mass(mass)?;
        check_finite("mu", &[gravitational_parameter])?;
        if gravitational_parameter < 0.0 {
            return Err(MechanicsError::InvalidSetting {
                name: "mu",
                value: gravitational_parameter.to_string(),
                reason: "the gravitational parameter GM must be non-negative",
            });
        }
        Ok(Self {
            inertia,
            mass,
            gravitational_parameter,
        })
    }

    /// Its inertia.
    pub fn inertia(&self) -> &Inertia {
        &self.inertia
    }

    /// Its mass.
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// `μ = GM`.
    pub fn gravitational_parameter(&self) -> f64 {
        self.gravitational_parameter
    }

    /// MacCullagh's potential at attitude `R`, position `x`.
    pub fn potential<T: RealField + Copy>(&self, r: &Matrix3<T>, x: &Vector3<T>) -> T {
        let mu: T = nalgebra::convert(self.gravitational_parameter);
        let m: T = nalgebra::convert(self.mass);
        let j: Matrix3<T> = self.inertia.matrix().map(nalgebra::convert);
        let three: T = nalgebra::convert(3.0);
        let half: T = nalgebra::convert(0.5);
        let r2 = x.dot(x);
        let dist = r2.sqrt();
        // x̂ᵀRJRᵀx̂ = bᵀJb with b = Rᵀx/r.
        let b = r.transpose() * x / dist;
        let gradient_term = j.trace() - three * b.dot(&(j * b));
        -mu * m / dist - half * mu * gradient_term / (r2 * dist)
    }
}

impl GroupLagrangian<6> for OrbitingBody {
    type Group = RigidMotions;
    fn lagrangian<T: RealField + Copy>(&self, _t: f64, g: &SE3<T>, xi: &SVector<T, 6>) -> T {
        kinetic6(&self.inertia, self.mass, xi)
            - self.potential(g.rotation().matrix(), g.translation())
    }
    fn velocity_from_momentum(
        &self,
        _t: f64,
        _g: &SE3,
        mu: &SVector<f64, 6>,
    ) -> Option<SVector<f64, 6>> {
        Some(velocity6(&self.inertia, self.mass, mu))
    }
}
