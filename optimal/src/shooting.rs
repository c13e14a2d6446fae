//! One run of the integrator under given torques: its states, the terminal miss, and the
//! terminal state's exact sensitivity to every torque and to the common step length.

use crate::OptimalError;
use lgsvi_mechanics::built_in::{BuiltInSe3, BuiltInSo3};
use lgsvi_mechanics::group::GroupChart;
use lgsvi_mechanics::gyrostat::{BodyWheels, Gyrostat};
use lgsvi_mechanics::lie::{LieGroup, SE3, SO3};
use lgsvi_mechanics::linearization::{world_coordinates, Coordinates};
use lgsvi_mechanics::system::ElementOf;
use lgsvi_mechanics::{Integrator, State, StepSettings, System};
use nalgebra::{DMatrix, DVector, SVector, Vector3, Vector6};

/// What the slew's steps integrate: a rigid body or heavy top on SO(3) driven by a body
/// torque, or a spacecraft with three reaction wheels (SO(3) × ℝ³) driven by the wheels'
/// motor torques, its wheels starting at the given `speeds` (relative to the body); each
/// under a constant body torque `disturbance` beside the inputs (zero for none).
#[derive(Debug, Clone, Copy)]
pub(crate) enum Plant {
    Body {
        body: BuiltInSo3,
        disturbance: Vector3<f64>,
    },
    Wheels {
        craft: Gyrostat<3>,
        speeds: Vector3<f64>,
        disturbance: Vector3<f64>,
    },
}

impl Plant {
    /// An integrator of the plant from the attitude and body rates `start`, and the
    /// integrator's Gauss points and weights (fractions of a step).
    pub fn quadrature(
        &self,
        settings: StepSettings,
        start: (SO3, Vector3<f64>),
    ) -> Result<(Vec<f64>, Vec<f64>), OptimalError> {
        Ok(match *self {
            Plant::Body { body, .. } => {
                let it = Integrator::new(body, settings, start.0, start.1)?;
                (it.quadrature_nodes(), it.quadrature_weights())
            }
            Plant::Wheels { craft, speeds, .. } => {
                let (g, xi) = wheel_start(start, speeds);
                let it = Integrator::new(craft, settings, g, xi)?;
                (it.quadrature_nodes(), it.quadrature_weights())
            }
        })
    }
}

/// A body torque as the first three of six input entries (the rest zero).
fn torque_entries(torque: Vector3<f64>) -> Vector6<f64> {
    Vector6::new(torque.x, torque.y, torque.z, 0.0, 0.0, 0.0)
}

/// The gyrostat's start: the attitude with its wheel angles at zero, the velocity
/// `(Ω, φ̇)`.
fn wheel_start(
    start: (SO3, Vector3<f64>),
    speeds: Vector3<f64>,
) -> (BodyWheels<f64, 3>, SVector<f64, 6>) {
    let g = BodyWheels {
        attitude: start.0,
        wheels: Vector3::zeros(),
    };
    (
        g,
        SVector::<f64, 6>::from_iterator(start.1.iter().chain(speeds.iter()).copied()),
    )
}

/// One run of the inputs: its states, the terminal state's sensitivity and miss. `St` is
/// the state recorded at each step boundary: an SO(3) [`State`] for a slew, the body's own
/// `State<SE3, 6>` for a manoeuvre in space.
pub(crate) struct Shot<St = State> {
    /// `x_0 … x_K`: attitude, body rates and (for a gyrostat, the total angular momentum
    /// in the body frame) body momentum; on SE(3) the pose and the body velocity.
    pub states: Vec<St>,
    /// With reaction wheels, their rates `φ̇` at `x_0 … x_K`; empty otherwise.
    pub wheel_speeds: Vec<Vector3<f64>>,
    /// `M = ∂x_K/∂u` (the observed rows, `m` columns per input of a step) in the
    /// coordinates of the miss: the body-frame `(θ, ω)` on SO(3), `(θ_R, δx, δΩ, δẋ)` with
    /// the position and velocity in the world frame on SE(3) ([`shoot_motion`]).
    /// [`Shot::input_jacobians`] and [`Shot::point_attitudes`] are in the
    /// linearisation's native `(θ, ω)` on both.
    pub sensitivity: DMatrix<f64>,
    /// `∂x_K/∂h` (the observed rows), the step length shared by every step; zero unless
    /// the run was asked for it.
    pub time_sensitivity: DVector<f64>,
    /// The terminal miss: on SO(3) `e = (log(R_Kᵀ R_f), Ω_f − Ω_K)`, on SE(3)
    /// `(log(R_Kᵀ R_f), x_f − x_K, Ω_f − Ω_K, ẋ_f − ẋ_K)`.
    pub miss: DVector<f64>,
    /// The map from the plant's linearisation state at `x_K` (velocity coordinates, `2D`
    /// columns) to the miss's coordinates: `sensitivity = terminal ∂x_K/∂u`. The observed
    /// rows' selection on SO(3); on SE(3) with the position and velocity taken to the
    /// world frame ([`world_coordinates`]).
    pub terminal: DMatrix<f64>,
    /// The rows of the plant's linearisation state `(θ, ω) ∈ ℝ^{2D}` that the problem
    /// observes: on a slew the attitude's and the body rates' (`0..3` and `D..D + 3`), on
    /// SE(3) all twelve.
    rows: Vec<usize>,
    /// The entries of one input, `m`.
    width: usize,
    /// Each step's `A_k` and input Jacobians `B_kj` (velocity coordinates, the inputs'
    /// `m` columns).
    a: Vec<DMatrix<f64>>,
    b: Vec<Vec<DMatrix<f64>>>,
    /// Where the run was asked for them ([`Plan::attitudes`]), each step's attitudes at its
    /// Gauss points: `∂θ_j/∂(x_k, u_k)`, the rotation's three rows, the start state's `2D`
    /// columns (velocity coordinates) then the step's inputs' (`m` each); empty otherwise.
    points: Vec<Vec<DMatrix<f64>>>,
}

impl<St> Shot<St> {
    /// `∂x_k/∂u` for `k = 1 … K` in the plant's whole linearisation state (`2D` rows, `n`
    /// columns each), chained forwards: `S_{k+1} = A_k S_k + [B_kj in step k's columns]`.
    /// Dense: `K` matrices of `2D × n`, so quadratic in the step count; the tests'
    /// condensed reference.
    #[cfg(test)]
    pub fn full_state_sensitivities(&self) -> Vec<DMatrix<f64>> {
        let columns = self.sensitivity.ncols();
        let per_step = columns / self.a.len().max(1);
        let size = self.state_size();
        let mut out = Vec::with_capacity(self.a.len());
        let mut s = DMatrix::<f64>::zeros(size, columns);
        for (k, (a, b)) in self.a.iter().zip(&self.b).enumerate() {
            s = a * &s;
            for (j, bj) in b.iter().enumerate() {
                s.view_mut((0, per_step * k + self.width * j), (size, self.width))
                    .copy_from(bj);
            }
            out.push(s.clone());
        }
        out
    }

    /// The size `2D` of the plant's linearisation state.
    pub fn state_size(&self) -> usize {
        self.terminal.ncols()
    }

    /// The selection of the observed rows from the plant's linearisation state
    /// (`rows × 2D`).
    pub fn observation(&self) -> DMatrix<f64> {
        DMatrix::<f64>::identity(self.state_size(), self.state_size()).select_rows(&self.rows)
    }

    /// Each step's `A_k` (velocity coordinates, `2D × 2D`).
    pub fn state_jacobians(&self) -> &[DMatrix<f64>] {
        &self.a
    }

    /// Each step's input Jacobians `B_kj` (velocity coordinates, `2D × m` each, one per
    /// input of the step).
    pub fn input_jacobians(&self) -> &[Vec<DMatrix<f64>>] {
        &self.b
    }

    /// The gradient in the inputs of `Σ_k g_kᵀ x_k`, for `g_k` given at states `k ≥ 1`
    /// (`2D` entries each, `gradients[k − 1]`, in the plant's linearisation state): the
    /// adjoint recursion `p_K = g_K`, `∂/∂u_kj = B_kjᵀ p_{k+1}`,
    /// `p_k = A_kᵀ p_{k+1} + g_k`, linear in the step count (no sensitivity is formed).
    pub fn input_gradient(&self, gradients: &[DVector<f64>]) -> DVector<f64> {
        let columns = self.sensitivity.ncols();
        let k_steps = self.a.len();
        let per_step = columns / k_steps.max(1);
        let mut out = DVector::<f64>::zeros(columns);
        let mut p = DVector::<f64>::zeros(self.state_size());
        for k in (0..k_steps).rev() {
            p += &gradients[k];
            for (j, bj) in self.b[k].iter().enumerate() {
                out.rows_mut(per_step * k + self.width * j, self.width)
                    .copy_from(&(bj.transpose() * &p));
            }
            p = self.a[k].transpose() * &p;
        }
        out
    }

    /// Each step's attitudes at its Gauss points, `R_kj = R̄_kj exp(θ̂_kj)`: their
    /// derivatives `∂θ_kj/∂(x_k, u_k)` (three rows; the step's start state's `2D` columns
    /// in velocity coordinates, then the step's inputs' `m` each). Empty unless the run
    /// was asked for them ([`Plan::attitudes`]).
    pub fn point_attitudes(&self) -> &[Vec<DMatrix<f64>>] {
        &self.points
    }
}

/// The run from `start` under `inputs`, `per_step` of them per step of `settings` (one:
/// held over the step; the step's Gauss-point count: its values at the points,
/// [`Integrator::set_input_at_points`]), against `target`.
///
/// Each step is linearised exactly ([`Integrator::step_linearized`]: `A_k` and the input
/// Jacobians `B_kj`), and its derivative in the step length follows from the same `A_k`
/// and `B_kj` by the rigid body's time scaling: a step of length `ch` from `(R, Ω)` under
/// `u(t)` is the step of length `h` from `(R, cΩ)` under `c² u(ct)` with its end rates
/// divided by `c` (the Euler equations, and lgsvi's discrete action term by term, are
/// invariant under `t ↦ ct`, `Ω ↦ Ω/c`, `u ↦ u/c²`; the inputs at the points keep their
/// fractions of the step). Differentiating at `c = 1`:
///
/// ```text
/// h ∂x₊/∂h = A_ω Ω + 2 Σ_j B_j u_j − (0, Ω₊)
/// ```
///
/// with `A_ω` the columns of `A` in the start's rates and `u_j` the whole input, a
/// disturbance's included (it scales as the inputs do); `optimal/tests/free_time.rs`
/// checks both the scaling and this derivative against finite differences. The law is the
/// free body's, and a gyrostat's, whose kinetic energy is quadratic in `(Ω, φ̇)` too. A
/// potential does not scale so: the heavy top's action over `ch`,
/// `∫ (½ΩᵀJΩ + m g dᵀRρ) dt`, is `1/c` times the action over `h` of the top of mass `c²m`
/// (`t = cs`), so its step of length `ch` is the step of length `h` of the top of mass
/// `c² m`, and the law gains `2m ∂x₊/∂m`, the step's exact derivative in its mass
/// ([`Integrator::step_linearized_with_parameters`], the same implicit function theorem).
/// `∂x_K/∂h` is formed only where `with_time` asks for it (the minimum time).
pub(crate) fn shoot(
    plant: Plant,
    settings: StepSettings,
    start: (SO3, Vector3<f64>),
    target: (SO3, Vector3<f64>),
    inputs: &[Vector3<f64>],
    per_step: usize,
    with_time: bool,
) -> Result<Shot, OptimalError> {
    // The attitude's and the rates' miss at the last state.
    let miss = |last: &State| {
        let rotation = last.configuration.inverse().compose(&target.0).log();
        let rates = target.1 - last.velocity;
        DVector::from_iterator(6, rotation.iter().chain(rates.iter()).copied())
    };
    match plant {
        Plant::Body { body, disturbance } => {
            let it = Integrator::new(body, settings, start.0, start.1)?;
            // The mass that multiplies the potential.
            let potential = match body {
                BuiltInSo3::Top(top) if with_time && top.mass_times_gravity() != 0.0 => {
                    Some((top.mass(), "mass"))
                }
                _ => None,
            };
            let plan = Plan {
                per_step,
                offset: 0,
                potential,
                rows: vec![0, 1, 2, 3, 4, 5],
                with_time,
                attitudes: false,
                disturbance: torque_entries(disturbance),
            };
            shoot_with(it, inputs, plan, |s| (*s, None), miss)
        }
        Plant::Wheels {
            craft,
            speeds,
            disturbance,
        } => {
            let (g, xi) = wheel_start(start, speeds);
            let it = Integrator::new(craft, settings, g, xi)?;
            let plan = Plan {
                per_step,
                offset: 3,
                potential: None,
                rows: vec![0, 1, 2, 6, 7, 8],
                with_time,
                attitudes: false,
                disturbance: torque_entries(disturbance),
            };
            let observe = |s: &State<BodyWheels<f64, 3>, 6>| {
                let state = State {
                    time: s.time,
                    configuration: s.configuration.attitude,
                    momentum: s.momentum.fixed_rows::<3>(0).into_owned(),
                    velocity: s.velocity.fixed_rows::<3>(0).into_owned(),
                };
                (state, Some(s.velocity.fixed_rows::<3>(3).into_owned()))
            };
            shoot_with(it, inputs, plan, observe, miss)
        }
    }
}

/// The run of a body in space ([`BuiltInSe3`]) from the pose and body velocity `start`
/// under the body wrenches `inputs` (`per_step` a step, as in [`shoot`]), against
/// `target`: the miss is `(log(R_Kᵀ R_f), x_f − x_K, Ω_f − Ω_K, ẋ_f − ẋ_K)`, the attitude
/// and the rates as on SO(3), the position and its velocity in the world frame, and the
/// sensitivity's rows in the same coordinates ([`world_coordinates`] from the
/// linearisation's native `g = ḡ exp(θ)`, `ξ = ξ̄ + ω`). [`Wants`] says whether the
/// attitudes' derivatives at the Gauss points are kept ([`Shot::point_attitudes`])
/// and whether `∂x_K/∂h` is formed by [`shoot`]'s time scaling: the free body's kinetic
/// energy is quadratic in its body velocity, and the orbiting body's MacCullagh potential
/// is linear in `μ`, so that (as the heavy top's in its mass) its step of length `ch` is the
/// step of length `h` about a point mass of `c²μ` and the law gains `2μ ∂x₊/∂μ`.
///
/// Why the world frame: a body-frame velocity compares the target's and the run's in two
/// frames, so its miss turns with the attitude, by `|ẋ|` per radian: an orbiting body's
/// 7.6 km/s makes that curvature, times the velocity's multipliers, the whole of the
/// Lagrangian's Hessian, and the Gauss–Newton iteration, which leaves it out, diverge. In
/// the world frame the centre of mass's rows do not turn with the attitude.
pub(crate) fn shoot_motion(
    plant: SpacePlant,
    settings: StepSettings,
    start: (SE3, Vector6<f64>),
    target: (SE3, Vector6<f64>),
    inputs: &[Vector6<f64>],
    per_step: usize,
    wants: Wants,
) -> Result<Shot<State<SE3, 6>>, OptimalError> {
    let Wants { attitudes, time } = wants;
    let SpacePlant { body, disturbance } = plant;
    let it = Integrator::new(body, settings, start.0, start.1)?;
    // The gravitational parameter that multiplies the potential.
    let potential = match body {
        BuiltInSe3::Orbit(orbit) if time && orbit.gravitational_parameter() != 0.0 => {
            Some((orbit.gravitational_parameter(), "mu"))
        }
        _ => None,
    };
    let plan = Plan {
        per_step,
        offset: 0,
        potential,
        rows: (0..12).collect(),
        with_time: time,
        // Where the manoeuvre's subproblem measures the force in the world frame
        // (`crate::motion`), which reads them.
        attitudes,
        disturbance,
    };
    let world_velocity = |g: &SE3, xi: &Vector6<f64>| g.rotation().matrix() * xi.fixed_rows::<3>(3);
    let target_velocity = world_velocity(&target.0, &target.1);
    let miss = |last: &State<SE3, 6>| {
        let g = &last.configuration;
        let attitude = g.rotation().inverse().compose(target.0.rotation()).log();
        let position = target.0.translation() - g.translation();
        let rates = target.1.fixed_rows::<3>(0) - last.velocity.fixed_rows::<3>(0);
        let velocity = target_velocity - world_velocity(g, &last.velocity);
        DVector::from_iterator(
            12,
            [attitude, position, rates, velocity]
                .iter()
                .flat_map(|v| v.iter().copied()),
        )
    };
    let mut shot = shoot_with(it, inputs, plan, |s| (*s, None), miss)?;
    let last = &shot.states[shot.states.len() - 1];
    let world = world_coordinates(&last.configuration, &last.velocity);
    shot.sensitivity = &world * &shot.sensitivity;
    shot.terminal = &world * &shot.terminal;
    if time {
        shot.time_sensitivity = &world * &shot.time_sensitivity;
    }
    Ok(shot)
}

/// What a manoeuvre's steps integrate: a body in space under a constant body wrench
/// `disturbance = (τ, f)` beside the inputs (zero for none).
#[derive(Debug, Clone, Copy)]
pub(crate) struct SpacePlant {
    pub body: BuiltInSe3,
    pub disturbance: Vector6<f64>,
}

/// What a run of [`shoot_motion`] forms beyond its states, miss and sensitivity.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Wants {
    /// The attitudes' derivatives at the Gauss points ([`Shot::point_attitudes`]).
    pub attitudes: bool,
    /// `∂x_K/∂h` ([`Shot::time_sensitivity`]).
    pub time: bool,
}

/// How a run's inputs enter its integrator and what of its state the problem sees.
struct Plan {
    /// Inputs a step: one held over it, or one at each Gauss point.
    per_step: usize,
    /// Where the inputs enter the system's input (0: a body torque or wrench; 3: a
    /// gyrostat's motor torques).
    offset: usize,
    /// The parameter that multiplies the potential and its name among the linearisation's
    /// parameters, for `∂x₊/∂h`: the heavy top's mass, the orbiting body's `mu`.
    potential: Option<(f64, &'static str)>,
    /// The observed rows of the linearisation's state ([`Shot`]).
    rows: Vec<usize>,
    /// Whether to form `∂x_K/∂h` (else [`Shot::time_sensitivity`] is zero).
    with_time: bool,
    /// Whether to keep the attitudes' derivatives at the Gauss points
    /// ([`Shot::point_attitudes`]).
    attitudes: bool,
    /// A constant disturbance added to every input's first entries (a body torque on
    /// SO(3) and for a gyrostat, whose motor entries it leaves at zero; a body wrench
    /// `(τ, f)` on SE(3)); zero for none.
    disturbance: Vector6<f64>,
}

/// [`shoot`] for one integrator, inputs of `M` entries: `observe` reads the recorded
/// state of a state (and a gyrostat's wheel rates), `miss` the terminal miss of the last
/// recorded state.
fn shoot_with<S, C, St, const D: usize, const M: usize>(
    mut it: Integrator<S, C, D>,
    inputs: &[SVector<f64, M>],
    plan: Plan,
    observe: impl Fn(&State<ElementOf<S, D>, D>) -> (St, Option<Vector3<f64>>),
    miss: impl Fn(&St) -> DVector<f64>,
) -> Result<Shot<St>, OptimalError>
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
{
    let Plan {
        per_step,
        offset,
        potential,
        rows,
        with_time,
        attitudes,
        disturbance,
    } = plan;
    let h = it.settings().h();
    let disturbed = disturbance != Vector6::zeros();
    // The entries the disturbance reaches (all six, or the group's three).
    let reach = D.min(6);
    let widen = |u: &SVector<f64, M>| {
        let mut full = SVector::<f64, D>::zeros();
        full.fixed_rows_mut::<M>(offset).copy_from(u);
        if disturbed {
            for (entry, d) in full.iter_mut().zip(disturbance.iter()) {
                *entry += d;
            }
        }
        full
    };
    let record =
        |it: &Integrator<S, C, D>, states: &mut Vec<St>, speeds: &mut Vec<Vector3<f64>>| {
            let (state, wheels) = observe(it.state());
            states.push(state);
            speeds.extend(wheels);
        };
    let (mut states, mut wheel_speeds) = (Vec::new(), Vec::new());
    record(&it, &mut states, &mut wheel_speeds);
    let k_steps = inputs.len() / per_step;
    let mut a = Vec::with_capacity(k_steps);
    let mut b = Vec::with_capacity(k_steps);
    let mut d = Vec::with_capacity(k_steps);
    let mut points = Vec::new();
    for step_inputs in inputs.chunks(per_step) {
        let velocity = it.state().velocity;
        if per_step == 1 {
            it.set_input(widen(&step_inputs[0]))?;
        } else {
            let wide: Vec<SVector<f64, D>> = step_inputs.iter().map(widen).collect();
            it.set_input_at_points(&wide)?;
        }
        let step = if potential.is_some() {
            it.step_linearized_with_parameters()?
        } else {
            it.step_linearized()?
        };
        let ak = step.a(Coordinates::Velocity).clone();
        let bk: Vec<DMatrix<f64>> = match step.b_points(Coordinates::Velocity) {
            Some(points) => points
                .iter()
                .map(|p| p.columns(offset, M).into_owned())
                .collect(),
            None => vec![step
                .b(Coordinates::Velocity)
                .columns(offset, M)
                .into_owned()],
        };
        if attitudes {
            // The rotation's rows; the start's 2D columns, then each input's M entries.
            let columns: Vec<usize> = (0..2 * D)
                .chain((0..per_step).flat_map(|i| (0..M).map(move |c| 2 * D + D * i + offset + c)))
                .collect();
            points.push(
                step.point_configurations(Coordinates::Velocity)
                    .iter()
                    .map(|p| p.rows(0, 3).select_columns(&columns))
                    .collect(),
            );
        }
        if !with_time {
            a.push(ak);
            b.push(bk);
            record(&it, &mut states, &mut wheel_speeds);
            continue;
        }
        let end = it.state().velocity;
        let mut dk = ak.view((0, D), (2 * D, D)) * velocity;
        for (bj, u) in bk.iter().zip(step_inputs) {
            dk += 2.0 * (bj * u);
        }
        if disturbed {
            // The disturbance is an input too, the same at every point: its columns of the
            // step's `B`, the derivative in an input added at every point (the points'
            // `B_j` sum to it).
            let b = step.b(Coordinates::Velocity);
            dk += 2.0 * (b.columns(0, reach) * disturbance.rows(0, reach));
        }
        for i in 0..D {
            dk[D + i] -= end[i];
        }
        if let (Some((value, name)), Some(p)) = (potential, step.p(Coordinates::Velocity)) {
            let column = step.parameter_names().iter().position(|n| n == name);
            dk += p.column(column.expect("the system's parameters name its potential's"))
                * (2.0 * value);
        }
        d.push(dk / h);
        a.push(ak);
        b.push(bk);
        record(&it, &mut states, &mut wheel_speeds);
    }
    // M_kj = A_{K−1} ⋯ A_{k+1} B_kj and ∂x_K/∂h = Σ_k A_{K−1} ⋯ A_{k+1} d_k, chained
    // backwards in the plant's state, then read in the observed rows.
    let columns = M * per_step;
    let mut full = DMatrix::<f64>::zeros(2 * D, columns * k_steps);
    let mut time_full = DMatrix::<f64>::zeros(2 * D, 1);
    let mut chain = DMatrix::<f64>::identity(2 * D, 2 * D);
    for k in (0..k_steps).rev() {
        for (j, bj) in b[k].iter().enumerate() {
            full.view_mut((0, columns * k + M * j), (2 * D, M))
                .copy_from(&(&chain * bj));
        }
        if let Some(dk) = d.get(k) {
            time_full += &chain * dk;
        }
        chain = &chain * &a[k];
    }
    let miss = miss(&states[k_steps]);
    let sensitivity = full.select_rows(&rows);
    let terminal = DMatrix::<f64>::identity(2 * D, 2 * D).select_rows(&rows);
    let time_sensitivity = time_full.select_rows(&rows).column(0).into_owned();
    Ok(Shot {
        states,
        wheel_speeds,
        sensitivity,
        time_sensitivity,
        miss,
        terminal,
        rows,
        width: M,
        a,
        b,
        points,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use lgsvi_mechanics::Inertia;

    /// `∂x_K/∂h` from the time scaling against central differences of whole runs, for a
    /// free body, a heavy top (the law's mass term) and a gyrostat with spinning wheels,
    /// with torques held over each step and with torques at the Gauss points: with
    /// `δ = 1e-4 h` the difference's truncation error is `~δ² |x‴| ≈ 1e-8` relative and
    /// its rounding `~1e-16/δ·|x| ≈ 1e-11`, so they agree to about 1e-7 relative.
    #[test]
    fn the_time_derivative_matches_central_differences() {
        let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap();
        let top = lgsvi_mechanics::HeavyTop::new(
            inertia,
            2.0,
            1.5,
            Vector3::new(0.1, -0.2, 1.0),
            Vector3::new(0.3, 0.0, 1.0),
        )
        .unwrap();
        let craft = Gyrostat::new(
            inertia.matrix(),
            [Vector3::x(), Vector3::y(), Vector3::z()],
            [0.05; 3],
        )
        .unwrap();
        let plants = |disturbance: Vector3<f64>| {
            [
                (
                    "free body",
                    Plant::Body {
                        body: BuiltInSo3::Free(lgsvi_mechanics::RigidBody::new(inertia)),
                        disturbance,
                    },
                ),
                (
                    "heavy top",
                    Plant::Body {
                        body: BuiltInSo3::Top(top),
                        disturbance,
                    },
                ),
                (
                    "gyrostat",
                    Plant::Wheels {
                        craft,
                        speeds: Vector3::new(3.0, -2.0, 1.0),
                        disturbance,
                    },
                ),
            ]
        };
        let start = (
            SO3::exp(&Vector3::new(0.2, -0.4, 0.1)),
            Vector3::new(0.3, -0.2, 0.5),
        );
        let target = (SO3::identity(), Vector3::zeros());
        let h = 0.4;
        // Without a disturbance, and with one (the law's input terms then hold its
        // columns of the input Jacobians too).
        let disturbances = [Vector3::zeros(), Vector3::new(0.05, -0.1, 0.08)];
        for (disturbance, (name, plant)) in disturbances
            .into_iter()
            .flat_map(|d| plants(d).map(|p| (d, p)))
        {
            let points = plant
                .quadrature(StepSettings::new(h, 8).unwrap(), start)
                .unwrap()
                .0
                .len();
            for per_step in [1, points] {
                let inputs: Vec<Vector3<f64>> = (0..6 * per_step)
                    .map(|k| {
                        let t = k as f64 / per_step as f64;
                        Vector3::new(0.1 * t, -0.2, 0.05 * t.sin())
                    })
                    .collect();
                let at = |h: f64| {
                    shoot(
                        plant,
                        StepSettings::new(h, 8).unwrap(),
                        start,
                        target,
                        &inputs,
                        per_step,
                        true,
                    )
                    .unwrap()
                };
                let shot = at(h);
                let delta = 1e-4 * h;
                let (plus, minus) = (at(h + delta), at(h - delta));
                let (p, m) = (plus.states[6], minus.states[6]);
                let theta =
                    m.configuration.inverse().compose(&p.configuration).log() / (2.0 * delta);
                let omega = (p.velocity - m.velocity) / (2.0 * delta);
                let difference =
                    DVector::from_iterator(6, theta.iter().chain(omega.iter()).copied());
                let error = (&shot.time_sensitivity - &difference).amax() / difference.amax();
                assert!(
                    error < 1e-7,
                    "{name}, {per_step} inputs a step, disturbance {disturbance:?}: {error:e}"
                );
            }
        }
    }

    /// The same law on SE(3): `∂x_K/∂h` of the free body in space and of the orbiting body
    /// (the law's `μ` term), in the world-frame coordinates of the miss, against central
    /// differences of whole runs (the bound as above), with wrenches held over each step
    /// and at the Gauss points, without and with a disturbance wrench.
    #[test]
    fn the_time_derivative_in_space_matches_central_differences() {
        let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap();
        for body in [
            BuiltInSe3::Free(lgsvi_mechanics::FreeBody::new(inertia, 7.0).unwrap()),
            BuiltInSe3::Orbit(lgsvi_mechanics::OrbitingBody::new(inertia, 7.0, 3.0).unwrap()),
        ] {
            for disturbance in [
                Vector6::zeros(),
                Vector6::new(0.05, -0.1, 0.08, 0.2, 0.1, -0.3),
            ] {
                time_derivative_in_space(SpacePlant { body, disturbance });
            }
        }
    }

    fn time_derivative_in_space(plant: SpacePlant) {
        let body = plant.body;
        let start = (
            SE3::new(
                SO3::exp(&Vector3::new(0.2, -0.4, 0.1)),
                Vector3::new(4.0, -2.0, 1.0),
            ),
            Vector6::new(0.3, -0.2, 0.5, 0.4, 0.1, -0.3),
        );
        let target = (SE3::identity(), Vector6::zeros());
        let h = 0.4;
        let points = Integrator::new(body, StepSettings::new(h, 8).unwrap(), start.0, start.1)
            .unwrap()
            .quadrature_nodes()
            .len();
        for per_step in [1, points] {
            let inputs: Vec<Vector6<f64>> = (0..6 * per_step)
                .map(|k| {
                    let t = k as f64 / per_step as f64;
                    Vector6::new(0.1 * t, -0.2, 0.05 * t.sin(), 0.3, -0.1 * t, 0.2 * t.cos())
                })
                .collect();
            let wants = Wants {
                attitudes: false,
                time: true,
            };
            let at = |h: f64| {
                let settings = StepSettings::new(h, 8).unwrap();
                shoot_motion(plant, settings, start, target, &inputs, per_step, wants).unwrap()
            };
            let shot = at(h);
            let delta = 1e-4 * h;
            let (plus, minus) = (at(h + delta), at(h - delta));
            let (p, m) = (plus.states[6], minus.states[6]);
            let (gp, gm) = (p.configuration, m.configuration);
            let world = |s: &State<SE3, 6>| {
                s.configuration.rotation().matrix() * s.velocity.fixed_rows::<3>(3)
            };
            let parts = [
                gm.rotation().inverse().compose(gp.rotation()).log(),
                gp.translation() - gm.translation(),
                (p.velocity - m.velocity).fixed_rows::<3>(0).into_owned(),
                world(&p) - world(&m),
            ];
            let difference = DVector::from_iterator(
                12,
                parts
                    .iter()
                    .flat_map(|v| v.iter().map(|x| x / (2.0 * delta))),
            );
            let error = (&shot.time_sensitivity - &difference).amax() / difference.amax();
            assert!(
                error < 1e-7,
                "{plant:?}, {per_step} wrenches a step: {error:e}"
            );
        }
    }
}
