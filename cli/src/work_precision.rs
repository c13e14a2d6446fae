//! Work-precision points and the cells of the tables that compare them: one run of one
//! method at one setting (its error and median time), the fastest run at an error target,
//! the most accurate run, and the ratio cells of `lgsvi bench`'s tables.

use crate::error::Result;
use serde::Serialize;
use std::time::Instant;

/// One point of a work-precision curve.
#[derive(Debug, Clone, Serialize)]
pub struct Point {
    pub case: String,
    pub t_end: f64,
    pub method: String,
    /// The knob: `n` for lgsvi, the step for fixed-step methods, the tolerance for DOP853.
    pub knob: String,
    /// `‖R(T) − R_ref(T)‖_F` against the shared 40-digit reference.
    pub error: f64,
    /// Median wall time of the whole run (construction included), seconds.
    pub time_s: f64,
    pub failure: Option<String>,
}

impl Point {
    /// A run of `method` at `knob` on `case` to `t_end` that took `time_s`: its error, or
    /// the error that stopped it (error NaN, the message kept).
    pub fn new(
        case: &str,
        t_end: f64,
        method: &str,
        knob: String,
        error: Result<f64>,
        time_s: f64,
    ) -> Self {
        let (error, failure) = match error {
            Ok(error) => (error, None),
            Err(e) => (f64::NAN, Some(e.to_string())),
        };
        Self {
            case: case.into(),
            t_end,
            method: method.into(),
            knob,
            error,
            time_s,
            failure,
        }
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Times `run` `repeats` times; returns the last result and the median time.
pub fn timed<T>(repeats: usize, mut run: impl FnMut() -> T) -> (T, f64) {
    let mut times = Vec::with_capacity(repeats);
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        let out = run();
        times.push(start.elapsed().as_secs_f64());
        last = Some(out);
    }
    (last.expect("at least one run"), median(times))
}

/// The fastest run of `method` (prefix) at or below `error` for a case and horizon.
pub fn fastest<'a>(
    points: &'a [Point],
    case: &str,
    t_end: f64,
    method: &str,
    error: f64,
) -> Option<&'a Point> {
    points
        .iter()
        .filter(|p| {
            p.case == case && p.t_end == t_end && p.method.starts_with(method) && p.error <= error
        })
        .min_by(|a, b| a.time_s.total_cmp(&b.time_s))
}

/// The most accurate finite run of `method` (prefix) for a case and horizon.
pub fn most_accurate<'a>(
    points: &'a [Point],
    case: &str,
    t_end: f64,
    method: &str,
) -> Option<&'a Point> {
    points
        .iter()
        .filter(|p| {
            p.case == case
                && p.t_end == t_end
                && p.method.starts_with(method)
                && p.error.is_finite()
        })
        .min_by(|a, b| a.error.total_cmp(&b.error))
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
