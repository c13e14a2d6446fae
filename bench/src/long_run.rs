//! The long run: case A over many steps beside DOP853, its invariants over time, and the
//! energy-trend ensemble.

use crate::error::BenchError;
use crate::so3;
use lgsvi_baselines::{dop853, Dop853State, Model, State};
use lgsvi_experiments::Tracker;
use lgsvi_mechanics::lie::{ChartKind, SO3};
use lgsvi_mechanics::stepper::{each, StepInfo};
use lgsvi_mechanics::Stepper;
use lgsvi_mechanics::{Integrator, StepSettings};
use nalgebra::{Matrix3, Vector3};
use serde::Serialize;
use std::ops::ControlFlow;
use std::time::Instant;

type Result<T> = std::result::Result<T, BenchError>;

/// One sample of the long run: relative energy error, Casimir drift `||μ|² − |μ₀|²|/|μ₀|²`,
/// spatial momentum drift `|Rμ − R₀μ₀|/|μ₀|` and `‖RᵀR − I‖_F`.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Invariants {
    /// Time.
    pub t: f64,
    /// `|E − E₀|/E₀`.
    pub energy: f64,
    /// `||μ|² − |μ₀|²|/|μ₀|²`.
    pub casimir: f64,
    /// `|Rμ − R₀μ₀|/|μ₀|`.
    pub spatial_momentum: f64,
    /// `‖RᵀR − I‖_F`.
    pub orthogonality: f64,
}

fn invariants(t: f64, start: &State, model: &Model, state: &State) -> Invariants {
    // Case A, a free body: all of Rμ is conserved.
    let tracker = Tracker::new(model.energy(start), &start.attitude, &start.momentum, None);
    let drift = tracker.drift(model.energy(state), &state.attitude, &state.momentum);
    Invariants {
        t,
        energy: drift.energy,
        casimir: drift.casimir,
        spatial_momentum: drift.spatial_momentum,
        orthogonality: (state.attitude.transpose() * state.attitude - Matrix3::identity()).norm(),
    }
}

/// The settings of the long run and of its trend ensemble: exp chart, `h` and `n` as given
/// (the defaults, h = 0.5 and n = 8, are the issue's).
pub fn long_run_settings(h: f64, n: usize) -> Result<StepSettings> {
    Ok(StepSettings::new(h, n)?.with_chart(ChartKind::Exp))
}

/// The long run: lgsvi (case A, `settings`) for `steps` steps beside
/// DOP853 on the matrix state (tolerance 1e-13, restarted at each of the `samples`
/// sample times: sparse output) over the same horizon; both timed. Returns the samples
/// and the wall times `(lgsvi, DOP853)`.
pub fn long_run(
    settings: StepSettings,
    steps: usize,
    samples: usize,
    mut tick: impl FnMut(u64),
) -> Result<LongRun> {
    let case = so3::case_a();
    let h = settings.h();
    let every = (steps / samples.max(1)).max(1);
    let w0 = case.model.velocity(&case.start.momentum);
    let mut integrator = Integrator::new(so3::free_body(&case)?, settings, SO3::identity(), w0)?;
    let as_state = |s: &lgsvi_mechanics::State| State {
        attitude: *s.attitude().matrix(),
        momentum: s.momentum,
    };
    let mut lgsvi = vec![invariants(0.0, &case.start, &case.model, &case.start)];
    let clock = Instant::now();
    let mut reported = 0;
    let sample = |it: &Integrator<_>, step: StepInfo| {
        let k = step.index;
        if k.is_multiple_of(every) || step.last {
            let s = as_state(it.state());
            lgsvi.push(invariants(k as f64 * h, &case.start, &case.model, &s));
            tick((k - reported) as u64);
            reported = k;
        }
        Ok::<_, BenchError>(ControlFlow::Continue(()))
    };
    integrator.drive(steps, &mut each(sample))?;
    // The clock includes the sampling: a few µs per sample, against ~0.1 s between samples.
    let lgsvi_time = clock.elapsed().as_secs_f64();
    let mut dop = vec![invariants(0.0, &case.start, &case.model, &case.start)];
    let mut state = case.start;
    let segment = every as f64 * h;
    let clock = Instant::now();
    let mut t = 0.0;
    while t < steps as f64 * h - 1e-9 {
        let span = segment.min(steps as f64 * h - t);
        state = dop853(&case.model, &state, span, 1e-13, Dop853State::Matrix)?.0;
        t += span;
        dop.push(invariants(t, &case.start, &case.model, &state));
    }
    let dop_time = clock.elapsed().as_secs_f64();
    let nodes = integrator.nodes_used().collect();
    Ok(LongRun {
        lgsvi,
        dop,
        lgsvi_time,
        dop_time,
        nodes,
    })
}

/// The long run's samples and times, and the steps lgsvi took per node count.
pub struct LongRun {
    /// lgsvi's samples, from `t = 0`.
    pub lgsvi: Vec<Invariants>,
    /// DOP853's samples at the same times.
    pub dop: Vec<Invariants>,
    /// lgsvi's wall time, seconds.
    pub lgsvi_time: f64,
    /// DOP853's wall time, seconds.
    pub dop_time: f64,
    /// `(n, steps with n nodes)`.
    pub nodes: Vec<(usize, usize)>,
}

/// The signed end values of an ensemble: mean, its standard error, rms.
#[derive(Debug, Clone, Serialize)]
pub struct Spread {
    /// One value per member, in member order.
    pub values: Vec<f64>,
    /// Mean.
    pub mean: f64,
    /// Standard error of the mean, `sd/√members`.
    pub standard_error: f64,
    /// Root mean square.
    pub rms: f64,
}

impl Spread {
    fn new(values: Vec<f64>) -> Self {
        let count = values.len() as f64;
        let mean = values.iter().sum::<f64>() / count;
        let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (count - 1.0);
        let rms = (values.iter().map(|v| v * v).sum::<f64>() / count).sqrt();
        Self {
            values,
            mean,
            standard_error: (variance / count).sqrt(),
            rms,
        }
    }

    /// No trend: the mean is within three standard errors of zero.
    pub fn consistent_with_zero(&self) -> bool {
        self.mean.abs() <= 3.0 * self.standard_error
    }
}

/// The long run's trend test: one trajectory cannot tell a linear drift from a random
/// walk of rounding errors, an ensemble can. Signed relative errors of the energy and of
/// `|μ|²` after the same steps, over initial conditions near case A's.
#[derive(Debug, Clone, Serialize)]
pub struct EnergyTrend {
    /// Members.
    pub members: usize,
    /// Steps of each.
    pub steps: usize,
    /// `(E − E₀)/E₀` at the end.
    pub energy: Spread,
    /// `(|μ|² − |μ₀|²)/|μ₀|²` at the end.
    pub casimir: Spread,
    /// Wall time of the ensemble on every core (s).
    pub seconds: f64,
}

/// Runs [`EnergyTrend`]: member `k` starts from case A's `Ω₀` scaled by `1 + 10⁻³k` and
/// shifted by `10⁻³k` along the body y axis (`settings`), on rayon's pool.
pub fn energy_trend(
    settings: StepSettings,
    steps: usize,
    members: usize,
    tick: impl Fn(u64) + Sync,
) -> Result<EnergyTrend> {
    use rayon::prelude::*;
    let case = so3::case_a();
    let system = so3::free_body(&case)?;
    let w0 = case.model.velocity(&case.start.momentum);
    let clock = Instant::now();
    let ends: Vec<(f64, f64)> = (0..members)
        .into_par_iter()
        .map(|k| {
            let shift = 1e-3 * k as f64;
            let velocity = w0 * (1.0 + shift) + Vector3::y() * shift;
            let failed = |source| BenchError::Run {
                context: format!("trend member {k}"),
                source,
            };
            let mut integrator =
                Integrator::new(system, settings, SO3::identity(), velocity).map_err(failed)?;
            let (e0, c0) = (
                integrator.state().energy(&system),
                integrator.state().casimir(),
            );
            const TICK: usize = 10_000;
            for step in 1..=steps {
                integrator.step().map_err(failed)?;
                if step % TICK == 0 {
                    tick(TICK as u64);
                }
            }
            let end = integrator.state();
            Ok(((end.energy(&system) - e0) / e0, (end.casimir() - c0) / c0))
        })
        .collect::<Result<_>>()?;
    Ok(EnergyTrend {
        members,
        steps,
        energy: Spread::new(ends.iter().map(|e| e.0).collect()),
        casimir: Spread::new(ends.iter().map(|e| e.1).collect()),
        seconds: clock.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_spread_has_the_textbook_mean_standard_error_and_rms() {
        // Values 5, 6, 7, 10: mean 7, sample variance (4 + 1 + 0 + 9)/3 = 14/3, standard
        // error √(14/3/4) ≈ 1.08 (so the mean is 6.5 of them from zero), rms √(210/4).
        let s = Spread::new(vec![5.0, 6.0, 7.0, 10.0]);
        assert_eq!(s.mean, 7.0);
        assert!((s.standard_error - (14.0f64 / 12.0).sqrt()).abs() < 1e-15);
        assert!((s.rms - 52.5f64.sqrt()).abs() < 1e-14);
        assert!(!s.consistent_with_zero());
        // Symmetric about zero: no trend.
        assert!(Spread::new(vec![-1e-13, 2e-13, -2e-13, 1e-13]).consistent_with_zero());
    }
}
