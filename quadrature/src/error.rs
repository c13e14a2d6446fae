//! Errors of this crate.

/// Why a quadrature rule could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum QuadratureError {
    /// The rule asks for fewer points than it can have.
    #[error("{rule} needs at least {min} point(s), got {points}")]
    TooFewPoints {
        /// The rule's name, e.g. "Gauss-Lobatto".
        rule: &'static str,
        /// The number of points asked for.
        points: usize,
        /// The least number this rule can have.
        min: usize,
    },
    /// An end of the interval is NaN or infinite.
    #[error("the interval [{a}, {b}] has a non-finite end; give finite ends")]
    NonFiniteInterval {
        /// Left end.
        a: f64,
        /// Right end.
        b: f64,
    },
    /// The interval is empty (`a = b`).
    #[error("the interval [{a}, {b}] is empty; give a ≠ b (a > b integrates backwards)")]
    EmptyInterval {
        /// Left end.
        a: f64,
        /// Right end.
        b: f64,
    },
    /// The Jacobi matrix handed to [`golub_welsch`](crate::golub_welsch) has inconsistent sizes.
    #[error(
        "a Jacobi matrix with {diagonal} diagonal entries needs {} off-diagonal entries, got {off_diagonal}",
        diagonal.saturating_sub(1)
    )]
    JacobiShape {
        /// Length of the diagonal.
        diagonal: usize,
        /// Length of the off-diagonal.
        off_diagonal: usize,
    },
    /// An entry of the Jacobi matrix is NaN or infinite.
    #[error("Jacobi matrix entry {index} of the {part} is not finite")]
    NonFiniteJacobi {
        /// "diagonal" or "off-diagonal".
        part: &'static str,
        /// Index of the offending entry.
        index: usize,
    },
    /// The total mass `μ₀ = ∫ w(x) dx` of the weight function is not positive and finite.
    #[error("the total mass of the weight function must be positive and finite, got {mass}")]
    InvalidMass {
        /// The mass given.
        mass: f64,
    },
    /// An exponent of a weight function for which the weight is not integrable.
    #[error("the weight's exponent {name} = {value} must be finite and above −1 (the weight is not integrable otherwise)")]
    InvalidExponent {
        /// `"alpha"` or `"beta"`.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A rule on an infinite interval asked to map to a finite one.
    #[error("a {rule:?} rule integrates over {interval:?} and has no map to a finite interval; shift and scale its nodes (x = c + s·t) and weights (w·s) yourself")]
    UnboundedRule {
        /// The rule's family.
        rule: crate::RuleKind,
        /// Its interval.
        interval: (f64, f64),
    },
    /// A weighted rule mapped to a reversed interval.
    #[error("a weighted rule maps to [a, b] with a < b only (its weight (b − x)^α (x − a)^β is defined there), got [{a}, {b}]; map to [{b}, {a}] and negate the result")]
    ReversedWeight {
        /// Left end.
        a: f64,
        /// Right end.
        b: f64,
    },
    /// The Gauss–Jacobi rule asked for has no Gauss–Kronrod extension with real nodes
    /// inside `(−1, 1)` and positive weights.
    #[error("the {points}-point Gauss-Jacobi rule with α = {alpha}, β = {beta} has no Gauss-Kronrod extension with real nodes inside (−1, 1) and positive weights; take exponents with α = β in (−1/2, 3/2] (every n has one), fewer points, or a Gauss-Legendre pair on a mapped integrand")]
    NoKronrodExtension {
        /// The Gauss points asked for.
        points: usize,
        /// `α`.
        alpha: f64,
        /// `β`.
        beta: f64,
    },
    /// The implicit QL iteration did not converge (it converges in practice; this guards
    /// against pathological input such as entries spanning hundreds of orders of magnitude).
    #[error("the tridiagonal eigenvalue iteration did not converge for eigenvalue {index} in {iterations} sweeps")]
    EigenNotConverged {
        /// Index of the eigenvalue being deflated.
        index: usize,
        /// Sweeps spent on it.
        iterations: usize,
    },
}

/// [`QuadratureError::TooFewPoints`] when a `rule` of `points` points needs at least `min`.
pub(crate) fn at_least(
    rule: &'static str,
    points: usize,
    min: usize,
) -> Result<(), QuadratureError> {
    if points < min {
        return Err(QuadratureError::TooFewPoints { rule, points, min });
    }
    Ok(())
}
