//! The momentum matching: the last `D` equations of a step, their rows of the Newton
//! matrix, and the momentum the step hands on.
//!
//! **Exact** (the default; derived for any group in `docs/paper-notes.md` §3): the
//! discrete Lagrangian's derivative in the step's
//! start `g_k`, with the whole curve moving with its base point and `g_{k+1}` held: the
//! curve `g_k exp(η) Φ(ξ(t))` moves each Gauss point by the left variation
//! `Ad_{Φ(x_j)⁻¹} η` and the last node by `δξⁿ = −A(ξⁿ)⁻¹ Ad_{Φ(ξⁿ)⁻¹} η`, so that
//! `μ_k = −D₁L_d` reads
//!
//! `A(ξⁿ)ᵀ Ad_{Φ(ξⁿ)}ᵀ w = ∂S/∂ξⁿ`, `w = μ_k + Σ_j h b_j Ad_{Φ(x_j)⁻¹}ᵀ p_j`,
//!
//! with `p_j = ∂ℓ̃/∂ζ` (plus the force, [`crate::system`]). Then
//! `μ_{k+1} = A(ξⁿ)⁻ᵀ ∂S/∂ξⁿ = Ad_{Φ(ξⁿ)}ᵀ w`, so the spatial momentum
//! `Ad_{g_{k+1}⁻¹}ᵀ μ_{k+1} = Ad_{g_k⁻¹}ᵀ w` changes only by the configuration and
//! external forces: discrete Noether for every symmetry `ℓ` has, to rounding.
//!
//! **Paper** (`Matching::Paper`): `A(0)ᵀ μ_k + ∂S/∂ξ¹ = 0`, `μ_{k+1} = A(ξⁿ)⁻ᵀ ∂S/∂ξⁿ`;
//! not the derivative of the discrete Lagrangian, so momenta and energy drift.

use super::assembly::WorkspaceOf;
use super::product::fixed_product;
use super::{Element, MatchingTerms, StepOutcome, StepSolver};
use crate::group::{ConfigurationGroup, GroupChart, PointJet};
use crate::settings::Matching;
use crate::system::System;
use lgsvi_lie::LieGroup;
use nalgebra::{SMatrix, SVector};
#[cfg(test)]
use num_dual::DualSVec64;

impl<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> StepSolver<'_, S, C, D> {
    /// The matching residual at the last points and the scale of its terms; records `w`
    /// and the transport (and, with `with_jacobian`, `∂q/∂x`, `∂q/∂v`) for the Jacobian.
    pub(super) fn matching_residual(
        &self,
        mu: &SVector<f64, D>,
        work: &mut WorkspaceOf<S, D>,
        with_jacobian: bool,
    ) -> (SVector<f64, D>, f64) {
        let d = self.d;
        let (n, m) = (d.n, d.m);
        let chart = self.chart;
        let xi_n = work.xi[n - 1];
        // w = μ_k + Σ_j h b_j Ad_{Φ(x_j)⁻¹}ᵀ p_j (exact matching).
        let mut w = *mu;
        if self.needs_configuration() {
            let mut velocity_free = true;
            for j in 0..m {
                let x = &work.x[j];
                let point = &work.points[j];
                let p = SVector::<f64, D>::from_column_slice(&point.gradient()[2 * D..]);
                // The chart's terms from the point where it formed them, else from
                // the chart.
                let transport = &work.transports[j];
                if !with_jacobian {
                    let moved = match transport {
                        Some(t) => fixed_product(&t.to_start, &p),
                        None => chart.coadjoint_to_start(x, &p),
                    };
                    w += moved * d.weights[j];
                } else {
                    let (to_start, a) = match transport {
                        Some(t) => (t.to_start, t.differential),
                        None => chart.transport_and_differential(x),
                    };
                    w += to_start * p * d.weights[j];
                    // ∂q/∂x = Ad_{Φ⁻¹}ᵀ (H_ζx − C(p) A(x)), ∂q/∂v = Ad_{Φ⁻¹}ᵀ H_ζv, with
                    // C(p) η = ad_ηᵀ p (on SO(3), p̂).
                    let h_zx = SMatrix::<f64, D, D>::from_fn(|r, c| point.hessian(2 * D + r, c));
                    let h_zv =
                        SMatrix::<f64, D, D>::from_fn(|r, c| point.hessian(2 * D + r, D + c));
                    // Products inlined (`fixed_product`: nalgebra's, bit for bit).
                    let generator = <S::Group as ConfigurationGroup<D>>::coadjoint_generator(&p);
                    let dq_dx = fixed_product(&to_start, &(h_zx - fixed_product(&generator, &a)));
                    // `H_ζv = Aᵀ L_ξη` plus a force's `∂F/∂v`: zero but for a kinetic
                    // energy that depends on the configuration or a force that reads the
                    // velocity (damping), and then `∂q/∂v` is zero without the product.
                    // On SO(3) only: at `D = 6` the branch costs the matching's other
                    // products their vectorisation, which is worth more than the product
                    // it would skip.
                    let dq_dv = if D != 3 {
                        velocity_free = false;
                        fixed_product(&to_start, &h_zv)
                    } else if h_zv == SMatrix::<f64, D, D>::zeros() {
                        SMatrix::zeros()
                    } else {
                        velocity_free = false;
                        transported(&to_start, &h_zv)
                    };
                    work.dq
                        .col_as_slice_mut(2 * j)
                        .copy_from_slice(dq_dx.as_slice());
                    work.dq
                        .col_as_slice_mut(2 * j + 1)
                        .copy_from_slice(dq_dv.as_slice());
                }
            }
            work.dq_velocity_free = velocity_free;
        }
        let (a_n, phi_n) = (chart.left_differential(&xi_n), chart.to_group(&xi_n));
        let transport = fixed_product(&a_n.transpose(), &phi_n.adjoint().transpose());
        work.matching = MatchingTerms { w, transport };
        match self.settings.matching() {
            Matching::Exact => {
                let scale = Self::gradient_scale(work, n - 1).max((transport * w).amax());
                (transport * w - work.gradient[n - 1], scale)
            }
            Matching::Paper => {
                let a0 = chart.left_differential(&SVector::<f64, D>::zeros());
                let scale = Self::gradient_scale(work, 0).max((a0.transpose() * mu).amax());
                (a0.transpose() * mu + work.gradient[0], scale)
            }
        }
    }

    /// The matching rows of the Newton matrix (the last `D`), after the action Hessian of
    /// [`StepSolver::fill_jacobian`].
    pub(super) fn fill_matching_rows(&self, work: &mut WorkspaceOf<S, D>) {
        let d = self.d;
        let n = d.n;
        let last = D * (n - 2);
        let MatchingTerms { w, transport } = work.matching;
        match self.settings.matching() {
            Matching::Exact => {
                let map_jacobian = self.matching_map_jacobian(&work.xi[n - 1], &w);
                let configured = self.needs_configuration();
                if configured {
                    // ∂w/∂ξᵏ = Σ_j h b_j [∂q/∂x B_jk + ∂q/∂v D_jk] for every k ≥ 1: one
                    // product of the points' ∂q (by entries) with the weighted basis (the
                    // D × D products per (j, k) it replaces cost more than the rest of
                    // the matching rows).
                    // With every `∂q_j/∂v` zero their terms are skipped: each would add an
                    // exact zero to its sum, so the sums are the same bit for bit.
                    let rows = work.dw_by_entry.nrows();
                    let product = if work.dq_velocity_free {
                        super::product::replace_product_even
                    } else {
                        super::product::replace_product
                    };
                    product(
                        &mut work.dw_by_entry,
                        0..rows,
                        1..n,
                        &work.dq,
                        &d.weighted_basis,
                        1..n,
                    );
                    for (dw, column) in work.dw_dxi[1..].iter_mut().zip(1..n) {
                        dw.as_mut_slice()
                            .copy_from_slice(work.dw_by_entry.col_as_slice(column));
                    }
                }
                for k in 1..n {
                    let mut block = -self.hessian_block(work, n - 1, k);
                    if k == n - 1 {
                        block += map_jacobian;
                    }
                    if configured {
                        block += fixed_product(&transport, &work.dw_dxi[k]);
                    }
                    put_block(&mut work.jacobian, last, D * (k - 1), &block);
                }
            }
            Matching::Paper => {
                for k in 1..n {
                    let block = self.hessian_block(work, 0, k);
                    put_block(&mut work.jacobian, last, D * (k - 1), &block);
                }
            }
        }
    }

    /// Carries the matching's `w` through a step `δ` of the unknowns (`work.delta`, just
    /// added to `work.xi`) to first order, with the `∂w/∂ξ` of the last Newton matrix:
    /// `w += Σ_k ∂w/∂ξᵏ δᵏ`. Used after a last chord step from the rounding floor, where
    /// `|δ|` is itself at the floor and the neglected terms (`|δ|²`, and the matrix's
    /// staleness `r_f |δ|`) are far below rounding; a symmetry of `ℓ` that makes a
    /// component of `Ad_{g_k⁻¹}ᵀ w` independent of `ξ` keeps it, since every `∂w/∂ξᵏ` then
    /// has that component zero.
    pub(super) fn carry_matching(&self, work: &mut WorkspaceOf<S, D>) {
        if !self.needs_configuration() {
            return;
        }
        let mut w = work.matching.w;
        for (dw, delta) in work.dw_dxi[1..].iter().zip(work.delta.chunks_exact(D)) {
            w += dw * SVector::<f64, D>::from_column_slice(delta);
        }
        work.matching.w = w;
    }

    /// `∂/∂y [A(y)ᵀ Ad_{Φ(y)}ᵀ w]` at `y`: with `z = Ad_{Φ(y)}ᵀ w` and
    /// `Φ(y + t e_a) = Φ(y) exp(t A e_a + O(t²))`, `∂_a z = ad_{A e_a}ᵀ z = C(z) A e_a`,
    /// so the Jacobian is `∂(Aᵀz)/∂y` at fixed `z` plus `Aᵀ C(z) A`, from the chart's
    /// derivatives (closed form where the chart has them).
    pub(super) fn matching_map_jacobian(
        &self,
        y: &SVector<f64, D>,
        w: &SVector<f64, D>,
    ) -> SMatrix<f64, D, D> {
        let z = self.chart.to_group(y).adjoint().transpose() * w;
        self.chart.with_derivatives(y, false, |derivatives| {
            let a = derivatives.differential();
            derivatives.transpose_times(&z)
                + a.transpose() * <S::Group as ConfigurationGroup<D>>::coadjoint_generator(&z) * a
        })
    }

    /// [`StepSolver::matching_map_jacobian`] by dual numbers through the chart and the
    /// group's adjoint: the tests' reference.
    #[cfg(test)]
    pub(super) fn matching_map_jacobian_by_dual_numbers(
        &self,
        y: &SVector<f64, D>,
        w: &SVector<f64, D>,
    ) -> SMatrix<f64, D, D> {
        let chart = self.chart;
        let (_, jac) = num_dual::jacobian(
            |y: SVector<DualSVec64<D>, D>| {
                let w: SVector<DualSVec64<D>, D> = w.map(nalgebra::convert);
                let a = chart.left_differential(&y);
                let g = chart.to_group(&y);
                a.transpose() * (g.adjoint().transpose() * w)
            },
            y,
        );
        jac
    }

    /// The step's result at the unknowns in `work.xi`, from the last assembly's `w` (exact
    /// matching) or `∂S/∂ξⁿ` (the paper's).
    pub(super) fn outcome(
        &self,
        base: &Element<S, D>,
        work: &WorkspaceOf<S, D>,
        iterations: usize,
        factorizations: usize,
    ) -> StepOutcome<Element<S, D>, D> {
        let xi_n = work.xi[self.d.n - 1];
        let phi_n = self.chart.to_group(&xi_n);
        let momentum = match self.settings.matching() {
            // μ_{k+1} = A(ξⁿ)⁻ᵀ ∂S/∂ξⁿ equals Ad_{Φ(ξⁿ)}ᵀ w up to the matching residual.
            // Taken as Ad_{Φ(ξⁿ)}ᵀ w, the spatial momentum Ad_{g_{k+1}⁻¹}ᵀ μ_{k+1} is
            // Ad_{g_k⁻¹}ᵀ w to the rounding of two products: the conserved momenta (and
            // |μ|² on SO(3)) do not pick up the residual's floor every step, which over
            // millions of steps would add up to a drift far above rounding.
            Matching::Exact => phi_n.adjoint().transpose() * work.matching.w,
            Matching::Paper => {
                let a_inv = self
                    .chart
                    .left_differential_inverse(&xi_n)
                    .unwrap_or_else(|_| SMatrix::from_element(f64::NAN));
                a_inv.transpose() * work.gradient[self.d.n - 1]
            }
        };
        StepOutcome {
            configuration: base.compose(&phi_n),
            momentum,
            iterations,
            factorizations,
        }
    }
}

/// `Ad_{Φ⁻¹}ᵀ H_ζv`, out of line: the rare case of a nonzero `H_ζv`.
#[cold]
#[inline(never)]
fn transported<const D: usize>(
    to_start: &SMatrix<f64, D, D>,
    h_zv: &SMatrix<f64, D, D>,
) -> SMatrix<f64, D, D> {
    fixed_product(to_start, h_zv)
}

/// Writes a `D × D` block into the Newton matrix with its top-left entry at `(row, col)`.
fn put_block<const D: usize>(
    jac: &mut nalgebra::DMatrix<f64>,
    row: usize,
    col: usize,
    block: &SMatrix<f64, D, D>,
) {
    for r in 0..D {
        for c in 0..D {
            jac[(row + r, col + c)] = block[(r, c)];
        }
    }
}
