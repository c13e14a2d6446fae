//! The measurements behind the figures of Hall and Leok's paper, as data: n-refinement
//! (figures 1 and 5), h-refinement (2 and 6), long runs of energy and momenta (3 and 7),
//! body momenta on the sphere (4) and the pendulum near its unstable equilibrium (8 and 9).
//!
//! Each function runs a [`Subject`] over the paper's settings and returns what a figure or a
//! report needs; nothing here draws, writes or formats. Progress goes to a [`Progress`]
//! observer (`&mut ()` for none).

use crate::conserved::largest;
use crate::convergence::{measure, Measurement, Reference};
use crate::error::ExperimentError;
use crate::fit;
use crate::subject::Subject;
use lgsvi_mechanics::lie::ChartKind;
use lgsvi_mechanics::stepper::{each, StepInfo};
use lgsvi_mechanics::Stepper;
use lgsvi_mechanics::{Integrator, Matching, MechanicsError, StepSettings};
use nalgebra::Vector3;
use std::ops::ControlFlow;
use std::time::Instant;

type Result<T> = std::result::Result<T, ExperimentError>;

/// Told how far a measurement has come: a progress bar, a log, or nothing (`()`).
pub trait Progress {
    /// A measurement named `what` begins, `units` long.
    fn begin(&mut self, _what: &str, _units: u64) {}
    /// `units` more are done.
    fn advance(&mut self, _units: u64) {}
    /// The measurement has ended.
    fn end(&mut self) {}
}

/// No progress report.
impl Progress for () {}

/// Step settings in `chart` with `matching`.
pub fn settings(chart: ChartKind, matching: Matching, h: f64, n: usize) -> Result<StepSettings> {
    Ok(StepSettings::new(h, n)?
        .with_chart(chart)
        .with_matching(matching))
}

/// How the figures name a matching.
pub fn matching_name(m: Matching) -> &'static str {
    match m {
        Matching::Paper => "paper matching",
        _ => "exact matching",
    }
}

/// How the figures name a chart.
pub fn chart_name(c: ChartKind) -> &'static str {
    match c {
        ChartKind::Exp => "exp chart",
        ChartKind::Cayley => "Cayley chart",
        _ => "unscaled Cayley (paper)",
    }
}

/// An n-refinement fit: chart, matching, factor per node of the one-step map and of the
/// Galerkin curves.
pub type NodeFit = (ChartKind, Matching, Option<f64>, f64);

/// A long run's record.
#[derive(Debug, Clone, Default)]
pub struct LongRun {
    /// The time of each record (from `t = 0`, one per step).
    pub times: Vec<f64>,
    /// `|E − E₀|/|E₀|` at each record.
    pub energy_error: Vec<f64>,
    /// `||μ|² − |μ₀|²|/|μ₀|²` at each record.
    pub casimir_drift: Vec<f64>,
    /// The conserved spatial momentum's drift ([`crate::Drift`]) at each record.
    pub momentum_drift: Vec<f64>,
    /// Rotation angle of each step, `|log(R_kᵀ R_{k+1})|`.
    pub step_angle: Vec<f64>,
    /// Body momentum at each recorded step.
    pub momentum: Vec<Vector3<f64>>,
    /// `R ρ` (`ρ = e₃`) at each step.
    pub axis: Vec<Vector3<f64>>,
    /// `R ρ` on the steps' Galerkin curves, `(t, Rρ)`.
    pub curve_axis: Vec<(f64, Vector3<f64>)>,
    /// Why the run stopped early, if it did.
    pub failure: Option<String>,
    /// Wall time of the steps, seconds.
    pub wall_time_s: f64,
}

/// `steps` steps of `subject` with `settings`, every state recorded, and each step's
/// Galerkin curve sampled at `curve_samples` points (none for 0 or 1); `tick(k)` after every
/// 50 steps. A failing step ends the run, its reason kept in [`LongRun::failure`].
pub fn long_run<P: Subject>(
    subject: &P,
    settings: StepSettings,
    steps: usize,
    curve_samples: usize,
    mut tick: impl FnMut(usize),
) -> Result<LongRun> {
    let mut integrator = subject.integrator(settings)?;
    let system = subject.system();
    let s0 = *integrator.state();
    let tracker = subject.tracker(&s0);
    let mut run = LongRun::default();
    let record = |run: &mut LongRun, s: &lgsvi_mechanics::State| {
        run.times.push(s.time);
        let drift = tracker.drift(s.energy(system), s.attitude().matrix(), &s.momentum);
        run.energy_error.push(drift.energy);
        run.casimir_drift.push(drift.casimir);
        run.momentum_drift.push(drift.spatial_momentum);
        run.momentum.push(s.momentum);
        run.axis.push(s.attitude().matrix() * Vector3::z());
    };
    record(&mut run, &s0);
    let start = Instant::now();
    // After every step: the invariants, the step's rotation, samples of its curve; a failed
    // step ends the run with its reason kept.
    let mut before = *s0.attitude().matrix();
    let observe = |integrator: &Integrator<P::System>, step: StepInfo| {
        let s = *integrator.state();
        let relative = before.transpose() * s.attitude().matrix();
        before = *s.attitude().matrix();
        let cos = ((relative.trace() - 1.0) / 2.0).clamp(-1.0, 1.0);
        run.step_angle.push(cos.acos());
        record(&mut run, &s);
        if curve_samples > 1 {
            if let Some(curve) = integrator.last_curve() {
                for j in 0..curve_samples {
                    let tau = curve.step() * j as f64 / curve_samples as f64;
                    if let Ok((g, _)) = curve.at(tau) {
                        run.curve_axis
                            .push((curve.start() + tau, g.matrix() * Vector3::z()));
                    }
                }
            }
        }
        if (step.index - 1).is_multiple_of(50) {
            tick(50);
        }
        Ok::<_, MechanicsError>(ControlFlow::Continue(()))
    };
    let driven = integrator.drive(steps, &mut each(observe));
    if let Err(e) = driven {
        run.failure = Some(e.to_string());
    }
    run.wall_time_s = start.elapsed().as_secs_f64();
    Ok(run)
}

/// `max |ΔE|` over the second half of a run divided by that over the first half: about 1
/// for a bounded, oscillating error, about 2 or more for a drift.
pub fn halves_ratio(values: &[f64]) -> f64 {
    let half = values.len() / 2;
    let first = values[..half].iter().cloned().fold(0.0, f64::max);
    let second = values[half..].iter().cloned().fold(0.0, f64::max);
    second / first.max(1e-300)
}

/// The largest of `values` (0 for none); NaN if any is NaN (a drift not measured, not a
/// drift of 0).
pub fn max(values: &[f64]) -> f64 {
    values.iter().fold(0.0, |a, &b| largest(a, b))
}

/// The n-refinement configurations: (chart, matching).
pub const N_CONFIGS: [(ChartKind, Matching); 3] = [
    (ChartKind::CayleyUnscaled, Matching::Paper),
    (ChartKind::CayleyUnscaled, Matching::Exact),
    (ChartKind::Exp, Matching::Exact),
];

/// The long runs' configurations: the paper's chart with both matchings, and exp.
pub const LONG_CONFIGS: [(ChartKind, Matching); 3] = [
    (ChartKind::CayleyUnscaled, Matching::Exact),
    (ChartKind::CayleyUnscaled, Matching::Paper),
    (ChartKind::Exp, Matching::Exact),
];

/// A configuration's label: chart and matching.
pub fn label(chart: ChartKind, matching: Matching) -> String {
    format!("{}, {}", chart_name(chart), matching_name(matching))
}

/// Figures 1 and 5: n-refinement at `h = 0.5`, T = 10, for each of [`N_CONFIGS`].
pub struct NRefinement {
    /// The node counts.
    pub nodes: Vec<usize>,
    /// What the errors are measured against.
    pub reference: String,
    /// One measurement per configuration and node count, configuration-major.
    pub rows: Vec<Measurement>,
    /// The geometric factor per node of each configuration's map and curves.
    pub fits: Vec<NodeFit>,
}

/// Figures 1 and 5 for `base`: `n = 2..=20` at `h = 0.5` to `T = 10`, the curves sampled
/// at 8 points per step; `name` for the progress report.
pub fn n_refinement<P: Subject>(
    base: &P,
    name: &str,
    progress: &mut dyn Progress,
) -> Result<NRefinement> {
    let nodes: Vec<usize> = (2..=20).collect();
    let t_end = 10.0;
    let reference = Reference::for_subject(base, t_end)?;
    progress.begin(name, (N_CONFIGS.len() * nodes.len()) as u64);
    let mut rows: Vec<Measurement> = Vec::new();
    let mut fits = Vec::new();
    for &(chart, matching) in &N_CONFIGS {
        let mut ms = Vec::new();
        for &n in &nodes {
            ms.push(measure(
                base,
                settings(chart, matching, 0.5, n)?,
                t_end,
                &reference,
                8,
            ));
            progress.advance(1);
        }
        let factor =
            fit::geometric_factor(&ms.iter().map(|m| (m.nodes, m.error_r)).collect::<Vec<_>>());
        let curve_factor = fit::geometric_factor(
            &ms.iter()
                .map(|m| (m.nodes, m.error_curve))
                .collect::<Vec<_>>(),
        );
        fits.push((chart, matching, factor, curve_factor.unwrap_or(f64::NAN)));
        rows.extend(ms);
    }
    progress.end();
    Ok(NRefinement {
        nodes,
        reference: reference.describe(),
        rows,
        fits,
    })
}

impl NRefinement {
    /// The measurements of configuration `i` of [`N_CONFIGS`].
    pub fn config(&self, i: usize) -> &[Measurement] {
        &self.rows[i * self.nodes.len()..(i + 1) * self.nodes.len()]
    }
}

/// Figures 2 and 6: h-refinement, unscaled Cayley chart, T = 10, both matchings.
pub struct HRefinement {
    /// The node counts, one pair of series each.
    pub nodes: Vec<usize>,
    /// The steps.
    pub steps: Vec<f64>,
    /// What the errors are measured against.
    pub reference: String,
    /// Per node count, per matching ([`H_MATCHINGS`]), per step.
    pub rows: Vec<Measurement>,
    /// The fitted order per node count and matching.
    pub orders: Vec<(usize, Matching, Option<f64>)>,
}

/// The matchings of the h-refinement, in the order of [`HRefinement::rows`].
pub const H_MATCHINGS: [Matching; 2] = [Matching::Exact, Matching::Paper];

/// Figures 2 and 6 for `base`: `n = 2..=6` over `h = 1 … 1/32` to `T = 10`, unscaled
/// Cayley chart, both matchings; `name` for the progress report.
pub fn h_refinement<P: Subject>(
    base: &P,
    name: &str,
    progress: &mut dyn Progress,
) -> Result<HRefinement> {
    let nodes = vec![2usize, 3, 4, 5, 6];
    let steps = vec![1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125];
    let t_end = 10.0;
    let reference = Reference::for_subject(base, t_end)?;
    progress.begin(name, (nodes.len() * steps.len() * 2) as u64);
    let mut rows = Vec::new();
    let mut orders = Vec::new();
    for &n in &nodes {
        for &matching in &H_MATCHINGS {
            let mut ms = Vec::new();
            for &h in &steps {
                ms.push(measure(
                    base,
                    settings(ChartKind::CayleyUnscaled, matching, h, n)?,
                    t_end,
                    &reference,
                    1,
                ));
                progress.advance(1);
            }
            let order =
                fit::algebraic_order(&ms.iter().map(|m| (m.h, m.error_r)).collect::<Vec<_>>());
            orders.push((n, matching, order));
            rows.extend(ms);
        }
    }
    progress.end();
    Ok(HRefinement {
        nodes,
        steps,
        reference: reference.describe(),
        rows,
        orders,
    })
}

impl HRefinement {
    /// The series of node count index `i` and matching index `j` (of [`H_MATCHINGS`]).
    pub fn series(&self, i: usize, j: usize) -> &[Measurement] {
        let start = (i * H_MATCHINGS.len() + j) * self.steps.len();
        &self.rows[start..start + self.steps.len()]
    }
}

/// Figures 3 and 7: long runs of each of [`LONG_CONFIGS`].
pub struct EnergyRuns {
    /// Step.
    pub h: f64,
    /// Nodes.
    pub n: usize,
    /// Steps of each run.
    pub steps: usize,
    /// Whether the system is free (it conserves `|μ|²` and all of `Rμ`).
    pub free: bool,
    /// `(configuration, run)`.
    pub runs: Vec<(String, LongRun)>,
}

/// Figures 3 and 7 for `base`: `steps` steps of `(h, n)` in each of [`LONG_CONFIGS`];
/// `name` for the progress report.
pub fn energy_runs<P: Subject>(
    base: &P,
    name: &str,
    (h, n, steps): (f64, usize, usize),
    progress: &mut dyn Progress,
) -> Result<EnergyRuns> {
    progress.begin(name, (LONG_CONFIGS.len() * steps) as u64);
    let mut runs = Vec::new();
    for &(chart, matching) in &LONG_CONFIGS {
        let run = long_run(base, settings(chart, matching, h, n)?, steps, 0, |k| {
            progress.advance(k as u64)
        })?;
        runs.push((label(chart, matching), run));
    }
    progress.end();
    Ok(EnergyRuns {
        h,
        n,
        steps,
        free: base.is_free(),
        runs,
    })
}

/// Figure 4: body momenta on the unit sphere, unscaled Cayley, n = 8, h = 0.5.
pub struct SphereRuns {
    /// Steps of each run.
    pub steps: usize,
    /// The initial momenta's directions.
    pub directions: Vec<[f64; 3]>,
    /// Per matching (exact, then the paper's), one run per direction.
    pub runs: Vec<(Matching, Vec<LongRun>)>,
}

/// Figure 4: 200 steps of `h = 0.5`, `n = 8`, unscaled Cayley chart, both matchings, of
/// the free body `at(μ₀)` started with unit body momentum `μ₀` along each of the
/// figure's directions.
pub fn sphere_runs<P: Subject>(
    at: impl Fn(Vector3<f64>) -> P,
    progress: &mut dyn Progress,
) -> Result<SphereRuns> {
    // Initial body momenta on the unit sphere (case A: J = diag(3.3, 2.5, 3.4)): polhodes
    // about the smallest axis (J = 2.5, body y), about the largest (J = 3.4, body z), and two
    // near the separatrix through the middle axis (J = 3.3, body x).
    let directions = vec![
        [0.1, 1.0, 0.1],
        [0.4, 1.0, 0.2],
        [0.9, 1.0, 0.3],
        [1.0, 0.6, 0.1],
        [0.1, 0.1, 1.0],
        [0.4, 0.2, 1.0],
        [1.0, 0.2, 0.9],
        [1.0, 0.05, 0.3],
        [-0.1, -1.0, 0.1],
        [-0.4, 0.2, -1.0],
        [1.0, 0.0, 0.02],
        [1.0, 0.02, 0.0],
    ];
    let steps = 200;
    progress.begin(
        "fig4_rigid_body_momentum_sphere",
        (directions.len() * 2) as u64,
    );
    let mut runs = Vec::new();
    for matching in [Matching::Exact, Matching::Paper] {
        let mut these = Vec::new();
        for d in &directions {
            let mu = Vector3::from(*d).normalize();
            these.push(long_run(
                &at(mu),
                settings(ChartKind::CayleyUnscaled, matching, 0.5, 8)?,
                steps,
                0,
                |_| {},
            )?);
            progress.advance(1);
        }
        runs.push((matching, these));
    }
    progress.end();
    Ok(SphereRuns {
        steps,
        directions,
        runs,
    })
}

impl SphereRuns {
    /// Per matching, the largest relative drifts of `|μ|²` and of the energy.
    pub fn summary(&self) -> Vec<(Matching, f64, f64)> {
        self.runs
            .iter()
            .map(|(m, runs)| {
                let worst = |f: fn(&LongRun) -> &Vec<f64>| {
                    runs.iter().map(|r| max(f(r))).fold(0.0f64, f64::max)
                };
                (*m, worst(|r| &r.casimir_drift), worst(|r| &r.energy_error))
            })
            .collect()
    }
}

/// Figures 8 and 9: the 3D pendulum near its unstable equilibrium, n = 20, h = 0.6.
pub struct UnstableRuns {
    /// Step.
    pub h: f64,
    /// Nodes.
    pub n: usize,
    /// Steps of each run.
    pub steps: usize,
    /// `(configuration, run)` of each of [`LONG_CONFIGS`], with Galerkin curves.
    pub runs: Vec<(String, LongRun)>,
    /// The run figure 8 shows: the first that completed every step (the paper's chart
    /// with the exact matching, else exp with it, else the paper's own method).
    pub shown: usize,
    /// The shown run's five largest one-step jumps of the energy error:
    /// `(t, |ΔE|/|E₀|, rotation of that step)`.
    pub jumps: Vec<(f64, f64, f64)>,
    /// The shown run's median step rotation.
    pub median_angle: f64,
}

/// Figures 8 and 9: 100 steps of `h = 0.6`, `n = 20` of `base` (the pendulum started near
/// its unstable equilibrium) in each of [`LONG_CONFIGS`], curves sampled at 16 points.
pub fn unstable_runs<P: Subject>(base: &P, progress: &mut dyn Progress) -> Result<UnstableRuns> {
    let (h, n, steps) = (0.6, 20, 100);
    progress.begin(
        "fig8/9 unstable pendulum",
        (LONG_CONFIGS.len() * steps) as u64,
    );
    let mut runs = Vec::new();
    for &(chart, matching) in &LONG_CONFIGS {
        let run = long_run(base, settings(chart, matching, h, n)?, steps, 16, |k| {
            progress.advance(k as u64)
        })?;
        runs.push((label(chart, matching), run));
    }
    progress.end();
    let shown = [0, 2, 1]
        .into_iter()
        .find(|&i| runs[i].1.failure.is_none())
        .unwrap_or(1);
    let exact = &runs[shown].1;
    let mut jumps: Vec<(f64, f64, f64)> = (1..exact.energy_error.len())
        .map(|k| {
            (
                exact.times[k],
                (exact.energy_error[k] - exact.energy_error[k - 1]).abs(),
                exact.step_angle[k - 1],
            )
        })
        .collect();
    jumps.sort_by(|a, b| b.1.total_cmp(&a.1));
    jumps.truncate(5);
    let mut angles: Vec<f64> = exact.step_angle.clone();
    angles.sort_by(f64::total_cmp);
    let median_angle = angles.get(angles.len() / 2).copied().unwrap_or(0.0);
    Ok(UnstableRuns {
        h,
        n,
        steps,
        runs,
        shown,
        jumps,
        median_angle,
    })
}
