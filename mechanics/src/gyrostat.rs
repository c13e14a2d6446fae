//! A gyrostat: a rigid body carrying `K` reaction wheels about fixed body axes, on the
//! product group SO(3) × ℝᴷ (attitude and wheel angles, `D = 3 + K`), with the wheels'
//! motor torques as control inputs.
//!
//! With `J` the inertia of the whole spacecraft with its wheels locked (what one measures),
//! `a_i` the unit wheel axes (body frame), `I_i` the wheels' axial inertias and `φ_i` their
//! angles relative to the body, the kinetic energy is
//! `ℓ(Ω, φ̇) = ½ΩᵀJΩ + Σ_i I_i (a_iᵀΩ) φ̇_i + ½ Σ_i I_i φ̇_i²`, i.e. the constant mass matrix
//! `M = [[J, A 𝐈], [𝐈 Aᵀ, 𝐈]]` (`A = [a_1 … a_K]`, `𝐈 = diag(I_i)`), positive definite
//! exactly when `J_b = J − Σ I_i a_i a_iᵀ` is. `ℓ` depends on neither the attitude nor the
//! wheel angles (both cyclic), so the body momentum `μ = MΩ̃` (`Ω̃ = (Ω, φ̇)`) splits into
//! the total angular momentum in the body frame `h = JΩ + A𝐈φ̇` and the wheels' axial
//! momenta `p_i = I_i(a_iᵀΩ + φ̇_i)`.
//!
//! A motor torque `τ_i` acts between the body and wheel `i`: in these coordinates it is the
//! generalised force on `φ_i` alone, so the input is `u = (0, 0, 0, τ_1, …, τ_K)` (the first
//! three entries are an external body torque, e.g. thrusters). Then the spatial angular
//! momentum `Rh` is conserved exactly by the discrete map (discrete Noether for the
//! rotations, which the motor torques do not break), and `p_i` changes by `τ_i h` per step:
//! momentum moves between body and wheels.
//!
//! The charts are those of SO(3) on the attitude and the identity on the wheel angles
//! (every `So3Chart` is a chart of these groups).
//!
//! ```
//! use lgsvi_mechanics::Stepper;
//! use lgsvi_mechanics::gyrostat::{BodyWheels, Gyrostat};
//! use lgsvi_mechanics::lie::SO3;
//! use lgsvi_mechanics::{Integrator, StepSettings};
//! use nalgebra::{Matrix3, SVector, Vector3};
//!
//! // Three wheels along the body axes, axial inertia 0.05 each.
//! let craft = Gyrostat::new(Matrix3::from_diagonal(&Vector3::new(10.0, 12.0, 8.0)),
//!     [Vector3::x(), Vector3::y(), Vector3::z()], [0.05; 3])?;
//! let start = BodyWheels { attitude: SO3::identity(), wheels: Vector3::zeros() };
//! let mut integrator = Integrator::new(craft, StepSettings::new(0.1, 6)?, start, SVector::<f64, 6>::zeros())?;
//! // Spin the z wheel up: the body turns the other way, the total momentum stays zero.
//! integrator.set_input(SVector::<f64, 6>::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.01))?;
//! integrator.run(50, 1)?;
//! let s = integrator.state();
//! assert!(s.velocity[2] < 0.0 && s.momentum[5] > 0.0);
//! assert!((s.configuration.attitude.matrix() * s.momentum.fixed_rows::<3>(0)).norm() < 1e-15);
//! # Ok::<(), lgsvi_mechanics::MechanicsError>(())
//! ```

use crate::error::{check_finite, MechanicsError};
use crate::group::{
    dual_number_derivatives, ChartDerivatives, ConfigurationGroup, GroupChart, Rotations, Stacked,
};
use crate::matrix_jet::MatrixJet;
use crate::system::{LocalDerivatives, System};
use lgsvi_lie::{Chart, LieError, LieGroup, So3Chart, SO3};
use nalgebra::{Matrix3, RealField, SMatrix, SVector, Vector3};
use num_dual::{Dual2_64, Dual64};

/// An element of SO(3) × ℝᴷ: the attitude `R = world_from_body` and the wheel angles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyWheels<T: RealField + Copy, const K: usize> {
    /// `R`, world from body.
    pub attitude: SO3<T>,
    /// The wheel angles `φ_i` relative to the body.
    pub wheels: SVector<T, K>,
}

/// The marker type of the group SO(3) × ℝᴷ (`D = 3 + K`; implemented for `K = 1..=4`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BodyAndWheels<const K: usize>;

/// A rigid body with `K` reaction wheels (module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gyrostat<const K: usize> {
    inertia: Matrix3<f64>,
    axes: [Vector3<f64>; K],
    wheel_inertia: [f64; K],
    /// `J_b⁻¹`, `J_b = J − Σ I_i a_i a_iᵀ`.
    body_inverse: Matrix3<f64>,
}

impl<const K: usize> Gyrostat<K> {
    /// The spacecraft's inertia `J` with its wheels locked (body frame, symmetric), the
    /// wheel axes (body frame, normalised here) and the wheels' axial inertias.
    ///
    /// # Errors
    /// [`MechanicsError::NonFinite`]; [`MechanicsError::InvalidSetting`] for a zero axis,
    /// a wheel inertia that is not positive, or a `J` that is not symmetric or leaves
    /// `J − Σ I_i a_i a_iᵀ` not positive definite (the wheels' axial inertia must be part
    /// of `J`, and less than it about each axis).
    pub fn new(
        inertia: Matrix3<f64>,
        axes: [Vector3<f64>; K],
        wheel_inertia: [f64; K],
    ) -> Result<Self, MechanicsError> {
        check_finite("gyrostat inertia", inertia.as_slice())?;
        check_finite("wheel inertia", &wheel_inertia)?;
        let mut unit = axes;
        for axis in unit.iter_mut() {
            check_finite("wheel axis", axis.as_slice())?;
            let largest = axis.amax();
            if largest == 0.0 {
                return Err(MechanicsError::InvalidSetting {
                    name: "wheel axis",
                    value: format!("{:?}", axis.as_slice()),
                    reason: "must be a non-zero vector",
                });
            }
            *axis = (*axis / largest).normalize();
        }
        if let Some(i) = wheel_inertia.iter().find(|&&i| i <= 0.0) {
            return Err(MechanicsError::InvalidSetting {
                name: "wheel inertia",
                value: i.to_string(),
                reason: "each wheel's axial inertia must be positive",
            });
        }
        if (inertia - inertia.transpose()).amax() > 1e-12 * inertia.amax() {
            return Err(MechanicsError::InvalidSetting {
                name: "gyrostat inertia",
                value: format!("{inertia:?}"),
                reason: "must be symmetric",
            });
        }
        let body = unit
            .iter()
            .zip(&wheel_inertia)
            .fold(inertia, |j, (a, &i)| j - a * a.transpose() * i);
        let body_inverse = body
            .cholesky()
            .ok_or_else(|| MechanicsError::InvalidSetting {
                name: "gyrostat inertia",
                value: format!("{inertia:?}"),
                reason: "J − Σ I_i a_i a_iᵀ is not positive definite: J must be the whole \
                         spacecraft's inertia with the wheels locked (their axial inertia \
                         included)",
            })?
            .inverse();
        Ok(Self {
            inertia,
            axes: unit,
            wheel_inertia,
            body_inverse,
        })
    }

    /// `J`, the inertia with the wheels locked.
    pub fn inertia(&self) -> &Matrix3<f64> {
        &self.inertia
    }

    /// The unit wheel axes (body frame).
    pub fn axes(&self) -> &[Vector3<f64>; K] {
        &self.axes
    }

    /// The wheels' axial inertias.
    pub fn wheel_inertia(&self) -> &[f64; K] {
        &self.wheel_inertia
    }
}

/// A gyrostat whose wheel count (1 to 4) is known only at run time (a command line's,
/// a configuration file's): one type for the four [`Gyrostat`]s; match on it to run the
/// one it holds (`Gyrostat<K>` on SO(3) × ℝᴷ is a different configuration group for each
/// `K`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AnyGyrostat {
    /// One wheel.
    One(Gyrostat<1>),
    /// Two wheels.
    Two(Gyrostat<2>),
    /// Three wheels.
    Three(Gyrostat<3>),
    /// Four wheels.
    Four(Gyrostat<4>),
}

impl AnyGyrostat {
    /// The gyrostat with as many wheels as `axes` has entries ([`Gyrostat::new`]).
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for 0 or more than 4 wheels, or for
    /// `wheel_inertia` with another count than `axes`; [`Gyrostat::new`]'s errors.
    pub fn new(
        inertia: Matrix3<f64>,
        axes: &[Vector3<f64>],
        wheel_inertia: &[f64],
    ) -> Result<Self, MechanicsError> {
        if wheel_inertia.len() != axes.len() {
            return Err(MechanicsError::InvalidSetting {
                name: "wheel inertia",
                value: format!("{wheel_inertia:?}"),
                reason: "one axial inertia per wheel axis",
            });
        }
        fn fixed<T: Copy, const K: usize>(values: &[T]) -> [T; K] {
            std::array::from_fn(|i| values[i])
        }
        Ok(match axes.len() {
            1 => Self::One(Gyrostat::new(inertia, fixed(axes), fixed(wheel_inertia))?),
            2 => Self::Two(Gyrostat::new(inertia, fixed(axes), fixed(wheel_inertia))?),
            3 => Self::Three(Gyrostat::new(inertia, fixed(axes), fixed(wheel_inertia))?),
            4 => Self::Four(Gyrostat::new(inertia, fixed(axes), fixed(wheel_inertia))?),
            k => {
                return Err(MechanicsError::InvalidSetting {
                    name: "wheels",
                    value: k.to_string(),
                    reason: "a gyrostat here has 1 to 4 wheels",
                })
            }
        })
    }

    /// Its number of wheels.
    pub fn wheels(&self) -> usize {
        match self {
            Self::One(_) => 1,
            Self::Two(_) => 2,
            Self::Three(_) => 3,
            Self::Four(_) => 4,
        }
    }
}

/// The derivatives of an SO(3) chart on the attitude and the identity on ℝᴷ
/// (`A = diag(A_ω(ω), I)`) in closed form, from the Rodrigues jet of `A_ω`, which depends
/// on `ω` alone: with `x = (ω, φ)`, `∂(Av)/∂ω = [∂_kA_ω v_ω ; 0]_k`,
/// `∂(Aᵀg)/∂ω = [∂_kA_ωᵀ g_ω ; 0]_k`, `∇²(μᵀAv) = ⟨μ_ω v_ωᵀ, ∂²A_ω⟩` in the `ω` block,
/// nothing in `φ` (the identity's derivatives vanish).
struct AttitudeTimesVectorDerivatives {
    a: MatrixJet,
}

/// Implements the group, its charts and the gyrostat for one wheel count.
macro_rules! wheels {
    ($k:literal, $d:literal, $jet:literal, $local:literal) => {
        impl<T: RealField + Copy> LieGroup for BodyWheels<T, $k> {
            type Scalar = T;
            type Tangent = SVector<T, $d>;
            type Jacobian = SMatrix<T, $d, $d>;
            type Point = Vector3<T>;
            /// `(R, φ)`; `hat` gives `(ω̂, u)`.
            type Matrix = (Matrix3<T>, SVector<T, $k>);
            const DOF: usize = $d;
            const NAME: &'static str = "SO(3) × ℝᴷ";
            fn identity() -> Self {
                Self {
                    attitude: SO3::identity(),
                    wheels: SVector::zeros(),
                }
            }
            fn compose(&self, other: &Self) -> Self {
                Self {
                    attitude: self.attitude.compose(&other.attitude),
                    wheels: self.wheels + other.wheels,
                }
            }
            fn inverse(&self) -> Self {
                Self {
                    attitude: self.attitude.inverse(),
                    wheels: -self.wheels,
                }
            }
            /// Rotates a point (the wheels do not move points of the body).
            fn act(&self, point: &Vector3<T>) -> Vector3<T> {
                self.attitude.act(point)
            }
            fn to_matrix(&self) -> (Matrix3<T>, SVector<T, $k>) {
                (*self.attitude.matrix(), self.wheels)
            }
            fn hat(xi: &SVector<T, $d>) -> (Matrix3<T>, SVector<T, $k>) {
                (
                    lgsvi_lie::so3::hat(&xi.fixed_rows::<3>(0).into_owned()),
                    xi.fixed_rows::<$k>(3).into_owned(),
                )
            }
            fn vee(matrix: &(Matrix3<T>, SVector<T, $k>)) -> SVector<T, $d> {
                let mut xi = SVector::<T, $d>::zeros();
                xi.fixed_rows_mut::<3>(0)
                    .copy_from(&lgsvi_lie::so3::vee(&matrix.0));
                xi.fixed_rows_mut::<$k>(3).copy_from(&matrix.1);
                xi
            }
            /// `diag(R, I)`.
            fn adjoint(&self) -> SMatrix<T, $d, $d> {
                let mut ad = SMatrix::<T, $d, $d>::identity();
                ad.fixed_view_mut::<3, 3>(0, 0)
                    .copy_from(self.attitude.matrix());
                ad
            }
            /// `diag(ω̂, 0)`.
            fn small_adjoint(xi: &SVector<T, $d>) -> SMatrix<T, $d, $d> {
                let mut ad = SMatrix::<T, $d, $d>::zeros();
                ad.fixed_view_mut::<3, 3>(0, 0)
                    .copy_from(&lgsvi_lie::so3::hat(&xi.fixed_rows::<3>(0).into_owned()));
                ad
            }
            /// `(Rμ_R, μ_φ)`.
            fn coadjoint_action(&self, mu: &SVector<T, $d>) -> SVector<T, $d> {
                let mut out = *mu;
                out.fixed_rows_mut::<3>(0)
                    .copy_from(&(self.attitude.matrix() * mu.fixed_rows::<3>(0)));
                out
            }
        }

        /// `exp(ω, φ) = (exp(ω̂), φ)`, its inverse near the identity: what the law suite
        /// ([`lgsvi_lie::laws`]) reads.
        impl<T: RealField + Copy> lgsvi_lie::laws::ExponentialMap for BodyWheels<T, $k> {
            fn exp(xi: &SVector<T, $d>) -> Self {
                BodyWheels {
                    attitude: SO3::exp(&xi.fixed_rows::<3>(0).into_owned()),
                    wheels: xi.fixed_rows::<$k>(3).into_owned(),
                }
            }
            fn log(&self) -> SVector<T, $d> {
                let mut xi = SVector::<T, $d>::zeros();
                xi.fixed_rows_mut::<3>(0).copy_from(&self.attitude.log());
                xi.fixed_rows_mut::<$k>(3).copy_from(&self.wheels);
                xi
            }
        }

        impl ConfigurationGroup<$d> for BodyAndWheels<$k> {
            type Element<T: RealField + Copy> = BodyWheels<T, $k>;
            type Jet = Stacked<$jet>;
            type LocalJet = Stacked<$local>;
            const NAME: &'static str = "SO(3) × ℝᴷ";
            fn lift<T: RealField + Copy>(g: &BodyWheels<f64, $k>) -> BodyWheels<T, $k> {
                BodyWheels {
                    attitude: <Rotations as ConfigurationGroup<3>>::lift(&g.attitude),
                    wheels: g.wheels.map(nalgebra::convert),
                }
            }
            fn exp<T: RealField + Copy>(zeta: &SVector<T, $d>) -> BodyWheels<T, $k> {
                BodyWheels {
                    attitude: <Rotations as ConfigurationGroup<3>>::exp(
                        &zeta.fixed_rows::<3>(0).into_owned(),
                    ),
                    wheels: zeta.fixed_rows::<$k>(3).into_owned(),
                }
            }
            fn exp_second_order<T: RealField + Copy>(zeta: &SVector<T, $d>) -> BodyWheels<T, $k> {
                BodyWheels {
                    attitude: <Rotations as ConfigurationGroup<3>>::exp_second_order(
                        &zeta.fixed_rows::<3>(0).into_owned(),
                    ),
                    wheels: zeta.fixed_rows::<$k>(3).into_owned(),
                }
            }
            fn rotation_angle(g: &BodyWheels<f64, $k>) -> f64 {
                <Rotations as ConfigurationGroup<3>>::rotation_angle(&g.attitude)
            }
            fn angular_speed(xi: &SVector<f64, $d>) -> f64 {
                xi.fixed_rows::<3>(0).norm()
            }
            fn renormalise(g: &BodyWheels<f64, $k>) -> BodyWheels<f64, $k> {
                BodyWheels {
                    attitude: <Rotations as ConfigurationGroup<3>>::renormalise(&g.attitude),
                    wheels: g.wheels,
                }
            }
            fn is_finite(g: &BodyWheels<f64, $k>) -> bool {
                <Rotations as ConfigurationGroup<3>>::is_finite(&g.attitude)
                    && g.wheels.iter().all(|x| x.is_finite())
            }
            fn check_on_group(g: &BodyWheels<f64, $k>) -> Result<(), LieError> {
                <Rotations as ConfigurationGroup<3>>::check_on_group(&g.attitude)
            }
            /// `diag(p̂_R, 0)`.
            fn coadjoint_generator(p: &SVector<f64, $d>) -> SMatrix<f64, $d, $d> {
                let mut c = SMatrix::<f64, $d, $d>::zeros();
                c.fixed_view_mut::<3, 3>(0, 0).copy_from(
                    &<Rotations as ConfigurationGroup<3>>::coadjoint_generator(
                        &p.fixed_rows::<3>(0).into_owned(),
                    ),
                );
                c
            }
        }

        impl ChartDerivatives<$d> for AttitudeTimesVectorDerivatives {
            fn differential(&self) -> SMatrix<f64, $d, $d> {
                let mut a = SMatrix::<f64, $d, $d>::identity();
                a.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.a.value);
                a
            }
            fn differential_times(&self, v: &SVector<f64, $d>) -> SMatrix<f64, $d, $d> {
                let mut out = SMatrix::<f64, $d, $d>::zeros();
                out.fixed_view_mut::<3, 3>(0, 0)
                    .copy_from(&self.a.first_times(&v.fixed_rows::<3>(0).into_owned()));
                out
            }
            fn transpose_times(&self, g: &SVector<f64, $d>) -> SMatrix<f64, $d, $d> {
                let mut out = SMatrix::<f64, $d, $d>::zeros();
                out.fixed_view_mut::<3, 3>(0, 0).copy_from(
                    &self
                        .a
                        .first_transposed_times(&g.fixed_rows::<3>(0).into_owned())
                        .transpose(),
                );
                out
            }
            fn second(&self, mu: &SVector<f64, $d>, v: &SVector<f64, $d>) -> SMatrix<f64, $d, $d> {
                let mut out = SMatrix::<f64, $d, $d>::zeros();
                out.fixed_view_mut::<3, 3>(0, 0)
                    .copy_from(&self.a.second_contracted(
                        &(mu.fixed_rows::<3>(0) * v.fixed_rows::<3>(0).transpose()),
                    ));
                out
            }
        }

        /// The SO(3) chart on the attitude, the identity on the wheel angles.
        impl<C: So3Chart + Send + Sync> GroupChart<BodyAndWheels<$k>, $d> for C {
            fn name(&self) -> &'static str {
                self.chart_name()
            }
            fn to_group<T: RealField + Copy>(&self, xi: &SVector<T, $d>) -> BodyWheels<T, $k> {
                BodyWheels {
                    attitude: SO3::from_matrix_unchecked(
                        self.rotation_matrix(&xi.fixed_rows::<3>(0).into_owned()),
                    ),
                    wheels: xi.fixed_rows::<$k>(3).into_owned(),
                }
            }
            /// `diag(A(ω), I)`.
            fn left_differential<T: RealField + Copy>(
                &self,
                xi: &SVector<T, $d>,
            ) -> SMatrix<T, $d, $d> {
                let mut a = SMatrix::<T, $d, $d>::identity();
                a.fixed_view_mut::<3, 3>(0, 0).copy_from(
                    &self.rotation_left_differential(&xi.fixed_rows::<3>(0).into_owned()),
                );
                a
            }
            fn left_differential_inverse(
                &self,
                xi: &SVector<f64, $d>,
            ) -> Result<SMatrix<f64, $d, $d>, LieError> {
                let rotation = Chart::<SO3>::left_differential_inverse(
                    self,
                    &xi.fixed_rows::<3>(0).into_owned(),
                )?;
                let mut a = SMatrix::<f64, $d, $d>::identity();
                a.fixed_view_mut::<3, 3>(0, 0).copy_from(&rotation);
                Ok(a)
            }
            fn to_algebra_near(
                &self,
                g: &BodyWheels<f64, $k>,
                near: &SVector<f64, $d>,
            ) -> Result<SVector<f64, $d>, LieError> {
                let w = self.rotation_vector_near(
                    g.attitude.matrix(),
                    &near.fixed_rows::<3>(0).into_owned(),
                )?;
                let mut xi = SVector::<f64, $d>::zeros();
                xi.fixed_rows_mut::<3>(0).copy_from(&w);
                xi.fixed_rows_mut::<$k>(3).copy_from(&g.wheels);
                Ok(xi)
            }
            fn check_domain(&self, xi: &SVector<f64, $d>) -> Result<(), LieError> {
                if !xi.iter().all(|x| x.is_finite()) {
                    return Err(LieError::NonFinite {
                        what: "chart coordinates",
                    });
                }
                self.check_rotation_domain(&xi.fixed_rows::<3>(0).into_owned())
            }
            fn max_rotation_angle(&self) -> f64 {
                So3Chart::max_rotation_angle(self)
            }
            fn advice(&self) -> &'static str {
                GroupChart::<Rotations, 3>::advice(self)
            }
            /// `(Φ(ω) p_ω, p_φ)` (`Ad_{Φ⁻¹}ᵀ = diag(Φ(ω), I)`): the SO(3) chart's transport
            /// on the attitude, the identity on ℝᴷ.
            fn coadjoint_to_start(
                &self,
                x: &SVector<f64, $d>,
                p: &SVector<f64, $d>,
            ) -> SVector<f64, $d> {
                let turned = GroupChart::<Rotations, 3>::coadjoint_to_start(
                    self,
                    &x.fixed_rows::<3>(0).into_owned(),
                    &p.fixed_rows::<3>(0).into_owned(),
                );
                let mut out = *p;
                out.fixed_rows_mut::<3>(0).copy_from(&turned);
                out
            }
            /// `(diag(Φ(ω), I), diag(A(ω), I))` from the SO(3) chart's pair (one evaluation
            /// of its Rodrigues coefficients).
            fn transport_and_differential(
                &self,
                x: &SVector<f64, $d>,
            ) -> (SMatrix<f64, $d, $d>, SMatrix<f64, $d, $d>) {
                let (rotation, differential) =
                    GroupChart::<Rotations, 3>::transport_and_differential(
                        self,
                        &x.fixed_rows::<3>(0).into_owned(),
                    );
                let (mut transport, mut a) = (
                    SMatrix::<f64, $d, $d>::identity(),
                    SMatrix::<f64, $d, $d>::identity(),
                );
                transport.fixed_view_mut::<3, 3>(0, 0).copy_from(&rotation);
                a.fixed_view_mut::<3, 3>(0, 0).copy_from(&differential);
                (transport, a)
            }
            /// In closed form (those of the attitude's `A(ω)`, from its Rodrigues jet: the
            /// identity on ℝᴷ has none) where the chart has a Rodrigues form, by dual
            /// numbers otherwise.
            fn with_derivatives<R>(
                &self,
                x: &SVector<f64, $d>,
                second: bool,
                f: impl FnOnce(&dyn ChartDerivatives<$d>) -> R,
            ) -> R {
                let w = x.fixed_rows::<3>(0).into_owned();
                let s = w.norm_squared();
                let jet = if second {
                    self.rotation_left_differential_coefficients(Dual2_64::new(s, 1.0, 0.0))
                        .map(|a| MatrixJet::from_rodrigues(&a, &w))
                } else {
                    self.rotation_left_differential_coefficients(Dual64::new(s, 1.0))
                        .map(|a| MatrixJet::from_rodrigues_first_order(&a, &w))
                };
                match jet {
                    Some(a) => f(&AttitudeTimesVectorDerivatives { a }),
                    None => dual_number_derivatives::<BodyAndWheels<$k>, Self, R, $d>(self, x, f),
                }
            }
        }

        impl Gyrostat<$k> {
            /// The constant mass matrix `M = [[J, A𝐈], [𝐈Aᵀ, 𝐈]]`.
            pub fn mass_matrix(&self) -> SMatrix<f64, $d, $d> {
                let mut m = SMatrix::<f64, $d, $d>::zeros();
                m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.inertia);
                for (i, (a, &w)) in self.axes.iter().zip(&self.wheel_inertia).enumerate() {
                    m.fixed_view_mut::<3, 1>(0, 3 + i).copy_from(&(a * w));
                    m.fixed_view_mut::<1, 3>(3 + i, 0)
                        .copy_from(&(a.transpose() * w));
                    m[(3 + i, 3 + i)] = w;
                }
                m
            }
        }

        impl System<$d> for Gyrostat<$k> {
            type Group = BodyAndWheels<$k>;
            /// `½ΩᵀJΩ + Σ I_i (a_iᵀΩ) φ̇_i + ½ Σ I_i φ̇_i²`.
            fn lagrangian<T: RealField + Copy>(
                &self,
                _time: f64,
                _configuration: &BodyWheels<T, $k>,
                velocity: &SVector<T, $d>,
            ) -> T {
                let c = |x: f64| -> T { nalgebra::convert(x) };
                let w = velocity.fixed_rows::<3>(0).into_owned();
                let j: Matrix3<T> = self.inertia.map(nalgebra::convert);
                let mut value = w.dot(&(j * w)) * c(0.5);
                for (i, (a, &inertia)) in self.axes.iter().zip(&self.wheel_inertia).enumerate() {
                    let axis: Vector3<T> = a.map(nalgebra::convert);
                    let spin = velocity[3 + i];
                    value += c(inertia) * (axis.dot(&w) * spin + c(0.5) * spin * spin);
                }
                value
            }
            /// The six entries of `J` (wheels locked) and each wheel's axial inertia
            /// `I_1 … I_K`, each varied with the others held: `∂ℓ/∂I_i = (a_iᵀΩ) φ̇_i + ½φ̇_i²`.
            fn parameter_names(&self) -> Vec<String> {
                let mut names = crate::lagrangian::inertia_parameter_names(&[]);
                names.extend((1..=$k).map(|i| format!("I_{i}")));
                names
            }
            fn parameter_lagrangian<T: RealField + Copy>(
                &self,
                index: usize,
                _time: f64,
                _configuration: &BodyWheels<T, $k>,
                velocity: &SVector<T, $d>,
            ) -> T {
                let w = velocity.fixed_rows::<3>(0).into_owned();
                if index < 6 {
                    return crate::lagrangian::kinetic_parameter(index, &w);
                }
                let Some(a) = self.axes.get(index - 6) else {
                    return T::zero();
                };
                let axis: Vector3<T> = a.map(nalgebra::convert);
                let spin = velocity[3 + index - 6];
                axis.dot(&w) * spin + spin * spin * nalgebra::convert::<f64, T>(0.5)
            }
            fn is_left_invariant(&self) -> bool {
                true
            }
            /// `|Ω|` and the fastest wheel's spin `max |φ̇_i|`.
            fn motion_rate(
                &self,
                _time: f64,
                _configuration: &BodyWheels<f64, $k>,
                velocity: &SVector<f64, $d>,
            ) -> f64 {
                let spin = velocity.fixed_rows::<3>(0).norm();
                spin + velocity.iter().skip(3).fold(0.0f64, |m, w| m.max(w.abs()))
            }
            /// `Ω = J_b⁻¹(h − Σ a_i p_i)`, `φ̇_i = p_i / I_i − a_iᵀΩ`.
            fn velocity_from_momentum(
                &self,
                _time: f64,
                _configuration: &BodyWheels<f64, $k>,
                momentum: &SVector<f64, $d>,
            ) -> Option<SVector<f64, $d>> {
                let h = momentum.fixed_rows::<3>(0).into_owned();
                let wheels = self
                    .axes
                    .iter()
                    .enumerate()
                    .fold(Vector3::zeros(), |s, (i, a)| s + a * momentum[3 + i]);
                let w = self.body_inverse * (h - wheels);
                let mut xi = SVector::<f64, $d>::zeros();
                xi.fixed_rows_mut::<3>(0).copy_from(&w);
                for (i, (a, &inertia)) in self.axes.iter().zip(&self.wheel_inertia).enumerate() {
                    xi[3 + i] = momentum[3 + i] / inertia - a.dot(&w);
                }
                Some(xi)
            }
            /// `p = 0` (cyclic), `μ = MΩ̃`, Hessians `0` and `M`.
            fn local_derivatives(
                &self,
                _time: f64,
                _configuration: &BodyWheels<f64, $k>,
                velocity: &SVector<f64, $d>,
                with_hessian: bool,
            ) -> Option<LocalDerivatives<$d>> {
                let m = self.mass_matrix();
                Some(LocalDerivatives {
                    configuration_gradient: SVector::zeros(),
                    momentum: m * velocity,
                    configuration_hessian: SMatrix::zeros(),
                    velocity_hessian: if with_hessian { m } else { SMatrix::zeros() },
                })
            }
        }

        impl crate::control::GroupLog<$d> for BodyWheels<f64, $k> {
            /// `(log(R̄ᵀR), φ − φ̄)`.
            fn log_from(&self, reference: &Self) -> SVector<f64, $d> {
                let mut theta = SVector::<f64, $d>::zeros();
                theta
                    .fixed_rows_mut::<3>(0)
                    .copy_from(&reference.attitude.inverse().compose(&self.attitude).log());
                theta
                    .fixed_rows_mut::<$k>(3)
                    .copy_from(&(self.wheels - reference.wheels));
                theta
            }
        }
    };
}

wheels!(1, 4, 12, 8);
wheels!(2, 5, 15, 10);
wheels!(3, 6, 18, 12);
wheels!(4, 7, 21, 14);
