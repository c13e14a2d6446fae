//! Rates fitted to refinement series: the geometric factor per node of an n-refinement and
//! the algebraic order of an h-refinement, each on the series' asymptotic points only.
//!
//! A point is asymptotic when its error is below [`FIT_CEILING`] (the run has not lost all
//! accuracy) and the series has not yet reached its rounding floor: once the smallest error
//! of a series is below 1e-11, errors within ×30 of it are noise, and never is anything
//! below [`FIT_FLOOR`] fitted.

/// Errors below this are the rounding floor, left out of rate fits.
pub const FIT_FLOOR: f64 = 1e-13;

/// Errors above this are not yet asymptotic (the solution has lost all accuracy) and are
/// left out of fits.
pub const FIT_CEILING: f64 = 0.1;

/// Least-squares slope of `y` against `x`.
fn slope(points: &[(f64, f64)]) -> Option<f64> {
    if points.len() < 2 {
        return None;
    }
    let n = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    (sxx > 0.0).then(|| sxy / sxx)
}

/// The rounding floor of a series: when it reaches rounding (its smallest error below
/// 1e-11), errors within ×30 of that smallest error are noise; never below [`FIT_FLOOR`].
fn floor_of(errors: impl Iterator<Item = f64>) -> f64 {
    let min = errors
        .filter(|e| e.is_finite() && *e > 0.0)
        .fold(f64::INFINITY, f64::min);
    if min < 1e-11 {
        (30.0 * min).max(FIT_FLOOR)
    } else {
        FIT_FLOOR
    }
}

/// The points of a refinement series (ordered from coarse to fine) that are asymptotic:
/// below [`FIT_CEILING`], and before the first error at the series' rounding floor.
fn asymptotic(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let floor = floor_of(points.iter().map(|p| p.1));
    points
        .iter()
        .filter(|(_, e)| e.is_finite())
        .take_while(|(_, e)| *e > floor)
        .filter(|(_, e)| *e < FIT_CEILING)
        .map(|&(x, e)| (x, e.ln()))
        .collect()
}

/// The geometric factor per node: errors fall by this factor for each node added. A
/// least-squares fit of `ln error` against `n` over the asymptotic points (module
/// documentation); `None` with fewer than two.
///
/// ```
/// use lgsvi_experiments::fit::geometric_factor;
/// let series: Vec<(usize, f64)> = (3..10).map(|n| (n, 0.5 * 8f64.powi(-(n as i32)))).collect();
/// assert!((geometric_factor(&series).unwrap() - 8.0).abs() < 1e-9);
/// ```
pub fn geometric_factor(points: &[(usize, f64)]) -> Option<f64> {
    let mut sorted: Vec<(f64, f64)> = points.iter().map(|&(n, e)| (n as f64, e)).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    slope(&asymptotic(&sorted)).map(|s| (-s).exp())
}

/// The algebraic order in the asymptotic regime: the slope of `log error` against `log h`
/// between the two smallest steps among the asymptotic points (as for
/// [`geometric_factor`]); `None` with fewer than two.
///
/// ```
/// use lgsvi_experiments::fit::algebraic_order;
/// let series: Vec<(f64, f64)> = [0.5, 0.25, 0.125].iter().map(|&h: &f64| (h, 1e-2 * h.powi(4))).collect();
/// assert!((algebraic_order(&series).unwrap() - 4.0).abs() < 1e-9);
/// ```
pub fn algebraic_order(points: &[(f64, f64)]) -> Option<f64> {
    let mut sorted: Vec<(f64, f64)> = points.to_vec();
    sorted.sort_by(|a, b| b.0.total_cmp(&a.0));
    let fit = asymptotic(&sorted);
    let fit: Vec<(f64, f64)> = fit
        .iter()
        .rev()
        .take(2)
        .map(|&(h, e)| (h.ln(), e))
        .collect();
    slope(&fit)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_recover_known_rates_and_ignore_the_floor() {
        // error = 3·10^{-n} down to a noisy floor near 1e-14, saturated at n = 1.
        let mut points: Vec<(usize, f64)> = (2..=12)
            .map(|n| (n, 3.0 * 10f64.powi(-(n as i32))))
            .collect();
        points.insert(0, (1, 2.0));
        points.extend([(13, 4e-14), (14, 2e-14), (15, 9e-14), (16, 3e-14)]);
        let q = geometric_factor(&points).unwrap();
        assert!((q - 10.0).abs() < 1e-9, "{q}");
        // error = h^6 down to a floor.
        let mut points: Vec<(f64, f64)> = [1.0, 0.5, 0.25, 0.125, 0.0625]
            .iter()
            .map(|&h: &f64| (h, 1e-3 * h.powi(6)))
            .collect();
        points.push((0.03125, 3e-14));
        points.push((0.015625, 5e-14));
        let p = algebraic_order(&points).unwrap();
        assert!((p - 6.0).abs() < 1e-9, "{p}");
        // Not enough points: no fit.
        assert_eq!(algebraic_order(&[(1.0, 1e-3)]), None);
        assert_eq!(geometric_factor(&[(3, f64::NAN), (4, 1e-3)]), None);
    }
}
