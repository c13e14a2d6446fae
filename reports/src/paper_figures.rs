//! What `reproduce` draws: each figure, and the CSV of its data, from the measurements
//! (`measure`). Nothing here runs an integrator or writes a file.

use crate::convergence as study;
use lgsvi_experiments::paper::{
    chart_name, matching_name, EnergyRuns, HRefinement, LongRun, NRefinement, SphereRuns,
    UnstableRuns, H_MATCHINGS, N_CONFIGS,
};
use lgsvi_mechanics::Matching;
use lgsvi_plot::{Figure, Series, SphereFigure, Style};
use std::fmt::Write;

/// Figures 1 and 5: error of the one-step map (solid) and of the Galerkin curves (dashed)
/// against the number of nodes, per configuration.
pub fn n_refinement(data: &NRefinement, title: &str) -> Figure {
    let mut series = Vec::new();
    for (i, &(chart, matching)) in N_CONFIGS.iter().enumerate() {
        let ms = data.config(i);
        let label = format!("{}, {}", chart_name(chart), matching_name(matching));
        series.push(Series {
            label: format!("{label}: one-step map at T"),
            points: ms.iter().map(|m| (m.nodes as f64, m.error_r)).collect(),
            style: Style::LineMarkers,
            color: i,
        });
        series.push(Series {
            label: format!("{label}: Galerkin curves"),
            points: ms.iter().map(|m| (m.nodes as f64, m.error_curve)).collect(),
            style: Style::DashedMarkers,
            color: i,
        });
    }
    Figure {
        title: title.into(),
        x_label: "nodes n (polynomial degree n − 1)".into(),
        y_label: "error in R (Frobenius norm)".into(),
        x_log: false,
        y_log: true,
        series,
        hlines: vec![],
    }
}

/// The n-refinement's rows as CSV (one per node count).
pub fn n_refinement_csv(data: &NRefinement) -> String {
    study::csv(&data.rows.iter().collect::<Vec<_>>(), "nodes")
}

/// Figures 2 and 6: error against the step, per node count; exact matching solid, the
/// paper's dashed.
pub fn h_refinement(data: &HRefinement, title: &str) -> Figure {
    let mut series = Vec::new();
    for (i, &n) in data.nodes.iter().enumerate() {
        for (j, &matching) in H_MATCHINGS.iter().enumerate() {
            series.push(Series {
                label: format!("n = {n}, {}", matching_name(matching)),
                points: data.series(i, j).iter().map(|m| (m.h, m.error_r)).collect(),
                style: if matching == Matching::Exact {
                    Style::LineMarkers
                } else {
                    Style::DashedMarkers
                },
                color: i,
            });
        }
    }
    Figure {
        title: title.into(),
        x_label: "step h (s)".into(),
        y_label: "error in R at T = 10 (Frobenius norm)".into(),
        x_log: true,
        y_log: true,
        series,
        hlines: vec![],
    }
}

/// The h-refinement's rows as CSV (one per step length).
pub fn h_refinement_csv(data: &HRefinement) -> String {
    study::csv(&data.rows.iter().collect::<Vec<_>>(), "step")
}

/// The relative energy error of each run against time, every `stride`-th step after the
/// first, drawn as `style`.
fn energy_error_figure(
    title: String,
    runs: &[(String, LongRun)],
    stride: usize,
    style: Style,
) -> Figure {
    let series = runs
        .iter()
        .enumerate()
        .map(|(i, (m, run))| Series {
            label: m.clone(),
            points: run
                .times
                .iter()
                .zip(&run.energy_error)
                .step_by(stride)
                .skip(1)
                .map(|(t, e)| (*t, *e))
                .collect(),
            style,
            color: i,
        })
        .collect();
    Figure {
        title,
        x_label: "time t (s)".into(),
        y_label: "relative energy error |E − E₀|/|E₀|".into(),
        x_log: false,
        y_log: true,
        series,
        hlines: vec![],
    }
}

/// Figures 3 and 7: relative energy error over the long runs (at most ~1500 points per
/// series; the CSV has every step).
pub fn energy(data: &EnergyRuns, title: &str) -> Figure {
    let stride = (data.steps / 1500).max(1);
    energy_error_figure(title.into(), &data.runs, stride, Style::Line)
}

/// The long runs' relative energy errors as CSV: the time, then one column per run.
pub fn energy_csv(data: &EnergyRuns) -> String {
    let mut csv = String::from("t");
    for (m, _) in &data.runs {
        for q in [
            "energy_error",
            "casimir_drift",
            "momentum_drift",
            "step_angle",
        ] {
            // Column names without commas: "chart / matching".
            let _ = write!(csv, ",{q} [{}]", m.replace(", ", " / "));
        }
    }
    csv.push('\n');
    let len = data
        .runs
        .iter()
        .map(|(_, r)| r.times.len())
        .max()
        .unwrap_or(0);
    for k in 0..len {
        let mut row = vec![format!("{}", k as f64 * data.h)];
        for (_, r) in &data.runs {
            let get =
                |v: &Vec<f64>, k: usize| v.get(k).map(|x| format!("{x:e}")).unwrap_or_default();
            row.push(get(&r.energy_error, k));
            row.push(get(&r.casimir_drift, k));
            row.push(get(&r.momentum_drift, k));
            row.push(if k == 0 {
                String::new()
            } else {
                get(&r.step_angle, k - 1)
            });
        }
        let _ = writeln!(csv, "{}", row.join(","));
    }
    csv
}

/// Figure 4: the exact matching's body momenta on the sphere.
pub fn sphere(data: &SphereRuns) -> SphereFigure {
    let exact = data
        .runs
        .iter()
        .find(|(m, _)| *m == Matching::Exact)
        .map(|(_, runs)| runs.as_slice())
        .unwrap_or_default();
    SphereFigure {
        title: format!(
            "Rigid body: body momentum μ on |μ| = 1, {} steps each (unscaled Cayley, exact matching, n = 8, h = 0.5)",
            data.steps
        ),
        radius: 1.0,
        curves: exact
            .iter()
            .map(|run| run.momentum.iter().map(|m| (m.x, m.y, m.z)).collect())
            .collect(),
        labels: data
            .directions
            .iter()
            .map(|d| format!("μ(0) ∝ ({}, {}, {})", d[0], d[1], d[2]))
            .collect(),
        axes: ["μ₁".into(), "μ₂".into(), "μ₃".into()],
    }
}

/// The sphere test's body momenta as CSV: trajectory, matching, time and `μ`.
pub fn sphere_csv(data: &SphereRuns) -> String {
    let mut csv = String::from("trajectory,matching,t,mu_x,mu_y,mu_z\n");
    for (matching, runs) in &data.runs {
        for (i, run) in runs.iter().enumerate() {
            for (t, m) in run.times.iter().zip(&run.momentum) {
                let _ = writeln!(
                    csv,
                    "{i},{},{t},{},{},{}",
                    matching_name(*matching),
                    m.x,
                    m.y,
                    m.z
                );
            }
        }
    }
    csv
}

/// Figure 8: the centre-of-mass direction `Rρ` of the shown run, at the steps (markers)
/// and on the Galerkin curves (lines).
pub fn unstable_dynamics(data: &UnstableRuns) -> Figure {
    let (label, run) = &data.runs[data.shown];
    let names = ["x", "y", "z"];
    let mut series = Vec::new();
    for c in 0..3 {
        series.push(Series {
            label: format!("(Rρ)_{}: Galerkin curves", names[c]),
            points: run.curve_axis.iter().map(|(t, a)| (*t, a[c])).collect(),
            style: Style::Line,
            color: c,
        });
        series.push(Series {
            label: format!("(Rρ)_{}: steps", names[c]),
            points: run
                .times
                .iter()
                .zip(&run.axis)
                .map(|(t, a)| (*t, a[c]))
                .collect(),
            style: Style::Markers,
            color: c,
        });
    }
    Figure {
        title: format!(
            "3D pendulum (unstable): centre-of-mass direction Rρ, n = {}, h = {} ({label})",
            data.n, data.h
        ),
        x_label: "time t (s)".into(),
        y_label: "components of Rρ (unit vector, world frame)".into(),
        x_log: false,
        y_log: false,
        series,
        hlines: vec![],
    }
}

/// The shown unstable run's states as CSV.
pub fn unstable_dynamics_csv(data: &UnstableRuns) -> String {
    let run = &data.runs[data.shown].1;
    let mut csv = String::from("t,kind,axis_x,axis_y,axis_z\n");
    for (t, a) in run.times.iter().zip(&run.axis) {
        let _ = writeln!(csv, "{t},step,{},{},{}", a.x, a.y, a.z);
    }
    for (t, a) in &run.curve_axis {
        let _ = writeln!(csv, "{t},curve,{},{},{}", a.x, a.y, a.z);
    }
    csv
}

/// Figure 9: the energy error of every configuration, every step.
pub fn unstable_energy(data: &UnstableRuns) -> Figure {
    let title = format!(
        "3D pendulum (unstable): energy error, n = {}, h = {}",
        data.n, data.h
    );
    energy_error_figure(title, &data.runs, 1, Style::LineMarkers)
}

/// The unstable runs' relative energy errors as CSV: the time, then one column per run.
pub fn unstable_energy_csv(data: &UnstableRuns) -> String {
    let mut csv = String::from("t");
    for (m, _) in &data.runs {
        let m = m.replace(", ", " / ");
        let _ = write!(csv, ",step_angle_rad [{m}],energy_error [{m}]");
    }
    csv.push('\n');
    for k in 0..=data.steps {
        let _ = write!(csv, "{}", k as f64 * data.h);
        for (_, r) in &data.runs {
            let angle = if k == 0 {
                None
            } else {
                r.step_angle.get(k - 1)
            };
            let _ = write!(
                csv,
                ",{},{}",
                angle.map(|a| a.to_string()).unwrap_or_default(),
                r.energy_error
                    .get(k)
                    .map(|e| format!("{e:e}"))
                    .unwrap_or_default()
            );
        }
        csv.push('\n');
    }
    csv
}

#[cfg(test)]
mod tests {
    use super::*;
    use lgsvi_experiments::convergence::Measurement;

    fn measurement(nodes: usize, h: f64, error: f64) -> Measurement {
        Measurement {
            chart: "exp".into(),
            matching: "exact".into(),
            nodes,
            degree: nodes - 1,
            h,
            steps: 10,
            t_end: 10.0,
            error_r: error,
            error_omega: error,
            error_curve: 10.0 * error,
            energy_error: 0.0,
            momentum_drift: 0.0,
            newton_iterations: 3,
            wall_time_s: 0.0,
            failure: error.is_nan().then(|| "Newton did not converge".into()),
        }
    }

    #[test]
    fn n_refinement_draws_map_and_curves_per_configuration_and_keeps_failures() {
        let nodes = vec![2, 3, 4];
        let rows: Vec<Measurement> = (0..N_CONFIGS.len())
            .flat_map(|i| {
                nodes.iter().map(move |&n| {
                    // The first configuration fails at n = 2.
                    let error = if i == 0 && n == 2 {
                        f64::NAN
                    } else {
                        10f64.powi(-(n as i32))
                    };
                    measurement(n, 0.5, error)
                })
            })
            .collect();
        let data = NRefinement {
            nodes,
            reference: "the exact solution".into(),
            rows,
            fits: vec![],
        };
        let fig = n_refinement(&data, "t");
        assert_eq!(fig.series.len(), 2 * N_CONFIGS.len());
        assert!(fig.y_log && !fig.x_log);
        assert_eq!(fig.series[0].style, Style::LineMarkers);
        assert_eq!(fig.series[1].style, Style::DashedMarkers);
        // The failed run stays in the series (drawn as a failure mark), not dropped.
        assert_eq!(fig.series[0].points.len(), 3);
        assert!(fig.series[0].points[0].1.is_nan());
        assert_eq!(fig.series[1].points[2], (4.0, 1e-3));
        // One CSV row per measurement, under a header.
        assert_eq!(
            n_refinement_csv(&data).lines().count(),
            1 + 3 * N_CONFIGS.len()
        );
    }

    #[test]
    fn h_refinement_pairs_solid_exact_with_dashed_paper_series() {
        let (nodes, steps) = (vec![2, 3], vec![0.5, 0.25]);
        let rows = nodes
            .iter()
            .flat_map(|&n| {
                let steps = steps.clone();
                H_MATCHINGS
                    .iter()
                    .flat_map(move |_| steps.clone().into_iter().map(move |h| measurement(n, h, h)))
            })
            .collect();
        let data = HRefinement {
            nodes,
            steps,
            reference: String::new(),
            rows,
            orders: vec![],
        };
        let fig = h_refinement(&data, "t");
        let styles: Vec<Style> = fig.series.iter().map(|s| s.style).collect();
        assert_eq!(
            styles,
            [
                Style::LineMarkers,
                Style::DashedMarkers,
                Style::LineMarkers,
                Style::DashedMarkers
            ]
        );
        assert_eq!(fig.series[2].label, "n = 3, exact matching");
        assert_eq!(fig.series[2].points, [(0.5, 0.5), (0.25, 0.25)]);
        assert!(fig.x_log && fig.y_log);
    }
}
