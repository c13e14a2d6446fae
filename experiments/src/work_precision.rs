//! Work-precision comparisons: one run of one method at one setting (its error and median
//! time, [`Point`]), the fastest run at an error target and the most accurate run of a
//! method, and the timing policy they share ([`median_time`]).
//!
//! ```
//! use lgsvi_experiments::work_precision::{fastest, median_time, Point};
//! let mut points = Vec::new();
//! for (knob, error) in [("4", 1e-6), ("8", 1e-11)] {
//!     let (result, time_s) = median_time(3, || Ok::<f64, String>(error));
//!     points.push(Point::new("A", 10.0, "lgsvi", knob.into(), result, time_s));
//! }
//! assert_eq!(fastest(&points, "A", 10.0, "lgsvi", 1e-10).unwrap().knob, "8");
//! assert!(fastest(&points, "A", 10.0, "lgsvi", 1e-12).is_none());
//! ```

use serde::Serialize;
use std::fmt::Display;
use std::time::Instant;

/// One point of a work-precision curve.
#[derive(Debug, Clone, Serialize)]
pub struct Point {
    /// The case's name.
    pub case: String,
    /// The horizon.
    pub t_end: f64,
    /// The method's name (compared by prefix in [`fastest`] and [`most_accurate`]).
    pub method: String,
    /// The knob: `n` for lgsvi, the step for fixed-step methods, the tolerance for DOP853.
    pub knob: String,
    /// `‖R(T) − R_ref(T)‖_F` against the shared 40-digit reference.
    pub error: f64,
    /// Median wall time of the whole run (construction included), seconds.
    pub time_s: f64,
    /// Why the run failed, if it did (and then `error` is NaN).
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
        error: Result<f64, impl Display>,
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

/// The median of `v` (the upper one of an even count; NaN for none), the timing policy's
/// statistic ([`median_time`]).
pub fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Times `run` `repeats` times (at least once); returns the last result and the median
/// time in seconds: the timing policy of every work-precision comparison (the median
/// resists the outliers of a shared machine in both directions).
pub fn median_time<T>(repeats: usize, mut run: impl FnMut() -> T) -> (T, f64) {
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
