//! Exact first and second derivatives of `ℓ̃(x, v, ζ) = ℓ(B Φ(x) exp(ζ), A(x) v)` at
//! `ζ = 0` by the chain rule, from the chart's Rodrigues coefficients and
//! [`Lagrangian::derivatives`].
//!
//! Both `Φ` and `A` have the form `M(x) = e(s) I + a(s) x̂ + b(s) x̂²`, `s = |x|²`. The
//! coefficients' derivatives in `s` come from a second-order dual number in `s` alone
//! (three floats), and with `∂s/∂x_k = 2x_k`:
//!
//! - `∂_k M = 2e′x_k I + 2a′x_k x̂ + a ê_k + 2b′x_k x̂² + b D_k`,
//!   `D_k = ∂_k x̂² = e_k xᵀ + x e_kᵀ − 2x_k I`;
//! - `∂_k∂_l M = (4e″x_k x_l + 2e′δ_kl) I + (4a″x_k x_l + 2a′δ_kl) x̂ + 2a′(x_k ê_l + x_l ê_k)
//!   + (4b″x_k x_l + 2b′δ_kl) x̂² + 2b′(x_k D_l + x_l D_k) + b(e_k e_lᵀ + e_l e_kᵀ − 2δ_kl I)`.
//!
//! The chain rule then treats `ℓ` as a function of `R`'s nine entries and `Ω`:
//! `∇²ℓ̃ = Jᵀ ∇²ℓ J + Σ_u ∂ℓ/∂u ∇²u` over the inner variables `u = (R, Ω)`, with
//! `R = B Φ(x)(I + ζ̂ + ½ζ̂²) + O(ζ³)` and `Ω = A(x) v`. This replaces a 6- or 9-variable
//! second-order dual number through the whole chart (≈ 90 floats per operation) by a few
//! hundred floating-point operations per Gauss point.
//!
//! # Attitude terms
//! `Φ`'s derivatives are not needed beyond `A`'s: `A` is `Φ`'s left-trivialised
//! differential, `Φ⁻¹ ∂_kΦ = û_k` with `u_k = A e_k`, so `∂_k∂_lΦ = Φ(û_k û_l + (∂_kA e_l)^)`.
//! With `G = ∂ℓ/∂R`, `M = RᵀG`, `γ` the axial vector of `M − Mᵀ` (`⟨M, ŷ⟩ = γ·y`) and
//! `â b̂ = b aᵀ − (a·b) I`:
//!
//! - `∂ℓ/∂x_k = ⟨G, B ∂_kΦ⟩ = γ·u_k`, i.e. `Aᵀγ`; `∂ℓ/∂ζ = γ`;
//! - `⟨G, B ∂_k∂_lΦ⟩ = u_lᵀ M u_k − (u_k·u_l) tr M + γᵀ ∂_kA e_l`, i.e.
//!   `Aᵀ(Mᵀ − tr M I)A` plus `γ` contracted with `A`'s first derivatives;
//! - `⟨G, B ∂_kΦ ê_c⟩ = ⟨M, û_k ê_c⟩ = ((M − tr M I) A)_ck`.
//!
//! Only `Φ(x)`'s value is formed; `A`'s jet serves both.

use crate::group::{GroupChart, Rotations, Stacked};
use crate::lagrangian::Lagrangian;
use crate::step::points::add_force_terms;
use crate::system::GaussPoint;
use lgsvi_lie::so3::{hat, vee};
use lgsvi_lie::{RodriguesCoefficients, SO3};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use num_dual::{Dual2_64, Dual64};

/// A 3×3 matrix function `M(x) = e(s) I + a(s) x̂ + b(s) x̂²` of `x ∈ ℝ³` with the
/// derivatives of its coefficients in `s`: its first partial derivatives `∂_k M`
/// contracted with a vector ([`MatrixJet::first_times`],
/// [`MatrixJet::first_transposed_times`]); second
/// derivatives are only ever needed contracted with a matrix, `⟨G, ∂_k∂_l M⟩`, which
/// [`MatrixJet::second_contracted`] forms directly.
#[derive(Debug, Clone, Copy)]
pub(crate) struct MatrixJet {
    pub value: Matrix3<f64>,
    x: Vector3<f64>,
    /// `(e, a, b)`, their first and their second derivatives in `s`.
    c0: [f64; 3],
    c1: [f64; 3],
    c2: [f64; 3],
}

/// `γ` with `⟨G, ŷ⟩ = γ·y` for every `y`: the axial vector of `G − Gᵀ`.
fn axial(g: &Matrix3<f64>) -> Vector3<f64> {
    vee(&(g - g.transpose()))
}

/// `ê_k`.
fn unit_hat(k: usize) -> Matrix3<f64> {
    let mut e = Vector3::zeros();
    e[k] = 1.0;
    hat(&e)
}

impl MatrixJet {
    /// The jet at `x` from the coefficients evaluated at the dual number `s + ε` (value,
    /// first and second derivative in `s`).
    pub fn from_rodrigues(c: &RodriguesCoefficients<Dual2_64>, x: &Vector3<f64>) -> Self {
        let re = RodriguesCoefficients {
            identity: c.identity.re,
            hat: c.hat.re,
            hat_squared: c.hat_squared.re,
        };
        Self {
            value: re.matrix(x),
            x: *x,
            c0: [re.identity, re.hat, re.hat_squared],
            c1: [c.identity.v1, c.hat.v1, c.hat_squared.v1],
            c2: [c.identity.v2, c.hat.v2, c.hat_squared.v2],
        }
    }

    /// As [`MatrixJet::from_rodrigues`] from coefficients at a first-order dual number
    /// (the second derivatives set to zero): enough for the value and first derivatives,
    /// which is all a gradient needs, at about two thirds of the cost.
    pub fn from_rodrigues_first_order(c: &RodriguesCoefficients<Dual64>, x: &Vector3<f64>) -> Self {
        let lift = |d: Dual64| Dual2_64::new(d.re, d.eps, 0.0);
        Self::from_rodrigues(
            &RodriguesCoefficients {
                identity: lift(c.identity),
                hat: lift(c.hat),
                hat_squared: lift(c.hat_squared),
            },
            x,
        )
    }

    /// The matrix with columns `∂_k M v`: `u xᵀ − a v̂ + b (x·v) I + b x vᵀ` with
    /// `u = 2e′v + 2a′ x×v + 2b′ x̂²v − 2b v` (the formula for `∂_k M` applied to `v`,
    /// `D_k v = e_k (x·v) + x v_k − 2x_k v`), without forming the three matrices.
    pub fn first_times(&self, v: &Vector3<f64>) -> Matrix3<f64> {
        self.first_applied(v, 1.0)
    }

    /// The matrix with rows `((∂_k M)ᵀ g)ᵀ`, i.e. entries `gᵀ ∂_k M e_b`: `(∂_k M)ᵀ` is
    /// `∂_k M` with its skew terms (`a`, `a′`) negated (`x̂²` and `D_k` are symmetric), so
    /// this is [`MatrixJet::first_times`] of `g` with those signs flipped, transposed.
    pub fn first_transposed_times(&self, g: &Vector3<f64>) -> Matrix3<f64> {
        self.first_applied(g, -1.0).transpose()
    }

    /// Columns `∂_k M' v` for `M' = e I + σ a x̂ + b x̂²` (`σ = ±1`).
    fn first_applied(&self, v: &Vector3<f64>, skew_sign: f64) -> Matrix3<f64> {
        let x = &self.x;
        let [_, a, b] = self.c0;
        let [e1, a1, b1] = self.c1;
        let (a, a1) = (skew_sign * a, skew_sign * a1);
        let xv = x.dot(v);
        // x̂²v = x (x·v) − |x|² v.
        let xh2v = x * xv - v * x.norm_squared();
        let u = v * (2.0 * e1 - 2.0 * b) + x.cross(v) * (2.0 * a1) + xh2v * (2.0 * b1);
        let mut out = u * x.transpose() - hat(v) * a + x * v.transpose() * b;
        for i in 0..3 {
            out[(i, i)] += b * xv;
        }
        out
    }

    /// `[⟨G, ∂_k∂_l M⟩]_kl`, from the formula in the module's documentation with
    /// `⟨G, I⟩ = tr G`, `⟨G, ŷ⟩ = γ·y` (`γ` the axial vector of `G − Gᵀ`),
    /// `⟨G, x̂²⟩ = xᵀGx − s tr G`, `⟨G, D_k⟩ = ((G + Gᵀ)x − 2 tr G x)_k` and
    /// `⟨G, e_k e_lᵀ + e_l e_kᵀ⟩ = G_kl + G_lk`.
    pub fn second_contracted(&self, g: &Matrix3<f64>) -> Matrix3<f64> {
        let x = &self.x;
        let [_, _, b] = self.c0;
        let [e1, a1, b1] = self.c1;
        let [e2, a2, b2] = self.c2;
        let t = g.trace();
        let gamma = axial(g);
        let sym = g + g.transpose();
        let gx = gamma.dot(x);
        let q = x.dot(&(g * x)) - x.norm_squared() * t;
        let u = sym * x - x * (2.0 * t);
        let outer = 4.0 * (e2 * t + a2 * gx + b2 * q);
        let diagonal = 2.0 * (e1 * t + a1 * gx + b1 * q) - 2.0 * b * t;
        let w = gamma * (2.0 * a1) + u * (2.0 * b1);
        let mut out = x * x.transpose() * outer + x * w.transpose() + w * x.transpose() + sym * b;
        for i in 0..3 {
            out[(i, i)] += diagonal;
        }
        out
    }
}

/// `R`'s entries flattened row-major, as [`crate::LagrangianDerivatives`] indexes them.
fn flatten(m: &Matrix3<f64>) -> SVector<f64, 9> {
    SVector::<f64, 9>::from_fn(|i, _| m[(i / 3, i % 3)])
}

/// Writes `ℓ̃`'s derivatives by the chain rule into `out` (its Hessian only if
/// `point.with_hessian`, else left as it was), with the force terms of `point.force`;
/// false (`out` untouched) if the chart has no Rodrigues form. In place: the 90 floats
/// are written once, not returned and copied (the copies were 10% of a step, measured).
pub(crate) fn point_derivatives<L: Lagrangian, C: GroupChart<Rotations, 3>>(
    system: &L,
    chart: &C,
    point: &GaussPoint<'_, Rotations, 3>,
    out: &mut Stacked<9>,
) -> bool {
    let (x, v) = (point.x, point.v);
    let (with_configuration, with_hessian) = (point.with_configuration, point.with_hessian);
    let base = point.base.matrix();
    // The coefficients' second derivatives in s enter only the Hessian: for a gradient,
    // a first-order dual number does.
    let s = x.norm_squared();
    let (s2, s1) = (Dual2_64::new(s, 1.0, 0.0), Dual64::new(s, 1.0));
    let a = if with_hessian {
        let Some(c) = chart.left_differential_coefficients(s2) else {
            return false;
        };
        MatrixJet::from_rodrigues(&c, x)
    } else {
        let Some(c) = chart.left_differential_coefficients(s1) else {
            return false;
        };
        MatrixJet::from_rodrigues_first_order(&c, x)
    };
    // Φ(x)'s value for an attitude-dependent ℓ or a force that reads the attitude: its
    // derivatives follow from A's (module documentation, "Attitude terms"). A
    // left-invariant ℓ does not depend on R (the trait's contract): any attitude will do.
    let attitude = !system.is_left_invariant();
    let force_reads_attitude = point.force.is_some_and(|f| f.depends_on_configuration());
    // ℓ = k(Ω) + aᵀRb: M = Rᵀa bᵀ needs only Rᵀa = Φ(x)ᵀ(Bᵀa), a rotated vector.
    let field = match system.linear_attitude_term() {
        Some((field, body_vector)) if attitude && !force_reads_attitude => {
            let Some(c) = chart.rotation_coefficients(s) else {
                return false;
            };
            Some((
                c.transpose_times(x, &(base.transpose() * field)),
                body_vector,
            ))
        }
        _ => None,
    };
    let r = if field.is_none() && (attitude || force_reads_attitude) {
        base * chart.to_group(x).matrix()
    } else {
        *base
    };
    let omega = a.value * v;
    let l = system.derivatives(&r, &omega);
    let g = l.velocity_gradient;

    // Ω = A(x) v: ∂Ω/∂x = [∂_k A v]_k, ∂Ω/∂v = A.
    let dw_dx = a.first_times(v);
    let Stacked { gradient, hessian } = out;
    gradient.fill(0.0);
    gradient
        .fixed_rows_mut::<3>(0)
        .copy_from(&(dw_dx.transpose() * g));
    gradient
        .fixed_rows_mut::<3>(3)
        .copy_from(&(a.value.transpose() * g));
    let mut jw = SMatrix::<f64, 3, 9>::zeros();
    if with_hessian {
        hessian.fill(0.0);
        jw.fixed_view_mut::<3, 3>(0, 0).copy_from(&dw_dx);
        jw.fixed_view_mut::<3, 3>(0, 3).copy_from(&a.value);
        let top = jw.fixed_columns::<6>(0);
        hessian
            .fixed_view_mut::<6, 6>(0, 0)
            .copy_from(&(top.transpose() * l.velocity_hessian * top));
        // gᵀ ∂_k∂_l A v = ⟨g vᵀ, ∂_k∂_l A⟩.
        let second = a.second_contracted(&(g * v.transpose()));
        // gᵀ ∂_k A e_b: ∂²(gᵀA v)/∂x_k∂v_b.
        let cross = a.first_transposed_times(&g);
        for k in 0..3 {
            for m in 0..3 {
                hessian[(k, m)] += second[(k, m)];
            }
            for b in 0..3 {
                hessian[(k, 3 + b)] += cross[(k, b)];
                hessian[(3 + b, k)] += cross[(k, b)];
            }
        }
    }

    // ℓ's attitude terms (none for a left-invariant ℓ), with M = Rᵀ ∂ℓ/∂R and
    // u_k = A e_k (module documentation, "Attitude terms").
    if attitude {
        let m = match field {
            Some((rotated, body_vector)) => rotated * body_vector.transpose(),
            None => r.transpose() * l.attitude_gradient,
        };
        let gamma = axial(&m);
        let a_value = a.value;
        let gradient_x = a_value.transpose() * gamma;
        for k in 0..3 {
            gradient[k] += gradient_x[k];
        }
        if with_configuration {
            for c in 0..3 {
                gradient[6 + c] += gamma[c];
            }
        }
        if with_hessian {
            let trace = m.trace();
            let mut m_t = m.transpose();
            let mut m_shifted = m;
            for i in 0..3 {
                m_t[(i, i)] -= trace;
                m_shifted[(i, i)] -= trace;
            }
            // ⟨M, û_k û_l⟩ + γᵀ ∂_kA e_l.
            let second = a_value.transpose() * m_t * a_value + a.first_transposed_times(&gamma);
            for k in 0..3 {
                for l in 0..3 {
                    hessian[(k, l)] += second[(k, l)];
                }
            }
            if with_configuration {
                // ⟨M, û_k ê_c⟩ = ((M − tr M) A)_ck.
                let mixed = m_shifted * a_value;
                for c in 0..3 {
                    for k in 0..3 {
                        hessian[(k, 6 + c)] += mixed[(c, k)];
                        hessian[(6 + c, k)] += mixed[(c, k)];
                    }
                    // ½⟨M, ê_c ê_d + ê_d ê_c⟩ with ê_c ê_d = e_d e_cᵀ − δ_cd I.
                    for d in 0..3 {
                        let delta = if c == d { trace } else { 0.0 };
                        hessian[(6 + c, 6 + d)] += 0.5 * (m[(d, c)] + m[(c, d)]) - delta;
                    }
                }
            }
            if l.attitude_hessian.is_some() || l.mixed_hessian.is_some() {
                // ∂R/∂y for y = (x, v, ζ), flattened: columns x (R û_k) and ζ (R ê_c).
                let mut jr = SMatrix::<f64, 9, 9>::zeros();
                for k in 0..3 {
                    let u = a_value.column(k).into_owned();
                    jr.set_column(k, &flatten(&(r * hat(&u))));
                }
                if with_configuration {
                    for c in 0..3 {
                        jr.set_column(6 + c, &flatten(&(r * unit_hat(c))));
                    }
                }
                if let Some(h_rr) = l.attitude_hessian {
                    *hessian += jr.transpose() * h_rr * jr;
                }
                if let Some(h_rw) = l.mixed_hessian {
                    let t = jr.transpose() * h_rw * jw;
                    *hessian += t + t.transpose();
                }
            }
        }
    }
    if let Some(force) = point.force {
        let jet = force.jet(&SO3::from_matrix_unchecked(r), &omega);
        // ∂(AᵀF)_b/∂x_k = Fᵀ ∂_k A e_b.
        let k = if with_hessian {
            a.first_transposed_times(&jet.value).transpose()
        } else {
            Matrix3::zeros()
        };
        add_force_terms(out, &jet, &a.value, &dw_dx, &k, with_hessian);
    }
    true
}
