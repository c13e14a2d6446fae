//! The cells of `lgsvi bench`'s ratio tables, from the work-precision points of
//! `lgsvi_experiments::work_precision`.

use lgsvi_experiments::work_precision::Point;

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
