//! The product group SO(3) × ℝᴷ (`D = 3 + K`, `K = 1..=4`): an attitude with `K` angles or
//! lengths beside it that the rotation does not act on, such as a gyrostat's wheel angles.
//! Elements are [`BodyWheels`] (attitude `R = world_from_body`, the vector `φ`), the marker
//! is [`BodyAndWheels`]; tangents are `(ω, φ̇)`, `ω` the body angular velocity. Every
//! [`So3Chart`] is a [`GroupChart`] of it: the SO(3) chart on the attitude and the identity
//! on `ℝᴷ`, with derivatives in closed form from the Rodrigues jet of `A(ω)`.
//!
//! ```
//! use lgsvi_lie::laws::{group_chart_laws, group_laws};
//! use lgsvi_lie::product::{BodyAndWheels, BodyWheels};
//! use lgsvi_lie::{CayleyChart, SO3};
//! use nalgebra::{SVector, Vector2};
//!
//! let g = BodyWheels { attitude: SO3::about_x(0.4), wheels: Vector2::new(1.0, -2.0) };
//! let h = BodyWheels { attitude: SO3::about_z(-0.7), wheels: Vector2::new(0.5, 3.0) };
//! let tangents = [SVector::<f64, 5>::new(0.1, -0.2, 0.3, 1.0, 2.0)];
//! group_laws(&[g, h], &tangents, 1e-13)?;
//! group_chart_laws::<BodyAndWheels<2>, _, 5>(&CayleyChart, &tangents, 1e-13)?;
//! # Ok::<(), lgsvi_lie::laws::LawViolation>(())
//! ```

use crate::chart::{Chart, So3Chart};
use crate::configuration::{ConfigurationGroup, Rotations};
use crate::error::LieError;
use crate::group::{ExponentialMap, LieGroup};
use crate::group_chart::{dual_number_derivatives, so3_advice, ChartDerivatives, GroupChart};
use crate::jet::MatrixJet;
use crate::so3::SO3;
use nalgebra::{Matrix3, RealField, SMatrix, SVector, Vector3};
use num_dual::{Dual2_64, Dual64};

/// An element of SO(3) × ℝᴷ: the attitude `R = world_from_body` and a vector the rotation
/// does not act on (named for the gyrostat, its first use: the wheel angles).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyWheels<T: RealField + Copy, const K: usize> {
    /// `R`, world from body.
    pub attitude: SO3<T>,
    /// The ℝᴷ part `φ`: a gyrostat's wheel angles relative to the body, or any `K`
    /// coordinates beside the attitude (a centre of mass, for `K = 3`).
    pub wheels: SVector<T, K>,
}

/// The marker type of the group SO(3) × ℝᴷ (`D = 3 + K`; implemented for `K = 1..=4`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BodyAndWheels<const K: usize>;

/// The derivatives of an SO(3) chart on the attitude and the identity on ℝᴷ
/// (`A = diag(A_ω(ω), I)`) in closed form, from the Rodrigues jet of `A_ω`, which depends
/// on `ω` alone: with `x = (ω, φ)`, `∂(Av)/∂ω = [∂_kA_ω v_ω ; 0]_k`,
/// `∂(Aᵀg)/∂ω = [∂_kA_ωᵀ g_ω ; 0]_k`, `∇²(μᵀAv) = ⟨μ_ω v_ωᵀ, ∂²A_ω⟩` in the `ω` block,
/// nothing in `φ` (the identity's derivatives vanish).
struct AttitudeTimesVectorDerivatives {
    a: MatrixJet,
}

/// Implements the group and its charts for one `K`.
macro_rules! product {
    ($k:literal, $d:literal) => {
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
                    crate::so3::hat(&xi.fixed_rows::<3>(0).into_owned()),
                    xi.fixed_rows::<$k>(3).into_owned(),
                )
            }
            fn vee(matrix: &(Matrix3<T>, SVector<T, $k>)) -> SVector<T, $d> {
                let mut xi = SVector::<T, $d>::zeros();
                xi.fixed_rows_mut::<3>(0)
                    .copy_from(&crate::so3::vee(&matrix.0));
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
                    .copy_from(&crate::so3::hat(&xi.fixed_rows::<3>(0).into_owned()));
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
        /// ([`crate::laws`]) reads.
        impl<T: RealField + Copy> ExponentialMap for BodyWheels<T, $k> {
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
                so3_advice(self)
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
    };
}

product!(1, 4);
product!(2, 5);
product!(3, 6);
product!(4, 7);
