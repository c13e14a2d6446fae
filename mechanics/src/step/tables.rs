//! The discretisation tables of a step: Gauss–Legendre rule on `[0, h]`, the
//! Chebyshev–Lobatto Lagrange basis and its derivative at the Gauss points, the weighted
//! basis the Newton matrix is multiplied by, and the continuation matrix of the predictor.
//!
//! On step `k` the curve is `ξ(t) = Σ_i ξⁱ φ_i(t)` on `n` Chebyshev–Lobatto nodes of
//! `[0, h]`; at Gauss point `c_j h` (weight `h b_j`) its value is `x_j = Σ_i φ_i(c_j h) ξⁱ`
//! and its slope `v_j = Σ_i φ_i'(c_j h) ξⁱ`. These tables depend on `(h, n, m)` only, never
//! on the group or the system.

use crate::error::MechanicsError;
use crate::settings::StepSettings;
use faer::Mat;
use lgsvi_quadrature::gauss_legendre;
use lgsvi_spectral::Barycentric;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// The predictor continues the last step's curve through at most this many nodes.
const EXTRAPOLATION_NODES: usize = 12;

/// The most tables the process keeps ([`Discretisation::shared`]); past it the cache is
/// emptied and refilled (a sweep over `(h, n, m)` wider than this pays construction again,
/// nothing worse). Each table is a few kilobytes.
const CACHED_TABLES: usize = 256;

/// `C` of [`Discretisation::error_estimate`]: the true local error (the step against one
/// with 14 more nodes from the same state) over `(n − 1)⁴ t² q²`, measured over 470 steps
/// of the free body and the heavy top (`h = 0.25 … 1.25`, `n = 5 … 12`, every step of
/// `T = 10` with an error above rounding) is `10^−2.06` on average, between `10^−3.5` and
/// `10^−0.6` (standard deviation 0.46 decades). `C = 10^−2` puts the estimate near the
/// typical error, at most 25× below the largest seen and 30× above the smallest.
pub(crate) const ERROR_CALIBRATION: f64 = 0.01;

/// The tables built so far, by `(h` bit pattern, `n`, `m)`.
type TableCache = Mutex<HashMap<(u64, usize, usize), Arc<Discretisation>>>;

fn cache() -> &'static TableCache {
    static CACHE: OnceLock<TableCache> = OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// Fixed data of a step: quadrature, basis matrices.
#[derive(Debug, Clone)]
pub(crate) struct Discretisation {
    pub n: usize,
    pub m: usize,
    /// `h b_j`.
    pub weights: Vec<f64>,
    /// The Gauss points `c_j h` (time into the step).
    pub times: Vec<f64>,
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
    /// The last `min(n, 4)` rows of the Chebyshev coefficient matrix (row-major, `n`
    /// columns): the last Chebyshev coefficients of the step's curve from its nodal
    /// values, which the error estimate reads.
    pub tail: Vec<f64>,
}

impl Discretisation {
    /// The tables of `settings`' `(h, n, m)`, built once per process and shared by every
    /// integrator with the same three numbers: Golub–Welsch, the barycentric basis and the
    /// continuation matrix cost about as much as a step, and a user integrating many short
    /// trajectories would pay them at every `Integrator::new`. The tables depend on nothing
    /// else, so sharing them changes no result. A poisoned lock (a panic elsewhere while
    /// holding it) only skips the cache.
    pub fn shared(settings: &StepSettings) -> Result<Arc<Self>, MechanicsError> {
        let key = (
            settings.h().to_bits(),
            settings.nodes(),
            settings.quadrature_points(),
        );
        if let Ok(tables) = cache().lock() {
            if let Some(found) = tables.get(&key) {
                return Ok(Arc::clone(found));
            }
        }
        let built = Arc::new(Self::new(settings)?);
        if let Ok(mut tables) = cache().lock() {
            if tables.len() >= CACHED_TABLES {
                tables.clear();
            }
            tables.insert(key, Arc::clone(&built));
        }
        Ok(built)
    }

    pub fn new(settings: &StepSettings) -> Result<Self, MechanicsError> {
        let (n, m, h) = (settings.nodes(), settings.quadrature_points(), settings.h());
        let rule = gauss_legendre(m)?.on(0.0, h)?;
        let basis = Barycentric::chebyshev_lobatto(n, 0.0, h)?;
        let (b, d) = basis.evaluation_and_derivative_matrices(rule.nodes())?;
        let weights = rule.weights().to_vec();
        let times = rule.nodes().to_vec();
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
        let coefficients = lgsvi_spectral::chebyshev_coefficient_matrix(n)?;
        let tail = (n.saturating_sub(4)..n)
            .flat_map(|k| coefficients.row(k).to_vec())
            .collect();
        Ok(Self {
            n,
            m,
            extrapolation,
            tail,
            weights,
            times,
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

    /// The estimated local error of a step whose curve has the nodal values `nodes`, and
    /// the decay `q` it read:
    /// `C (n − 1)⁴ t² q²`, where `t = max(|c_{n−1}|, |c_{n−2}|)` is the size of the curve's
    /// last Chebyshev coefficients (max norm over the algebra), `q = √(t / t′)` their decay
    /// per degree (`t′` the same two coefficients before, `q ≤ 1`; `q = 1` below five nodes,
    /// where there is no decay to read) and `C` = [`ERROR_CALIBRATION`].
    ///
    /// Why this form: the interior of the curve is accurate to about the first neglected
    /// coefficient `t q`; its velocity, which the action weighs, to `(n − 1)² t q`; and the
    /// step's end point, where a variational method superconverges, to the square of that.
    pub fn error_estimate<const D: usize>(
        &self,
        nodes: &[nalgebra::SVector<f64, D>],
    ) -> (f64, f64) {
        let n = self.n;
        let coefficient = |row: &[f64]| {
            row.iter()
                .zip(nodes)
                .fold(nalgebra::SVector::<f64, D>::zeros(), |acc, (c, x)| {
                    acc + x * *c
                })
                .amax()
        };
        let mut sizes = [0.0; 4];
        let mut k = 0;
        for (size, row) in sizes.iter_mut().zip(self.tail.chunks_exact(n)) {
            *size = coefficient(row);
            k += 1;
        }
        let tail = sizes[k - 1].max(sizes[k - 2]);
        let decay = if k == 4 {
            let before = sizes[0].max(sizes[1]);
            if before > 0.0 {
                (tail / before).sqrt().min(1.0)
            } else {
                1.0
            }
        } else {
            1.0
        };
        let degree = (n - 1) as f64;
        (
            ERROR_CALIBRATION * degree.powi(4) * (tail * decay).powi(2),
            decay,
        )
    }

    /// The node times `t_i ∈ [0, h]`.
    pub fn node_times(&self) -> &[f64] {
        self.basis.nodes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Equal `(h, n, m)` share one table, equal to a freshly built one entry for entry;
    /// a change in any of the three gives another table.
    #[test]
    fn shared_tables_are_keyed_by_h_n_and_m() {
        let settings = StepSettings::new(0.37, 9).unwrap();
        let (a, b) = (
            Discretisation::shared(&settings).unwrap(),
            Discretisation::shared(&settings).unwrap(),
        );
        assert!(Arc::ptr_eq(&a, &b));
        let fresh = Discretisation::new(&settings).unwrap();
        assert_eq!(a.weights, fresh.weights);
        assert_eq!(a.values, fresh.values);
        assert_eq!(a.slopes, fresh.slopes);
        assert_eq!(a.extrapolation, fresh.extrapolation);
        for other in [
            StepSettings::new(0.38, 9).unwrap(),
            StepSettings::new(0.37, 10).unwrap(),
            StepSettings::new(0.37, 9)
                .unwrap()
                .with_quadrature_points(11)
                .unwrap(),
        ] {
            let c = Discretisation::shared(&other).unwrap();
            assert!(!Arc::ptr_eq(&a, &c));
            assert_eq!((c.n, c.m, c.times.last().copied()), {
                let f = Discretisation::new(&other).unwrap();
                (f.n, f.m, f.times.last().copied())
            });
        }
    }
}
