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
use crate::system::{LocalDerivatives, System};
use lgsvi_lie::LieGroup;
use nalgebra::{Matrix3, RealField, SMatrix, SVector, Vector3};

pub use lgsvi_lie::product::{BodyAndWheels, BodyWheels};

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

/// Implements the gyrostat for one wheel count.
macro_rules! wheels {
    ($k:literal, $d:literal) => {
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

wheels!(1, 4);
wheels!(2, 5);
wheels!(3, 6);
wheels!(4, 7);
