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
}

impl RuleKind {
    /// Highest polynomial degree integrated exactly by the `m`-point rule of this family.
    pub fn degree_of_exactness(self, m: usize) -> usize {
        match self {
            RuleKind::GaussLegendre => 2 * m - 1,
            RuleKind::GaussLobatto => 2 * m - 3,
            RuleKind::GaussRadauLeft | RuleKind::GaussRadauRight => 2 * m - 2,
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
}

impl Rule {
    /// A rule on `[−1, 1]` from nodes (ascending) and weights computed by this crate.
    pub(crate) fn reference(kind: RuleKind, nodes: Vec<f64>, weights: Vec<f64>) -> Self {
        debug_assert_eq!(nodes.len(), weights.len());
        debug_assert!(nodes.windows(2).all(|w| w[0] < w[1]));
        Self {
            kind,
            reference_nodes: nodes.clone(),
            reference_weights: weights.clone(),
            nodes,
            weights,
            interval: (-1.0, 1.0),
        }
    }

    /// The same rule mapped to `[a, b]`. With `a > b` the rule integrates backwards, as
    /// `∫_a^b = −∫_b^a` in calculus: its nodes run from `a` down to `b` and its weights are
    /// negative (each the negated weight of the forward rule's node at the same place).
    ///
    /// # Errors
    /// [`QuadratureError::NonFiniteInterval`] if `a` or `b` is NaN or infinite,
    /// [`QuadratureError::EmptyInterval`] if `a = b`.
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
        let half_length = 0.5 * (b - a);
        let nodes = self
            .reference_nodes
            .iter()
            .map(|&t| a * (0.5 * (1.0 - t)) + b * (0.5 * (1.0 + t)))
            .collect();
        let weights = self
            .reference_weights
            .iter()
            .map(|&w| w * half_length)
            .collect();
        Ok(Self {
            kind: self.kind,
            reference_nodes: self.reference_nodes.clone(),
            reference_weights: self.reference_weights.clone(),
            nodes,
            weights,
            interval: (a, b),
        })
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

    /// The interval `(a, b)` the rule integrates over.
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
}
