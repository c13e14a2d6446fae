//! The SQP's quadratic subproblem, solved by `clarabel`:
//!
//! ```text
//! minimise ½ δᵀ P δ + qᵀ δ   subject to   M δ = e,   lower ≤ δ ≤ upper
//! ```
//!
//! with `M` the terminal state's sensitivity (six rows) and the bounds per variable
//! (infinite where there is none).

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
    let (rows_eq, n) = m.shape();
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
    for j in 0..n {
        for i in 0..rows_eq {
            rowval.push(i);
            nzval.push(m[(i, j)]);
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
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(tolerance)
        .tol_gap_rel(tolerance)
        .tol_feas(tolerance)
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
