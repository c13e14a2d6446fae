//! The residual of a step's equations and their exact Newton matrix, from the Gauss
//! points' derivatives.
//!
//! `∂S/∂ξⁱ = Σ_j h b_j [φ_i(c_j h) ∂ℓ̃/∂x + φ_i'(c_j h) ∂ℓ̃/∂v]_j`, and
//! `∂²S/∂ξⁱ∂ξᵏ = Σ_j h b_j [φ_i φ_k H_xx + φ_i φ_k' H_xv + φ_i' φ_k H_vx + φ_i' φ_k' H_vv]_j`,
//! formed for all `D` components at once as the basis times the points' Hessian entries
//! (`D·D(n−1) × 2m`) times the weighted basis (`2m × n`): one dense product instead of
//! `n²m` small block sums ([`StepSolver::fill_jacobian`] says how its rows are laid out).

use super::newton::carry::Carry;
use super::points::{point_derivatives, EllTilde, StepForce};
use super::tables::Discretisation;
use super::{Element, MatchingTerms, StepSolver};
use crate::error::MechanicsError;
use crate::group::{GroupChart, PointJet, StepGroup};
use crate::point::{ForceAtPoint, GaussPoints, PointTransport};
use crate::settings::{Matching, NewtonJacobian};
use crate::system::{PointForce, System};
use faer::Mat;
use nalgebra::{DMatrix, SMatrix, SVector};

/// Preallocated buffers of the Newton iteration: nothing is allocated per step.
pub(crate) struct Workspace<J, const D: usize> {
    /// Unknowns `ξ², …, ξⁿ` (with `ξ¹ = 0` at index 0): `n` vectors.
    pub xi: Vec<SVector<f64, D>>,
    /// The last accepted iterate, for the line search.
    pub(super) xi_accepted: Vec<SVector<f64, D>>,
    pub(super) points: Vec<J>,
    /// The chart's `Ad_{Φ(x_j)⁻¹}ᵀ` and `A(x_j)` where the last assembly's points handed
    /// them back ([`crate::System::point_derivatives_and_transport`]), for the
    /// matching.
    pub(super) transports: Vec<Option<PointTransport<D>>>,
    /// The force's power `F·ξ` at each point in the last assembly (NaN unforced): the
    /// step's work `Σ w_j F_j·ξ_j` without evaluating the force again.
    pub(crate) power: Vec<f64>,
    /// Exact matching with configuration terms: `∂q_j/∂x`, `∂q_j/∂v` per point,
    /// `q_j = Ad_{Φ(x_j)⁻¹}ᵀ p_j` (computed once per assembly, used by every column of the
    /// matching rows).
    /// Stored as the columns of one matrix (`D² × 2m`: column `2j` the entries of
    /// `∂q_j/∂x`, column `2j + 1` those of `∂q_j/∂v`, each `D × D` matrix column-major),
    /// so that `∂w/∂ξᵏ` for every `k` is one product with the weighted basis.
    pub(super) dq: Mat<f64>,
    /// Whether every `∂q_j/∂v` in `dq` is zero (then the product skips them).
    pub(super) dq_velocity_free: bool,
    /// That product: `D² × n`, column `k ≥ 1` the entries of `∂w/∂ξᵏ` (column 0 unused).
    pub(super) dw_by_entry: Mat<f64>,
    /// `∂w/∂ξᵏ` (index `k`, `k ≥ 1`) from the last Newton matrix with configuration
    /// terms: carries `w` through a last chord step without another assembly.
    pub(super) dw_dxi: Vec<SMatrix<f64, D, D>>,
    pub(super) x: Vec<SVector<f64, D>>,
    pub(super) v: Vec<SVector<f64, D>>,
    /// The matching's `w` and `A(ξⁿ)ᵀ Ad_{Φ(ξⁿ)}ᵀ`, from the last assembly.
    pub(super) matching: MatchingTerms<D>,
    /// The basis times the points' Hessian entries (`D·D(n−1) × 2m`, columns `2j`,
    /// `2j + 1` for `x`, `v`), and `∂²S/∂ξᵏ_c ∂ξⁱ_r` (`D·D(n−1) × n`) = that times
    /// `weighted_basis`, laid out by [`StepSolver::fill_jacobian`]: with the exact matching
    /// row `D(n−1)c + D(i−1) + r`, column `k`; with the paper's, row
    /// `D(n−1)r + D(k−1) + c`, column `i`.
    hessian_times_basis: Mat<f64>,
    pub(super) action_hessian: Mat<f64>,
    pub(super) gradient: Vec<SVector<f64, D>>,
    /// The same by components: `D` rows of `n` (row `c`: component `c` at every node),
    /// as the assembly accumulates it.
    gradient_by_component: Vec<f64>,
    /// The points' `x` and `v` gradients, `2D` a point, for that accumulation.
    point_gradients: Vec<f64>,
    gradient_scale: Vec<f64>,
    pub(super) residual: Vec<f64>,
    trial: Vec<f64>,
    /// The Newton matrix, then its LU factors ([`super::lu`]): contiguous column-major.
    pub(super) jacobian: DMatrix<f64>,
    /// The Newton (or chord) step `−J⁻¹F`, kept for the backtracking.
    pub(super) delta: Vec<f64>,
    pub(super) perm: Vec<usize>,
    /// A linearisation's `F_P` (`D(n−1) × 3D`, column-major: columns `θ`, `μ_k`, `u`),
    /// and the permuted `−F_P` by rows (row `r`: entry `r` of the `θ`, `μ_k` and `u`
    /// columns), solved in place for `∂Ξ/∂P`.
    pub(super) f_p: Vec<f64>,
    /// A linearisation's point terms (`2D² × 2m`): column `2j` the entries of point `j`'s
    /// `M^x` then of `A(x_j)ᵀ`, column `2j + 1` those of `M^v` then zeros (column-major
    /// `D × D` matrices), so that `F_P`'s `θ` and `u` blocks at every node are one product
    /// with the weighted basis, into `node_blocks` (`2D² × n`, column `i` node `i`'s).
    pub(super) point_columns: Mat<f64>,
    pub(super) node_blocks: Mat<f64>,
    pub(super) sensitivity: Vec<[SVector<f64, D>; 3]>,
    /// `(‖F‖∞, scale)` of an assembly (with Hessians for the exact Jacobian) at the
    /// current `xi`, made by [`StepSolver::relative_residual`]: the Newton loop's first
    /// assembly, saved.
    pub(super) guess_assembled: Option<(f64, f64)>,
    /// Asked for by a caller that linearises the step it solves
    /// ([`StepSolver::linearize`]): the assembly the Newton loop expects to be its last then
    /// carries the points' Hessians, so that the linearisation forms its Newton matrix
    /// from it instead of assembling the converged step once more.
    pub(crate) keep_converged_hessians: bool,
    /// Whether the points hold Hessians from an assembly at the rounding floor of the
    /// last solve (set by the Newton loop as it accepts the step, cleared by every
    /// assembly): the converged step's, to rounding, for [`StepSolver::linearize`].
    pub(super) converged_hessians: bool,
    /// Whether `jacobian` holds an earlier solve's factors that the next step may start
    /// from, and the reuse policy's waits ([`super::newton::carry`]).
    pub(super) carry: Carry,
    /// The unknowns at which `jacobian` was last factored.
    factored_xi: Vec<SVector<f64, D>>,
    /// The run's factors, set aside while a linearisation at the state solves its own
    /// step ([`Workspace::park_factors`]).
    parked: Option<Box<Factors<D>>>,
}

/// A factored Newton matrix and what a later step reads with it: the pivots, the
/// unknowns it was formed at, the matching's `∂w/∂ξᵏ` from the same matrix, the reuse
/// policy's state.
struct Factors<const D: usize> {
    jacobian: DMatrix<f64>,
    perm: Vec<usize>,
    xi: Vec<SVector<f64, D>>,
    dw_dxi: Vec<SMatrix<f64, D, D>>,
    carry: Carry,
}

impl<J: PointJet, const D: usize> Workspace<J, D> {
    pub fn new(d: &Discretisation) -> Self {
        let unknowns = D * (d.n - 1);
        Self {
            xi: vec![SVector::zeros(); d.n],
            xi_accepted: vec![SVector::zeros(); d.n],
            points: vec![J::zeros(); d.m],
            transports: vec![None; d.m],
            power: vec![f64::NAN; d.m],
            dq: Mat::zeros(D * D, 2 * d.m),
            dq_velocity_free: false,
            dw_by_entry: Mat::zeros(D * D, d.n),
            dw_dxi: vec![SMatrix::zeros(); d.n],
            x: vec![SVector::zeros(); d.m],
            v: vec![SVector::zeros(); d.m],
            matching: MatchingTerms::default(),
            hessian_times_basis: Mat::zeros(D * unknowns, 2 * d.m),
            action_hessian: Mat::zeros(D * unknowns, d.n),
            gradient: vec![SVector::zeros(); d.n],
            gradient_by_component: vec![0.0; D * d.n],
            point_gradients: vec![0.0; 2 * D * d.m],
            gradient_scale: vec![0.0; d.n],
            residual: vec![0.0; unknowns],
            trial: vec![0.0; unknowns],
            jacobian: DMatrix::zeros(unknowns, unknowns),
            delta: vec![0.0; unknowns],
            perm: vec![0; unknowns],
            f_p: vec![0.0; unknowns * 3 * D],
            point_columns: Mat::zeros(2 * D * D, 2 * d.m),
            node_blocks: Mat::zeros(2 * D * D, d.n),
            sensitivity: vec![[SVector::zeros(); 3]; unknowns],
            guess_assembled: None,
            keep_converged_hessians: false,
            converged_hessians: false,
            carry: Carry::default(),
            factored_xi: vec![SVector::zeros(); d.n],
            parked: None,
        }
    }

    /// Forgets the assembly at the guess: call after changing `xi` from outside the solve.
    pub fn guess_changed(&mut self) {
        self.guess_assembled = None;
    }

    /// The largest entry of the difference between the unknowns and those at which the
    /// Newton matrix was last factored.
    pub(super) fn drift(&self) -> f64 {
        self.xi
            .iter()
            .zip(&self.factored_xi)
            .fold(0.0, |m, (a, b)| m.max((a - b).amax()))
    }

    /// Sets the run's factors aside (the first time, buffers of the same sizes are made
    /// for the work in between), so that a solve in between starts without them and
    /// [`Workspace::unpark_factors`] gives them back unchanged.
    pub(crate) fn park_factors(&mut self) {
        let (unknowns, n) = (self.perm.len(), self.factored_xi.len());
        self.parked.get_or_insert_with(|| {
            Box::new(Factors {
                jacobian: DMatrix::zeros(unknowns, unknowns),
                perm: vec![0; unknowns],
                xi: vec![SVector::zeros(); n],
                dw_dxi: vec![SMatrix::zeros(); n],
                carry: Carry::default(),
            })
        });
        self.swap_parked();
        self.carry.forget();
    }

    /// Takes back the factors [`Workspace::park_factors`] set aside.
    pub(crate) fn unpark_factors(&mut self) {
        self.swap_parked();
    }

    fn swap_parked(&mut self) {
        if let Some(parked) = self.parked.as_deref_mut() {
            std::mem::swap(&mut self.jacobian, &mut parked.jacobian);
            std::mem::swap(&mut self.perm, &mut parked.perm);
            std::mem::swap(&mut self.factored_xi, &mut parked.xi);
            std::mem::swap(&mut self.dw_dxi, &mut parked.dw_dxi);
            std::mem::swap(&mut self.carry, &mut parked.carry);
        }
    }

    /// Forgets the factored Newton matrix, so that the next step forms its own (a new
    /// start, where an earlier step's matrix says nothing).
    pub(crate) fn forget_factors(&mut self) {
        self.carry.forget();
    }

    /// Factors the Newton matrix in place (partial-pivoting LU, [`super::lu`]: `perm`),
    /// for [`super::newton::substitute`].
    pub(super) fn factor(&mut self) {
        super::lu::lu_in_place(&mut self.jacobian, &mut self.perm);
        self.carry.factored();
        self.factored_xi.copy_from_slice(&self.xi);
    }
}

/// The workspace of a system's group.
pub(crate) type WorkspaceOf<S, const D: usize> =
    Workspace<<<S as System<D>>::Group as StepGroup<D>>::Jet, D>;

impl<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> StepSolver<'_, S, C, D> {
    /// The residual at the unknowns in `work.xi` relative to the equations' largest terms
    /// (infinite outside the chart's domain or where not finite): how good a predictor is.
    /// The assembly (with Hessians, for the exact Jacobian) is kept for [`StepSolver::solve`]'s
    /// first iteration until `work.xi` changes ([`Workspace::guess_changed`]).
    pub fn relative_residual(
        &self,
        base: &Element<S, D>,
        mu: &SVector<f64, D>,
        work: &mut WorkspaceOf<S, D>,
    ) -> f64 {
        work.guess_changed();
        if self.check_domain(work, 0, 0.0).is_err() {
            return f64::INFINITY;
        }
        let exact = self.settings.jacobian() == NewtonJacobian::Exact;
        let (residual, scale) = self.assemble(base, mu, work, exact);
        let relative = residual / scale.max(f64::MIN_POSITIVE);
        if relative.is_finite() {
            work.guess_assembled = Some((residual, scale));
            relative
        } else {
            f64::INFINITY
        }
    }

    /// Evaluates the points (with their Hessians if `with_jacobian`, for a following
    /// [`StepSolver::fill_jacobian`]) and the residual at the current unknowns; returns
    /// `(‖F‖∞, scale)` with the residual written to `work.residual`.
    pub(super) fn assemble(
        &self,
        base: &Element<S, D>,
        mu: &SVector<f64, D>,
        work: &mut WorkspaceOf<S, D>,
        with_jacobian: bool,
    ) -> (f64, f64) {
        let d = self.d;
        let (n, m) = (d.n, d.m);
        let with_configuration = self.needs_configuration();
        work.converged_hessians = false;
        for j in 0..m {
            let mut x = SVector::<f64, D>::zeros();
            let mut v = SVector::<f64, D>::zeros();
            let (values, slopes) = (d.values_at(j), d.slopes_at(j));
            for i in 1..n {
                x += work.xi[i] * values[i];
                v += work.xi[i] * slopes[i];
            }
            work.x[j] = x;
            work.v[j] = v;
        }
        // Every point at once where the system has a path for it (SO(3) bodies, free or
        // in a uniform field: `crate::jet_lanes`), else one by one. The force at point j
        // as the point-by-point path forms it (`point_derivatives`).
        let force_at = |j: usize, g: &Element<S, D>, xi: &SVector<f64, D>| {
            let input = self.input_at(j).expect("asked for a forced step only");
            StepForce::new(self.system, self.time + d.times[j], &input).jet_and_power(
                g,
                xi,
                with_jacobian,
            )
        };
        let force = self.forcing.as_ref().map(|input| {
            let reads = StepForce::new(self.system, self.time, input).depends_on_configuration();
            (&force_at as ForceAtPoint<'_, S::Group, D>, reads)
        });
        let points = GaussPoints {
            base,
            x: &work.x,
            v: &work.v,
            with_configuration,
            with_hessian: with_jacobian,
            force,
        };
        let in_lanes = self.system.points_in_lanes(
            self.chart,
            &points,
            &mut work.points,
            &mut work.transports,
            &mut work.power,
        );
        if !in_lanes {
            for j in 0..m {
                let ell = EllTilde {
                    system: self.system,
                    chart: self.chart,
                    base,
                    time: self.time + d.times[j],
                };
                work.power[j] = point_derivatives(
                    &ell,
                    &work.x[j],
                    &work.v[j],
                    with_configuration,
                    with_jacobian,
                    self.input_at(j).as_ref(),
                    &mut work.points[j],
                    &mut work.transports[j],
                );
            }
        }
        // ∂S/∂ξⁱ and the scale of its terms, accumulated point by point (the same sums,
        // in the same order, as node by node), one component over all nodes at a time.
        for (j, point) in work.points.iter().enumerate() {
            let g = point.gradient();
            work.point_gradients[2 * D * j..2 * D * (j + 1)].copy_from_slice(&g[..2 * D]);
        }
        accumulate_gradient::<D>(
            &mut work.gradient_by_component,
            &mut work.gradient_scale,
            &work.point_gradients,
            &d.weights,
            (&d.values, &d.slopes),
        );
        for (i, node) in work.gradient.iter_mut().enumerate() {
            for c in 0..D {
                node[c] = work.gradient_by_component[c * n + i];
            }
        }
        // Residual blocks: internal stages i = 2..n−1 (rows D(i−2)..), then matching.
        let rows = D * (n - 1);
        let mut scale = mu.amax();
        for i in 1..n - 1 {
            for c in 0..D {
                work.residual[D * (i - 1) + c] = work.gradient[i][c];
            }
            scale = scale.max(work.gradient_scale[i]);
        }
        let (matching, matching_scale) = self.matching_residual(mu, work, with_jacobian);
        scale = scale.max(matching_scale);
        // A force formed from larger terms than itself (a spring near its target) carries
        // their rounding into every equation, weighted by the step's quadrature (Σ h b_j = h).
        let formed_from = self.system.force_rounding_scale();
        if formed_from > 0.0 {
            scale = scale.max(formed_from * d.weights.iter().sum::<f64>());
        }
        for c in 0..D {
            work.residual[rows - D + c] = matching[c];
        }
        let norm = work.residual.iter().fold(0.0f64, |a, r| a.max(r.abs()));
        (norm, scale)
    }

    /// The largest term of `∂S/∂ξⁱ` at node `i` in the last assembly.
    pub(super) fn gradient_scale(work: &WorkspaceOf<S, D>, i: usize) -> f64 {
        work.gradient_scale[i]
    }

    /// The exact Newton matrix from the point Hessians of the last assembly (module
    /// documentation); the matching rows from [`StepSolver::fill_matching_rows`].
    ///
    /// The product's rows run over the equations' `(i, r)` inside each component `c` of
    /// an unknown, and its columns over that unknown's node `k` (`by_unknown`, the exact
    /// matching): the Newton matrix's column of unknown `(k, c)` is then one contiguous
    /// stretch of the product's column `k`, copied whole. The paper's matching also reads
    /// the equation of `ξ¹`, which has no unknown: there the rows run over the unknowns
    /// `(k, c)` inside each component `r` of an equation and the columns over its node
    /// `i` (the equations of `ξ¹` to `ξⁿ`), and the matrix gathers its columns with a
    /// stride.
    pub(super) fn fill_jacobian(&self, work: &mut WorkspaceOf<S, D>) {
        let d = self.d;
        let n = d.n;
        let unknowns = D * (n - 1);
        let by_unknown = self.by_unknown();
        // Point by point, each point's Hessian read once, each column written in order.
        // Column `2j + half` of the left factor multiplies the weighted basis's
        // `h b_j φ(c_j)` (half = 0) or `h b_j φ'(c_j)` (half = 1) of the node in the
        // product's column; its rows hold the basis at the point times the Hessian
        // entries that pair with it.
        let z = &mut work.hessian_times_basis;
        for (j, point) in work.points.iter().enumerate() {
            let (values, slopes) = (&d.values_at(j)[1..], &d.slopes_at(j)[1..]);
            for half in 0..2 {
                let column = z.col_as_slice_mut(2 * j + half);
                let h0 = D * half;
                // Row a of these: the entries that the basis of the rows' node scales.
                let (hx, hv): ([[f64; D]; D], [[f64; D]; D]) = if by_unknown {
                    // Rows (c; i, r): equation rows r (x, then v), the unknown's variable
                    // h0 + c.
                    (
                        std::array::from_fn(|c| std::array::from_fn(|r| point.hessian(r, h0 + c))),
                        std::array::from_fn(|c| {
                            std::array::from_fn(|r| point.hessian(D + r, h0 + c))
                        }),
                    )
                } else {
                    // Rows (r; k, c): the equation's row h0 + r, variables c (x, then v).
                    (
                        std::array::from_fn(|r| std::array::from_fn(|c| point.hessian(h0 + r, c))),
                        std::array::from_fn(|r| {
                            std::array::from_fn(|c| point.hessian(h0 + r, D + c))
                        }),
                    )
                };
                scaled_rows(column, &hx, &hv, values, slopes);
            }
        }
        // One product for all D components ([`super::product`]: by hand at a step's
        // sizes, where faer's `matmul` took up to 43% of a step's time). Column 0 (the
        // node of ξ¹) is not an unknown; only the paper's matching reads its equation.
        let first = if by_unknown { 1 } else { 0 };
        let rows = work.action_hessian.nrows();
        super::product::replace_product(
            &mut work.action_hessian,
            0..rows,
            first..n,
            &work.hessian_times_basis,
            &d.weighted_basis,
            first..n,
        );
        // The interior rows, written down the Newton matrix's columns (its storage
        // order): row by row the stores would be strided, each entry to another cache
        // line.
        let jac = work.jacobian.as_mut_slice();
        if by_unknown {
            let interior = unknowns - D;
            for k in 1..n {
                let source = work.action_hessian.col_as_slice(k);
                for c in 0..D {
                    let col = D * (k - 1) + c;
                    jac[col * unknowns..col * unknowns + interior]
                        .copy_from_slice(&source[c * unknowns..c * unknowns + interior]);
                }
            }
        } else {
            // Column i of the product holds the D rows of the equation of ξⁱ⁺¹ one after
            // the other, i.e. those rows transposed.
            for (col, target) in jac.chunks_exact_mut(unknowns).enumerate() {
                for i in 1..n - 1 {
                    let source = work.action_hessian.col_as_slice(i);
                    for (r, entry) in target[D * (i - 1)..D * i].iter_mut().enumerate() {
                        *entry = source[r * unknowns + col];
                    }
                }
            }
        }
        self.fill_matching_rows(work);
    }

    /// Whether [`StepSolver::fill_jacobian`]'s product is laid out by unknowns (the exact
    /// matching) rather than by equations (the paper's).
    fn by_unknown(&self) -> bool {
        self.settings.matching() == Matching::Exact
    }

    /// `∂²S/∂ξᵏ∂ξⁱ` as a `D × D` block (rows the components of `ξⁱ`'s equation, columns
    /// those of the unknown `ξᵏ`, `k ≥ 1`), from the last [`StepSolver::fill_jacobian`]; `i ≥ 1`
    /// with the exact matching.
    #[inline]
    pub(super) fn hessian_block(
        &self,
        work: &WorkspaceOf<S, D>,
        i: usize,
        k: usize,
    ) -> SMatrix<f64, D, D> {
        let unknowns = D * (work.xi.len() - 1);
        if self.by_unknown() {
            SMatrix::from_fn(|r, c| work.action_hessian[(unknowns * c + D * (i - 1) + r, k)])
        } else {
            SMatrix::from_fn(|r, c| work.action_hessian[(unknowns * r + D * (k - 1) + c, i)])
        }
    }

    /// Forward-difference Newton matrix (the paper's solver), column by column.
    pub(super) fn fill_jacobian_by_differences(
        &self,
        base: &Element<S, D>,
        mu: &SVector<f64, D>,
        work: &mut WorkspaceOf<S, D>,
    ) {
        let n = self.d.n;
        let unknowns = D * (n - 1);
        work.trial.copy_from_slice(&work.residual);
        for col in 0..unknowns {
            let (i, c) = (1 + col / D, col % D);
            let saved = work.xi[i][c];
            let step = f64::EPSILON.sqrt() * saved.abs().max(1.0);
            work.xi[i][c] = saved + step;
            self.assemble(base, mu, work, false);
            for row in 0..unknowns {
                work.jacobian[(row, col)] = (work.residual[row] - work.trial[row]) / step;
            }
            work.xi[i][c] = saved;
        }
        work.residual.copy_from_slice(&work.trial);
    }

    /// Checks every node against the chart's domain.
    pub(super) fn check_domain(
        &self,
        work: &WorkspaceOf<S, D>,
        step: usize,
        time: f64,
    ) -> Result<(), MechanicsError> {
        for xi in &work.xi {
            self.chart
                .check_domain(xi)
                .map_err(|source| MechanicsError::OutsideChart { step, time, source })?;
        }
        Ok(())
    }
}

/// `∂S/∂ξⁱ` at every node `i` into `gradient` (`D` rows of `n`, row `c` component `c`),
/// and the scale of its terms into `scale`, from the points' `x` and `v` gradients
/// (`point_gradients`, `2D` a point) and the tables (`values`, `slopes`: `n` a point):
/// with point `j`'s weight `w`, `φ_i`'s value `b` and slope `s` there, the sums of
/// `(g_x[c] b + g_v[c] s) w` and the largest `w (|g_x|∞ |b| + |g_v|∞ |s|)`. Along the
/// nodes, so that it vectorises (node by node, `D` = 3 components left it to scalar code);
/// compiled for the x86-64 baseline and with AVX2 (chosen at run time, once an
/// assembly), element-wise products and sums in the same order in both: bit-identical
/// (test `the_gradient_kernel_is_the_point_by_point_sum_bit_for_bit`).
#[multiversion::multiversion(targets("x86_64+avx+avx2+fma"))]
pub(super) fn accumulate_gradient<const D: usize>(
    gradient: &mut [f64],
    scale: &mut [f64],
    point_gradients: &[f64],
    weights: &[f64],
    (values, slopes): (&[f64], &[f64]),
) {
    let n = scale.len();
    gradient.fill(0.0);
    scale.fill(0.0);
    let tables = values.chunks_exact(n).zip(slopes.chunks_exact(n));
    for ((g, &weight), (values, slopes)) in
        point_gradients.chunks_exact(2 * D).zip(weights).zip(tables)
    {
        for (c, row) in gradient.chunks_exact_mut(n).enumerate() {
            let (x, v) = (g[c], g[D + c]);
            for i in 0..n {
                row[i] += (x * values[i] + v * slopes[i]) * weight;
            }
        }
        let size_x = g[..D].iter().fold(0.0f64, |a, b| a.max(b.abs()));
        let size_v = g[D..].iter().fold(0.0f64, |a, b| a.max(b.abs()));
        for i in 0..n {
            scale[i] = scale[i].max(weight * (size_x * values[i].abs() + size_v * slopes[i].abs()));
        }
    }
}

/// One point's Hessian entries, scaled by the basis at the point, into a column of the
/// product's left factor: in the chunk of outer index `a`, node `k`'s entry `b` gets
/// `φ_k hx[a][b] + φ'_k hv[a][b]` ([`StepSolver::fill_jacobian`] chooses which entries `hx`
/// and `hv` hold). Compiled for the x86-64 baseline and with AVX2 (chosen at run time,
/// as the LU): element-wise products and sums, the same in both.
#[multiversion::multiversion(targets("x86_64+avx+avx2+fma"))]
fn scaled_rows<const D: usize>(
    column: &mut [f64],
    hx: &[[f64; D]; D],
    hv: &[[f64; D]; D],
    values: &[f64],
    slopes: &[f64],
) {
    let unknowns = D * values.len();
    for ((rows, x), v) in column.chunks_exact_mut(unknowns).zip(hx).zip(hv) {
        for ((block, &bk), &dk) in rows.chunks_exact_mut(D).zip(values).zip(slopes) {
            for c in 0..D {
                block[c] = bk * x[c] + dk * v[c];
            }
        }
    }
}
