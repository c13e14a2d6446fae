//! The settings a slew and a manoeuvre share, checked once: each refusal names the setting
//! and says what to give.

use crate::OptimalError;
use nalgebra::SVector;

/// A setting out of range.
pub(crate) fn invalid(name: &'static str, value: String, reason: &str) -> OptimalError {
    OptimalError::InvalidSetting {
        name,
        value,
        reason: reason.into(),
    }
}

/// A disturbance (torque or wrench), where given: finite.
pub(crate) fn disturbance<const N: usize>(
    disturbance: Option<SVector<f64, N>>,
) -> Result<(), OptimalError> {
    match disturbance.filter(|d| !d.iter().all(|x| x.is_finite())) {
        Some(d) => Err(invalid(
            "disturbance",
            format!("{:?}", d.as_slice()),
            "not finite",
        )),
        None => Ok(()),
    }
}

/// The final time (positive and finite) and the step count (2 to 100000); `conditions`
/// says why two steps at least (the terminal conditions against one step's inputs).
pub(crate) fn horizon(t_end: f64, steps: usize, conditions: &str) -> Result<(), OptimalError> {
    if !(t_end.is_finite() && t_end > 0.0) {
        return Err(invalid(
            "t_end",
            format!("{t_end:?}"),
            "the final time is positive and finite",
        ));
    }
    if !(2..=100_000).contains(&steps) {
        return Err(invalid(
            "steps",
            steps.to_string(),
            &format!("from 2 to 100000 steps ({conditions})"),
        ));
    }
    Ok(())
}

/// A bound per axis, each positive and finite.
pub(crate) fn bound<const N: usize>(
    name: &'static str,
    bound: Option<SVector<f64, N>>,
) -> Result<(), OptimalError> {
    match bound {
        Some(bound) if bound.iter().any(|b| !(b.is_finite() && *b > 0.0)) => Err(invalid(
            name,
            format!("{:?}", bound.as_slice()),
            "each axis's bound is positive and finite",
        )),
        _ => Ok(()),
    }
}

/// The scaled KKT residual to reach, from 1e-14 to below 1.
pub(crate) fn tolerance(tolerance: f64) -> Result<(), OptimalError> {
    if tolerance.is_finite() && (1e-14..1.0).contains(&tolerance) {
        return Ok(());
    }
    Err(invalid(
        "tolerance",
        format!("{tolerance:?}"),
        "a scaled KKT residual from 1e-14 to below 1",
    ))
}

/// A warm start of `steps` steps: finite, and one input (`noun`, e.g. "torque", plural
/// `nouns`) per step
/// or, with polynomial inputs, one per Gauss point of each step (`points`, asked only for
/// finite inputs).
pub(crate) fn warm_start<const M: usize>(
    initial: &[SVector<f64, M>],
    steps: usize,
    points: impl FnOnce() -> Result<usize, OptimalError>,
    [noun, nouns]: [&str; 2],
) -> Result<(), OptimalError> {
    let value = format!("{} {nouns}", initial.len());
    if initial.iter().any(|u| !u.iter().all(|x| x.is_finite())) {
        return Err(invalid("warm_start", value, "not finite"));
    }
    let points = points()?;
    if initial.len() != steps && initial.len() != steps * points {
        return Err(invalid(
            "warm_start",
            value,
            &format!(
                "one {noun} per step (or, with polynomial inputs, one per Gauss point of each \
                 step)"
            ),
        ));
    }
    Ok(())
}

/// The tracking and terminal costs: `tracking` as the reference states and their weights
/// (one state per step boundary after the start, `steps` of them, each `finite`);
/// `terminal` as its weights; every weight finite and not negative.
pub(crate) fn costs<T, const W: usize>(
    tracking: Option<&(Vec<T>, [f64; W])>,
    finite: impl Fn(&T) -> bool,
    steps: usize,
    terminal: Option<&[f64; W]>,
) -> Result<(), OptimalError> {
    let valid = |w: &[f64]| w.iter().all(|x| x.is_finite() && *x >= 0.0);
    if let Some((states, weights)) = tracking {
        let count = states.len();
        if count != steps || !valid(weights) || !states.iter().all(&finite) {
            return Err(invalid(
                "track",
                format!("{count} states, weights {weights:?}"),
                "one finite reference state per step boundary after the start (K of them), \
                 weights finite and not negative",
            ));
        }
    }
    match terminal {
        Some(weights) if !valid(weights) => Err(invalid(
            "terminal_cost",
            format!("{weights:?}"),
            "weights finite and not negative",
        )),
        _ => Ok(()),
    }
}
