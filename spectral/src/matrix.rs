//! A small dense row-major matrix, the output of the evaluation routines.

use crate::SpectralError;
use std::ops::Index;

/// A dense `rows × cols` matrix stored row-major.
///
/// Returned by [`Barycentric::evaluation_matrix`](crate::Barycentric::evaluation_matrix)
/// and friends: row `j` holds the `n` basis functions (or their derivatives) at point
/// `j`, so a row is a contiguous slice, which is what a quadrature loop reads: that is why
/// this crate returns its own row-major type rather than `nalgebra::DMatrix` (column-major,
/// where a row is strided). [`Matrix::to_dmatrix`] (or `DMatrix::from(&m)`) gives the
/// nalgebra matrix for everything else: products, solves, decompositions.
///
/// ```
/// use lgsvi_spectral::Barycentric;
/// let basis = Barycentric::chebyshev_lobatto(3, 0.0, 1.0)?;
/// let b = basis.evaluation_matrix(&[0.0, 0.25])?;
/// assert_eq!((b.nrows(), b.ncols()), (2, 3));
/// assert_eq!(b.row(0), &[1.0, 0.0, 0.0]);
/// assert!((b[(1, 1)] - 0.75).abs() < 1e-15); // φ_1(t) = 4t(1 − t)
/// # Ok::<(), lgsvi_spectral::SpectralError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Matrix {
    rows: usize,
    cols: usize,
    data: Vec<f64>,
}

impl Matrix {
    pub(crate) fn zeros(rows: usize, cols: usize) -> Self {
        Self {
            rows,
            cols,
            data: vec![0.0; rows * cols],
        }
    }

    pub(crate) fn row_mut(&mut self, j: usize) -> &mut [f64] {
        &mut self.data[j * self.cols..(j + 1) * self.cols]
    }

    /// Number of rows.
    pub fn nrows(&self) -> usize {
        self.rows
    }

    /// Number of columns.
    pub fn ncols(&self) -> usize {
        self.cols
    }

    /// Row `j` as a slice.
    ///
    /// # Panics
    /// If `j ≥ nrows()`, like slice indexing.
    pub fn row(&self, j: usize) -> &[f64] {
        &self.data[j * self.cols..(j + 1) * self.cols]
    }

    /// All entries, row-major.
    pub fn as_slice(&self) -> &[f64] {
        &self.data
    }

    /// The product with a vector, `y_j = Σ_i M[j][i] x_i`.
    ///
    /// # Errors
    /// [`SpectralError::LengthMismatch`] if `x.len() ≠ ncols()`.
    pub fn mul_vec(&self, x: &[f64]) -> Result<Vec<f64>, SpectralError> {
        if x.len() != self.cols {
            return Err(SpectralError::LengthMismatch {
                what: "the vector multiplied",
                expected: self.cols,
                got: x.len(),
            });
        }
        Ok((0..self.rows)
            .map(|j| self.row(j).iter().zip(x).map(|(a, b)| a * b).sum())
            .collect())
    }

    /// The same matrix as a `nalgebra::DMatrix` (a copy, column-major).
    ///
    /// ```
    /// use lgsvi_spectral::Barycentric;
    /// let basis = Barycentric::chebyshev_lobatto(4, -1.0, 1.0)?;
    /// let d = basis.differentiation_matrix().to_dmatrix();
    /// // The derivative of a constant is zero: every row of D sums to 0.
    /// assert!((d * nalgebra::DVector::from_element(4, 1.0)).amax() < 1e-14);
    /// # Ok::<(), lgsvi_spectral::SpectralError>(())
    /// ```
    pub fn to_dmatrix(&self) -> nalgebra::DMatrix<f64> {
        nalgebra::DMatrix::from_row_slice(self.rows, self.cols, &self.data)
    }
}

impl Index<(usize, usize)> for Matrix {
    type Output = f64;

    /// Entry `(row, column)`.
    fn index(&self, (j, i): (usize, usize)) -> &f64 {
        assert!(
            i < self.cols,
            "column {i} out of range for {} columns",
            self.cols
        );
        &self.data[j * self.cols + i]
    }
}

impl From<&Matrix> for nalgebra::DMatrix<f64> {
    fn from(m: &Matrix) -> Self {
        m.to_dmatrix()
    }
}
