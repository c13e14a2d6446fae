//! Errors of this crate.

/// Why a set of nodes, a basis or an evaluation was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SpectralError {
    /// Fewer nodes than the construction needs.
    #[error("{kind} needs at least {min} node(s), got {n}")]
    TooFewNodes {
        /// The node family, e.g. "Chebyshev-Lobatto".
        kind: &'static str,
        /// Nodes asked for.
        n: usize,
        /// Least number allowed.
        min: usize,
    },
    /// An end of the interval is NaN or infinite.
    #[error("the interval [{a}, {b}] has a non-finite end; give finite a < b")]
    NonFiniteInterval {
        /// Left end.
        a: f64,
        /// Right end.
        b: f64,
    },
    /// The interval is empty or reversed.
    #[error("the interval [{a}, {b}] is empty or reversed; give a < b")]
    EmptyInterval {
        /// Left end.
        a: f64,
        /// Right end.
        b: f64,
    },
    /// A node is NaN or infinite.
    #[error("node {index} is not finite ({value})")]
    NonFiniteNode {
        /// Position of the node in the input.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// Two nodes coincide; interpolation needs distinct nodes.
    #[error("nodes {first} and {second} are both {value}; interpolation nodes must be distinct")]
    DuplicateNode {
        /// Position of one of them.
        first: usize,
        /// Position of the other.
        second: usize,
        /// The shared value.
        value: f64,
    },
    /// The nodes are so badly spread that a barycentric weight underflows double precision
    /// (the interpolant's Lebesgue constant would exceed ~1e300).
    #[error("barycentric weight {index} underflows: these {n} nodes are too badly spread for double precision; use Chebyshev nodes")]
    WeightUnderflow {
        /// The weight that vanished.
        index: usize,
        /// Number of nodes.
        n: usize,
    },
    /// An evaluation point is NaN or infinite.
    #[error("evaluation point {value} is not finite")]
    NonFinitePoint {
        /// The point.
        value: f64,
    },
    /// A slice has the wrong length.
    #[error("{what} has length {got}, expected {expected}")]
    LengthMismatch {
        /// Which argument.
        what: &'static str,
        /// Length required.
        expected: usize,
        /// Length given.
        got: usize,
    },
    /// A function value is NaN or infinite where the fit sampled it.
    #[error("the function is not finite at x = {x} ({value}): fit it on an interval where it is")]
    NonFiniteValue {
        /// The sample point.
        x: f64,
        /// The value there.
        value: f64,
    },
    /// A series coefficient is NaN or infinite.
    #[error("coefficient {index} is not finite ({value})")]
    NonFiniteCoefficient {
        /// Its index.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// The fit did not reach its tolerance with the most samples it takes.
    #[error("the function is not resolved to {tol:e} on [{a}, {b}] by {points} Chebyshev points: it is not smooth there or needs more; split the interval or raise the tolerance")]
    NotResolved {
        /// Samples taken last.
        points: usize,
        /// Left end.
        a: f64,
        /// Right end.
        b: f64,
        /// The tolerance.
        tol: f64,
    },
    /// A fit tolerance outside `[ε, 1)`.
    #[error("tolerance {tol:e} is outside [2.2e-16, 1): double precision cannot fit below ε")]
    InvalidTolerance {
        /// The tolerance given.
        tol: f64,
    },
    /// An evaluation point outside the series' interval.
    #[error("x = {x} is outside [{a}, {b}]: a Chebyshev series says nothing outside its interval (refit on a larger one)")]
    OutsideInterval {
        /// The point.
        x: f64,
        /// Left end.
        a: f64,
        /// Right end.
        b: f64,
    },
    /// Two series on different intervals combined.
    #[error("the series live on {first:?} and {second:?}: combine series on one interval")]
    IntervalMismatch {
        /// The first interval.
        first: (f64, f64),
        /// The second.
        second: (f64, f64),
    },
}
