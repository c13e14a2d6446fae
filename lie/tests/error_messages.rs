//! Every error of this crate, triggered through the public API, says what was wrong with
//! which input: each message is checked for the input's name or value and what to change.

use lgsvi_lie::so3::right_jacobian_inverse;
use lgsvi_lie::{CayleyChart, Chart, ExpChart, LieError, SE3, SO3};
use nalgebra::{Matrix3, Matrix4, Vector3};
use std::f64::consts::PI;

/// The error's message holds every needle.
fn says<T: std::fmt::Debug>(result: Result<T, LieError>, needles: &[&str]) {
    let text = result.expect_err("refused").to_string();
    for needle in needles {
        assert!(text.contains(needle), "{text:?} does not say {needle:?}");
    }
}

#[test]
fn every_error_names_its_input_and_the_remedy() {
    // NonFinite: which input, and finite entries.
    let mut nan = Matrix3::identity();
    nan[(1, 2)] = f64::NAN;
    says(
        SO3::try_from_matrix(nan),
        &["rotation matrix", "give finite entries"],
    );
    says(
        SO3::try_from_quaternion_wxyz([1.0, f64::INFINITY, 0.0, 0.0]),
        &["quaternion holds a non-finite number"],
    );
    let mut homogeneous = Matrix4::identity();
    homogeneous[(0, 3)] = f64::NAN;
    says(SE3::try_from_matrix(homogeneous), &["homogeneous matrix"]);
    // NotOrthogonal: the deviation, the tolerance and the orthonormalising constructor.
    let scaled = Matrix3::identity() * 1.001;
    says(
        SO3::try_from_matrix(scaled),
        &["not a rotation", "from_matrix_orthonormalized"],
    );
    // NotProperRotation: the determinant and that a rotation has +1.
    let reflection = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0));
    says(
        SO3::try_from_matrix(reflection),
        &["determinant -1", "a rotation has determinant +1"],
    );
    // Degenerate: the singular values and what to give instead.
    let flat = Matrix3::from_diagonal(&Vector3::new(1e20, 1e-10, 1e-10));
    says(
        SO3::from_matrix_orthonormalized(flat),
        &[
            "singular values [1e20, 1e-10, 1e-10]",
            "singular values are all near 1",
        ],
    );
    // ZeroQuaternion: the norm and what to give.
    says(
        SO3::try_from_quaternion_wxyz([0.0; 4]),
        &["norm 0", "give a non-zero one"],
    );
    // OutsideChart: the chart, the angle, its limit and what to change.
    let axis = Vector3::new(2.0, -3.0, 6.0) / 7.0;
    let half_turn =
        SO3::from_matrix_unchecked(Matrix3::identity() * -1.0 + axis * axis.transpose() * 2.0);
    says(
        CayleyChart.to_algebra(&half_turn),
        &["Cayley", "a shorter step", "take the exp chart"],
    );
    says(
        ExpChart.to_algebra(&half_turn),
        &["exponential", "keep the rotation below π"],
    );
    says(
        right_jacobian_inverse(&(axis * (2.0 * PI + 0.1))),
        &[
            "exponential chart",
            "must stay below 6.28",
            "take a shorter step",
        ],
    );
}
