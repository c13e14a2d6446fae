//! Convergence studies: n-refinement and h-refinement of an SO(3) system against the exact
//! free-body solution or a high-accuracy run, with fitted rates.
//!
//! Every run of a study keeps its [`Subject`]'s chart, matching and Newton Jacobian and
//! varies only the step `h` and the node count `n`. A run that fails (Newton, the chart's
//! domain) is kept in the results with its reason and NaN errors: a study reports where the
//! method stops working rather than stopping itself.

use crate::conserved::largest;
use crate::error::ExperimentError;
use crate::fit::{algebraic_order, geometric_factor};
use crate::subject::Subject;
use lgsvi_mechanics::exact::FreeRigidBodyExact;
use lgsvi_mechanics::integrator::GalerkinCurve;
use lgsvi_mechanics::lie::{ChartKind, SO3};
use lgsvi_mechanics::stepper::{each, StepInfo};
use lgsvi_mechanics::Stepper;
use lgsvi_mechanics::{Integrator, Matching, StepSettings};
use nalgebra::{Matrix3, Vector3};
use serde::Serialize;
use std::ops::ControlFlow;
use std::time::Instant;

/// The step of the high-accuracy reference run used when no exact solution is known.
///
/// With [`REFERENCE_NODES`], the exp chart and the exact matching, this run is within
/// 1e-12 (4.5e-14 to 7.4e-13 depending on rounding) of 40-digit references of the paper's
/// pendulum with m g = 9.81 and 1, up to t = 10 (the workspace's `exact_solution` tests).
pub const REFERENCE_STEP: f64 = 0.25;
/// Nodes of the high-accuracy reference run.
pub const REFERENCE_NODES: usize = 20;

/// The most points per step at which a study compares the Galerkin curve.
pub const MAX_CURVE_SAMPLES: usize = 1000;

/// What the errors are measured against.
pub enum Reference {
    /// The closed-form free rigid body.
    Exact(Box<FreeRigidBodyExact>),
    /// A high-accuracy run, with its nodal states and Galerkin curves as dense output.
    Dense {
        /// Its step ([`REFERENCE_STEP`]).
        step: f64,
        /// `(R, Ω)` at every step's end, from `t = 0`.
        states: Vec<(SO3, Vector3<f64>)>,
        /// Every step's Galerkin curve.
        curves: Vec<GalerkinCurve>,
        /// Its own error estimate: the difference at the final time to a run with 4 more
        /// nodes.
        self_check: f64,
    },
}

impl Reference {
    /// The exact solution where the subject has one, otherwise a high-accuracy run to
    /// `t_end` ([`REFERENCE_STEP`], [`REFERENCE_NODES`], exp chart, exact matching) and a
    /// second one with 4 more nodes as its self-check.
    pub fn for_subject<P: Subject>(subject: &P, t_end: f64) -> Result<Self, ExperimentError> {
        if let Some(exact) = subject.exact() {
            return Ok(Reference::Exact(Box::new(exact?)));
        }
        let run = |nodes: usize| -> Result<(Vec<_>, Vec<_>), ExperimentError> {
            let settings = StepSettings::new(REFERENCE_STEP, nodes)?
                .with_chart(ChartKind::Exp)
                .with_matching(Matching::Exact);
            let mut integrator = subject.integrator(settings)?;
            let steps = integrator.steps_until(t_end)?;
            let mut states = vec![(*integrator.state().attitude(), integrator.state().velocity)];
            let mut curves = Vec::with_capacity(steps);
            let record = |it: &Integrator<P::System>, _: StepInfo| {
                states.push((*it.state().attitude(), it.state().velocity));
                curves.extend(it.last_curve());
                Ok::<_, lgsvi_mechanics::MechanicsError>(ControlFlow::Continue(()))
            };
            integrator
                .drive(steps, &mut each(record))
                .map_err(|source| ExperimentError::Run {
                    context: reference_context(REFERENCE_STEP, nodes),
                    source,
                })?;
            Ok((states, curves))
        };
        let (states, curves) = run(REFERENCE_NODES)?;
        let (check, _) = run(REFERENCE_NODES + 4)?;
        let (a, b) = (states.last(), check.last());
        let self_check = match (a, b) {
            (Some(a), Some(b)) => (a.0.matrix() - b.0.matrix()).norm(),
            _ => 0.0,
        };
        Ok(Reference::Dense {
            step: REFERENCE_STEP,
            states,
            curves,
            self_check,
        })
    }

    /// One line saying what the reference is.
    pub fn describe(&self) -> String {
        match self {
            Reference::Exact(_) => {
                "the exact solution (Jacobi elliptic functions, lgsvi_mechanics::exact)".into()
            }
            Reference::Dense { self_check, .. } => format!(
                "a high-accuracy run (exp chart, exact matching, h = {REFERENCE_STEP}, \
                 n = {REFERENCE_NODES}; differs from n = {} by {self_check:.1e} at the final time)",
                REFERENCE_NODES + 4
            ),
        }
    }

    /// `(R(t), Ω(t))`: at a step's end from the stored state, inside a step from its
    /// Galerkin curve.
    pub fn at(&self, t: f64) -> Result<(Matrix3<f64>, Vector3<f64>), ExperimentError> {
        match self {
            Reference::Exact(body) => {
                let s = body.state(t)?;
                Ok((*s.attitude().matrix(), s.velocity))
            }
            Reference::Dense {
                step,
                states,
                curves,
                ..
            } => {
                let k = (t / step).round();
                if (t - k * step).abs() <= 1e-12 * t.abs().max(1.0) && (k as usize) < states.len() {
                    let (r, w) = &states[k as usize];
                    return Ok((*r.matrix(), *w));
                }
                let k = ((t / step).floor() as usize).min(curves.len().saturating_sub(1));
                let curve = curves.get(k).ok_or(ExperimentError::NoReferenceCurve(t))?;
                let (g, w) = curve.at(t - curve.start())?;
                Ok((*g.matrix(), w))
            }
        }
    }
}

/// One run of a study.
#[derive(Debug, Clone, Serialize)]
pub struct Measurement {
    /// The chart's name.
    pub chart: String,
    /// `"exact"` or `"paper"`.
    pub matching: String,
    /// Nodes `n`.
    pub nodes: usize,
    /// Polynomial degree `n − 1`.
    pub degree: usize,
    /// Step.
    pub h: f64,
    /// Steps taken.
    pub steps: usize,
    /// The final time reached.
    pub t_end: f64,
    /// `‖R(T) − R_ref(T)‖_F` at the final time (the one-step map's global error).
    pub error_r: f64,
    /// `|Ω(T) − Ω_ref(T)|`.
    pub error_omega: f64,
    /// Largest `‖R(t) − R_ref(t)‖_F` on the Galerkin curves, sampled inside every step.
    pub error_curve: f64,
    /// Largest `|E − E₀|/|E₀|` over the steps.
    pub energy_error: f64,
    /// Largest drift of the conserved spatial momentum ([`crate::Drift`]); NaN for a system
    /// that conserves none ([`crate::Symmetry::None`]: under a torque or damping).
    pub momentum_drift: f64,
    /// Newton iterations over the run.
    pub newton_iterations: usize,
    /// Wall time of the steps (construction excluded), seconds.
    pub wall_time_s: f64,
    /// Why the run stopped, if it failed (Newton, chart): the errors are then NaN.
    pub failure: Option<String>,
}

/// Runs `settings` on `subject` to `t_end` and measures it against `reference`, sampling
/// each step's Galerkin curve at `curve_samples − 1` interior points (none for
/// `curve_samples ≤ 1`, and then `error_curve` is NaN). A failed run comes back with its
/// reason in `failure`.
pub fn measure<P: Subject>(
    subject: &P,
    settings: StepSettings,
    t_end: f64,
    reference: &Reference,
    curve_samples: usize,
) -> Measurement {
    let mut m = Measurement {
        chart: settings.chart().to_string(),
        matching: format!("{:?}", settings.matching()).to_lowercase(),
        nodes: settings.nodes(),
        degree: settings.degree(),
        h: settings.h(),
        steps: 0,
        t_end,
        error_r: f64::NAN,
        error_omega: f64::NAN,
        error_curve: f64::NAN,
        energy_error: f64::NAN,
        momentum_drift: f64::NAN,
        newton_iterations: 0,
        wall_time_s: 0.0,
        failure: None,
    };
    if let Err(e) = measure_into(subject, settings, t_end, reference, curve_samples, &mut m) {
        m.failure = Some(e.to_string());
        m.error_r = f64::NAN;
        m.error_omega = f64::NAN;
        m.error_curve = f64::NAN;
    }
    m
}

fn measure_into<P: Subject>(
    subject: &P,
    settings: StepSettings,
    t_end: f64,
    reference: &Reference,
    curve_samples: usize,
    m: &mut Measurement,
) -> Result<(), ExperimentError> {
    let mut integrator = subject.integrator(settings)?;
    let steps = integrator.steps_until(t_end)?;
    let system = subject.system();
    let s0 = *integrator.state();
    let tracker = subject.tracker(&s0);
    let (mut energy_error, mut drift, mut curve_error) = (0.0f64, 0.0f64, 0.0f64);
    let start = Instant::now();
    // After every step: the drifts, and the Galerkin curve against the reference.
    let observe = |integrator: &Integrator<P::System>, _: StepInfo| {
        let s = integrator.state();
        let d = tracker.drift(s.energy(system), s.attitude().matrix(), &s.momentum);
        energy_error = energy_error.max(d.energy);
        drift = largest(drift, d.spatial_momentum);
        if curve_samples > 1 {
            if let Some(curve) = integrator.last_curve() {
                for j in 1..curve_samples {
                    let tau = curve.step() * j as f64 / curve_samples as f64;
                    let (g, _) = curve.at(tau)?;
                    let (r_ref, _) = reference.at(curve.start() + tau)?;
                    curve_error = curve_error.max((g.matrix() - r_ref).norm());
                }
            }
        }
        Ok::<_, ExperimentError>(ControlFlow::Continue(()))
    };
    integrator.drive(steps, &mut each(observe))?;
    m.wall_time_s = start.elapsed().as_secs_f64();
    let s = integrator.state();
    let (r_ref, w_ref) = reference.at(s.time)?;
    m.steps = steps;
    m.t_end = s.time;
    m.error_r = (s.attitude().matrix() - r_ref).norm();
    m.error_omega = (s.velocity - w_ref).norm();
    m.error_curve = if curve_samples > 1 {
        curve_error.max(m.error_r)
    } else {
        f64::NAN
    };
    m.energy_error = energy_error;
    m.momentum_drift = drift;
    m.newton_iterations = integrator.statistics().newton_iterations;
    Ok(())
}

/// What a study runs: n-refinement over `nodes` at step `h`, and h-refinement over `steps`
/// for each of `step_nodes`, every run to `t_end`.
#[derive(Debug, Clone, PartialEq)]
pub struct Refinement {
    /// The step of the n-refinement.
    pub h: f64,
    /// The node counts of the n-refinement (none: no n-refinement).
    pub nodes: Vec<usize>,
    /// The steps of the h-refinement (none: no h-refinement).
    pub steps: Vec<f64>,
    /// The node counts at which the h-refinement runs.
    pub step_nodes: Vec<usize>,
    /// The final time of every run.
    pub t_end: f64,
    /// Points per step at which the Galerkin curve is compared (`curve_samples − 1`
    /// interior points; at most [`MAX_CURVE_SAMPLES`] is sensible).
    pub curve_samples: usize,
}

impl Refinement {
    /// The number of runs: `nodes.len() + steps.len() · step_nodes.len()`.
    pub fn runs(&self) -> usize {
        self.nodes.len() + self.steps.len() * self.step_nodes.len()
    }
}

/// A study's results.
#[derive(Debug, Clone, Serialize)]
pub struct Study {
    /// What the errors were measured against ([`Reference::describe`]).
    pub reference: String,
    /// The n-refinement's runs, in the order of [`Refinement::nodes`].
    pub nodes_refinement: Vec<Measurement>,
    /// The h-refinement's runs, by node count then step.
    pub step_refinement: Vec<Measurement>,
    /// `(chart, matching, h, factor per node)`: the n-refinement's
    /// [`geometric_factor`] of `‖R(T) − R_ref(T)‖`.
    pub geometric_factors: Vec<(String, String, f64, Option<f64>)>,
    /// `(chart, matching, n, order)`: each node count's [`algebraic_order`].
    pub orders: Vec<(String, String, usize, Option<f64>)>,
}

/// Runs `refinement` on `subject` against `reference`, calling `tick` after each run (for
/// progress). Settings that the method refuses (a step that is not positive, a node count
/// out of range) are errors; runs that fail are kept with their reason.
pub fn study<P: Subject>(
    subject: &P,
    reference: &Reference,
    refinement: &Refinement,
    mut tick: impl FnMut(),
) -> Result<Study, ExperimentError> {
    let base = subject.settings();
    let t_end = refinement.t_end;
    let curve_samples = refinement.curve_samples;
    let with = |h: f64, n: usize| -> Result<StepSettings, ExperimentError> {
        let mut s = StepSettings::new(h, n)?
            .with_chart(base.chart())
            .with_matching(base.matching())
            .with_jacobian(base.jacobian());
        if base.quadrature_points()
            != base.nodes() + lgsvi_mechanics::settings::DEFAULT_EXTRA_QUADRATURE_POINTS
        {
            s = s.with_quadrature_points(base.quadrature_points().max(n))?;
        }
        Ok(s)
    };
    let mut nodes_refinement = Vec::new();
    for &n in &refinement.nodes {
        nodes_refinement.push(measure(
            subject,
            with(refinement.h, n)?,
            t_end,
            reference,
            curve_samples,
        ));
        tick();
    }
    let mut step_refinement = Vec::new();
    for &n in &refinement.step_nodes {
        for &hh in &refinement.steps {
            step_refinement.push(measure(
                subject,
                with(hh, n)?,
                t_end,
                reference,
                curve_samples,
            ));
            tick();
        }
    }
    let chart = base.chart().to_string();
    let matching = format!("{:?}", base.matching()).to_lowercase();
    let geometric_factors = if nodes_refinement.is_empty() {
        Vec::new()
    } else {
        let points: Vec<(usize, f64)> = nodes_refinement
            .iter()
            .map(|m| (m.nodes, m.error_r))
            .collect();
        vec![(
            chart.clone(),
            matching.clone(),
            refinement.h,
            geometric_factor(&points),
        )]
    };
    let orders = refinement
        .step_nodes
        .iter()
        .map(|&n| {
            let points: Vec<(f64, f64)> = step_refinement
                .iter()
                .filter(|m| m.nodes == n)
                .map(|m| (m.h, m.error_r))
                .collect();
            (chart.clone(), matching.clone(), n, algebraic_order(&points))
        })
        .collect();
    Ok(Study {
        reference: reference.describe(),
        nodes_refinement,
        step_refinement,
        geometric_factors,
        orders,
    })
}

/// The context of a failed reference run: its step and nodes are the study's own (not the
/// run's `h` and `n`), so a motion that needs a shorter step is beyond the study.
pub(crate) fn reference_context(h: f64, nodes: usize) -> String {
    format!(
        "the study's reference run (its own h = {h}, {nodes} nodes, not the run's: a motion \
         that needs a shorter step than that is beyond this study; run it with a tolerance \
         instead)"
    )
}
