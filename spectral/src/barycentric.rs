//! Barycentric Lagrange interpolation (Berrut & Trefethen, *SIAM Review* 46, 2004).

use crate::matrix::Matrix;
use crate::nodes::{chebyshev_first_kind, chebyshev_lobatto};
use crate::SpectralError;
use std::f64::consts::PI;

/// The Lagrange basis `φ_0, …, φ_{n−1}` of a set of distinct nodes (`φ_i(x_k) = δ_ik`),
/// evaluated by the barycentric formula.
///
/// For `x` not a node, `φ_i(x) = (w_i/(x − x_i)) / Σ_k w_k/(x − x_k)` with barycentric
/// weights `w_i ∝ 1/Π_{k≠i}(x_i − x_k)`. Every evaluation is taken relative to the node
/// `x_p` nearest to `x`, with numerators scaled by `x − x_p`, so the formulas stay finite
/// and accurate exactly at a node (where they return `δ_ip` and the differentiation
/// matrix row) and arbitrarily close to one (no 0/0, no cancellation in `1 − φ_p`).
/// First derivatives use `φ_i' = φ_i (Σ_k φ_k/(x − x_k) − 1/(x − x_i))` in the same scaled
/// form for `i ≠ p`, and `φ_p' = −Σ_{i≠p} φ_i'` (the basis sums to one).
///
/// For Chebyshev nodes the weights have closed forms and interpolation is stable for any
/// `n` (the Lebesgue constant grows like `(2/π) log n`).
///
/// # Example
/// ```
/// use lgsvi_spectral::Barycentric;
/// // Interpolate e^x on 16 Chebyshev–Lobatto nodes in [0, 1].
/// let basis = Barycentric::chebyshev_lobatto(16, 0.0, 1.0)?;
/// let values: Vec<f64> = basis.nodes().iter().map(|x| x.exp()).collect();
/// let x = 0.3;
/// assert!((basis.interpolate(&values, x)? - x.exp()).abs() < 1e-15);
/// assert!((basis.interpolate_derivative(&values, x)? - x.exp()).abs() < 1e-13);
/// # Ok::<(), lgsvi_spectral::SpectralError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Barycentric {
    nodes: Vec<f64>,
    weights: Vec<f64>,
}

impl Barycentric {
    /// The basis of arbitrary distinct finite nodes (any order), with weights
    /// `1/Π_{k≠i}(x_i − x_k)` computed in logarithms and scaled so the largest is 1.
    /// `O(n²)`.
    ///
    /// # Errors
    /// [`SpectralError::TooFewNodes`] for no nodes, [`SpectralError::NonFiniteNode`],
    /// [`SpectralError::DuplicateNode`], and [`SpectralError::WeightUnderflow`] for node
    /// sets too ill-conditioned for double precision (e.g. 1100 equispaced nodes).
    ///
    /// ```
    /// use lgsvi_spectral::Barycentric;
    /// let basis = Barycentric::new(vec![0.0, 1.0, 3.0])?;
    /// // The quadratic through (0,0), (1,1), (3,9) is x².
    /// assert!((basis.interpolate(&[0.0, 1.0, 9.0], 2.0)? - 4.0).abs() < 1e-14);
    /// assert!(Barycentric::new(vec![0.0, 1.0, 0.0]).is_err());
    /// # Ok::<(), lgsvi_spectral::SpectralError>(())
    /// ```
    pub fn new(nodes: Vec<f64>) -> Result<Self, SpectralError> {
        let n = nodes.len();
        if n == 0 {
            return Err(SpectralError::TooFewNodes {
                kind: "a Lagrange basis",
                n,
                min: 1,
            });
        }
        if let Some(index) = nodes.iter().position(|x| !x.is_finite()) {
            return Err(SpectralError::NonFiniteNode {
                index,
                value: nodes[index],
            });
        }
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&i, &j| nodes[i].total_cmp(&nodes[j]));
        if let Some(w) = order.windows(2).find(|w| nodes[w[0]] == nodes[w[1]]) {
            return Err(SpectralError::DuplicateNode {
                first: w[0].min(w[1]),
                second: w[0].max(w[1]),
                value: nodes[w[0]],
            });
        }
        // log|w_i| = −Σ ln|x_i − x_k|, sign from the number of negative factors.
        let log_and_sign: Vec<(f64, bool)> = (0..n)
            .map(|i| {
                let mut log = 0.0;
                let mut negative = false;
                for k in (0..n).filter(|&k| k != i) {
                    let d = nodes[i] - nodes[k];
                    log -= d.abs().ln();
                    negative ^= d < 0.0;
                }
                (log, negative)
            })
            .collect();
        let max_log = log_and_sign
            .iter()
            .map(|&(l, _)| l)
            .fold(f64::NEG_INFINITY, f64::max);
        let weights: Vec<f64> = log_and_sign
            .iter()
            .map(|&(l, negative)| {
                let magnitude = (l - max_log).exp();
                if negative {
                    -magnitude
                } else {
                    magnitude
                }
            })
            .collect();
        if let Some(index) = weights.iter().position(|w| *w == 0.0) {
            return Err(SpectralError::WeightUnderflow { index, n });
        }
        Ok(Self { nodes, weights })
    }

    /// The basis on the `n` Chebyshev–Lobatto points of `[a, b]`
    /// ([`chebyshev_lobatto`](crate::chebyshev_lobatto)), with the closed-form weights
    /// `w_j = (−1)^j δ_j`, `δ_j = ½` at the ends and 1 inside.
    ///
    /// # Errors
    /// As [`chebyshev_lobatto`](crate::chebyshev_lobatto): `n ≥ 2` and finite `a < b`.
    pub fn chebyshev_lobatto(n: usize, a: f64, b: f64) -> Result<Self, SpectralError> {
        let nodes = chebyshev_lobatto(n, a, b)?;
        let weights = (0..n)
            .map(|j| {
                let sign = if j.is_multiple_of(2) { 1.0 } else { -1.0 };
                if j == 0 || j == n - 1 {
                    0.5 * sign
                } else {
                    sign
                }
            })
            .collect();
        Ok(Self { nodes, weights })
    }

    /// The basis on the `n` Chebyshev points of the first kind of `[a, b]`
    /// ([`chebyshev_first_kind`](crate::chebyshev_first_kind)), with the closed-form
    /// weights `w_j = (−1)^j sin((2j + 1)π/(2n))`.
    ///
    /// # Errors
    /// As [`chebyshev_first_kind`](crate::chebyshev_first_kind): `n ≥ 1` and finite `a < b`.
    pub fn chebyshev_first_kind(n: usize, a: f64, b: f64) -> Result<Self, SpectralError> {
        let nodes = chebyshev_first_kind(n, a, b)?;
        let weights = (0..n)
            .map(|j| {
                let sign = if j.is_multiple_of(2) { 1.0 } else { -1.0 };
                sign * (PI * (2 * j + 1) as f64 / (2 * n) as f64).sin()
            })
            .collect();
        Ok(Self { nodes, weights })
    }

    /// The nodes, in the order given (ascending for the Chebyshev constructors).
    pub fn nodes(&self) -> &[f64] {
        &self.nodes
    }

    /// The barycentric weights (defined up to a common factor).
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// Number of nodes `n`; the polynomial degree is `n − 1`.
    pub fn num_nodes(&self) -> usize {
        self.nodes.len()
    }

    fn check_point(x: f64) -> Result<(), SpectralError> {
        if x.is_finite() {
            Ok(())
        } else {
            Err(SpectralError::NonFinitePoint { value: x })
        }
    }

    fn check_len(&self, what: &'static str, got: usize) -> Result<(), SpectralError> {
        if got == self.num_nodes() {
            Ok(())
        } else {
            Err(SpectralError::LengthMismatch {
                what,
                expected: self.num_nodes(),
                got,
            })
        }
    }

    /// Index of the node nearest to `x`.
    fn nearest(&self, x: f64) -> usize {
        let mut best = 0;
        let mut best_distance = f64::INFINITY;
        for (k, &xk) in self.nodes.iter().enumerate() {
            let d = (x - xk).abs();
            if d < best_distance {
                best = k;
                best_distance = d;
            }
        }
        best
    }

    /// Writes `φ_i(x)` into `values[i]`. No allocation.
    ///
    /// # Errors
    /// [`SpectralError::NonFinitePoint`], or [`SpectralError::LengthMismatch`] unless
    /// `values.len() == num_nodes()`.
    pub fn basis_into(&self, x: f64, values: &mut [f64]) -> Result<(), SpectralError> {
        Self::check_point(x)?;
        self.check_len("values", values.len())?;
        self.scaled_basis(x, values);
        Ok(())
    }

    /// Fills `phi` with the basis at `x` and returns `(p, d_p, D̃)`: the nearest node, the
    /// offset `x − x_p`, and the scaled denominator `D̃ = Σ_k w_k d_p/d_k` (with the `k = p`
    /// term `w_p`).
    fn scaled_basis(&self, x: f64, phi: &mut [f64]) -> (usize, f64, f64) {
        let p = self.nearest(x);
        let dp = x - self.nodes[p];
        if dp == 0.0 {
            phi.fill(0.0);
            phi[p] = 1.0;
            return (p, 0.0, self.weights[p]);
        }
        let mut denominator = 0.0;
        for (k, (phik, (&xk, &wk))) in phi
            .iter_mut()
            .zip(self.nodes.iter().zip(&self.weights))
            .enumerate()
        {
            *phik = if k == p { wk } else { wk * dp / (x - xk) };
            denominator += *phik;
        }
        for phik in phi.iter_mut() {
            *phik /= denominator;
        }
        (p, dp, denominator)
    }

    /// Writes `φ_i(x)` into `values[i]` and `φ_i'(x)` into `derivatives[i]`. Exact at the
    /// nodes (the row of the differentiation matrix) and accurate arbitrarily close to
    /// them. No allocation.
    ///
    /// # Errors
    /// [`SpectralError::NonFinitePoint`], or [`SpectralError::LengthMismatch`] unless both
    /// slices have length `num_nodes()`.
    ///
    /// ```
    /// use lgsvi_spectral::Barycentric;
    /// let basis = Barycentric::chebyshev_lobatto(3, -1.0, 1.0)?; // nodes −1, 0, 1
    /// let (mut phi, mut dphi) = ([0.0; 3], [0.0; 3]);
    /// basis.basis_and_derivatives_into(0.0, &mut phi, &mut dphi)?;
    /// assert_eq!(phi, [0.0, 1.0, 0.0]);
    /// assert_eq!(dphi, [-0.5, 0.0, 0.5]);
    /// # Ok::<(), lgsvi_spectral::SpectralError>(())
    /// ```
    pub fn basis_and_derivatives_into(
        &self,
        x: f64,
        values: &mut [f64],
        derivatives: &mut [f64],
    ) -> Result<(), SpectralError> {
        Self::check_point(x)?;
        self.check_len("values", values.len())?;
        self.check_len("derivatives", derivatives.len())?;
        let (p, dp, denominator) = self.scaled_basis(x, values);
        let wp = self.weights[p];
        let xp = self.nodes[p];
        if dp == 0.0 {
            // Row p of the differentiation matrix: (w_i/w_p)/(x_p − x_i).
            for (i, di) in derivatives.iter_mut().enumerate() {
                *di = if i == p {
                    0.0
                } else {
                    (self.weights[i] / wp) / (xp - self.nodes[i])
                };
            }
        } else {
            // S = Σ_{k≠p} φ_k/d_k; φ_i' = w_i w_p/(d_i D̃²) + φ_i (S − 1/d_i) for i ≠ p.
            let s: f64 = (0..self.num_nodes())
                .filter(|&k| k != p)
                .map(|k| values[k] / (x - self.nodes[k]))
                .sum();
            let scale = wp / (denominator * denominator);
            for (i, di) in derivatives.iter_mut().enumerate() {
                if i != p {
                    let di_inv = 1.0 / (x - self.nodes[i]);
                    *di = self.weights[i] * scale * di_inv + values[i] * (s - di_inv);
                }
            }
        }
        derivatives[p] = 0.0;
        derivatives[p] = -derivatives.iter().sum::<f64>();
        Ok(())
    }

    /// The interpolant `Σ_i f_i φ_i(x)` of `values[i] = f(x_i)` (second barycentric form).
    ///
    /// # Errors
    /// [`SpectralError::NonFinitePoint`], or [`SpectralError::LengthMismatch`].
    pub fn interpolate(&self, values: &[f64], x: f64) -> Result<f64, SpectralError> {
        Self::check_point(x)?;
        self.check_len("values", values.len())?;
        let p = self.nearest(x);
        let dp = x - self.nodes[p];
        if dp == 0.0 {
            return Ok(values[p]);
        }
        let (mut numerator, mut denominator) = (0.0, 0.0);
        for (k, ((&xk, &wk), &fk)) in self.nodes.iter().zip(&self.weights).zip(values).enumerate() {
            let t = if k == p { wk } else { wk * dp / (x - xk) };
            numerator += t * fk;
            denominator += t;
        }
        Ok(numerator / denominator)
    }

    /// The derivative of the interpolant, `Σ_i f_i φ_i'(x)`. Allocates two vectors of
    /// length `n`; for repeated use call [`Barycentric::basis_and_derivatives_into`].
    ///
    /// # Errors
    /// [`SpectralError::NonFinitePoint`], or [`SpectralError::LengthMismatch`].
    pub fn interpolate_derivative(&self, values: &[f64], x: f64) -> Result<f64, SpectralError> {
        self.check_len("values", values.len())?;
        let n = self.num_nodes();
        let (mut phi, mut dphi) = (vec![0.0; n], vec![0.0; n]);
        self.basis_and_derivatives_into(x, &mut phi, &mut dphi)?;
        Ok(dphi.iter().zip(values).map(|(d, f)| d * f).sum())
    }

    /// The evaluation matrix at `points`: `B[j][i] = φ_i(points[j])`, `points.len() × n`.
    ///
    /// # Errors
    /// [`SpectralError::NonFinitePoint`] for a non-finite point.
    pub fn evaluation_matrix(&self, points: &[f64]) -> Result<Matrix, SpectralError> {
        let mut b = Matrix::zeros(points.len(), self.num_nodes());
        for (j, &x) in points.iter().enumerate() {
            self.basis_into(x, b.row_mut(j))?;
        }
        Ok(b)
    }

    /// Evaluation and derivative matrices at `points`: `B[j][i] = φ_i(c_j)` and
    /// `D[j][i] = φ_i'(c_j)` — what a Galerkin method needs at its quadrature points.
    ///
    /// # Errors
    /// [`SpectralError::NonFinitePoint`] for a non-finite point.
    ///
    /// ```
    /// use lgsvi_spectral::Barycentric;
    /// let basis = Barycentric::chebyshev_lobatto(4, 0.0, 1.0)?;
    /// let (b, d) = basis.evaluation_and_derivative_matrices(&[0.2, 0.5, 0.9])?;
    /// // The basis sums to 1 and its derivatives to 0 at every point.
    /// for j in 0..3 {
    ///     assert!((b.row(j).iter().sum::<f64>() - 1.0).abs() < 1e-15);
    ///     assert!(d.row(j).iter().sum::<f64>().abs() < 1e-13);
    /// }
    /// # Ok::<(), lgsvi_spectral::SpectralError>(())
    /// ```
    pub fn evaluation_and_derivative_matrices(
        &self,
        points: &[f64],
    ) -> Result<(Matrix, Matrix), SpectralError> {
        let n = self.num_nodes();
        let mut b = Matrix::zeros(points.len(), n);
        let mut d = Matrix::zeros(points.len(), n);
        for (j, &x) in points.iter().enumerate() {
            self.basis_and_derivatives_into(x, b.row_mut(j), d.row_mut(j))?;
        }
        Ok((b, d))
    }

    /// The `n × n` differentiation matrix on the nodes, `D[j][i] = φ_i'(x_j)`:
    /// off the diagonal `(w_i/w_j)/(x_j − x_i)`, on it minus the sum of the row
    /// (the "negative-sum trick", which makes `D · 1 = 0` hold to rounding and is more
    /// accurate than the closed-form diagonal).
    ///
    /// ```
    /// use lgsvi_spectral::Barycentric;
    /// let basis = Barycentric::chebyshev_lobatto(3, -1.0, 1.0)?;
    /// let d = basis.differentiation_matrix();
    /// assert_eq!(d.row(0), &[-1.5, 2.0, -0.5]);
    /// # Ok::<(), lgsvi_spectral::SpectralError>(())
    /// ```
    pub fn differentiation_matrix(&self) -> Matrix {
        let n = self.num_nodes();
        let mut d = Matrix::zeros(n, n);
        for j in 0..n {
            let (xj, wj) = (self.nodes[j], self.weights[j]);
            let row = d.row_mut(j);
            let mut sum = 0.0;
            for i in (0..n).filter(|&i| i != j) {
                row[i] = (self.weights[i] / wj) / (xj - self.nodes[i]);
                sum += row[i];
            }
            row[j] = -sum;
        }
        d
    }
}
