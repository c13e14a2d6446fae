//! A convergence study as a console table and as CSV.

use lgsvi_experiments::convergence::{Measurement, Study};
use lgsvi_experiments::fit::FIT_CEILING;
use std::fmt::Write;

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
