//! Every error of this crate, triggered through the public API, says what was wrong with
//! which input: each message is checked for the input's name or value and, where there is
//! one, what to change.

use lgsvi_spectral::SpectralError;
use lgsvi_spectral::{chebyshev_first_kind, chebyshev_lobatto, Barycentric, Chebyshev};

/// The error's message holds every needle.
fn says<T: std::fmt::Debug>(result: Result<T, SpectralError>, needles: &[&str]) {
    let text = result.expect_err("refused").to_string();
    for needle in needles {
        assert!(text.contains(needle), "{text:?} does not say {needle:?}");
    }
}

#[test]
fn every_error_names_its_input_and_the_remedy() {
    // TooFewNodes: the family, the least count and the count given.
    says(
        chebyshev_lobatto(1, 0.0, 1.0),
        &["Chebyshev", "at least 2", "got 1"],
    );
    says(chebyshev_first_kind(0, 0.0, 1.0), &["at least 1", "got 0"]);
    // NonFiniteInterval and EmptyInterval: the interval and "a < b".
    says(
        chebyshev_lobatto(4, 0.0, f64::NAN),
        &["[0, NaN]", "finite a < b"],
    );
    says(chebyshev_lobatto(4, 1.0, 1.0), &["[1, 1]", "give a < b"]);
    // NonFiniteNode: which node; DuplicateNode: which two and "distinct".
    says(
        Barycentric::new(vec![0.0, f64::INFINITY]),
        &["node 1", "inf"],
    );
    says(
        Barycentric::new(vec![0.0, 2.0, 1.0, 2.0]),
        &["nodes 1 and 3", "must be distinct"],
    );
    // WeightUnderflow: the remedy (Chebyshev nodes).
    let equispaced: Vec<f64> = (0..1200).map(|k| k as f64 / 1199.0).collect();
    says(
        Barycentric::new(equispaced),
        &["1200 nodes", "use Chebyshev nodes"],
    );
    // LengthMismatch and NonFinitePoint.
    let basis = Barycentric::chebyshev_lobatto(4, 0.0, 1.0).unwrap();
    says(
        basis.interpolate(&[1.0, 2.0], 0.5),
        &["length 2", "expected 4"],
    );
    says(basis.interpolate(&[0.0; 4], f64::NAN), &["point NaN"]);
    // NonFiniteValue: where the function is not finite, and to fit elsewhere.
    says(
        Chebyshev::fit(|x| 1.0 / x, -1.0, 1.0),
        &["not finite at x = ", "fit it on an interval where it is"],
    );
    // NonFiniteCoefficient: which coefficient.
    says(
        Chebyshev::from_coefficients(vec![1.0, f64::NAN], 0.0, 1.0),
        &["coefficient 1", "NaN"],
    );
    // NotResolved: the tolerance, the interval and the remedies.
    says(
        Chebyshev::fit(f64::abs, -1.0, 2.0),
        &["[-1, 2]", "split the interval or raise the tolerance"],
    );
    // InvalidTolerance: the tolerance and its range.
    says(
        Chebyshev::fit_with_tolerance(f64::sin, 0.0, 1.0, 1e-20),
        &["1e-20", "outside [2.2e-16, 1)"],
    );
    // OutsideInterval: the point, the interval and the remedy.
    let f = Chebyshev::fit(f64::sin, 0.0, 1.0).unwrap();
    says(
        f.evaluate(10.0),
        &["x = 10", "[0, 1]", "refit on a larger one"],
    );
    // IntervalMismatch: both intervals and the remedy.
    let g = Chebyshev::fit(f64::cos, -1.0, 1.0).unwrap();
    says(
        f.add(&g),
        &[
            "(0.0, 1.0)",
            "(-1.0, 1.0)",
            "combine series on one interval",
        ],
    );
}
