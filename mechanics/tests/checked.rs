//! A checked run ([`Checked`]) measures its own error: the difference from a companion
//! taking the same steps with more nodes, against the exact motion of the free body (Jacobi
//! elliptic functions: `lgsvi_mechanics::exact`, not the integrator).

use lgsvi_mechanics::exact::FreeRigidBodyExact;
use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::settings::MAX_NODES;
use lgsvi_mechanics::tolerance::CheckedIntegrator;
use lgsvi_mechanics::Stepper;
use lgsvi_mechanics::{Inertia, Integrator, MechanicsError, RigidBody, StepSettings};
use nalgebra::Vector3;

mod common;
use common::truth;

/// On every step of runs where the errors of each step grow along the motion (a fast spin
/// near the intermediate axis, a slow one near the separatrix) and of the paper's body,
/// at fixed and adaptive nodes, the difference is the error within a factor 2 wherever
/// the error is above the rounding of the run (1e-13): the companion's 2 more nodes make
/// it about 1000× more accurate at these steps (30× per node), so the difference and the
/// error agree to much better than 2 — the factor leaves room for where the convergence
/// per node is slower.
#[test]
fn the_difference_is_the_error_along_the_run() {
    let inertia = Inertia::from_principal_moments([3.3, 2.5, 3.4]).unwrap();
    let cases = [
        (Vector3::new(20.0, 0.1, 0.1), 0.15, 9, None),
        (Vector3::new(20.0, 0.1, 0.1), 0.15, 8, Some(1e-9)),
        (Vector3::new(2.0, 0.01, 0.01), 1.0, 7, None),
        (Vector3::new(-2.0, 1.9, -1.0), 1.0, 7, Some(1e-8)),
    ];
    for (omega, h, n, rate) in cases {
        let mut settings = StepSettings::new(h, n).unwrap();
        if let Some(rate) = rate {
            settings = settings.with_tolerance(rate).unwrap();
        }
        let exact = FreeRigidBodyExact::new(inertia, SO3::identity(), omega).unwrap();
        let primary =
            Integrator::new(RigidBody::new(inertia), settings, SO3::identity(), omega).unwrap();
        let mut run = CheckedIntegrator::new(primary).unwrap();
        let mut compared = 0;
        for _ in 0..(10.0 / h) as usize {
            run.step().unwrap();
            let error = truth(&exact, run.integrator().state());
            if error > 1e-13 {
                let d = run.difference();
                assert!(
                    (error / 2.0..=2.0 * error).contains(&d),
                    "Ω₀ {omega:?}, h {h}, n {n}, t {}: difference {d:e}, error {error:e}",
                    run.integrator().state().time
                );
                compared += 1;
            }
        }
        assert!(compared > 5, "{compared} steps above rounding");
        assert!(run.largest_difference().value >= run.difference());
        // The companion stands at the primary's time.
        assert_eq!(run.companion_state().time, run.integrator().state().time);
    }
}

/// What a checked run refuses: no extra nodes, a step that may change, no room for the
/// companion's nodes.
#[test]
fn a_checked_run_refuses_what_it_cannot_check() {
    let body = RigidBody::new(Inertia::from_principal_moments([1.0, 2.0, 3.0]).unwrap());
    let make = |settings| {
        Integrator::new(body, settings, SO3::identity(), Vector3::new(0.1, 0.2, 0.3)).unwrap()
    };
    let fixed = StepSettings::new(0.5, 8).unwrap();
    for extra in [0, 9] {
        assert!(matches!(
            CheckedIntegrator::with_extra_nodes(make(fixed), extra),
            Err(MechanicsError::InvalidSetting {
                name: "extra nodes",
                ..
            })
        ));
    }
    let changing = fixed.with_tolerance(1e-8).unwrap().with_step_changes(true);
    assert!(matches!(
        CheckedIntegrator::new(make(changing)),
        Err(MechanicsError::InvalidSetting {
            name: "step changes",
            ..
        })
    ));
    let most = StepSettings::new(0.5, MAX_NODES - 1).unwrap();
    assert!(matches!(
        CheckedIntegrator::new(make(most)),
        Err(MechanicsError::InvalidSetting { name: "nodes", .. })
    ));
    // The input reaches both runs: a torque held over the steps moves the two alike.
    let mut run = CheckedIntegrator::new(make(fixed)).unwrap();
    run.set_input(Vector3::new(0.3, 0.0, -0.2)).unwrap();
    for _ in 0..10 {
        run.step().unwrap();
    }
    assert!(
        run.largest_difference().value < 1e-9,
        "{:?}",
        run.largest_difference()
    );
    assert_eq!(run.integrator().input(), &Vector3::new(0.3, 0.0, -0.2));
}

/// The tolerance policy: accepts at most 3·tol, tightens by at least 10× (by
/// `tol / (10 · difference)` where that is more), stops after three runs, and at the
/// rounding of a step says so with the closest run's difference.
#[test]
fn the_tolerance_policy_accepts_tightens_and_refuses() {
    use lgsvi_mechanics::settings::ROUNDING_FLOOR;
    use lgsvi_mechanics::stepper::Difference;
    use lgsvi_mechanics::tolerance::ToleranceCheck;
    let at = |value| Difference {
        value,
        step: 3,
        time: 1.5,
    };
    let fixed = StepSettings::new(0.5, 8).unwrap();
    assert!(ToleranceCheck::new(fixed, 1e-8).is_err());
    let settings = fixed.with_tolerance(1e-9).unwrap();
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(ToleranceCheck::new(settings, bad).is_err());
    }
    let mut policy = ToleranceCheck::new(settings, 1e-8).unwrap();
    assert!(policy.judge(at(3e-8)).unwrap());
    assert_eq!(policy.attempt(), 1);
    // 1e-6 against 1e-8: the share falls by 1e-8 / (10 · 1e-6) = 1e-3.
    // (At least tenfold: `tightened_rate` never takes less than a tenth.)
    assert_eq!(
        lgsvi_mechanics::tolerance::tightened_rate(1.0, 1e-9, 1e-8),
        0.1
    );
    assert!(!policy.judge(at(1e-6)).unwrap());
    assert_eq!(policy.attempt(), 2);
    assert!((policy.tightened() / 1e3 - 1.0).abs() < 1e-12);
    // Barely above: 1e-8 / (10 · 3.1e-8), more than tenfold.
    assert!(!policy.judge(at(3.1e-8)).unwrap());
    assert!((policy.tightened() / 3.1e4 - 1.0).abs() < 1e-12);
    match policy.judge(at(5e-8)) {
        Err(MechanicsError::ToleranceNotChecked {
            attempts: 3,
            at_floor: false,
            best,
            ..
        }) => {
            assert_eq!(best, 3e-8) // the least of every run judged
        }
        other => panic!("{other:?}"),
    }
    // A share that reaches the rounding of a step: refused there, with the best run.
    let tight = fixed.with_tolerance(2.0 * ROUNDING_FLOOR / 0.5).unwrap();
    let mut policy = ToleranceCheck::new(tight, 1e-14).unwrap();
    assert!(!policy.judge(at(1e-12)).unwrap());
    match policy.judge(at(2e-12)) {
        Err(error @ MechanicsError::ToleranceNotChecked { at_floor: true, .. }) => {
            assert!(error.to_string().contains("about 1.0e-12"), "{error}")
        }
        other => panic!("{other:?}"),
    }
}
