//! The integrator of any built-in system, chosen at run time ([`Run`]), and what a run
//! records: every `every`-th state, or the states at given times on the steps' Galerkin
//! curves (dense output), with the run's statistics.

use crate::errors::{invalid, mechanics};
use crate::state::{Element, Sample, Start};
use crate::systems::{Built, Se3System, So3System};
use lgsvi_lie::ChartKind;
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
use pyo3::prelude::*;
use std::ops::ControlFlow;
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
) -> Result<Recording, MechanicsError>
where
    S: System<D>,
    ElementOf<S, D>: Element<D>,
    ChartKind: GroupChart<S::Group, D>,
{
    let before = totals(it);
    let nodes_before: Vec<usize> = it.nodes_histogram().to_vec();
    let mut collect = Collect::new(record, it);
    let clock = Instant::now();
    it.drive_until(t_end, &mut collect)?;
    let wall_time_s = clock.elapsed().as_secs_f64();
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
) -> Result<Recording, MechanicsError>
where
    S: System<D> + Clone,
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
    let collect = loop {
        let mut collect = Collect::new(record, checked.integrator());
        let clock = Instant::now();
        checked.drive_until(t_end, &mut collect)?;
        wall_time_s += clock.elapsed().as_secs_f64();
        if checked.judge()? {
            break collect;
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
}

impl Linear {
    /// From the library's linearisation.
    pub fn of<E, const D: usize>(l: &StepLinearization<E, D>, coordinates: Coordinates) -> Self {
        Self {
            a: l.a(coordinates).clone(),
            b: l.b(coordinates).clone(),
            p: l.p(coordinates)
                .map(|p| (p.clone(), l.parameter_names().to_vec())),
        }
    }
}
