//! Inputs given at each Gauss point of a step (`Integrator::set_input_at_points`): a
//! torque polynomial in time on a spherical body against the closed form, the same input
//! at every point against the constant input, and the per-point input Jacobians against
//! differences of whole steps and against the constant input's.

use lgsvi_mechanics::lie::{LieGroup, SO3};
use lgsvi_mechanics::linearization::Coordinates;
use lgsvi_mechanics::{Inertia, Integrator, MechanicsError, RigidBody, StepSettings};
use nalgebra::{DMatrix, Vector3};

fn integrator(
    moments: [f64; 3],
    h: f64,
    nodes: usize,
    omega: Vector3<f64>,
) -> Integrator<RigidBody> {
    Integrator::new(
        RigidBody::new(Inertia::from_principal_moments(moments).unwrap()),
        StepSettings::new(h, nodes).unwrap(),
        SO3::exp(&Vector3::new(0.2, -0.1, 0.3)),
        omega,
    )
    .unwrap()
}

/// A spherical body `J = jI` from rest under a torque `u(t) = (a + bt + ct²) e` about a fixed
/// axis `e` turns about `e` with `j φ̈ = u`: over `[0, h]`, `φ = (a h²/2 + b h³/6 + c h⁴/12)/j`
/// and `φ̇ = (a h + b h²/2 + c h³/3)/j`. With 8 nodes the step's curve holds the quartic
/// `φ` and its quadrature (exact to degree 2m − 1) the action's terms, so the step is exact
/// to rounding (1e-14 on angles and rates of order 0.1–1).
#[test]
fn a_quadratic_torque_turns_a_spherical_body_exactly() {
    let (j, h) = (2.0, 0.8);
    let (a, b, c) = (0.3, -0.5, 0.7);
    let e = Vector3::new(1.0, 2.0, 2.0) / 3.0;
    let mut it = Integrator::new(
        RigidBody::new(Inertia::from_principal_moments([j; 3]).unwrap()),
        StepSettings::new(h, 8).unwrap(),
        SO3::identity(),
        Vector3::zeros(),
    )
    .unwrap();
    let inputs: Vec<Vector3<f64>> = it
        .quadrature_nodes()
        .iter()
        .map(|s| {
            let t = s * h;
            e * (a + b * t + c * t * t)
        })
        .collect();
    it.set_input_at_points(&inputs).unwrap();
    it.step().unwrap();
    let phi = (a * h * h / 2.0 + b * h.powi(3) / 6.0 + c * h.powi(4) / 12.0) / j;
    let rate = (a * h + b * h * h / 2.0 + c * h.powi(3) / 3.0) / j;
    let state = it.state();
    let turn = state.configuration.log();
    assert!(
        (turn - e * phi).amax() < 1e-14,
        "{turn} against {}",
        e * phi
    );
    assert!((state.velocity - e * rate).amax() < 1e-14);
    // The weighted mean is the constant input of the same impulse: ∫u dt / h.
    let mean = e * (a + b * h / 2.0 + c * h * h / 3.0);
    assert!((it.input() - mean).amax() < 1e-15);
}

/// The same input at every point is the constant input: the two steps agree to the Newton
/// solves' rounding (their predictors start from inputs that differ in the last bits), and
/// the per-point input Jacobians sum to the constant input's.
#[test]
fn equal_inputs_at_the_points_are_the_constant_input() {
    let u = Vector3::new(0.4, -0.2, 0.1);
    let omega = Vector3::new(0.5, -0.3, 0.8);
    let mut constant = integrator([3.0, 4.0, 5.5], 0.4, 9, omega);
    let mut points = integrator([3.0, 4.0, 5.5], 0.4, 9, omega);
    constant.set_input(u).unwrap();
    let m = points.quadrature_nodes().len();
    points.set_input_at_points(&vec![u; m]).unwrap();
    let (a, b) = (
        constant.step_linearized().unwrap(),
        points.step_linearized().unwrap(),
    );
    assert!(a.b_points(Coordinates::Velocity).is_none());
    let per_point = b.b_points(Coordinates::Velocity).unwrap();
    assert_eq!(per_point.len(), m);
    let sum = per_point.iter().fold(DMatrix::zeros(6, 3), |s, bj| s + bj);
    let scale = a.b(Coordinates::Velocity).amax();
    assert!((sum - a.b(Coordinates::Velocity)).amax() < 1e-13 * scale);
    assert!((a.a(Coordinates::Velocity) - b.a(Coordinates::Velocity)).amax() < 1e-13);
    let (x, y) = (constant.state(), points.state());
    assert!(
        x.configuration
            .inverse()
            .compose(&y.configuration)
            .log()
            .amax()
            < 1e-14
    );
    assert!((x.velocity - y.velocity).amax() < 1e-14);
}

/// Each `B_j` against central differences of whole steps in the input at point `j`: with
/// `δ = 1e-5` the truncation error is `~δ²` (the step is smooth in the inputs) and the
/// rounding `~1e-16/δ`, so they agree to about 1e-9 absolute on entries of order 0.1.
#[test]
fn the_input_jacobians_at_the_points_match_differences() {
    let omega = Vector3::new(0.5, -0.3, 0.8);
    let base = integrator([3.0, 4.0, 5.5], 0.5, 7, omega);
    let nodes = base.quadrature_nodes();
    let inputs: Vec<Vector3<f64>> = nodes
        .iter()
        .map(|s| Vector3::new(0.3 * s, -0.2 + s * s, 0.1 * (3.0 * s).sin()))
        .collect();
    let step = |inputs: &[Vector3<f64>]| {
        let mut it = integrator([3.0, 4.0, 5.5], 0.5, 7, omega);
        it.set_input_at_points(inputs).unwrap();
        it.step().unwrap();
        *it.state()
    };
    let mut it = integrator([3.0, 4.0, 5.5], 0.5, 7, omega);
    it.set_input_at_points(&inputs).unwrap();
    let linear = it.step_linearized().unwrap();
    let b = linear.b_points(Coordinates::Velocity).unwrap();
    let delta = 1e-5;
    for j in [0, nodes.len() / 2, nodes.len() - 1] {
        for c in 0..3 {
            let (mut plus, mut minus) = (inputs.clone(), inputs.clone());
            plus[j][c] += delta;
            minus[j][c] -= delta;
            let (p, q) = (step(&plus), step(&minus));
            let theta = q.configuration.inverse().compose(&p.configuration).log() / (2.0 * delta);
            let rates = (p.velocity - q.velocity) / (2.0 * delta);
            for r in 0..3 {
                assert!(
                    (b[j][(r, c)] - theta[r]).abs() < 1e-9,
                    "θ row {r}, point {j}, input {c}"
                );
                assert!(
                    (b[j][(3 + r, c)] - rates[r]).abs() < 1e-9,
                    "ω row {r}, point {j}, input {c}"
                );
            }
        }
    }
}

#[test]
fn inputs_at_the_points_are_checked() {
    let mut it = integrator([3.0, 4.0, 5.5], 0.5, 7, Vector3::zeros());
    let error = it.set_input_at_points(&[Vector3::zeros(); 2]).unwrap_err();
    assert!(matches!(
        error,
        MechanicsError::InvalidSetting {
            name: "input_at_points",
            ..
        }
    ));
    let m = it.quadrature_nodes().len();
    let mut bad = vec![Vector3::zeros(); m];
    bad[1].x = f64::NAN;
    assert!(matches!(
        it.set_input_at_points(&bad).unwrap_err(),
        MechanicsError::NonFinite { .. }
    ));
    assert!(it.inputs_at_points().is_none());
    // A constant input replaces the inputs at the points.
    it.set_input_at_points(&vec![Vector3::x(); m]).unwrap();
    assert!(it.inputs_at_points().is_some());
    it.set_input(Vector3::zeros()).unwrap();
    assert!(it.inputs_at_points().is_none());
    let weights: f64 = it.quadrature_weights().iter().sum();
    assert!((weights - 1.0).abs() < 1e-15);
}
