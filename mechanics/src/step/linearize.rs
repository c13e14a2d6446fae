//! The exact linearisation of a converged step, by the implicit function theorem.
//!
//! A step solves `F(Ξ; θ, μ_k, u) = 0` for its unknowns `Ξ = (ξ², …, ξⁿ)`, where the
//! start is perturbed as `g_k exp(θ)`, `μ_k` is the body momentum and `u` the control
//! input (held over the step). At the solution, `∂Ξ/∂P = −F_Ξ⁻¹ F_P` for
//! `P = (θ, μ_k, u)`: the Newton matrix `F_Ξ` formed and factored afresh at the converged
//! unknowns (never the chord iteration's kept factor, which is a few residuals old) — from
//! the points of the Newton loop's last assembly when the loop kept their Hessians
//! (`Workspace::converged_hessians`: an assembly at the rounding floor, at the accepted
//! unknowns or one chord step of at most a few ulps before them), else from an assembly
//! here — and `F_P` in closed form: the Gauss points' gradients move with `θ` through
//! their derivatives in `ζ` ([`StepSolver::point_mixed`]; three hyper-dual numbers per point
//! through the whole point are the tests' reference).
//!
//! With `ξⁿ` and `w` of the exact matching (module [`super::matching`]):
//! - `g_{k+1} exp(θ₊) = g_k exp(θ) Φ(ξⁿ + δξⁿ)` gives `θ₊ = Ad_{Φ(ξⁿ)⁻¹} θ + A(ξⁿ) δξⁿ`;
//! - `μ_{k+1} = Ad_{Φ(ξⁿ)}ᵀ w` gives `δμ₊ = Ad_{Φ(ξⁿ)}ᵀ δw + C(μ_{k+1}) A(ξⁿ) δξⁿ`, with
//!   `C(p)η = ad_ηᵀ p` and `δw = ∂w/∂P δP + Σ_k ∂w/∂ξᵏ δξᵏ`,
//!   `w = μ_k + Σ_j h b_j Ad_{Φ(x_j)⁻¹}ᵀ (p_j + F_j + u)`.
//!
//! The rows of `F_P`: an interior node's equation `Σ_j h b_j [φ_i ∂_x ℓ̃ + φ_i' ∂_v ℓ̃ +
//! φ_i A(x_j)ᵀ(F_j + u)]` gains `Σ_j h b_j [φ_i M^x_j + φ_i' M^v_j]` in `θ` and
//! `Σ_j h b_j φ_i A(x_j)ᵀ` in `u`; the matching equation `T w − ∂S/∂ξⁿ` (with
//! `T = A(ξⁿ)ᵀ Ad_{Φ(ξⁿ)}ᵀ`) gains `T ∂w/∂θ − Σ_j h b_j [φ_n M^x_j + φ_n' M^v_j]` in `θ`,
//! `T` in `μ_k` and `T Σ_j h b_j Ad_{Φ(x_j)⁻¹}ᵀ − Σ_j h b_j φ_n A(x_j)ᵀ` in `u`, where
//! `∂w/∂θ = Σ_j h b_j Ad_{Φ(x_j)⁻¹}ᵀ M^ζ_j`.

use super::assembly::WorkspaceOf;
use super::newton::{substitute, substitute_rows};
use super::points::StepForce;
use super::{Element, StepSolver};
use crate::error::MechanicsError;
use crate::group::{ConfigurationGroup, GroupChart, PointJet, StepGroup};
use crate::settings::Matching;
use crate::system::{ElementOf, GaussPoint, PointForce, System};
use lgsvi_lie::LieGroup;
use nalgebra::{DMatrix, RealField, SMatrix, SVector};
use std::marker::PhantomData;

/// The Jacobians of one step in momentum coordinates `(θ, δμ)` and the input `u`, as
/// `D × D` blocks (`row_column`), and the end momentum they were taken at.
#[derive(Debug, Clone)]
pub(crate) struct MomentumJacobians<const D: usize> {
    pub theta_theta: SMatrix<f64, D, D>,
    pub theta_mu: SMatrix<f64, D, D>,
    pub mu_theta: SMatrix<f64, D, D>,
    pub mu_mu: SMatrix<f64, D, D>,
    pub theta_u: SMatrix<f64, D, D>,
    pub mu_u: SMatrix<f64, D, D>,
    /// At each Gauss point `j`, the configuration's derivative `∂θ_j/∂(θ, μ_k, u)`, where
    /// the point's configuration moves as `g_j exp(θ_j)` (`θ_j = Ad_{Φ(x_j)⁻¹} θ +
    /// A(x_j) δx_j`, `δx_j = Σ_i φ_i(c_j h) δξⁱ`): three `D × D` blocks.
    pub points: Vec<[SMatrix<f64, D, D>; 3]>,
}

/// The input Jacobians of a step at one Gauss point `j`
/// ([`StepSolver::point_input_jacobians`]): the end state's `(θ, μ)` blocks and, at every
/// Gauss point `q`, the configuration's `∂θ_q/∂u_j`.
#[derive(Debug, Clone)]
pub(crate) struct PointInput<const D: usize> {
    pub theta: SMatrix<f64, D, D>,
    pub mu: SMatrix<f64, D, D>,
    pub configurations: Vec<SMatrix<f64, D, D>>,
}

/// The input Jacobians of a step at each Gauss point.
pub(crate) type PointInputJacobians<const D: usize> = Vec<PointInput<D>>;

/// The mixed derivatives of one Gauss point in `θ`: rows `x`, `v`, `ζ` of the point's
/// gradient (with the force's terms), columns `θ`.
#[derive(Debug, Clone, Copy)]
pub(super) struct PointMixed<const D: usize> {
    pub x: SMatrix<f64, D, D>,
    pub v: SMatrix<f64, D, D>,
    pub zeta: SMatrix<f64, D, D>,
}

/// A Gauss point's chart terms at `x`: `A(x)` and `B = Ad_{Φ(x)⁻¹}` (kept as `Bᵀ`, the
/// matching's transport, formed with `A(x)` from one evaluation of the chart's
/// coefficients), for both the point's `θ` derivatives and the input and matching columns.
pub(super) struct PointChart<E, const D: usize> {
    pub x: SVector<f64, D>,
    pub a: SMatrix<f64, D, D>,
    /// `Bᵀ = Ad_{Φ(x)⁻¹}ᵀ`.
    pub to_start: SMatrix<f64, D, D>,
    group: PhantomData<E>,
}

impl<E: LieGroup<Jacobian = SMatrix<f64, D, D>>, const D: usize> PointChart<E, D> {
    pub fn at<G, C>(chart: &C, x: &SVector<f64, D>) -> Self
    where
        G: ConfigurationGroup<D, Element<f64> = E>,
        C: GroupChart<G, D>,
    {
        let (to_start, a) = chart.transport_and_differential(x);
        Self {
            x: *x,
            a,
            to_start,
            group: PhantomData,
        }
    }
}

#[cfg(test)]
type Hyper<const D: usize> = num_dual::HyperDualSVec64<D, D>;

/// A system's `ℓ` replaced by its derivative in one of its parameters,
/// [`System::parameter_lagrangian`], with no force: a step's residual is linear
/// in `ℓ`, so this system's residual at the converged unknowns, with `μ_k = 0`, is the
/// step's residual's derivative in that parameter (and its `w` the explicit part of the
/// matching's; `docs/notes/linearization.md` §8). Its Gauss points go through the generic
/// dual-number chain rule.
pub(crate) struct ParameterDerivative<'a, S> {
    pub system: &'a S,
    pub index: usize,
}

impl<S: System<D>, const D: usize> System<D> for ParameterDerivative<'_, S> {
    type Group = S::Group;

    fn lagrangian<T: RealField + Copy>(
        &self,
        time: f64,
        configuration: &ElementOf<S, D, T>,
        velocity: &SVector<T, D>,
    ) -> T {
        self.system
            .parameter_lagrangian(self.index, time, configuration, velocity)
    }
    fn is_left_invariant(&self) -> bool {
        self.system.is_left_invariant()
    }
    fn point_derivatives<C: GroupChart<Self::Group, D>>(
        &self,
        chart: &C,
        point: &GaussPoint<'_, Self::Group, D>,
        out: &mut <Self::Group as StepGroup<D>>::Jet,
    ) -> bool {
        self.system
            .parameter_point_derivatives(self.index, chart, point, out)
    }
}

/// A step's derivatives in the system's parameters in momentum coordinates: rows `θ₊`
/// and `δμ₊`, one column a parameter (named in `names`), at the start's body momentum
/// held.
pub(crate) struct ParameterJacobians {
    pub names: Vec<String>,
    pub theta: DMatrix<f64>,
    pub mu: DMatrix<f64>,
}

/// The converged step's end terms that every column of the linearisation reads:
/// `Φ(ξⁿ)`, `A(ξⁿ)`, `Ad_{Φ(ξⁿ)}` and `C(μ₊)`.
struct EndMap<E, const D: usize> {
    phi_n: E,
    a_n: SMatrix<f64, D, D>,
    ad_n: SMatrix<f64, D, D>,
    c_end: SMatrix<f64, D, D>,
}

impl<E: LieGroup<Jacobian = SMatrix<f64, D, D>>, const D: usize> EndMap<E, D> {
    /// From the converged unknowns and the matching's `w` in `work`.
    fn at<S, C>(stepper: &StepSolver<'_, S, C, D>, work: &WorkspaceOf<S, D>) -> Self
    where
        S: System<D>,
        S::Group: ConfigurationGroup<D, Element<f64> = E>,
        C: GroupChart<S::Group, D>,
    {
        let xi_n = work.xi[stepper.d.n - 1];
        let phi_n = stepper.chart.to_group(&xi_n);
        let a_n = stepper.chart.left_differential(&xi_n);
        let ad_n = phi_n.adjoint();
        let end_momentum = ad_n.transpose() * work.matching.w;
        let c_end = <S::Group as ConfigurationGroup<D>>::coadjoint_generator(&end_momentum);
        Self {
            phi_n,
            a_n,
            ad_n,
            c_end,
        }
    }

    /// The end state's perturbation from one column of `∂Ξ/∂P` (`delta(k)`: node
    /// `k + 1`'s part) and that column's explicit `∂w` (module documentation):
    /// `(A(ξⁿ) δξⁿ, Ad_{Φ(ξⁿ)}ᵀ δw + C(μ₊) A(ξⁿ) δξⁿ)` with
    /// `δw = explicit + Σ_k ∂w/∂ξᵏ δξᵏ` (the sum only where the matching has
    /// configuration terms). A `θ` column adds `Ad_{Φ(ξⁿ)⁻¹}` to the first part itself.
    fn perturbation<S, C>(
        &self,
        stepper: &StepSolver<'_, S, C, D>,
        work: &WorkspaceOf<S, D>,
        explicit: SVector<f64, D>,
        delta: impl Fn(usize) -> SVector<f64, D>,
    ) -> (SVector<f64, D>, SVector<f64, D>)
    where
        S: System<D>,
        C: GroupChart<S::Group, D>,
    {
        let n = stepper.d.n;
        let mut dw = explicit;
        if stepper.needs_configuration() {
            for k in 0..n - 1 {
                dw += work.dw_dxi[k + 1] * delta(k);
            }
        }
        let theta = self.a_n * delta(n - 2);
        (theta, self.ad_n.transpose() * dw + self.c_end * theta)
    }
}

impl<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> StepSolver<'_, S, C, D> {
    /// The linearisation of the step from `(base, mu)` whose converged unknowns are in
    /// `work.xi` (module documentation). Overwrites the workspace's Newton matrix (and its
    /// assembly, when the Newton loop did not keep one with Hessians).
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for the paper's matching (not the derivative of
    /// a discrete Lagrangian: its step has no variational linearisation to offer);
    /// [`MechanicsError::OutsideChart`] if the unknowns left the chart;
    /// [`MechanicsError::SingularJacobian`] if the Newton matrix is singular there.
    pub(crate) fn linearize(
        &self,
        base: &Element<S, D>,
        mu: &SVector<f64, D>,
        work: &mut WorkspaceOf<S, D>,
        step: usize,
    ) -> Result<MomentumJacobians<D>, MechanicsError> {
        if self.settings.matching() == Matching::Paper {
            return Err(MechanicsError::InvalidSetting {
                name: "matching",
                value: "paper".into(),
                reason: "the paper's momentum matching is not the derivative of a discrete \
                         Lagrangian, so its step has no variational linearisation: use the exact \
                         matching",
            });
        }
        let d = self.d;
        let (n, m) = (d.n, d.m);
        let unknowns = D * (n - 1);
        // The exact Newton matrix at the converged unknowns, factored afresh: from the
        // Newton loop's last assembly when it kept its Hessians at the rounding floor (the
        // converged step's points, to rounding), else assembled here.
        if !work.converged_hessians {
            self.check_domain(work, step, self.time)?;
            self.assemble(base, mu, work, true);
        }
        self.fill_jacobian(work);
        work.factor();
        // F_P, columns θ (0..D), μ_k (D..2D), u (2D..3D), column-major. The θ and u blocks
        // of every node's rows, `Σ_j h b_j [φ_i M^x_j + φ_i' M^v_j]` and
        // `Σ_j h b_j φ_i A(x_j)ᵀ`, are one product of the points' terms with the weighted
        // basis (`docs/notes/linearization.md` §4).
        let dd = D * D;
        let mut dw_theta = SMatrix::<f64, D, D>::zeros();
        let mut dw_u = SMatrix::<f64, D, D>::zeros();
        let moves = self.moves_with_start();
        for j in 0..m {
            let point = PointChart::at(self.chart, &work.x[j]);
            let weight = d.weights[j];
            // The θ terms: zero where no point's gradient moves with the start.
            if moves {
                let mixed = self.point_mixed(base, j, &point, &work.v[j], &work.points[j]);
                work.point_columns.col_as_slice_mut(2 * j)[..dd]
                    .copy_from_slice(mixed.x.as_slice());
                work.point_columns.col_as_slice_mut(2 * j + 1)[..dd]
                    .copy_from_slice(mixed.v.as_slice());
                dw_theta += point.to_start * mixed.zeta * weight;
            }
            work.point_columns.col_as_slice_mut(2 * j)[dd..]
                .copy_from_slice(point.a.transpose().as_slice());
            dw_u += point.to_start * weight;
        }
        let first_row = if moves { 0 } else { dd };
        super::product::replace_product(
            &mut work.node_blocks,
            first_row..2 * dd,
            1..n,
            &work.point_columns,
            &d.weighted_basis,
            1..n,
        );
        let block = |i: usize, half: usize| {
            SMatrix::<f64, D, D>::from_column_slice(
                &work.node_blocks.col_as_slice(i)[half * dd..(half + 1) * dd],
            )
        };
        let f_p = &mut work.f_p;
        f_p.fill(0.0);
        for i in 1..n - 1 {
            if moves {
                add_rows(f_p, unknowns, D * (i - 1), 0, &block(i, 0));
            }
            add_rows(f_p, unknowns, D * (i - 1), 2 * D, &block(i, 1));
        }
        let last_theta = if moves {
            block(n - 1, 0)
        } else {
            SMatrix::zeros()
        };
        let last_u = block(n - 1, 1);
        let transport = work.matching.transport;
        let last = D * (n - 2);
        add_rows(f_p, unknowns, last, 0, &(transport * dw_theta - last_theta));
        add_rows(f_p, unknowns, last, D, &transport);
        add_rows(f_p, unknowns, last, 2 * D, &(transport * dw_u - last_u));
        // ∂Ξ/∂P = −F_Ξ⁻¹ F_P with the fresh factors, the 3D columns solved together (one
        // pass over the factors for all of them).
        let solution = &mut work.sensitivity;
        for (row, &p) in solution.iter_mut().zip(&work.perm) {
            for (family, part) in row.iter_mut().enumerate() {
                for (c, e) in part.iter_mut().enumerate() {
                    *e = -f_p[(D * family + c) * unknowns + p];
                }
            }
        }
        // Where no point moves with the start, the θ columns of F_P are zero, and so are
        // their solutions (left as the zeros copied in).
        substitute_rows(&work.jacobian, solution, !moves);
        if !solution.iter().flatten().flatten().all(|e| e.is_finite()) {
            return Err(MechanicsError::SingularJacobian {
                step,
                time: self.time,
                advice: self.chart.advice(),
            });
        }
        let end = EndMap::at(self, work);
        let ad_n_inverse = end.phi_n.inverse().adjoint();
        let mut blocks = [[SMatrix::<f64, D, D>::zeros(); 3]; 2];
        let solution = &work.sensitivity;
        for p in 0..3 * D {
            let (family, c) = (p / D, p % D);
            let explicit: SVector<f64, D> = match family {
                0 => dw_theta.column(c).into_owned(),
                1 => SMatrix::<f64, D, D>::identity().column(c).into_owned(),
                _ => dw_u.column(c).into_owned(),
            };
            // Node k + 1's part of column `(family, c)`.
            let delta =
                |k: usize| SVector::<f64, D>::from_fn(|r, _| solution[D * k + r][family][c]);
            let (mut theta, momentum) = end.perturbation(self, work, explicit, delta);
            if family == 0 {
                theta += ad_n_inverse.column(c);
            }
            blocks[0][family].set_column(c, &theta);
            blocks[1][family].set_column(c, &momentum);
        }
        let points = (0..m)
            .map(|j| {
                let point = PointChart::at(self.chart, &work.x[j]);
                let ad_inverse = point.to_start.transpose();
                let mut columns = [SMatrix::<f64, D, D>::zeros(); 3];
                for p in 0..3 * D {
                    let (family, c) = (p / D, p % D);
                    let delta = |k: usize| {
                        SVector::<f64, D>::from_fn(|r, _| solution[D * k + r][family][c])
                    };
                    let mut theta = self.point_motion(j, &point.a, delta);
                    if family == 0 {
                        theta += ad_inverse.column(c);
                    }
                    columns[family].set_column(c, &theta);
                }
                columns
            })
            .collect();
        Ok(MomentumJacobians {
            points,
            theta_theta: blocks[0][0],
            theta_mu: blocks[0][1],
            mu_theta: blocks[1][0],
            mu_mu: blocks[1][1],
            theta_u: blocks[0][2],
            mu_u: blocks[1][2],
        })
    }

    /// `A(x_j) δx_j` at Gauss point `j` (`a` its `A(x_j)`) for one column of `∂Ξ/∂P`
    /// (`delta(k)`: node `k + 1`'s part; the first node is the start, fixed):
    /// `δx_j = Σ_i φ_i(c_j h) δξⁱ`.
    fn point_motion(
        &self,
        j: usize,
        a: &SMatrix<f64, D, D>,
        delta: impl Fn(usize) -> SVector<f64, D>,
    ) -> SVector<f64, D> {
        let values = self.d.values_at(j);
        let mut dx = SVector::<f64, D>::zeros();
        for k in 0..self.d.n - 1 {
            dx += delta(k) * values[k + 1];
        }
        a * dx
    }

    /// `solution = −F_Ξ⁻¹ column` with the fresh factors in `work` (the unknowns'
    /// derivative in a parameter whose residual derivative is `column`).
    ///
    /// # Errors
    /// [`MechanicsError::SingularJacobian`] if the solution is not finite.
    fn solve_column(
        &self,
        work: &WorkspaceOf<S, D>,
        column: &[f64],
        solution: &mut [f64],
        step: usize,
    ) -> Result<(), MechanicsError> {
        for (entry, &p) in solution.iter_mut().zip(&work.perm) {
            *entry = -column[p];
        }
        substitute(&work.jacobian, solution);
        if solution.iter().all(|e| e.is_finite()) {
            Ok(())
        } else {
            Err(MechanicsError::SingularJacobian {
                step,
                time: self.time,
                advice: self.chart.advice(),
            })
        }
    }

    /// The step's derivatives in the input at each Gauss point, after
    /// [`StepSolver::linearize`] of the same step (its fresh factors, `∂w/∂ξ` and matching
    /// terms in `work`): for point `j`, the input columns of the module documentation with
    /// the sums over the points reduced to point `j`'s term — node `i`'s rows
    /// `h b_j φ_i(c_j h) A(x_j)ᵀ`, the matching rows `T Ad_{Φ(x_j)⁻¹}ᵀ h b_j −
    /// h b_j φ_n(c_j h) A(x_j)ᵀ`, and `w`'s explicit part `h b_j Ad_{Φ(x_j)⁻¹}ᵀ`. Their sum
    /// over the points is the constant input's `(θ, μ)` columns. Per point, one `(θ, μ)`
    /// pair of `D × D` blocks and, at every Gauss point `q`, the configuration's
    /// `∂θ_q/∂u_j` ([`PointInput`]).
    ///
    /// # Errors
    /// [`MechanicsError::SingularJacobian`] if a solution is not finite.
    pub(crate) fn point_input_jacobians(
        &self,
        work: &WorkspaceOf<S, D>,
        step: usize,
    ) -> Result<PointInputJacobians<D>, MechanicsError> {
        let d = self.d;
        let (n, m) = (d.n, d.m);
        let unknowns = D * (n - 1);
        let end = EndMap::at(self, work);
        let transport = work.matching.transport;
        let mut out = Vec::with_capacity(m);
        let mut column = vec![0.0; unknowns];
        let mut solution = vec![0.0; unknowns];
        let differentials: Vec<SMatrix<f64, D, D>> = (0..m)
            .map(|q| PointChart::<Element<S, D>, D>::at(self.chart, &work.x[q]).a)
            .collect();
        for j in 0..m {
            let point = PointChart::at(self.chart, &work.x[j]);
            let a_t = point.a.transpose();
            let explicit = point.to_start * d.weights[j];
            let mut theta = SMatrix::<f64, D, D>::zeros();
            let mut mu = SMatrix::<f64, D, D>::zeros();
            let mut configurations = vec![SMatrix::<f64, D, D>::zeros(); m];
            for c in 0..D {
                column.fill(0.0);
                for i in 1..n - 1 {
                    let weight = d.weighted_basis[(2 * j, i)];
                    for r in 0..D {
                        column[D * (i - 1) + r] = a_t[(r, c)] * weight;
                    }
                }
                let last = D * (n - 2);
                let weight = d.weighted_basis[(2 * j, n - 1)];
                let matching = transport * explicit;
                for r in 0..D {
                    column[last + r] = matching[(r, c)] - a_t[(r, c)] * weight;
                }
                self.solve_column(work, &column, &mut solution, step)?;
                let delta =
                    |k: usize| SVector::<f64, D>::from_column_slice(&solution[D * k..D * (k + 1)]);
                let (t, p) = end.perturbation(self, work, explicit.column(c).into_owned(), delta);
                theta.set_column(c, &t);
                mu.set_column(c, &p);
                for (q, configuration) in configurations.iter_mut().enumerate() {
                    configuration.set_column(c, &self.point_motion(q, &differentials[q], delta));
                }
            }
            out.push(PointInput {
                theta,
                mu,
                configurations,
            });
        }
        Ok(out)
    }

    /// The step's derivatives in the system's parameters ([`ParameterJacobians`]), after
    /// [`StepSolver::linearize`] of the same step: its fresh factors of the Newton matrix at
    /// the converged unknowns, its `∂w/∂ξ` and matching terms in `work` (unchanged here).
    /// Each parameter costs one gradient-only assembly of [`ParameterDerivative`] in
    /// `scratch` and one substitution: `∂Ξ/∂p_k = −F_Ξ⁻¹ F[∂ℓ/∂p_k]`, then the end state as
    /// for the other columns, with `w`'s explicit part from that assembly.
    ///
    /// # Errors
    /// [`MechanicsError::SingularJacobian`] if a solution is not finite.
    pub(crate) fn parameter_jacobians(
        &self,
        base: &Element<S, D>,
        work: &WorkspaceOf<S, D>,
        scratch: &mut WorkspaceOf<S, D>,
        step: usize,
    ) -> Result<ParameterJacobians, MechanicsError> {
        let unknowns = D * (self.d.n - 1);
        let names = self.system.parameter_names();
        let count = names.len();
        let mut jacobians = ParameterJacobians {
            names,
            theta: DMatrix::zeros(D, count),
            mu: DMatrix::zeros(D, count),
        };
        let end = EndMap::at(self, work);
        let zero = SVector::<f64, D>::zeros();
        let mut solution = vec![0.0; unknowns];
        for index in 0..count {
            let derivative = ParameterDerivative {
                system: self.system,
                index,
            };
            let stepper = StepSolver {
                system: &derivative,
                chart: self.chart,
                settings: self.settings,
                d: self.d,
                time: self.time,
                forcing: None,
                point_inputs: None,
            };
            scratch.xi.copy_from_slice(&work.xi);
            stepper.assemble(base, &zero, scratch, false);
            self.solve_column(work, &scratch.residual, &mut solution, step)?;
            let delta =
                |k: usize| SVector::<f64, D>::from_column_slice(&solution[D * k..D * (k + 1)]);
            let (theta, momentum) = end.perturbation(self, work, scratch.matching.w, delta);
            jacobians.theta.set_column(index, &theta);
            jacobians.mu.set_column(index, &momentum);
        }
        Ok(jacobians)
    }

    /// Whether any Gauss point's gradient moves with `θ`: `ℓ` depends on the
    /// configuration, or the system's force does.
    fn moves_with_start(&self) -> bool {
        !self.system.is_left_invariant()
            || (self.system.is_forced() && self.system.force_depends_on_configuration())
    }

    /// Point `j`'s mixed derivatives in `θ`, from its derivatives in `(x, v, ζ)`. With
    /// `B = Ad_{Φ(x)⁻¹}`, the start's perturbation is `g_k exp(θ) Φ(x) = g_k Φ(x) exp(Bθ)`,
    /// so `ℓ̃` at `θ` is `f(x, v, B(x)θ)` with `f(x, v, η) = ℓ(t, g_k Φ(x) exp(η), A(x) v)`:
    /// - `x` rows: `H_xζ B + Aᵀ C(p) B` (the second term from `∂_x B = −ad_{A·} B`);
    /// - `v` rows: `H_vζ B`;
    /// - `ζ` rows: `(H_ζζ + ½ C(p)) B` (`exp(Bθ) exp(ζ) = exp(Bθ + ζ + ½ ad_{Bθ} ζ + …)`),
    ///
    /// with `p = ∂f/∂η` and `C(p)η = ad_ηᵀ p`; a force `F(t, g, ξ)` adds `Aᵀ F_η B` to the
    /// `x` rows and `F_η B` to the `ζ` rows. `jet` holds the point's derivatives with
    /// their `ζ` rows and Hessian (as the assembly of a step with the exact matching
    /// leaves them); with `self.forcing`, its `ζ` gradient includes the force, which is
    /// taken off again (the force never enters the `ζ` columns read here).
    pub(super) fn point_mixed(
        &self,
        base: &Element<S, D>,
        j: usize,
        point: &PointChart<Element<S, D>, D>,
        v: &SVector<f64, D>,
        jet: &<S::Group as StepGroup<D>>::Jet,
    ) -> PointMixed<D> {
        let time = self.time + self.d.times[j];
        let system = self.system;
        let (a, b) = (point.a, point.to_start.transpose());
        let configured_force = system.is_forced() && system.force_depends_on_configuration();
        let at = (self.forcing.is_some() || configured_force)
            .then(|| base.compose(&self.chart.to_group(&point.x)));
        let force = self
            .input_at(j)
            .zip(at.as_ref())
            .map(|(input, at)| StepForce::new(system, time, &input).jet(at, &(a * v)));
        let mut mixed = PointMixed {
            x: SMatrix::zeros(),
            v: SMatrix::zeros(),
            zeta: SMatrix::zeros(),
        };
        if !system.is_left_invariant() {
            let block =
                |r0: usize| SMatrix::<f64, D, D>::from_fn(|r, c| jet.hessian(r0 + r, 2 * D + c));
            let mut p = SVector::<f64, D>::from_column_slice(&jet.gradient()[2 * D..]);
            if let Some(force) = &force {
                p -= force.value;
            }
            let c_p = <S::Group as ConfigurationGroup<D>>::coadjoint_generator(&p);
            mixed.x = (block(0) + a.transpose() * c_p) * b;
            mixed.v = block(D) * b;
            mixed.zeta = (block(2 * D) + c_p * 0.5) * b;
        }
        if let (true, Some(at)) = (configured_force, &at) {
            let f_eta = match &force {
                Some(force) => force.configuration,
                None => system.force_jet(time, at, &(a * v)).configuration,
            } * b;
            mixed.x += a.transpose() * f_eta;
            mixed.zeta += f_eta;
        }
        mixed
    }

    /// [`StepSolver::point_mixed`] by three hyper-dual evaluations through the whole point
    /// (first variables `x`, `v`, `ζ` in turn, second variables `θ`): the tests'
    /// independent reference.
    #[cfg(test)]
    pub(super) fn point_mixed_by_dual_numbers(
        &self,
        base: &Element<S, D>,
        j: usize,
        x: &SVector<f64, D>,
        v: &SVector<f64, D>,
    ) -> PointMixed<D> {
        let time = self.time + self.d.times[j];
        let (system, chart) = (self.system, self.chart);
        let a = chart.left_differential(x);
        let zero = SVector::<f64, D>::zeros();
        let block = |which: usize| {
            let (_, _, _, mixed) = num_dual::partial_hessian(
                |(y, theta): (SVector<Hyper<D>, D>, SVector<Hyper<D>, D>)| {
                    let x0: SVector<Hyper<D>, D> = x.map(nalgebra::convert);
                    let v0: SVector<Hyper<D>, D> = v.map(nalgebra::convert);
                    let (mut xs, mut vs, mut zeta) = (x0, v0, SVector::<Hyper<D>, D>::zeros());
                    match which {
                        0 => xs += y,
                        1 => vs += y,
                        _ => zeta = y,
                    }
                    let start = <S::Group as ConfigurationGroup<D>>::lift::<Hyper<D>>(base)
                        .compose(&<S::Group as ConfigurationGroup<D>>::exp(&theta));
                    let g = start
                        .compose(&chart.to_group(&xs))
                        .compose(&<S::Group as ConfigurationGroup<D>>::exp(&zeta));
                    let omega = chart.left_differential(&xs) * vs;
                    let mut value = system.lagrangian(time, &g, &omega);
                    if system.is_forced() && which != 1 {
                        // The virtual work of the force at the point itself (its value
                        // moves with θ only): F·(A(x)δx) or F·ζ.
                        let at = start.compose(&chart.to_group(&x0));
                        let force = system.force(time, &at, &(chart.left_differential(&x0) * v0));
                        let displacement = if which == 0 {
                            a.map(nalgebra::convert::<f64, Hyper<D>>) * y
                        } else {
                            y
                        };
                        value += force.dot(&displacement);
                    }
                    value
                },
                (&zero, &zero),
            );
            mixed
        };
        PointMixed {
            x: block(0),
            v: block(1),
            zeta: block(2),
        }
    }
}

/// Adds a `D × D` block to rows `row..row + D`, columns `col..col + D` of a column-major
/// matrix with `rows` rows.
fn add_rows<const D: usize>(
    matrix: &mut [f64],
    rows: usize,
    row: usize,
    col: usize,
    block: &SMatrix<f64, D, D>,
) {
    for c in 0..D {
        for r in 0..D {
            matrix[(col + c) * rows + row + r] += block[(r, c)];
        }
    }
}
