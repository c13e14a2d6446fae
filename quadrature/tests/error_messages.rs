//! Every error of this crate that an input can cause, triggered through the public API,
//! says what was wrong with which input: each message is checked for the input's name or
//! value and, where there is one, what to change. (`EigenNotConverged` guards the
//! eigenvalue iteration, which converges on every Jacobi matrix the rules build: no input
//! reaches it.)

use lgsvi_quadrature::{
    gauss_hermite, gauss_jacobi, gauss_kronrod_jacobi, gauss_laguerre, gauss_legendre,
    gauss_lobatto, golub_welsch, QuadratureError,
};

/// The error's message holds every needle.
fn says<T: std::fmt::Debug>(result: Result<T, QuadratureError>, needles: &[&str]) {
    let text = result.expect_err("refused").to_string();
    for needle in needles {
        assert!(text.contains(needle), "{text:?} does not say {needle:?}");
    }
}

#[test]
fn every_error_names_its_input_and_the_remedy() {
    // TooFewPoints: the rule, the least count and the count given.
    says(gauss_lobatto(1), &["Lobatto", "at least 2", "got 1"]);
    says(gauss_legendre(0), &["at least 1", "got 0"]);
    // NonFiniteInterval and EmptyInterval.
    let rule = gauss_legendre(4).unwrap();
    says(
        rule.on(0.0, f64::INFINITY),
        &["[0, inf]", "give finite ends"],
    );
    says(rule.on(2.0, 2.0), &["[2, 2]", "give a ≠ b"]);
    // JacobiShape, NonFiniteJacobi, InvalidMass: the Jacobi matrix's entries and mass.
    says(
        golub_welsch(&[0.0, 0.0], &[], 1.0),
        &["2 diagonal entries", "needs 1 off-diagonal", "got 0"],
    );
    says(
        golub_welsch(&[0.0, f64::NAN], &[1.0], 1.0),
        &["entry 1 of the diagonal"],
    );
    says(
        golub_welsch(&[0.0], &[], -1.0),
        &["positive and finite", "got -1"],
    );
    // InvalidExponent: which exponent, its value and the allowed range.
    says(gauss_laguerre(3, -1.5), &["alpha = -1.5", "above −1"]);
    says(gauss_jacobi(3, 0.0, f64::NAN), &["beta = NaN"]);
    // UnboundedRule: the family and what to do instead.
    says(
        gauss_hermite(4).unwrap().on(0.0, 1.0),
        &["Hermite", "shift and scale its nodes"],
    );
    // ReversedWeight: the interval and the remedy.
    says(
        gauss_jacobi(4, 0.5, 0.5).unwrap().on(1.0, 0.0),
        &["got [1, 0]", "map to [0, 1] and negate the result"],
    );
    // NoKronrodExtension: the rule asked for and the exponents that have one (the
    // reference table lists (−½, −½) with 2 points as having none).
    says(
        gauss_kronrod_jacobi(2, -0.5, -0.5),
        &[
            "2-point",
            "α = -0.5, β = -0.5",
            "take exponents with α = β in (−1/2, 3/2]",
        ],
    );
}
