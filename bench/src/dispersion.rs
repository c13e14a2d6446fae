//! Monte Carlo throughput: dispersed members of case A, each run to T = 100 at an attitude
//! accuracy of 1e-10, by lgsvi and by DOP853 on the same threads, side by side.
//!
//! The members are `lgsvi_montecarlo`'s draws about case A (start rates dispersed by
//! 0.02 rad/s per axis, the principal moments by 1% truncated at 3%), so both methods run
//! the same bodies from the same starts. The settings are chosen on the nominal, whose
//! 40-digit reference is known: lgsvi's fewest nodes at `h = 0.5`, DOP853's loosest
//! tolerance (half decades), each at most [`TARGET`] off in attitude at T = 100. The
//! members are then checked against each other: the two methods' final attitudes agree to
//! `agreement` (each is within about [`TARGET`] of the truth, so a few times that).

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

/// lgsvi's step.
const H: f64 = 0.5;

/// What [`throughput`] measured.
#[derive(Debug, Clone, Serialize)]
pub struct Throughput {
    /// Members run by each method.
    pub members: usize,
    /// Threads of the parallel runs.
    pub threads: usize,
    /// lgsvi's nodes at `h = 0.5` (the fewest within [`TARGET`] on the nominal).
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
fn lgsvi_member(body: &Body, nodes: usize) -> Result<Matrix3<f64>> {
    let settings = StepSettings::new(H, nodes)?.with_chart(ChartKind::Exp);
    let mut it = Integrator::new(
        RigidBody::new(body.inertia),
        settings,
        body.attitude,
        body.omega,
    )?;
    let steps = (T_END / H).round() as usize;
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
    let (mut lgsvi_nodes, mut lgsvi_nominal_error) = (0, f64::INFINITY);
    for n in 6..=24 {
        let e = error(lgsvi_member(&nominal, n)?);
        if e <= TARGET {
            (lgsvi_nodes, lgsvi_nominal_error) = (n, e);
            break;
        }
    }
    let (mut dop853_tolerance, mut dop853_nominal_error) = (0.0, f64::INFINITY);
    for k in 0..=14 {
        let tol = 1e-7 / 10f64.powf(k as f64 / 2.0);
        let e = error(dop853_member(&nominal, tol)?);
        if e <= TARGET {
            (dop853_tolerance, dop853_nominal_error) = (tol, e);
            break;
        }
    }
    if lgsvi_nodes == 0 || dop853_tolerance == 0.0 {
        return Err(BenchError::Setup(format!(
            "no setting reached {TARGET:e} on the nominal (lgsvi n ≤ 24, DOP853 tol ≥ 1e-14)"
        )));
    }
    let bodies: Vec<Member> = (0..members as u64)
        .map(|i| plan.member(i))
        .collect::<std::result::Result<_, _>>()
        .map_err(|e| BenchError::Setup(format!("a member's draw: {e}")))?;
    let run_lgsvi = || -> Vec<Option<Matrix3<f64>>> {
        bodies
            .par_iter()
            .map(|m| lgsvi_member(&m.body, lgsvi_nodes).ok())
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
        lgsvi_nodes,
        lgsvi_nominal_error,
        dop853_tolerance,
        dop853_nominal_error,
        lgsvi_one_thread_s,
        lgsvi_parallel_s,
        dop853_parallel_s,
        lgsvi_scaling: lgsvi_one_thread_s / lgsvi_parallel_s,
        time_ratio: lgsvi_parallel_s / dop853_parallel_s,
        agreement,
        failures,
    })
}
