//! The tolerance module's measurements against the closed-form free rigid body.

use lgsvi_experiments::tolerance::{calibration, distance, local_errors, Observe};
use lgsvi_mechanics::exact::FreeRigidBodyExact;
use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::{Inertia, Integrator, RigidBody, StepSettings};

#[test]
fn the_true_local_error_is_the_distance_to_the_exact_flow() {
    // Case A (the paper's free body): the "truth" of a step is the same step with 14 more
    // nodes; it must be the distance to the exact flow from the step's start state.
    let a = lgsvi_cases::case("A").unwrap();
    let inertia = Inertia::from_tensor(a.inertia).unwrap();
    let attitude0 = SO3::try_from_matrix(a.attitude0).unwrap();
    let make = |s: StepSettings| Integrator::new(RigidBody::new(inertia), s, attitude0, a.omega0);
    let (h, t_end) = (0.5, 2.0);
    let rows = local_errors(&make, &[h], &[4, 5, 6], t_end, &mut || {}).unwrap();
    assert_eq!(rows.len(), 3 * 4);
    for n in [4, 5, 6] {
        let mut integrator = make(StepSettings::new(h, n).unwrap()).unwrap();
        for row in rows.iter().filter(|r| r.nodes == n) {
            let s = *integrator.state();
            let exact = FreeRigidBodyExact::new(inertia, *s.attitude(), s.velocity)
                .unwrap()
                .state(h)
                .unwrap();
            integrator.step().unwrap();
            let measured = distance(&integrator.state().observe(), &exact.observe());
            // The truth run's own error (n + 14 = 18 to 20 nodes at h = 0.5) is at rounding:
            // a few ulps of the entries (|Ω| ≈ 3), far below these local errors (≥ 1e-11).
            assert!(
                (row.truth - measured).abs() <= 1e-14 + 1e-6 * measured,
                "n = {n}, step {}: truth {} against the exact flow {measured}",
                row.step,
                row.truth
            );
            assert!(row.estimate > 0.0 && row.estimate.is_finite());
        }
    }
    let (_, _, _, _, within, count) = calibration(&rows).unwrap();
    assert_eq!(count, rows.len());
    assert!((0.0..=1.0).contains(&within));
}
