//! lgsvi against what users would pick instead, measured side by side in one process:
//! DOP853 on quaternions and on matrices, the Lie group variational integrator of Lee, Leok
//! and McClamroch, a rotation splitting and their Yoshida compositions
//! (`lgsvi-baselines`), on the named cases of `lgsvi-cases` against their 40-digit
//! references.
//!
//! - [`so3`]: the work-precision sweep of cases A and B (every method over its knob, each
//!   run timed whole, construction included, median of the repeats), and the parallel
//!   ensemble;
//! - [`space`]: the same protocol for the orbiting body O1 and the torqued body F1;
//! - [`dispersion`]: Monte Carlo throughput, dispersed members of case A to 1e-10 by lgsvi
//!   and by DOP853 on the same threads;
//! - [`long_run`]: a long run of case A beside DOP853, its invariants over time, and the
//!   energy-trend ensemble that tells a drift from a random walk.
//!
//! Everything returns data (`lgsvi_experiments::work_precision::Point` and the structs
//! here); `lgsvi bench` turns it into tables, plots and files.

#![warn(missing_docs)]

pub mod dispersion;
mod error;
pub mod long_run;
pub mod report;
pub mod so3;
pub mod space;

pub use error::BenchError;

/// The 40-digit reference attitude of a named case at `t` (10 or 100).
fn reference(case: &str, t: f64) -> nalgebra::Matrix3<f64> {
    named_case(case)
        .attitude_at(t)
        .expect("the references hold t = 10 and t = 100")
}

/// lgsvi's fixed-`(h, n)` arm of a work-precision sweep: every `n` of every `(h, nodes)` in
/// `sweeps`, timed whole by `run(h, n)` (median of `repeats`), handed to `push` as method
/// `lgsvi (exp, h = …)` and knob `n = …`, then `tick`.
fn lgsvi_fixed_runs<R>(
    repeats: usize,
    sweeps: &[(f64, std::ops::RangeInclusive<usize>)],
    mut run: impl FnMut(f64, usize) -> R,
    push: &mut impl FnMut(&str, String, R, f64),
    tick: &mut impl FnMut(),
) {
    for (h, nodes) in sweeps {
        for n in nodes.clone() {
            let (r, t) = lgsvi_experiments::work_precision::median_time(repeats, || run(*h, n));
            push(&format!("lgsvi (exp, h = {h})"), format!("n = {n}"), r, t);
            tick();
        }
    }
}

/// A case this crate names itself: a literal, so its absence is a defect of the build.
fn named_case(name: &str) -> &'static lgsvi_cases::Case {
    lgsvi_cases::case(name).unwrap_or_else(|e| panic!("{e}"))
}
