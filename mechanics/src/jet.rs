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
use crate::point::{add_force_terms, add_force_value, GaussPoint, PointTransport};
use lgsvi_lie::jet::{axial, unit_hat, MatrixJet};
use lgsvi_lie::so3::hat;
use lgsvi_lie::SO3;
use nalgebra::{Matrix3, SMatrix, SVector};
use num_dual::{Dual2_64, Dual64};

/// `R`'s entries flattened row-major, as [`crate::system::LagrangianDerivatives`] indexes them.
fn flatten(m: &Matrix3<f64>) -> SVector<f64, 9> {
    SVector::<f64, 9>::from_fn(|i, _| m[(i / 3, i % 3)])
}

/// Writes `ℓ̃`'s derivatives by the chain rule into `out` (its Hessian only if
/// `point.with_hessian`, else left as it was), with the force terms of `point.force`;
/// false (`out` untouched) if the chart has no Rodrigues form. In place: the 90 floats
/// are written once, not returned and copied. Where `point.with_configuration` and the
/// point forms `Φ(x)` (an `ℓ` or force that reads the attitude), `transport` gets
/// `(Φ(x), A(x))` for the exact matching; else `None`.
pub(crate) fn point_derivatives<L: Lagrangian, C: GroupChart<Rotations, 3>>(
    system: &L,
    chart: &C,
    point: &GaussPoint<'_, Rotations, 3>,
    out: &mut Stacked<9>,
    transport: &mut Option<PointTransport<3>>,
) -> bool {
    *transport = None;
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
            if point.with_configuration {
                *transport = Some(PointTransport {
                    to_start: c.matrix(x),
                    differential: a.value,
                });
            }
            Some((
                c.transpose_times(x, &(base.transpose() * field)),
                body_vector,
            ))
        }
        _ => None,
    };
    let r = if field.is_none() && (attitude || force_reads_attitude) {
        let phi = *chart.to_group(x).matrix();
        if point.with_configuration {
            *transport = Some(PointTransport {
                to_start: phi,
                differential: a.value,
            });
        }
        base * phi
    } else {
        *base
    };
    let omega = a.value * v;
    let l = system.derivatives(&r, &omega);
    let g = l.velocity_gradient;

    // Ω = A(x) v: ∂Ω/∂x = [∂_k A v]_k, ∂Ω/∂v = A.
    let dw_dx = a.first_times(v);
    let Stacked { gradient, hessian } = out;
    *gradient = SVector::zeros();
    gradient
        .fixed_rows_mut::<3>(0)
        .copy_from(&(dw_dx.transpose() * g));
    gradient
        .fixed_rows_mut::<3>(3)
        .copy_from(&(a.value.transpose() * g));
    let mut jw = SMatrix::<f64, 3, 9>::zeros();
    if with_hessian {
        *hessian = SMatrix::zeros();
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
    match point.force {
        Some(force) if with_hessian => {
            let jet = force.jet(&SO3::from_matrix_unchecked(r), &omega);
            // ∂(AᵀF)_b/∂x_k = Fᵀ ∂_k A e_b.
            let k = a.first_transposed_times(&jet.value).transpose();
            add_force_terms(out, &jet, &a.value, &dw_dx, &k, true);
        }
        Some(force) => add_force_value(
            out,
            &force.value(&SO3::from_matrix_unchecked(r), &omega),
            &a.value,
        ),
        None => {}
    }
    true
}
