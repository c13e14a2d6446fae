//! The step's small matrix products — the points' Hessian entries, or the matching's and
//! the linearisation's point columns, times the weighted basis — written for their sizes
//! (a few dozen to a few hundred rows, `2m` terms, `n − 1` columns) and compiled twice:
//! for the x86-64 baseline and with AVX2 (chosen at run time by `multiversion`, as the LU
//! in [`super::lu`]).
//!
//! Why not faer's `matmul`: at these sizes a call costs more in dispatch and setup than in
//! arithmetic, and takes far more time than its instructions suggest, so a product written
//! for the shapes at hand is faster (the measurements are in the lab notebook,
//! `docs/notes/performance.md`). Products above [`FAER_ABOVE`] multiply-adds still go to
//! faer, whose kernels win there.
//!
//! Each output column is a combination of the left factor's columns, accumulated in
//! order of the terms. On the AVX2 path each term is a fused multiply-add, on the
//! baseline path a product and a sum: as with faer's product, the Newton matrix can
//! differ at rounding between processors with and without FMA (the LU, [`super::lu`],
//! uses none). The residual does not read this product, so a step's converged result
//! moves with it at rounding at most; a linearisation's `A`, `B` are formed from it.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};
use nalgebra::SMatrix;
use std::ops::Range;

/// Rows accumulated together in registers (four AVX2 vectors).
const BLOCK: usize = 16;

/// Products of more multiply-adds than this go to faer's `matmul`: below it a call's
/// fixed cost dominates and the hand product is faster, above it faer's blocked kernels
/// are. The SO(3) fill takes the hand product up to `n = 11` and faer's from `n = 12`.
const FAER_ABOVE: usize = 25_000;

/// `out[rows, out_cols.start + k] = Σ_p lhs[rows, p] · rhs[p, rhs_cols.start + k]` for
/// every `k < out_cols.len()`, over all of `lhs`'s columns (`rhs`'s rows), replacing what
/// `out` held there.
///
/// # Panics
/// If the ranges do not fit the matrices or disagree in length, or `lhs.ncols() !=
/// rhs.nrows()` (the callers' tables are built to fit; a panic is a bug here).
pub(crate) fn replace_product(
    out: &mut Mat<f64>,
    rows: Range<usize>,
    out_cols: Range<usize>,
    lhs: &Mat<f64>,
    rhs: &Mat<f64>,
    rhs_cols: Range<usize>,
) {
    assert!(
        out_cols.len() == rhs_cols.len()
            && lhs.ncols() == rhs.nrows()
            && rows.end <= out.nrows()
            && rows.end <= lhs.nrows()
            && out_cols.end <= out.ncols()
            && rhs_cols.end <= rhs.ncols(),
        "the product's shapes agree"
    );
    let terms = lhs.ncols();
    if rows.len() * terms * out_cols.len() > FAER_ABOVE {
        matmul(
            out.as_mut()
                .subrows_mut(rows.start, rows.len())
                .subcols_mut(out_cols.start, out_cols.len()),
            Accum::Replace,
            lhs.as_ref().subrows(rows.start, rows.len()),
            rhs.as_ref().subcols(rhs_cols.start, rhs_cols.len()),
            1.0,
            Par::Seq,
        );
        return;
    }
    by_columns(out, rows, out_cols, lhs, rhs, rhs_cols, combine);
}

/// Each column of the product by `kernel` ([`combine`] or [`combine_even`]). faer stores a
/// matrix by columns with a row stride of one: every column cut to `rows` is a contiguous
/// slice. Without terms each block writes its empty sum, zero.
#[inline(always)]
fn by_columns(
    out: &mut Mat<f64>,
    rows: Range<usize>,
    out_cols: Range<usize>,
    lhs: &Mat<f64>,
    rhs: &Mat<f64>,
    rhs_cols: Range<usize>,
    kernel: fn(&mut [f64], &Mat<f64>, usize, &[f64]),
) {
    for (k, r) in out_cols.zip(rhs_cols) {
        let coefficients = rhs.col_as_slice(r);
        let target = &mut out.col_as_slice_mut(k)[rows.clone()];
        kernel(target, lhs, rows.start, coefficients);
    }
}

/// [`replace_product`] over the even columns of `lhs` (rows of `rhs`) alone: the product
/// when the odd columns of `lhs` are zero (the matching's `∂q/∂v` where no force reads
/// the velocity), each of which would add an exact zero to its sum (`a + c·0 = a` for
/// finite `a` and `c`; a sum starts at `+0` and `+0 + (−0) = +0`, so not even a zero's
/// sign differs): the same values bit for bit. Where the whole product has more than
/// [`FAER_ABOVE`] multiply-adds it is the whole product, as there.
///
/// # Panics
/// As [`replace_product`].
pub(crate) fn replace_product_even(
    out: &mut Mat<f64>,
    rows: Range<usize>,
    out_cols: Range<usize>,
    lhs: &Mat<f64>,
    rhs: &Mat<f64>,
    rhs_cols: Range<usize>,
) {
    if rows.len() * lhs.ncols() * out_cols.len() > FAER_ABOVE
        || out_cols.len() != rhs_cols.len()
        || lhs.ncols() != rhs.nrows()
    {
        // The whole product (which also checks the shapes).
        replace_product(out, rows, out_cols, lhs, rhs, rhs_cols);
        return;
    }
    by_columns(out, rows, out_cols, lhs, rhs, rhs_cols, combine_even);
}

/// `target = Σ_p coefficients[p] · lhs[offset.., p]` (cut to `target`'s length), the
/// terms in order, `BLOCK` rows at a time, the rest four at a time (one at a time below
/// four rows, nine rows at once); each term a fused multiply-add where the processor has
/// one.
#[multiversion::multiversion(targets("x86_64+avx+avx2+fma"))]
fn combine(target: &mut [f64], lhs: &Mat<f64>, offset: usize, coefficients: &[f64]) {
    if multiversion::target::target_cfg_f!(target_feature = "fma") {
        combine_blocks::<true, 1>(target, lhs, offset, coefficients);
    } else {
        combine_blocks::<false, 1>(target, lhs, offset, coefficients);
    }
}

/// [`combine`] over the even terms alone (`p = 0, 2, 4, …`), in order.
#[multiversion::multiversion(targets("x86_64+avx+avx2+fma"))]
fn combine_even(target: &mut [f64], lhs: &Mat<f64>, offset: usize, coefficients: &[f64]) {
    if multiversion::target::target_cfg_f!(target_feature = "fma") {
        combine_blocks::<true, 2>(target, lhs, offset, coefficients);
    } else {
        combine_blocks::<false, 2>(target, lhs, offset, coefficients);
    }
}

/// [`combine`] by blocks: `BLOCK` rows, then the rest in one block moved back to end at
/// the last row (below four rows, one row at a time; nine rows, one block); every
/// `STRIDE`-th term (one or two) from the first.
#[inline(always)]
fn combine_blocks<const FMA: bool, const STRIDE: usize>(
    target: &mut [f64],
    lhs: &Mat<f64>,
    offset: usize,
    coefficients: &[f64],
) {
    let rows = target.len();
    // Nine rows (`D²` for SO(3): the matching's `∂w/∂ξ` of an attitude-dependent `ℓ`) in
    // one block: by fours it would take three passes over the terms, and the loop over the
    // terms is what a block costs.
    if rows == 9 {
        block::<9, FMA, STRIDE>(target, lhs, offset, coefficients, 0);
        return;
    }
    if rows < 4 {
        for start in 0..rows {
            block::<1, FMA, STRIDE>(target, lhs, offset, coefficients, start);
        }
        return;
    }
    let whole = rows / BLOCK * BLOCK;
    for start in (0..whole).step_by(BLOCK) {
        block::<BLOCK, FMA, STRIDE>(target, lhs, offset, coefficients, start);
    }
    // The rest in one block moved back to end at the last row (of four rows if it fits
    // there, else of `BLOCK`), or by fours below `BLOCK` rows: the rows a block repeats
    // get the same operations in the same order, so the same values. One wide block costs
    // about what one block of four does (the loop over the terms dominates).
    let rest = rows - whole;
    if whole > 0 && rest > 4 {
        block::<BLOCK, FMA, STRIDE>(target, lhs, offset, coefficients, rows - BLOCK);
        return;
    }
    let mut start = whole;
    while start < rows {
        block::<4, FMA, STRIDE>(target, lhs, offset, coefficients, start.min(rows - 4));
        start += 4;
    }
}

/// Rows `start..start + R` of [`combine`]'s sum over every `STRIDE`-th term (one or
/// two), accumulated in registers. The two strides are two loops: one loop for both, by
/// `step_by`, costs more per term than a plain loop.
#[inline(always)]
fn block<const R: usize, const FMA: bool, const STRIDE: usize>(
    target: &mut [f64],
    lhs: &Mat<f64>,
    offset: usize,
    coefficients: &[f64],
    start: usize,
) {
    let mut acc = [0.0f64; R];
    if STRIDE == 1 {
        for (p, &c) in coefficients.iter().enumerate() {
            add_term::<R, FMA>(&mut acc, c, &lhs.col_as_slice(p)[offset + start..]);
        }
    } else {
        for (q, pair) in coefficients.chunks(2).enumerate() {
            add_term::<R, FMA>(
                &mut acc,
                pair[0],
                &lhs.col_as_slice(2 * q)[offset + start..],
            );
        }
    }
    target[start..start + R].copy_from_slice(&acc);
}

/// `acc += c · column[..R]`, a fused multiply-add per entry where `FMA`.
#[inline(always)]
fn add_term<const R: usize, const FMA: bool>(acc: &mut [f64; R], c: f64, column: &[f64]) {
    let column = &column[..R];
    for i in 0..R {
        acc[i] = if FMA {
            c.mul_add(column[i], acc[i])
        } else {
            acc[i] + c * column[i]
        };
    }
}

/// `a · b` for fixed-size matrices, inlined where it is used: the same sums in the same
/// order as nalgebra's product (each entry `Σ_p a_ip b_pk` accumulated from `p = 0`, a
/// product and a sum per term), so the same values bit for bit (test
/// `the_fixed_product_is_nalgebras_bit_for_bit`). nalgebra's generic product is not
/// inlined at `6 × 6`, and as calls the matching's products (the Gauss points' `∂q` and
/// the matching rows on the orbiting body) cost noticeably more than inlined.
#[inline(always)]
pub(crate) fn fixed_product<const R: usize, const K: usize, const C: usize>(
    a: &SMatrix<f64, R, K>,
    b: &SMatrix<f64, K, C>,
) -> SMatrix<f64, R, C> {
    let mut out = SMatrix::<f64, R, C>::zeros();
    for c in 0..C {
        let mut column = [0.0f64; R];
        if K > 0 {
            let (first, b0) = (a.fixed_columns::<1>(0), b[(0, c)]);
            for (i, entry) in column.iter_mut().enumerate() {
                *entry = first[i] * b0;
            }
        }
        for p in 1..K {
            let (lhs, coefficient) = (a.column(p), b[(p, c)]);
            for (i, entry) in column.iter_mut().enumerate() {
                *entry += lhs[i] * coefficient;
            }
        }
        out.column_mut(c).copy_from_slice(&column);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic, irregular test matrix (no two entries alike, mixed signs).
    fn matrix(rows: usize, cols: usize, seed: f64) -> Mat<f64> {
        Mat::from_fn(rows, cols, |i, j| {
            ((i as f64 + 1.3) * (j as f64 + 0.7) * seed).sin() * (1.0 + j as f64)
        })
    }

    /// Against the product by its definition, summed in the same order: every block
    /// size's path (16, 9, 4 and 1 rows: row counts 0 … 41 from several offsets), every
    /// column range. The sums differ from the definition's only by the fused
    /// multiply-add's rounding: each of the `terms` sums is within `terms` roundings
    /// of the definition's, `terms · ε · Σ|a_ip b_pk|`.
    #[test]
    fn replaces_its_block_by_the_product() {
        let terms = 9;
        let lhs = matrix(45, terms, 0.37);
        let rhs = matrix(terms, 6, 1.91);
        for start in [0, 1, 3] {
            for len in 0..=41 {
                let rows = start..start + len;
                let mut out = Mat::from_fn(46, 7, |_, _| f64::NAN);
                replace_product(&mut out, rows.clone(), 2..6, &lhs, &rhs, 1..5);
                for k in 0..7 {
                    for i in 0..46 {
                        let written = rows.contains(&i) && (2..6).contains(&k);
                        if !written {
                            // What the product must leave alone.
                            assert!(out[(i, k)].is_nan(), "({i}, {k}) was overwritten");
                            continue;
                        }
                        let (mut exact, mut scale) = (0.0, 0.0);
                        for p in 0..terms {
                            exact += lhs[(i, p)] * rhs[(p, k - 1)];
                            scale += (lhs[(i, p)] * rhs[(p, k - 1)]).abs();
                        }
                        let bound = terms as f64 * f64::EPSILON * scale;
                        assert!(
                            (out[(i, k)] - exact).abs() <= bound,
                            "({i}, {k}): {} against {exact}",
                            out[(i, k)]
                        );
                    }
                }
            }
        }
    }

    /// A product above [`FAER_ABOVE`] multiply-adds (faer's kernels): the same bound,
    /// and the rows and columns outside the block left alone.
    #[test]
    fn a_large_product_is_the_product_too() {
        let terms = 40;
        let lhs = matrix(300, terms, 0.11);
        let rhs = matrix(terms, 5, 2.3);
        let rows = 7..290;
        assert!(rows.len() * terms * 3 > FAER_ABOVE);
        let mut out = Mat::from_fn(300, 6, |_, _| f64::NAN);
        replace_product(&mut out, rows.clone(), 1..4, &lhs, &rhs, 2..5);
        for k in 0..6 {
            for i in 0..300 {
                if !(rows.contains(&i) && (1..4).contains(&k)) {
                    assert!(out[(i, k)].is_nan(), "({i}, {k}) was overwritten");
                    continue;
                }
                let (mut exact, mut scale) = (0.0, 0.0);
                for p in 0..terms {
                    exact += lhs[(i, p)] * rhs[(p, k + 1)];
                    scale += (lhs[(i, p)] * rhs[(p, k + 1)]).abs();
                }
                assert!((out[(i, k)] - exact).abs() <= terms as f64 * f64::EPSILON * scale);
            }
        }
    }

    /// Each path against its definition summed in order, bit for bit: a product and a sum
    /// (the baseline), or a fused multiply-add, per term, whatever the block that computes
    /// the row (overlapping blocks included).
    #[test]
    fn each_path_sums_its_terms_in_order() {
        let terms = 7;
        let lhs = matrix(40, terms, 0.53);
        let rhs = matrix(terms, 1, 1.7);
        let coefficients = rhs.col_as_slice(0);
        for offset in [0, 2] {
            for len in 0..=38 {
                let mut plain = vec![f64::NAN; len];
                let mut fused = vec![f64::NAN; len];
                combine_blocks::<false, 1>(&mut plain, &lhs, offset, coefficients);
                combine_blocks::<true, 1>(&mut fused, &lhs, offset, coefficients);
                for i in 0..len {
                    let (mut by_sum, mut by_fma) = (0.0f64, 0.0f64);
                    for (p, &c) in coefficients.iter().enumerate() {
                        by_sum += c * lhs[(offset + i, p)];
                        by_fma = c.mul_add(lhs[(offset + i, p)], by_fma);
                    }
                    assert_eq!(plain[i].to_bits(), by_sum.to_bits(), "row {i} of {len}");
                    assert_eq!(fused[i].to_bits(), by_fma.to_bits(), "row {i} of {len}");
                }
            }
        }
    }

    /// The product over the even terms is the whole product, bit for bit, when the odd
    /// columns of `lhs` are zero (of either sign, as `∂q/∂v` written by a product of zeros
    /// may be): every block size's path (16, 9, 4 and 1 rows; odd and even term counts),
    /// and the whole product above [`FAER_ABOVE`]. With a nonzero odd column it is not
    /// (the odd terms are really skipped, so the caller's test of them matters).
    #[test]
    fn the_even_product_is_the_product_when_the_odd_terms_are_zero() {
        for (terms, len) in [(16, 36), (16, 9), (9, 21), (8, 5), (7, 3), (16, 0)] {
            let mut lhs = matrix(len + 3, terms, 0.71);
            for p in (1..terms).step_by(2) {
                for i in 0..len + 3 {
                    lhs[(i, p)] = if (i + p) % 3 == 0 { -0.0 } else { 0.0 };
                }
            }
            let rhs = matrix(terms, 8, 1.3);
            let rows = 2..len + 2;
            let mut whole = Mat::from_fn(len + 3, 8, |_, _| f64::NAN);
            let mut even = whole.clone();
            replace_product(&mut whole, rows.clone(), 1..8, &lhs, &rhs, 1..8);
            replace_product_even(&mut even, rows.clone(), 1..8, &lhs, &rhs, 1..8);
            for k in 0..8 {
                for i in 0..len + 3 {
                    assert_eq!(
                        whole[(i, k)].to_bits(),
                        even[(i, k)].to_bits(),
                        "({i}, {k}), {terms} terms, {len} rows"
                    );
                }
            }
            if len > 0 && terms > 1 {
                lhs[(2, 1)] = 0.5;
                replace_product(&mut whole, rows.clone(), 1..8, &lhs, &rhs, 1..8);
                replace_product_even(&mut even, rows, 1..8, &lhs, &rhs, 1..8);
                assert_ne!(whole[(2, 1)], even[(2, 1)], "{terms} terms, {len} rows");
            }
        }
        // Above FAER_ABOVE both are faer's product of all the terms.
        let terms = 40;
        let lhs = matrix(300, terms, 0.11);
        let rhs = matrix(terms, 5, 2.3);
        assert!(280 * terms * 3 > FAER_ABOVE);
        let mut whole = Mat::from_fn(300, 6, |_, _| f64::NAN);
        let mut even = whole.clone();
        replace_product(&mut whole, 10..290, 1..4, &lhs, &rhs, 2..5);
        replace_product_even(&mut even, 10..290, 1..4, &lhs, &rhs, 2..5);
        for k in 1..4 {
            for i in 10..290 {
                assert_eq!(
                    whole[(i, k)].to_bits(),
                    even[(i, k)].to_bits(),
                    "({i}, {k})"
                );
            }
        }
    }

    /// No terms: the block is zero (an empty sum), nothing else is touched.
    #[test]
    fn an_empty_sum_is_zero() {
        let lhs = Mat::<f64>::zeros(5, 0);
        let rhs = Mat::<f64>::zeros(0, 3);
        let mut out = Mat::from_fn(5, 3, |_, _| 7.0);
        replace_product(&mut out, 1..4, 0..2, &lhs, &rhs, 1..3);
        for i in 0..5 {
            for k in 0..3 {
                let expected = if (1..4).contains(&i) && k < 2 {
                    0.0
                } else {
                    7.0
                };
                assert_eq!(out[(i, k)], expected);
            }
        }
    }

    /// [`fixed_product`] against nalgebra's product, bit for bit, at the sizes the step
    /// uses (3 and 6, square and not) on irregular entries of mixed sign and magnitude.
    #[test]
    fn the_fixed_product_is_nalgebras_bit_for_bit() {
        fn entries<const R: usize, const C: usize>(seed: f64) -> SMatrix<f64, R, C> {
            SMatrix::from_fn(|i, j| {
                ((i as f64 + 1.7) * (j as f64 + 0.3) * seed).sin()
                    * 10f64.powi((i as i32 * 3 + j as i32) % 7 - 3)
            })
        }
        fn check<const R: usize, const K: usize, const C: usize>(seed: f64) {
            let (a, b) = (entries::<R, K>(seed), entries::<K, C>(seed * 1.37 + 0.2));
            let (ours, theirs) = (fixed_product(&a, &b), a * b);
            for (x, y) in ours.iter().zip(theirs.iter()) {
                assert_eq!(x.to_bits(), y.to_bits(), "{R}×{K}·{K}×{C}: {x} against {y}");
            }
        }
        for seed in [0.31, 1.9, 7.3, 11.05] {
            check::<6, 6, 6>(seed);
            check::<3, 3, 3>(seed);
            check::<6, 6, 1>(seed);
            check::<3, 6, 6>(seed);
            check::<6, 3, 2>(seed);
        }
    }
}
