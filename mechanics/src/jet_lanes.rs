//! The Gauss points of an SO(3) step evaluated four at a time: [`crate::jet`]'s chain rule
//! with every quantity stored as a lane over four points (struct of arrays), compiled for
//! the x86-64 baseline and with AVX2 (chosen at run time by `multiversion`, as the LU).
//!
//! Per point, as in [`crate::jet::point_derivatives`]: `A = e I + a x̂ + b x̂²`, `Ω = A v`,
//! `g = ∂ℓ/∂Ω`, `H = ∂²ℓ/∂Ω²`, `J = [∂_k A v]_k`; gradient `(Jᵀg, Aᵀg, 0)`; Hessian
//! `[J A]ᵀ H [J A]` plus `⟨g vᵀ, ∂_k∂_l A⟩` in the `xx` block and `gᵀ ∂_k A e_b` in the `xv`
//! and `vx` blocks ([`lgsvi_lie::jet::MatrixJet`] has the formulas); then ℓ's attitude
//! terms through `M = Rᵀ ∂ℓ/∂R` where ℓ's attitude term is linear in `R`, and a force's
//! terms ([`crate::point::add_force_terms`]). The chart's coefficients, ℓ's derivatives and
//! the force's jet are asked point by point (a `sin_cos` or series, trait calls), and
//! `A(x)`, which `Ω` needs before ℓ is asked, is formed there too; the lanes form it again
//! from the coefficients rather than read nine more entries a point (forming it costs less
//! than reading it). The rest of a point's arithmetic runs in the lanes.
//!
//! **The same bits as point by point.** Every sum and product is taken in the order the
//! scalar path's nalgebra expressions take it (matrix products by columns, left to right;
//! the two triangles of a symmetric block formed separately), and no multiply–add is
//! fused (Rust does not contract them, in either compilation), so a step's results do not
//! depend on whether its points went through the lanes or on the processor
//! (`step::tests::points_in_lanes_match_dual_numbers` compares bits). Systems outside the
//! lanes (an ℓ whose attitude term is not linear, a force that reads the attitude, a chart
//! without a Rodrigues form) take the scalar path.

use crate::group::{GroupChart, Rotations, Stacked};
use crate::lagrangian::Lagrangian;
use crate::point::{GaussPoints, PointTransport};
use lgsvi_lie::{RodriguesCoefficients, SO3};
use nalgebra::Vector3;
use num_dual::{Dual2_64, Dual64};
use std::ops::{Add, Mul, Neg, Sub};

/// Points a lane holds.
const LANES: usize = 4;

/// One quantity at four points.
#[derive(Clone, Copy, Default)]
struct V([f64; LANES]);

macro_rules! lane_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for V {
            type Output = V;
            #[inline(always)]
            fn $method(self, o: V) -> V {
                let (a, b) = (self.0, o.0);
                V([a[0] $op b[0], a[1] $op b[1], a[2] $op b[2], a[3] $op b[3]])
            }
        }
        impl $trait<f64> for V {
            type Output = V;
            #[inline(always)]
            fn $method(self, o: f64) -> V {
                let a = self.0;
                V([a[0] $op o, a[1] $op o, a[2] $op o, a[3] $op o])
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);

impl Neg for V {
    type Output = V;
    #[inline(always)]
    fn neg(self) -> V {
        let a = self.0;
        V([-a[0], -a[1], -a[2], -a[3]])
    }
}

type V3 = [V; 3];

/// `[f(0), f(1), f(2)]`, written out (`std::array::from_fn` was not unrolled).
macro_rules! three {
    (|$i:ident| $e:expr) => {
        [
            {
                let $i = 0usize;
                $e
            },
            {
                let $i = 1usize;
                $e
            },
            {
                let $i = 2usize;
                $e
            },
        ]
    };
}
/// Row-major: `m[i][j]`.
type M3 = [[V; 3]; 3];

#[inline(always)]
fn dot(a: &V3, b: &V3) -> V {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
fn cross(a: &V3, b: &V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a w`, each entry summed over the columns in order (nalgebra's order).
#[inline(always)]
fn times(a: &M3, w: &V3) -> V3 {
    three!(|i| a[i][0] * w[0] + a[i][1] * w[1] + a[i][2] * w[2])
}

/// `aᵀ w`.
#[inline(always)]
fn transposed_times(a: &M3, w: &V3) -> V3 {
    three!(|i| a[0][i] * w[0] + a[1][i] * w[1] + a[2][i] * w[2])
}

/// `a b`.
#[inline(always)]
fn product(a: &M3, b: &M3) -> M3 {
    three!(|r| three!(|c| a[r][0] * b[0][c] + a[r][1] * b[1][c] + a[r][2] * b[2][c]))
}

/// `aᵀ b`.
#[inline(always)]
fn transposed_product(a: &M3, b: &M3) -> M3 {
    three!(|r| three!(|c| a[0][r] * b[0][c] + a[1][r] * b[1][c] + a[2][r] * b[2][c]))
}

/// `γ` with `⟨M, ŷ⟩ = γ·y`: the axial vector of `M − Mᵀ` (`lgsvi_lie::jet::axial`).
#[inline(always)]
fn axial(m: &M3) -> V3 {
    [m[2][1] - m[1][2], m[0][2] - m[2][0], m[1][0] - m[0][1]]
}

/// `ŵ`.
#[inline(always)]
fn hat(w: &V3) -> M3 {
    let z = V::default();
    [[z, -w[2], w[1]], [w[2], z, -w[0]], [-w[1], w[0], z]]
}

/// What the lanes read of four points.
#[derive(Clone, Copy, Default)]
struct Inputs {
    x: V3,
    v: V3,
    /// `(e, a, b)` and their first and second derivatives in `s = |x|²`.
    c0: V3,
    c1: V3,
    c2: V3,
    /// `∂ℓ/∂Ω`, `∂²ℓ/∂Ω²` at `Ω = A v`.
    g: V3,
    h: M3,
    /// `M = Rᵀ ∂ℓ/∂R` (an `ℓ` that reads the attitude; else unused).
    m: M3,
    /// The force's value, `∂F/∂ξ` and `∂F/∂η` (a forced step; else unused), and whether
    /// its derivatives are zero at each point.
    f: V3,
    f_velocity: M3,
    f_configuration: M3,
    f_constant: [bool; LANES],
}

/// What the lanes compute besides the free body's terms.
#[derive(Clone, Copy)]
struct Terms {
    attitude: bool,
    forced: bool,
    with_configuration: bool,
    with_hessian: bool,
}

/// Columns `∂_k M' w` for `M' = e I + σ a x̂ + b x̂²`, `σ = ±1`
/// ([`lgsvi_lie::jet::MatrixJet::first_times`]): `u xᵀ − σa ŵ + b x wᵀ + b (x·w) I`,
/// `u = 2e′w + 2σa′ x×w + 2b′ x̂²w − 2b w`.
#[inline(always)]
fn first_applied(p: &Inputs, s: V, w: &V3, skew_sign: f64) -> M3 {
    let x = &p.x;
    let (a, b) = (p.c0[1] * skew_sign, p.c0[2]);
    let (e1, a1, b1) = (p.c1[0], p.c1[1] * skew_sign, p.c1[2]);
    let xw = dot(x, w);
    let xw_cross = cross(x, w);
    let (cw, cc, ch) = ((e1 * 2.0) - b * 2.0, a1 * 2.0, b1 * 2.0);
    let u: V3 = three!(|i| w[i] * cw + xw_cross[i] * cc + (x[i] * xw - w[i] * s) * ch);
    let wh = hat(w);
    let mut out: M3 = three!(|i| three!(|j| u[i] * x[j] - wh[i][j] * a + x[i] * w[j] * b));
    for (i, row) in out.iter_mut().enumerate() {
        row[i] = row[i] + b * xw;
    }
    out
}

/// `[⟨g vᵀ, ∂_k∂_l A⟩]_kl` ([`lgsvi_lie::jet::MatrixJet::second_contracted`] with
/// `G = g vᵀ`).
#[inline(always)]
fn second_contracted(p: &Inputs, s: V) -> M3 {
    let (x, g, v) = (&p.x, &p.g, &p.v);
    let b = p.c0[2];
    let [e1, a1, b1] = p.c1;
    let [e2, a2, b2] = p.c2;
    let t = dot(g, v);
    // γ = vee(G − Gᵀ) for G = g vᵀ: g vᵀ − v gᵀ = (v × g)^.
    let gamma = cross(v, g);
    let gx = dot(&gamma, x);
    // G x and (G + Gᵀ) x with G = g vᵀ, as matrix–vector products.
    let gm: M3 = three!(|i| three!(|j| g[i] * v[j]));
    let sym: M3 = three!(|i| three!(|j| gm[i][j] + gm[j][i]));
    let q = dot(x, &times(&gm, x)) - s * t;
    let sym_x = times(&sym, x);
    let u: V3 = three!(|i| sym_x[i] - x[i] * (t * 2.0));
    let outer = (e2 * t + a2 * gx + b2 * q) * 4.0;
    let diagonal = (e1 * t + a1 * gx + b1 * q) * 2.0 - b * t * 2.0;
    let w: V3 = three!(|i| gamma[i] * (a1 * 2.0) + u[i] * (b1 * 2.0));
    let mut out: M3 =
        three!(|i| three!(|j| x[i] * x[j] * outer + x[i] * w[j] + w[i] * x[j] + sym[i][j] * b));
    for (i, row) in out.iter_mut().enumerate() {
        row[i] = row[i] + diagonal;
    }
    out
}

/// The lanes' arithmetic for up to four points, written into `out` (one `Stacked` a
/// point, `out.len() ≤ 4`): the gradient always, the Hessian if `with_hessian`.
#[multiversion::multiversion(targets("x86_64+avx+avx2+fma"))]
fn lanes(p: &Inputs, terms: Terms, out: &mut [Stacked<9>]) {
    let Terms {
        attitude,
        forced,
        with_configuration,
        with_hessian,
    } = terms;
    let (x, v, g_vec) = (&p.x, &p.v, &p.g);
    let [e, a, b] = p.c0;
    let s = dot(x, x);
    // A = e I + a x̂ + b x̂² entry by entry, as `RodriguesCoefficients::matrix` forms it:
    // x̂² = x xᵀ − s I with the diagonal 1 − b(x_j² + x_k²), then e − 1 added.
    let sq = [x[0] * x[0], x[1] * x[1], x[2] * x[2]];
    let (bxy, bxz, byz) = (b * x[0] * x[1], b * x[0] * x[2], b * x[1] * x[2]);
    let (ax, ay, az) = (a * x[0], a * x[1], a * x[2]);
    let (one, shift) = (V([1.0; LANES]), e - 1.0);
    let am: M3 = [
        [one - b * (sq[1] + sq[2]) + shift, bxy - az, bxz + ay],
        [bxy + az, one - b * (sq[0] + sq[2]) + shift, byz - ax],
        [bxz - ay, byz + ax, one - b * (sq[0] + sq[1]) + shift],
    ];
    // J = [∂_k A v]_k.
    let jm = first_applied(p, s, v, 1.0);
    // Gradient: Jᵀg, Aᵀg.
    let (gx, gv) = (transposed_times(&jm, g_vec), transposed_times(&am, g_vec));
    for (l, point) in out.iter_mut().enumerate() {
        let (x_rows, v_rows) = ([gx[0], gx[1], gx[2]], [gv[0], gv[1], gv[2]]);
        point.gradient = nalgebra::SVector::from([
            x_rows[0].0[l],
            x_rows[1].0[l],
            x_rows[2].0[l],
            v_rows[0].0[l],
            v_rows[1].0[l],
            v_rows[2].0[l],
            0.0,
            0.0,
            0.0,
        ]);
    }
    // ℓ's attitude terms with γ = vee(M − Mᵀ) (`crate::jet`, "Attitude terms"): the
    // gradient gains Aᵀγ in the x rows and γ in the ζ rows.
    let gamma = axial(&p.m);
    if attitude {
        let gradient_x = transposed_times(&am, &gamma);
        for (l, point) in out.iter_mut().enumerate() {
            let gradient = &mut point.gradient;
            for k in 0..3 {
                gradient[k] += gradient_x[k].0[l];
                if with_configuration {
                    gradient[6 + k] += gamma[k].0[l];
                }
            }
        }
    }
    // The force: A(x)ᵀF in the x rows, F in the ζ rows.
    let f = &p.f;
    if forced {
        let projected = transposed_times(&am, f);
        for (l, point) in out.iter_mut().enumerate() {
            let gradient = &mut point.gradient;
            for c in 0..3 {
                gradient[c] += projected[c].0[l];
                gradient[6 + c] += f[c].0[l];
            }
        }
    }
    if !with_hessian {
        return;
    }
    // top = [J A] (3 × 6); T = topᵀ H top.
    let top: [V3; 6] = [
        [jm[0][0], jm[1][0], jm[2][0]],
        [jm[0][1], jm[1][1], jm[2][1]],
        [jm[0][2], jm[1][2], jm[2][2]],
        [am[0][0], am[1][0], am[2][0]],
        [am[0][1], am[1][1], am[2][1]],
        [am[0][2], am[1][2], am[2][2]],
    ];
    // (topᵀ H) top, in the order of the scalar path's products: P = topᵀ H (6 × 3), then
    // P top, every entry of the 6 × 6 (the two triangles round alike only by chance).
    let h = &p.h;
    let mut pm = [[V::default(); 3]; 6];
    for (row, t) in pm.iter_mut().zip(&top) {
        *row = transposed_times(h, t);
    }
    let second = second_contracted(p, s);
    // gᵀ ∂_k A e_b at (k, b): the transpose of the columns ∂_k A' g with the skew terms
    // negated.
    let cross_t = first_applied(p, s, g_vec, -1.0);
    for (l, point) in out.iter_mut().enumerate() {
        let hessian = &mut point.hessian;
        *hessian = nalgebra::SMatrix::zeros();
        for r in 0..6 {
            for c in 0..6 {
                let t = dot(&pm[r], &top[c]).0[l];
                hessian[(r, c)] = if r < 3 && c < 3 {
                    t + second[r][c].0[l]
                } else if r < 3 {
                    // (k, 3 + b) and (3 + b, k): gᵀ ∂_k A e_b = cross_t[b][k].
                    t + cross_t[c - 3][r].0[l]
                } else if c < 3 {
                    t + cross_t[r - 3][c].0[l]
                } else {
                    t
                };
            }
        }
    }
    if attitude {
        attitude_hessian(p, s, &am, &gamma, with_configuration, out);
    }
    if forced {
        force_hessian(p, s, &am, &jm, out);
    }
}

/// ℓ's attitude terms in the Hessian (`crate::jet`, "Attitude terms").
#[inline(always)]
fn attitude_hessian(
    p: &Inputs,
    s: V,
    am: &M3,
    gamma: &V3,
    with_configuration: bool,
    out: &mut [Stacked<9>],
) {
    let m = &p.m;
    // ⟨M, û_k û_l⟩ + γᵀ ∂_kA e_l = (Aᵀ (Mᵀ − tr M I)) A + (the columns ∂_k A' γ, skew
    // terms negated)ᵀ, and with the ζ rows ((M − tr M) A)_ck and ½(M_dc + M_cd) − δ_cd tr M.
    let trace = m[0][0] + m[1][1] + m[2][2];
    let m_t: M3 = three!(|i| three!(|j| if i == j { m[j][i] - trace } else { m[j][i] }));
    let sandwich = product(&transposed_product(am, &m_t), am);
    let gamma_cross = first_applied(p, s, gamma, -1.0);
    let m_shifted: M3 = three!(|i| three!(|j| if i == j { m[i][j] - trace } else { m[i][j] }));
    let mixed = product(&m_shifted, am);
    for (l, point) in out.iter_mut().enumerate() {
        let hessian = &mut point.hessian;
        for k in 0..3 {
            for j in 0..3 {
                hessian[(k, j)] += (sandwich[k][j] + gamma_cross[j][k]).0[l];
            }
        }
        if with_configuration {
            for c in 0..3 {
                for k in 0..3 {
                    hessian[(k, 6 + c)] += mixed[c][k].0[l];
                    hessian[(6 + c, k)] += mixed[c][k].0[l];
                }
                for d in 0..3 {
                    let delta = if c == d { trace.0[l] } else { 0.0 };
                    hessian[(6 + c, 6 + d)] += 0.5 * (m[d][c].0[l] + m[c][d].0[l]) - delta;
                }
            }
        }
    }
}

/// The force's terms in the Hessian (`crate::point::add_force_terms`): `K_F` (the columns
/// `∂_k A' F`, skew terms negated) alone where the force's derivatives are zero, else
/// `K_F + Aᵀ ∂F/∂x`, `Aᵀ ∂F/∂v` and the `ζ` rows `∂F/∂x = F_η A + F_ξ J`, `∂F/∂v = F_ξ A`.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // entries (r, c) of several matrices at once
fn force_hessian(p: &Inputs, s: V, am: &M3, jm: &M3, out: &mut [Stacked<9>]) {
    let k = first_applied(p, s, &p.f, -1.0);
    let n = out.len();
    if p.f_constant[..n].iter().all(|&constant| constant) {
        for (l, point) in out.iter_mut().enumerate() {
            for r in 0..3 {
                for c in 0..3 {
                    point.hessian[(r, c)] += k[r][c].0[l];
                }
            }
        }
        return;
    }
    let (p1, p2) = (product(&p.f_configuration, am), product(&p.f_velocity, jm));
    let df_dx: M3 = three!(|r| three!(|c| p1[r][c] + p2[r][c]));
    let df_dv = product(&p.f_velocity, am);
    let at_df_dx = transposed_product(am, &df_dx);
    let xv = transposed_product(am, &df_dv);
    for (l, point) in out.iter_mut().enumerate() {
        let hessian = &mut point.hessian;
        for r in 0..3 {
            for c in 0..3 {
                if p.f_constant[l] {
                    hessian[(r, c)] += k[r][c].0[l];
                } else {
                    hessian[(r, c)] += (k[r][c] + at_df_dx[r][c]).0[l];
                    hessian[(r, 3 + c)] += xv[r][c].0[l];
                    hessian[(6 + r, c)] += df_dx[r][c].0[l];
                    hessian[(6 + r, 3 + c)] += df_dv[r][c].0[l];
                }
            }
        }
    }
}

/// Writes every point's derivatives into `out` four points at a time, for a step of a
/// left-invariant `ℓ` or one whose attitude term is linear in `R`
/// ([`Lagrangian::linear_attitude_term`]: `M = Φ(x)ᵀ(Bᵀa) bᵀ`) under no force or one
/// that does not read the attitude, with the chart's `(Φ(x), A(x))` in `transports` where
/// `with_configuration` and `ℓ` reads the attitude (else `None`) and the force's power in
/// `power` (NaN unforced), as [`crate::jet::point_derivatives`] writes them point by
/// point, bit for bit. False (nothing written) for any other system or force, or a chart
/// without a Rodrigues form.
pub(crate) fn points_in_lanes<L: Lagrangian, C: GroupChart<Rotations, 3>>(
    system: &L,
    chart: &C,
    points: &GaussPoints<'_, Rotations, 3>,
    out: &mut [Stacked<9>],
    transports: &mut [Option<PointTransport<3>>],
    power: &mut [f64],
) -> bool {
    let GaussPoints {
        base,
        x,
        v,
        with_configuration,
        with_hessian,
        force,
    } = *points;
    let attitude = !system.is_left_invariant();
    let r = base.matrix();
    let force = match force {
        Some((_, true)) => return false,
        Some((force, false)) => Some(force),
        None => None,
    };
    // The attitude field in the base's frame, Bᵀa, and the body vector b.
    let field = match system.linear_attitude_term() {
        Some((field, body_vector)) if attitude => Some((r.transpose() * field, body_vector)),
        // A chart without a Rodrigues form returns at the first point, before the lanes
        // write anything.
        _ if !attitude => None,
        _ => return false,
    };
    let terms = Terms {
        attitude,
        forced: force.is_some(),
        with_configuration,
        with_hessian,
    };
    let at_base = SO3::from_matrix_unchecked(*r);
    // Filled lane by lane for each chunk of points; a short last chunk leaves the earlier
    // chunk's points (or zeros) in its spare lanes, whose results are not written. The
    // lanes divide by nothing, so those stay finite.
    let mut p = Inputs::default();
    for (chunk, (((xs, vs), outs), transports)) in x
        .chunks(LANES)
        .zip(v.chunks(LANES))
        .zip(out.chunks_mut(LANES))
        .zip(transports.chunks_mut(LANES))
        .enumerate()
    {
        for l in 0..xs.len() {
            let (xl, vl) = (&xs[l], &vs[l]);
            let s = xl.norm_squared();
            let (c0, c1, c2) = if with_hessian {
                let Some(c) = chart.left_differential_coefficients(Dual2_64::new(s, 1.0, 0.0))
                else {
                    return false;
                };
                (
                    [c.identity.re, c.hat.re, c.hat_squared.re],
                    [c.identity.v1, c.hat.v1, c.hat_squared.v1],
                    [c.identity.v2, c.hat.v2, c.hat_squared.v2],
                )
            } else {
                let Some(c) = chart.left_differential_coefficients(Dual64::new(s, 1.0)) else {
                    return false;
                };
                (
                    [c.identity.re, c.hat.re, c.hat_squared.re],
                    [c.identity.eps, c.hat.eps, c.hat_squared.eps],
                    [0.0; 3],
                )
            };
            // Ω = A v, A formed as the scalar path forms it (the same bits).
            let a = RodriguesCoefficients {
                identity: c0[0],
                hat: c0[1],
                hat_squared: c0[2],
            }
            .matrix(xl);
            let omega: Vector3<f64> = a * vl;
            transports[l] = None;
            if let Some((field, body_vector)) = &field {
                let Some(phi) = chart.rotation_coefficients(s) else {
                    return false;
                };
                if with_configuration {
                    transports[l] = Some(PointTransport {
                        to_start: phi.matrix(xl),
                        differential: a,
                    });
                }
                let m = phi.transpose_times(xl, field) * body_vector.transpose();
                for i in 0..3 {
                    for j in 0..3 {
                        p.m[i][j].0[l] = m[(i, j)];
                    }
                }
            }
            let j = LANES * chunk + l;
            power[j] = f64::NAN;
            if let Some(force) = force {
                // The force at the attitude the scalar path gives it: the base (ℓ reads
                // the attitude through M alone, the force not at all).
                let (jet, point_power) = force(j, &at_base, &omega);
                power[j] = point_power;
                p.f_constant[l] = jet
                    .velocity
                    .iter()
                    .chain(jet.configuration.iter())
                    .all(|&e| e == 0.0);
                for i in 0..3 {
                    p.f[i].0[l] = jet.value[i];
                    for k in 0..3 {
                        p.f_velocity[i][k].0[l] = jet.velocity[(i, k)];
                        p.f_configuration[i][k].0[l] = jet.configuration[(i, k)];
                    }
                }
            }
            let d = system.derivatives(r, &omega);
            for i in 0..3 {
                p.x[i].0[l] = xl[i];
                p.v[i].0[l] = vl[i];
                p.c0[i].0[l] = c0[i];
                p.c1[i].0[l] = c1[i];
                p.c2[i].0[l] = c2[i];
                p.g[i].0[l] = d.velocity_gradient[i];
                for j in 0..3 {
                    p.h[i][j].0[l] = d.velocity_hessian[(i, j)];
                }
            }
        }
        lanes(&p, terms, outs);
    }
    true
}
