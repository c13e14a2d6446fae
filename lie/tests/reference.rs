//! exp, log, both Cayley transforms, J_r and J_r⁻¹ against 50-digit mpmath values
//! (`tests/data/generate_reference.py`) at rotation angles 0, 1e-12, 1e-8, 1e-4, 1, π/2,
//! π − 1e-6 and, for exp and J_r, 2π − 1e-3, about the axis (2, −3, 6)/7. Run with
//! `--nocapture` for the worst errors per function and angle.

mod common;

use common::EPS;
use lgsvi_lie::so3::{right_jacobian, right_jacobian_inverse};
use lgsvi_lie::{CayleyChart, Chart, ExpChart, UnscaledCayleyChart, SO3};
use nalgebra::{Matrix3, Vector3};
use std::collections::HashMap;
use std::f64::consts::PI;

type Table = HashMap<(String, String), Vec<f64>>;

fn table() -> Table {
    include_str!("data/reference_values.txt")
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let mut it = l.split_whitespace();
            let kind = it.next().unwrap().to_string();
            let label = it.next().unwrap().to_string();
            ((kind, label), it.map(|x| x.parse().unwrap()).collect())
        })
        .collect()
}

fn angle(label: &str) -> f64 {
    match label {
        "0" => 0.0,
        "1e-12" => 1e-12,
        "1e-8" => 1e-8,
        "1e-4" => 1e-4,
        "1" => 1.0,
        "pi/2" => PI / 2.0,
        "pi-1e-6" => PI - 1e-6,
        "2pi-1e-3" => 2.0 * PI - 1e-3,
        other => panic!("unknown angle {other}"),
    }
}

const LABELS: [&str; 8] = [
    "0", "1e-12", "1e-8", "1e-4", "1", "pi/2", "pi-1e-6", "2pi-1e-3",
];

fn axis() -> Vector3<f64> {
    Vector3::new(2.0, -3.0, 6.0) / 7.0
}

fn matrix(values: &[f64]) -> Matrix3<f64> {
    Matrix3::from_row_slice(values)
}

fn vector(values: &[f64]) -> Vector3<f64> {
    Vector3::from_row_slice(values)
}

fn report(name: &str, label: &str, err: f64, tol: f64) {
    println!(
        "{name:<16} θ = {label:<9} error {:>8.2} ε   (bound {:>9.1} ε)",
        err / EPS,
        tol / EPS
    );
    assert!(err <= tol, "{name} at θ = {label}: {err:e} > {tol:e}");
}

#[test]
fn exponential_and_jacobians() {
    let t = table();
    for label in LABELS {
        let w = axis() * angle(label);
        // Rodrigues sums three O(1) terms per entry (a few ε), and rounding ω to doubles
        // moves it by up to ε|ω|, which moves R as much: 4ε(2 + |ω|).
        let r = SO3::exp(&w);
        let expected = matrix(&t[&("exp".into(), label.into())]);
        let tol_exp = 4.0 * EPS * (2.0 + w.norm());
        report("exp", label, (r.matrix() - expected).amax(), tol_exp);
        if label == "0" {
            continue;
        }
        let jr = matrix(&t[&("jr".into(), label.into())]);
        report("J_r", label, (right_jacobian(&w) - jr).amax(), tol_exp);
        // J_r⁻¹ = I + ω̂/2 + d ω̂², d = 1/θ² − cot(θ/2)/(2θ): a relative error ε in θ/2
        // moves cot(θ/2) by ε(θ/2)/sin²(θ/2), hence the entries (~θ² d) by
        // εθ²/(4 sin²(θ/2)) — large only near 2π, where J_r is singular.
        let jr_inv = matrix(&t[&("jr_inverse".into(), label.into())]);
        let th = angle(label);
        let conditioning = th * th / (4.0 * (th / 2.0).sin().powi(2));
        report(
            "J_r^-1",
            label,
            (right_jacobian_inverse(&w).unwrap() - jr_inv).amax(),
            16.0 * EPS * (jr_inv.amax() + conditioning),
        );
    }
}

#[test]
fn logarithm() {
    let t = table();
    for label in LABELS.iter().filter(|l| **l != "2pi-1e-3") {
        // Input: the reference rotation matrix rounded to doubles (entry errors ≤ ε/2), so
        // the recovered vector carries that rounding through log's derivative, which is
        // ≤ θ/(2 sin(θ/2)) ≤ π/2: 8ε(1 + |ω|) covers rounding in and out.
        let r = SO3::from_matrix_unchecked(matrix(&t[&("exp".into(), (*label).into())]));
        let expected = vector(&t[&("log".into(), (*label).into())]);
        let tol = 8.0 * EPS * (1.0 + expected.norm());
        report("log", label, (r.log() - expected).amax(), tol);
        let via_chart = ExpChart.to_algebra(&r).unwrap();
        assert_eq!(via_chart, r.log());
    }
}

#[test]
fn cayley_transforms() {
    let t = table();
    for label in LABELS.iter().filter(|l| **l != "2pi-1e-3") {
        for (kind, vector_kind) in [
            ("cayley", "cayley_vector"),
            ("cayley_unscaled", "cayley_unscaled_vector"),
        ] {
            let c = vector(&t[&(vector_kind.into(), (*label).into())]);
            let expected = matrix(&t[&(kind.into(), (*label).into())]);
            let (r, back): (SO3, Vector3<f64>) = if kind == "cayley" {
                let r: SO3 = CayleyChart.to_group(&c);
                let back = CayleyChart
                    .to_algebra(&SO3::from_matrix_unchecked(expected))
                    .unwrap();
                (r, back)
            } else {
                let r: SO3 = UnscaledCayleyChart.to_group(&c);
                let back = UnscaledCayleyChart
                    .to_algebra(&SO3::from_matrix_unchecked(expected))
                    .unwrap();
                (r, back)
            };
            report(kind, label, (r.matrix() - expected).amax(), 8.0 * EPS);
            // Φ⁻¹ from the rounded matrix: |c| = k tan(θ/2) with d|c|/dθ = (k/2)(1 + tan²),
            // so an input rounding of ε in θ moves c by (k/2 + |c|²/(2k))·ε; plus the
            // direction's 8ε|c|. (k = 2 standard, 1 unscaled.)
            let k = if kind == "cayley" { 2.0 } else { 1.0 };
            let cn = c.norm();
            let tol = 8.0 * EPS * (k / 2.0 + cn * cn / (2.0 * k) + cn + 1.0);
            report(&format!("{kind}^-1"), label, (back - c).amax(), tol);
        }
    }
}

#[test]
fn domains_are_refused_with_typed_errors() {
    use lgsvi_lie::LieError;
    let half_turn = SO3::exp(&(axis() * PI));
    // A rotation by exactly π: no chart here has it in its image.
    let exact_pi =
        SO3::from_matrix_unchecked(Matrix3::identity() * -1.0 + axis() * axis().transpose() * 2.0);
    let r = exact_pi;
    assert!(matches!(
        ExpChart.to_algebra(&r),
        Err(LieError::OutsideChart { .. })
    ));
    assert!(matches!(
        CayleyChart.to_algebra(&r),
        Err(LieError::OutsideChart { .. })
    ));
    assert!(matches!(
        UnscaledCayleyChart.to_algebra(&r),
        Err(LieError::OutsideChart { .. })
    ));
    // log itself is total: angle π.
    assert!((half_turn.log().norm() - PI).abs() < 1e-15);
    // The differential of exp is singular at 2π.
    let w = axis() * (2.0 * PI);
    let err = right_jacobian_inverse(&w).unwrap_err();
    assert!(matches!(err, LieError::OutsideChart { .. }));
    assert!(err.to_string().contains("shorter step"), "{err}");
    let tau = 2.0 * PI;
    assert!(Chart::<SO3>::check_domain(&ExpChart, &(axis() * (tau - 1e-3))).is_ok());
    assert!(Chart::<SO3>::check_domain(&ExpChart, &(axis() * (tau + 1e-3))).is_err());
    let nan = Vector3::new(f64::NAN, 0.0, 0.0);
    assert!(matches!(
        Chart::<SO3>::check_domain(&CayleyChart, &nan),
        Err(LieError::NonFinite { .. })
    ));
    assert!(matches!(
        Chart::<SO3>::left_differential_inverse(&ExpChart, &nan),
        Err(LieError::NonFinite { .. })
    ));
}
