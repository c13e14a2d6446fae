//! The reuse policy of the Newton loop across steps: when a step starts with chord steps
//! on the Newton matrix an earlier step factored (a simplified Newton whose matrix is
//! carried from step to step, as implicit Runge–Kutta codes keep their iteration matrix),
//! and when it gives that matrix up.
//!
//! A step's own exact Newton step from the predictor lands at ~0.1 r² (quadratic
//! convergence): at a control loop's short steps one Newton matrix, its LU and two
//! assemblies solve it. Carried factors save the matrix and the LU but contract only by
//! how far the matrix has moved since they were formed, so the step takes more assemblies
//! (four from the predictor's 1e-9 at a contraction of 4e-4). That pays while the
//! contraction stays below a few 1e-3, where the extra assemblies cost less than the
//! matrix and the LU they save. The matrix of a step is a function of its unknowns `Ξ`
//! (and, through a potential or a force, of where the step starts): how far the new step's
//! guess lies from the `Ξ` the carried matrix was formed at ([`DRIFT`]) decides whether to
//! try it, and a checked chord step that contracts less than [`CONTRACTION`] ends the try.

/// A chord step with carried factors must cut the relative residual at least this much;
/// otherwise the step forms its own Newton matrix from where the chord step left it. With
/// contraction `ρ` a solve from the predictor's ~1e-9 to the chord chain's 1e-20 takes
/// about `1 + 11/(−log₁₀ ρ)` assemblies, against two and a Newton matrix with its LU
/// for the step's own Newton step (worth about three assemblies on SO(3)).
pub(super) const CONTRACTION: f64 = 5e-3;

/// Carried factors are tried only when every entry of the step's guess `Ξ` lies within
/// this of the `Ξ` they were formed at. The matrix moves with `Ξ` through the chart's
/// `A(x)` and the Lagrangian's Hessians, about linearly: at short steps the contraction
/// is a fraction of this distance, so a guess within it passes [`CONTRACTION`]'s check.
/// The test is absolute: on SE(3) it reads the translation's entries in the user's length
/// unit, so a body whose centre moves far in those units per step tries the factors less
/// often.
/// What the distance cannot see (a new step size, a changed system) forgets the factors
/// instead (`Integrator::reset`, the step's and the nodes' changes, `system_mut`, a failed
/// solve); an input changed between steps is left to the contraction check.
pub(super) const DRIFT: f64 = 5e-3;

/// A chord step's contraction is measured from a relative residual at or above this:
/// `CONTRACTION` times it is then above the rounding floor of the residual (1e-15 to a few
/// 1e-15 of the terms), whose noise adds to the reading: a failing contraction cannot read
/// as a passing one. A
/// guess closer than this is not solved on carried factors (no measurement would check
/// them; the next step does not try them either), and a chain is accepted only after one
/// measurement.
pub(super) const MEASURABLE: f64 = 1e-11;

/// A chord step whose relative residual after it is at least this (a hundred times the
/// floor's few ulps) measures the contraction cleanly; below it the floor's noise inflates
/// the reading, which then only checks the factors (and stands for the contraction only
/// while no clean reading exists: on the safe side).
pub(super) const CLEAN: f64 = 1e-13;

/// Carried factors are tried only with at least this many Newton iterations allowed: a
/// chain takes 4 to 6, and a miss then needs room for the step's own Newton steps.
pub(super) const MIN_ITERATIONS: usize = 12;

/// The longest wait, in steps, between attempts after misses in a row (the wait doubles
/// with each from [`FIRST_WAIT`]).
const MAX_WAIT: u32 = 64;

/// The wait after a second miss in a row.
const FIRST_WAIT: u32 = 8;

/// What a workspace knows about the factors in its Newton matrix between steps.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Carry {
    /// The matrix holds the LU factors of a Newton matrix of this workspace's size.
    factored: bool,
    /// Steps to wait before the next attempt.
    wait: u32,
    /// The wait after the next miss.
    next_wait: u32,
    /// The last solve's guess was at least [`MEASURABLE`] from the solution.
    measurable: bool,
}

impl Carry {
    /// The matrix now holds fresh factors.
    pub(crate) fn factored(&mut self) {
        self.factored = true;
    }

    /// Forget the factors (a new start: `Integrator::reset`, another size).
    pub(crate) fn forget(&mut self) {
        *self = Self::default();
    }

    /// Whether this step starts from the carried factors, its guess lying `drift` (the
    /// largest entry of the difference) from the unknowns they were formed at; counts
    /// down a wait.
    pub(super) fn attempt(&mut self, drift: f64) -> bool {
        if !(self.factored && self.measurable && drift <= DRIFT) {
            return false;
        }
        if self.wait > 0 {
            self.wait -= 1;
            return false;
        }
        true
    }

    /// The relative residual of a solve's guess: the next solve tries carried factors
    /// only if this one's could have been checked on them.
    pub(super) fn guessed(&mut self, relative: f64) {
        self.measurable = relative >= MEASURABLE;
    }

    /// A chord step with the carried factors contracted too little. The step forms its
    /// own matrix, which the next step may try at once; when that misses too, wait
    /// before the next attempt, longer after every miss in a row.
    pub(super) fn missed(&mut self) {
        self.wait = self.next_wait;
        self.next_wait = (self.next_wait * 2).clamp(FIRST_WAIT, MAX_WAIT);
    }

    /// A step solved on the carried factors: attempts continue at every step.
    pub(super) fn served(&mut self) {
        self.next_wait = 0;
    }
}

/// One solve's chain of chord steps on carried factors: what its checked chord steps
/// measured. Every chord step from a relative residual of at least [`MEASURABLE`] is
/// checked ([`Chain::record`]); the contraction that stands for the factors' `r_f` in
/// the predicted remainder is the largest reading, except that a reading from a residual
/// below [`CLEAN`] (the floor's noise inflates it) stands only until a clean one exists.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Chain {
    /// The contraction standing for `r_f`.
    contraction: f64,
    /// A chord step has been checked (and passed).
    measured: bool,
    /// One of the readings was clean.
    clean: bool,
}

impl Chain {
    /// The `r_f` a chain predicts with before its first reading: the most it may be.
    pub(super) const UNMEASURED: f64 = CONTRACTION;

    /// Records a checked chord step's `contraction`, the relative residual after it
    /// being `relative`: the `r_f` to predict with, or `None` when it contracted less
    /// than [`CONTRACTION`] (the factors are too far off).
    pub(super) fn record(&mut self, contraction: f64, relative: f64) -> Option<f64> {
        if contraction > CONTRACTION {
            return None;
        }
        let clean = relative >= CLEAN;
        match (clean, self.clean) {
            // The first clean reading replaces the noisy ones.
            (true, false) => self.contraction = contraction,
            // A noisy reading after a clean one says nothing more.
            (false, true) => {}
            // Readings of one kind: the largest.
            _ => self.contraction = self.contraction.max(contraction),
        }
        self.measured = true;
        self.clean |= clean;
        Some(self.contraction)
    }

    /// Whether a chord step has been checked: only then may the chain end the solve.
    pub(super) fn measured(&self) -> bool {
        self.measured
    }
}

/// Whether the next assembly of a solve on carried factors is expected to be the last:
/// the chord step after it will be the chain's last when the error it starts from (the
/// remainder the last chord step predicted, `pending`; none left when that was below
/// [`super::chord::CHORD_REMAINDER`]) times the factors' contraction `r_f` is below
/// that remainder. A step to be linearised takes its Hessians there.
pub(super) fn expect_last(iterations: usize, pending: f64, r_f: Option<f64>) -> bool {
    iterations > 0
        && (pending == 0.0 || pending * r_f.unwrap_or(1.0) <= super::chord::CHORD_REMAINDER)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No factors or a guess too far from them, no attempt; the first miss leaves the next
    /// step free to try its own fresh factors, misses in a row wait 8, 16, … 64 steps; a
    /// step served by the carried factors resets the waits; forgetting ends the attempts.
    #[test]
    fn misses_space_the_attempts_out() {
        let mut carry = Carry::default();
        assert!(!carry.attempt(0.0));
        carry.factored();
        assert!(!carry.attempt(0.0), "no guess seen yet");
        carry.guessed(0.1 * MEASURABLE);
        assert!(
            !carry.attempt(0.0),
            "guesses too close to check the factors on"
        );
        carry.guessed(1e-9);
        assert!(!carry.attempt(2.0 * DRIFT), "a guess too far off");
        assert!(carry.attempt(0.5 * DRIFT));
        let mut waits = Vec::new();
        for _ in 0..6 {
            carry.missed();
            let mut waited = 0;
            while !carry.attempt(0.0) {
                waited += 1;
            }
            waits.push(waited);
        }
        assert_eq!(waits, [0, 8, 16, 32, 64, 64]);
        carry.served();
        carry.missed();
        assert!(
            carry.attempt(0.0),
            "a first miss: the fresh factors are tried at once"
        );
        carry.forget();
        assert!(!carry.attempt(0.0));
    }

    /// A chain's readings: a failing one ends it; the largest clean one stands for `r_f`,
    /// noisy ones only until a clean one exists; measured after the first passing one.
    #[test]
    fn the_chain_predicts_with_its_largest_clean_contraction() {
        let mut chain = Chain::default();
        assert!(!chain.measured());
        assert_eq!(
            chain.record(2e-3, 1e-14),
            Some(2e-3),
            "a noisy reading stands"
        );
        assert!(chain.measured());
        assert_eq!(
            chain.record(3e-3, 1e-14),
            Some(3e-3),
            "the largest noisy one"
        );
        assert_eq!(
            chain.record(1e-4, 1e-9),
            Some(1e-4),
            "a clean one replaces them"
        );
        assert_eq!(
            chain.record(4e-3, 1e-14),
            Some(1e-4),
            "noise after a clean one"
        );
        assert_eq!(
            chain.record(5e-4, 1e-10),
            Some(5e-4),
            "the largest clean one"
        );
        assert_eq!(chain.record(2.0 * CONTRACTION, 1e-9), None, "too little");
    }

    /// The chain's last assembly: none left to predict, or a prediction whose next
    /// remainder is below the chord chain's end.
    #[test]
    fn the_last_assembly_is_where_the_remainder_ends() {
        assert!(!expect_last(0, 0.0, Some(1e-3)));
        assert!(expect_last(2, 0.0, Some(1e-3)));
        assert!(expect_last(2, 1e-18, Some(1e-3)));
        assert!(!expect_last(2, 1e-16, Some(1e-3)));
        assert!(
            !expect_last(2, 1e-19, None),
            "no contraction known: the remainder alone"
        );
        assert!(expect_last(2, 1e-21, None));
    }
}
