//! The integrator of any built-in system, chosen at run time ([`Run`]), and what a run
//! records: every `every`-th state, or the states at given times on the steps' Galerkin
//! curves (dense output), with the run's statistics.

use crate::errors::{invalid, mechanics};
use crate::state::{Element, Sample, Start};
use crate::systems::{Built, Se3System, So3System};
use lgsvi_lie::ChartKind;
use lgsvi_mechanics::events::{Direction, Event, Events};
use lgsvi_mechanics::group::GroupChart;
use lgsvi_mechanics::gyrostat::{AnyGyrostat, Gyrostat};
use lgsvi_mechanics::integrator::GalerkinCurve;
use lgsvi_mechanics::linearization::{Coordinates, StepLinearization};
use lgsvi_mechanics::state::body_momentum;
use lgsvi_mechanics::stepper::CheckReport;
use lgsvi_mechanics::stepper::{Observer, StepInfo};
use lgsvi_mechanics::system::ElementOf;
use lgsvi_mechanics::{Integrator, Matching, MechanicsError, State, StepSettings, Stepper, System};
use nalgebra::DMatrix;
use nalgebra::SVector;
use pyo3::prelude::*;
use std::ops::ControlFlow;
use std::sync::Mutex;
use std::time::Instant;

/// The integrator's settings as given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// The step `h`.
    pub h: f64,
    /// The nodes `n`.
    pub nodes: usize,
    /// The chart.
    pub chart: ChartKind,
    /// The momentum matching.
    pub matching: Matching,
    /// The Gauss points `m` (default `n`).
    pub quadrature_points: Option<usize>,
    /// The cap on Newton iterations per step (default the library's).
    pub max_newton_iterations: Option<usize>,
}

impl Options {
    /// The step settings.
    pub fn settings(&self) -> PyResult<StepSettings> {
        let mut s = StepSettings::new(self.h, self.nodes).map_err(mechanics)?;
        if let Some(m) = self.quadrature_points {
            s = s.with_quadrature_points(m).map_err(mechanics)?;
        }
        if let Some(cap) = self.max_newton_iterations {
            s = s.with_max_newton_iterations(cap);
        }
        Ok(s.with_chart(self.chart).with_matching(self.matching))
    }
}

/// `work` on a pool of `threads` threads, or on rayon's global pool (one thread per core)
/// for `None`.
pub fn in_pool<T: Send>(
    threads: Option<usize>,
    work: impl FnOnce() -> PyResult<T> + Send,
) -> PyResult<T> {
    match threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| invalid(format!("threads: {e}")))?
            .install(work),
        None => work(),
    }
}

/// The chart named `name`.
pub fn chart_named(name: &str) -> PyResult<ChartKind> {
    match name {
        "exp" => Ok(ChartKind::Exp),
        "cayley" => Ok(ChartKind::Cayley),
        "cayley-unscaled" | "cayley_unscaled" => Ok(ChartKind::CayleyUnscaled),
        other => Err(invalid(format!(
            "chart must be \"exp\", \"cayley\" or \"cayley-unscaled\", got {other:?}"
        ))),
    }
}

/// The chart's name.
pub fn chart_name(chart: ChartKind) -> &'static str {
    match chart {
        ChartKind::Exp => "exp",
        ChartKind::Cayley => "cayley",
        ChartKind::CayleyUnscaled => "cayley-unscaled",
    }
}

/// The matching named `name`.
pub fn matching_named(name: &str) -> PyResult<Matching> {
    match name {
        "exact" => Ok(Matching::Exact),
        "paper" => Ok(Matching::Paper),
        other => Err(invalid(format!(
            "matching must be \"exact\" or \"paper\", got {other:?}"
        ))),
    }
}

/// The matching's name.
pub fn matching_name(matching: Matching) -> &'static str {
    match matching {
        Matching::Exact => "exact",
        Matching::Paper => "paper",
    }
}

/// The coordinates named `name`.
pub fn coordinates_named(name: &str) -> PyResult<Coordinates> {
    match name {
        "velocity" => Ok(Coordinates::Velocity),
        "momentum" => Ok(Coordinates::Momentum),
        other => Err(invalid(format!(
            "coordinates must be \"velocity\" ((θ, ω)) or \"momentum\" ((θ, δμ)), got {other:?}"
        ))),
    }
}

/// An integrator of one of the built-in systems.
pub enum Run {
    /// On SO(3).
    So3(Integrator<So3System>),
    /// On SE(3).
    Se3(Integrator<Se3System, ChartKind, 6>),
    /// A gyrostat with one wheel.
    W1(Integrator<Gyrostat<1>, ChartKind, 4>),
    /// Two wheels.
    W2(Integrator<Gyrostat<2>, ChartKind, 5>),
    /// Three wheels.
    W3(Integrator<Gyrostat<3>, ChartKind, 6>),
    /// Four wheels.
    W4(Integrator<Gyrostat<4>, ChartKind, 7>),
}

/// `$body` with the variant's integrator bound to `$it`.
macro_rules! each_run {
    ($run:expr, $it:ident => $body:expr) => {
        match $run {
            Run::So3($it) => $body,
            Run::Se3($it) => $body,
            Run::W1($it) => $body,
            Run::W2($it) => $body,
            Run::W3($it) => $body,
            Run::W4($it) => $body,
        }
    };
}
pub(crate) use each_run;

/// An integrator of `system` from `start`.
pub fn make<S, const D: usize>(
    system: S,
    settings: StepSettings,
    start: &Start,
) -> PyResult<Integrator<S, ChartKind, D>>
where
    S: System<D>,
    ElementOf<S, D>: Element<D>,
    ChartKind: GroupChart<S::Group, D>,
{
    let (g, xi) = <ElementOf<S, D> as Element<D>>::from_start(start)?;
    let mut it = Integrator::new(system, settings, g, xi).map_err(mechanics)?;
    if start.t != 0.0 {
        it.reset(start.t, g, xi).map_err(mechanics)?;
    }
    Ok(it)
}

impl Run {
    /// The integrator of `built` from `start`.
    pub fn new(built: Built, options: &Options, start: &Start) -> PyResult<Self> {
        let settings = options.settings()?;
        check_start(&built, start)?;
        Ok(match built {
            Built::So3(s) => Run::So3(make(s, settings, start)?),
            Built::Se3(s) => Run::Se3(make(s, settings, start)?),
            Built::Wheels(AnyGyrostat::One(g)) => Run::W1(make(g, settings, start)?),
            Built::Wheels(AnyGyrostat::Two(g)) => Run::W2(make(g, settings, start)?),
            Built::Wheels(AnyGyrostat::Three(g)) => Run::W3(make(g, settings, start)?),
            Built::Wheels(AnyGyrostat::Four(g)) => Run::W4(make(g, settings, start)?),
        })
    }

    /// The present state's numbers.
    pub fn sample(&self) -> Sample {
        each_run!(self, it => sample_of(it))
    }

    /// The control input's entries.
    pub fn input(&self) -> Vec<f64> {
        each_run!(self, it => it.input().iter().copied().collect())
    }

    /// Sets the control input.
    pub fn set_input(&mut self, u: &[f64]) -> PyResult<()> {
        each_run!(self, it => set_input_of(it, u))
    }

    /// The Gauss points of a step as fractions of it, and their weights.
    pub fn quadrature(&self) -> (Vec<f64>, Vec<f64>) {
        each_run!(self, it => (it.quadrature_nodes(), it.quadrature_weights()))
    }

    /// Sets the control input at each Gauss point: `rows` one input's entries a point.
    pub fn set_input_at_points(&mut self, rows: &[Vec<f64>]) -> PyResult<()> {
        each_run!(self, it => set_input_at_points_of(it, rows))
    }

    /// Restarts from `start` (the input and statistics are kept).
    pub fn reset(&mut self, start: &Start) -> PyResult<()> {
        each_run!(self, it => {
            let (g, xi) = Element::from_start(start)?;
            it.reset(start.t, g, xi).map_err(mechanics)
        })
    }

    /// One step; its Newton iterations.
    pub fn step(&mut self) -> Result<usize, MechanicsError> {
        each_run!(self, it => it.step())
    }

    /// The integrator's statistics and estimates.
    pub fn totals(&self) -> Totals {
        each_run!(self, it => totals(it))
    }
}

/// Refuses a start the system cannot take (an orbiting body at its attracting centre or
/// inside its own far field: [`lgsvi_mechanics::OrbitingBody::check_position`]).
pub fn check_start(built: &Built, start: &Start) -> PyResult<()> {
    start_refusal(built, start).map_or(Ok(()), |e| Err(mechanics(e)))
}

/// Why the system refuses `start`, if it does ([`check_start`]).
pub fn start_refusal(built: &Built, start: &Start) -> Option<MechanicsError> {
    match built {
        Built::Se3(system) => match &system.system {
            lgsvi_mechanics::built_in::BuiltInSe3::Orbit(body) => {
                body.check_position(&start.position).err()
            }
            _ => None,
        },
        _ => None,
    }
}

/// Sets `it`'s input from the entries `u`.
fn set_input_of<S, C, const D: usize>(it: &mut Integrator<S, C, D>, u: &[f64]) -> PyResult<()>
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: Element<D>,
{
    let input = <ElementOf<S, D> as Element<D>>::input(u)?;
    it.set_input(input).map_err(mechanics)
}

/// Sets `it`'s inputs at the Gauss points from the entries `rows`.
fn set_input_at_points_of<S, C, const D: usize>(
    it: &mut Integrator<S, C, D>,
    rows: &[Vec<f64>],
) -> PyResult<()>
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: Element<D>,
{
    let inputs = rows
        .iter()
        .map(|u| <ElementOf<S, D> as Element<D>>::input(u))
        .collect::<PyResult<Vec<_>>>()?;
    it.set_input_at_points(&inputs).map_err(mechanics)
}

/// The numbers of a state of `it`.
pub fn sample_of<S, C, const D: usize>(it: &Integrator<S, C, D>) -> Sample
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: Element<D>,
{
    let s = it.state();
    Element::sample(s, energy(it.system(), s))
}

/// `⟨μ, ξ⟩ − ℓ` of a state.
fn energy<S: System<D>, const D: usize>(system: &S, s: &State<ElementOf<S, D>, D>) -> f64 {
    s.momentum.dot(&s.velocity) - system.lagrangian(s.time, &s.configuration, &s.velocity)
}

/// An integrator's running totals.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Totals {
    /// Steps taken.
    pub steps: usize,
    /// Newton iterations.
    pub newton_iterations: usize,
    /// The most of one step.
    pub max_newton_iterations: usize,
    /// Newton matrices factored.
    pub factorizations: usize,
    /// Solves redone with more nodes.
    pub rejected_steps: usize,
    /// The sum of the local error estimates since the start or the last reset.
    pub estimated_error: f64,
    /// The forces' work since the start or the last reset.
    pub work: f64,
}

fn totals<S, C, const D: usize>(it: &Integrator<S, C, D>) -> Totals
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
{
    let s = it.statistics();
    Totals {
        steps: s.steps,
        newton_iterations: s.newton_iterations,
        max_newton_iterations: s.max_newton_iterations,
        factorizations: s.factorizations,
        rejected_steps: s.rejected_steps,
        estimated_error: it.estimated_global_error(),
        work: it.work_done(),
    }
}

/// What a run recorded.
#[derive(Debug, Clone, Default)]
pub struct Recording {
    /// The states.
    pub samples: Vec<Sample>,
    /// The Newton iterations of the step that reached each (0 for the start).
    pub iterations: Vec<usize>,
    /// The run's statistics.
    pub stats: RunStats,
    /// The events located, in time order.
    pub hits: Vec<Hit>,
    /// Whether a terminal event stopped the run.
    pub stopped: bool,
}

/// An event as Python gave it (`lgsvi.Event`): a function of a `State`.
pub struct PyEvent {
    /// Its name.
    pub name: String,
    /// `function(state) -> float`.
    pub function: Py<PyAny>,
    /// Which crossings count.
    pub direction: Direction,
    /// Whether the first crossing stops the run.
    pub terminal: bool,
}

/// The events of a `run_until(events=...)` list: `lgsvi.Event` objects (anything with
/// `function`, `direction`, `terminal` and `name`).
pub fn events_of(events: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<PyEvent>> {
    let Some(events) = events else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for (k, event) in events.try_iter()?.enumerate() {
        let event = event?;
        let field = |name: &str| {
            event.getattr(name).map_err(|_| {
                invalid(format!(
                    "events[{k}] is not an lgsvi.Event (it has no {name}): make each with \
                     lgsvi.Event(function, direction=..., terminal=...)"
                ))
            })
        };
        let function = field("function")?;
        if !function.is_callable() {
            return Err(invalid(format!(
                "events[{k}].function is not callable: give a function of a State"
            )));
        }
        let direction = match field("direction")?.extract::<String>()?.as_str() {
            "rising" => Direction::Rising,
            "falling" => Direction::Falling,
            "either" => Direction::Either,
            other => {
                return Err(invalid(format!(
                    "events[{k}].direction must be \"rising\", \"falling\" or \"either\", got {other:?}"
                )))
            }
        };
        out.push(PyEvent {
            name: field("name")?.extract()?,
            function: function.unbind(),
            direction,
            terminal: field("terminal")?.is_truthy()?,
        });
    }
    Ok(out)
}

/// A located event: which, its direction and the state on the curve there.
#[derive(Debug, Clone)]
pub struct Hit {
    /// The event's index in the list given.
    pub event: usize,
    /// Its name.
    pub name: String,
    /// The crossing's direction.
    pub direction: Direction,
    /// The state at the crossing.
    pub sample: Sample,
}

/// The library's events observer for `events`, each calling its Python function with the
/// `State` on the step's curve; a Python exception is kept in `failure` (the first one)
/// and ends the run through a NaN.
fn observer_of<'a, S, const D: usize>(
    system: &'a S,
    events: &'a [PyEvent],
    failure: &'a Mutex<Option<PyErr>>,
) -> Events<'a, ElementOf<S, D>, D>
where
    S: System<D> + Sync,
    ElementOf<S, D>: Element<D>,
{
    Events::new(
        events
            .iter()
            .map(|e| {
                let function = move |t: f64, g: &ElementOf<S, D>, xi: &SVector<f64, D>| {
                    let state = State {
                        time: t,
                        configuration: *g,
                        momentum: body_momentum(system, t, g, xi),
                        velocity: *xi,
                    };
                    let sample = Element::sample(&state, energy(system, &state));
                    Python::attach(|py| {
                        let value = e
                            .function
                            .call1(py, (crate::state::State { sample },))
                            .and_then(|v| v.extract::<f64>(py));
                        value.unwrap_or_else(|error| {
                            let mut slot = failure.lock().unwrap_or_else(|p| p.into_inner());
                            slot.get_or_insert(error);
                            f64::NAN
                        })
                    })
                };
                let event = Event::new(e.name.clone(), function).direction(e.direction);
                if e.terminal {
                    event.terminal()
                } else {
                    event
                }
            })
            .collect(),
    )
}

/// The hits of an events observer as plain numbers.
fn hits_of<S, const D: usize>(
    system: &S,
    events: &[PyEvent],
    observer: Events<'_, ElementOf<S, D>, D>,
) -> (Vec<Hit>, bool)
where
    S: System<D>,
    ElementOf<S, D>: Element<D>,
{
    let stopped = observer.stopped();
    let hits = observer
        .into_hits()
        .into_iter()
        .map(|hit| {
            let state = State {
                time: hit.time,
                configuration: hit.configuration,
                momentum: body_momentum(system, hit.time, &hit.configuration, &hit.velocity),
                velocity: hit.velocity,
            };
            Hit {
                event: hit.event,
                name: events[hit.event].name.clone(),
                direction: hit.direction,
                sample: Element::sample(&state, energy(system, &state)),
            }
        })
        .collect();
    (hits, stopped)
}

/// A failed run's error: the Python event function's own exception where one raised,
/// else the library's error.
pub enum RunError {
    /// The library's.
    Mechanics(MechanicsError),
    /// An event function's.
    Python(PyErr),
}

impl From<MechanicsError> for RunError {
    fn from(error: MechanicsError) -> Self {
        RunError::Mechanics(error)
    }
}

impl From<RunError> for PyErr {
    fn from(error: RunError) -> Self {
        match error {
            RunError::Mechanics(error) => mechanics(error),
            RunError::Python(error) => error,
        }
    }
}

/// `error`, or the Python exception an event function raised first.
fn run_error(error: MechanicsError, failure: &Mutex<Option<PyErr>>) -> RunError {
    match failure.lock().unwrap_or_else(|p| p.into_inner()).take() {
        Some(python) => RunError::Python(python),
        None => RunError::Mechanics(error),
    }
}

/// A run's statistics.
#[derive(Debug, Clone, Default)]
pub struct RunStats {
    /// Steps, iterations, factorisations, redone solves of this run; the estimate since the
    /// integrator's start.
    pub totals: Totals,
    /// The integration's wall time (summed over the runs of a checked tolerance run).
    pub wall_time_s: f64,
    /// `(n, steps)` of this run's steps.
    pub nodes: Vec<(usize, usize)>,
    /// A checked run's measurement and the tolerance it was held to.
    pub check: Option<(CheckReport, f64)>,
}

/// What to record: every `every`-th state, or the states at `dense` times.
pub enum Record {
    /// The start, every `every`-th state and the last.
    Every(usize),
    /// The states at these times (ascending, within the run), on the steps' curves.
    Dense(Vec<f64>),
}

/// The observer that records a run.
struct Collect<'a> {
    record: &'a Record,
    next: usize,
    samples: Vec<Sample>,
    iterations: Vec<usize>,
    /// The Newton iterations of the last step taken.
    last_iterations: usize,
}

impl<'a> Collect<'a> {
    fn new<S, C, const D: usize>(record: &'a Record, it: &Integrator<S, C, D>) -> Self
    where
        S: System<D>,
        C: GroupChart<S::Group, D>,
        ElementOf<S, D>: Element<D>,
    {
        let mut collect = Self {
            record,
            next: 0,
            samples: Vec::new(),
            iterations: Vec::new(),
            last_iterations: 0,
        };
        let start = sample_of(it);
        match record {
            Record::Every(_) => {
                collect.samples.push(start);
                collect.iterations.push(0);
            }
            Record::Dense(times) => {
                let slack = 1e-12 * it.settings().h();
                while collect.next < times.len() && times[collect.next] <= start.t + slack {
                    collect.samples.push(Sample {
                        t: times[collect.next],
                        ..start
                    });
                    collect.iterations.push(0);
                    collect.next += 1;
                }
            }
        }
        collect
    }
}

impl Collect<'_> {
    /// After a run a terminal event stopped: its last state, where the recording did not
    /// take it (a run of `every` steps records its planned last step only).
    fn finish<S, C, const D: usize>(&mut self, it: &Integrator<S, C, D>, stopped: bool)
    where
        S: System<D>,
        C: GroupChart<S::Group, D>,
        ElementOf<S, D>: Element<D>,
    {
        if stopped
            && matches!(self.record, Record::Every(_))
            && self.samples.last().is_none_or(|s| s.t != it.state().time)
        {
            self.samples.push(sample_of(it));
            self.iterations.push(self.last_iterations);
        }
    }
}

impl<S, C, const D: usize> Observer<S, C, D> for Collect<'_>
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: Element<D>,
{
    type Error = MechanicsError;
    fn after_step(
        &mut self,
        it: &Integrator<S, C, D>,
        step: StepInfo,
    ) -> Result<ControlFlow<()>, MechanicsError> {
        self.last_iterations = step.iterations;
        match self.record {
            Record::Every(every) => {
                if step.index.is_multiple_of(*every) || step.last {
                    self.samples.push(sample_of(it));
                    self.iterations.push(step.iterations);
                }
            }
            Record::Dense(times) => {
                let end = it.state().time;
                let Some(curve) = it.last_curve() else {
                    return Ok(ControlFlow::Continue(()));
                };
                let slack = 1e-12 * curve.step();
                while self.next < times.len() && times[self.next] <= end + slack {
                    let t = times[self.next];
                    self.samples.push(on_curve(it.system(), &curve, t)?);
                    self.iterations.push(step.iterations);
                    self.next += 1;
                }
            }
        }
        Ok(ControlFlow::Continue(()))
    }
}

/// The state at time `t` on a step's Galerkin curve (its momentum from the Legendre
/// transform at that point).
pub fn on_curve<S, C, const D: usize>(
    system: &S,
    curve: &GalerkinCurve<S::Group, C, D>,
    t: f64,
) -> Result<Sample, MechanicsError>
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: Element<D>,
{
    let (g, xi) = curve.at(t - curve.start())?;
    let state = State {
        time: t,
        configuration: g,
        momentum: body_momentum(system, t, &g, &xi),
        velocity: xi,
    };
    Ok(Element::sample(&state, energy(system, &state)))
}

/// Runs `it` to `t_end`, recording as `record` says.
pub fn run_until<S, const D: usize>(
    it: &mut Integrator<S, ChartKind, D>,
    t_end: f64,
    record: &Record,
    events: &[PyEvent],
) -> Result<Recording, RunError>
where
    S: System<D> + Clone + Sync,
    ElementOf<S, D>: Element<D>,
    ChartKind: GroupChart<S::Group, D>,
{
    let before = totals(it);
    let nodes_before: Vec<usize> = it.nodes_histogram().to_vec();
    let mut collect = Collect::new(record, it);
    let system = it.system().clone();
    let failure = Mutex::new(None);
    let mut observer = observer_of(&system, events, &failure);
    let clock = Instant::now();
    it.drive_until(t_end, &mut (&mut collect, &mut observer))
        .map_err(|e| run_error(e, &failure))?;
    let wall_time_s = clock.elapsed().as_secs_f64();
    let (hits, stopped) = hits_of(&system, events, observer);
    collect.finish(it, stopped);
    let after = totals(it);
    let nodes = it
        .nodes_histogram()
        .iter()
        .zip(&nodes_before)
        .enumerate()
        .filter(|(_, (a, b))| a > b)
        .map(|(n, (a, b))| (n, a - b))
        .collect();
    Ok(Recording {
        samples: collect.samples,
        iterations: collect.iterations,
        stats: RunStats {
            totals: Totals {
                steps: after.steps - before.steps,
                newton_iterations: after.newton_iterations - before.newton_iterations,
                max_newton_iterations: after.max_newton_iterations,
                factorizations: after.factorizations - before.factorizations,
                rejected_steps: after.rejected_steps - before.rejected_steps,
                estimated_error: after.estimated_error,
                work: after.work,
            },
            wall_time_s,
            nodes,
            check: None,
        },
        hits,
        stopped,
    })
}

/// A checked tolerance-driven run from `it`'s state to `t_end` (the builder's policy, as
/// `lgsvi simulate --tol`: the step from the motion unless `step` is given, the nodes per
/// step adapted, a companion with two more nodes measuring the error, a run that misses
/// taken again); `it` is moved to the accepted run's end state.
pub fn run_to_tolerance<S, const D: usize>(
    it: &mut Integrator<S, ChartKind, D>,
    t_end: f64,
    tolerance: f64,
    step: Option<f64>,
    record: &Record,
    events: &[PyEvent],
) -> Result<Recording, RunError>
where
    S: System<D> + Clone + Sync,
    ElementOf<S, D>: Element<D> + lgsvi_mechanics::control::GroupLog<D>,
    ChartKind: GroupChart<S::Group, D>,
{
    let start = *it.state();
    let mut builder = Integrator::builder(it.system().clone())
        .start_at(start.time, start.configuration, start.velocity)
        .tolerance(tolerance)
        .horizon(t_end - start.time)
        .chart(*it.chart())
        .matching(it.settings().matching())
        .input(*it.input());
    if let Some(h) = step {
        builder = builder.step(h);
    }
    let mut checked = builder.build_checked()?;
    let mut wall_time_s = 0.0;
    let system = it.system().clone();
    let failure = Mutex::new(None);
    // Each run (a missed one is taken again, tightened) records and locates afresh.
    let (collect, hits, stopped) = loop {
        let mut collect = Collect::new(record, checked.integrator());
        let mut observer = observer_of(&system, events, &failure);
        let clock = Instant::now();
        checked
            .drive_until(t_end, &mut (&mut collect, &mut observer))
            .map_err(|e| run_error(e, &failure))?;
        wall_time_s += clock.elapsed().as_secs_f64();
        if checked.judge()? {
            let (hits, stopped) = hits_of(&system, events, observer);
            collect.finish(checked.integrator(), stopped);
            break (collect, hits, stopped);
        }
    };
    let primary = checked.integrator();
    let report = checked.check_report();
    let end = *primary.state();
    let stats = RunStats {
        totals: Totals {
            estimated_error: checked.estimated_error(),
            ..totals(primary)
        },
        wall_time_s,
        nodes: primary.nodes_used().collect(),
        check: report.map(|r| (r, tolerance)),
    };
    it.reset(end.time, end.configuration, end.velocity)?;
    Ok(Recording {
        samples: collect.samples,
        iterations: collect.iterations,
        stats,
        hits,
        stopped,
    })
}

/// A step's `(A, B)` (and, with the parameters, `P` and their names) in `coordinates`.
pub struct Linear {
    /// `A`.
    pub a: DMatrix<f64>,
    /// `B`.
    pub b: DMatrix<f64>,
    /// `P` and the parameters' names.
    pub p: Option<(DMatrix<f64>, Vec<String>)>,
    /// The Gauss points' parts, when asked for.
    pub points: Option<PointParts>,
}

/// A step's linearisation at its Gauss points.
pub struct PointParts {
    /// `B_j`, one per point (`None` unless the inputs were given per point).
    pub b: Option<Vec<DMatrix<f64>>>,
    /// `∂θ_j/∂(x, u)`, the configuration's derivative at each point.
    pub configurations: Vec<DMatrix<f64>>,
}

impl Linear {
    /// From the library's linearisation, with the Gauss points' parts when `points`.
    pub fn of<E, const D: usize>(
        l: &StepLinearization<E, D>,
        coordinates: Coordinates,
        points: bool,
    ) -> Self {
        Self {
            a: l.a(coordinates).clone(),
            b: l.b(coordinates).clone(),
            p: l.p(coordinates)
                .map(|p| (p.clone(), l.parameter_names().to_vec())),
            points: points.then(|| PointParts {
                b: l.b_points(coordinates).map(<[_]>::to_vec),
                configurations: l.point_configurations(coordinates).to_vec(),
            }),
        }
    }
}
