//! Optimal control on the group with lgsvi's variational step as the constraint: slews of
//! a rigid body from a start `(R₀, Ω₀)` to a target `(R_f, Ω_f)`, the torques bounded per
//! axis, at the least input energy in a fixed time or in the least time; likewise a heavy
//! top's ([`Slew::gravity`]) and a spacecraft's by its three reaction wheels, the motor
//! torques bounded per wheel ([`Slew::wheels`]), each also under a known constant
//! disturbance torque ([`Slew::disturbance`]); and manoeuvres of a body in space (SE(3),
//! a body wrench bounded per axis, a known disturbance wrench beside it where given) at
//! the least input energy or in the least time ([`Manoeuvre`]).
//!
//! # The problem
//!
//! `K` steps of a common length `h`, each one of lgsvi's steps (`n` nodes, exp chart,
//! exact matching), the body torque `u_k` held over step `k` (the integrator's input):
//!
//! ```text
//! minimise   Σ_k h |u_k|²  (= ∫ |u|² dt, no ½; h = T/K fixed)   [Cost::Energy]
//!       or   T = K h       (h free)                             [Cost::Time]
//! subject to x_{k+1} = step_h(x_k, u_k),  x_0 = (R₀, Ω₀),  x_K = (R_f, Ω_f),
//!            |u_k,i| ≤ u_max,i
//! ```
//!
//! The states are the step's own, so the solution replays exactly: an
//! [`Integrator`](lgsvi_mechanics::Integrator)
//! driven with the optimal torques at the solution's `h` lands on the target (to the
//! solver's tolerance).
//!
//! # The solvers
//!
//! Both are sequential quadratic programming over the torques (single shooting: each
//! iterate's states come from a run of the integrator, so every iterate is a motion),
//! with the QP subproblems solved by `clarabel`. Each iteration linearises every step
//! exactly ([`Integrator::step_linearized`](lgsvi_mechanics::Integrator::step_linearized): `A_k = ∂x_{k+1}/∂x_k`,
//! `B_k = ∂x_{k+1}/∂u_k` in the body-frame coordinates `(θ, ω)` of
//! `docs/notes/linearization.md`) and chains them into the terminal state's sensitivity
//! `M = ∂x_K/∂u`; the subproblem is
//!
//! ```text
//! minimise  ½ δᵀ W δ + ∇Jᵀ δ  subject to  M δ = e,  bounds
//! ```
//!
//! with `e = (log(R_Kᵀ R_f), Ω_f − Ω_K)` the terminal state's miss. An iteration ends
//! when the scaled KKT residual (stationarity over `1 + |∇J|`, and the terminal miss) is at
//! most the tolerance.
//!
//! - **Minimum energy.** `W` is the cost's Hessian `2h I`, exact; the constraint's
//!   curvature (the step's second derivatives, which lgsvi does not form) is left out: a
//!   Gauss–Newton SQP, converging linearly at a rate set by the multipliers times that
//!   curvature, quadratically for a motion that is linear in the torques. A step that
//!   does not lower the merit `J + ρ |e|₁` is halved.
//! - **Manoeuvres in space** ([`Manoeuvre`]): the same SQP with the body force measured in
//!   the world frame (the step's `δf` as `δf − f̂ δθ`, `δθ` the attitude's change at the
//!   force's Gauss point), which takes the translation's curvature out of the model, so
//!   that the iteration converges as fast as a slew's however large the translation's
//!   share of the cost, the force bounded or not (the subproblem's banded form, below,
//!   keeps the measured steps' relation to the inputs as a block over each step, so a
//!   bound stays a bound).
//! - **Tracking and terminal costs** ([`Slew::track`], [`Slew::terminal_cost`]): the
//!   same Gauss–Newton SQP on the least squares, the residuals' Jacobians exact (in the
//!   states they read, the group log's through `J_r(e)⁻¹`), the Hessian
//!   `diag(2w) + 2 GᵀG`. The subproblem keeps the states among its variables: the steps'
//!   linearisations `δx_{k+1} = A_k δx_k + B_k δu_k` as banded equality rows, the Hessian
//!   block diagonal (`2w` on the torques, each state's `2 G_kᵀG_k` on its own), so that
//!   `clarabel`'s sparse factorisation costs a fixed amount a step; eliminating the
//!   states gives the condensed subproblem above, whose `2GᵀG` is dense (its cost the
//!   cube of the step count). The gradient `2Gᵀr` comes from the adjoint recursion.
//! - **Minimum time.** The cost is linear, so the constraint's curvature is all there is:
//!   `W` is the Lagrangian's Hessian `Σ λ_i ∂²e_i/∂z²`, by forward differences of its exact
//!   gradient `Mᵀλ` in each torque off its bounds and in `h` (one run of the integrator
//!   each), made positive definite on the constraints' null space. The optimum is
//!   bang-bang: all torques but a few on their bounds, so few are free and the Hessian is
//!   cheap, and Newton's convergence is quadratic (to the differences' 1e-8). The
//!   derivative in the step length, `∂x_{k+1}/∂h`, comes from the same `A_k`, `B_k` by
//!   the time scaling of the kinetic energy (`h ∂x₊/∂h = A_ω Ω + 2 B u − (0, Ω₊)`, plus
//!   `2m ∂x₊/∂m` for a heavy top's potential; derived in `docs/guide/optimal.md`). The subproblem's solution is made exact on its active set (the
//!   interior-point method meets it only to its tolerance), a step the merit refuses gets
//!   a second-order correction, then the subproblem with the Hessian's negative
//!   eigenvalues mirrored, before it is halved, and the solve climbs a ladder of step
//!   counts (`K` halved down to about 20 steps, each level started from the one below),
//!   from the minimum-energy slew rescaled in time until its largest torque meets its
//!   bound (rest to rest, without gravity or a disturbance) or at the shortest time that
//!   slew is found for (otherwise),
//!   perturbed off symmetric motions.
//!
//! A minimum-time slew whose optimum has a singular arc (a torque strictly inside its
//! bounds over a stretch of steps, as for a 90° turn of `diag(3, 4, 5)` about
//! `(1, 1, 0)/√2`) has a nearly singular reduced Hessian: at some step counts its
//! iteration settles the final time but stalls at a scaled KKT residual near 1e-6,
//! reported as [`OptimalError::NotConverged`]; a looser tolerance accepts it, another
//! step count may converge.
//!
//! The torque is constant over each step by default: the optimal cost of the discrete
//! problem then converges to the continuous one at second order in `h`, whatever the
//! integrator's order. With [`Inputs::Polynomial`] it is a polynomial within each step,
//! given by its values at the step's Gauss points
//! ([`lgsvi_mechanics::Integrator::set_input_at_points`], whose per-point input Jacobians
//! the SQP chains), and the minimum-energy cost converges at the integrator's order
//! `2(n − 1)`: 8 nodes and 10 steps meet an independent Pontryagin solution to 7e-14
//! (measured in `optimal/tests/slews.rs` and `docs/guide/optimal.md`).
//!
//! ```
//! use lgsvi_mechanics::lie::{LieGroup, SO3};
//! use lgsvi_mechanics::Inertia;
//! use lgsvi_optimal::{Cost, Slew};
//! use nalgebra::Vector3;
//!
//! // A 66° rest-to-rest slew about an oblique axis in 20 s, at most 0.05 N·m per axis.
//! let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.0])?;
//! let target = SO3::exp(&Vector3::new(0.5, 0.3, 1.0));
//! let solution = Slew::new(inertia, 20.0)
//!     .to(target, Vector3::zeros())
//!     .steps(40)
//!     .torque_max([0.05; 3])
//!     .solve()?;
//! assert!(solution.converged);
//! assert!(solution.inputs.iter().all(|u| u.amax() <= 0.05 + 1e-9));
//!
//! // The same turn in the least time the bounds allow (the time given is a first guess).
//! let fastest = Slew::new(inertia, 20.0)
//!     .to(target, Vector3::zeros())
//!     .steps(40)
//!     .torque_max([0.05; 3])
//!     .cost(Cost::Time)
//!     .solve()?;
//! assert!(fastest.t_end < 20.0 && fastest.cost == fastest.t_end);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

mod checks;
mod energy;
mod motion;
mod qp;
mod shooting;
mod time;
mod tracking;

use lgsvi_mechanics::built_in::BuiltInSo3;
use lgsvi_mechanics::gyrostat::Gyrostat;
use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::{HeavyTop, Inertia, MechanicsError, RigidBody, State, StepSettings};
use nalgebra::Vector3;
use shooting::Plant;

pub use motion::{separate_bang_bang_time, Manoeuvre, ManoeuvreSolution};

/// Why a slew was not solved.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OptimalError {
    /// A setting out of range.
    #[error("invalid {name} = {value}: {reason}")]
    InvalidSetting {
        /// The setting.
        name: &'static str,
        /// Its value, as given.
        value: String,
        /// Why, and what to give.
        reason: String,
    },
    /// No inputs (within the bounds, where there are any) reach the target in the time.
    #[error(
        "infeasible: {} (the closest iterate misses it by {residual:.3e}): {}",
        if *bounded { "no inputs within the bounds reach the target in the time" }
        else { "the QP finds no inputs that reach the target" },
        if *bounded { "raise the torque (or force) bound or the final time (for a minimum-time \
                      slew, its first guess), or give more steps" }
        else { "the problem's numbers are too far apart for the QP (give the time, inertia \
               and inputs units that make them comparable) or too few steps" }
    )]
    Infeasible {
        /// The terminal miss of the last iterate.
        residual: f64,
        /// Whether the torques were bounded (the bounds are then the likely cause).
        bounded: bool,
    },
    /// The iteration did not reach the tolerance.
    #[error(
        "not converged after {iterations} iterations: scaled KKT residual {residual:.3e} \
         against {tolerance:e}; allow more iterations, loosen the tolerance, or give more \
         steps or time"
    )]
    NotConverged {
        /// Iterations taken.
        iterations: usize,
        /// The scaled KKT residual reached.
        residual: f64,
        /// The tolerance asked for.
        tolerance: f64,
    },
    /// A step of the integrator failed.
    #[error("a step failed: {0}")]
    Mechanics(#[from] MechanicsError),
    /// The QP subproblem solver failed.
    #[error(
        "the QP subproblem: {0}; the problem's numbers may be too far apart for it: give the \
         time, inertia and torques units that make them comparable"
    )]
    Subproblem(String),
}

/// The time of a rest-to-rest bang-bang turn by `rotation` (body frame: the start's
/// inverse times the target) about its fixed axis, with the largest torque along that
/// axis the bounds allow and the gyroscopic torque ignored: a first guess for
/// [`Cost::Time`] (what `lgsvi optimize --cost time` uses without `--t-end`). `None` for no
/// rotation or a bound that is not positive.
///
/// ```
/// # use lgsvi_mechanics::{Inertia, lie::{LieGroup, SO3}};
/// # use nalgebra::Vector3;
/// // About a principal axis: 2 √(θ J₁ / u_max).
/// let inertia = Inertia::from_principal_moments([5621.0, 4547.0, 2364.0])?;
/// let turn = SO3::exp(&(Vector3::x() * 150f64.to_radians()));
/// let t = lgsvi_optimal::eigen_axis_time(&inertia, &turn, [50.0; 3]).unwrap();
/// assert!((t - 2.0 * (150f64.to_radians() * 5621.0 / 50.0).sqrt()).abs() < 1e-12 * t);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn eigen_axis_time(inertia: &Inertia, rotation: &SO3, torque_max: [f64; 3]) -> Option<f64> {
    let rotation = rotation.log();
    let angle = rotation.norm();
    if !(angle > 0.0 && angle.is_finite()) || torque_max.iter().any(|u| u.is_nan() || *u <= 0.0) {
        return None;
    }
    let axis = rotation / angle;
    // The largest s with |s a_i| ≤ u_max,i; the inertia about the axis aᵀJa.
    let torque = (0..3)
        .filter(|&i| axis[i] != 0.0)
        .map(|i| torque_max[i] / axis[i].abs())
        .fold(f64::INFINITY, f64::min);
    let moment = axis.dot(&(inertia.matrix() * axis));
    let time = 2.0 * (angle * moment / torque).sqrt();
    time.is_finite().then_some(time)
}

/// A slew of a rigid body, a heavy top ([`Slew::gravity`]) or a spacecraft by its reaction
/// wheels ([`Slew::wheels`]) (crate documentation): built, then
/// [`Slew::solve`]d.
#[derive(Debug, Clone)]
pub struct Slew {
    inertia: Inertia,
    gravity: Option<Gravity>,
    wheels: Option<Wheels>,
    t_end: f64,
    start: (SO3, Vector3<f64>),
    target: (SO3, Vector3<f64>),
    steps: usize,
    nodes: usize,
    torque_max: Option<Vector3<f64>>,
    disturbance: Option<Vector3<f64>>,
    cost: Cost,
    inputs: Inputs,
    tracking: Option<(Vec<Target>, [f64; 2])>,
    terminal_cost: Option<[f64; 2]>,
    tolerance: f64,
    max_iterations: usize,
    initial: Option<Vec<Vector3<f64>>>,
}

/// Gravity on the body: it is then a heavy top, `ℓ = ½ΩᵀJΩ + m g dᵀRρ`
/// ([`lgsvi_mechanics::HeavyTop`]), whose gravity torque `m g ρ × Rᵀd` the slew's torques
/// work with or against ([`Slew::gravity`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gravity {
    /// The mass `m ≥ 0` (kg).
    pub mass: f64,
    /// The gravitational acceleration `g ≥ 0`.
    pub gravity: f64,
    /// The centre of mass `ρ` from the fixed point, body frame.
    pub center_of_mass: Vector3<f64>,
    /// The direction gravity pulls in, `d`, world frame (normalised).
    pub direction: Vector3<f64>,
}

/// Three reaction wheels on the body: the slew's inputs are then the wheels' motor torques
/// (`τ_i` between the body and wheel `i`), not a body torque, and the body is a gyrostat
/// ([`lgsvi_mechanics::gyrostat::Gyrostat`]): `ℓ = ½ΩᵀJΩ + Σ I_i (a_iᵀΩ) φ̇_i + ½ Σ I_i φ̇_i²`
/// with `J` the inertia given to [`Slew::new`], that of the whole spacecraft with its wheels
/// locked ([`Slew::wheels`]). The motors move momentum between the body and the wheels:
/// the total angular momentum is conserved, but for a disturbance's impulse
/// ([`Slew::disturbance`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wheels {
    /// The wheels' spin axes (body frame; any length: the solver normalises them). They
    /// span the three body axes.
    pub axes: [Vector3<f64>; 3],
    /// Their axial inertias `I_i > 0` (kg·m²), part of `J`.
    pub inertia: [f64; 3],
    /// Their rates `φ̇_i` relative to the body at the start (rad/s); the final rates are
    /// free.
    pub speeds: Vector3<f64>,
}

/// How the torque varies within a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Inputs {
    /// Constant over each step (zero-order hold): three values a step. The optimal cost
    /// then converges at second order in `h`, whatever the integrator's order.
    #[default]
    Constant,
    /// A polynomial within each step, given by its values at the step's Gauss points
    /// ([`lgsvi_mechanics::Integrator::set_input_at_points`]; three values a point): the
    /// cost `∫|u|² dt` is the step's quadrature of them, exact for that polynomial, and
    /// the optimal cost converges at the integrator's order. The bounds hold at the
    /// points. For [`Cost::Energy`] (the minimum time's optimum is bang-bang).
    Polynomial,
}

/// A state to reach or follow: attitude (body to world) and body rates.
pub type Target = (SO3, Vector3<f64>);

/// What a slew minimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Cost {
    /// `∫ |u|² dt` (no ½) at the fixed final time.
    #[default]
    Energy,
    /// The final time, the torques bounded ([`Slew::torque_max`]).
    Time,
}

/// The solver's record of a solve.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Statistics {
    /// SQP iterations.
    pub iterations: usize,
    /// The scaled KKT residual at each iterate.
    pub kkt_residuals: Vec<f64>,
    /// The terminal miss at each iterate.
    pub terminal_misses: Vec<f64>,
    /// Wall time (s).
    pub time_s: f64,
}

/// A solved slew.
#[derive(Debug, Clone)]
pub struct Solution {
    /// The states at the step boundaries, `x_0 … x_K` (with reaction wheels, the
    /// attitude, the body rates and the total angular momentum in the body frame).
    pub states: Vec<State>,
    /// With reaction wheels ([`Slew::wheels`]), their rates `φ̇` relative to the body at
    /// `x_0 … x_K`; empty otherwise.
    pub wheel_speeds: Vec<Vector3<f64>>,
    /// The torque of each step, `u_0 … u_{K−1}` (body frame, N·m; with [`Slew::wheels`],
    /// the three motor torques), a disturbance ([`Slew::disturbance`]) not included; with
    /// [`Inputs::Polynomial`], each step's mean `Σ_j b_j u_kj` (the constant torque of
    /// the same impulse).
    pub inputs: Vec<Vector3<f64>>,
    /// With [`Inputs::Polynomial`], each step's torques at its Gauss points
    /// ([`Solution::quadrature_nodes`]), which replay the solution through
    /// [`lgsvi_mechanics::Integrator::set_input_at_points`] (plus a disturbance, where
    /// there is one); empty otherwise.
    pub inputs_at_points: Vec<Vec<Vector3<f64>>>,
    /// The Gauss points of a step as fractions of its length, `c_j`.
    pub quadrature_nodes: Vec<f64>,
    /// The cost: `Σ h |u_k|²` for [`Cost::Energy`] (plus the tracking and terminal costs
    /// where given), the final time for [`Cost::Time`].
    pub cost: f64,
    /// The terminal constraint's multipliers (`∂J*/∂e`, in `(θ, ω)` at the target).
    pub multipliers: [f64; 6],
    /// The step `h = T/K`.
    pub h: f64,
    /// The final time `T = K h` (the given one for [`Cost::Energy`]).
    pub t_end: f64,
    /// Whether the scaled KKT residual reached the tolerance.
    pub converged: bool,
    /// The solver's record.
    pub statistics: Statistics,
}

impl Slew {
    /// A slew of the body of `inertia` in time `t_end`, by default rest to rest from the
    /// identity to the identity, 20 steps of 10 nodes, no torque bound, tolerance 1e-10,
    /// at most 100 iterations, from rest.
    pub fn new(inertia: Inertia, t_end: f64) -> Self {
        Self {
            inertia,
            gravity: None,
            wheels: None,
            t_end,
            start: (SO3::identity(), Vector3::zeros()),
            target: (SO3::identity(), Vector3::zeros()),
            steps: 20,
            nodes: 10,
            torque_max: None,
            disturbance: None,
            cost: Cost::Energy,
            inputs: Inputs::Constant,
            tracking: None,
            terminal_cost: None,
            tolerance: 1e-10,
            max_iterations: 100,
            initial: None,
        }
    }

    /// Puts the body under gravity: a heavy top about its fixed point ([`Gravity`]); the
    /// torques then work with or against gravity on the way. For [`Cost::Time`] the step's
    /// derivative in its length takes the step's exact derivative in the mass
    /// (`crate::shooting`'s time law), and the solve starts from the weightless slew: a
    /// bound well below the gravity torque (a swing-up) is a problem the solver may not
    /// converge on.
    pub fn gravity(mut self, gravity: Gravity) -> Self {
        self.gravity = Some(gravity);
        self
    }

    /// Puts three reaction wheels on the body ([`Wheels`]): the torques solved for, bounded
    /// by [`Slew::torque_max`] per wheel, are then the motors'. Without gravity. The
    /// minimum time holds too: the gyrostat's kinetic energy is quadratic in `(Ω, φ̇)`, so
    /// its steps scale in time as the rigid body's do.
    pub fn wheels(mut self, wheels: Wheels) -> Self {
        self.wheels = Some(wheels);
        self
    }

    /// The system the steps integrate: the free rigid body, the heavy top, or the
    /// spacecraft with its reaction wheels.
    pub(crate) fn system(&self) -> Result<Plant, OptimalError> {
        if let Some(w) = self.wheels {
            // (Gravity with m g = 0 beside wheels, which `check` lets through, is none.)
            let craft = Gyrostat::new(self.inertia.matrix(), w.axes, w.inertia)?;
            return Ok(Plant::Wheels {
                craft,
                speeds: w.speeds,
                disturbance: self.disturbance_torque(),
            });
        }
        let body = match self.gravity {
            None => BuiltInSo3::Free(RigidBody::new(self.inertia)),
            Some(g) => BuiltInSo3::Top(HeavyTop::new(
                self.inertia,
                g.mass,
                g.gravity,
                g.center_of_mass,
                g.direction,
            )?),
        };
        Ok(Plant::Body {
            body,
            disturbance: self.disturbance_torque(),
        })
    }

    /// The start `(R₀, Ω₀)` (body to world; body rates).
    pub fn from(mut self, attitude: SO3, omega: Vector3<f64>) -> Self {
        self.start = (attitude, omega);
        self
    }

    /// The target `(R_f, Ω_f)`.
    pub fn to(mut self, attitude: SO3, omega: Vector3<f64>) -> Self {
        self.target = (attitude, omega);
        self
    }

    /// `K` steps.
    pub fn steps(mut self, steps: usize) -> Self {
        self.steps = steps;
        self
    }

    /// `n` nodes per step.
    pub fn nodes(mut self, nodes: usize) -> Self {
        self.nodes = nodes;
        self
    }

    /// The largest torque per body axis (with [`Slew::wheels`], per wheel: the motors'
    /// limits).
    pub fn torque_max(mut self, bound: [f64; 3]) -> Self {
        self.torque_max = Some(Vector3::from(bound));
        self
    }

    /// A constant torque on the body beside the slew's own (body frame, N·m): a known
    /// disturbance, such as a solar-pressure or outgassing torque or a mean gravity-gradient
    /// torque, that the torques (or, with [`Slew::wheels`], the motors, whose wheels then
    /// take up its momentum) work against. It enters each step as a body torque added to
    /// the slew's, is not part of the cost, and is not in [`Solution::inputs`]: a replay
    /// adds it to them (with the wheels, as the gyrostat's first three input entries).
    /// Beside a bound, it must leave room to move: the solver does not check that the
    /// bounds can hold it.
    pub fn disturbance(mut self, torque: [f64; 3]) -> Self {
        self.disturbance = Some(Vector3::from(torque));
        self
    }

    /// The disturbance torque, zero without one.
    pub(crate) fn disturbance_torque(&self) -> Vector3<f64> {
        self.disturbance.unwrap_or_else(Vector3::zeros)
    }

    /// What to minimise: the input energy (the default) or the final time. For
    /// [`Cost::Time`] the torques must be bounded ([`Slew::torque_max`]) and the final
    /// time given to [`Slew::new`] is a first guess: rest to rest, without gravity or a
    /// disturbance, the start does not depend on it (the minimum-energy slew is rescaled
    /// in time until its largest torque meets its bound); otherwise the start is the bounded
    /// minimum-energy slew at the shortest time within 30% that it is found for, from
    /// the guess. A warm start ([`Slew::warm_start`]) is used at the guess as it is.
    pub fn cost(mut self, cost: Cost) -> Self {
        self.cost = cost;
        self
    }

    /// How the torque varies within a step: constant (the default) or a polynomial
    /// given at the step's Gauss points ([`Inputs`]).
    pub fn inputs(mut self, inputs: Inputs) -> Self {
        self.inputs = inputs;
        self
    }

    /// Adds a cost for straying from a reference motion, one state `(R_ref,k, Ω_ref,k)` per
    /// step boundary `k = 1 … K`:
    /// `Σ_k h (q_θ |log(R_ref,kᵀ R_k)|² + q_ω |Ω_k − Ω_ref,k|²)` with
    /// `weights = [q_θ, q_ω]` (the attitude error taken by the group's log). The problem
    /// stays a least-squares one, solved by Gauss–Newton with the residuals' exact
    /// Jacobians (the log's through the inverse right Jacobian), the Hessian
    /// `diag(2w) + 2 GᵀG`: converging linearly where the residuals at the optimum are not
    /// small. An iteration's cost is linear in the step count (the subproblem's banded
    /// form, crate documentation), so long horizons are cheap. For [`Cost::Energy`].
    pub fn track(mut self, reference: Vec<Target>, weights: [f64; 2]) -> Self {
        self.tracking = Some((reference, weights));
        self
    }

    /// Replaces the exact terminal condition by a cost on the miss,
    /// `q_θ |log(R_fᵀ R_K)|² + q_ω |Ω_K − Ω_f|²` with `weights = [q_θ, q_ω]`: a soft target.
    /// For [`Cost::Energy`].
    pub fn terminal_cost(mut self, weights: [f64; 2]) -> Self {
        self.terminal_cost = Some(weights);
        self
    }

    /// The scaled KKT residual to reach.
    pub fn tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }

    /// The most SQP iterations.
    pub fn max_iterations(mut self, iterations: usize) -> Self {
        self.max_iterations = iterations;
        self
    }

    /// Start the iteration from these torques (a warm start: one per step, or with
    /// [`Inputs::Polynomial`] one per Gauss point of each step) instead of rest.
    pub fn warm_start(mut self, inputs: Vec<Vector3<f64>>) -> Self {
        self.initial = Some(inputs);
        self
    }

    fn check(&self) -> Result<StepSettings, OptimalError> {
        use checks::invalid;
        checks::horizon(
            self.t_end,
            self.steps,
            "the terminal attitude and rates are six conditions; one step has three torques",
        )?;
        checks::bound("torque_max", self.torque_max)?;
        checks::tolerance(self.tolerance)?;
        checks::disturbance(self.disturbance)?;
        for (name, (r, w)) in [("start", self.start), ("target", self.target)] {
            if !(r.matrix().iter().all(|x| x.is_finite()) && w.iter().all(|x| x.is_finite())) {
                return Err(invalid(
                    name,
                    format!("{:?}, {:?}", r.matrix().as_slice(), w.as_slice()),
                    "not finite",
                ));
            }
        }
        let settings = StepSettings::new(self.t_end / self.steps as f64, self.nodes)?;
        if self.inputs == Inputs::Polynomial && self.cost == Cost::Time {
            return Err(invalid(
                "inputs",
                "Polynomial".into(),
                "polynomial inputs are built for the energy cost; a minimum-time optimum is \
                 bang-bang: hold the torques constant over each step",
            ));
        }
        checks::costs(
            self.tracking.as_ref(),
            |(r, w): &Target| {
                r.matrix().iter().all(|x| x.is_finite()) && w.iter().all(|x| x.is_finite())
            },
            self.steps,
            self.terminal_cost.as_ref(),
        )?;
        if let Some(w) = &self.wheels {
            if self.gravity.is_some_and(|g| g.mass * g.gravity != 0.0) {
                return Err(invalid(
                    "wheels",
                    "with gravity".into(),
                    "a spacecraft with reaction wheels is slewed without gravity: give one \
                     of the two",
                ));
            }
            // (A zero axis is the gyrostat's own refusal, below.)
            let unit = w.axes.map(|a| a / a.norm());
            let volume = unit[0].dot(&unit[1].cross(&unit[2])).abs();
            if w.axes.iter().all(|a| a.norm() > 0.0) && (volume.is_nan() || volume < 1e-6) {
                return Err(invalid(
                    "wheel axes",
                    format!(
                        "axes {:?}",
                        w.axes.iter().map(|a| [a.x, a.y, a.z]).collect::<Vec<_>>()
                    ),
                    "the three wheel axes must span the body's three axes (|a₁·(a₂ × a₃)| of \
                     the unit axes is below 1e-6: two are parallel, or all three in a plane)",
                ));
            }
            // The spacecraft's own checks, named by the setting that holds what they refuse.
            if let Err(error) = Gyrostat::new(self.inertia.matrix(), w.axes, w.inertia) {
                use lgsvi_mechanics::MechanicsError as M;
                let list = |v: &[f64]| format!("{v:?}");
                let flat: Vec<f64> = w.axes.iter().flat_map(|a| [a.x, a.y, a.z]).collect();
                let (name, value) = match &error {
                    M::InvalidSetting {
                        name: "wheel axis", ..
                    }
                    | M::NonFinite {
                        what: "wheel axis", ..
                    } => ("wheel axes", list(&flat)),
                    M::InvalidSetting {
                        name: "wheel inertia",
                        ..
                    }
                    | M::NonFinite {
                        what: "wheel inertia",
                        ..
                    } => ("wheel inertia", list(&w.inertia)),
                    _ => (
                        "inertia and wheel inertia",
                        format!("{:?}; {}", self.inertia.matrix(), list(&w.inertia)),
                    ),
                };
                let reason = match error {
                    M::InvalidSetting { reason, .. } => reason.to_string(),
                    M::NonFinite { .. } => "not finite".to_string(),
                    other => other.to_string(),
                };
                return Err(invalid(name, value, &reason));
            }
            if !w.speeds.iter().all(|x| x.is_finite()) {
                return Err(invalid(
                    "wheel speeds",
                    format!("{:?}", w.speeds.as_slice()),
                    "not finite",
                ));
            }
        }
        self.system()?;
        if self.cost == Cost::Time && (self.tracking.is_some() || self.terminal_cost.is_some()) {
            return Err(invalid(
                "cost",
                "Time".into(),
                "tracking and terminal costs are built for the energy cost",
            ));
        }
        if self.cost == Cost::Time && self.start == self.target {
            return Err(invalid(
                "target",
                "the start".into(),
                "the target is the start, reached in no time: give another target",
            ));
        }
        if let Some(initial) = &self.initial {
            checks::warm_start(
                initial,
                self.steps,
                || self.points_per_step(settings),
                ["torque", "torques"],
            )?;
        }
        Ok(settings)
    }

    /// The inputs of a step: one, or its Gauss-point count with [`Inputs::Polynomial`].
    fn points_per_step(&self, settings: StepSettings) -> Result<usize, OptimalError> {
        Ok(match self.inputs {
            Inputs::Constant => 1,
            _ => quadrature(self, settings)?.0.len(),
        })
    }

    /// Solves the slew (crate documentation).
    ///
    /// # Errors
    /// [`OptimalError::InvalidSetting`] for a setting out of range (and for a
    /// minimum-time slew without a torque bound);
    /// [`OptimalError::Infeasible`] when the bounds leave the target out of reach;
    /// [`OptimalError::NotConverged`] when the iterations run out;
    /// [`OptimalError::Mechanics`] for a step that fails (a slew too fast for its steps:
    /// give more steps).
    pub fn solve(&self) -> Result<Solution, OptimalError> {
        let settings = self.check()?;
        match self.cost {
            Cost::Energy => energy::minimum_energy(self, settings, self.tolerance),
            Cost::Time => time::minimum_time(self, self.tolerance),
        }
    }
}

/// The Gauss points of a step of `settings` (fractions of the step) and their weights.
fn quadrature(slew: &Slew, settings: StepSettings) -> Result<(Vec<f64>, Vec<f64>), OptimalError> {
    slew.system()?.quadrature(settings, slew.start)
}

/// The page `docs/guide/optimal.md`, whose Rust example is compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../../docs/guide/optimal.md")]
pub struct DocsPage;

/// This crate's `README.md`, whose Rust example is compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
