//! One run of the integrator under given torques: its states, the terminal miss, and the
//! terminal state's exact sensitivity to every torque and to the common step length.

use crate::OptimalError;
use lgsvi_mechanics::built_in::BuiltInSo3;
use lgsvi_mechanics::group::GroupChart;
use lgsvi_mechanics::gyrostat::{BodyWheels, Gyrostat};
use lgsvi_mechanics::lie::{LieGroup, SO3};
use lgsvi_mechanics::linearization::Coordinates;
use lgsvi_mechanics::system::ElementOf;
use lgsvi_mechanics::{Integrator, State, StepSettings, System};
use nalgebra::{DMatrix, DVector, SVector, Vector3};

/// What the slew's steps integrate: a rigid body or heavy top on SO(3) driven by a body
/// torque, or a spacecraft with three reaction wheels (SO(3) × ℝ³) driven by the wheels'
/// motor torques, its wheels starting at the given rates (relative to the body).
#[derive(Debug, Clone, Copy)]
pub(crate) enum Plant {
    Body(BuiltInSo3),
    Wheels(Gyrostat<3>, Vector3<f64>),
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
            Plant::Body(body) => {
                let it = Integrator::new(body, settings, start.0, start.1)?;
                (it.quadrature_nodes(), it.quadrature_weights())
            }
            Plant::Wheels(craft, speeds) => {
                let (g, xi) = wheel_start(start, speeds);
                let it = Integrator::new(craft, settings, g, xi)?;
                (it.quadrature_nodes(), it.quadrature_weights())
            }
        })
    }
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

/// One run of the torques: its states, the terminal state's sensitivity and miss.
pub(crate) struct Shot {
    /// `x_0 … x_K`: attitude, body rates and (for a gyrostat, the total angular momentum
    /// in the body frame) body momentum.
    pub states: Vec<State>,
    /// With reaction wheels, their rates `φ̇` at `x_0 … x_K`; empty otherwise.
    pub wheel_speeds: Vec<Vector3<f64>>,
    /// `M = ∂x_K/∂u` (`6 × 3K` per input of a step) in the body-frame coordinates `(θ, ω)`.
    pub sensitivity: DMatrix<f64>,
    /// `∂x_K/∂h` (6), the step length shared by every step.
    pub time_sensitivity: DVector<f64>,
    /// `e = (log(R_Kᵀ R_f), Ω_f − Ω_K)`.
    pub miss: DVector<f64>,
    /// The dimension `D` of the plant's algebra: its linearisation's state is
    /// `(θ, ω) ∈ ℝ^{2D}`, whose rows `0..3` and `D..D + 3` are the attitude and the body
    /// rates.
    dimension: usize,
    /// Each step's `A_k` and input Jacobians `B_kj` (velocity coordinates, the torques'
    /// three columns).
    a: Vec<DMatrix<f64>>,
    b: Vec<Vec<DMatrix<f64>>>,
}

impl Shot {
    /// The rows of the attitude and the body rates in the plant's state.
    fn observed(&self, full: &DMatrix<f64>) -> DMatrix<f64> {
        let d = self.dimension;
        DMatrix::from_fn(6, full.ncols(), |i, j| {
            full[(if i < 3 { i } else { d + i - 3 }, j)]
        })
    }

    /// `∂x_k/∂u` for `k = 1 … K` (`6 × n` each, attitude and rates), chained forwards:
    /// `S_{k+1} = A_k S_k + [B_kj in step k's columns]`.
    pub fn state_sensitivities(&self) -> Vec<DMatrix<f64>> {
        let columns = self.sensitivity.ncols();
        let per_step = columns / self.a.len().max(1);
        let mut out = Vec::with_capacity(self.a.len());
        let mut s = DMatrix::<f64>::zeros(2 * self.dimension, columns);
        for (k, (a, b)) in self.a.iter().zip(&self.b).enumerate() {
            s = a * &s;
            for (j, bj) in b.iter().enumerate() {
                s.view_mut((0, per_step * k + 3 * j), (2 * self.dimension, 3))
                    .copy_from(bj);
            }
            out.push(self.observed(&s));
        }
        out
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
/// with `A_ω` the columns of `A` in the start's rates; `optimal/tests/free_time.rs`
/// checks both the scaling and this derivative against finite differences. The law is the
/// free body's, and a gyrostat's, whose kinetic energy is quadratic in `(Ω, φ̇)` too. A
/// potential does not scale so: the heavy top's action over `ch`,
/// `∫ (½ΩᵀJΩ + m g dᵀRρ) dt`, is `1/c` times the action over `h` of the top of mass `c²m`
/// (`t = cs`), so its step of length `ch` is the step of length `h` of the top of mass
/// `c² m`, and the law gains `2m ∂x₊/∂m`, the step's exact derivative in its mass
/// ([`Integrator::step_linearized_with_parameters`], the same implicit function theorem);
/// it is formed where `with_time` asks for `∂x_K/∂h`.
pub(crate) fn shoot(
    plant: Plant,
    settings: StepSettings,
    start: (SO3, Vector3<f64>),
    target: (SO3, Vector3<f64>),
    inputs: &[Vector3<f64>],
    per_step: usize,
    with_time: bool,
) -> Result<Shot, OptimalError> {
    match plant {
        Plant::Body(body) => {
            let it = Integrator::new(body, settings, start.0, start.1)?;
            // The mass that multiplies the potential.
            let potential = match body {
                BuiltInSo3::Top(top) if with_time && top.mass_times_gravity() != 0.0 => {
                    Some(top.mass())
                }
                _ => None,
            };
            shoot_with(it, target, inputs, per_step, 0, potential, |s| (*s, None))
        }
        Plant::Wheels(craft, speeds) => {
            let (g, xi) = wheel_start(start, speeds);
            let it = Integrator::new(craft, settings, g, xi)?;
            shoot_with(it, target, inputs, per_step, 3, None, |s| {
                let state = State {
                    time: s.time,
                    configuration: s.configuration.attitude,
                    momentum: s.momentum.fixed_rows::<3>(0).into_owned(),
                    velocity: s.velocity.fixed_rows::<3>(0).into_owned(),
                };
                (state, Some(s.velocity.fixed_rows::<3>(3).into_owned()))
            })
        }
    }
}

/// [`shoot`] for one integrator: the torques enter its input at `offset` (0: a body
/// torque; 3: a gyrostat's motor torques), `potential` is the value of a mass that
/// multiplies the potential (the heavy top's, for `∂x₊/∂h`; its parameter column is the
/// one the linearisation names "mass"), and `observe`
/// reads the attitude, rates and momentum of a state (and a gyrostat's wheel rates).
#[allow(clippy::too_many_arguments)]
fn shoot_with<S, C, const D: usize>(
    mut it: Integrator<S, C, D>,
    target: (SO3, Vector3<f64>),
    inputs: &[Vector3<f64>],
    per_step: usize,
    offset: usize,
    potential: Option<f64>,
    observe: impl Fn(&State<ElementOf<S, D>, D>) -> (State, Option<Vector3<f64>>),
) -> Result<Shot, OptimalError>
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
{
    let h = it.settings().h();
    let widen = |u: &Vector3<f64>| {
        let mut full = SVector::<f64, D>::zeros();
        full.fixed_rows_mut::<3>(offset).copy_from(u);
        full
    };
    let record =
        |it: &Integrator<S, C, D>, states: &mut Vec<State>, speeds: &mut Vec<Vector3<f64>>| {
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
                .map(|p| p.columns(offset, 3).into_owned())
                .collect(),
            None => vec![step
                .b(Coordinates::Velocity)
                .columns(offset, 3)
                .into_owned()],
        };
        let end = it.state().velocity;
        let mut dk = ak.view((0, D), (2 * D, D)) * velocity;
        for (bj, u) in bk.iter().zip(step_inputs) {
            dk += 2.0 * (bj * u);
        }
        for i in 0..D {
            dk[D + i] -= end[i];
        }
        if let (Some(mass), Some(p)) = (potential, step.p(Coordinates::Velocity)) {
            let column = step
                .parameter_names()
                .iter()
                .position(|name| name == "mass");
            dk += p.column(column.expect("a heavy top's parameters name its mass")) * (2.0 * mass);
        }
        d.push(dk / h);
        a.push(ak);
        b.push(bk);
        record(&it, &mut states, &mut wheel_speeds);
    }
    // M_kj = A_{K−1} ⋯ A_{k+1} B_kj and ∂x_K/∂h = Σ_k A_{K−1} ⋯ A_{k+1} d_k, chained
    // backwards in the plant's state, then read in the attitude and rates.
    let columns = 3 * per_step;
    let mut full = DMatrix::<f64>::zeros(2 * D, columns * k_steps);
    let mut time_full = DMatrix::<f64>::zeros(2 * D, 1);
    let mut chain = DMatrix::<f64>::identity(2 * D, 2 * D);
    for k in (0..k_steps).rev() {
        for (j, bj) in b[k].iter().enumerate() {
            full.view_mut((0, columns * k + 3 * j), (2 * D, 3))
                .copy_from(&(&chain * bj));
        }
        time_full += &chain * &d[k];
        chain = &chain * &a[k];
    }
    let last = states[k_steps];
    let rotation = last.configuration.inverse().compose(&target.0).log();
    let rates = target.1 - last.velocity;
    let miss = DVector::from_iterator(6, rotation.iter().chain(rates.iter()).copied());
    let mut shot = Shot {
        states,
        wheel_speeds,
        sensitivity: DMatrix::zeros(0, 0),
        time_sensitivity: DVector::zeros(0),
        miss,
        dimension: D,
        a,
        b,
    };
    shot.sensitivity = shot.observed(&full);
    shot.time_sensitivity = shot.observed(&time_full).column(0).into_owned();
    Ok(shot)
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
        let plants = [
            (
                "free body",
                Plant::Body(BuiltInSo3::Free(lgsvi_mechanics::RigidBody::new(inertia))),
            ),
            ("heavy top", Plant::Body(BuiltInSo3::Top(top))),
            (
                "gyrostat",
                Plant::Wheels(craft, Vector3::new(3.0, -2.0, 1.0)),
            ),
        ];
        let start = (
            SO3::exp(&Vector3::new(0.2, -0.4, 0.1)),
            Vector3::new(0.3, -0.2, 0.5),
        );
        let target = (SO3::identity(), Vector3::zeros());
        let h = 0.4;
        for (name, plant) in plants {
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
                assert!(error < 1e-7, "{name}, {per_step} inputs a step: {error:e}");
            }
        }
    }
}
