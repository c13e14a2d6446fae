//! The convergence test of the Newton loop: when an iterate is accepted, and when the next
//! assembly is expected to be the last.

/// A Newton step taken from a residual below this fraction of the largest terms of the
/// equations lands, by quadratic convergence (`r_{k+1} ≈ 0.1 r_k²` in relative terms on
/// the paper's cases), at an error ~1e-17 of them: below rounding, so the step is accepted
/// once the residual is at its rounding floor (≤ √ε of the terms) without a further
/// iteration that could only confirm the floor.
///
/// From an iterate this close, the full Newton step is also always taken (no backtracking):
/// the residual after it is rounding noise, and comparing noise with noise would reject
/// about half of these steps and keep the previous iterate, whose error — the quadratic
/// remainder of the step before, ~ the rounding floor but with a fixed sign along a
/// trajectory — then accumulates into a steady energy drift, where taking the full step
/// leaves only the random walk of rounding.
pub(super) const QUADRATIC_REGIME: f64 = 1e-8;

/// Whether the next assembly is expected to be the last: after a Newton step from a
/// relative residual below [`QUADRATIC_REGIME`], the error is (quadratic convergence) far
/// below rounding, and the assembly needs no Hessians.
pub(super) fn expect_converged(iterations: usize, previous: f64, previous_scale: f64) -> bool {
    iterations > 0 && previous <= QUADRATIC_REGIME * previous_scale
}

/// Whether an iterate with `residual` (`scale` its equations' largest terms) is at the
/// rounding floor: a few ulps of the terms, or — once below √ε of them — no longer halving
/// (the rounding floor of the sums, which for m·n terms can sit a little above a few ulps),
/// or below √ε when the assembly was expected to be the last. Newton converges
/// quadratically, so the last accepted step is always taken at the floor.
pub(super) fn at_rounding_floor(
    residual: f64,
    scale: f64,
    previous: f64,
    iterations: usize,
    expect_converged: bool,
) -> bool {
    let tight = 4.0 * f64::EPSILON * scale;
    let loose = f64::EPSILON.sqrt() * scale;
    let stagnated = iterations > 0 && residual > 0.5 * previous && residual <= loose;
    residual <= tight || stagnated || (expect_converged && residual <= loose)
}
