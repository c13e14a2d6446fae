//! The integrator's state by concern, beside the state of the motion itself: the clock
//! that counts steps, the predictor's memory of the last step, the node and step
//! controller of tolerance-driven runs, and the ledger of statistics and sums. Each is
//! reset or kept as a whole ([`super::Integrator::reset`]).

use super::advance::NODES_HOLD;
use super::Statistics;
use nalgebra::SVector;

/// A sum of many terms with Kahan's compensation: `carry` holds what the last additions
/// lost. Long runs add millions of terms (the work of the forces, the error estimates),
/// whose plain sum would lose digits to rounding.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct CompensatedSum {
    sum: f64,
    carry: f64,
}

impl CompensatedSum {
    /// Adds `term`.
    pub(crate) fn add(&mut self, term: f64) {
        let term = term - self.carry;
        let total = self.sum + term;
        self.carry = (total - self.sum) - term;
        self.sum = total;
    }

    /// The sum so far.
    pub(crate) fn value(&self) -> f64 {
        self.sum
    }
}

/// Where the steps are counted from: the time of the start (or the last reset, or the last
/// change of step) and the step index there. A state's time is formed from the step count,
/// `origin + (step_index − origin_steps) h`, never summed step by step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct Clock {
    /// Steps since the start (or the last reset).
    pub step_index: usize,
    /// The time from which steps of the present `h` are counted.
    pub origin: f64,
    /// The step index at which `origin` was last set.
    pub origin_steps: usize,
}

/// The last step, as the predictor and the dense output read it, and the predictor's
/// scratch (sized for the run's largest node count at construction: a step allocates
/// nothing).
#[derive(Debug, Clone)]
pub(crate) struct Predictor<E, const D: usize> {
    /// The velocity at the start of the last step taken; `None` before the first step
    /// (then there is no previous Galerkin curve either).
    pub previous_velocity: Option<SVector<f64, D>>,
    /// The last step's chart coordinates at its nodes.
    pub last_nodes: Vec<SVector<f64, D>>,
    /// The last step's base configuration.
    pub last_base: E,
    /// The flow predictor's configuration at the end of the step being taken, relative to
    /// its start, when the flow could be integrated: the check against aliased roots.
    pub flow_end: Option<E>,
    /// Whether the continued curve beat the flow in the chart at its last try.
    pub continued_wins: bool,
    /// Scratch for the predictor's comparison.
    pub extrapolated: Vec<SVector<f64, D>>,
    /// Scratch for moving the last curve to other nodes.
    pub resampled: Vec<SVector<f64, D>>,
    /// Scratch for the basis values of that move.
    pub basis_values: Vec<f64>,
}

/// The node and step controller of tolerance-driven runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Controller {
    /// The nodes the next step starts with, when they change.
    pub next_nodes: Option<usize>,
    /// Steps left before the nodes may fall again after a step needed more.
    pub hold_nodes: usize,
    /// The present length of that wait.
    pub hold_length: usize,
    /// Whether the step being taken lowered the nodes.
    pub lowered: bool,
    /// The last step's estimate, for the trend.
    pub previous_estimate: f64,
    /// The step the run started with (the largest it returns to).
    pub largest_step: f64,
    /// The step the next step takes, when it changes.
    pub next_step: Option<f64>,
}

impl Controller {
    /// A run that starts with step `h`.
    pub(crate) fn new(h: f64) -> Self {
        Self {
            next_nodes: None,
            hold_nodes: 0,
            hold_length: NODES_HOLD,
            lowered: false,
            previous_estimate: 0.0,
            largest_step: h,
            next_step: None,
        }
    }
}

/// What a run has spent and estimated: Newton's statistics, the steps per node count, the
/// work of the forces and the error estimates (the last step's and their compensated sum).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Ledger {
    /// Newton statistics since construction.
    pub statistics: Statistics,
    /// Steps taken with `n` nodes, at index `n` (length `MAX_NODES + 1`).
    pub nodes_used: Vec<usize>,
    /// The work of the forces since the start (or the last reset).
    pub work: CompensatedSum,
    /// The last step's estimated local error.
    pub estimate: f64,
    /// The sum of the local estimates since the start (or the last reset).
    pub estimates: CompensatedSum,
}

impl Ledger {
    /// An empty ledger for node counts up to `max_nodes`.
    pub(crate) fn new(max_nodes: usize) -> Self {
        Self {
            statistics: Statistics::default(),
            nodes_used: vec![0; max_nodes + 1],
            work: CompensatedSum::default(),
            estimate: 0.0,
            estimates: CompensatedSum::default(),
        }
    }

    /// Forgets the sums of a run that restarts (the statistics and node counts are kept).
    pub(crate) fn restart(&mut self) {
        self.work = CompensatedSum::default();
        self.estimate = 0.0;
        self.estimates = CompensatedSum::default();
    }
}
