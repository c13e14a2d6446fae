//! Convergence studies: n-refinement and h-refinement against the exact free-body solution
//! or a high-accuracy run, with fitted rates; `lgsvi converge`.

use crate::config::{node_count, node_range, positive_step, ConvergeOptions, Format, StudyKind};
use crate::error::{CliError, Result};
use crate::problem::{whole_steps, Problem};
use lgsvi_mechanics::exact::FreeRigidBodyExact;
use lgsvi_mechanics::lie::{ChartKind, SO3};
use lgsvi_mechanics::{GalerkinCurve, Matching, StepSettings};
use nalgebra::{Matrix3, Vector3};
use serde::Serialize;
use std::fmt::Write;
use std::time::Instant;

/// Errors below this are the rounding floor, left out of rate fits.
pub const FIT_FLOOR: f64 = 1e-13;

/// The high-accuracy run used as reference when no exact solution is known: exp chart,
/// exact matching, `h = 0.25`, `n = 20` (`tests/tests/exact_solution.rs` measures this
/// setting below 1e-12 — 4.5e-14 to 7.4e-13 depending on rounding — against the 40-digit
/// references of the paper's pendulum with m g = 9.81 and 1, up to t = 10).
pub const REFERENCE_STEP: f64 = 0.25;
/// Nodes of the high-accuracy reference run.
pub const REFERENCE_NODES: usize = 20;

/// What the errors are measured against.
pub enum Reference {
    /// The closed-form free rigid body.
    Exact(Box<FreeRigidBodyExact>),
    /// A high-accuracy run, with its nodal states and Galerkin curves as dense output.
    Dense {
        step: f64,
        states: Vec<(SO3, Vector3<f64>)>,
        curves: Vec<GalerkinCurve>,
        /// Its own error estimate: the difference at the final time to a run with 4 more nodes.
        self_check: f64,
    },
}

impl Reference {
    /// The exact solution for a free body, otherwise a high-accuracy run to `t_end`.
    pub fn for_problem(problem: &Problem, t_end: f64) -> Result<Self> {
        if problem.is_free() {
            return Ok(Reference::Exact(Box::new(problem.exact()?)));
        }
        let run = |nodes: usize| -> Result<(Vec<_>, Vec<_>)> {
            let settings = StepSettings::new(REFERENCE_STEP, nodes)?
                .with_chart(ChartKind::Exp)
                .with_matching(Matching::Exact);
            let mut integrator = problem.integrator(settings)?;
            let steps = integrator.steps_until(t_end)?;
            let mut states = vec![(*integrator.state().attitude(), integrator.state().velocity)];
            let mut curves = Vec::with_capacity(steps);
            for _ in 0..steps {
                integrator.step().map_err(|source| CliError::Run {
                    context: "reference run".into(),
                    source,
                })?;
                states.push((*integrator.state().attitude(), integrator.state().velocity));
                curves.extend(integrator.last_curve());
            }
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

    /// `(R(t), Ω(t))`.
    pub fn at(&self, t: f64) -> Result<(Matrix3<f64>, Vector3<f64>)> {
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
                let curve = curves.get(k).ok_or(CliError::NoReferenceCurve(t))?;
                let (g, w) = curve.at(t - curve.start())?;
                Ok((*g.matrix(), w))
            }
        }
    }
}

/// One run of a study.
#[derive(Debug, Clone, Serialize)]
pub struct Measurement {
    pub chart: String,
    pub matching: String,
    pub nodes: usize,
    pub degree: usize,
    pub h: f64,
    pub steps: usize,
    pub t_end: f64,
    /// `‖R(T) − R_ref(T)‖_F` at the final time (the one-step map's global error).
    pub error_r: f64,
    /// `|Ω(T) − Ω_ref(T)|`.
    pub error_omega: f64,
    /// Largest `‖R(t) − R_ref(t)‖_F` on the Galerkin curves, sampled inside every step.
    pub error_curve: f64,
    /// Largest `|E − E₀|/|E₀|` over the steps.
    pub energy_error: f64,
    /// Largest `|Rμ − R₀μ₀|/|R₀μ₀|` (free body) or `|e₃·(Rμ − R₀μ₀)|/|R₀μ₀|` (top).
    pub momentum_drift: f64,
    pub newton_iterations: usize,
    pub wall_time_s: f64,
    /// Why the run stopped, if it failed (Newton, chart): the errors are then NaN.
    pub failure: Option<String>,
}

/// Runs `settings` on `problem` to `t_end` and measures it against `reference`, sampling
/// each step's Galerkin curve at `curve_samples − 1` interior points.
pub fn measure(
    problem: &Problem,
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
        h: settings.step(),
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
    if let Err(e) = measure_into(problem, settings, t_end, reference, curve_samples, &mut m) {
        m.failure = Some(e.to_string());
        m.error_r = f64::NAN;
        m.error_omega = f64::NAN;
        m.error_curve = f64::NAN;
    }
    m
}

fn measure_into(
    problem: &Problem,
    settings: StepSettings,
    t_end: f64,
    reference: &Reference,
    curve_samples: usize,
    m: &mut Measurement,
) -> Result<()> {
    let mut integrator = problem.integrator(settings)?;
    let steps = integrator.steps_until(t_end)?;
    let system = problem.system;
    let s0 = *integrator.state();
    let tracker = problem.tracker(&s0);
    let (mut energy_error, mut drift, mut curve_error) = (0.0f64, 0.0f64, 0.0f64);
    let start = Instant::now();
    for _ in 0..steps {
        integrator.step()?;
        let s = integrator.state();
        let d = tracker.drift(s.energy(&system), s.attitude().matrix(), &s.momentum);
        energy_error = energy_error.max(d.energy);
        drift = drift.max(d.spatial_momentum);
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
    }
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

/// Least-squares slope of `y` against `x`.
fn slope(points: &[(f64, f64)]) -> Option<f64> {
    if points.len() < 2 {
        return None;
    }
    let n = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    (sxx > 0.0).then(|| sxy / sxx)
}

/// Errors above this are not yet asymptotic (the solution has lost all accuracy) and are
/// left out of fits.
pub const FIT_CEILING: f64 = 0.1;

/// The rounding floor of a series: when it reaches rounding (its smallest error below
/// 1e-11), errors within ×30 of that smallest error are noise; never below [`FIT_FLOOR`].
fn floor_of(errors: impl Iterator<Item = f64>) -> f64 {
    let min = errors
        .filter(|e| e.is_finite() && *e > 0.0)
        .fold(f64::INFINITY, f64::min);
    if min < 1e-11 {
        (30.0 * min).max(FIT_FLOOR)
    } else {
        FIT_FLOOR
    }
}

/// The points of a refinement series (ordered from coarse to fine) that are asymptotic:
/// below [`FIT_CEILING`], and before the first error at the series' rounding floor.
fn asymptotic(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let floor = floor_of(points.iter().map(|p| p.1));
    points
        .iter()
        .filter(|(_, e)| e.is_finite())
        .take_while(|(_, e)| *e > floor)
        .filter(|(_, e)| *e < FIT_CEILING)
        .map(|&(x, e)| (x, e.ln()))
        .collect()
}

/// The geometric factor per node: errors fall by this factor for each node added. A
/// least-squares fit of `ln error` against `n` over the asymptotic points: errors below
/// [`FIT_CEILING`] and above the series' rounding floor (see `floor_of`).
pub fn geometric_factor(points: &[(usize, f64)]) -> Option<f64> {
    let mut sorted: Vec<(f64, f64)> = points.iter().map(|&(n, e)| (n as f64, e)).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    slope(&asymptotic(&sorted)).map(|s| (-s).exp())
}

/// The algebraic order in the asymptotic regime: the slope of `log error` against `log h`
/// between the two smallest steps among the asymptotic points (as for
/// [`geometric_factor`]).
pub fn algebraic_order(points: &[(f64, f64)]) -> Option<f64> {
    let mut sorted: Vec<(f64, f64)> = points.to_vec();
    sorted.sort_by(|a, b| b.0.total_cmp(&a.0));
    let fit = asymptotic(&sorted);
    let fit: Vec<(f64, f64)> = fit
        .iter()
        .rev()
        .take(2)
        .map(|&(h, e)| (h.ln(), e))
        .collect();
    slope(&fit)
}

/// The most points per step at which `converge` compares the Galerkin curve.
pub const MAX_CURVE_SAMPLES: usize = 1000;

/// The studies' results.
#[derive(Debug, Clone, Serialize)]
pub struct Study {
    pub reference: String,
    pub nodes_refinement: Vec<Measurement>,
    pub step_refinement: Vec<Measurement>,
    /// `(chart, matching, h, factor per node)`.
    pub geometric_factors: Vec<(String, String, f64, Option<f64>)>,
    /// `(chart, matching, n, order)`.
    pub orders: Vec<(String, String, usize, Option<f64>)>,
}

/// Runs n-refinement over `nodes` at step `h` and h-refinement over `steps` for each of
/// `step_nodes`, with the problem's chart and matching.
#[allow(clippy::too_many_arguments)]
pub fn study(
    problem: &Problem,
    reference: &Reference,
    h: f64,
    nodes: &[usize],
    steps: &[f64],
    step_nodes: &[usize],
    t_end: f64,
    curve_samples: usize,
    mut tick: impl FnMut(),
) -> Result<Study> {
    let base = problem.settings;
    let with = |h: f64, n: usize| -> Result<StepSettings> {
        let mut s = StepSettings::new(h, n)?
            .with_chart(base.chart())
            .with_matching(base.matching())
            .with_jacobian(base.jacobian());
        if base.quadrature_points()
            != base.nodes() + lgsvi_mechanics::DEFAULT_EXTRA_QUADRATURE_POINTS
        {
            s = s.with_quadrature_points(base.quadrature_points().max(n))?;
        }
        Ok(s)
    };
    let mut nodes_refinement = Vec::new();
    for &n in nodes {
        nodes_refinement.push(measure(
            problem,
            with(h, n)?,
            t_end,
            reference,
            curve_samples,
        ));
        tick();
    }
    let mut step_refinement = Vec::new();
    for &n in step_nodes {
        for &hh in steps {
            step_refinement.push(measure(
                problem,
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
            h,
            geometric_factor(&points),
        )]
    };
    let orders = step_nodes
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

fn fmt_err(e: f64) -> String {
    if e.is_finite() {
        format!("{e:9.2e}")
    } else {
        format!("{:>9}", "failed")
    }
}

/// The printed table.
pub fn table(study: &Study) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "errors against {}", study.reference);
    let header = "    n  degree        h  steps   ‖R−Rref‖   |Ω−Ωref|    curve    energy   Newton";
    let row = |out: &mut String, m: &Measurement| {
        let _ = writeln!(
            out,
            "{:5} {:7} {:8} {:6} {}  {}  {}  {}  {:7}{}",
            m.nodes,
            m.degree,
            m.h,
            m.steps,
            fmt_err(m.error_r),
            fmt_err(m.error_omega),
            fmt_err(m.error_curve),
            fmt_err(m.energy_error),
            m.newton_iterations,
            m.failure
                .as_ref()
                .map(|f| format!("  ({f})"))
                .unwrap_or_default()
        );
    };
    if let Some(first) = study.nodes_refinement.first() {
        let _ = writeln!(
            out,
            "\nn-refinement: {} chart, {} matching, h = {}, T = {}",
            first.chart, first.matching, first.h, first.t_end
        );
        let _ = writeln!(out, "{header}");
        for m in &study.nodes_refinement {
            row(&mut out, m);
        }
        for (_, _, _, factor) in &study.geometric_factors {
            match factor {
                Some(q) => {
                    let _ = writeln!(
                        out,
                        "fitted: the error falls by ×{q:.1} per node (asymptotic errors: below {FIT_CEILING}, above the rounding floor)"
                    );
                }
                None => {
                    let _ = writeln!(out, "fitted: too few asymptotic errors to fit");
                }
            }
        }
    }
    if let Some(first) = study.step_refinement.first() {
        let _ = writeln!(
            out,
            "\nh-refinement: {} chart, {} matching, T = {}",
            first.chart, first.matching, first.t_end
        );
        let _ = writeln!(out, "{header}");
        for m in &study.step_refinement {
            row(&mut out, m);
        }
        for (_, _, n, order) in &study.orders {
            let _ = match order {
                Some(p) => writeln!(
                    out,
                    "fitted: n = {n} (degree {}): order {p:.2} (nodal superconvergence predicts {})",
                    n - 1,
                    2 * (n - 1)
                ),
                None => writeln!(out, "fitted: n = {n}: too few errors above the floor"),
            };
        }
    }
    out
}

/// The measurements as CSV.
pub fn csv(rows: &[&Measurement], study: &str) -> String {
    let mut out = String::from(
        "study,chart,matching,nodes,degree,h,steps,t_end,error_R,error_omega,error_curve,energy_error,momentum_drift,newton_iterations,wall_time_s,failure\n",
    );
    for m in rows {
        let _ = writeln!(
            out,
            "{study},{},{},{},{},{},{},{},{:e},{:e},{:e},{:e},{:e},{},{},{}",
            m.chart,
            m.matching,
            m.nodes,
            m.degree,
            m.h,
            m.steps,
            m.t_end,
            m.error_r,
            m.error_omega,
            m.error_curve,
            m.energy_error,
            m.momentum_drift,
            m.newton_iterations,
            m.wall_time_s,
            m.failure.as_deref().unwrap_or("").replace(',', ";")
        );
    }
    out
}

/// `lgsvi converge`.
pub fn run_converge(options: ConvergeOptions) -> Result<()> {
    let mut options = options;
    if let Some(path) = options.base.config.clone() {
        let (_, table) = crate::config::read_config_table(&path)?;
        if let Some(table) = table {
            let file: ConvergeOptions =
                crate::config::deserialize_naming_the_key(table, &path, "[converge] ")?;
            options.study = options.study.or(file.study);
            options.nodes_range = options.nodes_range.or(file.nodes_range);
            options.steps = options.steps.or(file.steps);
            options.step_nodes = options.step_nodes.or(file.step_nodes);
            options.curve_samples = options.curve_samples.or(file.curve_samples);
            options.tols = options.tols.or(file.tols);
        }
    }
    if options.base.no_check || options.base.check {
        return Err(CliError::SimulateOnly {
            flag: if options.base.check {
                "--check"
            } else {
                "--no-check"
            },
            why: "converge measures every run's error against a reference itself",
        });
    }
    if options.base.exact {
        return Err(CliError::SimulateOnly {
            flag: "--exact",
            why: "converge always measures against the exact solution when there is one",
        });
    }
    if options.base.every.is_some() {
        return Err(CliError::SimulateOnly {
            flag: "--every",
            why: "converge measures every step",
        });
    }
    if let Some(samples) = options.curve_samples {
        if !(1..=MAX_CURVE_SAMPLES).contains(&samples) {
            return Err(CliError::Invalid {
                flag: "--curve-samples",
                value: samples.to_string(),
                reason: format!("from 1 (no curve check) to {MAX_CURVE_SAMPLES}"),
            });
        }
    }
    let kind = options.study.unwrap_or(StudyKind::Both);
    if matches!(kind, StudyKind::Estimate | StudyKind::Tolerance) {
        return crate::tolerance::run(options, kind == StudyKind::Estimate);
    }
    let (problem, base) = Problem::resolve(options.base)?;
    if problem.wheels.is_some() {
        return Err(CliError::NotForSystem {
            flag: "converge",
            system: "gyrostat",
            applies: "rigid-body, heavy-top, se3-body and orbiting-body",
        });
    }
    if problem.motion.is_some() {
        return Err(CliError::NotForSystem {
            flag: "converge",
            system: if base.system() == crate::config::SystemKind::OrbitingBody {
                "orbiting-body"
            } else {
                "se3-body"
            },
            applies: "the SO(3) systems (rigid-body, heavy-top) for --study nodes, step and \
                 both; --study estimate and tolerance run every system",
        });
    }
    let [first, last] = options.nodes_range.unwrap_or([2, 16]);
    // Values from a config file did not pass the flags' parsers.
    if let Some([a, b]) = options.nodes_range {
        node_range(&format!("{a}..{b}")).map_err(|reason| CliError::ConfigValue {
            key: "nodes-range",
            reason,
        })?;
    }
    for h in options.steps.iter().flatten() {
        positive_step(&h.to_string()).map_err(|reason| CliError::ConfigValue {
            key: "steps",
            reason,
        })?;
        whole_steps(problem.t_end, *h).map_err(|e| CliError::ConfigValue {
            key: "steps",
            reason: e.to_string(),
        })?;
    }
    for n in options.step_nodes.iter().flatten() {
        node_count(&n.to_string()).map_err(|reason| CliError::ConfigValue {
            key: "step-nodes",
            reason,
        })?;
    }
    let nodes: Vec<usize> = if kind == StudyKind::Step {
        Vec::new()
    } else {
        (first..=last).collect()
    };
    let steps = if kind == StudyKind::Nodes {
        Vec::new()
    } else {
        options
            .steps
            .unwrap_or_else(|| vec![1.0, 0.5, 0.25, 0.125, 0.0625])
    };
    let step_nodes = if kind == StudyKind::Nodes {
        Vec::new()
    } else {
        options.step_nodes.unwrap_or_else(|| vec![2, 3, 4, 5])
    };
    let curve_samples = options.curve_samples.unwrap_or(8).max(1);
    let t_end = problem.t_end;
    let progress = crate::progress_bar(
        (nodes.len() + steps.len() * step_nodes.len()) as u64,
        "converge",
        "runs",
        problem.quiet,
    );
    let reference = Reference::for_problem(&problem, t_end)?;
    let h = problem.settings.step();
    let result = study(
        &problem,
        &reference,
        h,
        &nodes,
        &steps,
        &step_nodes,
        t_end,
        curve_samples,
        || progress.inc(1),
    )?;
    progress.finish_and_clear();
    print!("{}", table(&result));
    if let Some(path) = &base.out {
        let text = match base.format.unwrap_or(Format::Json) {
            Format::Json => {
                let mut t = serde_json::to_string_pretty(&serde_json::json!({
                    "description": problem.description,
                    "study": result,
                }))?;
                t.push('\n');
                t
            }
            Format::Csv => {
                let mut t = csv(&result.nodes_refinement.iter().collect::<Vec<_>>(), "nodes");
                let h_rows = csv(&result.step_refinement.iter().collect::<Vec<_>>(), "step");
                t.push_str(h_rows.split_once('\n').map(|(_, rest)| rest).unwrap_or(""));
                t
            }
        };
        crate::files::write(path, text.as_bytes())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_recover_known_rates_and_ignore_the_floor() {
        // error = 3·10^{-n} down to a noisy floor near 1e-14, saturated at n = 1.
        let mut points: Vec<(usize, f64)> = (2..=12)
            .map(|n| (n, 3.0 * 10f64.powi(-(n as i32))))
            .collect();
        points.insert(0, (1, 2.0));
        points.extend([(13, 4e-14), (14, 2e-14), (15, 9e-14), (16, 3e-14)]);
        let q = geometric_factor(&points).unwrap();
        assert!((q - 10.0).abs() < 1e-9, "{q}");
        // error = h^6 down to a floor.
        let mut points: Vec<(f64, f64)> = [1.0, 0.5, 0.25, 0.125, 0.0625]
            .iter()
            .map(|&h: &f64| (h, 1e-3 * h.powi(6)))
            .collect();
        points.push((0.03125, 3e-14));
        points.push((0.015625, 5e-14));
        let p = algebraic_order(&points).unwrap();
        assert!((p - 6.0).abs() < 1e-9, "{p}");
        // Not enough points: no fit.
        assert_eq!(algebraic_order(&[(1.0, 1e-3)]), None);
        assert_eq!(geometric_factor(&[(3, f64::NAN), (4, 1e-3)]), None);
    }
}
