//! One Gauss point of a step: `ℓ̃(x, v, ζ) = ℓ(t, g_k Φ(x) exp(ζ), A(x) v)` and its first
//! and second derivatives in the `3D` stacked variables `(x, v, ζ)` at `ζ = 0`.
//!
//! The `ζ` derivatives are needed by the exact momentum matching of a system that is not
//! left-invariant: `p = ∂ℓ̃/∂ζ` is the left-trivialised configuration force. A system
//! either writes the derivatives itself ([`System::point_derivatives`]: the SO(3)
//! systems' chain rule through the chart's Rodrigues form, `crate::jet`; the built-in SE(3)
//! systems' by 3 × 3 blocks on the rotation–translation chart,
//! [`super::rotation_translation`]) or they come from the generic chain rule below (any
//! group, any chart). A force `F(t, g, ξ)` adds
//! `A(x)ᵀF` to the `x` rows and `F` to the `ζ` rows (discrete Lagrange–d'Alembert,
//! [`crate::system`]); its derivatives come from the force's own jet ([`ForceJet`]: closed
//! form for the built-in forces) and the chart's derivatives, which either path has at
//! hand: with `J = ∂(A(x)v)/∂x` and `K_F = ∂(A(x)ᵀF)/∂x` at fixed `F`,
//! `∂F/∂x = F_η A + F_ξ J`, `∂F/∂v = F_ξ A`, so the `x` rows gain `K_F + Aᵀ ∂F/∂x` and
//! `Aᵀ ∂F/∂v`, the `ζ` rows `∂F/∂x` and `∂F/∂v` ([`add_force_terms`]). The dual-number
//! path through the whole point ([`crate::group::PointJet::add_force`]) is the tests'
//! independent reference.
//!
//! # The generic chain rule
//! At `g₀ = g_k Φ(x)`, `ξ₀ = A(x) v`, let `L(η, ξ) = ℓ(t, g₀ exp(η), ξ)` with gradient
//! `(p, μ)` and Hessian blocks `L_ηη, L_ηξ, L_ξξ` (one dual number over `2D` variables of
//! the Lagrangian alone). A perturbation `(δ, ν, ζ)` of `(x, v, ζ)` moves the configuration
//! to `g₀ exp(η)` with `η = θ(δ) + ζ + ½ ad_{θ(δ)} ζ + O(3)` (Baker–Campbell–Hausdorff),
//! `θ(δ) = log(Φ(x)⁻¹Φ(x + δ)) = Aδ + ½ (∂A[δ]) δ + O(3)` (from `A(x+δ)δ' = J_r(θ) θ'`),
//! and the velocity to `A(x + δ)(v + ν)`. So, with `J = ∂(A(x)v)/∂x`,
//! `K_ab = pᵀ ∂_a A e_b`, `M_ab = μᵀ ∂_a A e_b`, `H = ∇²_x (μᵀ A(x) v)` and
//! `C(p) η = ad_ηᵀ p`:
//!
//! - gradient `(Aᵀp + Jᵀμ, Aᵀμ, p)`;
//! - `H_xx = AᵀL_ηηA + AᵀL_ηξJ + JᵀL_ξηA + JᵀL_ξξJ + ½(K + Kᵀ) + H`,
//!   `H_xv = AᵀL_ηξA + JᵀL_ξξA + M`, `H_vv = AᵀL_ξξA`,
//!   `H_xζ = AᵀL_ηη + JᵀL_ξη + ½(C(p)A)ᵀ`, `H_vζ = AᵀL_ξη`, `H_ζζ = L_ηη`.
//!
//! Every derivative of the chart comes from [`GroupChart::with_derivatives`] (closed form
//! from the Rodrigues jets for this crate's charts, small dual numbers in `x` alone, `D`
//! variables, for others), and the Lagrangian is differentiated once: far cheaper than one
//! second-order dual number over all `3D` variables through `ℓ̃`, which the tests keep as
//! the independent reference.

use crate::forces::ForceJet;
use crate::group::{
    ChartDerivatives, ConfigurationGroup, GroupChart, PointJet, StackedFunction, StepGroup,
};
pub(crate) use crate::point::{add_force_terms, add_force_value};
use crate::system::{ElementOf, GaussPoint, PointForce, PointTransport, System};
use lgsvi_lie::LieGroup;
use nalgebra::{RealField, SMatrix, SVector};
use num_dual::{Dual2SVec64, DualSVec64};

/// `ℓ̃` of the stacked variables `(x, v)` or `(x, v, ζ)`.
pub(crate) struct EllTilde<'a, S: System<D>, C, const D: usize> {
    pub system: &'a S,
    pub chart: &'a C,
    pub base: &'a ElementOf<S, D>,
    pub time: f64,
}

impl<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> StackedFunction
    for EllTilde<'_, S, C, D>
{
    fn eval<T: RealField + Copy>(&self, y: &[T]) -> T {
        let x = SVector::<T, D>::from_column_slice(&y[..D]);
        let v = SVector::<T, D>::from_column_slice(&y[D..2 * D]);
        let base = <S::Group as ConfigurationGroup<D>>::lift::<T>(self.base);
        let mut g = base.compose(&self.chart.to_group(&x));
        if y.len() == 3 * D {
            let z = SVector::<T, D>::from_column_slice(&y[2 * D..]);
            g = g.compose(&<S::Group as ConfigurationGroup<D>>::exp(&z));
        }
        let omega = self.chart.left_differential(&x) * v;
        self.system.lagrangian(self.time, &g, &omega)
    }
}

/// The force terms of one Gauss point: `(x, v) ↦ (A(x)ᵀ F, F)`, `F = F(t, g_k Φ(x), A(x) v)`
/// plus the constant control input: the tests' reference (dual numbers through the whole
/// point, chart included).
#[cfg(test)]
pub(super) struct ForceTerms<'a, S: System<D>, C, const D: usize> {
    pub ell: &'a EllTilde<'a, S, C, D>,
    pub input: &'a SVector<f64, D>,
}

#[cfg(test)]
impl<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> crate::group::StackedMap
    for ForceTerms<'_, S, C, D>
{
    fn eval<T: RealField + Copy>(&self, y: &[T], out: &mut [T]) {
        let ell = self.ell;
        let x = SVector::<T, D>::from_column_slice(&y[..D]);
        let v = SVector::<T, D>::from_column_slice(&y[D..2 * D]);
        let base = <S::Group as ConfigurationGroup<D>>::lift::<T>(ell.base);
        let g = base.compose(&ell.chart.to_group(&x));
        let a = ell.chart.left_differential(&x);
        let omega = a * v;
        let mut force = self.input.map(nalgebra::convert::<f64, T>);
        if ell.system.is_forced() {
            force += ell.system.force(ell.time, &g, &omega);
        }
        let projected = a.transpose() * force;
        out[..D].copy_from_slice(projected.as_slice());
        out[D..2 * D].copy_from_slice(force.as_slice());
    }
}

/// The force at a step's Gauss points: the system's (when it has one) plus the constant
/// control input.
pub(crate) struct StepForce<'a, S, const D: usize> {
    pub system: &'a S,
    pub time: f64,
    pub input: &'a SVector<f64, D>,
    /// The power `F·ξ` at the velocity of the last [`PointForce::jet`] (NaN before it):
    /// the integrand of the step's work, which the Gauss point has at hand.
    pub power: std::cell::Cell<f64>,
    /// `system.is_forced()` and whether that force reads the configuration, asked once
    /// (per point, or per step for the predictor's stages, [`StepForce::at`]) rather than
    /// at every use (a `Forced` system answers by testing its force for zero).
    forced: bool,
    reads_configuration: bool,
}

impl<'a, S: System<D>, const D: usize> StepForce<'a, S, D> {
    /// The force of `system` and `input` at `time`.
    pub fn new(system: &'a S, time: f64, input: &'a SVector<f64, D>) -> Self {
        let forced = system.is_forced();
        Self {
            system,
            time,
            input,
            power: std::cell::Cell::new(f64::NAN),
            forced,
            reads_configuration: forced && system.force_depends_on_configuration(),
        }
    }

    /// The force's jet at a point (its value alone, as a constant jet, where the Hessian
    /// is not wanted) and its power `F·ξ` there: what a point's closed form asks of it
    /// ([`crate::jet`]), for a path that takes the points together
    /// ([`crate::system::GaussPoints`]).
    pub fn jet_and_power(
        &self,
        configuration: &ElementOf<S, D>,
        velocity: &SVector<f64, D>,
        with_hessian: bool,
    ) -> (ForceJet<D>, f64) {
        let jet = if with_hessian {
            self.jet(configuration, velocity)
        } else {
            ForceJet::constant(self.value(configuration, velocity))
        };
        (jet, self.power.get())
    }

    /// The same force at another time, without asking the system again.
    pub fn at(&self, time: f64) -> Self {
        Self {
            time,
            power: std::cell::Cell::new(f64::NAN),
            ..*self
        }
    }
}

impl<S: System<D>, const D: usize> PointForce<S::Group, D> for StepForce<'_, S, D> {
    fn jet(&self, configuration: &ElementOf<S, D>, velocity: &SVector<f64, D>) -> ForceJet<D> {
        let mut jet = if self.forced {
            self.system.force_jet(self.time, configuration, velocity)
        } else {
            ForceJet::constant(SVector::zeros())
        };
        jet.value += self.input;
        self.power.set(jet.value.dot(velocity));
        jet
    }
    fn value(
        &self,
        configuration: &ElementOf<S, D>,
        velocity: &SVector<f64, D>,
    ) -> SVector<f64, D> {
        // As the jet's value: the system's force (zero if it has none) plus the input.
        let mut value = if self.forced {
            self.system.force(self.time, configuration, velocity)
        } else {
            SVector::zeros()
        };
        value += self.input;
        self.power.set(value.dot(velocity));
        value
    }
    fn depends_on_configuration(&self) -> bool {
        self.reads_configuration
    }
}

/// Writes one Gauss point's derivatives into `out` (the Hessian only if `with_hessian`),
/// with the force terms when `forced` (the system's force and `input`); returns the
/// force's power `F·ξ` at the point (NaN unforced, or where a system's own
/// [`System::point_derivatives`] did not ask for the force's jet). `transport`
/// gets the chart's terms at the point where the system's closed form handed them back
/// ([`System::point_derivatives_and_transport`]), else `None`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn point_derivatives<S, C, const D: usize>(
    ell: &EllTilde<'_, S, C, D>,
    x: &SVector<f64, D>,
    v: &SVector<f64, D>,
    with_configuration: bool,
    with_hessian: bool,
    forced: Option<&SVector<f64, D>>,
    out: &mut <S::Group as StepGroup<D>>::Jet,
    transport: &mut Option<PointTransport<D>>,
) -> f64
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
{
    let force = forced.map(|input| StepForce::new(ell.system, ell.time, input));
    let point = GaussPoint {
        time: ell.time,
        base: ell.base,
        x,
        v,
        with_configuration,
        with_hessian,
        force: force.as_ref().map(|f| f as &dyn PointForce<S::Group, D>),
    };
    // Nothing left from the last assembly for a system that hands nothing back.
    *transport = None;
    if !ell
        .system
        .point_derivatives_and_transport(ell.chart, &point, out, transport)
    {
        *transport = None;
        chain_rule(ell, &point, out);
    }
    force.map_or(f64::NAN, |f| f.power.get())
}

/// `L(η, ξ) = ℓ(t, g₀ exp(η), ξ)` of the stacked `(η, ξ)` (the exponential to second
/// order: only `L`'s first and second derivatives at `η = 0` are read).
struct Local<'a, S: System<D>, const D: usize> {
    system: &'a S,
    at: &'a ElementOf<S, D>,
    time: f64,
}

impl<S: System<D>, const D: usize> StackedFunction for Local<'_, S, D> {
    fn eval<T: RealField + Copy>(&self, y: &[T]) -> T {
        let eta = SVector::<T, D>::from_column_slice(&y[..D]);
        let xi = SVector::<T, D>::from_column_slice(&y[D..2 * D]);
        let g = <S::Group as ConfigurationGroup<D>>::lift::<T>(self.at)
            .compose(&<S::Group as ConfigurationGroup<D>>::exp_second_order(&eta));
        self.system.lagrangian(self.time, &g, &xi)
    }
}

/// The generic chain rule (module documentation).
pub(super) fn chain_rule<S, C, const D: usize>(
    ell: &EllTilde<'_, S, C, D>,
    point: &GaussPoint<'_, S::Group, D>,
    out: &mut <S::Group as StepGroup<D>>::Jet,
) where
    S: System<D>,
    C: GroupChart<S::Group, D>,
{
    ell.chart
        .with_derivatives(point.x, point.with_hessian, |derivatives| {
            chain_rule_with(ell, point, derivatives, out);
        });
}

/// The generic chain rule with the chart's derivatives at the point in hand.
pub(crate) fn chain_rule_with<S, C, const D: usize>(
    ell: &EllTilde<'_, S, C, D>,
    point: &GaussPoint<'_, S::Group, D>,
    derivatives: &dyn ChartDerivatives<D>,
    out: &mut <S::Group as StepGroup<D>>::Jet,
) where
    S: System<D>,
    C: GroupChart<S::Group, D>,
{
    let (x, v) = (point.x, point.v);
    let (with_configuration, with_hessian) = (point.with_configuration, point.with_hessian);
    let chart = ell.chart;
    let at = ell.base.compose(&chart.to_group(x));
    let a = derivatives.differential();
    let xi = a * v;
    let local = Local {
        system: ell.system,
        at: &at,
        time: ell.time,
    };
    // L's gradient (p, μ) and Hessian blocks: over ξ alone for a left-invariant ℓ (p = 0),
    // else over (η, ξ) in the group's 2D-variable storage.
    let mut l_ee = SMatrix::<f64, D, D>::zeros();
    let mut l_ex = SMatrix::<f64, D, D>::zeros();
    let l_xx;
    let (p, mu);
    if let Some(local) = ell
        .system
        .local_derivatives(ell.time, &at, &xi, with_hessian)
    {
        // The system's own closed form of L's derivatives.
        p = local.configuration_gradient;
        mu = local.momentum;
        l_ee = local.configuration_hessian;
        l_xx = local.velocity_hessian;
    } else if ell.system.is_left_invariant() {
        p = SVector::<f64, D>::zeros();
        if with_hessian {
            let (_, gradient, hessian) = num_dual::hessian(
                |w: SVector<Dual2SVec64<D>, D>| {
                    let g = <S::Group as ConfigurationGroup<D>>::lift(&at);
                    ell.system.lagrangian(ell.time, &g, &w)
                },
                &xi,
            );
            mu = gradient;
            l_xx = hessian;
        } else {
            // A gradient-only assembly: first-order dual numbers, no Hessian.
            let (_, gradient) = num_dual::gradient(
                |w: SVector<DualSVec64<D>, D>| {
                    let g = <S::Group as ConfigurationGroup<D>>::lift(&at);
                    ell.system.lagrangian(ell.time, &g, &w)
                },
                &xi,
            );
            mu = gradient;
            l_xx = SMatrix::zeros();
        }
    } else {
        let origin = SVector::<f64, D>::zeros();
        let mut jet = <<S::Group as StepGroup<D>>::LocalJet as PointJet>::zeros();
        if with_hessian {
            jet.set_by_dual_numbers(&local, origin.as_slice(), xi.as_slice(), false);
            let block = |r0: usize, c0: usize| {
                SMatrix::<f64, D, D>::from_fn(|r, c| jet.hessian(r0 + r, c0 + c))
            };
            l_ee = block(0, 0);
            l_ex = block(0, D);
            l_xx = block(D, D);
        } else {
            jet.set_gradient_by_dual_numbers(&local, origin.as_slice(), xi.as_slice(), false);
            l_xx = SMatrix::zeros();
        }
        p = SVector::<f64, D>::from_column_slice(&jet.gradient()[..D]);
        mu = SVector::<f64, D>::from_column_slice(&jet.gradient()[D..2 * D]);
    }
    // A's first derivatives, contracted three ways (closed form, or one dual evaluation of
    // A(x)).
    let j = derivatives.differential_times(v);
    let gradient_x = a.transpose() * p + j.transpose() * mu;
    let gradient_v = a.transpose() * mu;
    if with_hessian {
        // K(b, a) = ∂(Aᵀp)_b/∂x_a = pᵀ∂_aA e_b, the transpose of K_ab; M likewise.
        let k = derivatives.transpose_times(&p).transpose();
        let m = derivatives.transpose_times(&mu).transpose();
        let h = derivatives.second(&mu, v);
        let at_ = a.transpose();
        let jt = j.transpose();
        // The products grouped (L_ηη, L_ξξ symmetric, L_ξη = L_ηξᵀ):
        // T₁ = L_ηη A + L_ηξ J, T₂ = L_ξη A + L_ξξ J; then H_xx = AᵀT₁ + JᵀT₂ + …,
        // H_xv = T₂ᵀA + M, H_xζ = T₁ᵀ + …, H_vζ = (L_ηξ A)ᵀ: 12 products of D × D
        // matrices where the formula has 18, and fewer where ℓ's own derivatives have
        // no mixed block (L_ηξ = 0: every system with local_derivatives) or no
        // configuration block (L_ηη = 0: a free body).
        // (Slices: nalgebra's element iterator costs several instructions an entry.)
        let mixed = l_ex.as_slice().iter().any(|&e| e != 0.0);
        let configured = l_ee.as_slice().iter().any(|&e| e != 0.0);
        let mut t1 = SMatrix::<f64, D, D>::zeros();
        let mut t2 = l_xx * j;
        if configured {
            t1 = l_ee * a;
        }
        let mut l_ex_a = SMatrix::<f64, D, D>::zeros();
        if mixed {
            t1 += l_ex * j;
            t2 += l_ex.transpose() * a;
            l_ex_a = l_ex * a;
        }
        let mut h_xx = jt * t2 + (k + k.transpose()) * 0.5 + h;
        if configured || mixed {
            h_xx += at_ * t1;
        }
        let h_xv = t2.transpose() * a + m;
        let h_vv = at_ * (l_xx * a);
        let mut put = |r0: usize, c0: usize, b: &SMatrix<f64, D, D>| {
            for r in 0..D {
                for c in 0..D {
                    out.set_hessian(r0 + r, c0 + c, b[(r, c)]);
                    out.set_hessian(c0 + c, r0 + r, b[(r, c)]);
                }
            }
        };
        put(0, 0, &h_xx);
        put(0, D, &h_xv);
        put(D, D, &h_vv);
        if with_configuration {
            let coadjoint = <S::Group as ConfigurationGroup<D>>::coadjoint_generator(&p);
            let h_xz = t1.transpose() + (coadjoint * a).transpose() * 0.5;
            let h_vz = l_ex_a.transpose();
            put(0, 2 * D, &h_xz);
            put(D, 2 * D, &h_vz);
            put(2 * D, 2 * D, &l_ee);
        } else {
            put(0, 2 * D, &SMatrix::zeros());
            put(D, 2 * D, &SMatrix::zeros());
            put(2 * D, 2 * D, &SMatrix::zeros());
        }
    }
    let g = out.gradient_mut();
    g[..D].copy_from_slice(gradient_x.as_slice());
    g[D..2 * D].copy_from_slice(gradient_v.as_slice());
    if with_configuration {
        g[2 * D..3 * D].copy_from_slice(p.as_slice());
    } else {
        g[2 * D..3 * D].fill(0.0);
    }
    match point.force {
        Some(force) if with_hessian => {
            let jet = force.jet(&at, &xi);
            let k = derivatives.transpose_times(&jet.value);
            add_force_terms(out, &jet, &a, &j, &k, true);
        }
        Some(force) => add_force_value(out, &force.value(&at, &xi), &a),
        None => {}
    }
}
