//! One step: the Galerkin discrete action, its derivatives, and the Newton solve.
//!
//! On step `k` the curve is `g(t) = g_k Φ(ξ(t))`, `ξ(t) = Σ_i ξⁱ φ_i(t)` on `n`
//! Chebyshev–Lobatto nodes of `[0, h]`, `ξ¹ = 0`. With Gauss points `c_j h` and weights
//! `h b_j`, the action is `S = Σ_j h b_j ℓ̃(x_j, v_j)`, where `x_j = Σ_i φ_i(c_j h) ξⁱ`,
//! `v_j = Σ_i φ_i'(c_j h) ξⁱ` and `ℓ̃(x, v) = ℓ(g_k Φ(x), A(x) v)`. Each Gauss point needs
//! the gradient and Hessian of `ℓ̃` in its six arguments, taken exactly with dual numbers;
//! for the exact momentum matching of a Lagrangian that depends on `R` also the
//! derivatives in a configuration perturbation `ζ`, `ℓ(g_k Φ(x) exp(ζ), A(x) v)`, giving
//! nine arguments.
//!
//! Unknowns `ξ², …, ξⁿ`; equations: `∂S/∂ξⁱ = 0` for `i = 2..n−1` and three matching
//! equations,
//! - exact: `A(ξⁿ)ᵀ Φ(ξⁿ)ᵀ w − ∂S/∂ξⁿ = 0`, `w = μ_k + Σ_j h b_j Φ(x_j) p_j` with
//!   `p_j = ∂ℓ̃/∂ζ` (zero for a left-invariant Lagrangian), which is
//!   `μ_k = Φ(ξⁿ) A(ξⁿ)⁻ᵀ ∂S/∂ξⁿ − A(0)⁻ᵀ ∂_η S(g_k Φ(η) Φ(ξ(t)))` of `docs/paper-notes.md` §3;
//! - paper: `A(0)ᵀ μ_k + ∂S/∂ξ¹ = 0`.
//!
//! Afterwards `g_{k+1} = g_k Φ(ξⁿ)` and `μ_{k+1} = A(ξⁿ)⁻ᵀ ∂S/∂ξⁿ`, which the exact
//! matching equation turns into `μ_{k+1} = Φ(ξⁿ)ᵀ w`: that form is used (see
//! [`Stepper::solve`]).

use crate::error::MechanicsError;
use crate::jet::{self, PointDerivatives};
use crate::lagrangian::Lagrangian;
use crate::settings::{Matching, NewtonJacobian, StepSettings};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};
use lgsvi_lie::{ChartKind, So3Chart, SO3};
use lgsvi_quadrature::gauss_legendre;
use lgsvi_spectral::Barycentric;
use nalgebra::{Matrix3, RealField, SMatrix, SVector, Vector3};
use num_dual::{Dual2SVec64, DualSVec64};

/// The predictor continues the last step's curve through at most this many nodes.
const EXTRAPOLATION_NODES: usize = 12;

/// Fixed data of a step: quadrature, basis matrices.
#[derive(Debug, Clone)]
pub(crate) struct Discretisation {
    pub n: usize,
    pub m: usize,
    /// `h b_j`.
    pub weights: Vec<f64>,
    /// `φ_i(c_j h)`, row-major `m × n`.
    pub values: Vec<f64>,
    /// `φ_i'(c_j h)`, row-major `m × n`.
    pub slopes: Vec<f64>,
    /// The Lagrange basis on `[0, h]`, for dense output.
    pub basis: Barycentric,
    /// `2m × n`: row `2j` is `h b_j φ_i(c_j h)`, row `2j + 1` is `h b_j φ_i'(c_j h)`; the
    /// Newton matrix's blocks are the basis times the points' Hessians times this.
    pub weighted_basis: Mat<f64>,
    /// `φ_p(h + t_i)`, row-major `n × n`: the last step's polynomial continued over the
    /// next step, for the predictor.
    pub extrapolation: Vec<f64>,
}

impl Discretisation {
    pub fn new(settings: &StepSettings) -> Result<Self, MechanicsError> {
        let (n, m, h) = (
            settings.nodes(),
            settings.quadrature_points(),
            settings.step(),
        );
        let rule = gauss_legendre(m)?.on(0.0, h)?;
        let basis = Barycentric::chebyshev_lobatto(n, 0.0, h)?;
        let (b, d) = basis.evaluation_and_derivative_matrices(rule.nodes())?;
        let weights = rule.weights().to_vec();
        let values = b.as_slice().to_vec();
        let slopes = d.as_slice().to_vec();
        let weighted_basis = Mat::from_fn(2 * m, n, |row, i| {
            let j = row / 2;
            let table = if row % 2 == 0 { &values } else { &slopes };
            weights[j] * table[j * n + i]
        });
        // The continuation amplifies errors by ~|T_d(3)| ≈ 5.8^d / 2 at degree d: through
        // at most EXTRAPOLATION_NODES nodes (resampled onto their Lobatto points), rounding
        // stays below 1e-8 of the curve.
        let continued: Vec<f64> = basis.nodes().iter().map(|t| h + t).collect();
        let coarse = Barycentric::chebyshev_lobatto(n.min(EXTRAPOLATION_NODES), 0.0, h)?;
        let resample = basis.evaluation_matrix(coarse.nodes())?;
        let continue_coarse = coarse.evaluation_matrix(&continued)?;
        // extrapolation = continue_coarse · resample, row by row.
        let mut extrapolation = vec![0.0; n * n];
        for (i, row) in extrapolation.chunks_exact_mut(n).enumerate() {
            for (q, &c) in continue_coarse.row(i).iter().enumerate() {
                for (e, r) in row.iter_mut().zip(resample.row(q)) {
                    *e += c * r;
                }
            }
        }
        Ok(Self {
            n,
            m,
            extrapolation,
            weights,
            values,
            slopes,
            basis,
            weighted_basis,
        })
    }

    /// `φ_i(c_j h)` for every `i`.
    #[inline]
    pub fn values_at(&self, j: usize) -> &[f64] {
        &self.values[j * self.n..(j + 1) * self.n]
    }

    /// `φ_i'(c_j h)` for every `i`.
    #[inline]
    pub fn slopes_at(&self, j: usize) -> &[f64] {
        &self.slopes[j * self.n..(j + 1) * self.n]
    }

    #[inline]
    pub fn value(&self, j: usize, i: usize) -> f64 {
        self.values[j * self.n + i]
    }

    #[inline]
    pub fn slope(&self, j: usize, i: usize) -> f64 {
        self.slopes[j * self.n + i]
    }

    /// The node times `t_i ∈ [0, h]`.
    pub fn node_times(&self) -> &[f64] {
        self.basis.nodes()
    }
}

/// `ℓ(g Φ(x) exp(ζ), A(x) v)` for any scalar.
fn ell_tilde<T: RealField + Copy, L: Lagrangian>(
    system: &L,
    chart: ChartKind,
    base: &Matrix3<f64>,
    x: &Vector3<T>,
    v: &Vector3<T>,
    zeta: Option<&Vector3<T>>,
) -> T {
    let base: Matrix3<T> = base.map(nalgebra::convert);
    let mut r = base * chart.rotation_matrix(x);
    if let Some(z) = zeta {
        r *= *SO3::exp(z).matrix();
    }
    let omega = chart.rotation_left_differential(x) * v;
    system.lagrangian(&r, &omega)
}

/// `ℓ̃` of the stacked variables `(x, v, ζ)` (9) or `(x, v)` (6), for the dual-number drivers.
fn ell_stacked<T: RealField + Copy, L: Lagrangian, const N: usize>(
    system: &L,
    chart: ChartKind,
    base: &Matrix3<f64>,
    y: &SVector<T, N>,
) -> T {
    let x = Vector3::new(y[0], y[1], y[2]);
    let v = Vector3::new(y[3], y[4], y[5]);
    let z = (N == 9).then(|| Vector3::new(y[6], y[7], y[8]));
    ell_tilde(system, chart, base, &x, &v, z.as_ref())
}

/// Writes the gradient and (if `with_hessian`) Hessian of `ℓ̃` at one Gauss point into
/// `out`: by the chain rule from the chart's Rodrigues form and the system's
/// [`Lagrangian::derivatives`] (every built-in chart has one), else by dual numbers
/// through the whole of `ℓ̃`.
#[allow(clippy::too_many_arguments)]
fn point_derivatives<L: Lagrangian>(
    system: &L,
    chart: ChartKind,
    base: &Matrix3<f64>,
    x: &Vector3<f64>,
    v: &Vector3<f64>,
    with_configuration: bool,
    with_hessian: bool,
    out: &mut PointDerivatives,
) {
    if !jet::point_derivatives(
        system,
        chart,
        base,
        x,
        v,
        with_configuration,
        with_hessian,
        out,
    ) {
        *out = point_derivatives_by_dual_numbers(system, chart, base, x, v, with_configuration);
    }
}

/// `ℓ̃`'s gradient and Hessian by a 6- or 9-variable second-order dual number: the
/// general path, and the tests' independent check of the chain rule.
fn point_derivatives_by_dual_numbers<L: Lagrangian>(
    system: &L,
    chart: ChartKind,
    base: &Matrix3<f64>,
    x: &Vector3<f64>,
    v: &Vector3<f64>,
    with_configuration: bool,
) -> PointDerivatives {
    let mut gradient = SVector::<f64, 9>::zeros();
    let mut hessian = SMatrix::<f64, 9, 9>::zeros();
    if with_configuration {
        let y =
            SVector::<f64, 9>::from_column_slice(&[x.x, x.y, x.z, v.x, v.y, v.z, 0.0, 0.0, 0.0]);
        let (_, g, h) = num_dual::hessian(
            |y: SVector<Dual2SVec64<9>, 9>| ell_stacked(system, chart, base, &y),
            &y,
        );
        gradient.copy_from(&g);
        hessian.copy_from(&h);
    } else {
        let y = SVector::<f64, 6>::from_column_slice(&[x.x, x.y, x.z, v.x, v.y, v.z]);
        let (_, g, h) = num_dual::hessian(
            |y: SVector<Dual2SVec64<6>, 6>| ell_stacked(system, chart, base, &y),
            &y,
        );
        gradient.fixed_rows_mut::<6>(0).copy_from(&g);
        hessian.fixed_view_mut::<6, 6>(0, 0).copy_from(&h);
    }
    PointDerivatives { gradient, hessian }
}

/// `∂/∂y [A(y)ᵀ Φ(y)ᵀ w]` at `y`, by dual numbers.
fn matching_map_jacobian(chart: ChartKind, y: &Vector3<f64>, w: &Vector3<f64>) -> Matrix3<f64> {
    let (_, jac) = num_dual::jacobian(
        |y: SVector<DualSVec64<3>, 3>| {
            let w: Vector3<DualSVec64<3>> = w.map(nalgebra::convert);
            let a = chart.rotation_left_differential(&y);
            let r = chart.rotation_matrix(&y);
            a.transpose() * (r.transpose() * w)
        },
        y,
    );
    jac
}

/// A Newton step taken from a residual below this fraction of the largest terms of the
/// equations lands, by quadratic convergence (measured contraction `r_{k+1} ≈ 0.1 r_k²`
/// in relative terms on the paper's cases), at an error ~1e-17 of them: below rounding,
/// so the step is accepted once the residual is at its rounding floor (≤ √ε of the terms)
/// without a further iteration that could only confirm the floor.
///
/// From an iterate this close, the full Newton step is also always taken (no backtracking):
/// the residual after it is rounding noise, and comparing noise with noise would reject
/// about half of these steps and keep the previous iterate, whose error — the quadratic
/// remainder of the step before, ~ the rounding floor but with a fixed sign along a
/// trajectory — then accumulates: measured, case A (exp, h = 0.5, n = 8), an energy drift
/// of 1.7e-17 per step (3.1e-13 after 2·10⁴ steps), none without the backtracking
/// (7e-15, random).
const QUADRATIC_REGIME: f64 = 1e-8;

/// A Newton matrix factored at an iterate with relative residual `r_f` at or below this is
/// kept for the rest of the step: each chord step with it (an assembly without Hessians
/// and two triangular solves, no LU) multiplies the error by ~`r_f` (the matrices differ
/// by ~`r_f`), and `r₁ ≈ 0.1 r_f²` after the Newton step (measured). Two or three chord
/// steps then cost less than one more Newton step (measured, case A, n = 10).
const CHORD_EXPECTED: f64 = 1e-4;

/// Chord steps continue until their predicted remainder (the product of `r_f` and the
/// error estimate they started from) is below this, far below rounding: a remainder kept
/// at the rounding floor has a fixed sign along a trajectory and accumulates (see
/// [`QUADRATIC_REGIME`]), so the iterate is accepted only after it (typical chain from
/// `r_f = 3e-6`: 7e-13 → 2e-18 → 6e-24).
const CHORD_REMAINDER: f64 = 1e-20;

/// Writes a 3×3 block into the Newton matrix with its top-left entry at `(row, col)`.
fn put_block(jac: &mut Mat<f64>, row: usize, col: usize, block: &Matrix3<f64>) {
    for r in 0..3 {
        for c in 0..3 {
            jac[(row + r, col + c)] = block[(r, c)];
        }
    }
}

/// Solves `L U x = b` in place, with `L U` the unit-lower and upper factors that faer's
/// partial-pivoting LU left in `lu` (the row permutation already applied to `b`): forward
/// and back substitution by columns. For one right-hand side of the sizes a step has
/// (`3(n − 1)` ≤ ~70), faer's blocked triangular solves spend more in dispatch than in
/// arithmetic: measured 0.55 → 0.35 µs at 27 unknowns, 0.79 → 0.48 µs at 33.
fn substitute(lu: &Mat<f64>, b: &mut [f64]) {
    let size = b.len();
    for k in 0..size {
        let bk = b[k];
        let below = &lu.col_as_slice(k)[k + 1..];
        for (x, l) in b[k + 1..].iter_mut().zip(below) {
            *x -= l * bk;
        }
    }
    for k in (0..size).rev() {
        let column = lu.col_as_slice(k);
        b[k] /= column[k];
        let bk = b[k];
        for (x, u) in b[..k].iter_mut().zip(&column[..k]) {
            *x -= u * bk;
        }
    }
}

/// Preallocated buffers of the Newton iteration: nothing is allocated per step.
pub(crate) struct Workspace {
    /// Unknowns `ξ², …, ξⁿ` (with `ξ¹ = 0` at index 0): `n` vectors.
    pub xi: Vec<Vector3<f64>>,
    /// The last accepted iterate, for the line search.
    xi_accepted: Vec<Vector3<f64>>,
    points: Vec<PointDerivatives>,
    /// Exact matching of an `R`-dependent Lagrangian: `∂q_j/∂x`, `∂q_j/∂v` per point,
    /// `q_j = Φ(x_j) p_j` (computed once per assembly, used by every column of the
    /// matching rows).
    dq_dx: Vec<Matrix3<f64>>,
    dq_dv: Vec<Matrix3<f64>>,
    x: Vec<Vector3<f64>>,
    v: Vec<Vector3<f64>>,
    /// `w` of the exact matching and `A(ξⁿ)ᵀΦ(ξⁿ)ᵀ`, from the last assembly.
    w: Vector3<f64>,
    transport: Matrix3<f64>,
    /// The basis times the points' Hessian rows, the three component rows `r` stacked
    /// (`3·3(n−1) × 2m`, row `3(n−1)r + 3(k−1) + c`, columns `2j`, `2j + 1` for `x`, `v`),
    /// and `∂²S/∂ξᵏ_c ∂ξⁱ_r` (`3·3(n−1) × n`, the same rows, column `i`) = that times
    /// `weighted_basis`.
    hessian_times_basis: Mat<f64>,
    action_hessian: Mat<f64>,
    gradient: Vec<Vector3<f64>>,
    gradient_scale: Vec<f64>,
    residual: Vec<f64>,
    trial: Vec<f64>,
    jacobian: Mat<f64>,
    /// The Newton (or chord) step `−J⁻¹F`, kept for the backtracking.
    delta: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    stack: MemBuffer,
    /// `(‖F‖∞, scale)` of an assembly (with Hessians for the exact Jacobian) at the
    /// current `xi`, made by [`Stepper::relative_residual`]: the Newton loop's first
    /// assembly, saved.
    guess_assembled: Option<(f64, f64)>,
}

impl Workspace {
    pub fn new(d: &Discretisation) -> Self {
        let unknowns = 3 * (d.n - 1);
        let scratch = factor::lu_in_place_scratch::<usize, f64>(
            unknowns,
            unknowns,
            Par::Seq,
            Default::default(),
        );
        Self {
            xi: vec![Vector3::zeros(); d.n],
            xi_accepted: vec![Vector3::zeros(); d.n],
            points: vec![PointDerivatives::zeros(); d.m],
            dq_dx: vec![Matrix3::zeros(); d.m],
            dq_dv: vec![Matrix3::zeros(); d.m],
            x: vec![Vector3::zeros(); d.m],
            v: vec![Vector3::zeros(); d.m],
            w: Vector3::zeros(),
            transport: Matrix3::zeros(),
            hessian_times_basis: Mat::zeros(3 * unknowns, 2 * d.m),
            action_hessian: Mat::zeros(3 * unknowns, d.n),
            gradient: vec![Vector3::zeros(); d.n],
            gradient_scale: vec![0.0; d.n],
            residual: vec![0.0; unknowns],
            trial: vec![0.0; unknowns],
            jacobian: Mat::zeros(unknowns, unknowns),
            delta: vec![0.0; unknowns],
            perm: vec![0; unknowns],
            perm_inv: vec![0; unknowns],
            stack: MemBuffer::new(scratch),
            guess_assembled: None,
        }
    }

    /// Forgets the assembly at the guess: call after changing `xi` from outside the solve.
    pub fn guess_changed(&mut self) {
        self.guess_assembled = None;
    }
}

/// What a converged step returns.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StepOutcome {
    pub attitude: Matrix3<f64>,
    pub momentum: Vector3<f64>,
    pub iterations: usize,
    /// Newton matrices factored (the other iterations were chord steps).
    pub factorizations: usize,
}

/// The solver of one step, for a system, a chart and fixed settings.
pub(crate) struct Stepper<'a, L: Lagrangian> {
    pub system: &'a L,
    pub settings: &'a StepSettings,
    pub d: &'a Discretisation,
}

impl<L: Lagrangian> Stepper<'_, L> {
    fn chart(&self) -> ChartKind {
        self.settings.chart()
    }

    fn needs_configuration(&self) -> bool {
        self.settings.matching() == Matching::Exact && !self.system.is_left_invariant()
    }

    /// The residual at the unknowns in `work.xi` relative to the equations' largest terms
    /// (infinite outside the chart's domain or where not finite): how good a predictor is.
    /// The assembly (with Hessians, for the exact Jacobian) is kept for [`Stepper::solve`]'s
    /// first iteration until `work.xi` changes ([`Workspace::guess_changed`]).
    pub fn relative_residual(
        &self,
        base: &Matrix3<f64>,
        mu: &Vector3<f64>,
        work: &mut Workspace,
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
    /// [`Stepper::fill_jacobian`]) and the residual at the current unknowns; returns
    /// `(‖F‖∞, scale)` with the residual written to `work.residual`.
    fn assemble(
        &self,
        base: &Matrix3<f64>,
        mu: &Vector3<f64>,
        work: &mut Workspace,
        with_jacobian: bool,
    ) -> (f64, f64) {
        let d = self.d;
        let (n, m) = (d.n, d.m);
        let chart = self.chart();
        let with_configuration = self.needs_configuration();
        for j in 0..m {
            let mut x = Vector3::zeros();
            let mut v = Vector3::zeros();
            let (values, slopes) = (d.values_at(j), d.slopes_at(j));
            for i in 1..n {
                x += work.xi[i] * values[i];
                v += work.xi[i] * slopes[i];
            }
            work.x[j] = x;
            work.v[j] = v;
            point_derivatives(
                self.system,
                chart,
                base,
                &x,
                &v,
                with_configuration,
                with_jacobian,
                &mut work.points[j],
            );
        }
        // ∂S/∂ξⁱ and the scale of its terms, accumulated point by point (the same sums,
        // in the same order, as node by node).
        work.gradient.fill(Vector3::zeros());
        work.gradient_scale.fill(0.0);
        for j in 0..m {
            let p = &work.points[j];
            let gx: Vector3<f64> = p.gradient.fixed_rows::<3>(0).into_owned();
            let gv: Vector3<f64> = p.gradient.fixed_rows::<3>(3).into_owned();
            let (size_x, size_v) = (gx.amax(), gv.amax());
            let weight = d.weights[j];
            let (values, slopes) = (d.values_at(j), d.slopes_at(j));
            for i in 0..n {
                let term = gx * values[i] + gv * slopes[i];
                work.gradient[i] += term * weight;
                work.gradient_scale[i] = work.gradient_scale[i]
                    .max(weight * (size_x * values[i].abs() + size_v * slopes[i].abs()));
            }
        }
        let xi_n = work.xi[n - 1];
        // w = μ_k + Σ_j h b_j Φ(x_j) p_j (exact matching).
        let mut w = *mu;
        if with_configuration {
            for j in 0..m {
                let pt = &work.points[j];
                let x = &work.x[j];
                let phi = chart.rotation_matrix(x);
                let p: Vector3<f64> = pt.gradient.fixed_rows::<3>(6).into_owned();
                w += phi * p * d.weights[j];
                if with_jacobian {
                    // ∂q/∂x = Φ(x)(H_ζx − p̂ A(x)), ∂q/∂v = Φ(x) H_ζv.
                    let h_zx: Matrix3<f64> = pt.hessian.fixed_view::<3, 3>(6, 0).into_owned();
                    let h_zv: Matrix3<f64> = pt.hessian.fixed_view::<3, 3>(6, 3).into_owned();
                    work.dq_dx[j] = phi
                        * (h_zx - lgsvi_lie::so3::hat(&p) * chart.rotation_left_differential(x));
                    work.dq_dv[j] = phi * h_zv;
                }
            }
        }
        let (a_n, r_n) = (
            chart.rotation_left_differential(&xi_n),
            chart.rotation_matrix(&xi_n),
        );
        let transport = a_n.transpose() * r_n.transpose();
        // Residual blocks: internal stages i = 2..n−1 (rows 3(i−2)..), then matching.
        let rows = 3 * (n - 1);
        let mut scale = mu.amax();
        for i in 1..n - 1 {
            for c in 0..3 {
                work.residual[3 * (i - 1) + c] = work.gradient[i][c];
            }
            scale = scale.max(work.gradient_scale[i]);
        }
        let matching = match self.settings.matching() {
            Matching::Exact => {
                scale = scale
                    .max(work.gradient_scale[n - 1])
                    .max((transport * w).amax());
                transport * w - work.gradient[n - 1]
            }
            Matching::Paper => {
                let a0 = chart.rotation_left_differential(&Vector3::zeros());
                scale = scale
                    .max(work.gradient_scale[0])
                    .max((a0.transpose() * mu).amax());
                a0.transpose() * mu + work.gradient[0]
            }
        };
        for c in 0..3 {
            work.residual[rows - 3 + c] = matching[c];
        }
        let norm = work.residual.iter().fold(0.0f64, |a, r| a.max(r.abs()));
        work.w = w;
        work.transport = transport;
        (norm, scale)
    }

    /// The exact Newton matrix from the point Hessians of the last assembly.
    ///
    /// `∂²S/∂ξⁱ∂ξᵏ = Σ_j h b_j [φ_i φ_k H_xx + φ_i φ_k' H_xv + φ_i' φ_k H_vx + φ_i' φ_k' H_vv]_j`
    /// is formed for the three component rows `r` at once as the product of the basis times
    /// the points' Hessian rows (`3·3(n−1) × 2m`, filled point by point) with
    /// `Discretisation::weighted_basis` (`2m × n`): one dense product instead of `n²m`
    /// small block sums.
    fn fill_jacobian(&self, work: &mut Workspace) {
        let d = self.d;
        let (n, m) = (d.n, d.m);
        let chart = self.chart();
        let with_configuration = self.needs_configuration();
        let (transport, w, xi_n) = (work.transport, work.w, work.xi[n - 1]);
        let points = &work.points;
        let unknowns = 3 * (n - 1);
        // Point by point, each point's Hessian read once, each column written in order.
        let z = &mut work.hessian_times_basis;
        for (j, point) in points.iter().enumerate() {
            let h = &point.hessian;
            let (values, slopes) = (d.values_at(j), d.slopes_at(j));
            for half in 0..2 {
                let column = z.col_as_slice_mut(2 * j + half);
                let row = 3 * half;
                for (r, rows) in column.chunks_exact_mut(unknowns).enumerate() {
                    let (hx, hv) = (
                        [h[(row + r, 0)], h[(row + r, 1)], h[(row + r, 2)]],
                        [h[(row + r, 3)], h[(row + r, 4)], h[(row + r, 5)]],
                    );
                    for ((block, &bk), &dk) in
                        rows.chunks_exact_mut(3).zip(&values[1..]).zip(&slopes[1..])
                    {
                        for c in 0..3 {
                            block[c] = bk * hx[c] + dk * hv[c];
                        }
                    }
                }
            }
        }
        // One product for the three component rows (three would pay faer's dispatch thrice).
        matmul(
            work.action_hessian.as_mut(),
            Accum::Replace,
            work.hessian_times_basis.as_ref(),
            d.weighted_basis.as_ref(),
            1.0,
            Par::Seq,
        );
        let action_hessian = &work.action_hessian;
        let hessian_block = |i: usize, k: usize| -> Matrix3<f64> {
            Matrix3::from_fn(|r, c| action_hessian[(unknowns * r + 3 * (k - 1) + c, i)])
        };
        let jac = &mut work.jacobian;
        for i in 1..n - 1 {
            let source = action_hessian.col_as_slice(i);
            for (r, rows) in source.chunks_exact(unknowns).enumerate() {
                for (col, &value) in rows.iter().enumerate() {
                    jac[(3 * (i - 1) + r, col)] = value;
                }
            }
        }
        let last = 3 * (n - 2);
        match self.settings.matching() {
            Matching::Exact => {
                let map_jacobian = matching_map_jacobian(chart, &xi_n, &w);
                for k in 1..n {
                    let mut block = -hessian_block(n - 1, k);
                    if k == n - 1 {
                        block += map_jacobian;
                    }
                    if with_configuration {
                        // ∂w/∂ξᵏ = Σ_j h b_j [∂q/∂x B_jk + ∂q/∂v D_jk].
                        let mut dw = Matrix3::zeros();
                        for j in 0..m {
                            dw += (work.dq_dx[j] * d.value(j, k) + work.dq_dv[j] * d.slope(j, k))
                                * d.weights[j];
                        }
                        block += transport * dw;
                    }
                    put_block(jac, last, 3 * (k - 1), &block);
                }
            }
            Matching::Paper => {
                for k in 1..n {
                    let block = hessian_block(0, k);
                    put_block(jac, last, 3 * (k - 1), &block);
                }
            }
        }
    }

    /// Forward-difference Newton matrix (the paper's solver), column by column.
    fn fill_jacobian_by_differences(
        &self,
        base: &Matrix3<f64>,
        mu: &Vector3<f64>,
        work: &mut Workspace,
    ) {
        let n = self.d.n;
        let unknowns = 3 * (n - 1);
        work.trial.copy_from_slice(&work.residual);
        for col in 0..unknowns {
            let (i, c) = (1 + col / 3, col % 3);
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
    fn check_domain(&self, work: &Workspace, step: usize, time: f64) -> Result<(), MechanicsError> {
        for xi in &work.xi {
            self.chart()
                .check_rotation_domain(xi)
                .map_err(|source| MechanicsError::OutsideChart { step, time, source })?;
        }
        Ok(())
    }

    /// Newton on the step's equations from the guess in `work.xi`.
    pub fn solve(
        &self,
        base: &Matrix3<f64>,
        mu: &Vector3<f64>,
        work: &mut Workspace,
        step: usize,
        time: f64,
    ) -> Result<StepOutcome, MechanicsError> {
        let n = self.d.n;
        let exact = self.settings.jacobian() == NewtonJacobian::Exact;
        let max_iterations = self.settings.max_newton_iterations();
        let mut previous = f64::INFINITY;
        let mut previous_scale = 0.0f64;
        let mut iterations = 0;
        let mut factorizations = 0;
        // Backtracking: a Newton step that does not lower the residual is halved (from the
        // last accepted iterate) up to `MAX_HALVINGS` times. Far from the solution (long
        // steps, the heavy top with the exact matching) the full step can overshoot;
        // near it the full step is always taken, so convergence stays quadratic.
        const MAX_HALVINGS: u32 = 8;
        let mut damping = 1.0f64;
        // The relative residual of the iterate at which `work.jacobian` was factored in this
        // solve, if it was.
        let mut factored_at: Option<f64> = None;
        // After a chord step whose predicted remainder is above CHORD_REMAINDER: that
        // prediction (the residual at the rounding floor can no longer show it); else 0.
        let mut pending = 0.0f64;
        // Whether the last step taken was a chord step.
        let mut last_was_chord = false;
        loop {
            // After a Newton step from a residual below QUADRATIC_REGIME of its terms, the
            // error is (quadratic convergence) far below rounding: this assembly is
            // expected to be the last, and needs no Hessians.
            let expect_converged = iterations > 0 && previous <= QUADRATIC_REGIME * previous_scale;
            // With a matrix factored below CHORD_EXPECTED, the next step is a chord step:
            // assemble without Hessians.
            let expect_chord = factored_at.is_some_and(|r_f| r_f <= CHORD_EXPECTED);
            // A halved trial point only needs its residual: the Hessians follow if it is
            // accepted and another step is needed.
            let with_hessians = exact && !expect_converged && !expect_chord && damping == 1.0;
            let in_domain = self.check_domain(work, step, time);
            let saved = work.guess_assembled.take().filter(|_| iterations == 0);
            let assembled = in_domain
                .as_ref()
                .ok()
                .map(|_| saved.unwrap_or_else(|| self.assemble(base, mu, work, with_hessians)));
            let worse = match assembled {
                // NaN counts as worse; near the solution the full step stands.
                Some((r, _)) => r.is_nan() || (r >= previous && !expect_converged),
                None => true,
            };
            if iterations > 0 && worse && damping > 0.5f64.powi(MAX_HALVINGS as i32) {
                damping *= 0.5;
                for i in 1..n {
                    for c in 0..3 {
                        work.xi[i][c] =
                            work.xi_accepted[i][c] + damping * work.delta[3 * (i - 1) + c];
                    }
                }
                continue;
            }
            in_domain?;
            let (residual, scale) = assembled.unwrap_or((f64::NAN, 0.0));
            if !residual.is_finite() {
                return Err(MechanicsError::SingularJacobian { step, time });
            }
            // Converged: the residual is a few ulps of its largest terms, or — once below
            // √ε of them — it has stopped halving (the rounding floor of the sums, which
            // for m·n terms can sit a little above a few ulps). Newton converges
            // quadratically, so the last accepted step is always taken at the floor.
            let scale = scale.max(f64::MIN_POSITIVE);
            let tight = 4.0 * f64::EPSILON * scale;
            let loose = f64::EPSILON.sqrt() * scale;
            let stagnated = iterations > 0 && residual > 0.5 * previous && residual <= loose;
            let at_floor =
                residual <= tight || stagnated || (expect_converged && residual <= loose);
            if at_floor && pending == 0.0 {
                return Ok(self.outcome(base, work, iterations, factorizations));
            }
            if iterations >= max_iterations {
                return Err(MechanicsError::NewtonDiverged {
                    step,
                    time,
                    iterations,
                    residual,
                });
            }
            // The error after the last step: the residual bounds it, and so does a pending
            // chord prediction once the residual is at the floor.
            let relative = residual / scale;
            let error = if pending > 0.0 {
                relative.min(pending)
            } else {
                relative
            };
            // A chord step that did not cut the residual tenfold (above the floor) means the
            // kept matrix is too far off: take a Newton step instead.
            let slow = last_was_chord
                && !at_floor
                && relative > 0.1 * previous / previous_scale.max(f64::MIN_POSITIVE);
            // The kept matrix's residual, when this step is a chord step with it.
            let chord = factored_at.filter(|&r_f| {
                exact && !slow && (r_f <= CHORD_EXPECTED || error * r_f <= CHORD_REMAINDER)
            });
            last_was_chord = chord.is_some();
            pending = 0.0;
            if let Some(r_f) = chord {
                let remainder = error * r_f;
                if remainder > CHORD_REMAINDER {
                    pending = remainder;
                }
            } else {
                if exact {
                    if !with_hessians {
                        self.assemble(base, mu, work, true);
                    }
                    self.fill_jacobian(work);
                } else {
                    self.fill_jacobian_by_differences(base, mu, work);
                }
                factor::lu_in_place(
                    work.jacobian.as_mut(),
                    &mut work.perm,
                    &mut work.perm_inv,
                    Par::Seq,
                    MemStack::new(&mut work.stack),
                    Default::default(),
                );
                factored_at = Some(relative);
                factorizations += 1;
            }
            for (d, &p) in work.delta.iter_mut().zip(&work.perm) {
                *d = -work.residual[p];
            }
            substitute(&work.jacobian, &mut work.delta);
            work.xi_accepted.copy_from_slice(&work.xi);
            damping = 1.0;
            let deltas = &work.delta;
            if !deltas.iter().all(|x| x.is_finite()) {
                return Err(MechanicsError::SingularJacobian { step, time });
            }
            for (xi, delta) in work.xi[1..].iter_mut().zip(deltas.chunks_exact(3)) {
                *xi += Vector3::new(delta[0], delta[1], delta[2]);
            }
            previous = residual;
            previous_scale = scale;
            iterations += 1;
            // A chord step from an iterate at the rounding floor whose predicted remainder
            // is below CHORD_REMAINDER leaves nothing for another assembly to show but the
            // floor again; where the momentum update needs no assembly at the new iterate
            // (exact matching of a left-invariant ℓ: w = μ_k), accept it now (the
            // simplified Newton stopping rule of implicit Runge–Kutta codes: stop when the
            // estimated error after the step is below tolerance). Saves one of the four
            // assemblies of a typical step.
            if chord.is_some() && pending == 0.0 && at_floor && self.momentum_is_assembly_free() {
                self.check_domain(work, step, time)?;
                return Ok(self.outcome(base, work, iterations, factorizations));
            }
        }
    }

    /// Whether the momentum update reads nothing from an assembly at the final iterate:
    /// exact matching of a left-invariant ℓ, where `w = μ_k`.
    fn momentum_is_assembly_free(&self) -> bool {
        self.settings.matching() == Matching::Exact && self.system.is_left_invariant()
    }

    /// The step's result at the unknowns in `work.xi`, from the last assembly's `w` (exact
    /// matching) or `∂S/∂ξⁿ` (the paper's).
    fn outcome(
        &self,
        base: &Matrix3<f64>,
        work: &Workspace,
        iterations: usize,
        factorizations: usize,
    ) -> StepOutcome {
        let xi_n = work.xi[self.d.n - 1];
        let chart = self.chart();
        let phi_n = chart.rotation_matrix(&xi_n);
        let momentum = match self.settings.matching() {
            // μ_{k+1} = A(ξⁿ)⁻ᵀ ∂S/∂ξⁿ equals Φ(ξⁿ)ᵀ w up to the matching residual. Taken
            // as Φ(ξⁿ)ᵀ w, R_{k+1} μ_{k+1} = R_k w to the rounding of two products: the
            // spatial momentum (its vertical part for the heavy top) and |μ|² no longer
            // pick up the residual's floor every step. Measured over 10⁶ steps of case A:
            // |μ|² drift 6.6e-11 → 6.6e-13.
            Matching::Exact => phi_n.transpose() * work.w,
            Matching::Paper => {
                chart.rotation_left_differential_inverse(&xi_n).transpose()
                    * work.gradient[self.d.n - 1]
            }
        };
        StepOutcome {
            attitude: base * phi_n,
            momentum,
            iterations,
            factorizations,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::inertia::Inertia;
    use crate::lagrangian::HeavyTop;

    fn top() -> HeavyTop {
        HeavyTop::new(
            Inertia::from_paper_jd([1.0, 2.8, 2.0]).unwrap(),
            1.3,
            9.81,
            Vector3::new(0.1, -0.2, 1.0),
            Vector3::new(0.3, 0.1, 1.0),
        )
        .unwrap()
    }

    fn base() -> Matrix3<f64> {
        *SO3::exp(&Vector3::new(0.4, -0.7, 0.2)).matrix()
    }

    /// The chain-rule path alone ([`jet::point_derivatives`]), as a value.
    fn chain_rule_at<L: Lagrangian>(
        system: &L,
        chart: ChartKind,
        x: &Vector3<f64>,
        v: &Vector3<f64>,
        with_configuration: bool,
        with_hessian: bool,
    ) -> PointDerivatives {
        let mut out = PointDerivatives::zeros();
        let b = base();
        let done = jet::point_derivatives(
            system,
            chart,
            &b,
            x,
            v,
            with_configuration,
            with_hessian,
            &mut out,
        );
        assert!(done, "{chart} has a Rodrigues form");
        out
    }

    /// The per-point gradient and Hessian from dual numbers against central differences of
    /// the same function in f64. Step 1e-4 for the gradient (truncation ~h²·|f'''| ≈ 1e-8·10,
    /// rounding ε|f|/h ≈ 1e-11) and 1e-4 on the gradient for the Hessian: bound 1e-6
    /// relative to the largest entry.
    #[test]
    fn point_derivatives_match_central_differences() {
        let system = top();
        for chart in ChartKind::ALL {
            let (x, v) = (Vector3::new(0.3, -0.1, 0.25), Vector3::new(1.1, 0.4, -0.6));
            let p = chain_rule_at(&system, chart, &x, &v, true, true);
            let f = |y: &SVector<f64, 9>| {
                let x = y.fixed_rows::<3>(0).into_owned();
                let v = y.fixed_rows::<3>(3).into_owned();
                let z = y.fixed_rows::<3>(6).into_owned();
                ell_tilde(&system, chart, &base(), &x, &v, Some(&z))
            };
            let y0 = SVector::<f64, 9>::from_column_slice(&[
                x.x, x.y, x.z, v.x, v.y, v.z, 0.0, 0.0, 0.0,
            ]);
            let h = 1e-4;
            let scale = p.hessian.amax().max(p.gradient.amax());
            for a in 0..9 {
                let e = SVector::<f64, 9>::from_fn(|i, _| if i == a { h } else { 0.0 });
                let fd = (f(&(y0 + e)) - f(&(y0 - e))) / (2.0 * h);
                assert!(
                    (fd - p.gradient[a]).abs() <= 1e-6 * scale,
                    "{chart} gradient {a}"
                );
                let gp = chain_rule_at(
                    &system,
                    chart,
                    &(x + e.fixed_rows::<3>(0)),
                    &(v + e.fixed_rows::<3>(3)),
                    true,
                    true,
                );
                // The ζ-columns need the function itself (the point is always at ζ = 0).
                for b in 0..6 {
                    if a < 6 {
                        let gm = chain_rule_at(
                            &system,
                            chart,
                            &(x - e.fixed_rows::<3>(0)),
                            &(v - e.fixed_rows::<3>(3)),
                            true,
                            true,
                        );
                        let fd2 = (gp.gradient[b] - gm.gradient[b]) / (2.0 * h);
                        assert!(
                            (fd2 - p.hessian[(a, b)]).abs() <= 1e-6 * scale,
                            "{chart} hessian ({a},{b})"
                        );
                    }
                }
            }
        }
    }

    /// A Lagrangian that couples `R` and `Ω` and is not linear in `R` (exercises every block
    /// of the chain rule through the default, dual-number [`Lagrangian::derivatives`]).
    struct Coupled;
    impl Lagrangian for Coupled {
        fn lagrangian<T: RealField + Copy>(&self, r: &Matrix3<T>, w: &Vector3<T>) -> T {
            let c = |x: f64| -> T { nalgebra::convert(x) };
            let up = r.transpose() * Vector3::new(c(0.2), c(-0.1), c(1.0));
            c(0.5) * (w.x * w.x * c(1.2) + w.y * w.y * c(2.1) + w.z * w.z * c(2.7))
                + up.dot(w) * c(0.3)
                + r[(0, 1)] * r[(2, 2)] * c(1.7)
                - r[(1, 0)] * c(0.4)
        }
    }

    /// A potential quadratic in `R` (through [`RigidBodyInPotential`]'s closed-form kinetic
    /// part and dual-number potential).
    struct Quadratic;
    impl crate::Potential for Quadratic {
        fn potential<T: RealField + Copy>(&self, r: &Matrix3<T>) -> T {
            let c = |x: f64| -> T { nalgebra::convert(x) };
            r[(2, 0)] * r[(2, 0)] * c(3.0) - r[(1, 2)] * c(0.5)
        }
    }

    /// The chain rule (chart Rodrigues jets and [`Lagrangian::derivatives`]) against a
    /// second-order dual number through the whole of `ℓ̃`, for every chart, system and
    /// variable set, at points from `x = 0` to rotations past 3 rad. Both are exact up to
    /// rounding, which here is a few hundred ulps of the largest entry at most (sums of
    /// tens of terms of size ~ the scale): 1e-13 relative.
    #[test]
    fn chain_rule_derivatives_match_dual_numbers() {
        let inertia = Inertia::from_paper_jd([1.0, 2.8, 2.0]).unwrap();
        let points = [
            (Vector3::zeros(), Vector3::new(1.1, 0.4, -0.6)),
            (
                Vector3::new(1e-9, -2e-9, 5e-10),
                Vector3::new(-0.3, 0.9, 0.2),
            ),
            (Vector3::new(0.3, -0.1, 0.25), Vector3::new(1.1, 0.4, -0.6)),
            (Vector3::new(-0.4, 0.2, 0.1), Vector3::new(0.5, -1.5, 2.0)),
            (Vector3::new(1.5, -2.2, 1.1), Vector3::new(2.0, 0.7, -1.0)),
        ];
        fn compare<L: Lagrangian>(system: &L, name: &str, x: &Vector3<f64>, v: &Vector3<f64>) {
            for chart in ChartKind::ALL {
                for with_configuration in [false, true] {
                    let fast = chain_rule_at(system, chart, x, v, with_configuration, true);
                    let gradient_only =
                        chain_rule_at(system, chart, x, v, with_configuration, false);
                    // The gradient-only path takes the coefficients' first derivatives
                    // from a first-order dual number instead of a second-order one: the
                    // same formulas, evaluated in another order, so a few ulps apart.
                    let size = fast.gradient.amax().max(1.0);
                    assert!(
                        (gradient_only.gradient - fast.gradient).amax()
                            <= 8.0 * f64::EPSILON * size,
                        "{chart}: {} vs {}",
                        gradient_only.gradient,
                        fast.gradient
                    );
                    let slow = point_derivatives_by_dual_numbers(
                        system,
                        chart,
                        &base(),
                        x,
                        v,
                        with_configuration,
                    );
                    let scale = slow.gradient.amax().max(slow.hessian.amax()).max(1.0);
                    let gradient = (fast.gradient - slow.gradient).amax();
                    let hessian = (fast.hessian - slow.hessian).amax();
                    assert!(
                        gradient <= 1e-13 * scale && hessian <= 1e-13 * scale,
                        "{name} {chart} x = {x:?} ζ = {with_configuration}: \
                         gradient {gradient:e}, Hessian {hessian:e} of {scale:e}"
                    );
                }
            }
        }
        for (x, v) in &points {
            compare(&crate::RigidBody::new(inertia), "rigid body", x, v);
            compare(&top(), "heavy top", x, v);
            compare(
                &crate::RigidBodyInPotential::new(inertia, Quadratic),
                "quadratic potential",
                x,
                v,
            );
            compare(&Coupled, "coupled", x, v);
        }
    }

    /// [`substitute`] on faer's LU solves the system: the residual `‖A x − b‖∞` of the
    /// computed solution is at most a small multiple of `ε ‖A‖∞ ‖x‖∞` (partial pivoting is
    /// backward stable; for these sizes the growth factor stays small), on a nonsymmetric
    /// matrix that needs row exchanges (its diagonal is small).
    #[test]
    fn substitution_on_faer_factors_solves_the_system() {
        for size in [1usize, 3, 27, 45] {
            let entry = |i: usize, j: usize| {
                let (x, y) = (i as f64, j as f64);
                (1.3 * x + 0.7 * y).sin() + if i == j { 1e-3 } else { 0.0 }
            };
            let a = Mat::from_fn(size, size, entry);
            let b: Vec<f64> = (0..size).map(|i| (0.4 * i as f64).cos() + 0.5).collect();
            let mut lu = a.clone();
            let (mut perm, mut perm_inv) = (vec![0; size], vec![0; size]);
            let mut stack = MemBuffer::new(factor::lu_in_place_scratch::<usize, f64>(
                size,
                size,
                Par::Seq,
                Default::default(),
            ));
            factor::lu_in_place(
                lu.as_mut(),
                &mut perm,
                &mut perm_inv,
                Par::Seq,
                MemStack::new(&mut stack),
                Default::default(),
            );
            let mut x: Vec<f64> = perm.iter().map(|&p| b[p]).collect();
            substitute(&lu, &mut x);
            let norm_a = (0..size)
                .map(|i| (0..size).map(|j| a[(i, j)].abs()).sum::<f64>())
                .fold(0.0, f64::max);
            let norm_x = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let residual = (0..size)
                .map(|i| ((0..size).map(|j| a[(i, j)] * x[j]).sum::<f64>() - b[i]).abs())
                .fold(0.0, f64::max);
            assert!(
                residual <= 64.0 * size as f64 * f64::EPSILON * norm_a * norm_x,
                "size {size}: residual {residual:e}, ‖A‖ {norm_a:e}, ‖x‖ {norm_x:e}"
            );
        }
    }

    /// The exact Newton matrix (both matchings, a configuration-dependent system, every
    /// chart) against forward differences of the residual away from the solution. Forward
    /// differences with step √ε·max(1, |z|) are accurate to ~√ε·|F''| ≈ 1e-7 relative.
    #[test]
    fn exact_newton_matrix_matches_differences_of_the_residual() {
        let system = top();
        for chart in ChartKind::ALL {
            for matching in [Matching::Exact, Matching::Paper] {
                let settings = StepSettings::new(0.4, 5)
                    .unwrap()
                    .with_chart(chart)
                    .with_matching(matching);
                let d = Discretisation::new(&settings).unwrap();
                let stepper = Stepper {
                    system: &system,
                    settings: &settings,
                    d: &d,
                };
                let mut work = Workspace::new(&d);
                let omega = Vector3::new(0.5, -0.8, 0.3);
                for (i, t) in d.node_times().iter().enumerate() {
                    // A curve that is not a solution: constant velocity plus a wobble.
                    work.xi[i] = omega * *t + Vector3::new(0.02, -0.01, 0.03) * (t * t);
                }
                work.xi[0] = Vector3::zeros();
                let mu = Vector3::new(2.4, -1.5, 1.52);
                stepper.assemble(&base(), &mu, &mut work, true);
                stepper.fill_jacobian(&mut work);
                let exact = work.jacobian.clone();
                stepper.fill_jacobian_by_differences(&base(), &mu, &mut work);
                let mut worst = 0.0f64;
                let mut scale = 0.0f64;
                for r in 0..exact.nrows() {
                    for c in 0..exact.ncols() {
                        worst = worst.max((exact[(r, c)] - work.jacobian[(r, c)]).abs());
                        scale = scale.max(exact[(r, c)].abs());
                    }
                }
                assert!(
                    worst <= 1e-6 * scale,
                    "{chart} {matching:?}: {worst:e} of {scale:e}"
                );
            }
        }
    }
}
