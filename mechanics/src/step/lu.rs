//! The Newton matrix's LU factorisation (partial pivoting), written for the sizes a step
//! has (`D(n − 1)`: 21 unknowns for SO(3) at `n = 8`, 42 for a body in space) and compiled
//! twice: for the x86-64 baseline and with AVX2 (chosen at run time by `multiversion`, so
//! one binary runs on any x86-64 and uses the wider registers where the processor has
//! them). The work is the update of the trailing columns, two pivots at a time: one sweep
//! down each column of the contiguous column-major storage applies both rank-one updates,
//! which the compiler vectorises in both versions.
//!
//! Why not faer's `lu_in_place`: at these sizes its blocked recursion spends much of its
//! time in dispatch (a `matmul` call per column of its unblocked kernel, the kernels'
//! thread-local selection) rather than arithmetic (`docs/performance.md` §5.5). Both
//! versions here do the same operations in the same order, a product and a subtraction
//! each (no fused multiply-add): a step's result does not depend on the processor it ran
//! on.

use nalgebra::DMatrix;

/// Factors the square `a` in place as `P a = L U` (`L` unit lower triangular below the
/// diagonal, `U` on and above it), with row `i` of `P a` row `perm[i]` of `a`: the layout
/// [`super::newton::substitute`] reads. A zero pivot is divided by as it is (the
/// infinities and NaNs it leaves are what the Newton loop reports as a singular matrix).
pub(crate) fn lu_in_place(a: &mut DMatrix<f64>, perm: &mut [usize]) {
    let size = a.nrows();
    assert!(
        a.ncols() == size && perm.len() == size,
        "a square matrix, one row index each"
    );
    for (i, p) in perm.iter_mut().enumerate() {
        *p = i;
    }
    if size > 0 {
        factor_columns(a.as_mut_slice(), size, perm);
    }
}

/// The row of the largest entry of `column` from `from` on (the first of equal ones, as
/// LAPACK takes it).
#[inline(always)]
fn pivot_row(column: &[f64], from: usize) -> usize {
    let mut pivot = from;
    let mut largest = column[from].abs();
    for (i, x) in column.iter().enumerate().skip(from + 1) {
        if x.abs() > largest {
            largest = x.abs();
            pivot = i;
        }
    }
    pivot
}

/// Exchanges rows `k` and `pivot` of every column (and of `perm`), then divides the
/// entries of column `k` below the diagonal by the pivot: they become `L`'s multipliers.
#[inline(always)]
fn pivot_and_scale(data: &mut [f64], size: usize, perm: &mut [usize], k: usize) {
    let pivot = pivot_row(&data[k * size..(k + 1) * size], k);
    if pivot != k {
        perm.swap(k, pivot);
        for column in data.chunks_exact_mut(size) {
            column.swap(k, pivot);
        }
    }
    let column = &mut data[k * size..(k + 1) * size];
    let inverse = 1.0 / column[k];
    for x in &mut column[k + 1..] {
        *x *= inverse;
    }
}

/// The elimination on the column-major storage `data` of a `size × size` matrix, two
/// pivots at a time: columns `k` and `k + 1` are factored first (the second updated by
/// the first), then each trailing column takes both rank-one updates in one pass, so its
/// entries are read and written once per two pivots instead of once per pivot.
#[multiversion::multiversion(targets("x86_64+avx+avx2+fma"))]
fn factor_columns(data: &mut [f64], size: usize, perm: &mut [usize]) {
    let mut k = 0;
    while k + 1 < size {
        pivot_and_scale(data, size, perm, k);
        {
            let (done, rest) = data.split_at_mut((k + 1) * size);
            let first = &done[k * size..];
            let second = &mut rest[..size];
            let u = second[k];
            for (x, l) in second[k + 1..].iter_mut().zip(&first[k + 1..]) {
                *x -= l * u;
            }
        }
        pivot_and_scale(data, size, perm, k + 1);
        let (done, rest) = data.split_at_mut((k + 2) * size);
        let first = &done[k * size + k + 2..(k + 1) * size];
        let second = &done[(k + 1) * size + k + 2..(k + 2) * size];
        let between = done[k * size + k + 1];
        for column in rest.chunks_exact_mut(size) {
            let u1 = column[k];
            let u2 = column[k + 1] - between * u1;
            column[k + 1] = u2;
            for ((x, l1), l2) in column[k + 2..].iter_mut().zip(first).zip(second) {
                *x -= l1 * u1 + l2 * u2;
            }
        }
        k += 2;
    }
    if k < size {
        // The last pivot of an odd size: nothing below or beside it to update.
        pivot_and_scale(data, size, perm, k);
    }
}
