//! The [`Rule`] type: nodes and weights on an interval.

use crate::QuadratureError;

/// Which family a [`Rule`] belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum RuleKind {
    /// Gauss–Legendre: interior nodes only; exact for degree `2m − 1`.
    GaussLegendre,
    /// Gauss–Lobatto (Legendre): both ends are nodes; exact for degree `2m − 3`.
    GaussLobatto,
    /// Gauss–Radau with the left end as a node; exact for degree `2m − 2`.
    GaussRadauLeft,
    /// Gauss–Radau with the right end as a node; exact for degree `2m − 2`.
    GaussRadauRight,
    /// Gauss–Hermite, weight `e^{−x²}` on the real line; exact for degree `2m − 1`.
    GaussHermite,
    /// Generalised Gauss–Laguerre, weight `x^α e^{−x}` on `[0, ∞)`; exact for degree `2m − 1`.
    GaussLaguerre,
    /// Gauss–Jacobi, weight `(1 − x)^α (1 + x)^β` on `[−1, 1]`; exact for degree `2m − 1`.
    GaussJacobi,
    /// Gauss–Chebyshev of the first kind, weight `1/√(1 − x²)`; exact for degree `2m − 1`.
    GaussChebyshevFirst,
    /// Gauss–Chebyshev of the second kind, weight `√(1 − x²)`; exact for degree `2m − 1`.
    GaussChebyshevSecond,
    /// Gauss–Kronrod (Legendre): `m = 2n + 1` points extending the `n`-point Gauss rule;
    /// exact for degree `3n + 1` (`3n + 2` for odd `n`).
    GaussKronrod,
    /// Gauss–Kronrod–Jacobi, weight `(1 − x)^α (1 + x)^β`: `m = 2n + 1` points extending the
    /// `n`-point Gauss–Jacobi rule; exact for degree `3n + 1` (one more for odd `n` where
    /// `α = β`, by symmetry).
    GaussKronrodJacobi,
}

impl RuleKind {
    /// Highest polynomial degree integrated exactly by the `m`-point rule of this family.
    pub fn degree_of_exactness(self, m: usize) -> usize {
        match self {
            RuleKind::GaussLegendre
            | RuleKind::GaussHermite
            | RuleKind::GaussLaguerre
            | RuleKind::GaussJacobi
            | RuleKind::GaussChebyshevFirst
            | RuleKind::GaussChebyshevSecond => 2 * m - 1,
            RuleKind::GaussLobatto => 2 * m - 3,
            RuleKind::GaussRadauLeft | RuleKind::GaussRadauRight => 2 * m - 2,
            RuleKind::GaussKronrod => {
                let n = (m - 1) / 2;
                3 * n + 1 + n % 2
            }
            RuleKind::GaussKronrodJacobi => 3 * ((m - 1) / 2) + 1,
        }
    }
}

/// A quadrature rule `∫_a^b f(x) dx ≈ Σ_i w_i f(x_i)`, nodes ascending.
///
/// A rule keeps its nodes and weights on the reference interval `[−1, 1]` and maps them
/// afresh on every call to [`Rule::on`], so repeated remapping loses nothing. The map is
/// `x = a(1 − t)/2 + b(1 + t)/2`, which sends `t = ±1` exactly to `a` and `b`.
///
/// ```
/// use lgsvi_quadrature::gauss_legendre;
/// // ∫_0^1 x⁵ dx = 1/6, exact for a 3-point Gauss rule (degree 5).
/// let rule = gauss_legendre(3)?.on(0.0, 1.0)?;
/// assert!((rule.integrate(|x| x.powi(5)) - 1.0 / 6.0).abs() < 1e-16);
/// assert_eq!(rule.degree_of_exactness(), 5);
/// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Rule {
    kind: RuleKind,
    reference_nodes: Vec<f64>,
    reference_weights: Vec<f64>,
    nodes: Vec<f64>,
    weights: Vec<f64>,
    interval: (f64, f64),
    /// The reference interval: `[−1, 1]`, or the real line or `[0, ∞)`.
    reference_interval: (f64, f64),
    /// `(α, β)` of a weight `(1 − t)^α (1 + t)^β` on `[−1, 1]` (Jacobi, Chebyshev), or of
    /// `x^α e^{−x}` (Laguerre: `β = 0`); `None` for weight 1 and for Hermite.
    exponents: Option<(f64, f64)>,
}

impl Rule {
    /// A rule on `[−1, 1]` from nodes (ascending) and weights computed by this crate.
    pub(crate) fn reference(kind: RuleKind, nodes: Vec<f64>, weights: Vec<f64>) -> Self {
        debug_assert_eq!(nodes.len(), weights.len());
        debug_assert!(nodes.windows(2).all(|w| w[0] < w[1]));
        Self::with_weight(kind, nodes, weights, (-1.0, 1.0), None)
    }

    /// A rule of a weighted family on its reference interval.
    pub(crate) fn with_weight(
        kind: RuleKind,
        nodes: Vec<f64>,
        weights: Vec<f64>,
        interval: (f64, f64),
        exponents: Option<(f64, f64)>,
    ) -> Self {
        debug_assert_eq!(nodes.len(), weights.len());
        debug_assert!(nodes.windows(2).all(|w| w[0] < w[1]));
        Self {
            kind,
            reference_nodes: nodes.clone(),
            reference_weights: weights.clone(),
            nodes,
            weights,
            interval,
            reference_interval: interval,
            exponents,
        }
    }

    /// The exponents `(α, β)` of the rule's weight function: `(1 − x)^α (1 + x)^β` for
    /// Gauss–Jacobi (Chebyshev: `±½`), `x^α e^{−x}` for Gauss–Laguerre (`β = 0`); `None` for
    /// weight 1 (Legendre, Lobatto, Radau) and for Hermite (`e^{−x²}`).
    pub fn weight_exponents(&self) -> Option<(f64, f64)> {
        self.exponents
    }

    /// The same rule mapped to `[a, b]`. With `a > b` the rule integrates backwards, as
    /// `∫_a^b = −∫_b^a` in calculus: its nodes run from `a` down to `b` and its weights are
    /// negative (each the negated weight of the forward rule's node at the same place).
    ///
    /// A Gauss–Jacobi or Gauss–Chebyshev rule maps with its weight: on `[a, b]` it
    /// integrates `(b − x)^α (x − a)^β f(x)`, its weights scaled by `((b − a)/2)^{α+β+1}`.
    ///
    /// # Errors
    /// [`QuadratureError::NonFiniteInterval`] if `a` or `b` is NaN or infinite,
    /// [`QuadratureError::EmptyInterval`] if `a = b`,
    /// [`QuadratureError::UnboundedRule`] for a Hermite or Laguerre rule (its interval is
    /// infinite: shift and scale its nodes yourself), [`QuadratureError::ReversedWeight`]
    /// for a weighted rule on `a > b` (its weight function is defined for `a < b`).
    ///
    /// ```
    /// use lgsvi_quadrature::{gauss_legendre, gauss_lobatto};
    /// let rule = gauss_lobatto(4)?.on(2.0, 5.0)?;
    /// assert_eq!((rule.nodes()[0], rule.nodes()[3]), (2.0, 5.0));
    /// assert!(gauss_lobatto(4)?.on(1.0, 1.0).is_err());
    /// // Backwards: ∫_1^0 x² dx = −1/3.
    /// let back = gauss_legendre(3)?.on(1.0, 0.0)?;
    /// assert!((back.integrate(|x| x * x) + 1.0 / 3.0).abs() < 1e-15);
    /// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
    /// ```
    pub fn on(&self, a: f64, b: f64) -> Result<Self, QuadratureError> {
        if !(a.is_finite() && b.is_finite()) {
            return Err(QuadratureError::NonFiniteInterval { a, b });
        }
        if a == b {
            return Err(QuadratureError::EmptyInterval { a, b });
        }
        if self.reference_interval != (-1.0, 1.0) {
            return Err(QuadratureError::UnboundedRule {
                rule: self.kind,
                interval: self.reference_interval,
            });
        }
        let half_length = 0.5 * (b - a);
        // Weight 1 scales by the half length; a weight (1 − t)^α (1 + t)^β by its power
        // α + β + 1.
        let scale = match self.exponents {
            None => half_length,
            Some(_) if a > b => return Err(QuadratureError::ReversedWeight { a, b }),
            Some((alpha, beta)) => half_length.powf(alpha + beta + 1.0),
        };
        let nodes = self
            .reference_nodes
            .iter()
            .map(|&t| a * (0.5 * (1.0 - t)) + b * (0.5 * (1.0 + t)))
            .collect();
        let weights = self.reference_weights.iter().map(|&w| w * scale).collect();
        Ok(self.mapped(nodes, weights, (a, b)))
    }

    /// This rule with the nodes and weights of a map to `interval` (the reference ones
    /// kept, so that mapping again loses nothing).
    fn mapped(&self, nodes: Vec<f64>, weights: Vec<f64>, interval: (f64, f64)) -> Self {
        Self {
            kind: self.kind,
            reference_nodes: self.reference_nodes.clone(),
            reference_weights: self.reference_weights.clone(),
            nodes,
            weights,
            interval,
            reference_interval: self.reference_interval,
            exponents: self.exponents,
        }
    }

    /// A Gauss–Legendre rule for `∫_a^∞ f(x) dx`, through the map `x = a + s(1 + t)/(1 − t)`
    /// (`dx = 2s/(1 − t)² dt`): the nodes are the images of the reference nodes, the weights
    /// carry the map's derivative. The scale `s > 0` is where half the rule's nodes lie
    /// (`x = a + s` is the image of `t = 0`): take it near where `f` decays. Exact for
    /// integrands that are polynomials of degree `2m − 1` in `t`, i.e. rational functions
    /// `(x − a + s)^{−k}`, `2 ≤ k ≤ 2m + 1`. Integrands decaying like a power converge
    /// geometrically; an exponential decay becomes an essential singularity at `t = 1`, where
    /// the error falls only like `e^{−c√m}` (`e^{−x}` on `[1, ∞)`, `s = 1`: 1.6e-7 at
    /// `m = 20`, 6.7e-12 at 40, 1e-16 at 80): for such weights [`crate::gauss_laguerre`] and
    /// [`crate::gauss_hermite`] converge geometrically.
    ///
    /// ```
    /// use lgsvi_quadrature::gauss_legendre;
    /// // ∫_0^∞ dx / (1 + x)³ = 1/2, exact (a rational function of the map).
    /// let rule = gauss_legendre(4)?.on_half_line(0.0, 1.0)?;
    /// assert!((rule.integrate(|x| (1.0 + x).powi(-3)) - 0.5).abs() < 1e-15);
    /// // ∫_1^∞ e^{−x} dx = e^{−1}: 80 points (an exponential converges slowly through the map).
    /// let rule = gauss_legendre(80)?.on_half_line(1.0, 1.0)?;
    /// assert!((rule.integrate(|x| (-x).exp()) - (-1f64).exp()).abs() < 1e-15);
    /// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
    /// ```
    ///
    /// # Errors
    /// [`QuadratureError::NonFiniteInterval`] for a non-finite `a` or a scale that is not
    /// positive and finite (reported as the interval `[a, s]`);
    /// [`QuadratureError::UnboundedRule`] for any rule but Gauss–Legendre (an end node at
    /// `t = 1` would map to infinity; weighted rules carry their own weight).
    pub fn on_half_line(&self, a: f64, s: f64) -> Result<Self, QuadratureError> {
        self.mapped_to_infinity(a, s, (a, f64::INFINITY), |t| {
            let u = 1.0 - t;
            ((1.0 + t) / u, 2.0 / (u * u))
        })
    }

    /// A Gauss–Legendre rule for `∫_{−∞}^{∞} f(x) dx`, through the map `x = c + s t/(1 − t²)`
    /// (`dx = s(1 + t²)/(1 − t²)² dt`), centred at `c` with scale `s > 0` (about half the
    /// nodes lie within `|x − c| ≤ √2·s`, the image of `|t| ≤ 1/√2`); as
    /// [`Rule::on_half_line`] otherwise.
    ///
    /// ```
    /// use lgsvi_quadrature::gauss_legendre;
    /// // ∫ dx / (1 + x²) = π.
    /// let rule = gauss_legendre(40)?.on_real_line(0.0, 1.0)?;
    /// assert!((rule.integrate(|x| 1.0 / (1.0 + x * x)) - std::f64::consts::PI).abs() < 4e-15);
    /// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
    /// ```
    ///
    /// # Errors
    /// As [`Rule::on_half_line`] (a non-finite `c`, a scale not positive and finite, a rule
    /// that is not Gauss–Legendre).
    pub fn on_real_line(&self, c: f64, s: f64) -> Result<Self, QuadratureError> {
        self.mapped_to_infinity(c, s, (f64::NEG_INFINITY, f64::INFINITY), |t| {
            let u = (1.0 - t) * (1.0 + t);
            (t / u, (1.0 + t * t) / (u * u))
        })
    }

    /// The reference Gauss–Legendre rule through `x = origin + s·φ(t)`, `dx = s·φ'(t) dt`
    /// onto `interval`, where `map(t)` returns `(φ(t), φ'(t))`.
    fn mapped_to_infinity(
        &self,
        origin: f64,
        s: f64,
        interval: (f64, f64),
        map: impl Fn(f64) -> (f64, f64),
    ) -> Result<Self, QuadratureError> {
        if !(origin.is_finite() && s.is_finite() && s > 0.0) {
            return Err(QuadratureError::NonFiniteInterval { a: origin, b: s });
        }
        if self.kind != RuleKind::GaussLegendre {
            return Err(QuadratureError::UnboundedRule {
                rule: self.kind,
                interval: self.reference_interval,
            });
        }
        let (nodes, weights) = self
            .reference_nodes
            .iter()
            .zip(&self.reference_weights)
            .map(|(&t, &w)| {
                let (x, dx) = map(t);
                (origin + s * x, w * s * dx)
            })
            .unzip();
        Ok(self.mapped(nodes, weights, interval))
    }

    /// Nodes, from `a` to `b`: ascending, or descending for a rule on a reversed interval.
    pub fn nodes(&self) -> &[f64] {
        &self.nodes
    }

    /// Weights, in the order of the nodes.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// `(node, weight)` pairs, in the order of [`Rule::nodes`].
    pub fn iter(&self) -> impl ExactSizeIterator<Item = (f64, f64)> + '_ {
        self.nodes.iter().copied().zip(self.weights.iter().copied())
    }

    /// Number of points `m`.
    pub fn num_points(&self) -> usize {
        self.nodes.len()
    }

    /// The interval `(a, b)` the rule integrates over (infinite ends for Hermite and
    /// Laguerre rules).
    pub fn interval(&self) -> (f64, f64) {
        self.interval
    }

    /// The family of the rule.
    pub fn kind(&self) -> RuleKind {
        self.kind
    }

    /// Highest polynomial degree the rule integrates exactly.
    pub fn degree_of_exactness(&self) -> usize {
        self.kind.degree_of_exactness(self.num_points())
    }

    /// `Σ_i w_i f(x_i)`, summed in the order of the nodes.
    pub fn integrate(&self, mut f: impl FnMut(f64) -> f64) -> f64 {
        self.iter().map(|(x, w)| w * f(x)).sum()
    }

    /// A vector- or matrix-valued integrand: `out = Σ_i w_i f(x_i)`, where `f(x, values)`
    /// writes the integrand's `out.len()` components at `x` into `values` (a scratch slice
    /// of that length, zeroed before each call). Nothing is allocated per node; each
    /// component is summed in the order of the nodes, as [`Rule::integrate`] sums.
    ///
    /// ```
    /// use lgsvi_quadrature::gauss_legendre;
    /// // ∫_0^1 (1, x, x²) dx and the 2 × 2 matrix ∫_0^1 [[x, x²], [x³, 1]] dx in one pass each.
    /// let rule = gauss_legendre(3)?.on(0.0, 1.0)?;
    /// let mut moments = [0.0; 3];
    /// rule.integrate_into(|x, v| { v[0] = 1.0; v[1] = x; v[2] = x * x; }, &mut moments);
    /// assert!((moments[2] - 1.0 / 3.0).abs() < 4.0 * f64::EPSILON);
    /// let mut m = [0.0; 4]; // row-major
    /// rule.integrate_into(|x, v| v.copy_from_slice(&[x, x * x, x.powi(3), 1.0]), &mut m);
    /// assert!((m[2] - 0.25).abs() < 4.0 * f64::EPSILON && (m[3] - 1.0).abs() < 4.0 * f64::EPSILON);
    /// # Ok::<(), lgsvi_quadrature::QuadratureError>(())
    /// ```
    pub fn integrate_into(&self, mut f: impl FnMut(f64, &mut [f64]), out: &mut [f64]) {
        out.fill(0.0);
        let mut values = vec![0.0; out.len()];
        for (x, w) in self.iter() {
            values.fill(0.0);
            f(x, &mut values);
            for (o, v) in out.iter_mut().zip(&values) {
                *o += w * v;
            }
        }
    }
}
