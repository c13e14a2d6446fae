//! Rigid bodies on SE(3): rotation and translation together.
//!
//! The configuration is `g = (R, x)` (`world_from_body`, `x` the centre of mass in the
//! world frame), the body velocity `ξ = (Ω, v)` with `ẋ = R v`; users read `ẋ` from
//! [`crate::State::linear_velocity`]. With the centre of mass as the body origin the
//! kinetic energy splits, `ℓ = ½ΩᵀJΩ + ½m|v|² − V(R, x)` (`|v| = |ẋ|`). The body momentum
//! is `μ = (JΩ, m v)`; the spatial momentum `Ad_{g⁻¹}ᵀ μ = (RJΩ + x × mẋ, mẋ)` is the
//! angular momentum about the world origin and the linear momentum.
//!
//! A step runs by default in SE(3)'s rotation–translation chart (every `So3Chart`, e.g.
//! `ChartKind::Exp`): the attitude in the SO(3) chart and the centre of mass a polynomial
//! in the world frame, the discrete map of SO(3) × ℝ³; `Screw(chart)` takes SE(3)'s own
//! screw-motion chart instead (`crate::group`). Both conserve the spatial momenta of every
//! symmetry of `ℓ` exactly.

use crate::error::{check_finite, MechanicsError};
use crate::group::{GroupChart, RigidMotions, Stacked};
use crate::inertia::Inertia;
use crate::lagrangian::{inertia_parameter_names, kinetic, kinetic_parameter};
use crate::point::GaussPoint;
use crate::system::{LocalDerivatives, System};
use lgsvi_lie::se3::{blocks, join, split};
use lgsvi_lie::SE3;
use nalgebra::{Matrix3, RealField, SMatrix, SVector, Vector3};
use num_dual::{Dual2SVec64, DualSVec64};

/// The built-in SE(3) systems' Gauss points: by 3 × 3 blocks on the rotation–translation
/// chart (`crate::step::rotation_translation`), the generic chain rule on other charts.
macro_rules! points_by_blocks {
    () => {
        fn point_derivatives<C: GroupChart<RigidMotions, 6>>(
            &self,
            chart: &C,
            point: &GaussPoint<'_, RigidMotions, 6>,
            out: &mut Stacked<18>,
        ) -> bool {
            crate::step::rotation_translation::point_derivatives(self, chart, point, out)
        }
        fn parameter_point_derivatives<C: GroupChart<RigidMotions, 6>>(
            &self,
            index: usize,
            chart: &C,
            point: &GaussPoint<'_, RigidMotions, 6>,
            out: &mut Stacked<18>,
        ) -> bool {
            let derivative = ParameterLocal {
                system: self,
                index,
            };
            crate::step::rotation_translation::point_derivatives(&derivative, chart, point, out)
        }
    };
}

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

/// `∂ℓ/∂p` of the kinetic energy `½ΩᵀJΩ + ½m|v|²` for [`INERTIA_PARAMETERS`](crate::inertia::INERTIA_PARAMETERS)
/// then the mass (index 6).
fn kinetic6_parameter<T: RealField + Copy>(index: usize, xi: &SVector<T, 6>) -> T {
    let w = Vector3::new(xi[0], xi[1], xi[2]);
    let v = Vector3::new(xi[3], xi[4], xi[5]);
    if index == 6 {
        v.dot(&v) * nalgebra::convert::<f64, T>(0.5)
    } else {
        kinetic_parameter(index, &w)
    }
}

/// [`kinetic6_parameter`]'s local derivatives in closed form (`p = 0`: no configuration).
fn kinetic6_parameter_local(
    index: usize,
    xi: &SVector<f64, 6>,
    with_hessian: bool,
) -> LocalDerivatives<6> {
    let mut local = LocalDerivatives::<6> {
        configuration_gradient: SVector::zeros(),
        momentum: SVector::zeros(),
        configuration_hessian: SMatrix::zeros(),
        velocity_hessian: SMatrix::zeros(),
    };
    if index == 6 {
        local
            .momentum
            .fixed_rows_mut::<3>(3)
            .copy_from(&xi.fixed_rows::<3>(3));
        if with_hessian {
            local
                .velocity_hessian
                .fixed_view_mut::<3, 3>(3, 3)
                .copy_from(&Matrix3::identity());
        }
    } else if let Some(e) = Inertia::parameter_direction(index) {
        local
            .momentum
            .fixed_rows_mut::<3>(0)
            .copy_from(&(e * xi.fixed_rows::<3>(0)));
        if with_hessian {
            local
                .velocity_hessian
                .fixed_view_mut::<3, 3>(0, 0)
                .copy_from(&e);
        }
    }
    local
}

/// A built-in SE(3) body's parameter Lagrangian's local derivatives
/// ([`LocalDerivatives`]), for the rotation–translation chart's 3 × 3 blocks
/// ([`ParameterLocal`]).
pub(crate) trait ParameterLocalDerivatives: System<6, Group = RigidMotions> {
    /// The default: the kinetic energy's alone (a body whose potential, if any, does not
    /// depend on its parameters).
    fn parameter_local(
        &self,
        index: usize,
        time: f64,
        g: &SE3,
        xi: &SVector<f64, 6>,
        with_hessian: bool,
    ) -> LocalDerivatives<6> {
        let _ = (time, g);
        kinetic6_parameter_local(index, xi, with_hessian)
    }
}

/// A built-in SE(3) body's `∂ℓ/∂p_k` as a system of its own whose local derivatives are
/// [`ParameterLocalDerivatives::parameter_local`]: the step's parameter columns then take
/// the rotation–translation chart's 3 × 3 blocks (`step::rotation_translation`) where the
/// generic chain rule would take `∂ℓ/∂p`'s derivatives by dual numbers.
pub(crate) struct ParameterLocal<'a, S> {
    pub system: &'a S,
    pub index: usize,
}

impl<S: ParameterLocalDerivatives> System<6> for ParameterLocal<'_, S> {
    type Group = RigidMotions;
    fn lagrangian<T: RealField + Copy>(&self, t: f64, g: &SE3<T>, xi: &SVector<T, 6>) -> T {
        self.system.parameter_lagrangian(self.index, t, g, xi)
    }
    fn is_left_invariant(&self) -> bool {
        self.system.is_left_invariant()
    }
    fn local_derivatives(
        &self,
        time: f64,
        g: &SE3,
        xi: &SVector<f64, 6>,
        with_hessian: bool,
    ) -> Option<LocalDerivatives<6>> {
        Some(
            self.system
                .parameter_local(self.index, time, g, xi, with_hessian),
        )
    }
}

/// `(J⁻¹μ_ω, μ_v/m)`.
fn velocity6(inertia: &Inertia, mass: f64, mu: &SVector<f64, 6>) -> SVector<f64, 6> {
    let w = inertia.velocity(&mu.fixed_rows::<3>(0).into_owned());
    let v = mu.fixed_rows::<3>(3) / mass;
    SVector::<f64, 6>::new(w.x, w.y, w.z, v.x, v.y, v.z)
}

/// A potential of the pose, generic over the scalar: what [`with_potential`]
/// differentiates.
trait PosePotential {
    fn eval<T: RealField + Copy>(
        &self,
        time: f64,
        attitude: &Matrix3<T>,
        position: &Vector3<T>,
    ) -> T;
}

/// `L(η, ξ) = ½ΩᵀJΩ + ½m|v|²` at `η = 0`: `μ = (JΩ, m v)`, `∂²/∂ξ² = diag(J, m I)` (zero
/// without the Hessian), no configuration terms. A potential adds its own
/// ([`with_potential`], or `OrbitingBody`'s closed form).
fn kinetic_local(
    inertia: &Inertia,
    mass: f64,
    xi: &SVector<f64, 6>,
    with_hessian: bool,
) -> LocalDerivatives<6> {
    let (w, v) = split(xi);
    let velocity_hessian = if with_hessian {
        let zero = Matrix3::zeros();
        blocks(
            &inertia.matrix(),
            &zero,
            &zero,
            &(Matrix3::identity() * mass),
        )
    } else {
        SMatrix::zeros()
    };
    LocalDerivatives {
        configuration_gradient: SVector::zeros(),
        momentum: join(&inertia.momentum(&w), &(v * mass)),
        configuration_hessian: SMatrix::zeros(),
        velocity_hessian,
    }
}

/// `local` with the terms of `−V(t, R', x')` added, `(R', x') = (R, x) exp(η)` to second
/// order, `R' = R(I + ω̂ + ½ω̂²)`, `x' = x + R(u + ½ ω × u)` for `η = (ω, u)`: `V`'s
/// derivatives by a dual number over the six `η` alone (second order with the Hessian,
/// first order without), through `V` and nothing else.
fn with_potential<P: PosePotential>(
    mut local: LocalDerivatives<6>,
    potential: &P,
    time: f64,
    g: &SE3,
    with_hessian: bool,
) -> LocalDerivatives<6> {
    let (r, x) = (g.rotation().matrix(), g.translation());
    if with_hessian {
        let (attitude, position) = seeded_pose(r, x);
        let v = -potential.eval(time, &attitude, &position);
        local.configuration_gradient =
            v.v1.unwrap_generic(nalgebra::Const::<1>, nalgebra::Const::<6>)
                .transpose();
        local.configuration_hessian =
            v.v2.unwrap_generic(nalgebra::Const::<6>, nalgebra::Const::<6>);
    } else {
        let (attitude, position) = seeded_pose_first_order(r, x);
        let v = -potential.eval(time, &attitude, &position);
        local.configuration_gradient = v
            .eps
            .unwrap_generic(nalgebra::Const::<6>, nalgebra::Const::<1>);
    }
    local
}

/// `(R', x') = (R, x) exp(η)` to second order as second-order dual numbers in the six
/// `η = (ω, u)`, written from their known derivatives rather than multiplied out:
/// `R' = R(I + ω̂ + ½ω̂²)` has `∂R'/∂ω_c = R ê_c`, `∂²R'/∂ω_c∂ω_d = ½R(ê_c ê_d + ê_d ê_c)`;
/// `x' = x + R(u + ½ ω × u)` has `∂x'/∂u_d = R e_d`, `∂²x'/∂ω_c∂u_d = ½R(e_c × e_d)`.
fn seeded_pose(
    r: &Matrix3<f64>,
    x: &Vector3<f64>,
) -> (Matrix3<Dual2SVec64<6>>, Vector3<Dual2SVec64<6>>) {
    let r_e = rotated_generators(r);
    // ½R(ê_c ê_d + ê_d ê_c) with ê_c ê_d = e_d e_cᵀ − δ_cd I: entry (i, j) is
    // ½(R_id δ_jc + R_ic δ_jd) − δ_cd R_ij, written out rather than multiplied.
    let second: [[Matrix3<f64>; 3]; 3] = std::array::from_fn(|c| {
        std::array::from_fn(|d| {
            let mut m = Matrix3::zeros();
            for i in 0..3 {
                m[(i, c)] += 0.5 * r[(i, d)];
                m[(i, d)] += 0.5 * r[(i, c)];
            }
            if c == d {
                m -= r;
            }
            m
        })
    });
    let attitude = Matrix3::from_fn(|i, j| {
        let mut gradient = SMatrix::<f64, 1, 6>::zeros();
        let mut hessian = SMatrix::<f64, 6, 6>::zeros();
        for c in 0..3 {
            gradient[c] = r_e[c][(i, j)];
            for d in 0..3 {
                hessian[(c, d)] = second[c][d][(i, j)];
            }
        }
        Dual2SVec64::<6>::new(
            r[(i, j)],
            num_dual::Derivative::some(gradient),
            num_dual::Derivative::some(hessian),
        )
    });
    // ½R(e_c × e_d) = ½R ê_c e_d, column d of ½ R ê_c.
    let position = Vector3::from_fn(|i, _| {
        let mut gradient = SMatrix::<f64, 1, 6>::zeros();
        let mut hessian = SMatrix::<f64, 6, 6>::zeros();
        for d in 0..3 {
            gradient[3 + d] = r[(i, d)];
            for c in 0..3 {
                let value = 0.5 * r_e[c][(i, d)];
                hessian[(c, 3 + d)] = value;
                hessian[(3 + d, c)] = value;
            }
        }
        Dual2SVec64::<6>::new(
            x[i],
            num_dual::Derivative::some(gradient),
            num_dual::Derivative::some(hessian),
        )
    });
    (attitude, position)
}

/// `R ê_c` for `c = 0, 1, 2`: column `j` is `R(e_c × e_j)`, i.e. `±` a column of `R` or
/// zero.
fn rotated_generators(r: &Matrix3<f64>) -> [Matrix3<f64>; 3] {
    std::array::from_fn(|c| {
        let (a, b) = ((c + 1) % 3, (c + 2) % 3);
        // e_c × e_a = e_b, e_c × e_b = −e_a.
        let mut m = Matrix3::zeros();
        m.set_column(a, &r.column(b));
        m.set_column(b, &(-r.column(a)));
        m
    })
}

/// [`seeded_pose`] to first order (a gradient-only assembly).
fn seeded_pose_first_order(
    r: &Matrix3<f64>,
    x: &Vector3<f64>,
) -> (Matrix3<DualSVec64<6>>, Vector3<DualSVec64<6>>) {
    let r_e = rotated_generators(r);
    let attitude = Matrix3::from_fn(|i, j| {
        let mut gradient = SVector::<f64, 6>::zeros();
        for c in 0..3 {
            gradient[c] = r_e[c][(i, j)];
        }
        DualSVec64::<6>::new(r[(i, j)], num_dual::Derivative::some(gradient))
    });
    let position = Vector3::from_fn(|i, _| {
        let mut gradient = SVector::<f64, 6>::zeros();
        for d in 0..3 {
            gradient[3 + d] = r[(i, d)];
        }
        DualSVec64::<6>::new(x[i], num_dual::Derivative::some(gradient))
    });
    (attitude, position)
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

impl System<6> for FreeBody {
    type Group = RigidMotions;
    points_by_blocks!();
    fn lagrangian<T: RealField + Copy>(&self, _t: f64, _g: &SE3<T>, xi: &SVector<T, 6>) -> T {
        kinetic6(&self.inertia, self.mass, xi)
    }
    /// The inertia tensor's six entries and the mass.
    fn parameter_names(&self) -> Vec<String> {
        inertia_parameter_names(&["mass"])
    }
    fn parameter_lagrangian<T: RealField + Copy>(
        &self,
        index: usize,
        _t: f64,
        _g: &SE3<T>,
        xi: &SVector<T, 6>,
    ) -> T {
        kinetic6_parameter(index, xi)
    }
    fn local_derivatives(
        &self,
        _time: f64,
        _g: &SE3,
        xi: &SVector<f64, 6>,
        with_hessian: bool,
    ) -> Option<LocalDerivatives<6>> {
        Some(kinetic_local(&self.inertia, self.mass, xi, with_hessian))
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
/// use lgsvi_mechanics::Stepper;
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

impl<V: FieldPotential> System<6> for BodyInField<V> {
    type Group = RigidMotions;
    points_by_blocks!();
    fn lagrangian<T: RealField + Copy>(&self, t: f64, g: &SE3<T>, xi: &SVector<T, 6>) -> T {
        kinetic6(&self.inertia, self.mass, xi)
            - self
                .potential
                .potential(t, g.rotation().matrix(), g.translation())
    }
    /// The inertia tensor's six entries and the mass in the kinetic energy (the
    /// potential's own constants, a mass inside `V` among them, are held).
    fn parameter_names(&self) -> Vec<String> {
        inertia_parameter_names(&["mass"])
    }
    fn parameter_lagrangian<T: RealField + Copy>(
        &self,
        index: usize,
        _t: f64,
        _g: &SE3<T>,
        xi: &SVector<T, 6>,
    ) -> T {
        kinetic6_parameter(index, xi)
    }
    fn local_derivatives(
        &self,
        time: f64,
        g: &SE3,
        xi: &SVector<f64, 6>,
        with_hessian: bool,
    ) -> Option<LocalDerivatives<6>> {
        struct Field<'a, V>(&'a V);
        impl<V: FieldPotential> PosePotential for Field<'_, V> {
            fn eval<T: RealField + Copy>(&self, t: f64, r: &Matrix3<T>, x: &Vector3<T>) -> T {
                self.0.potential(t, r, x)
            }
        }
        Some(with_potential(
            kinetic_local(&self.inertia, self.mass, xi, with_hessian),
            &Field(&self.potential),
            time,
            g,
            with_hessian,
        ))
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
/// # Resolution of the attitude
/// A step on SE(3) carries the body's momentum about the step's start, where the orbit's
/// part is `m |v| · h|v|`: against the spin's `|JΩ|` that ratio is small in units scaled
/// to the orbit (the examples' `μ = 1`), but on a low Earth orbit in SI units (100 kg at
/// 7.6 km/s, `h` = 30 s, `|JΩ|` ~ 1e-3) it is ~1e14, and rounding leaves the body rates a
/// relative error of a few per cent that does not fall with the step (measured: `Ω_z`
/// after 600 s between 8.66e-5 and 9.24e-5 rad/s for `h` from 30 s to 0.94 s, with both
/// charts). The orbit itself and the conserved quantities are unaffected; the attitude
/// there is not to be trusted beyond that. The same body written as a [`crate::System`] on
/// the product SO(3) × ℝ³ ([`crate::gyrostat::BodyAndWheels`]`<3>`, its ℝ³ part the centre
/// of mass in the world frame) carries no lever arm and resolves the attitude to rounding:
/// `Ω_z = 8.819729598619e-5` rad/s at every step from 30 s to 3.75 s and in both charts
/// (`tests/tests/orbit_attitude.rs` writes it out).
///
/// ```
/// use lgsvi_mechanics::Stepper;
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

    /// Checks a start at `position` (world frame, the attracting point at the origin) and
    /// returns its distance `r` from the attracting point.
    ///
    /// # Errors
    /// [`MechanicsError::InvalidStart`] at (or next to) the attracting point, where the
    /// potential `−μm/r` and its gravity gradient are singular; within twice the
    /// [radius of gyration](Self::radius_of_gyration), where the attracting point lies
    /// inside the body's mass and MacCullagh's far-field potential does not hold (a run
    /// there would integrate a model outside its validity); beyond `r = 1e75`, where the
    /// gravity gradient's terms (of order `r⁴`) overflow double precision. A body without
    /// gravity (`μ = 0`) takes any start.
    pub fn check_position(&self, position: &Vector3<f64>) -> Result<f64, MechanicsError> {
        let mu = self.gravitational_parameter;
        // |x| without underflow (1e-300 squared is zero).
        let scale = position.amax();
        let r = if scale > 0.0 {
            scale * (position / scale).norm()
        } else {
            0.0
        };
        let invalid = |reason| MechanicsError::InvalidStart {
            value: format!("{:?}", position.as_slice()),
            reason,
        };
        if mu == 0.0 {
            return Ok(r);
        }
        if !(r > 0.0 && (mu * self.mass / r.powi(3)).is_finite()) {
            return Err(invalid(format!(
                "the orbiting body starts at the attracting centre (r = {r:e}), where the \
                 potential −μm/r and its gravity gradient are singular: start it away from the \
                 origin"
            )));
        }
        let k = self.radius_of_gyration();
        if r < 2.0 * k {
            return Err(invalid(format!(
                "the orbiting body starts {r:e} from the attracting point mass, within twice \
                 its radius of gyration √(tr J / 2m) = {k:.4e} (from its inertia and mass): \
                 the attracting point lies inside the body's mass, where the far-field \
                 (MacCullagh) potential does not hold; raise the mass, lower the inertia or \
                 start further out"
            )));
        }
        // The gravity gradient's Hessian forms x xᵀ (xᵀJx) ~ r⁴ |J|, which overflows from
        // about r = 1e77 (a start at 1e70 runs, one at 1e80 fails).
        if r > 1e75 {
            return Err(invalid(format!(
                "the orbiting body starts at r = {r:e}, where its gravity gradient's terms (of \
                 order r⁴) overflow double precision (r ≤ 1e75): express lengths in larger \
                 units"
            )));
        }
        Ok(r)
    }

    /// The radius of gyration `√(tr J / 2m)`: within twice it of the attracting point, the
    /// point lies inside the body's mass, where MacCullagh's far-field potential does not
    /// hold ([`System::model_breakdown`]).
    pub fn radius_of_gyration(&self) -> f64 {
        (self.inertia.matrix().trace() / (2.0 * self.mass)).sqrt()
    }

    /// MacCullagh's potential at attitude `R`, position `x`.
    pub fn potential<T: RealField + Copy>(&self, r: &Matrix3<T>, x: &Vector3<T>) -> T {
        maccullagh(
            self.gravitational_parameter,
            self.mass,
            &self.inertia.matrix(),
            r,
            x,
        )
    }
}

/// `∂V/∂p_k` of MacCullagh's potential (linear in `J` and `m`): `−½μ(tr E_k − 3bᵀE_k b)/r³`
/// for inertia parameter `k` (`b = Rᵀx/r`), `−μ/r` for the mass.
struct ParameterPotential<'a> {
    body: &'a OrbitingBody,
    index: usize,
}

impl PosePotential for ParameterPotential<'_> {
    /// MacCullagh's potential is linear in `(J, m)` with no constant term, and in `μ`: its
    /// derivative in a parameter is the potential at that parameter's unit direction.
    fn eval<T: RealField + Copy>(&self, _time: f64, r: &Matrix3<T>, x: &Vector3<T>) -> T {
        let mu = self.body.gravitational_parameter;
        if self.index == 6 {
            maccullagh(mu, 1.0, &Matrix3::zeros(), r, x)
        } else if self.index == 7 {
            maccullagh(1.0, self.body.mass, &self.body.inertia.matrix(), r, x)
        } else if let Some(direction) = Inertia::parameter_direction(self.index) {
            maccullagh(mu, 0.0, &direction, r, x)
        } else {
            T::zero()
        }
    }
}

/// MacCullagh's potential of a body of inertia `j` and mass `m` at attitude `R`, position
/// `x`, about a point mass of gravitational parameter `μ` at the origin:
/// `−μm/r − ½μ(tr J − 3bᵀJb)/r³`, `b = Rᵀx/r`.
fn maccullagh<T: RealField + Copy>(
    mu: f64,
    m: f64,
    j: &Matrix3<f64>,
    r: &Matrix3<T>,
    x: &Vector3<T>,
) -> T {
    let mu: T = nalgebra::convert(mu);
    let m: T = nalgebra::convert(m);
    let j: Matrix3<T> = j.map(nalgebra::convert);
    let three: T = nalgebra::convert(3.0);
    let half: T = nalgebra::convert(0.5);
    let r2 = x.dot(x);
    let dist = r2.sqrt();
    // x̂ᵀRJRᵀx̂ = bᵀJb with b = Rᵀx/r.
    let b = r.transpose() * x / dist;
    let gradient_term = j.trace() - three * b.dot(&(j * b));
    -mu * m / dist - half * mu * gradient_term / (r2 * dist)
}

impl ParameterLocalDerivatives for OrbitingBody {
    fn parameter_local(
        &self,
        index: usize,
        time: f64,
        g: &SE3,
        xi: &SVector<f64, 6>,
        with_hessian: bool,
    ) -> LocalDerivatives<6> {
        with_potential(
            kinetic6_parameter_local(index, xi, with_hessian),
            &ParameterPotential { body: self, index },
            time,
            g,
            with_hessian,
        )
    }
}

impl ParameterLocalDerivatives for FreeBody {}

/// `V`'s own constants are held: the kinetic energy's derivatives alone.
impl<V: FieldPotential> ParameterLocalDerivatives for BodyInField<V> {}

impl System<6> for OrbitingBody {
    type Group = RigidMotions;
    points_by_blocks!();
    fn lagrangian<T: RealField + Copy>(&self, _t: f64, g: &SE3<T>, xi: &SVector<T, 6>) -> T {
        kinetic6(&self.inertia, self.mass, xi)
            - self.potential(g.rotation().matrix(), g.translation())
    }
    /// The inertia tensor's six entries and the mass, in the kinetic energy and in
    /// MacCullagh's potential (linear in both): `−∂V/∂J_k = ½μ(tr E_k − 3bᵀE_k b)/r³`,
    /// `−∂V/∂m = μ/r`; then the gravitational parameter `mu`, in the potential alone
    /// (`−∂V/∂μ = −V/μ`).
    fn parameter_names(&self) -> Vec<String> {
        inertia_parameter_names(&["mass", "mu"])
    }
    fn parameter_lagrangian<T: RealField + Copy>(
        &self,
        index: usize,
        _t: f64,
        g: &SE3<T>,
        xi: &SVector<T, 6>,
    ) -> T {
        let potential = ParameterPotential { body: self, index };
        kinetic6_parameter(index, xi) - potential.eval(0.0, g.rotation().matrix(), g.translation())
    }
    fn velocity_from_momentum(
        &self,
        _t: f64,
        _g: &SE3,
        mu: &SVector<f64, 6>,
    ) -> Option<SVector<f64, 6>> {
        Some(velocity6(&self.inertia, self.mass, mu))
    }
    /// `|ω|` and the gravity-gradient libration `√(3|μ|/r³)`, √3 times the orbit's mean
    /// motion (none without attraction).
    fn motion_rate(&self, _t: f64, g: &SE3, xi: &SVector<f64, 6>) -> f64 {
        let spin = xi.fixed_rows::<3>(0).norm();
        if self.gravitational_parameter == 0.0 {
            return spin;
        }
        // |x| without underflow (1e-300 squared is zero).
        let position = g.translation();
        let scale = position.amax();
        let r = if scale > 0.0 {
            scale * (position / scale).norm()
        } else {
            0.0
        };
        spin + (3.0 * self.gravitational_parameter.abs() / r.powi(3)).sqrt()
    }
    /// A state (a step's end, or a failed step's start) within twice the body's radius of gyration
    /// `k = √(tr J / 2m)` (the root-mean-square distance of its mass from its centre) of the
    /// attracting point: the attracting point lies within the body's mass, where
    /// MacCullagh's far-field expansion does not hold (the quadrupole term it keeps is of
    /// relative size `(k/r)²`, the terms it drops `(k/r)³`) and the point-mass term is
    /// singular at `r = 0`. A shorter step does not make the model hold there; the orbit or
    /// the body must change.
    fn model_breakdown(&self, _time: f64, g: &SE3, _xi: &SVector<f64, 6>) -> Option<String> {
        let r = g.translation().norm();
        let k = self.radius_of_gyration();
        (self.gravitational_parameter > 0.0 && r < 2.0 * k).then(|| {
            // Fixed decimals where they read well, else scientific (a radius of 1e40).
            let length = |x: f64| {
                if (1e-3..1e6).contains(&x) {
                    format!("{x:.3}")
                } else {
                    format!("{x:.3e}")
                }
            };
            let (r, k) = (length(r), length(k));
            format!(
                "the centre of mass is {r} from the attracting point mass, within twice \
                 the body's radius of gyration √(tr J / 2m) = {k}: the attracting point \
                 lies within the body's mass, where MacCullagh's far-field potential does not \
                 hold (its point-mass term is singular at r = 0); start on a wider orbit, or \
                 give the body an inertia small against m r²"
            )
        })
    }
    /// MacCullagh's potential through the body-frame position `b = Rᵀx`, in closed form:
    /// `W(b) = −μm/r − (μ tr J)/(2r³) + (3μ/2) bᵀJb/r⁵` (`r = |b|`), and under
    /// `(R, x) exp(η)`, `η = (ω, u)`, `b ↦ b + u − ω × b − ½ ω × u + ½ ω × (ω × b)` to second
    /// order: `∂b/∂η = [b̂, I]`, and the second derivatives of `b` contracted with `∇W`
    /// are `½(g bᵀ + b gᵀ − 2(g·b) I)` (ωω) and `½ ĝ` (ωu), `g = ∇W`. The tests compare it
    /// with dual numbers through the whole point.
    fn local_derivatives(
        &self,
        _time: f64,
        g: &SE3,
        xi: &SVector<f64, 6>,
        with_hessian: bool,
    ) -> Option<LocalDerivatives<6>> {
        let mut local = kinetic_local(&self.inertia, self.mass, xi, with_hessian);
        let (mu, m) = (self.gravitational_parameter, self.mass);
        let j = self.inertia.matrix();
        let b = g.rotation().matrix().transpose() * g.translation();
        let r2 = b.norm_squared();
        let r = r2.sqrt();
        let (r3, r5) = (r2 * r, r2 * r2 * r);
        let r7 = r5 * r2;
        let jb = j * b;
        let q = b.dot(&jb);
        let trace = j.trace();
        // ∇W.
        let grad =
            b * (mu * m / r3 + 1.5 * mu * trace / r5 - 7.5 * mu * q / r7) + jb * (3.0 * mu / r5);
        let b_hat = lgsvi_lie::so3::hat(&b);
        // p = −∂W(b(η))/∂η = −[b̂, I]ᵀ∇W = (b̂∇W, −∇W) (b̂ᵀ = −b̂).
        local.configuration_gradient = join(&(b_hat * grad), &-grad);
        if !with_hessian {
            return Some(local);
        }
        let r9 = r7 * r2;
        let bb = b * b.transpose();
        let identity = Matrix3::identity();
        let hessian = (identity / r3 - bb * (3.0 / r5)) * (mu * m)
            + (identity / r5 - bb * (5.0 / r7)) * (1.5 * mu * trace)
            + (j * (2.0 / r5)
                - (jb * b.transpose() + b * jb.transpose()) * (10.0 / r7)
                - identity * (5.0 * q / r7)
                + bb * (35.0 * q / r9))
                * (1.5 * mu);
        // Bᵀ ∇²W B with B = [b̂, I].
        let ww = b_hat.transpose() * hessian * b_hat;
        let wu = b_hat.transpose() * hessian;
        // Σ_i g_i ∂²b_i/∂η².
        let curvature_ww =
            (grad * b.transpose() + b * grad.transpose()) * 0.5 - identity * grad.dot(&b);
        let curvature_wu = lgsvi_lie::so3::hat(&grad) * 0.5;
        local.configuration_hessian = -blocks(
            &(ww + curvature_ww),
            &(wu + curvature_wu),
            &(wu + curvature_wu).transpose(),
            &hessian,
        );
        Some(local)
    }
}
