//! The paper's measurements on the paper's free body (case A of `lgsvi-cases`).

use lgsvi_experiments::paper::{self, long_run, max, settings, LONG_CONFIGS};
use lgsvi_experiments::Body;
use lgsvi_mechanics::lie::{ChartKind, SO3};
use lgsvi_mechanics::{Inertia, Matching, RigidBody, StepSettings};
use nalgebra::Vector3;

fn case_a(omega0: Vector3<f64>) -> Body<RigidBody> {
    let a = lgsvi_cases::case("A").unwrap();
    let inertia = Inertia::from_tensor(a.inertia).unwrap();
    Body::new(
        RigidBody::new(inertia),
        SO3::try_from_matrix(a.attitude0).unwrap(),
        omega0,
        StepSettings::new(0.5, 10).unwrap(),
    )
    .with_exact_solution(inertia)
}

/// A long run records every step: the exact matching conserves the free body's invariants
/// to rounding, and the step angles are the body's turn per step.
#[test]
fn a_long_run_records_invariants_and_step_angles() {
    let a = lgsvi_cases::case("A").unwrap();
    let run = long_run(
        &case_a(a.omega0),
        settings(ChartKind::Exp, Matching::Exact, 0.5, 10).unwrap(),
        200,
        4,
        |_| {},
    )
    .unwrap();
    assert!(run.failure.is_none());
    assert_eq!(run.times.len(), 201);
    assert_eq!(run.step_angle.len(), 200);
    assert_eq!(run.curve_axis.len(), 4 * 200);
    // Discrete Noether at rounding: ~100 ulps of drift over 200 steps at most.
    assert!(max(&run.momentum_drift) < 1e-13 && max(&run.casimir_drift) < 1e-13);
    assert!(max(&run.energy_error) < 1e-12);
    // Case A: |Ω| ranges over about [2.6, 3.1] rad/s, so a step of 0.5 s turns the body by
    // 1.3 to 1.6 rad.
    assert!(
        run.step_angle.iter().all(|a| (1.2..1.7).contains(a)),
        "{:?}",
        &run.step_angle[..3]
    );
}

/// Figure 4's runs: the exact matching keeps every body momentum on its sphere |μ| = 1 to
/// rounding (the Casimir), the paper's matching only to the method's error (n = 8,
/// h = 0.5: about 1e-13).
#[test]
fn momenta_stay_on_the_sphere_with_the_exact_matching() {
    let j = lgsvi_cases::case("A").unwrap().principal_moments().unwrap();
    let data = paper::sphere_runs(
        |mu| case_a(Vector3::new(mu.x / j[0], mu.y / j[1], mu.z / j[2])),
        &mut (),
    )
    .unwrap();
    assert_eq!(data.runs.len(), 2);
    let summary = data.summary();
    let (exact, paper) = (&summary[0], &summary[1]);
    assert_eq!((exact.0, paper.0), (Matching::Exact, Matching::Paper));
    // 200 steps, |μ|² = 1: rounding accumulates to a few tens of ulps (measured 3e-15).
    assert!(exact.1 < 2e-14, "{exact:?}");
    // Measured 1.3e-13: the paper's matching is exact only to the discretisation's error.
    assert!(paper.1 > 10.0 * exact.1, "{paper:?} against {exact:?}");
    assert_eq!(LONG_CONFIGS.len(), 3);
}
