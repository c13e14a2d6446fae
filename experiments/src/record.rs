//! A run recorded for output: every `every`-th state of a run to its horizon, with its
//! energy, the work of its forces, its translation or wheels, and the integrator's
//! statistics and error accounting — what `lgsvi simulate` writes as JSON or CSV
//! (`lgsvi_reports::trajectory`), for any group the command line runs.
//!
//! Every state is checked on the way (a state or invariant that overflows stops the run
//! with [`ExperimentError::Overflow`], naming the step and the quantity), the recorded ones
//! are kept. The run goes through the one driving loop ([`Stepper::drive`], of an
//! integrator or of a [`CheckedIntegrator`] beside its companion); the integration alone is
//! timed.
//!
//! ```
//! use lgsvi_experiments::record::{record, Recording};
//! use lgsvi_mechanics::lie::SO3;
//! use lgsvi_mechanics::{Inertia, Integrator, RigidBody, StepSettings};
//! use nalgebra::Vector3;
//!
//! # fn main() -> Result<(), lgsvi_experiments::ExperimentError> {
//! let body = RigidBody::new(Inertia::from_principal_moments([3.3, 2.5, 3.4])?);
//! let mut integrator =
//!     Integrator::new(body, StepSettings::new(0.5, 8)?, SO3::identity(), Vector3::new(-2.0, 1.9, -1.0))?;
//! let run: Recording = record(&mut integrator, 10.0, 4, &mut |_| {})?;
//! assert_eq!(run.steps, 20);
//! assert_eq!(run.states.len(), 6); // t = 0, 2, 4, 6, 8, 10
//! assert!((run.energies[5] - run.energies[0]).abs() < 1e-12);
//! # Ok(())
//! # }
//! ```

use crate::control::SampledLaw;
use crate::error::ExperimentError;
use crate::stop::Watch;
use lgsvi_mechanics::control::GroupLog;
use lgsvi_mechanics::events::Events;
use lgsvi_mechanics::exact::FreeRigidBodyExact;
use lgsvi_mechanics::group::{GroupChart, Rotations};
use lgsvi_mechanics::gyrostat::BodyWheels;
use lgsvi_mechanics::lie::{SE3, SO3};
use lgsvi_mechanics::state::body_momentum;
use lgsvi_mechanics::stepper::each;
use lgsvi_mechanics::stepper::CheckReport;
use lgsvi_mechanics::system::ElementOf;
use lgsvi_mechanics::tolerance::CheckedIntegrator;
use lgsvi_mechanics::{Integrator, State, StepSettings, Stepper, System};
use nalgebra::{SVector, Vector3};
use std::ops::ControlFlow;
use std::time::{Duration, Instant};

/// A recorded run. The attitude columns are SO(3)'s for every group: for a body in space
/// its rotational part (with [`MotionRecord`] beside it), for a gyrostat the body's
/// attitude, rate and total angular momentum (with [`WheelRecord`] beside it).
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// The recorded states' SO(3) columns (`R`, `Ω`, `μ`).
    pub states: Vec<State>,
    /// The Newton iterations of the step that reached each recorded state (0 for the
    /// initial state and an exact solution).
    pub newton_iterations: Vec<usize>,
    /// The energy of each recorded state.
    pub energies: Vec<f64>,
    /// The work of the forces and inputs up to each recorded state, for a forced run.
    pub work: Option<Vec<f64>>,
    /// Position, velocity and spatial momenta of each recorded state, for a body in space.
    pub motion: Option<Vec<MotionRecord>>,
    /// The wheels of each recorded state, for a gyrostat.
    pub wheels: Option<Vec<WheelRecord>>,
    /// The integration's wall time (with its companion's for a checked run; summed over
    /// the runs of a tolerance-driven one), without the checks and the recording.
    pub wall_time_s: f64,
    /// Steps taken.
    pub steps: usize,
    /// Newton iterations over the run.
    pub newton_iterations_total: usize,
    /// The most Newton iterations of one step.
    pub max_newton_iterations: usize,
    /// Newton matrices assembled and factored (the other iterations reused one).
    pub factorizations: usize,
    /// The integrator's error accounting (`None` for an exact solution).
    pub estimates: Option<Estimates>,
    /// Where a stop condition ended the run ([`record_until`]), `None` for a run to its
    /// horizon.
    pub stopped: Option<Stopped>,
    /// Where a settling condition ([`Watch::settle`]) holds from to the run's end, `None`
    /// for a run without one.
    pub settled: Option<Settled>,
}

/// Where a stop condition ([`crate::stop::StopWhen`]) ended a run: the crossing's time and
/// state (on the step's curve, refined by the method's own steps). The recording's last
/// state is the end of the step that holds it.
#[derive(Debug, Clone, PartialEq)]
pub struct Stopped {
    /// The condition, as given (`omega_3<0.1`).
    pub condition: String,
    /// The crossing's time.
    pub time: f64,
    /// The state's SO(3) columns there.
    pub state: State,
    /// Its translation, for a body in space.
    pub motion: Option<MotionRecord>,
    /// Its wheels, for a gyrostat.
    pub wheels: Option<WheelRecord>,
}

/// A run's settling time under a settling condition ([`Watch::settle`]): the time from
/// which the condition holds to the run's last state.
#[derive(Debug, Clone, PartialEq)]
pub struct Settled {
    /// The condition, as given (`omega<0.001`).
    pub condition: String,
    /// The last crossing into the condition (on the step's curve, refined by the
    /// method's own steps), or the run's start where it holds throughout; `None` where it
    /// does not hold at the run's last state.
    pub time: Option<f64>,
}

impl Recording {
    /// Whether every column has one entry per recorded state (a recording made by
    /// [`record`] or [`record_exact`] always has; one assembled by hand may not): the
    /// writers of `lgsvi_reports::trajectory` refuse one that has not.
    pub fn is_consistent(&self) -> bool {
        let n = self.states.len();
        self.newton_iterations.len() == n
            && self.energies.len() == n
            && self.work.as_ref().is_none_or(|w| w.len() == n)
            && self.motion.as_ref().is_none_or(|m| m.len() == n)
            && self.wheels.as_ref().is_none_or(|w| {
                w.len() == n
                    && w.iter().all(|r| {
                        r.angles.len() == w[0].angles.len()
                            && r.speeds.len() == r.angles.len()
                            && r.momenta.len() == r.angles.len()
                    })
            })
    }
}

/// What a run's error estimates say.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimates {
    /// The sum of the local error estimates, or for a checked run the difference its
    /// companion measured at the end.
    pub global: f64,
    /// `(n, steps with n nodes)`, by increasing `n`.
    pub nodes: Vec<(usize, usize)>,
    /// Solves redone with more nodes (adaptive runs).
    pub rejected: usize,
    /// A checked run's measurement.
    pub check: Option<CheckReport>,
}

/// The translational part of a recorded state of a body in space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionRecord {
    /// Centre of mass `x`, world frame.
    pub position: Vector3<f64>,
    /// `ẋ`, world frame.
    pub velocity: Vector3<f64>,
    /// The spatial momentum `(RJΩ + x × mẋ, mẋ)`: angular momentum about the world
    /// origin and linear momentum.
    pub spatial_momentum: SVector<f64, 6>,
}

/// The wheels of a recorded gyrostat state.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelRecord {
    /// The wheel angles `φ_i` relative to the body.
    pub angles: Vec<f64>,
    /// Their rates `φ̇_i`.
    pub speeds: Vec<f64>,
    /// The wheels' axial momenta `p_i = I_i (a_iᵀΩ + φ̇_i)`.
    pub momenta: Vec<f64>,
}

/// How a state of a group is recorded: its SO(3) columns, and the translation or the
/// wheels beside them. Implemented for SO(3), SE(3) and the gyrostats' SO(3) × ℝᴷ
/// (`K = 1..=4`).
pub trait Columns<const D: usize>: Sized {
    /// The state's SO(3) columns and what goes beside them.
    fn columns(state: &State<Self, D>) -> (State, Option<MotionRecord>, Option<WheelRecord>);
}

impl Columns<3> for SO3 {
    fn columns(state: &State) -> (State, Option<MotionRecord>, Option<WheelRecord>) {
        (*state, None, None)
    }
}

/// The rotational part as the SO(3) columns, the translation beside them.
impl Columns<6> for SE3 {
    fn columns(s: &State<SE3, 6>) -> (State, Option<MotionRecord>, Option<WheelRecord>) {
        let motion = MotionRecord {
            position: s.position(),
            velocity: s.linear_velocity(),
            spatial_momentum: s.spatial_momentum(),
        };
        let rotation = State {
            time: s.time,
            configuration: *s.attitude(),
            momentum: s.momentum.fixed_rows::<3>(0).into_owned(),
            velocity: s.angular_velocity(),
        };
        (rotation, Some(motion), None)
    }
}

/// The body's attitude, rate and total angular momentum `h` as the SO(3) columns (the
/// spatial `Rh` is what the wheels conserve), the wheels beside them: the body momentum is
/// `(h, p)`, the wheels' axial momenta its last `K` entries as their rates are the
/// velocity's.
macro_rules! wheel_columns {
    ($($k:literal => $d:literal),*) => {$(
        impl Columns<$d> for BodyWheels<f64, $k> {
            fn columns(
                s: &State<Self, $d>,
            ) -> (State, Option<MotionRecord>, Option<WheelRecord>) {
                let rotation = State {
                    time: s.time,
                    configuration: s.configuration.attitude,
                    momentum: s.momentum.fixed_rows::<3>(0).into_owned(),
                    velocity: s.velocity.fixed_rows::<3>(0).into_owned(),
                };
                let wheels = WheelRecord {
                    angles: s.configuration.wheels.iter().copied().collect(),
                    speeds: s.velocity.iter().skip(3).copied().collect(),
                    momenta: s.momentum.iter().skip(3).copied().collect(),
                };
                (rotation, None, Some(wheels))
            }
        }
    )*};
}
wheel_columns!(1 => 4, 2 => 5, 3 => 6, 4 => 7);

/// Checks that a state's SO(3) columns and invariants are finite.
///
/// # Errors
/// [`ExperimentError::Overflow`] naming the first quantity that is not.
pub fn check_finite(step: usize, state: &State, energy: f64) -> Result<(), ExperimentError> {
    let pi = state.spatial_momentum();
    let quantities: [(&'static str, &[f64]); 6] = [
        ("attitude R", &state.attitude().to_row_major()),
        ("angular velocity Ω", state.velocity.as_slice()),
        ("body momentum μ", state.momentum.as_slice()),
        ("energy", &[energy]),
        ("Casimir |μ|²", &[state.casimir()]),
        ("spatial momentum Rμ", pi.as_slice()),
    ];
    for (quantity, values) in quantities {
        if values.iter().any(|x| !x.is_finite()) {
            return Err(ExperimentError::Overflow {
                step,
                time: state.time,
                quantity,
                values: format!("{values:?}"),
            });
        }
    }
    Ok(())
}

/// How often [`record`] reports progress, in steps.
pub const PROGRESS_EVERY: usize = 64;

/// Whether and how a companion checks a run ([`lgsvi_mechanics::tolerance::CheckedIntegrator`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Check {
    /// Unchecked: the estimated error is the sum of the steps' local estimates.
    None,
    /// A fixed run measured by its companion (the same steps with 2 more nodes).
    Measure,
    /// A tolerance-driven run accepted or refused by its check
    /// ([`lgsvi_mechanics::tolerance::ToleranceCheck`], [`record_to_tolerance`]).
    Tolerance(f64),
}

/// Runs `runner` to `t_end` (to the first step at or after it, [`Integrator::steps_until`]),
/// checking every state and recording the initial one, every
/// `every`-th (at least 1) and the last; `progress(k)` is told the steps taken every
/// [`PROGRESS_EVERY`] steps. The integration alone is timed (with its companion, for a
/// checked run): not the checks or the recording.
///
/// # Errors
/// A horizon that is not finite, lies before the start or needs too many steps, or a run
/// whose step may change ([`Integrator::steps_until`]); a failed step; a state that
/// overflows ([`ExperimentError::Overflow`]).
pub fn record<S, C, const D: usize>(
    runner: &mut impl Stepper<S, C, D>,
    t_end: f64,
    every: usize,
    progress: &mut dyn FnMut(usize),
) -> Result<Recording, ExperimentError>
where
    S: System<D> + Copy,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: Columns<D>,
{
    record_until(runner, t_end, every, &Watch::NOTHING, None, progress)
}

/// As [`record`], ending the run after the step in which `watch`'s stop condition is met
/// (the crossing located on the step's curve and refined by the method's steps,
/// [`lgsvi_mechanics::events`]): its time and state in [`Recording::stopped`], the step's
/// end recorded as the last state; with `watch`'s settling condition, its settling time
/// in [`Recording::settled`]. With `control`, its sampled law sets the body torque input
/// at every sampling instant from the run's start ([`SampledLaw::observer`]).
///
/// # Errors
/// As [`record`]; [`ExperimentError::Stop`] for a condition on a quantity the system
/// lacks; [`ExperimentError::Parameter`] for a controller whose period is not a whole
/// number of steps, or on a gyrostat (whose input is its wheels' motor torques).
pub fn record_until<S, C, const D: usize>(
    runner: &mut impl Stepper<S, C, D>,
    t_end: f64,
    every: usize,
    watch: &Watch,
    control: Option<&SampledLaw>,
    progress: &mut dyn FnMut(usize),
) -> Result<Recording, ExperimentError>
where
    S: System<D> + Copy,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: Columns<D>,
{
    let every = every.max(1);
    let steps = runner.integrator().steps_until(t_end)?;
    let system = *runner.integrator().system();
    // Forced: by the system's own force, or by an input (a gyrostat's motor torques, a
    // sampled controller's torques).
    let forced = system.is_forced()
        || control.is_some()
        || runner.integrator().input().iter().any(|&u| u != 0.0);
    let (_, motion, wheels) = ElementOf::<S, D>::columns(runner.integrator().state());
    let mut run = Recording {
        states: Vec::new(),
        newton_iterations: Vec::new(),
        energies: Vec::new(),
        work: forced.then(Vec::new),
        motion: motion.map(|_| Vec::new()),
        wheels: wheels.map(|_| Vec::new()),
        wall_time_s: 0.0,
        steps: 0,
        newton_iterations_total: 0,
        max_newton_iterations: 0,
        factorizations: 0,
        estimates: None,
        stopped: None,
        settled: None,
    };
    let (start, start_motion, start_wheels) =
        ElementOf::<S, D>::columns(runner.integrator().state());
    if control.is_some() && start_wheels.is_some() {
        return Err(crate::control::on_a_gyrostat());
    }
    let h = runner.integrator().settings().h();
    let mut sampler = control.map(|c| c.observer(h)).transpose()?;
    let r0 = start.configuration;
    let target = watch.target();
    watch.check(&start, start_motion.as_ref(), start_wheels.as_ref())?;
    // The stop condition's event first (index 0 where there is one), the settling one's
    // after it.
    let settle_event = usize::from(watch.stop.is_some());
    let mut events = Events::new(
        watch
            .conditions()
            .map(|(condition, settle)| {
                if settle {
                    condition.crossings(r0, target, ElementOf::<S, D>::columns)
                } else {
                    condition.event(r0, target, ElementOf::<S, D>::columns)
                }
            })
            .collect(),
    );
    let mut visit = |k: usize,
                     state: &State<ElementOf<S, D>, D>,
                     iterations: Option<usize>,
                     done: f64|
     -> Result<(), ExperimentError> {
        let energy = state.energy(&system);
        let (rotation, motion, wheels) = ElementOf::<S, D>::columns(state);
        check_finite(k, &rotation, energy)?;
        if let Some(motion) = &motion {
            let translation = [motion.position, motion.velocity];
            if translation.iter().any(|v| v.iter().any(|x| !x.is_finite())) {
                return Err(ExperimentError::Overflow {
                    step: k,
                    time: state.time,
                    quantity: "position x or velocity ẋ",
                    values: format!("{translation:?}"),
                });
            }
        }
        let Some(iterations) = iterations else {
            return Ok(());
        };
        run.states.push(rotation);
        run.newton_iterations.push(iterations);
        run.energies.push(energy);
        if let Some(work) = run.work.as_mut() {
            work.push(done);
        }
        if let Some(records) = run.motion.as_mut() {
            records.extend(motion);
        }
        if let Some(records) = run.wheels.as_mut() {
            records.extend(wheels);
        }
        Ok(())
    };
    visit(0, runner.integrator().state(), Some(0), 0.0)?;
    // The time between one observer call's end and the next call is a step's.
    let mut wall_time = Duration::ZERO;
    let mut since = Instant::now();
    let mut last = (0, 0, false);
    let mut observer = each(
        |integrator: &Integrator<S, C, D>, step: lgsvi_mechanics::stepper::StepInfo| {
            wall_time += since.elapsed();
            let k = step.index;
            let recorded = k.is_multiple_of(every) || step.last;
            last = (k, step.iterations, recorded);
            visit(
                k,
                integrator.state(),
                recorded.then_some(step.iterations),
                integrator.work_done(),
            )?;
            if k.is_multiple_of(PROGRESS_EVERY) {
                progress(k);
            }
            since = Instant::now();
            Ok::<_, ExperimentError>(ControlFlow::Continue(()))
        },
    );
    runner.drive(steps, &mut ((&mut observer, &mut events), &mut sampler))?;
    if events.stopped() {
        // The step that holds the crossing ends the recording.
        let (k, iterations, recorded) = last;
        if !recorded {
            let integrator = runner.integrator();
            visit(
                k,
                integrator.state(),
                Some(iterations),
                integrator.work_done(),
            )?;
        }
    }
    let hits = events.into_hits();
    let start_time = start.time;
    run.stopped = watch.stop.and_then(|stop| {
        let hit = hits.iter().find(|hit| hit.event == 0)?;
        let (state, motion, wheels) = ElementOf::<S, D>::columns(&State {
            time: hit.time,
            configuration: hit.configuration,
            momentum: body_momentum(&system, hit.time, &hit.configuration, &hit.velocity),
            velocity: hit.velocity,
        });
        Some(Stopped {
            condition: stop.to_string(),
            time: hit.time,
            state,
            motion,
            wheels,
        })
    });
    run.settled = watch.settle.map(|settle| {
        // The run's end: where a stop condition ended it (crossings past it are not
        // looked for), else its last state.
        let (last, motion, wheels) = match &run.stopped {
            Some(stopped) => (stopped.state, stopped.motion, stopped.wheels.clone()),
            None => ElementOf::<S, D>::columns(runner.integrator().state()),
        };
        let holds = settle
            .quantity
            .value(&last, motion.as_ref(), wheels.as_ref(), &r0, &target)
            .is_some_and(|value| settle.holds(value));
        let entered = hits
            .iter()
            .rev()
            .find(|hit| hit.event == settle_event)
            .map_or(start_time, |hit| hit.time);
        Settled {
            condition: settle.to_string(),
            time: holds.then_some(entered),
        }
    });
    let integrator = runner.integrator();
    let stats = integrator.statistics();
    let local_sum = integrator.estimated_global_error();
    let check = runner.check_report();
    run.estimates = Some(Estimates {
        global: check.map_or(local_sum, |c| c.difference),
        nodes: integrator.nodes_used().collect(),
        rejected: stats.rejected_steps,
        check,
    });
    run.wall_time_s = wall_time.as_secs_f64();
    run.steps = stats.steps;
    run.newton_iterations_total = stats.newton_iterations;
    run.max_newton_iterations = stats.max_newton_iterations;
    run.factorizations = stats.factorizations;
    Ok(run)
}

/// Runs to `t_end` with the integrator `make` builds from `settings`, beside its
/// companion, until the companion's measured error is within `tolerance`
/// ([`CheckedIntegrator::with_tolerance`]: the first run with `settings`, then up to two
/// with a tightened share per step). The recording's [`CheckReport`] says how many runs it
/// took; its wall time is theirs together.
///
/// # Errors
/// As [`record`]; [`lgsvi_mechanics::MechanicsError::ToleranceNotChecked`] (as
/// [`ExperimentError::Mechanics`]) when no run met the tolerance.
#[allow(clippy::too_many_arguments)]
pub fn record_to_tolerance<S, C, E, const D: usize>(
    make: impl Fn(StepSettings) -> Result<Integrator<S, C, D>, E>,
    settings: StepSettings,
    tolerance: f64,
    t_end: f64,
    every: usize,
    watch: &Watch,
    control: Option<&SampledLaw>,
    progress: &mut dyn FnMut(usize),
) -> Result<Recording, E>
where
    S: System<D> + Copy,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: Columns<D> + GroupLog<D>,
    E: From<ExperimentError> + From<lgsvi_mechanics::MechanicsError>,
{
    let mut runner = CheckedIntegrator::new(make(settings)?)?.with_tolerance(tolerance)?;
    let mut wall_time = 0.0;
    loop {
        let mut run =
            record_until(&mut runner, t_end, every, watch, control, progress).map_err(E::from)?;
        wall_time += run.wall_time_s;
        run.wall_time_s = wall_time;
        if runner.judge()? {
            return Ok(run);
        }
    }
}

/// Runs to `t_end` (or to where `stop` is met) with the integrators `make` builds from
/// `settings`, as `check` says:
/// unchecked, one run ([`record`]); beside its companion ([`Check::Measure`]); or until
/// [`lgsvi_mechanics::tolerance::ToleranceCheck`] accepts a run or refuses ([`Check::Tolerance`],
/// [`record_to_tolerance`]).
///
/// # Errors
/// [`record`]'s and [`record_to_tolerance`]'s.
#[allow(clippy::too_many_arguments)]
pub fn record_checked<S, C, const D: usize>(
    make: impl Fn(StepSettings) -> Result<Integrator<S, C, D>, lgsvi_mechanics::MechanicsError>,
    settings: StepSettings,
    check: Check,
    t_end: f64,
    every: usize,
    watch: &Watch,
    control: Option<&SampledLaw>,
    progress: &mut dyn FnMut(usize),
) -> Result<Recording, ExperimentError>
where
    S: System<D> + Copy,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: Columns<D> + GroupLog<D>,
{
    match check {
        Check::None => record_until(&mut make(settings)?, t_end, every, watch, control, progress),
        Check::Measure => {
            let mut runner = CheckedIntegrator::new(make(settings)?)?;
            record_until(&mut runner, t_end, every, watch, control, progress)
        }
        Check::Tolerance(tol) => {
            let make = |s| make(s).map_err(ExperimentError::from);
            record_to_tolerance(make, settings, tol, t_end, every, watch, control, progress)
        }
    }
}

/// The exact free-body solution recorded as [`record`] records a run of `steps` steps of
/// `h`: the initial state, every `every`-th step's time and the last; energies from
/// `system` (the free body whose solution `body` is).
///
/// # Errors
/// A time the solution cannot be evaluated at, or a state that overflows.
pub fn record_exact<S: System<3, Group = Rotations>>(
    body: &FreeRigidBodyExact,
    system: &S,
    h: f64,
    steps: usize,
    every: usize,
) -> Result<Recording, ExperimentError> {
    let every = every.max(1);
    let start = Instant::now();
    let mut states = Vec::new();
    for k in (0..=steps).filter(|k| k % every == 0 || *k == steps) {
        states.push(body.state(k as f64 * h)?);
    }
    let wall_time_s = start.elapsed().as_secs_f64();
    let energies: Vec<f64> = states.iter().map(|s| s.energy(system)).collect();
    for (state, energy) in states.iter().zip(&energies) {
        // The step the integrator would have reached at this time.
        check_finite((state.time / h).round() as usize, state, *energy)?;
    }
    Ok(Recording {
        newton_iterations: vec![0; states.len()],
        states,
        energies,
        work: None,
        motion: None,
        wheels: None,
        wall_time_s,
        steps: 0,
        newton_iterations_total: 0,
        max_newton_iterations: 0,
        factorizations: 0,
        estimates: None,
        stopped: None,
        settled: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use lgsvi_mechanics::{FreeBody, Inertia, RigidBody};

    fn body() -> (RigidBody, Inertia) {
        let inertia = Inertia::from_principal_moments([3.3, 2.5, 3.4]).unwrap();
        (RigidBody::new(inertia), inertia)
    }

    #[test]
    fn a_recording_keeps_what_run_returns_with_the_closed_form_energy() {
        let (system, inertia) = body();
        let omega = Vector3::new(-2.0, 1.9, -1.0);
        let make = || {
            Integrator::new(
                system,
                StepSettings::new(0.5, 8).unwrap(),
                SO3::identity(),
                omega,
            )
            .unwrap()
        };
        let expected = make().run(7, 3).unwrap();
        let run = record(&mut make(), 3.5, 3, &mut |_| {}).unwrap();
        // The states and iterations of `Integrator::run` (the Recorder's path), bit for bit.
        assert_eq!(run.states, expected.states);
        assert_eq!(run.newton_iterations, expected.newton_iterations);
        assert_eq!(run.steps, 7);
        assert!(run.work.is_none() && run.motion.is_none() && run.wheels.is_none());
        // E = ½ΩᵀJΩ of the initial velocity; the method conserves it to rounding over 7
        // steps (a few ε of E ≈ 16).
        let e0 = 0.5 * omega.dot(&(inertia.matrix() * omega));
        for e in &run.energies {
            assert!((e - e0).abs() < 1e-13 * e0, "{e} against {e0}");
        }
    }

    #[test]
    fn a_body_in_space_records_its_translation() {
        let (_, inertia) = body();
        let system = FreeBody::new(inertia, 2.0).unwrap();
        let start = SE3::new(SO3::identity(), Vector3::new(1.0, 0.0, 0.0));
        let velocity = SVector::<f64, 6>::from_column_slice(&[0.3, 0.1, -0.2, 0.1, -0.2, 0.05]);
        let mut it =
            Integrator::new(system, StepSettings::new(0.5, 6).unwrap(), start, velocity).unwrap();
        let run = record(&mut it, 2.0, 1, &mut |_| {}).unwrap();
        let motion = run.motion.as_ref().unwrap();
        assert_eq!(motion.len(), 5);
        // A free body's centre of mass moves uniformly: x(t) = x₀ + t ẋ₀ with ẋ₀ = R₀v₀, and
        // its linear momentum is m ẋ₀ throughout.
        let xdot = Vector3::new(0.1, -0.2, 0.05);
        for (m, s) in motion.iter().zip(&run.states) {
            let x = Vector3::new(1.0, 0.0, 0.0) + s.time * xdot;
            assert!(
                (m.position - x).amax() < 1e-14,
                "{} at t = {}",
                m.position,
                s.time
            );
            assert!((m.spatial_momentum.fixed_rows::<3>(3) - 2.0 * xdot).amax() < 1e-14);
        }
    }

    #[test]
    fn an_overflowing_state_stops_the_run_naming_the_quantity() {
        let inertia = Inertia::from_principal_moments([1e300, 1e300, 1e300]).unwrap();
        let mut it = Integrator::new(
            RigidBody::new(inertia),
            StepSettings::new(0.5, 4).unwrap(),
            SO3::identity(),
            Vector3::new(1e200, 0.0, 0.0),
        )
        .unwrap();
        // μ = JΩ = 1e500 overflows already at the start.
        match record(&mut it, 1.0, 1, &mut |_| {}) {
            Err(ExperimentError::Overflow { step, quantity, .. }) => {
                assert_eq!(step, 0);
                assert_eq!(quantity, "body momentum μ");
            }
            other => panic!("expected an overflow, got {other:?}"),
        }
    }
}
