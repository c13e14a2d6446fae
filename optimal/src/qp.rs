//! The SQP's quadratic subproblem, solved by `clarabel`:
//!
//! ```text
//! minimise ½ δᵀ P δ + qᵀ δ   subject to   M δ = e,   lower ≤ δ ≤ upper
//! ```
//!
//! with `M` the terminal state's sensitivity (six rows) and the bounds per variable
//! (infinite where there is none), or in the banded form with the states among the
//! variables ([`solve_sparse`]: `M` then holds the steps' linearisations, sparse).

use crate::OptimalError;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus,
    SupportedConeT, ZeroConeT,
};
use nalgebra::{DMatrix, DVector};

/// The subproblem's solution: the step, the equality rows' multipliers and each
/// variable's bound multiplier (upper minus lower), so that at the solution
/// `P δ + q + Mᵀ λ + ν = 0`.
pub(crate) struct QpSolution {
    pub step: DVector<f64>,
    pub lambda: DVector<f64>,
    pub nu: DVector<f64>,
}

/// The Hessian's upper triangle in compressed columns: a diagonal or a dense matrix.
pub(crate) fn upper_triangle(p: &DMatrix<f64>) -> CscMatrix<f64> {
    let n = p.nrows();
    let (mut colptr, mut rowval, mut nzval) = (vec![0], Vec::new(), Vec::new());
    for j in 0..n {
        for i in 0..=j {
            if p[(i, j)] != 0.0 {
                rowval.push(i);
                nzval.push(p[(i, j)]);
            }
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(n, n, colptr, rowval, nzval)
}

/// Solves the subproblem; `None` where it is infeasible.
pub(crate) fn solve(
    p: CscMatrix<f64>,
    q: &[f64],
    m: &DMatrix<f64>,
    e: &DVector<f64>,
    lower: &[f64],
    upper: &[f64],
    tolerance: f64,
) -> Result<Option<QpSolution>, OptimalError> {
    let columns: Vec<Vec<(usize, f64)>> = (0..m.ncols())
        .map(|j| (0..m.nrows()).map(|i| (i, m[(i, j)])).collect())
        .collect();
    let refinement = Refinement::Default;
    solve_sparse(p, q, &columns, e, lower, upper, tolerance, refinement)
}

/// How far `clarabel` refines each of its linear solves.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Refinement {
    /// Its defaults (1e-13 relative, 1e-12 absolute, at most 10 rounds).
    Default,
    /// To rounding (at most 30 rounds): the banded subproblem has three to five times the
    /// variables of the condensed one (the states beside the inputs) and rows of both
    /// kinds, and its default refinement
    /// leaves multipliers a few 1e-10 off, which the SQP's stationarity test at 1e-10
    /// then sees (measured: the iteration stalls at 2e-10 on a 200-step tracking slew).
    Full,
}

/// [`solve`] with the equality rows `M` given by their columns' entries (row, value),
/// each column's rows increasing; `e` gives the row count.
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_sparse(
    p: CscMatrix<f64>,
    q: &[f64],
    m: &[Vec<(usize, f64)>],
    e: &DVector<f64>,
    lower: &[f64],
    upper: &[f64],
    tolerance: f64,
    refinement: Refinement,
) -> Result<Option<QpSolution>, OptimalError> {
    let (rows_eq, n) = (e.len(), m.len());
    let uppers: Vec<usize> = (0..n).filter(|&j| upper[j].is_finite()).collect();
    let lowers: Vec<usize> = (0..n).filter(|&j| lower[j].is_finite()).collect();
    let rows = rows_eq + uppers.len() + lowers.len();
    // Row index of each variable's upper and lower bound rows, if any.
    let mut upper_row = vec![None; n];
    let mut lower_row = vec![None; n];
    for (r, &j) in uppers.iter().enumerate() {
        upper_row[j] = Some(rows_eq + r);
    }
    for (r, &j) in lowers.iter().enumerate() {
        lower_row[j] = Some(rows_eq + uppers.len() + r);
    }
    let (mut colptr, mut rowval, mut nzval) = (vec![0], Vec::new(), Vec::new());
    for (j, column) in m.iter().enumerate() {
        for &(i, value) in column {
            rowval.push(i);
            nzval.push(value);
        }
        if let Some(r) = upper_row[j] {
            rowval.push(r);
            nzval.push(1.0);
        }
        if let Some(r) = lower_row[j] {
            rowval.push(r);
            nzval.push(-1.0);
        }
        colptr.push(rowval.len());
    }
    let a = CscMatrix::new(rows, n, colptr, rowval, nzval);
    let mut b: Vec<f64> = e.iter().copied().collect();
    b.extend(uppers.iter().map(|&j| upper[j]));
    b.extend(lowers.iter().map(|&j| -lower[j]));
    let mut cones: Vec<SupportedConeT<f64>> = Vec::new();
    if rows_eq > 0 {
        cones.push(ZeroConeT(rows_eq));
    }
    if rows > rows_eq {
        cones.push(NonnegativeConeT(rows - rows_eq));
    }
    let (refinement, rounds) = match refinement {
        Refinement::Default => (None, 10),
        Refinement::Full => (Some(f64::EPSILON), 30),
    };
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(tolerance)
        .tol_gap_rel(tolerance)
        .tol_feas(tolerance)
        .iterative_refinement_reltol(refinement.unwrap_or(1e-13))
        .iterative_refinement_abstol(refinement.unwrap_or(1e-12))
        .iterative_refinement_max_iter(rounds)
        .build()
        .map_err(|e| OptimalError::Subproblem(format!("{e:?}")))?;
    let mut solver = DefaultSolver::new(&p, q, &a, &b, &cones, settings)
        .map_err(|e| OptimalError::Subproblem(format!("{e:?}")))?;
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {
            let z = &solver.solution.z;
            let nu = DVector::from_iterator(
                n,
                (0..n).map(|j| {
                    upper_row[j].map_or(0.0, |r| z[r]) - lower_row[j].map_or(0.0, |r| z[r])
                }),
            );
            Ok(Some(QpSolution {
                step: DVector::from_column_slice(&solver.solution.x),
                lambda: DVector::from_column_slice(&z[..rows_eq]),
                nu,
            }))
        }
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => Ok(None),
        other => Err(OptimalError::Subproblem(format!(
            "clarabel stopped with status {other:?}"
        ))),
    }
}

/// A diagonal Hessian in compressed columns.
pub(crate) fn diagonal(d: &[f64]) -> CscMatrix<f64> {
    let n = d.len();
    CscMatrix::new(n, n, (0..=n).collect(), (0..n).collect(), d.to_vec())
}
