//! One step: the Galerkin discrete action on a configuration group, its derivatives, and
//! the Newton solve — written once for every group `G` (algebra `ℝ^D`) and chart.
//!
//! On step `k` the curve is `g(t) = g_k Φ(ξ(t))`, `ξ(t) = Σ_i ξⁱ φ_i(t)` on `n`
//! Chebyshev–Lobatto nodes of `[0, h]`, `ξ¹ = 0`. With Gauss points `c_j h` and weights
//! `h b_j`, the action is `S = Σ_j h b_j ℓ̃(x_j, v_j)`, where `x_j = Σ_i φ_i(c_j h) ξⁱ`,
//! `v_j = Σ_i φ_i'(c_j h) ξⁱ` and `ℓ̃(x, v) = ℓ(t_k + c_j h, g_k Φ(x), A(x) v)`.
//!
//! Unknowns `ξ², …, ξⁿ` (`D(n − 1)` numbers); equations: `∂S/∂ξⁱ = 0` (plus the force
//! terms) for `i = 2..n−1` and `D` matching equations ([`matching`]),
//! - exact: `A(ξⁿ)ᵀ Ad_{Φ(ξⁿ)}ᵀ w − ∂S/∂ξⁿ = 0`, `w = μ_k + Σ_j h b_j Ad_{Φ(x_j)⁻¹}ᵀ p_j`,
//!   `p_j = ∂ℓ̃/∂ζ` the configuration force of `ℓ(g Φ(x) exp(ζ), ·)` (plus the force);
//! - paper: `A(0)ᵀ μ_k + ∂S/∂ξ¹ = 0`.
//!
//! Afterwards `g_{k+1} = g_k Φ(ξⁿ)` and `μ_{k+1} = Ad_{Φ(ξⁿ)}ᵀ w`. On SO(3),
//! `Ad_R = R`, and these are the formulas of `docs/paper-notes.md` §3.
//!
//! | file | concern |
//! |---|---|
//! | [`tables`] | quadrature, basis and continuation tables of `(h, n, m)` |
//! | [`points`] | one Gauss point's `ℓ̃` and its derivatives (closed form or dual numbers), forces |
//! | [`rotation_translation`] | the same on SE(3)'s rotation–translation chart by 3 × 3 blocks (the built-in SE(3) systems) |
//! | [`assembly`] | the residual and the exact Newton matrix from the points |
//! | [`matching`] | the momentum-matching equations, their Jacobian rows, the momentum update |
//! | [`lu`] | the Newton matrix's LU factorisation (run-time SIMD dispatch) |
//! | [`newton`] | the Newton / chord policy and its stopping rules |
//! | [`linearize`] | the exact linearisation of a converged step (implicit function theorem) |

pub(crate) mod assembly;
pub(crate) mod linearize;
pub(crate) mod lu;
pub(crate) mod matching;
pub(crate) mod newton;
pub(crate) mod points;
pub(crate) mod product;
pub(crate) mod rotation_translation;
pub(crate) mod tables;

use crate::settings::{Matching, StepSettings};
use crate::system::{ElementOf, System};
use nalgebra::{SMatrix, SVector};
use tables::Discretisation;

/// What a converged step returns.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StepOutcome<E, const D: usize> {
    /// `g_k Φ(ξⁿ)`, before renormalisation.
    pub configuration: E,
    pub momentum: SVector<f64, D>,
    pub iterations: usize,
    /// Newton matrices factored (the other iterations were chord steps).
    pub factorizations: usize,
}

/// `w` of the exact matching and `A(ξⁿ)ᵀ Ad_{Φ(ξⁿ)}ᵀ`, from the last assembly.
#[derive(Debug, Clone, Copy)]
pub(crate) struct MatchingTerms<const D: usize> {
    pub w: SVector<f64, D>,
    pub transport: SMatrix<f64, D, D>,
}

impl<const D: usize> Default for MatchingTerms<D> {
    fn default() -> Self {
        Self {
            w: SVector::zeros(),
            transport: SMatrix::zeros(),
        }
    }
}

/// The solver of one step, for a system, a chart and fixed settings.
pub(crate) struct StepSolver<'a, S, C, const D: usize> {
    pub system: &'a S,
    pub chart: &'a C,
    pub settings: &'a StepSettings,
    pub d: &'a Discretisation,
    /// The step's start time `t_k`.
    pub time: f64,
    /// The control input added to the system's force, when the step is forced (the
    /// system has a force or the input is not zero); `None` for an unforced step.
    pub forcing: Option<SVector<f64, D>>,
    /// The input at each Gauss point, in place of the constant one in `forcing` (which
    /// is then `Some`), when the integrator was given them.
    pub point_inputs: Option<&'a [SVector<f64, D>]>,
}

impl<S: System<D>, C, const D: usize> StepSolver<'_, S, C, D> {
    /// The control input at Gauss point `j`: its own where the inputs are given per
    /// point, else the constant one; `None` for an unforced step.
    pub(crate) fn input_at(&self, j: usize) -> Option<SVector<f64, D>> {
        match self.point_inputs {
            Some(points) => Some(points[j]),
            None => self.forcing,
        }
    }

    /// Whether the points need their `ζ` derivatives: the exact matching of a system
    /// that is not left-invariant or is forced.
    fn needs_configuration(&self) -> bool {
        self.settings.matching() == Matching::Exact
            && (!self.system.is_left_invariant() || self.forcing.is_some())
    }

    /// Whether the momentum update needs no assembly at the final iterate: the exact
    /// matching, whose `w` is `μ_k` without configuration terms and is carried through a
    /// last chord step with them ([`StepSolver::carry_matching`]).
    fn momentum_is_assembly_free(&self) -> bool {
        self.settings.matching() == Matching::Exact
    }
}

/// The type of a step's configuration.
pub(crate) type Element<S, const D: usize> = ElementOf<S, D>;

#[cfg(test)]
mod tests;
