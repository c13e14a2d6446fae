//! Step parameters.

use crate::error::MechanicsError;
use lgsvi_lie::ChartKind;

/// How the incoming momentum is matched (the last three equations of a step).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Matching {
    /// The exact derivative of the discrete Lagrangian, including how the curve's base
    /// point moves (see `docs/paper-notes.md` §3): discrete Noether holds to rounding.
    #[default]
    Exact,
    /// The paper's recipe `μ_k = −A(0)⁻ᵀ ∂S/∂ξ¹`: not the derivative of the discrete
    /// Lagrangian, so momenta and energy drift. For reproducing the paper.
    Paper,
}

/// How the Newton matrix is formed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum NewtonJacobian {
    /// Exact second derivatives by automatic differentiation (the default).
    #[default]
    Exact,
    /// Forward differences of the residual, as in the paper's MATLAB solver; for
    /// comparison only (slower and less accurate).
    FiniteDifference,
}

/// Parameters of one step of the integrator.
///
/// ```
/// use lgsvi_mechanics::{Matching, StepSettings};
/// use lgsvi_lie::ChartKind;
/// let settings = StepSettings::new(0.5, 10)?
///     .with_chart(ChartKind::CayleyUnscaled)
///     .with_matching(Matching::Paper);
/// assert_eq!(settings.quadrature_points(), 10); // default: m = n
/// assert!(StepSettings::new(0.5, 1).is_err());
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepSettings {
    step: f64,
    nodes: usize,
    quadrature_points: Option<usize>,
    chart: ChartKind,
    matching: Matching,
    jacobian: NewtonJacobian,
    max_newton_iterations: usize,
    reuse_factors: bool,
    tolerance: Option<f64>,
    node_range: (usize, usize),
    step_changes: bool,
    falling_nodes: bool,
}

/// Nodes chosen per step from the step's own error estimate (see
/// [`StepSettings::with_tolerance`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptiveNodes {
    /// The error allowed per unit time: a step of length `h` keeps its estimated local
    /// error at or below `rate · h`.
    pub rate: f64,
    /// The fewest nodes a step may take.
    pub min_nodes: usize,
    /// The most nodes a step may take.
    pub max_nodes: usize,
    /// Whether the step `h` may change too ([`StepSettings::with_step_changes`]).
    pub step_changes: bool,
    /// Whether the nodes may fall as well as rise ([`StepSettings::with_falling_nodes`]).
    pub falling_nodes: bool,
}

/// The nodes of a fixed run built without a node count ([`crate::IntegratorBuilder`]): ten,
/// as the command line takes.
pub const DEFAULT_NODES: usize = 10;

/// The default node range of adaptive runs: below 5 nodes the estimate has no decay to read
/// (it needs the last four Chebyshev coefficients); 30 nodes reach the rounding floor at
/// steps up to `h|Ω| ≈ 4` on the reference cases (`lgsvi converge` shows it).
pub const DEFAULT_ADAPTIVE_NODES: (usize, usize) = (5, 30);

/// Extra Gauss points beyond the number of nodes in the default `m = n + 0`: `n` Gauss
/// points integrate polynomials of degree `2n − 1` exactly, which covers the product of
/// two basis polynomials (degree `2n − 2`), the exactness the paper's minimiser theorem
/// asks of the quadrature. Against `m = n + 2` (`lgsvi bench` sweeps, T = 10, exp chart),
/// on the paper's rigid body (h = 0.5 … 2, n = 4 … 20) and heavy top the errors agree to
/// within a factor 1.5 down to the rounding floor, at less time per step; `m = n − 1` is
/// as accurate on the free body but up to 3× less on the heavy top. With the unscaled
/// Cayley chart `m = n` is slightly less accurate than `n + 1 … n + 4` on the paper's
/// rigid body (h = 0.5), about what its smaller cost buys.
pub const DEFAULT_EXTRA_QUADRATURE_POINTS: usize = 0;

/// Default cap on Newton iterations per step (converged steps take 3 to 8).
pub const DEFAULT_MAX_NEWTON_ITERATIONS: usize = 40;

/// The least error a step's estimate reports, `4ε`: the rounding of one step. A step
/// composes `R_{k+1} = R_k Φ(ξⁿ)` and solves its equations to their rounding floor, which
/// moves the attitude by 2–2.5ε in its largest entry and up to three times that in the
/// Frobenius norm (single steps of the free body at `n ≥ 6`, against the exact
/// solution). The spectral estimate alone falls far below it (1e-18 … 1e-27 at many
/// nodes), and a global estimate summed from it would claim accuracies double precision
/// cannot deliver; with the floor, `n` steps estimate at least `4nε`, the linear
/// accumulation of a fixed-sign rounding (a conservative bound where it is random).
pub const ROUNDING_FLOOR: f64 = 4.0 * f64::EPSILON;

/// The most Chebyshev–Lobatto nodes a step may have. A step's Newton system has
/// `3(n − 1)` unknowns and its tables `O(n²)` entries; spectral convergence reaches the
/// rounding floor by `n ≈ 20` on every reference case, so 100 leaves ample room while
/// keeping a mistyped count from allocating without bound.
pub const MAX_NODES: usize = 100;

/// The most Gauss points a step may have (the quadrature rules are accurate to a few
/// ulps up to 1000 points and beyond; a step needs about `n`).
pub const MAX_QUADRATURE_POINTS: usize = 1000;

/// The range of steps `h`: wide enough for any unit system (femtoseconds in SI for a
/// molecule, years for an orbit), narrow enough that the node times, their differences
/// and the predictor's continuation to `2h` are normal floating-point numbers.
pub const STEP_RANGE: (f64, f64) = (1e-280, 1e280);

impl StepSettings {
    /// Step `h` in [`STEP_RANGE`] and `2 ≤ n ≤` [`MAX_NODES`] Chebyshev–Lobatto nodes
    /// (degree `n − 1`); defaults: `m = n` Gauss points, the exp chart, exact matching,
    /// exact Jacobian.
    ///
    /// ```
    /// use lgsvi_mechanics::StepSettings;
    /// assert!(StepSettings::new(0.5, 10).is_ok());
    /// assert!(StepSettings::new(0.5, 1).is_err());
    /// assert!(StepSettings::new(0.5, 5000).is_err());
    /// assert!(StepSettings::new(1e308, 10).is_err());
    /// ```
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for `h` outside [`STEP_RANGE`] (or not finite)
    /// and `n` outside `2..=MAX_NODES`.
    pub fn new(step: f64, nodes: usize) -> Result<Self, MechanicsError> {
        if !(step.is_finite() && step > 0.0) {
            return Err(MechanicsError::InvalidSetting {
                name: "h",
                value: format!("{step:?}"),
                reason: "the step must be positive and finite",
            });
        }
        if !(STEP_RANGE.0..=STEP_RANGE.1).contains(&step) {
            return Err(MechanicsError::InvalidSetting {
                name: "h",
                value: format!("{step:?}"),
                reason:
                    "the step must lie between 1e-280 and 1e280 (choose units in which it does)",
            });
        }
        if nodes < 2 {
            return Err(MechanicsError::InvalidSetting {
                name: "nodes",
                value: nodes.to_string(),
                reason: "at least 2 Chebyshev-Lobatto nodes (polynomial degree 1) are needed",
            });
        }
        if nodes > MAX_NODES {
            return Err(MechanicsError::InvalidSetting {
                name: "nodes",
                value: nodes.to_string(),
                reason: "at most 100 nodes (spectral convergence reaches rounding by about 20)",
            });
        }
        Ok(Self {
            step,
            nodes,
            quadrature_points: None,
            chart: ChartKind::Exp,
            matching: Matching::Exact,
            jacobian: NewtonJacobian::Exact,
            max_newton_iterations: DEFAULT_MAX_NEWTON_ITERATIONS,
            reuse_factors: true,
            tolerance: None,
            node_range: DEFAULT_ADAPTIVE_NODES,
            step_changes: false,
            falling_nodes: false,
        })
    }

    /// Chooses the nodes per step: each step is solved with the current `n`, its local
    /// error is estimated from the decay of its curve's Chebyshev coefficients
    /// ([`Integrator::error_estimate`](crate::Integrator::error_estimate)), and a step
    /// whose estimate exceeds `rate · h` is solved again with more nodes (up to the range's
    /// top, [`DEFAULT_ADAPTIVE_NODES`] unless [`StepSettings::with_node_range`] says
    /// otherwise); where the estimates grow, the next step takes a node more at once. The
    /// nodes only rise ([`StepSettings::with_falling_nodes`] lets them fall), so after the
    /// run's hardest part the map is one fixed symplectic map again and the energy error
    /// stays bounded; the step `h` stays fixed; momenta are conserved exactly at every
    /// step whatever its nodes. `rate` is an error per unit time: over a horizon `T`,
    /// the local errors add up to about `rate · T` where they accumulate linearly. The
    /// nodes given to [`StepSettings::new`] are the first step's; the Gauss points follow
    /// the nodes (`m = n`).
    ///
    /// ```
    /// use lgsvi_mechanics::StepSettings;
    /// let settings = StepSettings::new(0.5, 8)?.with_tolerance(1e-12)?;
    /// assert_eq!(settings.adaptive().unwrap().rate, 1e-12);
    /// assert!(StepSettings::new(0.5, 8)?.with_tolerance(0.0).is_err());
    /// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
    /// ```
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] unless `rate` is positive and finite, and for a
    /// rate whose share of one step, `rate · h`, is below [`ROUNDING_FLOOR`].
    pub fn with_tolerance(mut self, rate: f64) -> Result<Self, MechanicsError> {
        if !(rate.is_finite() && rate > 0.0) {
            return Err(MechanicsError::InvalidSetting {
                name: "tol",
                value: format!("{rate:?}"),
                reason: "the tolerance must be positive and finite",
            });
        }
        if rate * self.step < ROUNDING_FLOOR {
            return Err(MechanicsError::InvalidSetting {
                name: "tol",
                value: format!(
                    "{rate:e} per unit time (at least {:e} at h = {})",
                    ROUNDING_FLOOR / self.step,
                    self.step
                ),
                reason: "below what double precision can deliver: a step's error does not \
                         fall below the rounding of one step, 4ε ≈ 8.9e-16",
            });
        }
        self.tolerance = Some(rate);
        let (min_nodes, max_nodes) = self.node_range;
        self.nodes = self.nodes.clamp(min_nodes, max_nodes);
        self.quadrature_points = None;
        Ok(self)
    }

    /// The range of nodes an adaptive run may use (after
    /// [`StepSettings::with_tolerance`]; before it, the range is kept for it).
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] unless `5 ≤ min ≤ max ≤` [`MAX_NODES`] (the
    /// estimate reads the last four Chebyshev coefficients of a step's curve).
    pub fn with_node_range(mut self, min: usize, max: usize) -> Result<Self, MechanicsError> {
        if !(5 <= min && min <= max && max <= MAX_NODES) {
            return Err(MechanicsError::InvalidSetting {
                name: "node range",
                value: format!("{min}..{max}"),
                reason: "need 5 <= min <= max <= 100 nodes",
            });
        }
        self.node_range = (min, max);
        if self.tolerance.is_some() {
            self.nodes = self.nodes.clamp(min, max);
        }
        Ok(self)
    }

    /// Sets the number of Gauss points, `m ≥ n − 1` for the `n` nodes set so far: the
    /// velocity is a polynomial of degree `n − 2`, and with fewer points a nonzero one
    /// vanishes at all of them, so the quadrature gives it no action and the step's
    /// equations are singular (Newton wanders off: at `n = 10`, `m ≤ 5` fails).
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for `m < n − 1` (or `m = 0`) or
    /// `m >` [`MAX_QUADRATURE_POINTS`].
    pub fn with_quadrature_points(mut self, m: usize) -> Result<Self, MechanicsError> {
        if m == 0 || m.saturating_add(1) < self.nodes {
            return Err(MechanicsError::InvalidSetting {
                name: "quad",
                value: format!("{m} (with {} nodes)", self.nodes),
                reason: "at least one Gauss point fewer than the nodes: with fewer, a nonzero \
                         velocity polynomial vanishes at every Gauss point, has no action, and \
                         the step's equations are singular",
            });
        }
        if m > MAX_QUADRATURE_POINTS {
            return Err(MechanicsError::InvalidSetting {
                name: "quad",
                value: m.to_string(),
                reason: "at most 1000 Gauss points (a step needs about as many as it has nodes)",
            });
        }
        self.quadrature_points = Some(m);
        Ok(self)
    }

    /// Sets the chart.
    pub fn with_chart(mut self, chart: ChartKind) -> Self {
        self.chart = chart;
        self
    }

    /// Sets the momentum matching.
    pub fn with_matching(mut self, matching: Matching) -> Self {
        self.matching = matching;
        self
    }

    /// Sets how the Newton matrix is formed.
    pub fn with_jacobian(mut self, jacobian: NewtonJacobian) -> Self {
        self.jacobian = jacobian;
        self
    }

    /// Sets the cap on Newton iterations per step (at least 1).
    pub fn with_max_newton_iterations(mut self, iterations: usize) -> Self {
        self.max_newton_iterations = iterations.max(1);
        self
    }

    /// Whether a step may start from the Newton matrix an earlier step factored (the
    /// default, `true`): a simplified Newton across steps. Where the matrix changes
    /// little from one step to the next (short steps: a control loop's `h|Ω| ≲ 0.15`),
    /// chord steps with it replace the step's own Newton matrix and its LU. They are tried
    /// only when the step's guess lies close to the unknowns the matrix was formed at;
    /// each must contract the residual at least 200-fold or the step forms its own matrix,
    /// and after misses in a row the reuse waits a growing number of steps. Longer steps
    /// never try it. The step is solved to the same rounding floor either way; what
    /// changes is the path to it, so a run differs from one with `false` at the level of
    /// rounding. `false` solves every step from its own Newton matrix, making each step a
    /// function of its start state alone.
    pub fn with_factor_reuse(mut self, reuse: bool) -> Self {
        self.reuse_factors = reuse;
        self
    }

    /// The step `h`.
    pub fn h(&self) -> f64 {
        self.step
    }

    /// The number of nodes `n`.
    pub fn nodes(&self) -> usize {
        self.nodes
    }

    /// The polynomial degree `n − 1`.
    pub fn degree(&self) -> usize {
        self.nodes - 1
    }

    /// The number of Gauss points `m` (default `n`).
    pub fn quadrature_points(&self) -> usize {
        self.quadrature_points
            .unwrap_or(self.nodes + DEFAULT_EXTRA_QUADRATURE_POINTS)
    }

    /// The Gauss points set by [`StepSettings::with_quadrature_points`], if any.
    pub(crate) fn explicit_quadrature_points(&self) -> Option<usize> {
        self.quadrature_points
    }

    /// The chart.
    pub fn chart(&self) -> ChartKind {
        self.chart
    }

    /// The momentum matching.
    pub fn matching(&self) -> Matching {
        self.matching
    }

    /// The Newton matrix.
    pub fn jacobian(&self) -> NewtonJacobian {
        self.jacobian
    }

    /// The cap on Newton iterations.
    pub fn max_newton_iterations(&self) -> usize {
        self.max_newton_iterations
    }

    /// Whether a step may start from an earlier step's factored Newton matrix
    /// ([`StepSettings::with_factor_reuse`]).
    pub fn reuses_factors(&self) -> bool {
        self.reuse_factors
    }

    /// The adaptive node choice, when a tolerance is set.
    pub fn adaptive(&self) -> Option<AdaptiveNodes> {
        self.tolerance.map(|rate| AdaptiveNodes {
            rate,
            min_nodes: self.node_range.0,
            max_nodes: self.node_range.1,
            step_changes: self.step_changes,
            falling_nodes: self.falling_nodes,
        })
    }

    /// Lets an adaptive run lower its nodes again where its estimates allow (by default
    /// they only rise). Cheaper where a run's hard part passes (a slew that settles), but
    /// it costs the long-run energy behaviour: each node count is its own symplectic map
    /// with its own modified energy, and moving between two of them with the state pumps
    /// the energy. On the heavy top over 10⁵ steps (`examples/step_changes.rs` runs it),
    /// nodes moving between 7 and 8 drift the energy by 1.3e-10 per 10⁵ time units, where
    /// nodes that only rise (here to 8 after the first hard phase) keep it bounded at 1e-14,
    /// as with fixed nodes. Momenta stay exact.
    pub fn with_falling_nodes(mut self, allowed: bool) -> Self {
        self.falling_nodes = allowed;
        self
    }

    /// Lets an adaptive run ([`StepSettings::with_tolerance`]) change its step as well as
    /// its nodes: a step that misses the tolerance with the most nodes allowed, or that the
    /// chart cannot follow, is solved again at half the step; where the estimate leaves
    /// room for twice the step (the local error grows by about `2^(2n−1)`), the next step
    /// doubles, up to the step the run started with. **This costs the
    /// long-run energy behaviour:** a symplectic method keeps a modified energy of its
    /// *fixed* step, and a step chosen from the state is no longer one map. On the heavy
    /// top over 10⁵ steps (`examples/step_changes.rs`) the energy drifts where fixed steps
    /// keep it bounded. Momenta stay exact (every step is still a map of the exact
    /// matching). A run with step changes has no fixed number of steps:
    /// [`Integrator::steps_until`] refuses it; step until [`Integrator::state`]'s time
    /// reaches the end, or use
    /// [`Integrator::run_until`], which shortens the last step to land on it.
    ///
    /// [`Integrator::steps_until`]: crate::Integrator::steps_until
    /// [`Integrator::state`]: crate::Integrator::state
    /// [`Integrator::run_until`]: crate::Stepper::run_until
    pub fn with_step_changes(mut self, allowed: bool) -> Self {
        self.step_changes = allowed;
        self
    }

    /// These settings with step `h` (checked by the caller: halvings and doublings of a
    /// valid step, or a shortened last step).
    pub(crate) fn with_step_unchecked(&self, h: f64) -> Self {
        Self { step: h, ..*self }
    }

    /// These settings with `n` nodes, the default `m = n` Gauss points and no tolerance
    /// (a checked run's companion).
    pub(crate) fn fixed_with_nodes(&self, n: usize) -> Self {
        Self {
            tolerance: None,
            step_changes: false,
            falling_nodes: false,
            ..self.with_nodes(n)
        }
    }

    /// These settings with `n` nodes and the default `m = n` Gauss points (the nodes an
    /// adaptive run switches to).
    pub(crate) fn with_nodes(&self, n: usize) -> Self {
        Self {
            nodes: n,
            quadrature_points: None,
            ..*self
        }
    }
}
