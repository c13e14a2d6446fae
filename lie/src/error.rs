//! Errors of this crate.

/// Why a group element, a chart coordinate or a differential was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LieError {
    /// An input holds NaN or infinity.
    #[error("{what} holds a non-finite number; give finite entries")]
    NonFinite {
        /// What was given ("rotation matrix", "quaternion", ...).
        what: &'static str,
    },
    /// A matrix is not orthogonal to the stated tolerance.
    #[error(
        "not a rotation: ‖RᵀR − I‖_F = {deviation:e} exceeds the tolerance {tolerance:e}; \
         use `from_matrix_orthonormalized` for data that is only nearly a rotation"
    )]
    NotOrthogonal {
        /// `‖RᵀR − I‖_F`.
        deviation: f64,
        /// The tolerance it was held to.
        tolerance: f64,
    },
    /// An orthogonal matrix with determinant −1: a reflection, not a rotation.
    #[error(
        "not a rotation: determinant {determinant} (a reflection); a rotation has determinant +1"
    )]
    NotProperRotation {
        /// The determinant found.
        determinant: f64,
    },
    /// A matrix too degenerate to have a nearest rotation (rank below 2).
    #[error(
        "the matrix is too degenerate to orthonormalise (singular values {singular_values:?}); \
         give a matrix near a rotation, whose singular values are all near 1"
    )]
    Degenerate {
        /// Its singular values, descending.
        singular_values: [f64; 3],
    },
    /// A quaternion of zero (or non-finite) norm.
    #[error(
        "a quaternion of norm {norm} cannot be normalised to a rotation; give a non-zero one \
         (w, x, y, z)"
    )]
    ZeroQuaternion {
        /// Its norm.
        norm: f64,
    },
    /// A point outside the domain of a chart or of its differential's inverse.
    #[error("outside the domain of the {chart} chart: rotation angle {angle} must stay below {limit}; {hint}")]
    OutsideChart {
        /// The chart's name.
        chart: &'static str,
        /// The rotation angle (or chart-vector norm) met.
        angle: f64,
        /// The bound it must stay below.
        limit: f64,
        /// What to do about it.
        hint: &'static str,
    },
}
