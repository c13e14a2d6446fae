//! `lgsvi bench`'s table for the orbiting body O1 and the torqued body F1, from the sweep of
//! `lgsvi_bench::space`.

use crate::work_precision::{beyond_cell, ratio_cell};
use lgsvi_bench::space::{CASES, HORIZONS};
use lgsvi_experiments::work_precision::{fastest, most_accurate, Point};
use std::fmt::Write;

/// The ratio table: per case and horizon, the fastest lgsvi run at or below each error
/// target over the fastest DOP853 run at or below it, and where DOP853 does not go,
/// lgsvi's fastest run at ≤ 1e-12 and ≤ 1e-13 over DOP853's most accurate run.
pub fn ratios(points: &[Point]) -> String {
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
