//! The configuration groups and charts the integrator is generic over.
//!
//! A step works in the Lie algebra `ℝ^D` of a group `G` through a chart `Φ: ℝ^D → G`. All
//! it needs of the group is in [`ConfigurationGroup`] (composition, the adjoint, the
//! exponential for configuration variations, the storage of one Gauss point's
//! derivatives) and of the chart in [`GroupChart`] (`Φ`, its left-trivialised
//! differential `A` and inverse). Both are implemented here for
//!
//! | group | `D` | marker | element | charts |
//! |---|---|---|---|---|
//! | SO(3) | 3 | [`Rotations`] | [`SO3`] | every [`So3Chart`]: exp, Cayley, the paper's Cayley, [`lgsvi_lie::ChartKind`] |
//! | SE(3) | 6 | [`RigidMotions`] | [`SE3`] (tangent `(ω, v)`, body velocities) | every [`So3Chart`] as the rotation–translation chart `(Φ(ω), u)` (the default: SO(3) × ℝ³'s discrete map, derivatives in closed form); [`Screw`]`(chart)`, SE(3)'s own screw-motion charts as in `lgsvi_lie` |
//!
//! # Adding a group or a chart
//! A chart of SO(3) or SE(3) of your own: implement [`So3Chart`] (the lie crate's law
//! tests show what it must satisfy); the blanket impls here make it a [`GroupChart`] of
//! both groups. A group of your own with algebra dimension `D`: a marker type implementing
//! [`ConfigurationGroup<D>`] whose `Element<T>` implements [`LieGroup`] over any scalar
//! (dual numbers pass through it), with `Jet = Stacked<{3D}>` and
//! `LocalJet = Stacked<{2D}>` written out (e.g. `Stacked<12>` and `Stacked<8>` for `D = 4`), and a chart implementing [`GroupChart`] for it. The
//! integrator then runs any [`crate::System`] on it unchanged; the test
//! `tests/tests/generic_group.rs` does this for the torus `SO(2) × SO(2)`.

use crate::matrix_jet::MatrixJet;
use lgsvi_lie::se3::{blocks, split};
use lgsvi_lie::{Chart, LieError, LieGroup, RodriguesCoefficients, So3Chart, SE3, SO3};
use nalgebra::{Matrix3, RealField, SMatrix, SVector, Vector3};
use num_dual::{Dual2SVec64, Dual2_64, Dual64, DualSVec64};
use std::fmt::Debug;

mod se3_charts;
pub(crate) use se3_charts::RotationTranslationDerivatives;
pub use se3_charts::Screw;

/// A function of the stacked variables of one Gauss point, generic over the scalar so
/// that dual numbers pass through it (what [`PointJet::set_by_dual_numbers`] differentiates).
pub trait StackedFunction {
    /// The value at `y`.
    fn eval<T: RealField + Copy>(&self, y: &[T]) -> T;
}

/// A vector function of the stacked variables, generic over the scalar (what
/// [`PointJet::add_force`] differentiates).
pub trait StackedMap {
    /// Writes the value at `y` into `out` (`out.len()` outputs).
    fn eval<T: RealField + Copy>(&self, y: &[T], out: &mut [T]);
}

/// The first and second derivatives of `ℓ̃(x, v, ζ)` at one Gauss point, `3D` stacked
/// variables (`x`, then `v`, then `ζ`): the gradient and the Jacobian of the gradient
/// (the Hessian; with a non-conservative force added it is not symmetric), entry
/// `(component, variable)`.
pub trait PointJet: Clone + Debug + Send + Sync {
    /// All zero.
    fn zeros() -> Self;
    /// The number of stacked variables, `3D`.
    fn size(&self) -> usize;
    /// The gradient.
    fn gradient(&self) -> &[f64];
    /// The gradient, to write.
    fn gradient_mut(&mut self) -> &mut [f64];
    /// Entry `(component, variable)` of the Hessian.
    fn hessian(&self, row: usize, col: usize) -> f64;
    /// Adds to entry `(row, col)` of the Hessian.
    fn add_hessian(&mut self, row: usize, col: usize, value: f64);
    /// Sets the gradient and Hessian to those of `f` at the stacked `(x, v)`, or
    /// `(x, v, 0)` with `with_configuration`, by a second-order dual number (the entries
    /// of variables not passed are zero).
    fn set_by_dual_numbers<F: StackedFunction>(
        &mut self,
        f: &F,
        x: &[f64],
        v: &[f64],
        with_configuration: bool,
    );
    /// Sets the gradient of `f` at the stacked `(x, v)` (or `(x, v, 0)`) by a first-order
    /// dual number, leaving the Hessian as it was: a tenth of the cost or less.
    fn set_gradient_by_dual_numbers<F: StackedFunction>(
        &mut self,
        f: &F,
        x: &[f64],
        v: &[f64],
        with_configuration: bool,
    );
    /// Sets entry `(row, col)` of the Hessian.
    fn set_hessian(&mut self, row: usize, col: usize, value: f64);
    /// Adds a force term: `f` maps the stacked `(x, v)` to `2D` outputs, the first `D`
    /// added to the `x` rows of the gradient, the last `D` to its `ζ` rows, with their
    /// Jacobian (first-order dual numbers) added to those rows of the Hessian.
    fn add_force<F: StackedMap>(&mut self, f: &F, x: &[f64], v: &[f64]);
}

/// The derivatives of one Gauss point in `N = 3D` stacked variables: the storage every
/// group here uses (`Stacked<9>` for SO(3), `Stacked<18>` for SE(3)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stacked<const N: usize> {
    /// The gradient.
    pub gradient: SVector<f64, N>,
    /// The Hessian, entry `(component, variable)`.
    pub hessian: SMatrix<f64, N, N>,
}

/// `(x, v, 0)` stacked into `N` variables, and how many of them are live: `3D` with the
/// configuration variables, else `2D`.
fn stacked<const N: usize>(
    x: &[f64],
    v: &[f64],
    with_configuration: bool,
) -> (SVector<f64, N>, usize) {
    let d = x.len();
    let mut y = SVector::<f64, N>::zeros();
    y.as_mut_slice()[..d].copy_from_slice(x);
    y.as_mut_slice()[d..2 * d].copy_from_slice(v);
    (y, if with_configuration { 3 * d } else { 2 * d })
}

impl<const N: usize> PointJet for Stacked<N> {
    fn zeros() -> Self {
        Self {
            gradient: SVector::zeros(),
            hessian: SMatrix::zeros(),
        }
    }
    fn size(&self) -> usize {
        N
    }
    fn gradient(&self) -> &[f64] {
        self.gradient.as_slice()
    }
    fn gradient_mut(&mut self) -> &mut [f64] {
        self.gradient.as_mut_slice()
    }
    #[inline]
    fn hessian(&self, row: usize, col: usize) -> f64 {
        self.hessian[(row, col)]
    }
    #[inline]
    fn add_hessian(&mut self, row: usize, col: usize, value: f64) {
        self.hessian[(row, col)] += value;
    }
    fn set_by_dual_numbers<F: StackedFunction>(
        &mut self,
        f: &F,
        x: &[f64],
        v: &[f64],
        with_configuration: bool,
    ) {
        let (y, k) = stacked::<N>(x, v, with_configuration);
        let (_, gradient, hessian) = num_dual::hessian(
            |y: SVector<Dual2SVec64<N>, N>| f.eval(&y.as_slice()[..k]),
            &y,
        );
        self.gradient = gradient;
        self.hessian = hessian;
    }
    fn set_gradient_by_dual_numbers<F: StackedFunction>(
        &mut self,
        f: &F,
        x: &[f64],
        v: &[f64],
        with_configuration: bool,
    ) {
        let (y, k) = stacked::<N>(x, v, with_configuration);
        let (_, gradient) = num_dual::gradient(
            |y: SVector<DualSVec64<N>, N>| f.eval(&y.as_slice()[..k]),
            &y,
        );
        self.gradient = gradient;
    }
    #[inline]
    fn set_hessian(&mut self, row: usize, col: usize, value: f64) {
        self.hessian[(row, col)] = value;
    }
    fn add_force<F: StackedMap>(&mut self, f: &F, x: &[f64], v: &[f64]) {
        let d = x.len();
        let unit = |i: usize| SVector::<f64, N>::from_fn(|j, _| if i == j { 1.0 } else { 0.0 });
        // First-order dual numbers with N directions, the first 2D seeded.
        let y: SVector<DualSVec64<N>, N> = SVector::from_fn(|i, _| {
            if i < d {
                DualSVec64::<N>::new(x[i], num_dual::Derivative::some(unit(i)))
            } else if i < 2 * d {
                DualSVec64::<N>::new(v[i - d], num_dual::Derivative::some(unit(i)))
            } else {
                DualSVec64::<N>::from_re(0.0)
            }
        });
        let mut out: SVector<DualSVec64<N>, N> = SVector::from_element(DualSVec64::from_re(0.0));
        f.eval(&y.as_slice()[..2 * d], &mut out.as_mut_slice()[..2 * d]);
        for (o, value) in out.iter().take(2 * d).enumerate() {
            let row = if o < d { o } else { o + d };
            self.gradient[row] += value.re;
            let eps = value
                .eps
                .unwrap_generic(nalgebra::Const::<N>, nalgebra::Const::<1>);
            for col in 0..2 * d {
                self.hessian[(row, col)] += eps[col];
            }
        }
    }
}

/// A Lie group as the integrator uses it, with algebra `ℝ^D`. Implemented by the marker
/// types [`Rotations`] (SO(3)) and [`RigidMotions`] (SE(3)); see the module documentation
/// for adding your own.
pub trait ConfigurationGroup<const D: usize>:
    Copy + Debug + Default + Send + Sync + 'static
{
    /// The group element over a scalar (`f64`, or a dual number).
    type Element<T: RealField + Copy>: LieGroup<Scalar = T, Tangent = SVector<T, D>, Jacobian = SMatrix<T, D, D>>
        + Copy
        + Send
        + Sync;
    /// Storage of one Gauss point's derivatives in the `3D` stacked variables
    /// (`Stacked<{3D}>`).
    type Jet: PointJet;
    /// Storage of the derivatives of `ℓ(g exp(η), ξ)` in the `2D` variables `(η, ξ)`
    /// (`Stacked<{2D}>`): the generic chain rule's one differentiation of the Lagrangian.
    type LocalJet: PointJet;
    /// Name, for messages.
    const NAME: &'static str;
    /// What the initial body velocity `ξ₀` is called in messages ("initial angular
    /// velocity" on SO(3)).
    const INITIAL_VELOCITY: &'static str = "initial velocity";

    /// `g` over another scalar.
    fn lift<T: RealField + Copy>(g: &Self::Element<f64>) -> Self::Element<T>;
    /// The exponential map, for configuration variations `g exp(ζ)` (only its first two
    /// orders at `ζ = 0` matter).
    fn exp<T: RealField + Copy>(zeta: &SVector<T, D>) -> Self::Element<T>;
    /// `exp(ζ)` to second order, `I + ζ^ + ½(ζ^)²` in the matrix representation (not on
    /// the group beyond second order): what the derivatives of `ℓ(g exp(η), ξ)` at
    /// `η = 0` need, without the exponential's trigonometry. Defaults to
    /// [`ConfigurationGroup::exp`].
    fn exp_second_order<T: RealField + Copy>(zeta: &SVector<T, D>) -> Self::Element<T> {
        Self::exp(zeta)
    }
    /// The rotation angle of `g`'s rotational part (for the checks that a step stays in
    /// its chart). The default, `0`, is a group without one: no step is then refused for
    /// turning too far.
    fn rotation_angle(g: &Self::Element<f64>) -> f64 {
        let _ = g;
        0.0
    }
    /// The angular speed `|Ω|` of a body velocity (its rotational part), which bounds
    /// how far a step turns the body. The default, `0`, is a group without rotation.
    fn angular_speed(xi: &SVector<f64, D>) -> f64 {
        let _ = xi;
        0.0
    }
    /// `g` with the rounding of its products removed (one polar Newton step on a rotation
    /// block), so that millions of steps do not drift off the group. The default keeps `g`:
    /// a group whose elements cannot drift off it (angles, translations).
    fn renormalise(g: &Self::Element<f64>) -> Self::Element<f64> {
        *g
    }
    /// Whether every entry of `g` is finite.
    fn is_finite(g: &Self::Element<f64>) -> bool;
    /// Checks that `g` lies on the group to the group's tolerance (a starting state that
    /// does not would have its error dropped silently by the first step's
    /// renormalisation). The default accepts every element: a group whose elements
    /// cannot leave it.
    ///
    /// # Errors
    /// Why `g` is not on the group (for SO(3): [`LieError::NotOrthogonal`] beyond
    /// `‖RᵀR − I‖_F ≤ 1e-9`, [`LieError::NotProperRotation`] for a reflection).
    fn check_on_group(g: &Self::Element<f64>) -> Result<(), LieError> {
        let _ = g;
        Ok(())
    }
    /// The matrix of `η ↦ ad_ηᵀ p`: the coadjoint term of the Euler–Poincaré equations
    /// (`μ̇ = ad_ξᵀ μ + p`) and of the derivative of `Ad_{Φ(x)⁻¹}ᵀ p` in `x`. The default
    /// builds it from the element's [`LieGroup::small_adjoint`], one basis vector a column
    /// ([`coadjoint_generator_of`]); the built-in groups give it in closed form.
    fn coadjoint_generator(p: &SVector<f64, D>) -> SMatrix<f64, D, D> {
        coadjoint_generator_of::<Self::Element<f64>, D>(p)
    }
}

/// The matrix of `η ↦ ad_ηᵀ p` from a group's small adjoint: column `i` is
/// `ad_{e_i}ᵀ p` ([`ConfigurationGroup::coadjoint_generator`]'s default).
pub fn coadjoint_generator_of<E, const D: usize>(p: &SVector<f64, D>) -> SMatrix<f64, D, D>
where
    E: LieGroup<Scalar = f64, Tangent = SVector<f64, D>, Jacobian = SMatrix<f64, D, D>>,
{
    SMatrix::<f64, D, D>::from_fn(|row, column| {
        let basis = SVector::<f64, D>::from_fn(|i, _| if i == column { 1.0 } else { 0.0 });
        (E::small_adjoint(&basis).transpose() * p)[row]
    })
}

/// SO(3), `D = 3`, elements [`SO3`]: the rigid body's attitude.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Rotations;

/// SE(3), `D = 6`, elements [`SE3`] `(R, x)` with body velocities `(Ω, v)`, `ẋ = R v`:
/// a rigid body that rotates and translates.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RigidMotions;

/// `I + ω̂ + ½ω̂²`.
fn quadratic_rotation<T: RealField + Copy>(w: &Vector3<T>) -> Matrix3<T> {
    let half: T = nalgebra::convert(0.5);
    let w_hat = lgsvi_lie::so3::hat(w);
    Matrix3::identity() + w_hat + w_hat * w_hat * half
}

/// One polar Newton step `R(I + ½(I − RᵀR))`: squares the deviation from orthogonality.
fn polar_step(r: &Matrix3<f64>) -> Matrix3<f64> {
    let deviation = Matrix3::identity() - r.transpose() * r;
    r + r * deviation * 0.5
}

impl ConfigurationGroup<3> for Rotations {
    type Element<T: RealField + Copy> = SO3<T>;
    type Jet = Stacked<9>;
    type LocalJet = Stacked<6>;
    const NAME: &'static str = "SO(3)";
    const INITIAL_VELOCITY: &'static str = "initial angular velocity";

    fn lift<T: RealField + Copy>(g: &SO3) -> SO3<T> {
        SO3::from_matrix_unchecked(g.matrix().map(nalgebra::convert))
    }
    fn exp<T: RealField + Copy>(zeta: &Vector3<T>) -> SO3<T> {
        SO3::exp(zeta)
    }
    fn exp_second_order<T: RealField + Copy>(zeta: &Vector3<T>) -> SO3<T> {
        SO3::from_matrix_unchecked(quadratic_rotation(zeta))
    }
    fn rotation_angle(g: &SO3) -> f64 {
        g.angle()
    }
    fn angular_speed(xi: &Vector3<f64>) -> f64 {
        xi.norm()
    }
    fn renormalise(g: &SO3) -> SO3 {
        SO3::from_matrix_unchecked(polar_step(g.matrix()))
    }
    fn is_finite(g: &SO3) -> bool {
        g.matrix().iter().all(|x| x.is_finite())
    }
    fn check_on_group(g: &SO3) -> Result<(), LieError> {
        SO3::try_from_matrix(*g.matrix()).map(|_| ())
    }
    fn coadjoint_generator(p: &Vector3<f64>) -> Matrix3<f64> {
        lgsvi_lie::so3::hat(p)
    }
}

impl ConfigurationGroup<6> for RigidMotions {
    type Element<T: RealField + Copy> = SE3<T>;
    type Jet = Stacked<18>;
    type LocalJet = Stacked<12>;
    const NAME: &'static str = "SE(3)";
    const INITIAL_VELOCITY: &'static str = "initial velocity (Ω, v)";

    fn lift<T: RealField + Copy>(g: &SE3) -> SE3<T> {
        SE3::new(
            Rotations::lift(g.rotation()),
            g.translation().map(nalgebra::convert),
        )
    }
    fn exp<T: RealField + Copy>(zeta: &SVector<T, 6>) -> SE3<T> {
        SE3::exp(zeta)
    }
    /// `[[I + ω̂ + ½ω̂², (I + ½ω̂)u], [0, 1]]`.
    fn exp_second_order<T: RealField + Copy>(zeta: &SVector<T, 6>) -> SE3<T> {
        let w = Vector3::new(zeta[0], zeta[1], zeta[2]);
        let u = Vector3::new(zeta[3], zeta[4], zeta[5]);
        let half: T = nalgebra::convert(0.5);
        SE3::new(
            SO3::from_matrix_unchecked(quadratic_rotation(&w)),
            u + w.cross(&u) * half,
        )
    }
    fn rotation_angle(g: &SE3) -> f64 {
        g.rotation().angle()
    }
    fn angular_speed(xi: &SVector<f64, 6>) -> f64 {
        xi.fixed_rows::<3>(0).norm()
    }
    fn renormalise(g: &SE3) -> SE3 {
        SE3::new(Rotations::renormalise(g.rotation()), *g.translation())
    }
    fn is_finite(g: &SE3) -> bool {
        Rotations::is_finite(g.rotation()) && g.translation().iter().all(|x| x.is_finite())
    }
    fn check_on_group(g: &SE3) -> Result<(), LieError> {
        Rotations::check_on_group(g.rotation())
    }
    /// With `p = (p_ω, p_v)`: `ad_(ω,v)ᵀ p = (−ω̂ p_ω − v̂ p_v, −ω̂ p_v)`, i.e.
    /// `[[p̂_ω, p̂_v], [p̂_v, 0]]` applied to `(ω, v)`.
    fn coadjoint_generator(p: &SVector<f64, 6>) -> SMatrix<f64, 6, 6> {
        let (pw, pv) = split(p);
        let (pw, pv) = (lgsvi_lie::so3::hat(&pw), lgsvi_lie::so3::hat(&pv));
        blocks(&pw, &pv, &pv, &Matrix3::zeros())
    }
}

/// A chart's derivatives at one point `x`, contracted as the generic chain rule
/// (the integrator's Gauss points) reads them: `A(x)`, `∂(A(x)v)/∂x`, `∂(A(x)ᵀg)/∂x` and
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
    /// chart. Its type cannot be named, nor its contents read, outside this crate: the
    /// method is this crate's own fast path.
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
        crate::dual::jacobian_of(&y)
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
        a_dual: chart.left_differential(&crate::dual::seeded(x)),
        group: std::marker::PhantomData,
    };
    f(&derivatives)
}

/// `Ad_{Φ⁻¹}ᵀ` at a chart point's group element `Φ`: takes a configuration force there to
/// the step's start (the exact matching's transport, [`GroupChart::coadjoint_to_start`]).
pub(crate) fn coadjoint_to_start<G: ConfigurationGroup<D>, const D: usize>(
    phi: &G::Element<f64>,
) -> SMatrix<f64, D, D> {
    phi.inverse().adjoint().transpose()
}

/// A chart `Φ: ℝ^D → G` as the integrator uses it. Every [`So3Chart`] is one on both
/// [`Rotations`] and [`RigidMotions`]; implement it directly for a group of your own.
///
/// Chosen by type: the integrator is monomorphised for its chart, so a chart type costs
/// no dispatch per call ([`lgsvi_lie::ChartKind`], the run-time choice, matches per call).
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
fn so3_advice<C: So3Chart>(chart: &C) -> &'static str {
    if chart.max_rotation_angle() < std::f64::consts::TAU {
        " or the exp chart (--chart exp), which follows up to 2π per step"
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The default coadjoint generator, built from the small adjoint, is the closed form
    /// SO(3) and SE(3) give (`p̂`, and SE(3)'s blocks): exactly, the columns being sums of
    /// one or two products of `p`'s entries with ±1.
    #[test]
    fn the_default_coadjoint_generator_is_the_closed_form() {
        let p3 = Vector3::new(0.3, -1.7, 2.2);
        assert_eq!(
            coadjoint_generator_of::<SO3, 3>(&p3),
            Rotations::coadjoint_generator(&p3)
        );
        let p6 = SVector::<f64, 6>::new(0.3, -1.7, 2.2, -0.4, 0.9, 1.3);
        assert_eq!(
            coadjoint_generator_of::<SE3, 6>(&p6),
            RigidMotions::coadjoint_generator(&p6)
        );
    }
}
