//! The configuration groups and charts the integrator is generic over, and the storage of
//! its Gauss points' derivatives.
//!
//! A step works in the Lie algebra `ℝ^D` of a group `G` through a chart `Φ: ℝ^D → G`. The
//! group and chart traits are `lgsvi_lie`'s, re-exported here: [`ConfigurationGroup`]
//! (composition, the adjoint, the exponential for configuration variations, over every
//! scalar) and [`GroupChart`] (`Φ`, its left-trivialised differential `A` and inverse, the
//! derivatives of `A`). `lgsvi_lie` implements them for
//!
//! | group | `D` | marker | element | charts |
//! |---|---|---|---|---|
//! | SO(3) | 3 | [`Rotations`] | [`SO3`](lgsvi_lie::SO3) | every [`So3Chart`](lgsvi_lie::So3Chart): exp, Cayley, the paper's Cayley, [`lgsvi_lie::ChartKind`] |
//! | SE(3) | 6 | [`RigidMotions`] | [`SE3`](lgsvi_lie::SE3) (tangent `(ω, v)`, body velocities) | every [`So3Chart`](lgsvi_lie::So3Chart) as the rotation–translation chart `(Φ(ω), u)` (the default: SO(3) × ℝ³'s discrete map, derivatives in closed form); [`Screw`]`(chart)`, SE(3)'s own screw-motion charts |
//!
//! and SO(3) × ℝᴷ (`lgsvi_lie::product::BodyAndWheels`, re-exported by
//! [`crate::gyrostat`]).
//! What this module adds is the integrator's own: [`StepGroup`], every
//! [`ConfigurationGroup`] with `D ≤ 16` together with the storage of one Gauss point's
//! derivatives ([`Stacked`]`<{3D}>`, a [`PointJet`]), given to each by a blanket impl.
//!
//! # Adding a group or a chart
//! A chart of SO(3) or SE(3) of your own: implement [`So3Chart`](lgsvi_lie::So3Chart) (the
//! blanket impls in `lgsvi_lie` make it a [`GroupChart`] of both groups). A group of your
//! own with algebra dimension `D ≤ 16`: a marker type implementing [`ConfigurationGroup<D>`]
//! whose `Element<T>` implements [`LieGroup`](lgsvi_lie::LieGroup) over any scalar (dual
//! numbers pass through it), and a chart implementing [`GroupChart`] for it; run
//! `lgsvi_lie::laws::{group_laws, group_chart_laws}` on them with your examples. The
//! integrator then runs any [`crate::System`] on it unchanged; the test
//! `tests/tests/generic_group.rs` does this for the torus `SO(2) × SO(2)`.

pub use lgsvi_lie::{
    coadjoint_generator_of, dual_number_derivatives, ChartDerivatives, ConfigurationGroup,
    GroupChart, RigidMotions, RotationTranslationDerivatives, Rotations, Screw,
};
use nalgebra::{RealField, SMatrix, SVector};
use num_dual::{Dual2SVec64, DualSVec64};
use std::fmt::Debug;

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

/// A [`ConfigurationGroup`] as the integrator steps it: the group with the storage of its
/// Gauss points' derivatives. Every `ConfigurationGroup<D>` with `1 ≤ D ≤ 16` is one, by
/// the blanket impls below (the sizes `3D` and `2D` cannot be written from a generic `D`
/// in stable Rust, so each `D` has its own impl): a group of your own with `D ≤ 16` never
/// implements it. A larger one implements it by hand, with `Jet = Stacked<{3D}>` and
/// `LocalJet = Stacked<{2D}>` written out.
pub trait StepGroup<const D: usize>: ConfigurationGroup<D> {
    /// Storage of one Gauss point's derivatives in the `3D` stacked variables
    /// (`Stacked<{3D}>`).
    type Jet: PointJet;
    /// Storage of the derivatives of `ℓ(g exp(η), ξ)` in the `2D` variables `(η, ξ)`
    /// (`Stacked<{2D}>`): the generic chain rule's one differentiation of the Lagrangian.
    type LocalJet: PointJet;
}

/// `StepGroup<D>` for every `ConfigurationGroup<D>`, with `Stacked<{3D}>` and `Stacked<{2D}>`.
macro_rules! step_groups {
    ($(($d:literal, $jet:literal, $local:literal)),* $(,)?) => {$(
        impl<G: ConfigurationGroup<$d>> StepGroup<$d> for G {
            type Jet = Stacked<$jet>;
            type LocalJet = Stacked<$local>;
        }
    )*};
}

step_groups!(
    (1, 3, 2),
    (2, 6, 4),
    (3, 9, 6),
    (4, 12, 8),
    (5, 15, 10),
    (6, 18, 12),
    (7, 21, 14),
    (8, 24, 16),
    (9, 27, 18),
    (10, 30, 20),
    (11, 33, 22),
    (12, 36, 24),
    (13, 39, 26),
    (14, 42, 28),
    (15, 45, 30),
    (16, 48, 32),
);
