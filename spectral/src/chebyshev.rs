//! [`Chebyshev`]: a function on `[a, b]` held as its Chebyshev series
//! `f(x) = Σ_k c_k T_k(t)`, `t = (2x − a − b)/(b − a)`, fitted adaptively to machine
//! precision (or a tolerance), with Clenshaw evaluation, derivative, integrals, roots, sums
//! and products.
//!
//! The fit samples `f` at `n = 17, 33, 65, …` Chebyshev–Lobatto points until the
//! coefficients reach a plateau at the tolerance, and chops them there (the plateau and
//! chop rule of Aurentz & Trefethen, "Chopping a Chebyshev series", ACM TOMS 2017, as
//! chebfun applies it). Values ↔ coefficients go through the DCT-I
//! ([`chebyshev_coefficients`](crate::chebyshev_coefficients),
//! [`chebyshev_values`](crate::chebyshev_values): an FFT from
//! [`FFT_FROM`](crate::FFT_FROM) points on, `O(n log n)`); the fit stops at
//! [`MAX_FIT_POINTS`] samples. Composition `g ∘ f` is a new fit of the composed function
//! ([`Chebyshev::compose`], [`Chebyshev::compose_with`]), the range of `f` its extrema
//! ([`Chebyshev::range`]).

use crate::coefficients::{chebyshev_coefficients, chebyshev_values};
use crate::error::SpectralError;
use crate::nodes::chebyshev_lobatto;
use nalgebra::{DMatrix, DVector};

/// The most samples [`Chebyshev::fit`] takes (`2¹² + 1`): a function that needs more is not
/// resolved ([`SpectralError::NotResolved`]); split its interval.
pub const MAX_FIT_POINTS: usize = 4097;

/// A function on `[a, b]` as a Chebyshev series (module documentation).
///
/// ```
/// use lgsvi_spectral::Chebyshev;
/// let f = Chebyshev::fit(|x| (5.0 * x).sin() / (1.0 + x * x), -2.0, 3.0)?;
/// let x = 0.7;
/// assert!((f.evaluate(x)? - (5.0 * x).sin() / (1.0 + x * x)).abs() < 1e-14);
/// // Exact derivative and integral of the series; roots from the colleague matrix.
/// let roots = Chebyshev::fit(|x| (10.0 * x).cos(), 0.0, 3.0)?.roots();
/// assert_eq!(roots.len(), 10);
/// assert!((roots[0] - std::f64::consts::PI / 20.0).abs() < 1e-14);
/// # Ok::<(), lgsvi_spectral::SpectralError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Chebyshev {
    a: f64,
    b: f64,
    coefficients: Vec<f64>,
}

impl Chebyshev {
    /// Fits `f` on `[a, b]` to machine precision (relative to its largest coefficient).
    ///
    /// # Errors
    /// Interval errors for `a ≥ b` or non-finite ends; [`SpectralError::NonFiniteValue`]
    /// where `f` is not finite at a sample; [`SpectralError::NotResolved`] when
    /// [`MAX_FIT_POINTS`] samples do not reach the tolerance (a function that is not
    /// smooth on `[a, b]`, or needs more points).
    pub fn fit(f: impl FnMut(f64) -> f64, a: f64, b: f64) -> Result<Self, SpectralError> {
        Self::fit_with_tolerance(f, a, b, f64::EPSILON)
    }

    /// As [`Chebyshev::fit`] to the relative tolerance `tol` (at least `ε`, below 1).
    ///
    /// # Errors
    /// As [`Chebyshev::fit`]; [`SpectralError::InvalidTolerance`] for `tol` outside
    /// `[ε, 1)`.
    pub fn fit_with_tolerance(
        mut f: impl FnMut(f64) -> f64,
        a: f64,
        b: f64,
        tol: f64,
    ) -> Result<Self, SpectralError> {
        Self::try_fit_batch(
            |points: &[f64]| Ok::<_, SpectralError>(points.iter().map(|&x| f(x)).collect()),
            a,
            b,
            tol,
        )
    }

    /// As [`Chebyshev::fit_with_tolerance`], with `f` evaluated on all the points of a
    /// sampling at once (`f(points)` returns the values at `points`, in order): for a
    /// function that is cheaper on many points together (vectorised code, a call into
    /// another language), or that can fail with an error of its own, which ends the fit.
    /// The samples are those of [`Chebyshev::fit_with_tolerance`], so the series is the
    /// same, bit for bit.
    ///
    /// ```
    /// use lgsvi_spectral::{Chebyshev, SpectralError};
    /// let exp = |points: &[f64]| Ok::<_, SpectralError>(points.iter().map(|x| x.exp()).collect());
    /// let batch = Chebyshev::try_fit_batch(exp, 0.0, 1.0, 1e-12)?;
    /// assert_eq!(batch, Chebyshev::fit_with_tolerance(f64::exp, 0.0, 1.0, 1e-12)?);
    /// # Ok::<(), lgsvi_spectral::SpectralError>(())
    /// ```
    ///
    /// # Errors
    /// As [`Chebyshev::fit_with_tolerance`]; `f`'s own errors; [`SpectralError::LengthMismatch`]
    /// where `f` returns another number of values than it was given points.
    pub fn try_fit_batch<E: From<SpectralError>>(
        mut f: impl FnMut(&[f64]) -> Result<Vec<f64>, E>,
        a: f64,
        b: f64,
        tol: f64,
    ) -> Result<Self, E> {
        if !(f64::EPSILON..1.0).contains(&tol) {
            return Err(SpectralError::InvalidTolerance { tol }.into());
        }
        let mut n = 17;
        loop {
            let nodes = chebyshev_lobatto(n, a, b)?;
            let values = f(&nodes)?;
            if values.len() != n {
                return Err(SpectralError::LengthMismatch {
                    what: "values of the function at the fit's points",
                    expected: n,
                    got: values.len(),
                }
                .into());
            }
            if let Some((&x, &value)) = nodes.iter().zip(&values).find(|(_, y)| !y.is_finite()) {
                return Err(SpectralError::NonFiniteValue { x, value }.into());
            }
            let coefficients = chebyshev_coefficients(&values)?;
            let cutoff = standard_chop(&coefficients, tol);
            if cutoff < n {
                return Ok(Self {
                    a,
                    b,
                    coefficients: coefficients[..cutoff].to_vec(),
                });
            }
            if n >= MAX_FIT_POINTS {
                return Err(SpectralError::NotResolved {
                    points: n,
                    a,
                    b,
                    tol,
                }
                .into());
            }
            n = 2 * n - 1;
        }
    }

    /// The series with these coefficients `c_0, c_1, …` on `[a, b]`.
    ///
    /// # Errors
    /// Interval errors; [`SpectralError::TooFewNodes`] for no coefficient;
    /// [`SpectralError::NonFiniteCoefficient`] for a non-finite coefficient.
    pub fn from_coefficients(
        coefficients: Vec<f64>,
        a: f64,
        b: f64,
    ) -> Result<Self, SpectralError> {
        chebyshev_lobatto(2, a, b)?;
        if coefficients.is_empty() {
            return Err(SpectralError::TooFewNodes {
                kind: "Chebyshev series",
                n: 0,
                min: 1,
            });
        }
        if let Some((index, &value)) = coefficients
            .iter()
            .enumerate()
            .find(|(_, c)| !c.is_finite())
        {
            return Err(SpectralError::NonFiniteCoefficient { index, value });
        }
        Ok(Self { a, b, coefficients })
    }

    /// The interpolant through `values` at the `values.len()` Chebyshev–Lobatto points
    /// of `[a, b]` (ascending, as [`chebyshev_lobatto`] gives them).
    ///
    /// # Errors
    /// As [`Chebyshev::from_coefficients`]; [`SpectralError::TooFewNodes`] for fewer than
    /// two values.
    pub fn from_values(values: &[f64], a: f64, b: f64) -> Result<Self, SpectralError> {
        Self::from_coefficients(chebyshev_coefficients(values)?, a, b)
    }

    /// The coefficients `c_0, c_1, …`.
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    /// The interval `(a, b)`.
    pub fn interval(&self) -> (f64, f64) {
        (self.a, self.b)
    }

    /// The number of coefficients (the degree plus one).
    pub fn len(&self) -> usize {
        self.coefficients.len()
    }

    /// Whether the series has no coefficient (never, for a constructed series).
    pub fn is_empty(&self) -> bool {
        self.coefficients.is_empty()
    }

    /// The values at the `len()` Chebyshev–Lobatto points (at least two), ascending: the
    /// inverse of [`Chebyshev::from_values`].
    pub fn values(&self) -> Vec<f64> {
        if self.len() == 1 {
            return vec![self.coefficients[0]; 2];
        }
        chebyshev_values(&self.coefficients).expect("at least two coefficients")
    }

    /// `f(x)` by Clenshaw's recurrence.
    ///
    /// # Errors
    /// [`SpectralError::NonFinitePoint`]; [`SpectralError::OutsideInterval`] for `x`
    /// outside `[a, b]` by more than the rounding of the ends (the series would
    /// extrapolate, which a fit says nothing about).
    pub fn evaluate(&self, x: f64) -> Result<f64, SpectralError> {
        Ok(self.clenshaw(self.reference(x)?))
    }

    /// `t ∈ [−1, 1]` of `x`, clamped within the rounding of the ends.
    fn reference(&self, x: f64) -> Result<f64, SpectralError> {
        if !x.is_finite() {
            return Err(SpectralError::NonFinitePoint { value: x });
        }
        let slack = 4.0 * f64::EPSILON * self.a.abs().max(self.b.abs());
        if x < self.a - slack || x > self.b + slack {
            return Err(SpectralError::OutsideInterval {
                x,
                a: self.a,
                b: self.b,
            });
        }
        Ok(self.map_in(x))
    }

    /// `t ∈ [−1, 1]` of an `x` known to be in `[a, b]` (up to rounding).
    fn map_in(&self, x: f64) -> f64 {
        ((2.0 * x - self.a - self.b) / (self.b - self.a)).clamp(-1.0, 1.0)
    }

    /// `Σ c_k T_k(t)` by Clenshaw's recurrence.
    fn clenshaw(&self, t: f64) -> f64 {
        let (mut b1, mut b2) = (0.0, 0.0);
        for &c in self.coefficients[1..].iter().rev() {
            let b0 = 2.0 * t * b1 - b2 + c;
            b2 = b1;
            b1 = b0;
        }
        t * b1 - b2 + self.coefficients[0]
    }

    /// The derivative `f'` as a series on `[a, b]` (one coefficient fewer; a constant's
    /// derivative is the zero series): `d_{k−1} = d_{k+1} + 2k c_k`, `d_0` halved, times
    /// `2/(b − a)`.
    pub fn derivative(&self) -> Chebyshev {
        let n = self.len();
        if n == 1 {
            return Self {
                a: self.a,
                b: self.b,
                coefficients: vec![0.0],
            };
        }
        let mut d = vec![0.0; n + 1];
        for k in (1..n).rev() {
            d[k - 1] = d[k + 1] + 2.0 * k as f64 * self.coefficients[k];
        }
        d[0] *= 0.5;
        d.truncate(n - 1);
        let scale = 2.0 / (self.b - self.a);
        Self {
            a: self.a,
            b: self.b,
            coefficients: d.into_iter().map(|x| x * scale).collect(),
        }
    }

    /// The indefinite integral `F(x) = ∫_a^x f` as a series (one coefficient more):
    /// `C_1 = c_0 − c_2/2`, `C_k = (c_{k−1} − c_{k+1})/(2k)`, `C_0` such that `F(a) = 0`,
    /// times `(b − a)/2`.
    pub fn integral(&self) -> Chebyshev {
        let n = self.len();
        let c = |k: usize| self.coefficients.get(k).copied().unwrap_or(0.0);
        let mut big = vec![0.0; n + 1];
        for (k, slot) in big.iter_mut().enumerate().skip(1) {
            *slot = if k == 1 {
                c(0) - 0.5 * c(2)
            } else {
                (c(k - 1) - c(k + 1)) / (2.0 * k as f64)
            };
        }
        // F(−1) = Σ C_k (−1)^k = 0.
        big[0] = -big
            .iter()
            .enumerate()
            .skip(1)
            .map(|(k, &ck)| if k % 2 == 0 { ck } else { -ck })
            .sum::<f64>();
        let scale = 0.5 * (self.b - self.a);
        Self {
            a: self.a,
            b: self.b,
            coefficients: big.into_iter().map(|x| x * scale).collect(),
        }
    }

    /// `∫_a^b f = (b − a)/2 Σ_{k even} 2 c_k / (1 − k²)`.
    pub fn definite_integral(&self) -> f64 {
        let sum: f64 = self
            .coefficients
            .iter()
            .enumerate()
            .step_by(2)
            .map(|(k, &c)| 2.0 * c / (1.0 - (k * k) as f64))
            .sum();
        0.5 * (self.b - self.a) * sum
    }

    /// The real roots in `[a, b]`, ascending: the eigenvalues of the colleague matrix of
    /// the series (trailing coefficients below `ε` of the largest dropped first) that are
    /// real and in `[−1, 1]` to `1e-8`, mapped to `[a, b]` and polished by Newton steps on
    /// the series. A zero series has every point as a root: it returns none.
    /// A double root may split into a complex pair beyond `1e-8` and be missed (as in any
    /// eigenvalue method); the colleague matrix is dense, `O(N³)` for degree `N`.
    pub fn roots(&self) -> Vec<f64> {
        let largest = self.coefficients.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        if largest == 0.0 {
            return Vec::new();
        }
        let mut degree = self.len() - 1;
        while degree > 0 && self.coefficients[degree].abs() <= f64::EPSILON * largest {
            degree -= 1;
        }
        if degree == 0 {
            return Vec::new();
        }
        let c = &self.coefficients[..=degree];
        let candidates: Vec<f64> = if degree == 1 {
            vec![-c[0] / c[1]]
        } else {
            let mut m = DMatrix::<f64>::zeros(degree, degree);
            m[(0, 1)] = 1.0;
            for i in 1..degree {
                m[(i, i - 1)] = 0.5;
                if i + 1 < degree {
                    m[(i, i + 1)] = 0.5;
                }
            }
            let last = degree - 1;
            for (j, &cj) in c[..degree].iter().enumerate() {
                m[(last, j)] -= cj / (2.0 * c[degree]);
            }
            m.complex_eigenvalues()
                .iter()
                .filter(|z| z.im.abs() <= 1e-8 && z.re.abs() <= 1.0 + 1e-8)
                .map(|z| z.re.clamp(-1.0, 1.0))
                .collect()
        };
        let derivative = self.derivative();
        let mut roots: Vec<f64> = candidates
            .into_iter()
            .map(|t| {
                let mut x = self.a + 0.5 * (t + 1.0) * (self.b - self.a);
                // Newton on the series until its step is at the rounding of x (at most
                // 8 steps: the eigenvalues of a non-normal colleague matrix can be off
                // by ~1e-4 relative; Newton squares that away).
                for _ in 0..8 {
                    // x stays in [a, b]: it starts there and each step is clamped.
                    let at = self.map_in(x);
                    let (value, slope) = (self.clenshaw(at), derivative.clenshaw(at));
                    if slope == 0.0 || !value.is_finite() {
                        break;
                    }
                    let next = (x - value / slope).clamp(self.a, self.b);
                    if !next.is_finite() {
                        break;
                    }
                    let step = (next - x).abs();
                    x = next;
                    if step <= 4.0 * f64::EPSILON * x.abs().max(self.b - self.a) {
                        break;
                    }
                }
                x
            })
            .collect();
        // A candidate Newton could not bring to a zero of the series (a spurious real
        // eigenvalue at an end, clamped there) is not a root: keep those where the series
        // vanishes to its rounding (Σ|c_k| bounds every value it takes).
        let scale: f64 = self.coefficients.iter().map(|c| c.abs()).sum();
        roots.retain(|&x| self.clenshaw(self.map_in(x)).abs() <= 1e3 * f64::EPSILON * scale);
        roots.sort_by(f64::total_cmp);
        roots
    }

    /// `f + g` (same interval).
    ///
    /// # Errors
    /// [`SpectralError::IntervalMismatch`] for different intervals.
    pub fn add(&self, other: &Chebyshev) -> Result<Chebyshev, SpectralError> {
        self.check_same_interval(other)?;
        let n = self.len().max(other.len());
        let at = |s: &Chebyshev, k: usize| s.coefficients.get(k).copied().unwrap_or(0.0);
        Ok(Self {
            a: self.a,
            b: self.b,
            coefficients: (0..n).map(|k| at(self, k) + at(other, k)).collect(),
        })
    }

    /// `f g` (same interval): the exact product series, of degree the sum of the degrees,
    /// from `c_j T_j · d_k T_k = ½ c_j d_k (T_{j+k} + T_{|j−k|})`.
    ///
    /// # Errors
    /// [`SpectralError::IntervalMismatch`] for different intervals.
    pub fn mul(&self, other: &Chebyshev) -> Result<Chebyshev, SpectralError> {
        self.check_same_interval(other)?;
        let mut product = vec![0.0; self.len() + other.len() - 1];
        for (j, &cj) in self.coefficients.iter().enumerate() {
            for (k, &dk) in other.coefficients.iter().enumerate() {
                let half = 0.5 * cj * dk;
                product[j + k] += half;
                product[j.abs_diff(k)] += half;
            }
        }
        Ok(Self {
            a: self.a,
            b: self.b,
            coefficients: product,
        })
    }

    /// The least and the largest value of the series on `[a, b]`: at the ends or at a root
    /// of the derivative ([`Chebyshev::roots`] of [`Chebyshev::derivative`]).
    ///
    /// ```
    /// use lgsvi_spectral::Chebyshev;
    /// let f = Chebyshev::fit(|x| x.sin(), 0.0, 3.0)?;
    /// let (low, high) = f.range();
    /// assert!(low.abs() < 1e-15); // sin at 0
    /// assert!((high - 1.0).abs() < 1e-15); // sin at π/2
    /// # Ok::<(), lgsvi_spectral::SpectralError>(())
    /// ```
    pub fn range(&self) -> (f64, f64) {
        let ends = [self.clenshaw(-1.0), self.clenshaw(1.0)];
        let inner = self
            .derivative()
            .roots()
            .into_iter()
            .map(|x| self.clenshaw(self.map_in(x)));
        ends.into_iter()
            .chain(inner)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            })
    }

    /// `g ∘ f` on `[a, b]`: a new adaptive fit (as [`Chebyshev::fit`]) of `x ↦ g(f(x))`.
    ///
    /// ```
    /// use lgsvi_spectral::Chebyshev;
    /// let f = Chebyshev::fit(|x| x.cos(), -1.0, 2.0)?;
    /// let h = f.compose(f64::exp)?; // e^{cos x}
    /// assert!((h.evaluate(0.5)? - 0.5f64.cos().exp()).abs() < 1e-14);
    /// # Ok::<(), lgsvi_spectral::SpectralError>(())
    /// ```
    ///
    /// # Errors
    /// As [`Chebyshev::fit`] ([`SpectralError::NonFiniteValue`] where `g` is not finite,
    /// [`SpectralError::NotResolved`] where `g ∘ f` needs more than [`MAX_FIT_POINTS`]).
    pub fn compose(&self, mut g: impl FnMut(f64) -> f64) -> Result<Chebyshev, SpectralError> {
        Self::fit(|x| g(self.clenshaw(self.map_in(x))), self.a, self.b)
    }

    /// `outer ∘ self` on `self`'s interval, where `self`'s [`Chebyshev::range`] lies in
    /// `outer`'s interval (to the rounding of its ends): a new adaptive fit.
    ///
    /// ```
    /// use lgsvi_spectral::Chebyshev;
    /// let inner = Chebyshev::fit(|x| x * x, -1.0, 1.0)?; // range [0, 1]
    /// let outer = Chebyshev::fit(|y| (3.0 * y).sin(), 0.0, 1.0)?;
    /// let h = inner.compose_with(&outer)?;
    /// assert!((h.evaluate(0.3)? - (3.0 * 0.09f64).sin()).abs() < 1e-14);
    /// assert!(outer.compose_with(&inner).is_ok()); // sin(3y) on [0, 1] stays in [−1, 1]
    /// let narrow = Chebyshev::fit(|y| y, 0.0, 0.5)?;
    /// assert!(inner.compose_with(&narrow).is_err()); // x² reaches 1, outside [0, 0.5]
    /// # Ok::<(), lgsvi_spectral::SpectralError>(())
    /// ```
    ///
    /// # Errors
    /// [`SpectralError::OutsideInterval`] naming the extreme value of `self` that lies
    /// outside `outer`'s interval; as [`Chebyshev::fit`].
    pub fn compose_with(&self, outer: &Chebyshev) -> Result<Chebyshev, SpectralError> {
        let (low, high) = self.range();
        for value in [low, high] {
            outer.reference(value)?;
        }
        self.compose(|y| outer.clenshaw(outer.map_in(y)))
    }

    /// The values at `points` (each checked as in [`Chebyshev::evaluate`]).
    ///
    /// # Errors
    /// As [`Chebyshev::evaluate`].
    pub fn evaluate_many(&self, points: &DVector<f64>) -> Result<DVector<f64>, SpectralError> {
        let mut out = DVector::zeros(points.len());
        for (o, &x) in out.iter_mut().zip(points.iter()) {
            *o = self.evaluate(x)?;
        }
        Ok(out)
    }

    fn check_same_interval(&self, other: &Chebyshev) -> Result<(), SpectralError> {
        if (self.a, self.b) == (other.a, other.b) {
            Ok(())
        } else {
            Err(SpectralError::IntervalMismatch {
                first: (self.a, self.b),
                second: (other.a, other.b),
            })
        }
    }
}

/// The chop point of Aurentz & Trefethen's standard rule: the number of coefficients to
/// keep, or `coefficients.len()` when they have not reached a plateau at `tol` (more
/// samples are needed). Series of fewer than 17 coefficients are never chopped.
fn standard_chop(coefficients: &[f64], tol: f64) -> usize {
    let n = coefficients.len();
    if n < 17 {
        return n;
    }
    // The monotone envelope m_j = max_{k ≥ j} |c_k|, normalised by its first entry.
    let mut envelope = vec![0.0; n];
    let mut running = 0.0f64;
    for j in (0..n).rev() {
        running = running.max(coefficients[j].abs());
        envelope[j] = running;
    }
    if envelope[0] == 0.0 {
        return 1;
    }
    let first = envelope[0];
    for e in envelope.iter_mut() {
        *e /= first;
    }
    // A plateau: the envelope at j and at 1.25 j + 5 (1-based) differ by less than a
    // factor that shrinks as the envelope nears tol.
    let mut plateau = None;
    for j in 2..=n {
        let j2 = (1.25 * j as f64 + 5.0).round() as usize;
        if j2 > n {
            return n;
        }
        let (e1, e2) = (envelope[j - 1], envelope[j2 - 1]);
        let r = 3.0 * (1.0 - e1.ln() / tol.ln());
        if e1 == 0.0 || e2 / e1 > r {
            plateau = Some((j - 1, j2));
            break;
        }
    }
    let Some((point, mut j2)) = plateau else {
        return n;
    };
    if envelope[point - 1] == 0.0 {
        return point;
    }
    // The cut: the lowest point of the log envelope tilted upwards by a third of log tol.
    let floor = tol.powf(7.0 / 6.0);
    let j3 = envelope.iter().filter(|&&e| e >= floor).count();
    if j3 < j2 {
        j2 = j3 + 1;
        envelope[j2 - 1] = floor;
    }
    let tilt = -tol.log10() / 3.0;
    let mut best = (f64::INFINITY, 0);
    for (i, &e) in envelope[..j2].iter().enumerate() {
        let shift = if j2 > 1 {
            tilt * i as f64 / (j2 - 1) as f64
        } else {
            0.0
        };
        let value = e.log10() + shift;
        if value < best.0 {
            best = (value, i + 1);
        }
    }
    best.1.saturating_sub(1).max(1)
}
