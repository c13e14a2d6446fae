//! The Newton loop of a step: exact Newton from the predictor's guess, chord steps with a
//! matrix factored close enough to the solution, backtracking far from it, and stopping
//! rules that accept a step only at the rounding floor of its equations. The loop is here;
//! its policies are their own modules: [`convergence`] (the stopping test), [`chord`]
//! (when a factored matrix is kept), [`carry`] (when a step starts from an earlier step's
//! factored matrix) and [`line_search`] (backtracking).

use super::assembly::WorkspaceOf;
use super::{Element, StepOutcome, StepSolver};
use crate::error::MechanicsError;
use crate::group::GroupChart;
use crate::settings::NewtonJacobian;
use crate::system::System;
use nalgebra::{DMatrix, SVector};

pub(super) mod carry;
use carry::Chain;
mod chord;
mod convergence;
mod line_search;

/// Solves `L U x = b` in place, with `L U` the unit-lower and upper factors that
/// [`super::lu::lu_in_place`] left in `lu` (the row permutation already applied to `b`):
/// forward and back substitution down the columns of `lu`'s contiguous storage. For one
/// right-hand side of the sizes a step has (`3(n − 1)` ≤ ~70), faer's blocked triangular
/// solves spend more in dispatch than in arithmetic.
#[multiversion::multiversion(targets("x86_64+avx+avx2+fma"))]
pub(super) fn substitute(lu: &DMatrix<f64>, b: &mut [f64]) {
    let size = b.len();
    let column_of = |k: usize| &lu.as_slice()[k * size..(k + 1) * size];
    for k in 0..size {
        let bk = b[k];
        let below = &column_of(k)[k + 1..];
        for (x, l) in b[k + 1..].iter_mut().zip(below) {
            *x -= l * bk;
        }
    }
    for k in (0..size).rev() {
        let column = column_of(k);
        b[k] /= column[k];
        let bk = b[k];
        for (x, u) in b[..k].iter_mut().zip(&column[..k]) {
            *x -= u * bk;
        }
    }
}

/// [`substitute`] for `3D` right-hand sides at once, stored by rows (row `r` holds entry
/// `r` of every right-hand side, as three `D`-vectors): each elimination is one row
/// update `3D` wide, which vectorises, where one column's substitution is a chain of short
/// loops. With `skip_first`, the first family is left as it is (a linearisation whose `θ`
/// columns are zero skips them).
pub(super) fn substitute_rows<const D: usize>(
    lu: &DMatrix<f64>,
    b: &mut [[SVector<f64, D>; 3]],
    skip_first: bool,
) {
    if skip_first {
        substitute_families::<D, 1>(lu, b);
    } else {
        substitute_families::<D, 0>(lu, b);
    }
}

/// [`substitute_rows`] on the families from `FIRST` on (a constant, so that the row
/// updates keep their fixed width).
#[multiversion::multiversion(targets("x86_64+avx+avx2+fma"))]
fn substitute_families<const D: usize, const FIRST: usize>(
    lu: &DMatrix<f64>,
    b: &mut [[SVector<f64, D>; 3]],
) {
    let size = b.len();
    let column_of = |k: usize| &lu.as_slice()[k * size..(k + 1) * size];
    for k in 0..size {
        let bk = b[k];
        let below = &column_of(k)[k + 1..];
        for (x, &l) in b[k + 1..].iter_mut().zip(below) {
            for (xf, bf) in x[FIRST..].iter_mut().zip(&bk[FIRST..]) {
                *xf -= bf * l;
            }
        }
    }
    for k in (0..size).rev() {
        let column = column_of(k);
        let pivot = column[k];
        for e in b[k][FIRST..].iter_mut() {
            *e /= pivot;
        }
        let bk = b[k];
        for (x, &u) in b[..k].iter_mut().zip(&column[..k]) {
            for (xf, bf) in x[FIRST..].iter_mut().zip(&bk[FIRST..]) {
                *xf -= bf * u;
            }
        }
    }
}

/// The largest last chord step, relative to the unknowns, after which the points of the
/// assembly before it are kept for a linearisation (`Workspace::converged_hessians`):
/// 64 ulps, so that the linearisation from them is the converged step's to ~1e-14.
const KEPT_STEP: f64 = 64.0 * f64::EPSILON;

impl<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> StepSolver<'_, S, C, D> {
    /// Newton on the step's equations from the guess in `work.xi`. A solve that fails
    /// leaves no factors for a later step to start from.
    pub(crate) fn solve(
        &self,
        base: &Element<S, D>,
        mu: &SVector<f64, D>,
        work: &mut WorkspaceOf<S, D>,
        step: usize,
        time: f64,
    ) -> Result<StepOutcome<Element<S, D>, D>, MechanicsError> {
        let solved = self.newton(base, mu, work, step, time);
        if solved.is_err() {
            work.forget_factors();
        }
        solved
    }

    /// [`StepSolver::solve`]'s loop.
    fn newton(
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
        // Backtracking (`line_search`): the damping of the step being tried.
        let mut damping = 1.0f64;
        // Chord steps on an earlier step's factors (`carry`) while they last.
        let carried = exact
            && self.settings.reuses_factors()
            && max_iterations >= carry::MIN_ITERATIONS
            && work.carry.attempt(work.drift());
        let mut factors = ChordState::new(carried);
        let singular = || MechanicsError::SingularJacobian {
            step,
            time,
            advice: self.chart.advice(),
        };
        loop {
            // An assembly expected to be the last, or before a chord step, needs no Hessians
            // (but for a step to be linearised: below).
            // On carried factors the chord chain ends where its predicted remainder does.
            let expect_converged = if factors.carried() {
                carry::expect_last(iterations, factors.pending, factors.at)
            } else {
                convergence::expect_converged(iterations, previous, previous_scale)
            };
            let expect_chord = factors.carried() || chord::expect_chord(factors.at);
            // A halved trial point only needs its residual: the Hessians follow if it is
            // accepted and another step is needed.
            // A step to be linearised keeps the Hessians of the assembly expected to be
            // the last: the linearisation's Newton matrix is formed from them.
            let with_hessians = exact
                && damping == 1.0
                && if expect_converged {
                    work.keep_converged_hessians
                } else {
                    !expect_chord
                };
            let in_domain = self.check_domain(work, step, time);
            let saved = work.guess_assembled.take().filter(|_| iterations == 0);
            // The guess's saved assembly carries Hessians with the exact Jacobian.
            let has_hessians = if saved.is_some() {
                exact
            } else {
                with_hessians
            };
            let assembled = in_domain
                .as_ref()
                .ok()
                .map(|_| saved.unwrap_or_else(|| self.assemble(base, mu, work, with_hessians)));
            // A carried chord step from a residual below `carry::MEASURABLE` stands (only
            // the rounding floor's noise is left to compare); from above it, a worse iterate
            // means the factors are too far off: back to the accepted iterate, which the
            // step's own Newton matrix takes from (its assembly, with Hessians, comes next).
            let stands = if factors.carried() {
                previous < carry::MEASURABLE * previous_scale
            } else {
                expect_converged
            };
            let worse = line_search::worse(assembled, previous, stands);
            if iterations > 0 && worse && factors.carried() {
                factors.give_up(&mut work.carry, true);
                work.xi.copy_from_slice(&work.xi_accepted);
                previous = f64::INFINITY;
                continue;
            }
            if iterations > 0 && worse && line_search::may_halve(damping) {
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
                return Err(singular());
            }
            let scale = scale.max(f64::MIN_POSITIVE);
            let at_floor = convergence::at_rounding_floor(
                residual,
                scale,
                previous,
                iterations,
                expect_converged,
            );
            // On carried factors, only after a checked chord step (or at a guess that is
            // already at the floor, where no chord step was taken).
            if at_floor && factors.pending == 0.0 && (factors.checked() || iterations == 0) {
                work.converged_hessians = has_hessians;
                if factors.carried() {
                    work.carry.served();
                }
                return Ok(self.outcome(base, work, iterations, factorizations));
            }
            if iterations >= max_iterations {
                return Err(MechanicsError::NewtonDiverged {
                    step,
                    time,
                    iterations,
                    residual,
                    advice: self.chart.advice(),
                });
            }
            // The error after the last step: the residual bounds it, and so does a pending
            // chord prediction once the residual is at the floor.
            let relative = residual / scale;
            let error = if factors.pending > 0.0 {
                relative.min(factors.pending)
            } else {
                relative
            };
            let slow = chord::too_slow(
                factors.last_was_chord,
                at_floor,
                relative,
                previous,
                previous_scale,
            );
            let previous_relative = previous / previous_scale.max(f64::MIN_POSITIVE);
            if iterations == 0 {
                work.carry.guessed(relative);
            }
            if factors.carried() && iterations == 0 && relative < carry::MEASURABLE {
                // A guess this close leaves no chord step whose contraction could be
                // measured above the floor's noise: the step's own Newton step instead.
                factors.give_up(&mut work.carry, false);
            }
            if factors.last_was_chord && previous_relative >= carry::MEASURABLE {
                if let Some(chain) = &mut factors.chain {
                    // The carried factors' contraction, checked on this chord step (at the
                    // floor or not: a residual that stagnated from a measurable one is a
                    // contraction that failed).
                    match chain.record(relative / previous_relative, relative) {
                        Some(r_f) => factors.at = Some(r_f),
                        None => factors.give_up(&mut work.carry, true),
                    }
                }
            }
            let chord = if factors.carried() {
                factors.at
            } else {
                chord::chord_with(factors.at, exact, slow, error)
            };
            factors.last_was_chord = chord.is_some();
            factors.pending = 0.0;
            if let Some(r_f) = chord {
                let remainder = error * r_f;
                if remainder > chord::CHORD_REMAINDER {
                    factors.pending = remainder;
                }
            } else {
                if exact {
                    if !has_hessians {
                        self.assemble(base, mu, work, true);
                    }
                    self.fill_jacobian(work);
                } else {
                    self.fill_jacobian_by_differences(base, mu, work);
                }
                work.factor();
                factors.formed_at(relative);
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
                if factors.carried() {
                    // Carried factors that give no finite step (a singular matrix kept
                    // from a failed step): the step's own matrix at this iterate.
                    factors.give_up(&mut work.carry, true);
                    previous = f64::INFINITY;
                    continue;
                }
                return Err(singular());
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
            // to first order ([`StepSolver::carry_matching`]). Saves one of the four
            // assemblies of a typical step.
            if chord.is_some()
                && factors.pending == 0.0
                && at_floor
                && factors.checked()
                && self.momentum_is_assembly_free()
            {
                self.check_domain(work, step, time)?;
                self.carry_matching(work);
                // The points are those of the iterate before this last chord step: the
                // converged step's to rounding when that step moved the unknowns by no
                // more than a few ulps (the floor test also accepts a residual up to √ε of
                // its terms, from which the step can be larger: the linearisation then
                // assembles the converged unknowns itself).
                work.converged_hessians = has_hessians && {
                    let size = work.xi.iter().fold(0.0f64, |a, x| a.max(x.amax()));
                    let moved = work.delta.iter().fold(0.0f64, |a, d| a.max(d.abs()));
                    moved <= KEPT_STEP * size
                };
                if factors.carried() {
                    work.carry.served();
                }
                return Ok(self.outcome(base, work, iterations, factorizations));
            }
        }
    }
}

/// What a solve knows of the factors in its Newton matrix and of its chord steps (the
/// factors themselves are the workspace's).
struct ChordState {
    /// The relative residual of the iterate they were formed at in this solve; for
    /// carried factors, the contraction standing for their `r_f`; `None` before any, and
    /// after carried ones are given up.
    at: Option<f64>,
    /// While the factors are an earlier step's: the chain of chord steps on them.
    chain: Option<Chain>,
    /// After a chord step whose predicted remainder is above
    /// [`chord::CHORD_REMAINDER`]: that prediction (the residual at the rounding floor
    /// can no longer show it); else 0.
    pending: f64,
    /// The last step taken was a chord step.
    last_was_chord: bool,
}

impl ChordState {
    /// No factors yet, or (`carried`) an earlier step's, unmeasured.
    fn new(carried: bool) -> Self {
        Self {
            at: carried.then_some(Chain::UNMEASURED),
            chain: carried.then(Chain::default),
            pending: 0.0,
            last_was_chord: false,
        }
    }

    /// The factors are an earlier step's.
    fn carried(&self) -> bool {
        self.chain.is_some()
    }

    /// The solve may end on these factors: its own, or carried ones checked on a chord
    /// step.
    fn checked(&self) -> bool {
        self.chain.is_none_or(|chain| chain.measured())
    }

    /// The step's own Newton matrix was factored at an iterate of relative residual
    /// `relative`.
    fn formed_at(&mut self, relative: f64) {
        self.chain = None;
        self.at = Some(relative);
    }

    /// Gives carried factors up: the step forms its own Newton matrix next, with no
    /// chord step pending; `missed` (they contracted too little, or gave no finite step)
    /// tells the reuse policy, which waits before the next try.
    fn give_up(&mut self, carry: &mut carry::Carry, missed: bool) {
        *self = Self::new(false);
        if missed {
            carry.missed();
        }
    }
}
