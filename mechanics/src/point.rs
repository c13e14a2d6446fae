//! One Gauss point as a system's closed-form derivatives receive it ([`GaussPoint`]), the
//! force acting there ([`PointForce`]), and how a force's terms enter a point's
//! derivatives ([`add_force_terms`]).

use crate::forces::ForceJet;
use crate::group::{ConfigurationGroup, PointJet, StepGroup};
use nalgebra::{SMatrix, SVector};

/// One Gauss point of a step, as [`crate::System::point_derivatives`] receives it.
pub struct GaussPoint<'a, G: StepGroup<D>, const D: usize> {
    /// The point's time `t_k + c_j h`.
    pub time: f64,
    /// The step's start `g_k`.
    pub base: &'a G::Element<f64>,
    /// The chart coordinates `x` of the point.
    pub x: &'a SVector<f64, D>,
    /// Their time derivative `v` (the body velocity is `A(x) v`).
    pub v: &'a SVector<f64, D>,
    /// Whether the `ζ` rows (the configuration force) are wanted.
    pub with_configuration: bool,
    /// Whether the Hessian is wanted (else only the gradient).
    pub with_hessian: bool,
    /// The force acting at the point, when the step is forced: add `A(x)ᵀF` to the `x`
    /// rows and `F` to the `ζ` rows, with their derivatives.
    pub force: Option<&'a dyn PointForce<G, D>>,
}

/// The force at a step's Gauss point `j`, at a configuration and body velocity: its jet
/// (its value alone, as [`ForceJet::constant`], where the Hessian is not wanted) and its
/// power `F·ξ`. What [`GaussPoints`] carries for a forced step.
#[doc(hidden)]
pub type ForceAtPoint<'a, G, const D: usize> = &'a dyn Fn(
    usize,
    &<G as ConfigurationGroup<D>>::Element<f64>,
    &SVector<f64, D>,
) -> (ForceJet<D>, f64);

/// Every Gauss point of one assembly, as [`crate::System::points_in_lanes`]
/// receives them: point `j` at `x[j]`, `v[j]`, the flags and force as [`GaussPoint`]'s.
#[doc(hidden)]
pub struct GaussPoints<'a, G: StepGroup<D>, const D: usize> {
    /// The step's start `g_k`.
    pub base: &'a G::Element<f64>,
    /// The points' chart coordinates.
    pub x: &'a [SVector<f64, D>],
    /// Their time derivatives.
    pub v: &'a [SVector<f64, D>],
    /// Whether the `ζ` rows are wanted.
    pub with_configuration: bool,
    /// Whether the Hessians are wanted.
    pub with_hessian: bool,
    /// The force, when the step is forced, and whether it reads the configuration.
    pub force: Option<(ForceAtPoint<'a, G, D>, bool)>,
}

/// The chart's terms at a Gauss point that the exact momentum matching reads at every
/// point of a system whose `ℓ` or force depends on the configuration: the transport
/// `Ad_{Φ(x)⁻¹}ᵀ` of the point's configuration force to the step's start, and the chart's
/// left differential `A(x)` ([`crate::group::GroupChart::transport_and_differential`]'s pair). A
/// closed-form point path that forms `Φ(x)` and `A(x)` on its way hands them back
/// ([`crate::System::point_derivatives_and_transport`]), so that the matching does
/// not evaluate the chart at the point again.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointTransport<const D: usize> {
    /// `Ad_{Φ(x)⁻¹}ᵀ` (on SO(3), `Φ(x)` itself).
    pub to_start: SMatrix<f64, D, D>,
    /// `A(x)`.
    pub differential: SMatrix<f64, D, D>,
}

/// The force acting at a step's Gauss points (the system's force plus the control input),
/// evaluated where a closed-form point path needs it.
pub trait PointForce<G: StepGroup<D>, const D: usize> {
    /// The force's jet at the configuration `g` and body velocity `ξ`.
    fn jet(&self, configuration: &G::Element<f64>, velocity: &SVector<f64, D>) -> ForceJet<D>;
    /// The force's value alone, bit for bit [`PointForce::jet`]'s (what a gradient-only
    /// assembly reads). The default takes it from the jet; override it where the
    /// derivatives cost more than the value.
    fn value(
        &self,
        configuration: &G::Element<f64>,
        velocity: &SVector<f64, D>,
    ) -> SVector<f64, D> {
        self.jet(configuration, velocity).value
    }
    /// Whether the force depends on the configuration (if not, [`PointForce::jet`] may be
    /// given any configuration, and its `configuration` derivative is zero).
    fn depends_on_configuration(&self) -> bool;
}

/// [`add_force_terms`] for a gradient: `A(x)ᵀF` to the `x` rows, `F` to the `ζ` rows.
pub(crate) fn add_force_value<J: PointJet, const D: usize>(
    out: &mut J,
    value: &SVector<f64, D>,
    a: &SMatrix<f64, D, D>,
) {
    let projected = a.transpose() * value;
    let gradient = out.gradient_mut();
    for c in 0..D {
        gradient[c] += projected[c];
        gradient[2 * D + c] += value[c];
    }
}

/// Adds a force's terms to a point's derivatives (`crate::step::points`' documentation): `a = A(x)`,
/// `j = ∂(A(x)v)/∂x`, `k = ∂(A(x)ᵀF)/∂x` at fixed `F` (entry `(row, x component)`).
pub(crate) fn add_force_terms<J: PointJet, const D: usize>(
    out: &mut J,
    jet: &ForceJet<D>,
    a: &SMatrix<f64, D, D>,
    j: &SMatrix<f64, D, D>,
    k: &SMatrix<f64, D, D>,
    with_hessian: bool,
) {
    add_force_value(out, &jet.value, a);
    if !with_hessian {
        return;
    }
    if jet
        .velocity
        .as_slice()
        .iter()
        .chain(jet.configuration.as_slice())
        .all(|&e| e == 0.0)
    {
        // A force constant at the point (a torque, a profile in time, the input): only
        // the chart's K_F.
        for r in 0..D {
            for c in 0..D {
                out.add_hessian(r, c, k[(r, c)]);
            }
        }
        return;
    }
    let df_dx = jet.configuration * a + jet.velocity * j;
    let df_dv = jet.velocity * a;
    let xx = k + a.transpose() * df_dx;
    let xv = a.transpose() * df_dv;
    for r in 0..D {
        for c in 0..D {
            out.add_hessian(r, c, xx[(r, c)]);
            out.add_hessian(r, D + c, xv[(r, c)]);
            out.add_hessian(2 * D + r, c, df_dx[(r, c)]);
            out.add_hessian(2 * D + r, D + c, df_dv[(r, c)]);
        }
    }
}
