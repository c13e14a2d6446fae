//! The chord policy of the Newton loop: when a factored matrix is kept for the steps after
//! it, and when it is given up for a fresh one.

/// A Newton matrix factored at an iterate with relative residual `r_f` at or below this is
/// kept for the rest of the step: each chord step with it (an assembly without Hessians
/// and two triangular solves, no LU) multiplies the error by ~`r_f` (the matrices differ
/// by ~`r_f`), and `r₁ ≈ 0.1 r_f²` after the Newton step (quadratic convergence). Two or
/// three chord steps then cost less than one more Newton step, which forms the Hessians
/// and a new LU.
pub(super) const CHORD_EXPECTED: f64 = 1e-4;

/// Chord steps continue until their predicted remainder (the product of `r_f` and the
/// error estimate they started from) is below this, far below rounding: a remainder kept
/// at the rounding floor has a fixed sign along a trajectory and accumulates (see
/// [`super::convergence::QUADRATIC_REGIME`]), so the iterate is accepted only after it (typical chain from
/// `r_f = 3e-6`: 7e-13 → 2e-18 → 6e-24).
pub(super) const CHORD_REMAINDER: f64 = 1e-20;

/// Whether the next step will be a chord step with the matrix factored at relative
/// residual `factored_at` (then the assembly needs no Hessians).
pub(super) fn expect_chord(factored_at: Option<f64>) -> bool {
    factored_at.is_some_and(|r_f| r_f <= CHORD_EXPECTED)
}

/// A chord step that did not cut the relative residual tenfold (above the floor) means the
/// kept matrix is too far off: take a Newton step instead.
pub(super) fn too_slow(
    last_was_chord: bool,
    at_floor: bool,
    relative: f64,
    previous: f64,
    previous_scale: f64,
) -> bool {
    last_was_chord && !at_floor && relative > 0.1 * previous / previous_scale.max(f64::MIN_POSITIVE)
}

/// The kept matrix's residual `r_f` when this step is a chord step with it: with an exact
/// Jacobian, not after a slow chord step, and only while the matrix is close enough
/// (`r_f ≤ CHORD_EXPECTED`) or the predicted remainder `error · r_f` is below
/// [`CHORD_REMAINDER`].
pub(super) fn chord_with(
    factored_at: Option<f64>,
    exact: bool,
    slow: bool,
    error: f64,
) -> Option<f64> {
    factored_at
        .filter(|&r_f| exact && !slow && (r_f <= CHORD_EXPECTED || error * r_f <= CHORD_REMAINDER))
}
