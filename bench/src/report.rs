//! `lgsvi bench`'s tables, Markdown and figures, from the measurements of this crate.

use crate::long_run::{EnergyTrend, Invariants, LongRun, Spread};
use crate::so3::{EnsembleResult, ENSEMBLE_DOP853_TOLERANCE, LGSVI_FIXED};
use crate::space::{CASES, HORIZONS};
use lgsvi_experiments::work_precision::{fastest, most_accurate, Point};
use lgsvi_mechanics::StepSettings;
use lgsvi_plot::{Figure, Series, Style};
use std::fmt::Write;

fn best_error(points: &[Point], case: &str, t_end: f64, method: &str) -> f64 {
    most_accurate(points, case, t_end, method).map_or(f64::INFINITY, |p| p.error)
}

/// The targets, measured.
pub fn targets(points: &[Point]) -> String {
    let mut s = String::new();
    let ms = |p: Option<&Point>| {
        p.map(|p| format!("{:.3} ms ({})", 1e3 * p.time_s, p.knob))
            .unwrap_or_else(|| "not reached".into())
    };
    let _ = writeln!(s, "| target | measured | met |");
    let _ = writeln!(s, "|---|---|---|");
    let l = fastest(points, "A", 10.0, LGSVI_FIXED, 1e-12);
    let d = fastest(points, "A", 10.0, "DOP853 (quaternion)", 1e-12);
    let met = matches!((l, d), (Some(l), Some(d)) if l.time_s <= d.time_s);
    let _ = writeln!(s, "| A, T = 10, error ≤ 1e-12: lgsvi time ≤ DOP853 (quaternion) time | lgsvi {}, DOP853 {} | {} |", ms(l), ms(d), if met { "yes" } else { "no" });
    for case in ["A", "B"] {
        let l = fastest(points, case, 10.0, LGSVI_FIXED, 1e-10);
        let y1 = fastest(points, case, 10.0, "LGVI2-Yoshida4", 1e-10);
        let y2 = fastest(points, case, 10.0, "splitting-Yoshida4", 1e-10);
        let best = [y1, y2]
            .into_iter()
            .flatten()
            .min_by(|a, b| a.time_s.total_cmp(&b.time_s));
        let ratio = match (l, best) {
            (Some(l), Some(b)) => format!("{:.1}×", b.time_s / l.time_s),
            _ => "–".into(),
        };
        let met = matches!((l, best), (Some(l), Some(b)) if b.time_s >= 30.0 * l.time_s);
        let _ = writeln!(s, "| {case}, T = 10, error ≤ 1e-10: lgsvi ≥ 30× faster than the best Yoshida-4 | lgsvi {}, LGVI2-Yoshida4 {}, splitting-Yoshida4 {}: {ratio} | {} |", ms(l), ms(y1), ms(y2), if met { "yes" } else { "no" });
    }
    let l = best_error(points, "A", 100.0, LGSVI_FIXED);
    let d = best_error(points, "A", 100.0, "DOP853");
    let _ = writeln!(
        s,
        "| A, T = 100: lgsvi reaches ≤ 1e-12 | lgsvi best {l:.1e}, DOP853 best {d:.1e} | {} |",
        if l <= 1e-12 { "yes" } else { "no" }
    );
    s
}

/// The ratio table: for each case, horizon and error target, the fastest lgsvi
/// run (best `(h, n)` of the sweep) at or below the target over the fastest DOP853
/// (quaternion state) run at or below it; below 1 lgsvi is faster. The last column goes
/// where DOP853 does not: lgsvi's fastest run at ≤ 1e-13 over DOP853's most accurate run
/// (whatever its error), with both errors.
pub fn dop853_ratios(points: &[Point]) -> String {
    const TARGETS: [f64; 4] = [1e-6, 1e-8, 1e-10, 1e-12];
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| time lgsvi / time DOP853 (quaternion) | ≤ 1e-6 | ≤ 1e-8 | ≤ 1e-10 | ≤ 1e-12 | lgsvi ≤ 1e-13 / DOP853's most accurate run |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    for case in ["A", "B"] {
        for t_end in [10.0, 100.0] {
            let mut row = format!("| case {case}, T = {t_end} |");
            for target in TARGETS {
                let l = fastest(points, case, t_end, LGSVI_FIXED, target);
                let d = fastest(points, case, t_end, "DOP853 (quaternion)", target);
                row.push_str(&ratio_cell(l, d, |_| String::new()));
            }
            let l = fastest(points, case, t_end, LGSVI_FIXED, 1e-13);
            let d = most_accurate(points, case, t_end, "DOP853 (quaternion)");
            row.push_str(&beyond_cell(l, d));
            let _ = writeln!(s, "{row}");
        }
    }
    s
}

/// The `--tol` series: for each case, horizon and tolerance, the error the run reached,
/// its time, and the time of the fastest fixed `(h, n)` and DOP853 (quaternion) runs at
/// least as accurate (ratios above 1: the `--tol` run is slower).
pub fn tolerance_table(points: &[Point]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| case and horizon | tol | error | error / tol | time (ms) | / fastest fixed (h, n) as accurate | / fastest DOP853 as accurate |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for case in ["A", "B"] {
        for t_end in [10.0, 100.0] {
            for p in points
                .iter()
                .filter(|p| p.case == case && p.t_end == t_end && p.method == "lgsvi --tol")
            {
                let tol: f64 = p
                    .knob
                    .trim_start_matches("tol = ")
                    .parse()
                    .unwrap_or(f64::NAN);
                if !p.error.is_finite() {
                    let _ = writeln!(s, "| {case} at T = {t_end} | {tol:.0e} | failed | | | | |");
                    continue;
                }
                let ratio = |other: Option<&Point>| {
                    other.map_or("none as accurate".to_string(), |o| {
                        let what = o
                            .method
                            .trim_start_matches("lgsvi ")
                            .trim_start_matches("DOP853 ");
                        format!("{:.2} ({what}, {})", p.time_s / o.time_s, o.knob)
                    })
                };
                let _ = writeln!(
                    s,
                    "| {case} at T = {t_end} | {tol:.0e} | {:.1e} | {:.2} | {:.3} | {} | {} |",
                    p.error,
                    p.error / tol,
                    1e3 * p.time_s,
                    ratio(fastest(points, case, t_end, LGSVI_FIXED, p.error)),
                    ratio(fastest(points, case, t_end, "DOP853 (quaternion)", p.error)),
                );
            }
        }
    }
    s
}

/// The ratio table: per case and horizon, the fastest lgsvi run at or below each error
/// target over the fastest DOP853 run at or below it, and where DOP853 does not go,
/// lgsvi's fastest run at ≤ 1e-12 and ≤ 1e-13 over DOP853's most accurate run.
pub fn space_ratios(points: &[Point]) -> String {
    const TARGETS: [f64; 3] = [1e-8, 1e-10, 1e-12];
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| time lgsvi / time DOP853 | ≤ 1e-8 | ≤ 1e-10 | ≤ 1e-12 | lgsvi ≤ 1e-12 / DOP853's most accurate run |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|");
    for name in CASES {
        for t_end in HORIZONS {
            let mut row = format!("| {name}, T = {t_end} |");
            for target in TARGETS {
                let l = fastest(points, name, t_end, "lgsvi", target);
                let d = fastest(points, name, t_end, "DOP853", target);
                // The (h, n) of the lgsvi run: "h = 2, n = 8".
                row.push_str(&ratio_cell(l, d, |l| {
                    format!(
                        "{}, {}",
                        l.method
                            .trim_start_matches("lgsvi (exp, ")
                            .trim_end_matches(')'),
                        l.knob
                    )
                }));
            }
            let l = fastest(points, name, t_end, "lgsvi", 1e-12);
            let d = most_accurate(points, name, t_end, "DOP853");
            row.push_str(&beyond_cell(l, d));
            let _ = writeln!(s, "{row}");
        }
    }
    s
}
/// A ratio table's cell for one error target: lgsvi's fastest run there over DOP853's,
/// both times, and what `detail` says of the lgsvi run (after a `; `, when not empty);
/// or which of the two does not reach the target.
pub fn ratio_cell(
    lgsvi: Option<&Point>,
    dop853: Option<&Point>,
    detail: impl Fn(&Point) -> String,
) -> String {
    match (lgsvi, dop853) {
        (Some(l), Some(d)) => {
            let detail = detail(l);
            let detail = if detail.is_empty() {
                detail
            } else {
                format!("; {detail}")
            };
            format!(
                " {:.2} ({:.3} / {:.3} ms{detail}) |",
                l.time_s / d.time_s,
                1e3 * l.time_s,
                1e3 * d.time_s
            )
        }
        (Some(_), None) => " DOP853 does not reach it |".into(),
        (None, _) => " lgsvi does not reach it |".into(),
    }
}

/// A ratio table's last cell, where DOP853 does not go: lgsvi's run over DOP853's most
/// accurate run, with both errors and times.
pub fn beyond_cell(lgsvi: Option<&Point>, dop853: Option<&Point>) -> String {
    match (lgsvi, dop853) {
        (Some(l), Some(d)) => format!(
            " {:.2} (lgsvi {:.1e} in {:.3} ms; DOP853 {:.1e} in {:.3} ms) |",
            l.time_s / d.time_s,
            l.error,
            1e3 * l.time_s,
            d.error,
            1e3 * d.time_s
        ),
        _ => " – |".into(),
    }
}
/// `BENCH.md` of a sweep (`repeats` per run) with the ensemble measured beside it, and the
/// work-precision figure of each case and horizon, named `bench_{case}_T{t_end}`.
pub fn sweep_report(
    repeats: usize,
    points: &[Point],
    space_points: &[Point],
    ensemble: &EnsembleResult,
) -> (String, Vec<(String, Figure)>) {
    let mut figures = Vec::new();
    let mut table = String::new();
    let _ = writeln!(
        table,
        "# lgsvi bench — work-precision (median of {repeats} runs, one process)\n"
    );
    let _ = writeln!(table, "Errors ‖R(T) − R_ref(T)‖_F against the shared 40-digit references; times include construction.\n");
    let _ = writeln!(table, "## Targets\n\n{}", targets(points));
    let _ = writeln!(
        table,
        "## Against DOP853 (best (h, n) per target, construction included)\n\n{}",
        dop853_ratios(points)
    );
    let _ = writeln!(
        table,
        "## lgsvi --tol (nodes chosen per step; the step and first nodes as `simulate --tol` chooses them)\n\n{}",
        tolerance_table(points)
    );
    let _ = writeln!(
        table,
        "## The orbiting body O1 and the torqued body F1 against DOP853 (best (h, n) per target, construction included; errors: O1 max(‖R − R_ref‖_F, ‖x − x_ref‖), F1 ‖R − R_ref‖_F)\n\n{}",
        space_ratios(space_points)
    );
    let ensemble_line = ensemble_line(ensemble);
    let _ = writeln!(table, "## Parallel ensemble\n\n{ensemble_line}\n");
    for case in ["A", "B"] {
        for t_end in [10.0, 100.0] {
            let _ = writeln!(table, "## Case {case}, T = {t_end}\n\n| method | knob | error | time (ms) |\n|---|---|---|---|");
            let mut series: Vec<Series> = Vec::new();
            for p in points.iter().filter(|p| p.case == case && p.t_end == t_end) {
                let _ = writeln!(
                    table,
                    "| {} | {} | {} | {:.3} |",
                    p.method,
                    p.knob,
                    if p.error.is_finite() {
                        format!("{:.2e}", p.error)
                    } else {
                        "failed".into()
                    },
                    1e3 * p.time_s
                );
                if let Some(s) = series.iter_mut().find(|s| s.label == p.method) {
                    s.points.push((p.time_s, p.error));
                } else {
                    let color = series.len();
                    series.push(Series {
                        label: p.method.clone(),
                        points: vec![(p.time_s, p.error)],
                        style: if p.method == "lgsvi --tol" {
                            Style::DashedMarkers
                        } else {
                            Style::LineMarkers
                        },
                        color,
                    });
                }
            }
            let _ = writeln!(table);
            let name = format!("bench_{case}_T{t_end}");
            figures.push((
                name,
                Figure {
                    title: format!(
                        "Work-precision, case {case} ({}), T = {t_end}",
                        if case == "A" {
                            "free rigid body"
                        } else {
                            "3D pendulum"
                        }
                    ),
                    x_label: "wall time (s), median".into(),
                    y_label: "error in R at T (Frobenius norm)".into(),
                    x_log: true,
                    y_log: true,
                    series,
                    hlines: vec![],
                },
            ));
        }
    }
    (table, figures)
}

/// The ensemble's measurement in one line.
pub fn ensemble_line(ensemble: &EnsembleResult) -> String {
    format!(
        "Ensemble ({} initial conditions per case, A and B, T = 10, h = 0.5, n = 8): {:.1} ms on 1 thread, {:.1} ms on {} threads: speed-up {:.2} (target ≥ 1.8 on 2 cores; {} failures); the machine's own in the same repeats, as many tasks on the same pools, none of lgsvi's code: {:.2} for dependent chains of scalar arithmetic, {:.2} for 32 × 32 matrix products, which use the processor's execution units as a step does (on a shared VM whose second vCPU is not a free core, the second and lgsvi's speed-up fall together). The same trajectories by DOP853 (quaternion, tol = {:.0e}) on {} threads: {:.1} ms. Trajectories per second on {} threads: lgsvi {:.0}, DOP853 {:.0}.",
        ensemble.members,
        1e3 * ensemble.one_thread_s,
        1e3 * ensemble.parallel_s,
        ensemble.threads,
        ensemble.speedup,
        ensemble.failures,
        ensemble.machine_speedups.0,
        ensemble.machine_speedups.1,
        ENSEMBLE_DOP853_TOLERANCE,
        ensemble.threads,
        1e3 * ensemble.dop853_parallel_s,
        ensemble.threads,
        ensemble.trajectories_per_s.0,
        ensemble.trajectories_per_s.1
    )
}
/// `LONG_RUN.md` of a long run with `settings` over `steps` steps (and its trend ensemble,
/// if measured), and the figures `long_run_{energy,casimir,spatial_momentum,orthogonality}`.
pub fn long_run_report(
    settings: StepSettings,
    steps: usize,
    run: &LongRun,
    trend: Option<&EnergyTrend>,
) -> (String, Vec<(String, Figure)>) {
    let (h, n) = (settings.h(), settings.nodes());
    let LongRun {
        lgsvi,
        dop,
        lgsvi_time,
        dop_time,
        nodes,
    } = run;
    let (lgsvi_time, dop_time) = (*lgsvi_time, *dop_time);
    let legend = match settings.adaptive() {
        Some(_) => format!("lgsvi (h = {h}, n per step)"),
        None => format!("lgsvi (h = {h}, n = {n})"),
    };
    let n = match settings.adaptive() {
        Some(a) => {
            let counts: Vec<String> = nodes.iter().map(|(n, c)| format!("{n}: {c}")).collect();
            format!(
                "chosen per step for an error of {:.0e} per unit time (steps per n: {})",
                a.rate,
                counts.join(", ")
            )
        }
        None => n.to_string(),
    };
    let mut figures = Vec::new();
    let max = |v: &[Invariants], f: fn(&Invariants) -> f64| v.iter().map(f).fold(0.0, f64::max);
    let half = |v: &[Invariants], f: fn(&Invariants) -> f64| {
        let mid = v.len() / 2;
        (max(&v[..mid], f), max(&v[mid..], f))
    };
    type Get = fn(&Invariants) -> f64;
    let quantities: [(&str, &str, Get); 4] = [
        ("energy", "relative energy error |E − E₀|/E₀", |i| {
            i.energy
        }),
        (
            "casimir",
            "Casimir drift ||μ|² − |μ₀|²|/|μ₀|²",
            |i| i.casimir,
        ),
        (
            "spatial_momentum",
            "spatial momentum drift |Rμ − R₀μ₀|/|μ₀|",
            |i| i.spatial_momentum,
        ),
        ("orthogonality", "‖RᵀR − I‖_F", |i| i.orthogonality),
    ];
    let t_end = steps as f64 * h;
    let mut md = format!(
        "# lgsvi bench --long-run\n\nCase A (free rigid body), T = {t_end}: lgsvi {steps} steps (h = {h}, n = {n}, exp chart, exact matching) in {lgsvi_time:.1} s; DOP853 on (R, Ω) at tolerance 1e-13 over the same horizon (restarted at the {} sample times) in {dop_time:.1} s.\n\n| quantity | lgsvi max, first half | lgsvi max, second half | DOP853 max, first half | DOP853 max, second half |\n|---|---|---|---|---|\n",
        lgsvi.len() - 1
    );
    for (name, label, f) in quantities {
        let (l1, l2) = half(lgsvi, f);
        let (d1, d2) = half(dop, f);
        let cell = label.replace('|', "\\|");
        let _ = writeln!(md, "| {cell} | {l1:.2e} | {l2:.2e} | {d1:.2e} | {d2:.2e} |");
        let series = |label: &str, v: &[Invariants], color: usize| Series {
            label: label.into(),
            points: v.iter().skip(1).map(|i| (i.t, f(i))).collect(),
            style: Style::Line,
            color,
        };
        figures.push((
            format!("long_run_{name}"),
            Figure {
                title: format!("Long run, case A: {label}"),
                x_label: "time t".into(),
                y_label: label.into(),
                x_log: false,
                y_log: true,
                series: vec![
                    series(&legend, lgsvi, 0),
                    series("DOP853, (R, Ω), tol 1e-13", dop, 1),
                ],
                hlines: vec![],
            },
        ));
    }
    if let Some(trend) = trend {
        let row = |name: &str, spread: &Spread| {
            format!(
                "| {name} | {:+.2e} ± {:.2e} | {:.2e} | {}/{} | {} |",
                spread.mean,
                spread.standard_error,
                spread.rms,
                spread.values.iter().filter(|v| **v < 0.0).count(),
                trend.members,
                if spread.consistent_with_zero() {
                    "none detected"
                } else {
                    "**drift**"
                }
            )
        };
        let _ = write!(
            md,
            "\n## Trend\n\nOne trajectory cannot tell a linear drift from a random walk of rounding errors. {} initial conditions near case A's (Ω₀ scaled by 1 + 10⁻³k, shifted by 10⁻³k along y), {steps} steps each, same settings, in {:.1} s on every core: signed relative errors at the end. A trend is reported when the mean is more than three standard errors from 0; a random walk's rms grows as √steps.\n\n| quantity | mean ± standard error | rms | negative | trend |\n|---|---|---|---|---|\n{}\n{}\n",
            trend.members,
            trend.seconds,
            row("(E − E₀)/E₀", &trend.energy),
            row("(\\|μ\\|² − \\|μ₀\\|²)/\\|μ₀\\|²", &trend.casimir),
        );
    }
    (md, figures)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(method: &str, error: f64, time_s: f64) -> Point {
        Point::new(
            "A",
            10.0,
            method,
            "k".into(),
            Ok::<f64, String>(error),
            time_s,
        )
    }

    #[test]
    fn cells_state_the_ratio_or_who_does_not_reach_the_target() {
        let (l, d) = (
            point("lgsvi (exp", 1e-11, 2e-3),
            point("DOP853", 1e-11, 1e-3),
        );
        assert_eq!(
            ratio_cell(Some(&l), Some(&d), |_| String::new()),
            " 2.00 (2.000 / 1.000 ms) |"
        );
        assert_eq!(
            ratio_cell(Some(&l), Some(&d), |p| format!("n = {}", p.knob)),
            " 2.00 (2.000 / 1.000 ms; n = k) |"
        );
        assert_eq!(
            ratio_cell(Some(&l), None, |_| String::new()),
            " DOP853 does not reach it |"
        );
        assert_eq!(
            ratio_cell(None, Some(&d), |_| String::new()),
            " lgsvi does not reach it |"
        );
        assert_eq!(
            beyond_cell(Some(&l), Some(&d)),
            " 2.00 (lgsvi 1.0e-11 in 2.000 ms; DOP853 1.0e-11 in 1.000 ms) |"
        );
        assert_eq!(beyond_cell(None, Some(&d)), " – |");
    }
}
