//! One Gauss point of an SE(3) system on the rotation–translation chart, by 3 × 3 blocks.
//!
//! The generic chain rule (`super::points`) forms `ℓ̃`'s derivatives from the chart's
//! `A`, `J = ∂(A v)/∂x`, `K_ab = pᵀ ∂_aA e_b`, `M_ab = μᵀ ∂_aA e_b` and
//! `H = ∇²_x(μᵀA v)` as `D × D` matrices. On SE(3)'s rotation–translation chart
//! (`x = (ω, u)`, `v = (v_ω, v_u)`) half of their blocks are zero: `A = diag(A_ω, Pᵀ)` with
//! `P = Φ(ω)`, and everything depends on `ω` alone, so
//!
//! - `J = [[J_ω, 0], [J_P, 0]]`, `J_ω = ∂(A_ω v_ω)/∂ω`, `J_P = ∂(Pᵀ v_u)/∂ω`;
//! - `K = [[K_ωω, K_ωu], [0, 0]]` with `K_ωω = (∂(A_ωᵀ p_ω)/∂ω)ᵀ`, `K_ωu = (∂(P p_u)/∂ω)ᵀ`
//!   (likewise `M` with `μ`);
//! - `H = [[⟨μ_ω v_ωᵀ, ∂²A_ω⟩ + ⟨v_u μ_uᵀ, ∂²P⟩, 0], [0, 0]]`.
//!
//! With `L`'s derivatives from the system's closed form ([`System::local_derivatives`]:
//! `p`, `μ`, `L_ηη = E`, `L_ξξ = X`, no mixed block) the formulas of `super::points` become
//! (`T₂ = X J = [[T_ω, 0], [T_u, 0]]`, blocks of `E` and `X` by `ωω, ωu, uω, uu`):
//!
//! - gradient: `x`: `(A_ωᵀp_ω + J_ωᵀμ_ω + J_Pᵀμ_u, P p_u)`; `v`: `(A_ωᵀμ_ω, P μ_u)`; `ζ`: `p`;
//! - `H_xx`: `ωω`: `J_ωᵀT_ω + J_PᵀT_u + ½(K_ωω + K_ωωᵀ) + H_ω + A_ωᵀE_ωωA_ω`,
//!   `ωu`: `½K_ωu + A_ωᵀE_ωuPᵀ`, `uu`: `P E_uu Pᵀ`;
//! - `H_xv`: `ωω`: `T_ωᵀA_ω + M_ωω`, `ωu`: `T_uᵀPᵀ + M_ωu`, the `u` rows zero;
//! - `H_vv = Aᵀ X A` by blocks;
//! - `H_xζ = (E A)ᵀ + ½(C(p) A)ᵀ` with `C(p) = [[p̂_ω, p̂_u], [p̂_u, 0]]`, `H_vζ = 0`, `H_ζζ = E`.
//!
//! Twenty-odd 3 × 3 products where the generic rule multiplies a dozen 6 × 6 matrices, and
//! `Φ(ω)` is the jet's value (no second evaluation of the chart).
//!
//! Every built-in body's translational kinetic energy is isotropic, `½m|ξ_u|²` with
//! `ξ_u = Pᵀv_u` (`X_uu = m I`, `X_ωu = X_uω = 0`, `μ_u = m ξ_u`): as `|Pᵀv_u| = |v_u|` it
//! does not depend on `ω`, so `J_Pᵀμ_u`, `J_PᵀT_u + ⟨v_u μ_uᵀ, ∂²P⟩` and `T_uᵀPᵀ + M_ωu`
//! are exactly zero and `P X_uu Pᵀ = m I`. Where a point's derivatives show that structure
//! those terms are not computed (they would be rounding noise). The tests compare it with
//! dual numbers through the whole point (`step::tests::whole_point`).

use super::points::{chain_rule_with, EllTilde};
use crate::group::{
    ChartDerivatives, GroupChart, PointJet, RigidMotions, RotationTranslationDerivatives, Stacked,
};
use crate::point::{add_force_terms, add_force_value, GaussPoint};
use crate::system::System;
use lgsvi_lie::se3::{join, split};
use lgsvi_lie::so3::hat;
use lgsvi_lie::{LieGroup, SE3, SO3};
use nalgebra::{Matrix3, SMatrix, Vector3};

/// One Gauss point's derivatives for an SE(3) system: by blocks on the rotation–translation
/// chart when the system has [`System::local_derivatives`], else by the generic
/// chain rule (the chart's derivatives are taken once either way). Always `true`: for
/// [`System::point_derivatives`].
pub(crate) fn point_derivatives<S, C>(
    system: &S,
    chart: &C,
    point: &GaussPoint<'_, RigidMotions, 6>,
    out: &mut Stacked<18>,
) -> bool
where
    S: System<6, Group = RigidMotions>,
    C: GroupChart<RigidMotions, 6>,
{
    chart.with_derivatives(point.x, point.with_hessian, |derivatives| {
        if let Some(jets) = derivatives.rotation_translation() {
            if by_blocks(system, jets, point, out) {
                return;
            }
        }
        let ell = EllTilde {
            system,
            chart,
            base: point.base,
            time: point.time,
        };
        chain_rule_with(&ell, point, derivatives, out);
    });
    true
}

/// The 3 × 3 block of `m` at `(r, c)`.
fn block(m: &SMatrix<f64, 6, 6>, r: usize, c: usize) -> Matrix3<f64> {
    m.fixed_view::<3, 3>(r, c).into_owned()
}

/// Writes `b` at `(r0, c0)` of the point's Hessian and its transpose at `(c0, r0)` (on the
/// diagonal, `b`'s transpose: the diagonal blocks are symmetric but for rounding).
fn put(out: &mut Stacked<18>, r0: usize, c0: usize, b: &Matrix3<f64>) {
    out.hessian.fixed_view_mut::<3, 3>(r0, c0).copy_from(b);
    out.hessian
        .fixed_view_mut::<3, 3>(c0, r0)
        .copy_from(&b.transpose());
}

/// Whether `μ_u` lies along `ξ_u` to rounding: `|μ_u × ξ_u| ≤ 4ε |μ_u| |ξ_u|` (the
/// cross product of `fl(c ξ_u)` with `ξ_u` is a few ulps of that). Then `J_Pᵀμ_u`, whose
/// exact value is `c ∂(½|Pᵀv_u|²)/∂ω = 0` for `μ_u = c ξ_u`, is rounding noise.
fn along(mu: &Vector3<f64>, xi: &Vector3<f64>) -> bool {
    let tolerance = 4.0 * f64::EPSILON;
    mu.cross(xi).norm_squared() <= tolerance * tolerance * mu.norm_squared() * xi.norm_squared()
}

/// The translation's kinetic block `X_uu = c I` (exactly), not coupled to the rotation's
/// (`X_ωu = X_uω = 0`), and `μ_u = c ξ_u` to rounding: the kinetic energy `½c|ξ_u|²`
/// near the point.
fn isotropic_translation(x: &SMatrix<f64, 6, 6>, mu: &Vector3<f64>, xi: &Vector3<f64>) -> bool {
    let c = x[(3, 3)];
    let translation = (3..6).all(|r| (3..6).all(|k| x[(r, k)] == if r == k { c } else { 0.0 }));
    let uncoupled = (0..3).all(|r| (3..6).all(|k| x[(r, k)] == 0.0 && x[(k, r)] == 0.0));
    let tolerance = 4.0 * f64::EPSILON;
    translation
        && uncoupled
        && (mu - xi * c).norm_squared() <= tolerance * tolerance * mu.norm_squared()
}

/// The module's formulas; false (nothing written) where the system has no closed form of
/// `L`'s derivatives.
fn by_blocks<S: System<6, Group = RigidMotions>>(
    system: &S,
    jets: &RotationTranslationDerivatives,
    point: &GaussPoint<'_, RigidMotions, 6>,
    out: &mut Stacked<18>,
) -> bool {
    let (a, phi) = (&jets.a, &jets.phi);
    let (_, u) = split(point.x);
    let (vw, vu) = split(point.v);
    let (aw, rot) = (a.value, phi.value);
    let rot_t = rot.transpose();
    let at = point
        .base
        .compose(&SE3::new(SO3::from_matrix_unchecked(rot), u));
    let xi = join(&(aw * vw), &(rot_t * vu));
    let Some(local) = system.local_derivatives(point.time, &at, &xi, point.with_hessian) else {
        return false;
    };
    let (pw, pu) = split(&local.configuration_gradient);
    let (mw, mu) = split(&local.momentum);
    let jw = a.first_times(&vw);
    let (with_configuration, with_hessian) = (point.with_configuration, point.with_hessian);
    // The translation's kinetic terms through `P`: a momentum `μ_u = c ξ_u` along the
    // body's velocity `ξ_u = Pᵀv_u` with `X_uu = c I` (every built-in body, `c = m`) is
    // the kinetic energy `½c|Pᵀv_u|² = ½c|v_u|²`, which does not depend on `ω`: its
    // terms `J_Pᵀμ_u` (gradient), `J_PᵀT_u + ⟨v_u μ_uᵀ, ∂²P⟩` (`H_ωω`) and
    // `T_uᵀPᵀ + M_ωu` (`H_ωv_u`) are zero, and `P X_uu Pᵀ = c I`. Computed, they are
    // rounding noise; skipped, as are `J_P` and `P`'s jet contractions (module
    // documentation).
    let xi_u = xi.fixed_rows::<3>(3).into_owned();
    let isotropic = if with_hessian {
        isotropic_translation(&local.velocity_hessian, &mu, &xi_u)
    } else {
        along(&mu, &xi_u)
    };
    let jp = if isotropic {
        Matrix3::zeros()
    } else {
        phi.first_transposed_times(&vu).transpose()
    };
    if with_hessian {
        let e = &local.configuration_hessian;
        let x = &local.velocity_hessian;
        let configured = e.as_slice().iter().any(|&v| v != 0.0);
        let (xww, xwu, xuw, xuu) = (
            block(x, 0, 0),
            block(x, 0, 3),
            block(x, 3, 0),
            block(x, 3, 3),
        );
        // A body whose kinetic energy does not couple its turning and its moving (every
        // built-in one: the centre of mass at the body's origin) has `X_ωu = X_uω = 0`;
        // their products, zero, are skipped (adding them changed nothing but the
        // sign of a zero entry, and their cost).
        let coupled = xwu.iter().chain(xuw.iter()).any(|&v| v != 0.0);
        let (tw, tu) = if coupled {
            (xww * jw + xwu * jp, xuw * jw + xuu * jp)
        } else if isotropic {
            (xww * jw, Matrix3::zeros())
        } else {
            (xww * jw, xuu * jp)
        };
        let k_ww = a.first_transposed_times(&pw);
        let k_wu = phi.first_times(&pu).transpose();
        let m_ww = a.first_transposed_times(&mw);
        let mut xx_ww = if isotropic {
            jw.tr_mul(&tw)
                + (k_ww + k_ww.transpose()) * 0.5
                + a.second_contracted(&(mw * vw.transpose()))
        } else {
            let h_w = a.second_contracted(&(mw * vw.transpose()))
                + phi.second_contracted(&(vu * mu.transpose()));
            jw.tr_mul(&tw) + jp.tr_mul(&tu) + (k_ww + k_ww.transpose()) * 0.5 + h_w
        };
        let mut xx_wu = k_wu * 0.5;
        let mut xx_uu = Matrix3::zeros();
        // E A by blocks: [[E_ωω A_ω, E_ωu Pᵀ], [E_uω A_ω, E_uu Pᵀ]].
        let (mut ea_ww, mut ea_wu, mut ea_uw, mut ea_uu) = (
            Matrix3::zeros(),
            Matrix3::zeros(),
            Matrix3::zeros(),
            Matrix3::zeros(),
        );
        if configured {
            ea_ww = block(e, 0, 0) * aw;
            ea_wu = block(e, 0, 3) * rot_t;
            ea_uw = block(e, 3, 0) * aw;
            ea_uu = block(e, 3, 3) * rot_t;
            xx_ww += aw.tr_mul(&ea_ww);
            xx_wu += aw.tr_mul(&ea_wu);
            xx_uu = rot * ea_uu;
        }
        put(out, 0, 0, &xx_ww);
        put(out, 0, 3, &xx_wu);
        put(out, 3, 3, &xx_uu);
        let zero = Matrix3::zeros();
        put(out, 0, 6, &(tw.tr_mul(&aw) + m_ww));
        let xv_wu = if isotropic {
            zero
        } else {
            tu.tr_mul(&rot_t) + phi.first_times(&mu).transpose()
        };
        put(out, 0, 9, &xv_wu);
        put(out, 3, 6, &zero);
        put(out, 3, 9, &zero);
        put(out, 6, 6, &aw.tr_mul(&(xww * aw)));
        put(
            out,
            6,
            9,
            &if coupled {
                aw.tr_mul(&(xwu * rot_t))
            } else {
                Matrix3::zeros()
            },
        );
        let vv_uu = if isotropic { xuu } else { rot * (xuu * rot_t) };
        put(out, 9, 9, &vv_uu);
        if with_configuration {
            let (pw_hat, pu_hat) = (hat(&pw), hat(&pu));
            put(out, 0, 12, &(ea_ww + pw_hat * aw * 0.5).transpose());
            put(out, 0, 15, &(ea_uw + pu_hat * aw * 0.5).transpose());
            put(out, 3, 12, &(ea_wu + pu_hat * rot_t * 0.5).transpose());
            put(out, 3, 15, &ea_uu.transpose());
            for (r0, c0) in [(6, 12), (6, 15), (9, 12), (9, 15)] {
                put(out, r0, c0, &zero);
            }
            for (r0, c0) in [(0, 0), (0, 3), (3, 3)] {
                put(out, 12 + r0, 12 + c0, &block(e, r0, c0));
            }
        } else {
            // The ζ columns and the ζζ block, as the generic rule leaves them.
            let zeta_blocks = [
                (0, 12),
                (0, 15),
                (3, 12),
                (3, 15),
                (6, 12),
                (6, 15),
                (9, 12),
                (9, 15),
                (12, 12),
                (12, 15),
                (15, 15),
            ];
            for (r0, c0) in zeta_blocks {
                put(out, r0, c0, &zero);
            }
        }
    }
    let mut gx_w = aw.tr_mul(&pw) + jw.tr_mul(&mw);
    if !isotropic {
        gx_w += jp.tr_mul(&mu);
    }
    let gx_u = rot * pu;
    let gv_w = aw.tr_mul(&mw);
    let gv_u = rot * mu;
    let g = out.gradient_mut();
    for (i, part) in [gx_w, gx_u, gv_w, gv_u].iter().enumerate() {
        g[3 * i..3 * i + 3].copy_from_slice(part.as_slice());
    }
    if with_configuration {
        g[12..18].copy_from_slice(local.configuration_gradient.as_slice());
    } else {
        g[12..18].fill(0.0);
    }
    // The force's terms as the generic rule adds them, from the chart's 6 × 6 contractions.
    if let Some(force) = point.force {
        let a6 = jets.differential();
        if with_hessian {
            let jet = force.jet(&at, &xi);
            let j6 = jets.differential_times(point.v);
            let k6 = jets.transpose_times(&jet.value);
            add_force_terms(out, &jet, &a6, &j6, &k6, true);
        } else {
            add_force_value(out, &force.value(&at, &xi), &a6);
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The built-in bodies' kinetic terms (`X = diag(J, m I)`, `μ_u = m ξ_u`) take the
    /// isotropic path; a translation block that is not `c I`, one coupled to the rotation,
    /// or a momentum off `c ξ_u` (or off `ξ_u` for the gradient) does not.
    #[test]
    fn only_an_isotropic_translation_skips_its_terms() {
        let mass = 2.7;
        let xi = Vector3::new(0.3, -1.1, 0.45);
        let mu = xi * mass;
        let mut x = SMatrix::<f64, 6, 6>::zeros();
        x.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&Matrix3::new(3.0, 0.1, 0.0, 0.1, 2.0, 0.2, 0.0, 0.2, 4.0));
        x.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(Matrix3::identity() * mass));
        assert!(isotropic_translation(&x, &mu, &xi));
        assert!(along(&mu, &xi));
        // A momentum a few ulps off c ξ_u (as a product rounds) still is.
        let rounded = mu.map(|m| m * (1.0 + 2.0 * f64::EPSILON));
        assert!(isotropic_translation(&x, &rounded, &xi));
        assert!(along(&rounded, &xi));
        // Off by more, not.
        let off = mu + Vector3::new(0.0, 0.0, 1e-9);
        assert!(!isotropic_translation(&x, &off, &xi));
        assert!(!along(&off, &xi));
        // Along ξ_u but with another c: the gradient's term is zero, the Hessian's not.
        assert!(along(&(mu * 2.0), &xi));
        assert!(!isotropic_translation(&x, &(mu * 2.0), &xi));
        let mut anisotropic = x;
        anisotropic[(4, 4)] = 1.5 * mass;
        assert!(!isotropic_translation(&anisotropic, &mu, &xi));
        let mut off_diagonal = x;
        off_diagonal[(3, 5)] = 1e-3;
        assert!(!isotropic_translation(&off_diagonal, &mu, &xi));
        let mut coupled = x;
        coupled[(1, 4)] = 0.2;
        assert!(!isotropic_translation(&coupled, &mu, &xi));
        coupled = x;
        coupled[(5, 0)] = 0.2;
        assert!(!isotropic_translation(&coupled, &mu, &xi));
    }
}
