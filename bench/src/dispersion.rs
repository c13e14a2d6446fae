//! Monte Carlo throughput: dispersed members of case A, each run to T = 100 at an attitude
//! accuracy of 1e-10, by lgsvi and by DOP853 on the same threads, side by side.
//!
//! The members are `lgsvi_montecarlo`'s draws about case A (start rates dispersed by
//! 0.02 rad/s per axis, the principal moments by 1% truncated at 3%), so both methods run
//! the same bodies from the same starts. The settings are chosen on the nominal, whose
//! 40-digit reference is known, each at most [`TARGET`] off in attitude at T = 100:
//! DOP853's loosest tolerance (half decades), and lgsvi's cheapest `(h, n)`: at each step
//! of [`STEPS`] the fewest nodes within the target, timed on a sample of the members, the
//! fastest taken (every candidate is reported). The members are then checked against each
//! other: the two methods' final attitudes agree to `agreement` (each is within about
//! [`TARGET`] of the truth, so a few times that).

use crate::error::BenchError;
use crate::so3::case_a;
use lgsvi_baselines::{dop853, Dop853State, Model, State};
use lgsvi_experiments::work_precision::median_time;
use lgsvi_mechanics::lie::{ChartKind, SO3};
use lgsvi_mechanics::{Integrator, RigidBody, StepSettings, Stepper};
use lgsvi_montecarlo::{Body, Dispersion, Dispersions, Member, Plan};
use nalgebra::Matrix3;
use rayon::prelude::*;
use serde::Serialize;

type Result<T> = std::result::Result<T, BenchError>;

/// The attitude accuracy every member is run to (max entry of `R − R_ref` at T = 100, on
/// the nominal).
pub const TARGET: f64 = 1e-10;

/// The horizon.
pub const T_END: f64 = 100.0;

/// lgsvi's steps tried (each divides [`T_END`]): from the h = 0.5 of the paper's
/// figures to the largest at which few nodes still reach [`TARGET`] (at h = 1.6 case A
/// needs more than 24 nodes).
pub const STEPS: [f64; 4] = [0.5, 0.8, 1.0, 1.25];

/// Members in the sample that times each candidate setting.
pub const SAMPLE: usize = 200;

/// One of lgsvi's candidate settings: a step and its fewest nodes within [`TARGET`].
#[derive(Debug, Clone, Serialize)]
pub struct Candidate {
    /// The step.
    pub h: f64,
    /// The fewest nodes within [`TARGET`] on the nominal at this step.
    pub nodes: usize,
    /// The nominal's attitude error at T = 100 with them.
    pub nominal_error: f64,
    /// One thread's wall time over the sample's members (s, median of the repeats).
    pub sample_s: f64,
}

/// What [`throughput`] measured.
#[derive(Debug, Clone, Serialize)]
pub struct Throughput {
    /// Members run by each method.
    pub members: usize,
    /// Threads of the parallel runs.
    pub threads: usize,
    /// lgsvi's step (the cheapest of [`Throughput::candidates`]).
    pub lgsvi_step: f64,
    /// lgsvi's nodes at that step (the fewest within [`TARGET`] on the nominal).
    pub lgsvi_nodes: usize,
    /// lgsvi's nominal attitude error at T = 100 with them.
    pub lgsvi_nominal_error: f64,
    /// DOP853's tolerance (the loosest within [`TARGET`] on the nominal, quaternion
    /// state).
    pub dop853_tolerance: f64,
    /// DOP853's nominal attitude error at T = 100 with it.
    pub dop853_nominal_error: f64,
    /// lgsvi's wall time on one thread (s).
    pub lgsvi_one_thread_s: f64,
    /// lgsvi's wall time on `threads` threads (s).
    pub lgsvi_parallel_s: f64,
    /// DOP853's wall time on `threads` threads (s).
    pub dop853_parallel_s: f64,
    /// `lgsvi_one_thread_s / lgsvi_parallel_s`.
    pub lgsvi_scaling: f64,
    /// `lgsvi_parallel_s / dop853_parallel_s`: lgsvi's time against DOP853's (the goal is
    /// at most 1).
    pub time_ratio: f64,
    /// The largest difference of the two methods' final attitudes over the members.
    pub agreement: f64,
    /// Members that failed (either method).
    pub failures: usize,
    /// lgsvi's settings tried, each timed on the first [`SAMPLE`] members.
    pub candidates: Vec<Candidate>,
}

/// The members' plan: case A's nominal, its rates and principal moments dispersed.
fn plan(seed: u64) -> Result<(Plan, Model)> {
    let case = case_a();
    let inertia = *crate::so3::free_body(&case)?.inertia();
    let omega = case.model.velocity(&case.start.momentum);
    let nominal = Body::new(
        inertia,
        SO3::from_matrix_unchecked(case.start.attitude),
        omega,
    );
    let dispersions = Dispersions {
        omega: Some(Dispersion::Normal { sigma: 0.02 }),
        inertia: Some(Dispersion::TruncatedNormal {
            sigma: 0.01,
            bound: 0.03,
        }),
        ..Dispersions::default()
    };
    let plan = Plan::new(nominal, dispersions, seed)
        .map_err(|e| BenchError::Setup(format!("the dispersion plan: {e}")))?;
    Ok((plan, case.model))
}

/// A body's run by lgsvi: its final attitude.
fn lgsvi_member(body: &Body, h: f64, nodes: usize) -> Result<Matrix3<f64>> {
    let settings = StepSettings::new(h, nodes)?.with_chart(ChartKind::Exp);
    let mut it = Integrator::new(
        RigidBody::new(body.inertia),
        settings,
        body.attitude,
        body.omega,
    )?;
    let steps = (T_END / h).round() as usize;
    it.run(steps, steps)?;
    Ok(*it.state().attitude().matrix())
}

/// A body's run by DOP853 (quaternion state): its final attitude.
fn dop853_member(body: &Body, tolerance: f64) -> Result<Matrix3<f64>> {
    let moments = body.inertia.principal_moments();
    let model = Model::free(moments);
    let start = State {
        attitude: *body.attitude.matrix(),
        momentum: nalgebra::Vector3::from(moments).component_mul(&body.omega),
    };
    let (end, _) = dop853(&model, &start, T_END, tolerance, Dop853State::Quaternion)?;
    Ok(end.attitude)
}

/// Measures [`Throughput`] over `members` members of `seed`, medians of `repeats`.
///
/// # Errors
/// A member's draw or a run that fails while choosing the settings.
pub fn throughput(members: usize, seed: u64, repeats: usize) -> Result<Throughput> {
    let (plan, _) = plan(seed)?;
    let reference = crate::reference("A", T_END);
    let error = |r: Matrix3<f64>| (r - reference).amax();
    let nominal = plan.nominal().clone();
    let (mut dop853_tolerance, mut dop853_nominal_error) = (0.0, f64::INFINITY);
    for k in 0..=14 {
        let tol = 1e-7 / 10f64.powf(k as f64 / 2.0);
        let e = error(dop853_member(&nominal, tol)?);
        if e <= TARGET {
            (dop853_tolerance, dop853_nominal_error) = (tol, e);
            break;
        }
    }
    let bodies: Vec<Member> = (0..members as u64)
        .map(|i| plan.member(i))
        .collect::<std::result::Result<_, _>>()
        .map_err(|e| BenchError::Setup(format!("a member's draw: {e}")))?;
    let candidates = candidates(&nominal, &bodies[..bodies.len().min(SAMPLE)], repeats)?;
    let cheapest = candidates
        .iter()
        .min_by(|a, b| a.sample_s.total_cmp(&b.sample_s))
        .cloned();
    let (Some(cheapest), true) = (cheapest, dop853_tolerance > 0.0) else {
        return Err(BenchError::Setup(format!(
            "no setting reached {TARGET:e} on the nominal (lgsvi n ≤ 24 at h in {STEPS:?}, \
             DOP853 tol ≥ 1e-14)"
        )));
    };
    let (lgsvi_step, lgsvi_nodes) = (cheapest.h, cheapest.nodes);
    let run_lgsvi = || -> Vec<Option<Matrix3<f64>>> {
        bodies
            .par_iter()
            .map(|m| lgsvi_member(&m.body, lgsvi_step, lgsvi_nodes).ok())
            .collect()
    };
    let run_dop853 = || -> Vec<Option<Matrix3<f64>>> {
        bodies
            .par_iter()
            .map(|m| dop853_member(&m.body, dop853_tolerance).ok())
            .collect()
    };
    let pool = |threads: usize| rayon::ThreadPoolBuilder::new().num_threads(threads).build();
    let threads = rayon::current_num_threads();
    let (one, all) = (pool(1)?, pool(threads)?);
    let (mut t1, mut tp, mut td) = (Vec::new(), Vec::new(), Vec::new());
    let (mut ours, mut theirs) = (Vec::new(), Vec::new());
    // Alternating, repeat by repeat: a load that comes or goes affects all three alike.
    for _ in 0..repeats.max(1) {
        t1.push(one.install(|| median_time(1, run_lgsvi)).1);
        let (r, t) = all.install(|| median_time(1, run_lgsvi));
        tp.push(t);
        ours = r;
        let (r, t) = all.install(|| median_time(1, run_dop853));
        td.push(t);
        theirs = r;
    }
    let median = lgsvi_experiments::work_precision::median;
    let (lgsvi_one_thread_s, lgsvi_parallel_s, dop853_parallel_s) =
        (median(t1), median(tp), median(td));
    let mut failures = 0;
    let mut agreement = 0.0f64;
    for (a, b) in ours.iter().zip(&theirs) {
        match (a, b) {
            (Some(a), Some(b)) => agreement = agreement.max((a - b).amax()),
            _ => failures += 1,
        }
    }
    Ok(Throughput {
        members,
        threads,
        lgsvi_step,
        lgsvi_nodes,
        lgsvi_nominal_error: cheapest.nominal_error,
        dop853_tolerance,
        dop853_nominal_error,
        lgsvi_one_thread_s,
        lgsvi_parallel_s,
        dop853_parallel_s,
        lgsvi_scaling: lgsvi_one_thread_s / lgsvi_parallel_s,
        time_ratio: lgsvi_parallel_s / dop853_parallel_s,
        agreement,
        failures,
        candidates,
    })
}

/// lgsvi's candidate settings: at each of [`STEPS`], the fewest nodes (6 to 24) within
/// [`TARGET`] on the nominal, timed on one thread over `sample` (median of `repeats`).
fn candidates(nominal: &Body, sample: &[Member], repeats: usize) -> Result<Vec<Candidate>> {
    let reference = crate::reference("A", T_END);
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let mut found = Vec::new();
    for h in STEPS {
        // A run that fails (Newton at a step too large for its nodes) is a setting that
        // does not reach the target.
        let reaching = (6..=24).find_map(|n| {
            let e = (lgsvi_member(nominal, h, n).ok()? - reference).amax();
            (e <= TARGET).then_some((n, e))
        });
        let Some((nodes, nominal_error)) = reaching else {
            continue;
        };
        let run = || -> Vec<Option<Matrix3<f64>>> {
            sample
                .par_iter()
                .map(|m| lgsvi_member(&m.body, h, nodes).ok())
                .collect()
        };
        let (_, sample_s) = one.install(|| median_time(repeats.max(1), run));
        found.push(Candidate {
            h,
            nodes,
            nominal_error,
            sample_s,
        });
    }
    Ok(found)
}
