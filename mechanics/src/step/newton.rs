//! The Newton policy of a step: exact Newton from the predictor's guess, chord steps with
//! a matrix factored close enough to the solution, backtracking far from it, and stopping
//! rules that accept a step only at the rounding floor of its equations.

use super::assembly::WorkspaceOf;
use super::{Element, StepOutcome, Stepper};
use crate::error::MechanicsError;
use crate::group::GroupChart;
use crate::settings::NewtonJacobian;
use crate::system::GroupLagrangian;
use faer::Mat;
use nalgebra::SVector;

/// A Newton step taken from a residual below this fraction of the largest terms of the
/// equations lands, by quadratic convergence (measured contraction `r_{k+1} ≈ 0.1 r_k²`
/// in relative terms on the paper's cases), at an error ~1e-17 of them: below rounding,
/// so the step is accepted once the residual is at its rounding floor (≤ √ε of the terms)
/// without a further iteration that could only confirm the floor.
///
/// From an iterate this close, the full Newton step is also always taken (no backtracking):
/// the residual after it is rounding noise, and comparing noise with noise would reject
/// about half of these steps and keep the previous iterate, whose error — the quadratic
/// remainder of the step before, ~ the rounding floor but with a fixed sign along a
/// trajectory — then accumulates: measured, case A (exp, h = 0.5, n = 8), an energy drift
/// of 1.7e-17 per step (3.1e-13 after 2·10⁴ steps), none without the backtracking
/// (7e-15, random).
const QUADRATIC_REGIME: f64 = 1e-8;

/// A Newton matrix factored at an iterate with relative residual `r_f` at or below this is
/// kept for the rest of the step: each chord step with it (an assembly without Hessians
/// and two triangular solves, no LU) multiplies the error by ~`r_f` (the matrices differ
/// by ~`r_f`), and `r₁ ≈ 0.1 r_f²` after the Newton step (measured). Two or three chord
/// steps then cost less than one more Newton step (measured, case A, n = 10).
const CHORD_EXPECTED: f64 = 1e-4;

/// Chord steps continue until their predicted remainder (the product of `r_f` and the
/// error estimate they started from) is below this, far below rounding: a remainder kept
/// at the rounding floor has a fixed sign along a trajectory and accumulates (see
/// [`QUADRATIC_REGIME`]), so the iterate is accepted only after it (typical chain from
/// `r_f = 3e-6`: 7e-13 → 2e-18 → 6e-24).
const CHORD_REMAINDER: f64 = 1e-20;

/// Solves `L U x = b` in place, with `L U` the unit-lower and upper factors that faer's
/// partial-pivoting LU left in `lu` (the row permutation already applied to `b`): forward
/// and back substitution by columns. For one right-hand side of the sizes a step has
/// (`3(n − 1)` ≤ ~70), faer's blocked triangular solves spend more in dispatch than in
/// arithmetic (`docs/performance.md` §6).
pub(super) fn substitute(lu: &Mat<f64>, b: &mut [f64]) {
    let size = b.len();
    for k in 0..size {
        let bk = b[k];
        let below = &lu.col_as_slice(k)[k + 1..];
        for (x, l) in b[k + 1..].iter_mut().zip(below) {
            *x -= l * bk;
        }
    }
    for k in (0..size).rev() {
        let column = lu.col_as_slice(k);
        b[k] /= column[k];
        let bk = b[k];
        for (x, u) in b[..k].iter_mut().zip(&column[..k]) {
            *x -= u * bk;
        }
    }
}

impl<S: GroupLagrangian<D>, C: GroupChart<S::Group, D>, const D: usize> Stepper<'_, S, C, D> {
    /// Newton on the step's equations from the guess in `work.xi`.
    pub(crate) fn solve(
        &self,
        base: &Element<S, D>,
        mu: &SVector<f64, D>,
        work: &mut WorkspaceOf<S, D>,
        step: usize,
        time: f64,
    ) -> Result<StepOutcome<Element<S, D>, D>, MechanicsError> {
        let n = self.d.n;
        let exact = self.settings.jacobian() == NewtonJacobian::Exact;
        let max_iterations = self.settings.max_newton_iterations();
        let mut previous = f64::INFINITY;
        let mut previous_scale = 0.0f64;
        let mut iterations = 0;
        let mut factorizations = 0;
        // Backtracking: a Newton step that does not lower the residual is halved (from the
        // last accepted iterate) up to `MAX_HALVINGS` times. Far from the solution (long
        // steps, the heavy top with the exact matching) the full step can overshoot;
        // near it the full step is always taken, so convergence stays quadratic.
        const MAX_HALVINGS: u32 = 8;
        let mut damping = 1.0f64;
        // The relative residual of the iterate at which `work.jacobian` was factored in this
        // solve, if it was.
        let mut factored_at: Option<f64> = None;
        // After a chord step whose predicted remainder is above CHORD_REMAINDER: that
        // prediction (the residual at the rounding floor can no longer show it); else 0.
        let mut pending = 0.0f64;
        // Whether the last step taken was a chord step.
        let mut last_was_chord = false;
        loop {
            // After a Newton step from a residual below QUADRATIC_REGIME of its terms, the
            // error is (quadratic convergence) far below rounding: this assembly is
            // expected to be the last, and needs no Hessians.
            let expect_converged = iterations > 0 && previous <= QUADRATIC_REGIME * previous_scale;
            // With a matrix factored below CHORD_EXPECTED, the next step is a chord step:
            // assemble without Hessians.
            let expect_chord = factored_at.is_some_and(|r_f| r_f <= CHORD_EXPECTED);
            // A halved trial point only needs its residual: the Hessians follow if it is
            // accepted and another step is needed.
            let with_hessians = exact && !expect_converged && !expect_chord && damping == 1.0;
            let in_domain = self.check_domain(work, step, time);
            let saved = work.guess_assembled.take().filter(|_| iterations == 0);
            let assembled = in_domain
                .as_ref()
                .ok()
                .map(|_| saved.unwrap_or_else(|| self.assemble(base, mu, work, with_hessians)));
            let worse = match assembled {
                // NaN counts as worse; near the solution the full step stands.
                Some((r, _)) => r.is_nan() || (r >= previous && !expect_converged),
                None => true,
            };
            if iterations > 0 && worse && damping > 0.5f64.powi(MAX_HALVINGS as i32) {
                damping *= 0.5;
                for i in 1..n {
                    for c in 0..D {
                        work.xi[i][c] =
                            work.xi_accepted[i][c] + damping * work.delta[D * (i - 1) + c];
                    }
                }
                continue;
            }
            in_domain?;
            let (residual, scale) = assembled.unwrap_or((f64::NAN, 0.0));
            if !residual.is_finite() {
                return Err(MechanicsError::SingularJacobian { step, time });
            }
            // Converged: the residual is a few ulps of its largest terms, or — once below
            // √ε of them — it has stopped halving (the rounding floor of the sums, which
            // for m·n terms can sit a little above a few ulps). Newton converges
            // quadratically, so the last accepted step is always taken at the floor.
            let scale = scale.max(f64::MIN_POSITIVE);
            let tight = 4.0 * f64::EPSILON * scale;
            let loose = f64::EPSILON.sqrt() * scale;
            let stagnated = iterations > 0 && residual > 0.5 * previous && residual <= loose;
            let at_floor =
                residual <= tight || stagnated || (expect_converged && residual <= loose);
            if at_floor && pending == 0.0 {
                return Ok(self.outcome(base, work, iterations, factorizations));
            }
            if iterations >= max_iterations {
                return Err(MechanicsError::NewtonDiverged {
                    step,
                    time,
                    iterations,
                    residual,
                });
            }
            // The error after the last step: the residual bounds it, and so does a pending
            // chord prediction once the residual is at the floor.
            let relative = residual / scale;
            let error = if pending > 0.0 {
                relative.min(pending)
            } else {
                relative
            };
            // A chord step that did not cut the residual tenfold (above the floor) means the
            // kept matrix is too far off: take a Newton step instead.
            let slow = last_was_chord
                && !at_floor
                && relative > 0.1 * previous / previous_scale.max(f64::MIN_POSITIVE);
            // The kept matrix's residual, when this step is a chord step with it.
            let chord = factored_at.filter(|&r_f| {
                exact && !slow && (r_f <= CHORD_EXPECTED || error * r_f <= CHORD_REMAINDER)
            });
            last_was_chord = chord.is_some();
            pending = 0.0;
            if let Some(r_f) = chord {
                let remainder = error * r_f;
                if remainder > CHORD_REMAINDER {
                    pending = remainder;
                }
            } else {
                if exact {
                    if !with_hessians {
                        self.assemble(base, mu, work, true);
                    }
                    self.fill_jacobian(work);
                } else {
                    self.fill_jacobian_by_differences(base, mu, work);
                }
                work.factor();
                factored_at = Some(relative);
                factorizations += 1;
            }
            for (d, &p) in work.delta.iter_mut().zip(&work.perm) {
                *d = -work.residual[p];
            }
            substitute(&work.jacobian, &mut work.delta);
            work.xi_accepted.copy_from_slice(&work.xi);
            damping = 1.0;
            let deltas = &work.delta;
            if !deltas.iter().all(|x| x.is_finite()) {
                return Err(MechanicsError::SingularJacobian { step, time });
            }
            for (xi, delta) in work.xi[1..].iter_mut().zip(deltas.chunks_exact(D)) {
                *xi += SVector::<f64, D>::from_column_slice(delta);
            }
            previous = residual;
            previous_scale = scale;
            iterations += 1;
            // A chord step from an iterate at the rounding floor whose predicted remainder
            // is below CHORD_REMAINDER leaves nothing for another assembly to show but the
            // floor again: accept it now (the simplified Newton stopping rule of implicit
            // Runge–Kutta codes: stop when the estimated error after the step is below
            // tolerance). The exact matching's momentum update reads `w`, which is `μ_k`
            // for a left-invariant, unforced ℓ and otherwise is carried through the step
            // to first order ([`Stepper::carry_matching`]). Saves one of the four
            // assemblies of a typical step.
            if chord.is_some() && pending == 0.0 && at_floor && self.momentum_is_assembly_free() {
                self.check_domain(work, step, time)?;
                self.carry_matching(work);
                return Ok(self.outcome(base, work, iterations, factorizations));
            }
        }
    }
}
