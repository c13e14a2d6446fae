//! [`GroupChart`]: a chart `Φ: ℝ^D → G` of a [`ConfigurationGroup`] over every scalar,
//! with the derivatives of its left-trivialised differential ([`ChartDerivatives`]) that a
//! Galerkin step's Gauss points read. Every [`So3Chart`] is one on [`Rotations`] and, as
//! the rotation–translation chart, on [`RigidMotions`]; [`Screw`] gives SE(3)'s
//! screw-motion charts.

use crate::chart::{Chart, RodriguesCoefficients, So3Chart};
use crate::configuration::{ConfigurationGroup, RigidMotions, Rotations};
use crate::error::LieError;
use crate::group::LieGroup;
use crate::jet::{jacobian_of, seeded, MatrixJet};
use crate::se3::SE3;
use crate::so3::SO3;
use nalgebra::{Matrix3, RealField, SMatrix, SVector, Vector3};
use num_dual::{Dual2SVec64, Dual2_64, Dual64, DualSVec64};
use std::fmt::Debug;

mod se3;
#[doc(hidden)]
pub use se3::RotationTranslationDerivatives;
pub use se3::Screw;

/// A chart's derivatives at one point `x`, contracted as a Galerkin step's chain rule
/// (lgsvi's integrator at its Gauss points) reads them: `A(x)`, `∂(A(x)v)/∂x`, `∂(A(x)ᵀg)/∂x` and
/// `∇²_x(μᵀA(x)v)`. Every [`GroupChart`] has them by dual numbers in `x` alone
/// ([`GroupChart::with_derivatives`]'s default); the SO(3), SE(3) rotation–translation
/// and SO(3) × ℝᴷ charts of this crate in closed form.
pub trait ChartDerivatives<const D: usize> {
    /// `A(x)`.
    fn differential(&self) -> SMatrix<f64, D, D>;
    /// `∂(A(x) v)/∂x`, entry `(component, component of x)`.
    fn differential_times(&self, v: &SVector<f64, D>) -> SMatrix<f64, D, D>;
    /// `∂(A(x)ᵀ g)/∂x`, entry `(component, component of x)`.
    fn transpose_times(&self, g: &SVector<f64, D>) -> SMatrix<f64, D, D>;
    /// `∇²_x (μᵀ A(x) v)` (only asked for when [`GroupChart::with_derivatives`] was
    /// called with `second`).
    fn second(&self, mu: &SVector<f64, D>, v: &SVector<f64, D>) -> SMatrix<f64, D, D>;
    /// SE(3)'s rotation–translation chart's derivatives (`A = diag(A(ω), Φ(ω)ᵀ)`, the
    /// Rodrigues jets of `A(ω)` and `Φ(ω)`), from which the built-in SE(3) systems take a
    /// Gauss point's derivatives by 3 × 3 blocks; `None` (the default) for every other
    /// chart. Hidden: lgsvi's own fast path, whose form may change; a chart of your own
    /// leaves it `None`.
    #[doc(hidden)]
    fn rotation_translation(&self) -> Option<&RotationTranslationDerivatives> {
        None
    }
}

/// [`ChartDerivatives`] by dual numbers: `A` at first-order dual numbers in `x` (one
/// evaluation, contracted three ways), the second derivatives by a second-order dual
/// number through `μᵀA(x)v`.
struct DualDerivatives<'a, G, C, const D: usize> {
    chart: &'a C,
    x: &'a SVector<f64, D>,
    a: SMatrix<f64, D, D>,
    a_dual: SMatrix<DualSVec64<D>, D, D>,
    group: std::marker::PhantomData<G>,
}

impl<G: ConfigurationGroup<D>, C: GroupChart<G, D>, const D: usize> DualDerivatives<'_, G, C, D> {
    fn contract(&self, u: &SVector<f64, D>, transposed: bool) -> SMatrix<f64, D, D> {
        let u = u.map(nalgebra::convert::<f64, DualSVec64<D>>);
        let y = if transposed {
            self.a_dual.transpose() * u
        } else {
            self.a_dual * u
        };
        jacobian_of(&y)
    }
}

impl<G: ConfigurationGroup<D>, C: GroupChart<G, D>, const D: usize> ChartDerivatives<D>
    for DualDerivatives<'_, G, C, D>
{
    fn differential(&self) -> SMatrix<f64, D, D> {
        self.a
    }
    fn differential_times(&self, v: &SVector<f64, D>) -> SMatrix<f64, D, D> {
        self.contract(v, false)
    }
    fn transpose_times(&self, g: &SVector<f64, D>) -> SMatrix<f64, D, D> {
        self.contract(g, true)
    }
    fn second(&self, mu: &SVector<f64, D>, v: &SVector<f64, D>) -> SMatrix<f64, D, D> {
        let chart = self.chart;
        let (_, _, h) = num_dual::hessian(
            |y: SVector<Dual2SVec64<D>, D>| {
                let a = chart.left_differential(&y);
                let v = v.map(nalgebra::convert::<f64, Dual2SVec64<D>>);
                let mu = mu.map(nalgebra::convert::<f64, Dual2SVec64<D>>);
                mu.dot(&(a * v))
            },
            self.x,
        );
        h
    }
}

/// Calls `f` with the dual-number [`ChartDerivatives`] of `chart` at `x`: the default of
/// [`GroupChart::with_derivatives`], and the reference the closed forms are tested against.
pub fn dual_number_derivatives<G, C, R, const D: usize>(
    chart: &C,
    x: &SVector<f64, D>,
    f: impl FnOnce(&dyn ChartDerivatives<D>) -> R,
) -> R
where
    G: ConfigurationGroup<D>,
    C: GroupChart<G, D>,
{
    let derivatives = DualDerivatives::<G, C, D> {
        chart,
        x,
        a: chart.left_differential(x),
        a_dual: chart.left_differential(&seeded(x)),
        group: std::marker::PhantomData,
    };
    f(&derivatives)
}

/// `Ad_{Φ⁻¹}ᵀ` at a chart point's group element `Φ`: takes a configuration force there to
/// the step's start (the exact matching's transport, [`GroupChart::coadjoint_to_start`]).
fn coadjoint_to_start<G: ConfigurationGroup<D>, const D: usize>(
    phi: &G::Element<f64>,
) -> SMatrix<f64, D, D> {
    phi.inverse().adjoint().transpose()
}

/// A chart `Φ: ℝ^D → G` of a [`ConfigurationGroup`] over every scalar, as lgsvi's
/// integrator uses it. Every [`So3Chart`] is one on [`Rotations`], [`RigidMotions`] and
/// SO(3) × ℝᴷ ([`crate::product`]); implement it directly for a group of your own, and check
/// it with [`crate::laws::group_chart_laws`].
///
/// Chosen by type: an integrator is monomorphised for its chart, so a chart type costs
/// no dispatch per call ([`crate::ChartKind`], the run-time choice, matches per call).
pub trait GroupChart<G: ConfigurationGroup<D>, const D: usize>: Copy + Debug + Send + Sync {
    /// Name, for messages.
    fn name(&self) -> &'static str;
    /// `Φ(ξ)`.
    fn to_group<T: RealField + Copy>(&self, xi: &SVector<T, D>) -> G::Element<T>;
    /// The left-trivialised differential `A(ξ)`: `Φ(ξ)⁻¹ DΦ(ξ)[v] = (A(ξ) v)^`.
    fn left_differential<T: RealField + Copy>(&self, xi: &SVector<T, D>) -> SMatrix<T, D, D>;
    /// `A(ξ)⁻¹`.
    ///
    /// # Errors
    /// Outside the chart's domain.
    fn left_differential_inverse(
        &self,
        xi: &SVector<f64, D>,
    ) -> Result<SMatrix<f64, D, D>, LieError>;
    /// `A(y)⁻¹ ξ`, the chart velocity `ẏ` of a body velocity `ξ` at `y`, where `phi` is
    /// `Φ(y)`: what a flow integrated in the chart reads at every stage, with `Φ(y)` at
    /// hand. The default forms `A(y)⁻¹` ([`GroupChart::left_differential_inverse`]);
    /// SE(3)'s rotation–translation chart applies its blocks (`A(ω)⁻¹` and `Φ(ω)` from
    /// `phi`) to the halves of `ξ`, the same values.
    ///
    /// # Errors
    /// Outside the chart's domain.
    fn chart_velocity(
        &self,
        y: &SVector<f64, D>,
        phi: &G::Element<f64>,
        xi: &SVector<f64, D>,
    ) -> Result<SVector<f64, D>, LieError> {
        let _ = phi;
        Ok(self.left_differential_inverse(y)? * xi)
    }
    /// `Φ⁻¹(g)` on the branch nearest `near` (for charts that cover an element twice).
    ///
    /// # Errors
    /// Outside the chart's image.
    fn to_algebra_near(
        &self,
        g: &G::Element<f64>,
        near: &SVector<f64, D>,
    ) -> Result<SVector<f64, D>, LieError>;
    /// Finite and where `Φ` is a local diffeomorphism. The default accepts every finite
    /// `ξ`: a chart that is a diffeomorphism everywhere (angles, translations).
    ///
    /// # Errors
    /// [`LieError::NonFinite`] or [`LieError::OutsideChart`].
    fn check_domain(&self, xi: &SVector<f64, D>) -> Result<(), LieError> {
        if xi.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(LieError::NonFinite {
                what: "chart coordinates",
            })
        }
    }
    /// The largest rotation angle a curve from the identity can reach in this chart
    /// ([`So3Chart::max_rotation_angle`]). The default is infinite: a group without
    /// rotations.
    fn max_rotation_angle(&self) -> f64 {
        f64::INFINITY
    }
    /// Advice beside "take a smaller step" when a step outruns the chart.
    fn advice(&self) -> &'static str {
        ""
    }
    /// `Φ` on rotations in Rodrigues form, where it has one (the SO(3) closed-form path).
    fn rotation_coefficients<T: RealField + Copy>(&self, s: T) -> Option<RodriguesCoefficients<T>> {
        let _ = s;
        None
    }
    /// `A` on rotations in Rodrigues form, where it has one.
    fn left_differential_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<RodriguesCoefficients<T>> {
        let _ = s;
        None
    }
    /// `Ad_{Φ(x)⁻¹}ᵀ p`: a covector at the chart point `x` taken to the step's start (the
    /// exact matching's transport of a configuration force). The default forms `Φ(x)`;
    /// SO(3)'s charts apply `Φ(x)` (which `Ad_{Φ⁻¹}ᵀ` is on SO(3)) to `p` from its Rodrigues
    /// coefficients, and so does SE(3)'s rotation–translation chart to both halves of `p`.
    fn coadjoint_to_start(&self, x: &SVector<f64, D>, p: &SVector<f64, D>) -> SVector<f64, D> {
        coadjoint_to_start::<G, D>(&self.to_group(x)) * p
    }
    /// `(Ad_{Φ(x)⁻¹}ᵀ, A(x))` at a chart point together: the exact matching's transport of
    /// a configuration force and the chart's left differential, which its Newton rows read
    /// at every Gauss point. The default forms `Φ(x)` and `A(x)` apart; SO(3)'s charts and
    /// SE(3)'s rotation–translation chart build both from one evaluation of their Rodrigues
    /// coefficients.
    fn transport_and_differential(
        &self,
        x: &SVector<f64, D>,
    ) -> (SMatrix<f64, D, D>, SMatrix<f64, D, D>) {
        (
            coadjoint_to_start::<G, D>(&self.to_group(x)),
            self.left_differential(x),
        )
    }
    /// Calls `f` with the chart's derivatives at `x` ([`ChartDerivatives`]; with `second`,
    /// the second derivatives are asked for too). The default takes them by dual numbers
    /// in `x` alone ([`dual_number_derivatives`]); override it with a closed form.
    fn with_derivatives<R>(
        &self,
        x: &SVector<f64, D>,
        second: bool,
        f: impl FnOnce(&dyn ChartDerivatives<D>) -> R,
    ) -> R
    where
        Self: Sized,
    {
        let _ = second;
        dual_number_derivatives::<G, Self, R, D>(self, x, f)
    }
}

/// What to suggest besides a smaller step: the Cayley charts reach half a turn, exp two.
pub(crate) fn so3_advice<C: So3Chart>(chart: &C) -> &'static str {
    if chart.max_rotation_angle() < std::f64::consts::TAU {
        " or the exp chart, which follows up to 2π per step"
    } else {
        ""
    }
}

impl<C: So3Chart + Send + Sync> GroupChart<Rotations, 3> for C {
    fn name(&self) -> &'static str {
        self.chart_name()
    }
    #[inline]
    fn to_group<T: RealField + Copy>(&self, xi: &Vector3<T>) -> SO3<T> {
        SO3::from_matrix_unchecked(self.rotation_matrix(xi))
    }
    #[inline]
    fn left_differential<T: RealField + Copy>(&self, xi: &Vector3<T>) -> Matrix3<T> {
        self.rotation_left_differential(xi)
    }
    fn left_differential_inverse(&self, xi: &Vector3<f64>) -> Result<Matrix3<f64>, LieError> {
        Chart::<SO3>::left_differential_inverse(self, xi)
    }
    fn to_algebra_near(&self, g: &SO3, near: &Vector3<f64>) -> Result<Vector3<f64>, LieError> {
        self.rotation_vector_near(g.matrix(), near)
    }
    fn check_domain(&self, xi: &Vector3<f64>) -> Result<(), LieError> {
        self.check_rotation_domain(xi)
    }
    fn max_rotation_angle(&self) -> f64 {
        So3Chart::max_rotation_angle(self)
    }
    fn advice(&self) -> &'static str {
        so3_advice(self)
    }
    fn rotation_coefficients<T: RealField + Copy>(&self, s: T) -> Option<RodriguesCoefficients<T>> {
        self.rotation_matrix_coefficients(s)
    }
    /// `(Φ(x), A(x))` (`Ad_{R⁻¹}ᵀ = R` on SO(3)) from one evaluation of the Rodrigues
    /// coefficients where the chart has them.
    #[inline]
    fn transport_and_differential(&self, x: &Vector3<f64>) -> (Matrix3<f64>, Matrix3<f64>) {
        match self.rotation_and_left_differential_coefficients(x.norm_squared()) {
            Some((phi, a)) => (phi.matrix(x), a.matrix(x)),
            None => (self.rotation_matrix(x), self.rotation_left_differential(x)),
        }
    }
    /// `Φ(x) p` (`Ad_R = R` on SO(3)), without forming `Φ(x)` where the chart has a
    /// Rodrigues form.
    #[inline]
    fn coadjoint_to_start(&self, x: &Vector3<f64>, p: &Vector3<f64>) -> Vector3<f64> {
        match self.rotation_matrix_coefficients(x.norm_squared()) {
            Some(c) => c.times(x, p),
            None => self.rotation_matrix(x) * p,
        }
    }
    fn left_differential_coefficients<T: RealField + Copy>(
        &self,
        s: T,
    ) -> Option<RodriguesCoefficients<T>> {
        self.rotation_left_differential_coefficients(s)
    }
    /// In closed form from `A`'s Rodrigues jet where the chart has a Rodrigues form (the
    /// generic chain rule's Gauss points, the matching rows' map Jacobian); by dual
    /// numbers otherwise.
    fn with_derivatives<R>(
        &self,
        x: &Vector3<f64>,
        second: bool,
        f: impl FnOnce(&dyn ChartDerivatives<3>) -> R,
    ) -> R {
        let s = x.norm_squared();
        let jet = if second {
            self.rotation_left_differential_coefficients(Dual2_64::new(s, 1.0, 0.0))
                .map(|a| MatrixJet::from_rodrigues(&a, x))
        } else {
            self.rotation_left_differential_coefficients(Dual64::new(s, 1.0))
                .map(|a| MatrixJet::from_rodrigues_first_order(&a, x))
        };
        match jet {
            Some(a) => f(&RotationDerivatives { a }),
            None => dual_number_derivatives::<Rotations, Self, R, 3>(self, x, f),
        }
    }
}

/// An SO(3) chart's derivatives from the Rodrigues jet of `A(x)`
/// ([`GroupChart::with_derivatives`] of every [`So3Chart`] with a Rodrigues form).
struct RotationDerivatives {
    a: MatrixJet,
}

impl ChartDerivatives<3> for RotationDerivatives {
    fn differential(&self) -> Matrix3<f64> {
        self.a.value
    }
    fn differential_times(&self, v: &Vector3<f64>) -> Matrix3<f64> {
        self.a.first_times(v)
    }
    fn transpose_times(&self, g: &Vector3<f64>) -> Matrix3<f64> {
        self.a.first_transposed_times(g).transpose()
    }
    fn second(&self, mu: &Vector3<f64>, v: &Vector3<f64>) -> Matrix3<f64> {
        self.a.second_contracted(&(mu * v.transpose()))
    }
}
