//! Tolerance-driven runs, measured:
//!
//! - **local errors** ([`local_errors`]): every step of runs over a grid of `(h, n)` is
//!   compared with the step from the same state with [`TRUTH_EXTRA_NODES`] more nodes
//!   (spectral convergence makes that the exact flow to rounding at these steps); the ratio
//!   of the step's own error estimate ([`Integrator::error_estimate`]) to that true local
//!   error is its calibration ([`calibration`]).
//! - **tolerance runs** ([`tolerance_runs`]): runs with tolerance-driven settings against a
//!   high-accuracy reference at the horizon, each beside the fastest fixed `(h, n)` of a
//!   grid that is at least as accurate, with the run's own estimate of its global error and
//!   its nodes per step.
//!
//! The policy of tolerance-driven runs (the step from the initial motion's rate, the first
//! step's nodes from the tolerance) is the library's: [`lgsvi_mechanics::tolerance`].
//!
//! Both studies are generic over the group: the error of a state is the largest difference in the
//! entries of what [`Observe`] lists (`R`, `Ω` and, on SE(3), `x` and `ẋ`; for a gyrostat
//! the wheel angles `φ` and their rates `φ̇`).

use crate::error::ExperimentError;
use lgsvi_mechanics::group::GroupChart;
use lgsvi_mechanics::gyrostat::BodyWheels;
use lgsvi_mechanics::lie::{ChartKind, SE3, SO3};
use lgsvi_mechanics::stepper::{each, StepInfo};
use lgsvi_mechanics::system::ElementOf;
use lgsvi_mechanics::Stepper;
use lgsvi_mechanics::{Integrator, MechanicsError, State, StepSettings, System};
use serde::Serialize;
use std::ops::ControlFlow;
use std::time::Instant;

type Result<T> = std::result::Result<T, ExperimentError>;

/// Builds a run's integrator from its settings.
pub type Make<'a, S, C, const D: usize> =
    dyn Fn(StepSettings) -> std::result::Result<Integrator<S, C, D>, MechanicsError> + 'a;

/// The truth of a step: the same step with this many more nodes (at `h ≤ 1.25` on the
/// reference cases, 14 more nodes than 5…12 put the step's error below 1e-15).
pub const TRUTH_EXTRA_NODES: usize = 14;

/// Local errors at or below this, relative to the state's largest entry (at least 1), are
/// rounding and are left out of the calibration ([`LocalError::above_rounding`]).
pub const LOCAL_FLOOR: f64 = 1e-14;

/// The reference of the tolerance study: `h ≈ 0.25` dividing the horizon, this many nodes.
pub const REFERENCE_NODES: usize = 24;

/// Timing repetitions of every run of the tolerance study (the fastest is kept).
pub const REPEATS: usize = 5;

/// What a study compares: the entries of `R`, `Ω` (and `x`, `ẋ` on SE(3); `φ`, `φ̇` for a
/// gyrostat's wheels).
pub trait Observe {
    /// The compared numbers: `R` row by row, `Ω` (and `x`, `ẋ` on SE(3); the wheel angles
    /// `φ` and rates `φ̇` for a gyrostat).
    fn observe(&self) -> Vec<f64>;
}

/// `R`'s entries, row by row.
fn rows(r: &SO3) -> Vec<f64> {
    r.matrix().transpose().iter().copied().collect()
}

impl Observe for State<SO3, 3> {
    fn observe(&self) -> Vec<f64> {
        let mut v = rows(self.attitude());
        v.extend(self.velocity.iter());
        v
    }
}

impl Observe for State<SE3, 6> {
    fn observe(&self) -> Vec<f64> {
        let mut v = rows(self.attitude());
        v.extend(self.angular_velocity().iter());
        v.extend(self.position().iter());
        v.extend(self.linear_velocity().iter());
        v
    }
}

/// A gyrostat on SO(3) × ℝᴷ (`D = 3 + K`): `R` row by row, `Ω`, the wheel angles `φ`
/// (relative to the body) and their rates `φ̇`.
impl<const K: usize, const D: usize> Observe for State<BodyWheels<f64, K>, D> {
    fn observe(&self) -> Vec<f64> {
        let mut v = rows(&self.configuration.attitude);
        v.extend(self.velocity.iter().take(3));
        v.extend(self.configuration.wheels.iter());
        v.extend(self.velocity.iter().skip(3));
        v
    }
}

/// The largest difference of two observations' entries.
pub fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// One step of the estimate study.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct LocalError {
    /// The run's step.
    pub h: f64,
    /// The run's nodes.
    pub nodes: usize,
    /// The step's index in its run.
    pub step: usize,
    /// The step's own error estimate.
    pub estimate: f64,
    /// The step's true local error: the distance to the step with more nodes.
    pub truth: f64,
    /// The largest entry of the state the step ended in (`|Ω|`, a position, a wheel
    /// angle): the two runs' rounding, and so the floor of `truth`, grows with it.
    pub scale: f64,
}

impl LocalError {
    /// Whether the true local error is above the rounding floor, [`LOCAL_FLOOR`] times the
    /// state's largest entry (at least 1): a gyrostat's wheel angles of 200 rad round at
    /// 3e-14, where the same step's attitude alone would show 1e-16.
    pub fn above_rounding(&self) -> bool {
        self.truth > LOCAL_FLOOR * self.scale.max(1.0)
    }
}

/// One tolerance of the tolerance study.
#[derive(Debug, Clone, Serialize)]
pub struct ToleranceRun {
    /// The tolerance.
    pub tol: f64,
    /// The step the settings chose.
    pub h: f64,
    /// The error at the horizon against the reference.
    pub error: f64,
    /// The run's own estimate of it (the sum of its local estimates).
    pub estimated_error: f64,
    /// The fastest of [`REPEATS`] runs, seconds.
    pub wall_time_s: f64,
    /// `(n, steps with n nodes)`.
    pub nodes: Vec<(usize, usize)>,
    /// Solves redone with more nodes.
    pub rejected_steps: usize,
    /// The fastest fixed `(h, n)` of the grid with an error at most `error`:
    /// `(h, n, error, time)`.
    pub best_fixed: Option<(f64, usize, f64, f64)>,
    /// Why the run failed, if it did.
    pub failure: Option<String>,
}

/// The tolerance study's results ([`tolerance_runs`]).
#[derive(Debug, Clone, Serialize)]
pub struct ToleranceStudy {
    /// What the errors were measured against, in one line.
    pub reference: String,
    /// One per tolerance, in the order given.
    pub runs: Vec<ToleranceRun>,
    /// The fixed grid's runs that finished.
    pub fixed: Vec<FixedRun>,
}

/// A fixed `(h, n)` run of the tolerance study's grid.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct FixedRun {
    /// Step.
    pub h: f64,
    /// Nodes.
    pub nodes: usize,
    /// The error at the horizon against the reference.
    pub error: f64,
    /// The fastest of [`REPEATS`] runs, seconds.
    pub wall_time_s: f64,
}

/// The local errors of every step of runs with `steps × nodes` to `t_end`, calling `tick`
/// before each run. A setting the chart cannot follow (a long Cayley step) has no steps to
/// show and is left out.
pub fn local_errors<S, C, const D: usize>(
    make: &Make<S, C, D>,
    steps: &[f64],
    nodes: &[usize],
    t_end: f64,
    tick: &mut dyn FnMut(),
) -> Result<Vec<LocalError>>
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    State<ElementOf<S, D>, D>: Observe,
{
    let mut out = Vec::new();
    for &h in steps {
        for &n in nodes {
            tick();
            let run = || -> Result<Vec<LocalError>> {
                let mut integrator = make(StepSettings::new(h, n)?)?;
                let mut truth = make(StepSettings::new(h, n + TRUTH_EXTRA_NODES)?)?;
                let count = integrator.steps_until(t_end)?;
                let mut rows = Vec::with_capacity(count);
                // The truth takes each step from where the run stood before it.
                let mut before = *integrator.state();
                let compare = |it: &Integrator<S, C, D>, info: StepInfo| {
                    truth.reset(before.time, before.configuration, before.velocity)?;
                    truth.step()?;
                    let end = it.state().observe();
                    rows.push(LocalError {
                        h,
                        nodes: n,
                        step: info.index - 1,
                        estimate: it.error_estimate(),
                        truth: distance(&end, &truth.state().observe()),
                        scale: end.iter().fold(0.0, |m, x| m.max(x.abs())),
                    });
                    before = *it.state();
                    Ok::<_, ExperimentError>(ControlFlow::Continue(()))
                };
                integrator.drive(count, &mut each(compare))?;
                Ok(rows)
            };
            // A setting the chart cannot follow (a long Cayley step) has no steps to show.
            if let Ok(rows) = run() {
                out.extend(rows);
            }
        }
    }
    Ok(out)
}

/// Runs `settings` to `t_end` [`REPEATS`] times: the final state, the fastest time (the
/// timing policy of this study, against the median of `work_precision::median_time`), and
/// the integrator's accounts of the last run.
fn fastest_run<S, C, const D: usize>(
    make: &Make<S, C, D>,
    settings: StepSettings,
    t_end: f64,
) -> Result<(Vec<f64>, f64, Integrator<S, C, D>)>
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    State<ElementOf<S, D>, D>: Observe,
{
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..REPEATS {
        let mut integrator = make(settings)?;
        let steps = integrator.steps_until(t_end)?;
        let start = Instant::now();
        let none = |_: &Integrator<S, C, D>, _: StepInfo| {
            Ok::<_, ExperimentError>(ControlFlow::Continue(()))
        };
        integrator.drive(steps, &mut each(none))?;
        best = best.min(start.elapsed().as_secs_f64());
        last = Some(integrator);
    }
    let integrator = last.expect("REPEATS > 0");
    Ok((integrator.state().observe(), best, integrator))
}

/// The tolerance study: a run for each `(tol, settings)` of `tolerance_runs`, the fixed
/// grid `steps × nodes`, and the reference they are measured against (a run with
/// `h ≈ 0.25` dividing `t_end` and [`REFERENCE_NODES`] nodes, checked against 4 more), in
/// the chart `make` uses (named `chart`). Returns the reference's description, the
/// tolerance runs and the grid's runs; `tick` is called before each run.
pub fn tolerance_runs<S, C, const D: usize>(
    make: &Make<S, C, D>,
    chart: ChartKind,
    tolerance_runs: &[(f64, StepSettings)],
    steps: &[f64],
    nodes: &[usize],
    t_end: f64,
    tick: &mut dyn FnMut(),
) -> Result<ToleranceStudy>
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    State<ElementOf<S, D>, D>: Observe,
{
    let reference_step = t_end / (t_end / 0.25).ceil().max(1.0);
    let reference = |n: usize| -> Result<Vec<f64>> {
        let mut integrator = make(StepSettings::new(reference_step, n)?)?;
        let steps = integrator.steps_until(t_end)?;
        integrator
            .run(steps, steps.max(1))
            .map_err(|source| ExperimentError::Run {
                context: crate::convergence::reference_context(reference_step, n),
                source,
            })?;
        Ok(integrator.state().observe())
    };
    let truth = reference(REFERENCE_NODES)?;
    let check = distance(&truth, &reference(REFERENCE_NODES + 4)?);
    let describe = format!(
        "a run with h = {reference_step}, n = {REFERENCE_NODES} ({chart} chart, exact matching; \
         differs from n = {} by {check:.1e} at T = {t_end})",
        REFERENCE_NODES + 4
    );
    let mut fixed = Vec::new();
    for &h in steps {
        for &n in nodes {
            tick();
            if let Ok((end, time, _)) = fastest_run(make, StepSettings::new(h, n)?, t_end) {
                fixed.push(FixedRun {
                    h,
                    nodes: n,
                    error: distance(&end, &truth),
                    wall_time_s: time,
                });
            }
        }
    }
    let mut runs = Vec::new();
    for &(tol, settings) in tolerance_runs {
        tick();
        let mut run = ToleranceRun {
            tol,
            h: settings.h(),
            error: f64::NAN,
            estimated_error: f64::NAN,
            wall_time_s: f64::NAN,
            nodes: Vec::new(),
            rejected_steps: 0,
            best_fixed: None,
            failure: None,
        };
        match fastest_run(make, settings, t_end) {
            Ok((end, time, integrator)) => {
                run.error = distance(&end, &truth);
                run.estimated_error = integrator.estimated_global_error();
                run.wall_time_s = time;
                run.nodes = integrator.nodes_used().collect();
                run.rejected_steps = integrator.statistics().rejected_steps;
                run.best_fixed = fixed
                    .iter()
                    .filter(|f| f.error <= run.error.max(check))
                    .min_by(|a, b| a.wall_time_s.total_cmp(&b.wall_time_s))
                    .map(|f| (f.h, f.nodes, f.error, f.wall_time_s));
            }
            Err(e) => run.failure = Some(e.to_string()),
        }
        runs.push(run);
    }
    Ok(ToleranceStudy {
        reference: describe,
        runs,
        fixed,
    })
}

/// `log10(estimate / truth)` over the steps above rounding ([`LocalError::above_rounding`]):
/// `(mean, standard deviation, least, largest, share of steps within a factor 30 either way,
/// steps counted)`; `None` without a step above the floor.
pub fn calibration(rows: &[LocalError]) -> Option<(f64, f64, f64, f64, f64, usize)> {
    let logs: Vec<f64> = rows
        .iter()
        .filter(|r| r.above_rounding() && r.estimate > 0.0)
        .map(|r| (r.estimate / r.truth).log10())
        .collect();
    if logs.is_empty() {
        return None;
    }
    let count = logs.len() as f64;
    let mean = logs.iter().sum::<f64>() / count;
    let sd = (logs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / count).sqrt();
    let lo = logs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = logs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let within = logs.iter().filter(|x| x.abs() <= 30f64.log10()).count() as f64 / count;
    Some((mean, sd, lo, hi, within, logs.len()))
}

/// The rotation a tolerance-driven run's step takes at the initial motion's fastest rate,
/// as a fraction of what the chart can follow in one step (exp 2π, Cayley π), at most
#[cfg(test)]
mod tests {
    use super::*;

    fn step(truth: f64, scale: f64) -> LocalError {
        LocalError {
            h: 0.5,
            nodes: 8,
            step: 0,
            estimate: 1e-13,
            truth,
            scale,
        }
    }

    /// The rounding floor of a step's true error scales with the state's largest entry
    /// (at least 1), and the calibration leaves out what is at it.
    #[test]
    fn the_calibration_leaves_out_rounding_relative_to_the_state() {
        // 3e-14 is rounding on wheel angles of 200 rad (an ulp is 2.8e-14), not on an
        // attitude and rates of order one.
        assert!(!step(3e-14, 200.0).above_rounding());
        assert!(step(3e-14, 0.7).above_rounding());
        assert!(step(3e-12, 200.0).above_rounding());
        assert!(!step(1e-14, 0.5).above_rounding());
        let rows = [step(3e-14, 200.0), step(1e-13, 1.0)];
        let (mean, _, _, _, _, count) = calibration(&rows).unwrap();
        assert_eq!(count, 1);
        assert_eq!(mean, 0.0);
        assert!(calibration(&rows[..1]).is_none());
    }
}
