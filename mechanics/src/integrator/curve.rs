//! What a run returns beside the state: Newton's statistics, the last step's Galerkin
//! curve (dense output) and recorded trajectories.

use super::*;

/// Newton statistics of the run so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Statistics {
    /// Steps taken.
    pub steps: usize,
    /// Newton iterations, summed over the steps.
    pub newton_iterations: usize,
    /// The most Newton iterations one step took.
    pub max_newton_iterations: usize,
    /// Newton matrices assembled and factored, summed over the steps: the iterations
    /// beyond these were chord steps, which reuse the step's last factored matrix.
    pub factorizations: usize,
    /// Adaptive runs: solves whose error estimate was above the tolerance, redone with
    /// more nodes (their Newton iterations are counted above too).
    pub rejected_steps: usize,
}

/// A step's Galerkin curve: `g(t) = g_k Φ(ξ(t))`, `t ∈ [0, h]` from the step's start.
#[derive(Debug, Clone)]
pub struct GalerkinCurve<G: StepGroup<D> = Rotations, C = ChartKind, const D: usize = 3> {
    pub(super) base: G::Element<f64>,
    pub(super) nodes: Vec<SVector<f64, D>>,
    pub(super) basis: lgsvi_spectral::Barycentric,
    pub(super) chart: C,
    pub(super) start: f64,
    pub(super) group: PhantomData<G>,
}

impl<G: StepGroup<D>, C: GroupChart<G, D>, const D: usize> GalerkinCurve<G, C, D> {
    /// The step's start time.
    pub fn start(&self) -> f64 {
        self.start
    }

    /// The step length `h`.
    pub fn step(&self) -> f64 {
        *self.basis.nodes().last().unwrap_or(&0.0)
    }

    /// `(g(t), ξ(t))` at `t` seconds after the step's start, `0 ≤ t ≤ h` (up to a
    /// rounding slack of `1e-12 h` at either end).
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] for a `t` outside the step (the polynomial
    /// describes the motion within its step only) or not finite.
    pub fn at(&self, t: f64) -> Result<(G::Element<f64>, SVector<f64, D>), MechanicsError> {
        let h = self.step();
        let slack = 1e-12 * h;
        if !(t >= -slack && t <= h + slack) {
            return Err(MechanicsError::InvalidSetting {
                name: "t",
                value: format!("{t:?}"),
                reason: "outside the step [0, h] the Galerkin curve is an extrapolation, not the \
                         motion: take the curve of the step that contains the time",
            });
        }
        let t = t.clamp(0.0, h);
        let n = self.nodes.len();
        let mut phi = vec![0.0; n];
        let mut dphi = vec![0.0; n];
        self.basis
            .basis_and_derivatives_into(t, &mut phi, &mut dphi)?;
        let mut xi = SVector::<f64, D>::zeros();
        let mut xi_dot = SVector::<f64, D>::zeros();
        for i in 0..n {
            xi += self.nodes[i] * phi[i];
            xi_dot += self.nodes[i] * dphi[i];
        }
        let g = self.base.compose(&self.chart.to_group(&xi));
        Ok((g, self.chart.left_differential(&xi) * xi_dot))
    }

    /// The chart coordinates `ξ¹ = 0, ξ², …, ξⁿ` of the nodes.
    pub fn nodes(&self) -> &[SVector<f64, D>] {
        &self.nodes
    }
}

/// A recorded trajectory (every `every`-th step, always the first and the last).
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory<E = SO3, const D: usize = 3> {
    /// States, in time order.
    pub states: Vec<State<E, D>>,
    /// Newton iterations of the step that produced each state (0 for the initial one).
    pub newton_iterations: Vec<usize>,
}

impl<E, const D: usize> Default for Trajectory<E, D> {
    fn default() -> Self {
        Self {
            states: Vec::new(),
            newton_iterations: Vec::new(),
        }
    }
}
