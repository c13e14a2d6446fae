//! The element trait [`LieGroup`] and the exponential map the law suite reads ([`ExponentialMap`]).

use nalgebra::RealField;
use std::fmt::Debug;

/// A matrix Lie group with its Lie algebra identified with `ℝ^DOF` by `hat`/`vee`.
///
/// Implemented by [`SO3`](crate::SO3) and [`SE3`](crate::SE3), generic over the scalar
/// (`f64`, or a dual number for automatic differentiation). Conventions:
///
/// - `compose(a, b)` is the matrix product `a·b`; with frame-named variables,
///   `a_from_c = a_from_b.compose(&b_from_c)`.
/// - `adjoint()` is `Ad_g`, with `(Ad_g ξ)^ = g ξ^ g⁻¹`; `small_adjoint(ξ)` is `ad_ξ`,
///   with `ad_ξ η = [ξ^, η^]^∨`.
/// - The dual pairing is the Euclidean one on `ℝ^DOF`, so `Ad_g*` is `Ad_gᵀ`, and the
///   coadjoint action (body momentum to spatial momentum) is `μ ↦ Ad_{g⁻¹}ᵀ μ`; on SO(3)
///   that is `μ ↦ Rμ`.
pub trait LieGroup: Clone + Debug + PartialEq {
    /// Scalar type: `f64`, or a dual number.
    type Scalar: RealField + Copy;
    /// Lie algebra element in coordinates, `SVector<Scalar, DOF>`.
    type Tangent: Clone + Debug + PartialEq;
    /// Linear map on the algebra, `SMatrix<Scalar, DOF, DOF>`.
    type Jacobian: Clone + Debug + PartialEq;
    /// What the group acts on (points of ℝ³ for SO(3) and SE(3)).
    type Point;
    /// The matrix representation (3×3 for SO(3), homogeneous 4×4 for SE(3)); `hat`
    /// returns algebra elements in the same representation.
    type Matrix: Clone + Debug + PartialEq;

    /// Dimension of the group (of its Lie algebra).
    const DOF: usize;
    /// Name, for messages.
    const NAME: &'static str;

    /// The identity `e`.
    fn identity() -> Self;
    /// The product `self · other`.
    fn compose(&self, other: &Self) -> Self;
    /// The inverse `self⁻¹`.
    fn inverse(&self) -> Self;
    /// The action on a point.
    fn act(&self, point: &Self::Point) -> Self::Point;
    /// The matrix representation of the element.
    fn to_matrix(&self) -> Self::Matrix;
    /// `ξ ↦ ξ^`, coordinates to the matrix Lie algebra.
    fn hat(xi: &Self::Tangent) -> Self::Matrix;
    /// `ξ^ ↦ ξ`, the inverse of [`LieGroup::hat`] (reads only the entries `hat` writes).
    fn vee(matrix: &Self::Matrix) -> Self::Tangent;
    /// The adjoint `Ad_g`.
    fn adjoint(&self) -> Self::Jacobian;
    /// The adjoint of the algebra, `ad_ξ`.
    fn small_adjoint(xi: &Self::Tangent) -> Self::Jacobian;
    /// The coadjoint action `μ ↦ Ad_{g⁻¹}ᵀ μ` (body momentum to spatial momentum).
    fn coadjoint_action(&self, mu: &Self::Tangent) -> Self::Tangent;
}

/// The exponential map and its inverse near the identity: what the law suite
/// ([`crate::laws`]) reads of a group besides [`LieGroup`].
pub trait ExponentialMap: LieGroup {
    /// `exp(ξ)`.
    fn exp(xi: &Self::Tangent) -> Self;
    /// `log(g)`, the inverse of `exp` near the identity.
    fn log(&self) -> Self::Tangent;
}
