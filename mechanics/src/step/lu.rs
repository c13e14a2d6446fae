//! The Newton matrix's LU factorisation (partial pivoting), written for the sizes a step
//! has (`D(n − 1)`: 21 unknowns for SO(3) at `n = 8`, 42 for a body in space) and compiled
//! twice: for the x86-64 baseline and with AVX2 (chosen at run time by `multiversion`, so
//! one binary runs on any x86-64 and uses the wider registers where the processor has
//! them). The work is the update of the trailing columns, two pivots at a time: one sweep
//! down each column of the contiguous column-major storage applies both rank-one updates,
//! which the baseline leaves to the compiler's vectoriser and the AVX2 version does four
//! entries at a time in an explicit kernel ([`rank_two_update_avx`]).
//!
//! Why not faer's `lu_in_place`: at these sizes its blocked recursion spends much of its
//! time in dispatch (a `matmul` call per column of its unblocked kernel, the kernels'
//! thread-local selection) rather than arithmetic. Both versions here do the same
//! operations in the same order, a product and a subtraction each (no fused multiply-add):
//! a step's result does not depend on the processor it ran on.

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
            multiversion::target::match_target! {
                // SAFETY: this version of the function runs only where AVX is present.
                "x86_64+avx" => unsafe { rank_two_update_avx(&mut column[k + 2..], first, second, u1, u2) },
                _ => rank_two_update(&mut column[k + 2..], first, second, u1, u2),
            }
        }
        k += 2;
    }
    if k < size {
        // The last pivot of an odd size: nothing below or beside it to update.
        pivot_and_scale(data, size, perm, k);
    }
}

/// `x ← x − (l₁ u₁ + l₂ u₂)` element by element (the baseline version, which the
/// compiler vectorises as it sees fit).
#[inline(always)]
pub(super) fn rank_two_update(x: &mut [f64], l1: &[f64], l2: &[f64], u1: f64, u2: f64) {
    for ((x, a), b) in x.iter_mut().zip(l1).zip(l2) {
        *x -= a * u1 + b * u2;
    }
}

/// [`rank_two_update`] four elements at a time in AVX registers, at most three left for a
/// scalar loop. Left to itself the compiler unrolls to eight and leaves up to seven, which
/// on a step's short columns (27 entries on average at 42 unknowns, 13 at 21) costs about
/// as much as the vector part. The same products, sum and difference in the same order:
/// bit-identical to the baseline.
///
/// # Safety
/// The processor must support AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
pub(super) unsafe fn rank_two_update_avx(x: &mut [f64], l1: &[f64], l2: &[f64], u1: f64, u2: f64) {
    use std::arch::x86_64::{
        _mm256_add_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_set1_pd, _mm256_storeu_pd,
        _mm256_sub_pd,
    };
    let len = x.len();
    let (l1, l2) = (&l1[..len], &l2[..len]);
    let (v1, v2) = (_mm256_set1_pd(u1), _mm256_set1_pd(u2));
    let mut i = 0;
    while i + 4 <= len {
        // SAFETY: i + 4 ≤ len, the length of all three slices.
        unsafe {
            let a = _mm256_loadu_pd(l1.as_ptr().add(i));
            let b = _mm256_loadu_pd(l2.as_ptr().add(i));
            let y = _mm256_loadu_pd(x.as_ptr().add(i));
            let t = _mm256_add_pd(_mm256_mul_pd(a, v1), _mm256_mul_pd(b, v2));
            _mm256_storeu_pd(x.as_mut_ptr().add(i), _mm256_sub_pd(y, t));
        }
        i += 4;
    }
    // Written out rather than a call of `rank_two_update`: inlined here, the compiler
    // vectorises that loop again, overlap checks and all, for at most three entries.
    for j in i..len {
        x[j] -= l1[j] * u1 + l2[j] * u2;
    }
}
