//! The error-estimate and tolerance studies of `lgsvi_experiments::tolerance` as console
//! tables and figures.

use lgsvi_experiments::tolerance::{
    calibration, LocalError, ToleranceRun, LOCAL_FLOOR, TRUTH_EXTRA_NODES,
};
use lgsvi_plot::{Figure, Series, Style};
use std::fmt::Write;

/// The estimate study as a table: per `(h, n)`, then over all steps.
pub fn estimate_table(rows: &[LocalError]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Local error estimate against the true local error (the step with {TRUTH_EXTRA_NODES} \
         more nodes from the same state); log10(estimate / truth) over the steps whose true \
         error is above {LOCAL_FLOOR:.0e} of the state's largest entry (at least 1):"
    );
    let _ = writeln!(
        out,
        "{:>6} {:>4} {:>6} {:>9} {:>9} {:>8} {:>8} {:>8}",
        "h", "n", "steps", "truth max", "est max", "mean", "sd", "range"
    );
    let mut keys: Vec<(f64, usize)> = rows.iter().map(|r| (r.h, r.nodes)).collect();
    keys.dedup();
    for (h, n) in keys {
        let group: Vec<LocalError> = rows
            .iter()
            .filter(|r| r.h == h && r.nodes == n)
            .copied()
            .collect();
        let truth = group.iter().map(|r| r.truth).fold(0.0, f64::max);
        let est = group.iter().map(|r| r.estimate).fold(0.0, f64::max);
        match calibration(&group) {
            Some((mean, sd, lo, hi, _, count)) => {
                let _ = writeln!(
                    out,
                    "{h:>6} {n:>4} {count:>6} {truth:>9.1e} {est:>9.1e} {mean:>+8.2} {sd:>8.2} {lo:>+5.1}..{hi:+.1}"
                );
            }
            None => {
                let _ = writeln!(
                    out,
                    "{h:>6} {n:>4} {:>6} {truth:>9.1e} {est:>9.1e}   (at rounding)",
                    0
                );
            }
        }
    }
    if let Some((mean, sd, lo, hi, within, count)) = calibration(rows) {
        let _ = writeln!(
            out,
            "all: {count} steps, mean {mean:+.2}, sd {sd:.2}, range {lo:+.2}..{hi:+.2} decades; \
             {:.0}% within a factor 30",
            100.0 * within
        );
    }
    out
}

/// The tolerance study as a table.
pub fn tolerance_table(describe: &str, runs: &[ToleranceRun]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "Reference: {describe}.");
    let _ = writeln!(
        out,
        "{:>7} {:>7} {:>9} {:>7} {:>9} {:>9} {:>22} {:>6}  nodes (n:steps)",
        "tol", "h", "error", "err/tol", "estimate", "time ms", "best fixed h, n, ms", "ratio"
    );
    for r in runs {
        if let Some(why) = &r.failure {
            let _ = writeln!(out, "{:>7.0e} failed: {why}", r.tol);
            continue;
        }
        let best = r
            .best_fixed
            .map_or("none as accurate".to_string(), |(h, n, _, t)| {
                format!("{h}, {n}, {:.3}", t * 1e3)
            });
        let ratio = r.best_fixed.map_or(String::new(), |(_, _, _, t)| {
            format!("{:.2}", r.wall_time_s / t)
        });
        let nodes: Vec<String> = r.nodes.iter().map(|(n, c)| format!("{n}:{c}")).collect();
        let _ = writeln!(
            out,
            "{:>7.0e} {:>7.4} {:>9.1e} {:>7.2} {:>9.1e} {:>9.3} {:>22} {:>6}  {}{}",
            r.tol,
            r.h,
            r.error,
            r.error / r.tol,
            r.estimated_error,
            r.wall_time_s * 1e3,
            best,
            ratio,
            nodes.join(" "),
            if r.rejected_steps > 0 {
                format!(" ({} redone)", r.rejected_steps)
            } else {
                String::new()
            }
        );
    }
    out
}

/// The estimate-vs-truth scatter, with the diagonal and the factor-30 band.
pub fn estimate_figure(title: &str, rows: &[LocalError]) -> Figure {
    let kept: Vec<&LocalError> = rows
        .iter()
        .filter(|r| r.above_rounding() && r.estimate > 0.0)
        .collect();
    let mut nodes: Vec<usize> = kept.iter().map(|r| r.nodes).collect();
    nodes.sort_unstable();
    nodes.dedup();
    let mut series: Vec<Series> = nodes
        .iter()
        .enumerate()
        .map(|(i, &n)| Series {
            label: format!("n = {n}"),
            points: kept
                .iter()
                .filter(|r| r.nodes == n)
                .map(|r| (r.truth, r.estimate))
                .collect(),
            style: Style::Markers,
            color: i,
        })
        .collect();
    let lo = kept.iter().map(|r| r.truth).fold(f64::INFINITY, f64::min);
    let hi = kept.iter().map(|r| r.truth).fold(0.0, f64::max);
    if lo < hi {
        series.push(Series {
            label: "estimate = truth".into(),
            points: vec![(lo, lo), (hi, hi)],
            style: Style::Line,
            color: 11,
        });
        series.push(Series {
            label: "30 × truth".into(),
            points: vec![(lo, lo * 30.0), (hi, hi * 30.0)],
            style: Style::DashedMarkers,
            color: 8,
        });
        series.push(Series {
            label: "truth / 30".into(),
            points: vec![(lo, lo / 30.0), (hi, hi / 30.0)],
            style: Style::DashedMarkers,
            color: 8,
        });
    }
    Figure {
        title: title.into(),
        x_label: "true local error (the step with 14 more nodes)".into(),
        y_label: "estimated local error".into(),
        x_log: true,
        y_log: true,
        series,
        hlines: Vec::new(),
    }
}

/// Achieved error and the run's own estimate against the tolerance, with the window
/// `[tol/100, 10 tol]`.
pub fn tolerance_figure(title: &str, runs: &[ToleranceRun]) -> Figure {
    let ok: Vec<&ToleranceRun> = runs.iter().filter(|r| r.failure.is_none()).collect();
    let line = |label: &str, factor: f64, style: Style, color: usize| Series {
        label: label.into(),
        points: ok.iter().map(|r| (r.tol, r.tol * factor)).collect(),
        style,
        color,
    };
    Figure {
        title: title.into(),
        x_label: "tolerance".into(),
        y_label: "error at the horizon".into(),
        x_log: true,
        y_log: true,
        series: vec![
            Series {
                label: "error against the reference".into(),
                points: ok.iter().map(|r| (r.tol, r.error)).collect(),
                style: Style::LineMarkers,
                color: 0,
            },
            Series {
                label: "the run's own estimate".into(),
                points: ok.iter().map(|r| (r.tol, r.estimated_error)).collect(),
                style: Style::DashedMarkers,
                color: 1,
            },
            line("10 × tol", 10.0, Style::Line, 11),
            line("tol / 100", 0.01, Style::DashedMarkers, 8),
        ],
        hlines: Vec::new(),
    }
}
