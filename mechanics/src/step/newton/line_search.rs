//! The line search of the Newton loop: a step that does not lower the residual is halved
//! from the last accepted iterate.

/// Backtracking halves a Newton step that does not lower the residual up to this many
/// times. Far from the solution (long steps, the heavy top with the exact matching) the
/// full step can overshoot; near it the full step is always taken, so convergence stays
/// quadratic.
pub(super) const MAX_HALVINGS: u32 = 8;

/// Whether a trial iterate is worse than the last accepted one: outside the chart (no
/// assembly), NaN, or a residual not below `previous` — except when the assembly was
/// expected to be the last, where the full step stands.
pub(super) fn worse(assembled: Option<(f64, f64)>, previous: f64, expect_converged: bool) -> bool {
    match assembled {
        Some((r, _)) => r.is_nan() || (r >= previous && !expect_converged),
        None => true,
    }
}

/// Whether the step may be halved once more from `damping`.
pub(super) fn may_halve(damping: f64) -> bool {
    damping > 0.5f64.powi(MAX_HALVINGS as i32)
}
