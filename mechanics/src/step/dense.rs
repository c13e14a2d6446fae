//! The dense LU factorisation of a step's Newton matrix (partial pivoting) and the
//! substitutions that solve with it.
//!
//! A step's Newton matrix has `D(n − 1)` rows (27 for the rigid body at `n = 10`). At these
//! sizes a blocked LU spends more in dispatch, recursion and permutation bookkeeping than
//! in arithmetic. Measured (one process, best of 5 × 20000 factorisations of the same
//! nonsymmetric matrix, this machine): the unblocked column-major elimination below takes
//! 0.25, 0.75, 1.57, 2.80, 4.66, 6.57 µs at 9, 15, 21, 27, 33, 39 rows against faer's
//! `lu_in_place` 0.57, 1.35, 2.38, 3.33, 5.10, 6.24 µs; faer's blocked, vectorised kernel
//! wins from about 40 rows on (8.8 against 9.6 µs at 45, 21.5 against 31.6 µs at 69). So
//! the elimination below runs up to [`BLOCKED_FROM`] rows and faer's above, on the same
//! column-major storage. (A row-major elimination was 10% faster still, but faer's kernel
//! on a row-major view loses its unit stride: measured 13 µs slower per step at `n = 24`.)

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor;
use faer::{MatMut, Par};

/// From this many rows on, faer's blocked LU is faster (module documentation).
const BLOCKED_FROM: usize = 40;

/// A dense square matrix stored by columns, indexed `[(row, column)]`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct SquareMatrix {
    size: usize,
    data: Vec<f64>,
}

impl SquareMatrix {
    pub fn zeros(size: usize) -> Self {
        Self {
            size,
            data: vec![0.0; size * size],
        }
    }

    /// The number of rows (and columns).
    pub fn size(&self) -> usize {
        self.size
    }

    /// Column `k`.
    #[inline]
    pub fn col(&self, k: usize) -> &[f64] {
        &self.data[k * self.size..(k + 1) * self.size]
    }
}

impl std::ops::Index<(usize, usize)> for SquareMatrix {
    type Output = f64;
    #[inline]
    fn index(&self, (row, col): (usize, usize)) -> &f64 {
        &self.data[col * self.size + row]
    }
}

impl std::ops::IndexMut<(usize, usize)> for SquareMatrix {
    #[inline]
    fn index_mut(&mut self, (row, col): (usize, usize)) -> &mut f64 {
        &mut self.data[col * self.size + row]
    }
}

/// The factorisation's buffers: the row permutation, and faer's for the large sizes.
pub(crate) struct LuBuffers {
    /// `perm[i]`: the row of the original matrix now at row `i` (`P b` is `b[perm[i]]`).
    pub perm: Vec<usize>,
    perm_inv: Vec<usize>,
    stack: MemBuffer,
}

impl LuBuffers {
    pub fn new(size: usize) -> Self {
        let scratch = if size >= BLOCKED_FROM {
            factor::lu_in_place_scratch::<usize, f64>(size, size, Par::Seq, Default::default())
        } else {
            faer::dyn_stack::StackReq::EMPTY
        };
        Self {
            perm: vec![0; size],
            perm_inv: vec![0; size],
            stack: MemBuffer::new(scratch),
        }
    }
}

/// Factors `a` in place as `P a = L U` (unit lower `L` below the diagonal, `U` on and
/// above it) with partial pivoting; the permutation goes to `buffers.perm`. A zero pivot
/// leaves infinities or NaNs in `U`, which the caller sees in its solution (no panic).
pub(crate) fn lu_in_place(a: &mut SquareMatrix, buffers: &mut LuBuffers) {
    let size = a.size();
    if size >= BLOCKED_FROM {
        let view = MatMut::from_column_major_slice_mut(&mut a.data, size, size);
        factor::lu_in_place(
            view,
            &mut buffers.perm,
            &mut buffers.perm_inv,
            Par::Seq,
            MemStack::new(&mut buffers.stack),
            Default::default(),
        );
        return;
    }
    eliminate(&mut a.data, size, &mut buffers.perm);
}

/// Gaussian elimination with partial pivoting on a column-major `size × size` array:
/// after the pivot's row exchange, column `k` becomes the multipliers and every later
/// column loses its multiple of them (one contiguous axpy per column).
fn eliminate(data: &mut [f64], size: usize, perm: &mut [usize]) {
    for (i, p) in perm.iter_mut().enumerate().take(size) {
        *p = i;
    }
    for k in 0..size {
        // The pivot: the largest entry of column k on or below the diagonal.
        let column = &data[k * size..(k + 1) * size];
        let mut pivot = k;
        let mut largest = column[k].abs();
        for (i, value) in column.iter().enumerate().skip(k + 1) {
            if value.abs() > largest {
                largest = value.abs();
                pivot = i;
            }
        }
        if pivot != k {
            perm.swap(k, pivot);
            for j in 0..size {
                data.swap(j * size + k, j * size + pivot);
            }
        }
        let (head, trailing) = data.split_at_mut((k + 1) * size);
        let column = &mut head[k * size..];
        let inverse = 1.0 / column[k];
        for value in &mut column[k + 1..] {
            *value *= inverse;
        }
        let multipliers = &column[k + 1..];
        for later in trailing.chunks_exact_mut(size) {
            let u = later[k];
            if u != 0.0 {
                for (value, l) in later[k + 1..].iter_mut().zip(multipliers) {
                    *value -= l * u;
                }
            }
        }
    }
}

/// Solves `L U x = b` in place, with `L U` the unit-lower and upper factors that
/// [`lu_in_place`] left in `lu` (the row permutation already applied to `b`): forward
/// and back substitution by columns.
pub(crate) fn substitute(lu: &SquareMatrix, b: &mut [f64]) {
    let size = b.len();
    for k in 0..size {
        let bk = b[k];
        let below = &lu.col(k)[k + 1..];
        for (x, l) in b[k + 1..].iter_mut().zip(below) {
            *x -= l * bk;
        }
    }
    for k in (0..size).rev() {
        let column = lu.col(k);
        b[k] /= column[k];
        let bk = b[k];
        for (x, u) in b[..k].iter_mut().zip(&column[..k]) {
            *x -= u * bk;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The factors solve the system: the residual `‖A x − b‖∞` of the computed solution is
    /// at most a small multiple of `ε ‖A‖∞ ‖x‖∞` (partial pivoting is backward stable; at
    /// these sizes the growth factor stays small), on nonsymmetric matrices that need row
    /// exchanges (their diagonal is small), and `P A = L U` holds entry by entry.
    #[test]
    fn factors_reproduce_the_matrix_and_solve_the_system() {
        // Both kernels: the elimination below BLOCKED_FROM rows, faer's from it.
        for size in [1usize, 2, 3, 27, 39, 40, 69] {
            let entry = |i: usize, j: usize| {
                let (x, y) = (i as f64, j as f64);
                (1.3 * x + 0.7 * y).sin() + if i == j { 1e-3 } else { 0.0 }
            };
            let mut a = SquareMatrix::zeros(size);
            for i in 0..size {
                for j in 0..size {
                    a[(i, j)] = entry(i, j);
                }
            }
            let b: Vec<f64> = (0..size).map(|i| (0.4 * i as f64).cos() + 0.5).collect();
            let mut lu = a.clone();
            let mut buffers = LuBuffers::new(size);
            lu_in_place(&mut lu, &mut buffers);
            let perm = buffers.perm.clone();
            let mut sorted = perm.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..size).collect::<Vec<_>>(), "a permutation");
            if size >= 3 {
                assert!(
                    perm.iter().enumerate().any(|(i, &p)| i != p),
                    "rows exchanged"
                );
            }
            let norm_a = (0..size)
                .map(|i| (0..size).map(|j| a[(i, j)].abs()).sum::<f64>())
                .fold(0.0f64, f64::max);
            for i in 0..size {
                for j in 0..size {
                    let product: f64 = (0..=i.min(j))
                        .map(|k| {
                            let l = if k == i { 1.0 } else { lu[(i, k)] };
                            l * lu[(k, j)]
                        })
                        .sum();
                    assert!(
                        (product - a[(perm[i], j)]).abs() <= 1e3 * f64::EPSILON * norm_a,
                        "size {size}: (LU)[{i},{j}] = {product} against {}",
                        a[(perm[i], j)]
                    );
                }
            }
            let mut x: Vec<f64> = perm.iter().map(|&p| b[p]).collect();
            substitute(&lu, &mut x);
            let norm_x = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (i, bi) in b.iter().enumerate() {
                let ax: f64 = (0..size).map(|j| a[(i, j)] * x[j]).sum();
                assert!(
                    (ax - bi).abs() <= 64.0 * size as f64 * f64::EPSILON * norm_a * norm_x,
                    "size {size}, row {i}: {ax} against {bi}"
                );
            }
        }
    }

    /// A singular matrix leaves non-finite numbers in the solution, not a panic: the
    /// Newton loop reports them as a singular Jacobian.
    #[test]
    fn a_singular_matrix_gives_non_finite_numbers() {
        // Rank one: every row (1, 1, 0).
        let mut lu = SquareMatrix::zeros(3);
        for i in 0..3 {
            lu[(i, 0)] = 1.0;
            lu[(i, 1)] = 1.0;
        }
        let mut buffers = LuBuffers::new(3);
        lu_in_place(&mut lu, &mut buffers);
        let mut x = vec![1.0, 2.0, 3.0];
        substitute(&lu, &mut x);
        assert!(x.iter().any(|v| !v.is_finite()));
    }
}
