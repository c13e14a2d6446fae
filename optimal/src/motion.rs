//! Manoeuvres of a body in space (SE(3)): the pose and the body velocity driven from a
//! start to a target by a body wrench `(τ, f)`, at the least input energy in a fixed time
//! or in the least time.

use crate::energy::{by_step, Problem, Solved, Start};
use crate::shooting::{shoot_motion, Shot, SpacePlant, Wants};
use crate::time::{bracket, least_time, rescaled_to_bound, TimeSettings, Timed, START_TOLERANCE};
use crate::tracking::Residuals;
use crate::{Cost, Inputs, OptimalError, Statistics};
use lgsvi_mechanics::built_in::BuiltInSe3;
use lgsvi_mechanics::lie::{ExpChart, LieGroup, So3Chart, SE3};
use lgsvi_mechanics::linearization::world_coordinates;
use lgsvi_mechanics::{Integrator, State, StepSettings};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};
use std::time::Instant;

/// A state of a body in space.
type SE3State = State<SE3, 6>;

/// A pose and body velocity `(g, ξ)`: a start, a target, a reference state.
type PoseVelocity = (SE3, Vector6<f64>);

/// A first guess of a minimum-time manoeuvre's final time ([`Cost::Time`]): the longest of
/// the eigen-axis turn's bang-bang time ([`crate::eigen_axis_time`]), the straight move's
/// bang-bang time at the weakest axis's force, `2 √(m d / f_min)`, and the times to change
/// the body rates and the centre of mass's velocity at the weakest bounds,
/// `|ΔΩ| J_max/τ_min` and `m |Δẋ|/f_min` (`start` and `target` as [`Manoeuvre::from`] and [`Manoeuvre::to`] take
/// them). Each is the least time of one part of the motion alone under a bound no larger
/// than the box allows, so the guess is of the right size, not a bound on the least time.
/// `None` when the target is the start, or for a bound that is not positive and finite.
///
/// ```
/// use lgsvi_mechanics::lie::{LieGroup, SE3, SO3};
/// use lgsvi_mechanics::Inertia;
/// use nalgebra::{Vector3, Vector6};
///
/// // A move of 2 m by 10 kg at 0.2 N: 2 √(10 · 2 / 0.2) = 20 s.
/// let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5])?;
/// let start = (SE3::identity(), Vector6::zeros());
/// let moved = SE3::new(SO3::identity(), Vector3::new(2.0, 0.0, 0.0));
/// let target = (moved, Vector6::zeros());
/// let t = lgsvi_optimal::separate_bang_bang_time(&inertia, 10.0, &start, &target, [0.1; 3], [0.2; 3]);
/// assert!((t.unwrap() - 20.0).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn separate_bang_bang_time(
    inertia: &lgsvi_mechanics::Inertia,
    mass: f64,
    start: &(SE3, Vector6<f64>),
    target: &(SE3, Vector6<f64>),
    torque_max: [f64; 3],
    force_max: [f64; 3],
) -> Option<f64> {
    let valid = |b: &[f64; 3]| b.iter().all(|x| x.is_finite() && *x > 0.0);
    if !(valid(&torque_max) && valid(&force_max) && mass.is_finite() && mass > 0.0) {
        return None;
    }
    let turn = start.0.rotation().inverse().compose(target.0.rotation());
    let rotation = crate::eigen_axis_time(inertia, &turn, torque_max).unwrap_or(0.0);
    let weakest = |b: [f64; 3]| b.iter().copied().fold(f64::INFINITY, f64::min);
    let distance = (target.0.translation() - start.0.translation()).norm();
    let translation = 2.0 * (mass * distance / weakest(force_max)).sqrt();
    // The rates' change in the body, the centre of mass's in the world frame (`ẋ = R v`).
    let world = |(g, xi): &(SE3, Vector6<f64>)| g.rotation().matrix() * xi.fixed_rows::<3>(3);
    let rates = (target.1.fixed_rows::<3>(0) - start.1.fixed_rows::<3>(0)).norm();
    let largest_moment = inertia
        .principal_moments()
        .iter()
        .copied()
        .fold(0.0, f64::max);
    let spin = rates * largest_moment / weakest(torque_max);
    let speed = (world(target) - world(start)).norm() * mass / weakest(force_max);
    let guess = rotation.max(translation).max(spin).max(speed);
    (guess > 0.0 && guess.is_finite()).then_some(guess)
}

/// A manoeuvre of a rigid body in space: from a start `(g₀, ξ₀)` to a target `(g_f, ξ_f)`
/// in the fixed time `T`, driven by a body wrench `u = (τ, f)` (the torque and the force,
/// both in the body frame, as [`Integrator::set_input`] takes them), at the least
/// `∫ |u|² dt = ∫ (|τ|² + |f|²) dt` (no ½), the torque and the force bounded per axis
/// where bounds are given.
///
/// A pose is `g = (R, x)`: the attitude (body to world) and the centre of mass in the
/// world frame; a velocity is the body velocity `ξ = (Ω, v)`, the body rates and the
/// centre of mass's velocity in the body frame (`ẋ = R v`), as
/// [`lgsvi_mechanics::FreeBody`]'s states hold them. The body is a
/// [`BuiltInSe3`]: the free body in space or the body orbiting a point mass.
///
/// The problem is the slew's ([`crate::Slew`], crate documentation) on SE(3): `K` of
/// lgsvi's steps, the wrench held over each step or a polynomial given at its Gauss points
/// ([`Inputs`]), the terminal pose and velocity exact: twelve conditions, the miss
/// `(log(R_Kᵀ R_f), x_f − x_K, Ω_f − Ω_K, ẋ_f − ẋ_K)` with the centre of mass's position
/// and velocity in the world frame. It is solved by the slew's SQP with the steps' exact
/// linearisations, in a metric that measures the force in the world frame: the step's
/// `δf` counts as `δf − f̂ δθ`, with `δθ` the attitude's change at the force's Gauss point
/// that the step's start state and inputs bring (the step's own linearisation there,
/// [`lgsvi_mechanics::linearization::StepLinearization::point_configurations`]; the
/// step's mean for a held wrench).
/// The centre of mass moves under the world-frame force `F = R f`, so in the pair
/// (torque, world force) its miss is linear in `F` and does not depend on the torque (the
/// free body without a disturbance force off its turn, which `R` turns; the orbiting body
/// nearly so): the iteration converges in about as many
/// iterations as the slew alone, however large the translation's share of the cost (the
/// guide's "How fast it converges"), with the force bounded or not (the subproblem keeps
/// the states among its variables and the measured step in its Hessian, so a bound stays
/// a bound). Only the path changes: the cost, the constraints and their solution are the
/// same. The terminal miss that the tolerance bounds has its position measured in
/// units of `L = max(1, |x₀|, |x_f|)` and its velocity in units of
/// `V = max(1, |v₀|, |v_f|)`, so that a body far from the origin converges to its own
/// precision.
///
/// With [`Cost::Time`] ([`Manoeuvre::cost`]) the final time is minimised instead, the
/// wrench held over each step and bounded: the slew's minimum-time SQP ([`crate::Slew`],
/// [`Cost::Time`]) on SE(3), started (the free body, rest to rest, without a disturbance)
/// from the unbounded minimum-energy manoeuvre rescaled in time to its bounds, else from a
/// bounded minimum-energy one.
///
/// ```
/// use lgsvi_mechanics::lie::{LieGroup, SE3, SO3};
/// use lgsvi_mechanics::{FreeBody, Inertia};
/// use lgsvi_optimal::Manoeuvre;
/// use nalgebra::{Vector3, Vector6};
///
/// // Move a 10 kg body 2 m along x and turn it 90° about z, rest to rest, in 20 s,
/// // at most 0.05 N·m and 0.25 N per axis.
/// let body = FreeBody::new(Inertia::from_principal_moments([1.0, 1.5, 2.0])?, 10.0)?;
/// let target = SE3::new(
///     SO3::exp(&Vector3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2)),
///     Vector3::new(2.0, 0.0, 0.0),
/// );
/// let solution = Manoeuvre::new(body, 20.0)
///     .to(target, Vector6::zeros())
///     .torque_max([0.05; 3])
///     .force_max([0.25; 3])
///     .solve()?;
/// assert!(solution.converged);
/// let last = solution.states.last().unwrap();
/// assert!((last.position() - Vector3::new(2.0, 0.0, 0.0)).amax() < 1e-9);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct Manoeuvre {
    body: BuiltInSe3,
    t_end: f64,
    start: (SE3, Vector6<f64>),
    target: (SE3, Vector6<f64>),
    steps: usize,
    nodes: usize,
    torque_max: Option<Vector3<f64>>,
    force_max: Option<Vector3<f64>>,
    disturbance: Option<Vector6<f64>>,
    inputs: Inputs,
    cost: Cost,
    tolerance: f64,
    max_iterations: usize,
    initial: Option<Vec<Vector6<f64>>>,
    tracking: Option<(Vec<PoseVelocity>, [f64; 4])>,
    terminal_cost: Option<[f64; 4]>,
}

/// A solved [`Manoeuvre`].
#[derive(Debug, Clone)]
pub struct ManoeuvreSolution {
    /// The states at the step boundaries, `x_0 … x_K`: pose, body velocity `(Ω, v)` and
    /// body momentum.
    pub states: Vec<State<SE3, 6>>,
    /// The body wrench `(τ, f)` of each step, `u_0 … u_{K−1}` (N·m, N), a disturbance
    /// ([`Manoeuvre::disturbance`]) not included; with
    /// [`Inputs::Polynomial`], each step's mean `Σ_j b_j u_kj`.
    pub inputs: Vec<Vector6<f64>>,
    /// With [`Inputs::Polynomial`], each step's wrenches at its Gauss points
    /// ([`ManoeuvreSolution::quadrature_nodes`]), which replay the solution through
    /// [`Integrator::set_input_at_points`] (plus a disturbance, where there is one); empty
    /// otherwise.
    pub inputs_at_points: Vec<Vec<Vector6<f64>>>,
    /// The Gauss points of a step as fractions of its length, `c_j`.
    pub quadrature_nodes: Vec<f64>,
    /// The cost: `∫ |u|² dt` (the steps' quadrature of it), or with [`Cost::Time`] the
    /// final time.
    pub cost: f64,
    /// The terminal constraint's multipliers, `∂J*/∂e` for the miss
    /// `e = (log(R_Kᵀ R_f), x_f − x_K, Ω_f − Ω_K, ẋ_f − ẋ_K)`: the attitude's three, the
    /// position's (world frame), the body rates', the velocity's (world frame).
    pub multipliers: [f64; 12],
    /// The step `h = T/K`.
    pub h: f64,
    /// The final time `T`.
    pub t_end: f64,
    /// Whether the scaled KKT residual reached the tolerance.
    pub converged: bool,
    /// The solver's record.
    pub statistics: Statistics,
}

impl Manoeuvre {
    /// A manoeuvre of `body` in time `t_end`, by default rest to rest from the identity
    /// pose to the identity pose, 20 steps of 10 nodes, no bounds, tolerance 1e-10, at
    /// most 500 iterations (a manoeuvre whose translation dominates its cost takes
    /// about a hundred where the force is bounded: the guide's "How fast it converges"),
    /// from no wrench (with bounds, from the unbounded optimum clamped to them, and again
    /// from no wrench where that fails; each of these solves has the iteration limit, and
    /// the solution's record counts the unbounded solve's iterations with its own).
    pub fn new(body: impl Into<BuiltInSe3>, t_end: f64) -> Self {
        Self {
            body: body.into(),
            t_end,
            start: (SE3::identity(), Vector6::zeros()),
            target: (SE3::identity(), Vector6::zeros()),
            steps: 20,
            nodes: 10,
            torque_max: None,
            force_max: None,
            disturbance: None,
            inputs: Inputs::Constant,
            cost: Cost::Energy,
            tolerance: 1e-10,
            max_iterations: 500,
            initial: None,
            tracking: None,
            terminal_cost: None,
        }
    }

    /// The start: pose `(R₀, x₀)` and body velocity `(Ω₀, v₀)`.
    pub fn from(mut self, pose: SE3, velocity: Vector6<f64>) -> Self {
        self.start = (pose, velocity);
        self
    }

    /// The target: pose `(R_f, x_f)` and body velocity `(Ω_f, v_f)`.
    pub fn to(mut self, pose: SE3, velocity: Vector6<f64>) -> Self {
        self.target = (pose, velocity);
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

    /// The largest torque per body axis (N·m).
    pub fn torque_max(mut self, bound: [f64; 3]) -> Self {
        self.torque_max = Some(Vector3::from(bound));
        self
    }

    /// The largest force per body axis (N).
    pub fn force_max(mut self, bound: [f64; 3]) -> Self {
        self.force_max = Some(Vector3::from(bound));
        self
    }

    /// A constant body wrench on the body beside the manoeuvre's own (body frame: torque
    /// N·m, force N): a known disturbance, such as a solar-pressure torque and force, a
    /// leak or a thruster's misalignment, that the wrench works against. It enters each
    /// step as a body wrench added to the inputs, is not part of the cost, and is not in
    /// [`ManoeuvreSolution::inputs`]: a replay adds it to them. Beside a bound, it must
    /// leave room to move: the solver does not check that the bounds can hold it.
    pub fn disturbance(mut self, torque: [f64; 3], force: [f64; 3]) -> Self {
        let [tx, ty, tz] = torque;
        let [fx, fy, fz] = force;
        self.disturbance = Some(Vector6::new(tx, ty, tz, fx, fy, fz));
        self
    }

    /// The body and the disturbance its steps integrate.
    fn plant(&self) -> SpacePlant {
        SpacePlant {
            body: self.body,
            disturbance: self.disturbance.unwrap_or_else(Vector6::zeros),
        }
    }

    /// How the wrench varies within a step: constant (the default) or a polynomial given
    /// at the step's Gauss points ([`Inputs`]).
    pub fn inputs(mut self, inputs: Inputs) -> Self {
        self.inputs = inputs;
        self
    }

    /// What to minimise: the input energy `∫ |u|² dt` in the fixed time (the default), or
    /// the final time ([`Cost::Time`]), the time given to [`Manoeuvre::new`] then being
    /// the first guess's. The least time needs both bounds ([`Manoeuvre::torque_max`],
    /// [`Manoeuvre::force_max`]) and a wrench held over each step (its optimum is
    /// bang-bang); tracking and terminal costs are for the energy.
    pub fn cost(mut self, cost: Cost) -> Self {
        self.cost = cost;
        self
    }

    /// Adds the cost of straying from a reference motion, one state `(g_ref,k, ξ_ref,k)`
    /// (pose, body velocity) per step boundary `k = 1 … K`:
    /// `Σ_k h (q_θ |log(R_ref,kᵀ R_k)|² + q_x |x_k − x_ref,k|² + q_ω |Ω_k − Ω_ref,k|²
    /// + q_v |ẋ_k − ẋ_ref,k|²)` with `weights = [q_θ, q_x, q_ω, q_v]`, the centre of
    /// mass's position and velocity `ẋ = R v` in the world frame. The problem stays a least
    /// squares one (the slew's [`crate::Slew::track`]).
    pub fn track(mut self, reference: Vec<(SE3, Vector6<f64>)>, weights: [f64; 4]) -> Self {
        self.tracking = Some((reference, weights));
        self
    }

    /// Replaces the exact terminal state by a cost on the miss, `q_θ |log(R_fᵀ R_K)|² +
    /// q_x |x_K − x_f|² + q_ω |Ω_K − Ω_f|² + q_v |ẋ_K − ẋ_f|²` with
    /// `weights = [q_θ, q_x, q_ω, q_v]`: a soft target.
    pub fn terminal_cost(mut self, weights: [f64; 4]) -> Self {
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

    /// Start the iteration from these wrenches (a warm start: one per step, or with
    /// [`Inputs::Polynomial`] one per Gauss point of each step) instead of none.
    pub fn warm_start(mut self, inputs: Vec<Vector6<f64>>) -> Self {
        self.initial = Some(inputs);
        self
    }

    /// The bound on each entry of the wrench: infinite where the torque or the force has
    /// none; `None` where neither has one.
    fn wrench_bound(&self) -> Option<Vector6<f64>> {
        if self.torque_max.is_none() && self.force_max.is_none() {
            return None;
        }
        let free = Vector3::repeat(f64::INFINITY);
        let (t, f) = (
            self.torque_max.unwrap_or(free),
            self.force_max.unwrap_or(free),
        );
        Some(Vector6::new(t.x, t.y, t.z, f.x, f.y, f.z))
    }

    /// The settings' steps, after the manoeuvre's settings are checked.
    fn check(&self) -> Result<StepSettings, OptimalError> {
        use crate::checks::{self, invalid};
        checks::horizon(
            self.t_end,
            self.steps,
            "the terminal pose and velocity are twelve conditions; one step has six inputs",
        )?;
        checks::bound("torque_max", self.torque_max)?;
        checks::bound("force_max", self.force_max)?;
        checks::tolerance(self.tolerance)?;
        checks::disturbance(self.disturbance)?;
        for (name, (g, xi)) in [("start", self.start), ("target", self.target)] {
            let finite = g.rotation().matrix().iter().all(|x| x.is_finite())
                && g.translation().iter().all(|x| x.is_finite())
                && xi.iter().all(|x| x.is_finite());
            if !finite {
                return Err(invalid(
                    name,
                    format!(
                        "R {:?} (row-major), x {:?}, body velocity {:?}",
                        g.rotation().to_row_major(),
                        g.translation().as_slice(),
                        xi.as_slice()
                    ),
                    "not finite",
                ));
            }
        }
        let settings = StepSettings::new(self.t_end / self.steps as f64, self.nodes)?;
        if let Some(initial) = &self.initial {
            let points = || {
                Ok(match self.inputs {
                    Inputs::Constant => 1,
                    _ => self.quadrature(settings)?.0.len(),
                })
            };
            checks::warm_start(initial, self.steps, points, ["wrench", "wrenches"])?;
        }
        checks::costs(
            self.tracking.as_ref(),
            |(g, xi): &PoseVelocity| {
                g.rotation().matrix().iter().all(|x| x.is_finite())
                    && g.translation().iter().all(|x| x.is_finite())
                    && xi.iter().all(|x| x.is_finite())
            },
            self.steps,
            self.terminal_cost.as_ref(),
        )?;
        if self.cost == Cost::Time {
            let energy_only = |name, value: &str, reason| Err(invalid(name, value.into(), reason));
            if self.torque_max.is_none() || self.force_max.is_none() {
                let name = if self.torque_max.is_none() {
                    "torque_max"
                } else {
                    "force_max"
                };
                return energy_only(
                    name,
                    "(none)",
                    "a minimum-time manoeuvre needs bounds on both the torque and the force \
                     (without one, the motion it drives takes no time and the least time is \
                     not attained)",
                );
            }
            if self.inputs == Inputs::Polynomial {
                return energy_only(
                    "inputs",
                    "Polynomial",
                    "polynomial inputs are built for the energy cost; a minimum-time optimum \
                     is bang-bang: hold the wrench constant over each step",
                );
            }
            if self.tracking.is_some() || self.terminal_cost.is_some() {
                return energy_only(
                    "cost",
                    "Time",
                    "tracking and terminal costs are built for the energy cost",
                );
            }
            if self.start == self.target {
                return energy_only(
                    "target",
                    "the start",
                    "the target is the start, reached in no time: give another target",
                );
            }
        }
        Ok(settings)
    }

    /// The Gauss points of a step (fractions of the step) and their weights.
    fn quadrature(&self, settings: StepSettings) -> Result<(Vec<f64>, Vec<f64>), OptimalError> {
        let it = Integrator::new(self.body, settings, self.start.0, self.start.1)?;
        Ok((it.quadrature_nodes(), it.quadrature_weights()))
    }

    /// Solves the manoeuvre (the type's documentation).
    ///
    /// # Errors
    /// [`OptimalError::InvalidSetting`] for a setting out of range;
    /// [`OptimalError::Infeasible`] when the bounds leave the target out of reach;
    /// [`OptimalError::NotConverged`] when the iterations run out;
    /// [`OptimalError::Mechanics`] for a step that fails (a start off the group, a body
    /// falling onto its attracting mass, a manoeuvre too fast for its steps).
    pub fn solve(&self) -> Result<ManoeuvreSolution, OptimalError> {
        let clock = Instant::now();
        let settings = self.check()?;
        if self.cost == Cost::Time {
            return self.minimum_time();
        }
        let (k_steps, h) = (self.steps, settings.h());
        let (nodes, weights) = self.quadrature(settings)?;
        let bound = self.wrench_bound();
        let scale = self.scale();
        let attempt = |initial: Option<&[Vector6<f64>]>, bound: Option<Vector6<f64>>| {
            let start = Start::of(self.inputs, h, k_steps, &weights, initial, bound);
            self.solve_from(settings, start, bound, &scale, &weights)
        };
        // Bounded without a warm start: first the unbounded manoeuvre (the fastest to solve,
        // in the world-frame force's metric), then the bounded one from its optimum clamped
        // to the bounds, nearer the solution than rest (a subproblem linearised about the
        // unforced drift can also find no wrench within the bounds where the manoeuvre has
        // one). Where the unbounded manoeuvre has no solution, or the bounded one from its
        // optimum fails, again from rest; where that fails too, its verdict where it finds
        // the manoeuvre infeasible (a subproblem with no wrench within the bounds: the
        // clamped start can instead stall without one), else the first verdict.
        let solved = match (&self.initial, bound) {
            (None, Some(_)) => match attempt(None, None) {
                Ok((per_step, free)) => {
                    let (means, at_points) = by_step(&free.inputs, per_step, &weights);
                    let inputs = if at_points.is_empty() {
                        means
                    } else {
                        at_points.concat()
                    };
                    match attempt(Some(&inputs), bound) {
                        Ok((per_step, found)) => (per_step, after(free.statistics, found)),
                        Err(first) => match attempt(None, bound) {
                            Ok((per_step, found)) => (per_step, after(free.statistics, found)),
                            Err(infeasible @ OptimalError::Infeasible { .. }) => {
                                return Err(infeasible)
                            }
                            Err(_) => return Err(first),
                        },
                    }
                }
                Err(_) => attempt(None, bound)?,
            },
            _ => attempt(self.initial.as_deref(), bound)?,
        };
        let per_step = solved.0;
        let solved = solved.1;
        // The multipliers of the scaled rows, in the unscaled miss (none for a soft target).
        let mut multipliers = [0.0; 12];
        // `∂J*/∂e`: the negative of the rows `M δ = e`'s multipliers, in the unscaled miss.
        for ((m, l), s) in multipliers.iter_mut().zip(&solved.multipliers).zip(scale) {
            *m = -l / s;
        }
        let (means, at_points) = by_step(&solved.inputs, per_step, &weights);
        let mut statistics = solved.statistics;
        statistics.time_s = clock.elapsed().as_secs_f64();
        Ok(ManoeuvreSolution {
            states: solved.run.states,
            inputs: means,
            inputs_at_points: at_points,
            quadrature_nodes: nodes,
            cost: solved.cost,
            multipliers,
            h,
            t_end: h * k_steps as f64,
            converged: true,
            statistics,
        })
    }

    /// The lengths that the miss's rows are measured in: 1 for the attitude's and the
    /// rates', `L = max(1, |x₀|, |x_f|)` for the position's and `V = max(1, |v₀|, |v_f|)`
    /// for the velocity's, so that the tolerance on the miss is relative to the
    /// manoeuvre's own size (a body 7000 km from the origin has its position to ~1e-9 m
    /// only, in double precision).
    fn scale(&self) -> [f64; 12] {
        let length = self
            .start
            .0
            .translation()
            .norm()
            .max(self.target.0.translation().norm())
            .max(1.0);
        let speed = self
            .start
            .1
            .fixed_rows::<3>(3)
            .norm()
            .max(self.target.1.fixed_rows::<3>(3).norm())
            .max(1.0);
        std::array::from_fn(|i| match i {
            3..=5 => length,
            9..=11 => speed,
            _ => 1.0,
        })
    }

    /// The Gauss–Newton SQP from `start`, the miss's rows measured in `scale`: the inputs
    /// a step and what it found.
    fn solve_from(
        &self,
        settings: StepSettings,
        start: Start<6>,
        bound: Option<Vector6<f64>>,
        scale: &[f64; 12],
        weights: &[f64],
    ) -> Result<(usize, Solved<SE3State, 6>), OptimalError> {
        let per_step = start.step_weights.len();
        let shoot = |u: &[Vector6<f64>]| {
            let mut shot = shoot_motion(
                self.plant(),
                settings,
                self.start,
                self.target,
                u,
                per_step,
                Wants {
                    attitudes: true,
                    time: false,
                },
            )?;
            for (i, l) in scale.iter().enumerate() {
                shot.miss[i] /= l;
                shot.sensitivity.row_mut(i).unscale_mut(*l);
                shot.terminal.row_mut(i).unscale_mut(*l);
            }
            Ok(shot)
        };
        let metric = |run: &Shot<SE3State>, inputs: &[Vector6<f64>]| {
            world_force_metric(run, inputs, per_step, weights)
        };
        let h = settings.h();
        let fit = |run: &Shot<SE3State>| self.residuals(h, run);
        let problem = Problem {
            step_weights: &start.step_weights,
            bound,
            exact_target: self.terminal_cost.is_none(),
            max_iterations: self.max_iterations,
            shoot: &shoot,
            residuals: &fit,
            equilibrate: true,
            metric: Some(&metric),
        };
        Ok((per_step, problem.solve(start.inputs, self.tolerance)?))
    }
}

impl Manoeuvre {
    /// The least time ([`Cost::Time`]): the slew's iteration ([`least_time`]) on SE(3).
    fn minimum_time(&self) -> Result<ManoeuvreSolution, OptimalError> {
        let found = least_time(self, self.tolerance)?;
        let settings = StepSettings::new(found.h, self.nodes)?;
        // The multipliers of the scaled rows, in the unscaled miss.
        let mut multipliers = [0.0; 12];
        for ((m, l), s) in multipliers
            .iter_mut()
            .zip(&found.multipliers)
            .zip(self.scale())
        {
            *m = l / s;
        }
        Ok(ManoeuvreSolution {
            states: found.shot.states,
            inputs: found.inputs,
            inputs_at_points: Vec::new(),
            quadrature_nodes: self.quadrature(settings)?.0,
            cost: found.t_end,
            multipliers,
            h: found.h,
            t_end: found.t_end,
            converged: true,
            statistics: found.statistics,
        })
    }
}

impl Timed<6> for Manoeuvre {
    type State = SE3State;
    fn bound(&self) -> Result<Vector6<f64>, OptimalError> {
        // Both bounds are given (`Manoeuvre::check`).
        self.wrench_bound()
            .filter(|b| b.iter().all(|x| x.is_finite()))
            .ok_or_else(|| {
                crate::checks::invalid(
                    "torque_max",
                    "(none)".into(),
                    "a minimum-time manoeuvre needs bounds on both the torque and the force",
                )
            })
    }
    fn settings(&self) -> TimeSettings {
        TimeSettings {
            steps: self.steps,
            nodes: self.nodes,
            max_iterations: self.max_iterations,
            warm: self.initial.is_some(),
        }
    }
    fn shoot(
        &self,
        settings: StepSettings,
        inputs: &[Vector6<f64>],
    ) -> Result<Shot<SE3State>, OptimalError> {
        let wants = Wants {
            attitudes: false,
            time: true,
        };
        let mut shot = shoot_motion(
            self.plant(),
            settings,
            self.start,
            self.target,
            inputs,
            1,
            wants,
        )?;
        for (i, l) in self.scale().iter().enumerate() {
            shot.miss[i] /= l;
            shot.sensitivity.row_mut(i).unscale_mut(*l);
            shot.terminal.row_mut(i).unscale_mut(*l);
            shot.time_sensitivity[i] /= l;
        }
        Ok(shot)
    }
    fn rate_rows(&self) -> std::ops::Range<usize> {
        // The body rates and the centre of mass's velocity.
        6..12
    }
    /// The warm start if given; for the free body from rest to rest, the unbounded
    /// minimum-energy manoeuvre rescaled in time until its largest wrench entry meets its
    /// bound (as the slew's: `u(t)` over `T` becomes `u(t/c)/c²` over `cT`, the same path;
    /// an orbiting body's gravity and a disturbance do not scale so); else the bounded
    /// minimum-energy manoeuvre at a time [`bracket`] finds.
    fn feasible_start(&self, k_steps: usize) -> Result<(Vec<Vector6<f64>>, f64), OptimalError> {
        if let Some(initial) = &self.initial {
            return Ok((initial.clone(), self.t_end));
        }
        let bound = Timed::bound(self)?;
        let energy = |t_end: f64, bounded: bool| {
            Manoeuvre {
                t_end,
                steps: k_steps,
                cost: Cost::Energy,
                tolerance: START_TOLERANCE,
                torque_max: self.torque_max.filter(|_| bounded),
                force_max: self.force_max.filter(|_| bounded),
                ..self.clone()
            }
            .solve()
        };
        // (A disturbance does not scale with the time either.)
        let free = matches!(self.body, BuiltInSe3::Free(_))
            && self.plant().disturbance == Vector6::zeros();
        if free && self.start.1 == Vector6::zeros() && self.target.1 == Vector6::zeros() {
            let unbounded = energy(self.t_end, false)?;
            if let Some(start) = rescaled_to_bound(&unbounded.inputs, &bound, self.t_end) {
                return Ok(start);
            }
        }
        bracket(self.t_end, |t_end| Ok(energy(t_end, true)?.inputs))
    }
}

impl Manoeuvre {
    /// The tracking and terminal costs' weighted residuals and their Jacobians in the states
    /// they read (the slew's, `crate::tracking`, on SE(3)): each state `k` with weights `q`
    /// gives `√q_θ log(R_refᵀ R_k)`, `√q_x (x_k − x_ref)`, `√q_ω (Ω_k − Ω_ref)`,
    /// `√q_v (ẋ_k − ẋ_ref)` (times `√h` when tracked), the state's coordinates taken to the
    /// world frame ([`world_coordinates`]), the attitude's through `J_r(e)⁻¹`. `None`
    /// without either cost.
    fn residuals(&self, h: f64, shot: &Shot<SE3State>) -> Option<Residuals> {
        if self.tracking.is_none() && self.terminal_cost.is_none() {
            return None;
        }
        let mut terms: Vec<(usize, PoseVelocity, [f64; 4])> = Vec::new();
        if let Some((reference, q)) = &self.tracking {
            for (k, state) in reference.iter().enumerate() {
                terms.push((k + 1, *state, q.map(|q| h * q)));
            }
        }
        if let Some(q) = self.terminal_cost {
            terms.push((shot.states.len() - 1, self.target, q));
        }
        let observation = shot.observation();
        let mut values = DVector::<f64>::zeros(12 * terms.len());
        let mut blocks = Vec::with_capacity(terms.len());
        for (row, (k, (pose, xi), q)) in terms.into_iter().enumerate() {
            let state = &shot.states[k];
            let world = |g: &SE3, xi: &Vector6<f64>| g.rotation().matrix() * xi.fixed_rows::<3>(3);
            let e = pose
                .rotation()
                .inverse()
                .compose(state.configuration.rotation())
                .log();
            let parts = [
                e,
                state.configuration.translation() - pose.translation(),
                state.velocity.fixed_rows::<3>(0) - xi.fixed_rows::<3>(0),
                world(&state.configuration, &state.velocity) - world(&pose, &xi),
            ];
            // The world-frame coordinates to the weighted residual's rows.
            let mut local = DMatrix::<f64>::zeros(12, 12);
            for (part, weight) in q.iter().enumerate() {
                let w = weight.sqrt();
                let jacobian = if part == 0 {
                    ExpChart.rotation_left_differential_inverse(&e)
                } else {
                    Matrix3::identity()
                };
                local
                    .view_mut((3 * part, 3 * part), (3, 3))
                    .copy_from(&(jacobian * w));
                values
                    .rows_mut(12 * row + 3 * part, 3)
                    .copy_from(&(parts[part] * w));
            }
            let to_world = world_coordinates(&state.configuration, &state.velocity);
            blocks.push((k, 12 * row, local * to_world * &observation));
        }
        Some(Residuals { values, blocks })
    }
}

/// `found` with the record of an earlier solve before its own (the record covers both).
fn after(first: Statistics, mut found: Solved<SE3State, 6>) -> Solved<SE3State, 6> {
    let then = &mut found.statistics;
    then.iterations += first.iterations;
    then.kkt_residuals.splice(0..0, first.kkt_residuals);
    then.terminal_misses.splice(0..0, first.terminal_misses);
    found
}

/// The maps `C_i` of the world-frame force metric ([`Problem::metric`]): the body force
/// `f` of an input seen through the attitude's motion, `δf − f̂ δθ`, is `Rᵀ δF`, the
/// world-frame force's change brought back to the body (`F = R f`, so
/// `δF = R (δf − f̂ δθ)` with `R → R exp(θ̂)`). `δθ_i = P_i [δx_k; δu_k]` is the
/// attitude's change at input `i`'s Gauss point, exact from the step's start state and
/// inputs (the quadrature mean over the step for a held wrench), so `C_i` is `f̂_i P_i` in
/// its force rows and zero in its torque rows.
///
/// Why: the translation is driven by the world-frame force alone, which turns with the
/// attitude when the force is held fixed in the body, so in `(τ, f)` the position's miss
/// is curved (`∂²x/∂τ∂f ≠ 0`) and the Gauss–Newton model, which leaves that curvature out,
/// converges slowly or not at all where the translation dominates the cost. Measured in
/// `(τ, F)` the free body's position is linear in `F` and independent of `τ`, the cost
/// `|τ|² + |F|²` unchanged; the metric is that change of variables at the iterate. It
/// measures the control force alone, whose square the cost is: a disturbance force
/// ([`Manoeuvre::disturbance`]) off the turn still turns with the body, a curvature the
/// model leaves out (the KKT points are the same either way).
fn world_force_metric(
    run: &Shot<SE3State>,
    inputs: &[Vector6<f64>],
    per_step: usize,
    weights: &[f64],
) -> Vec<DMatrix<f64>> {
    let points = run.point_attitudes();
    inputs
        .iter()
        .enumerate()
        .map(|(i, u)| {
            let (k, j) = (i / per_step, i % per_step);
            let theta = if per_step == 1 {
                points[k]
                    .iter()
                    .zip(weights)
                    .fold(DMatrix::zeros(3, points[k][0].ncols()), |sum, (p, b)| {
                        sum + p * *b
                    })
            } else {
                points[k][j].clone()
            };
            let f = lgsvi_mechanics::lie::so3::hat(&Vector3::new(u[3], u[4], u[5]));
            let mut map = DMatrix::zeros(6, theta.ncols());
            map.rows_mut(3, 3).copy_from(&(f * theta));
            map
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::tests::banded_matches_condensed;
    use lgsvi_mechanics::lie::SO3;
    use lgsvi_mechanics::{FreeBody, Inertia, OrbitingBody};

    /// The banded subproblem of a body in space against the condensed one, with a tracking
    /// cost (the world-frame residual rows, the miss's rows scaled) or without, in the
    /// body frame's metric and the world frame's, for the free body and the orbiting body
    /// (near a circular orbit of speed 0.1 at r = 4), wrenches held and at the Gauss
    /// points, the terminal state exact (its rows equilibrated or not) or soft, unbounded
    /// and bounded below the unbounded optimum (so that a bound is active).
    #[test]
    fn the_banded_subproblem_in_space_is_the_condensed_one() {
        let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap();
        let (t_end, k_steps, nodes) = (8.0, 10usize, 6);
        let h = t_end / k_steps as f64;
        let start = (
            SE3::new(SO3::identity(), Vector3::new(4.0, 0.0, 0.0)),
            Vector6::new(0.0, 0.0, 0.0, 0.0, 0.1, 0.0),
        );
        let reference: Vec<_> = (1..=k_steps)
            .map(|k| {
                let t = k as f64 * h;
                (
                    SE3::new(
                        SO3::exp(&Vector3::new(0.0, 0.0, 0.02 * t)),
                        Vector3::new(4.0, 0.1 * t, 0.0),
                    ),
                    Vector6::new(0.0, 0.0, 0.02, 0.0, 0.1, 0.0),
                )
            })
            .collect();
        for body in [
            BuiltInSe3::Free(FreeBody::new(inertia, 7.0).unwrap()),
            BuiltInSe3::Orbit(OrbitingBody::new(inertia, 7.0, 0.04).unwrap()),
        ] {
            let manoeuvre = Manoeuvre::new(body, t_end)
                .from(start.0, start.1)
                .to(reference[k_steps - 1].0, reference[k_steps - 1].1)
                .steps(k_steps)
                .nodes(nodes)
                .track(reference.clone(), [2.0, 1.0, 0.5, 0.5]);
            let settings = StepSettings::new(h, nodes).unwrap();
            let weights = Integrator::new(body, settings, start.0, start.1)
                .unwrap()
                .quadrature_weights();
            for per_step in [1, weights.len()] {
                let inputs: Vec<Vector6<f64>> = (0..k_steps * per_step)
                    .map(|i| {
                        let t = i as f64 / per_step as f64;
                        Vector6::new(0.02 * t.cos(), -0.01, 0.01, 0.1, 0.05 * t.sin(), -0.2)
                    })
                    .collect();
                let mut run = shoot_motion(
                    SpacePlant {
                        body,
                        disturbance: Vector6::zeros(),
                    },
                    settings,
                    manoeuvre.start,
                    manoeuvre.target,
                    &inputs,
                    per_step,
                    Wants {
                        attitudes: true,
                        time: false,
                    },
                )
                .unwrap();
                for (i, l) in manoeuvre.scale().iter().enumerate() {
                    run.miss[i] /= l;
                    run.sensitivity.row_mut(i).unscale_mut(*l);
                    run.terminal.row_mut(i).unscale_mut(*l);
                }
                let fit = manoeuvre.residuals(h, &run).unwrap();
                let step_weights: Vec<f64> = if per_step == 1 {
                    vec![h]
                } else {
                    weights.iter().map(|b| h * b).collect()
                };
                let maps = world_force_metric(&run, &inputs, per_step, &weights);
                for metric in [None, Some(maps.as_slice())] {
                    for fit in [None, Some(&fit)] {
                        for (exact, equilibrate) in [(true, true), (true, false), (false, false)] {
                            let check = |bound: f64| {
                                banded_matches_condensed(
                                    &run,
                                    fit,
                                    metric,
                                    &inputs,
                                    &step_weights,
                                    bound,
                                    exact,
                                    equilibrate,
                                )
                            };
                            // Unbounded, then bounded below the unbounded optimum's largest
                            // entry, so that a bound is active (the subproblem is convex);
                            // without a target or residuals that optimum is no wrench.
                            let (_, peak) = check(f64::INFINITY);
                            if exact || fit.is_some() {
                                let (active, _) = check(0.9 * peak);
                                assert!(active > 0, "no bound active");
                            }
                        }
                    }
                }
            }
        }
    }
}
