//! The front door for runs ([`IntegratorBuilder`]): checked tolerance runs against the exact
//! motion of the free body (Jacobi elliptic functions, `lgsvi_mechanics::exact`, not the
//! integrator), the policy's choices against the rules the policy states, and every missing
//! or bad input refused with the setting named.

use lgsvi_mechanics::exact::FreeRigidBodyExact;
use lgsvi_mechanics::prelude::*;
use lgsvi_mechanics::settings::DEFAULT_ADAPTIVE_NODES;
use lgsvi_mechanics::tolerance::{first_nodes, step_count, CHECK_ACCEPTS};

mod common;
use common::truth;

/// A checked tolerance run ends within the acceptance (3 · tol) of the exact motion, and its
/// estimate is the companion's measured difference, within a factor 3 of the true error
/// (the companion is ~1000× more accurate at these steps: `tolerance` module docs). The
/// fast spin near the intermediate axis makes the first run miss (its errors grow along
/// the motion): the run is taken again, which the report says.
#[test]
fn a_checked_tolerance_run_ends_within_its_tolerance_of_the_exact_motion() {
    let inertia = Inertia::from_principal_moments([3.3, 2.5, 3.4]).unwrap();
    for (omega, t_end, tol, runs) in [
        (Vector3::new(-2.0, 1.9, -1.0), 100.0, 1e-10, 1),
        (Vector3::new(20.0, 0.1, 0.1), 10.0, 1e-8, 2),
    ] {
        let exact = FreeRigidBodyExact::new(inertia, SO3::identity(), omega).unwrap();
        let mut run = Integrator::builder(RigidBody::new(inertia))
            .start(SO3::identity(), omega)
            .tolerance(tol)
            .horizon(t_end)
            .build_checked()
            .unwrap();
        let trajectory = run.run_until(t_end, 1).unwrap();
        let last = trajectory.states.last().unwrap();
        assert_eq!(last.time, t_end);
        assert_eq!(trajectory.states[0].time, 0.0);
        let error = truth(&exact, last);
        assert!(error <= CHECK_ACCEPTS * tol, "{omega:?}: error {error:e}");
        let estimate = run.estimated_error();
        assert!(
            (error / 3.0..=3.0 * error).contains(&estimate),
            "{omega:?}: estimate {estimate:e}, error {error:e}"
        );
        let report = run.check_report().unwrap();
        assert_eq!(report.attempts, runs, "{omega:?}");
        assert_eq!(report.difference, estimate);
    }
}

/// The builder applies the policy it documents: the step divides the horizon into the
/// fewest steps that turn at most 3 rad at the motion's rate (the spin, plus the heavy
/// top's pendulum frequency `√(m g |ρ| / J_min)`), the first step takes
/// `3 + ⌈−log₁₀(tol)/2⌉` nodes, and each step's share is `tol / T` per unit time.
#[test]
fn the_builder_chooses_the_step_and_nodes_by_the_policy() {
    let inertia = Inertia::from_paper_jd([1.0, 2.8, 2.0]).unwrap();
    let top = HeavyTop::paper(inertia).unwrap();
    let omega = Vector3::new(0.5, -0.5, 0.4);
    let it = Integrator::builder(top)
        .start(SO3::identity(), omega)
        .tolerance(1e-9)
        .horizon(20.0)
        .build()
        .unwrap();
    // J = diag(4.8, 3.0, 3.8), m g |ρ| = 9.81: the pendulum turns at √(9.81/3).
    let rate = omega.norm() + (9.81f64 / 3.0).sqrt();
    let steps = (20.0 * rate / 3.0).ceil();
    assert_eq!(steps, step_count(20.0, rate, std::f64::consts::TAU));
    assert!((it.settings().h() - 20.0 / steps).abs() < 1e-15);
    assert_eq!(it.settings().nodes(), 3 + 5);
    assert_eq!(first_nodes(1e-9), 8);
    let adaptive = it.settings().adaptive().unwrap();
    assert_eq!(adaptive.rate, 1e-9 / 20.0);
    // A step or nodes given override the policy; the nodes stay in the adaptive range.
    let it = Integrator::builder(top)
        .start(SO3::identity(), omega)
        .tolerance(1e-9)
        .horizon(20.0)
        .step(0.25)
        .nodes(12)
        .build()
        .unwrap();
    assert_eq!((it.settings().h(), it.settings().nodes()), (0.25, 12));
    // A fixed run: the step and nodes as given, the chart and matching as asked.
    let it = Integrator::builder(top)
        .start(SO3::identity(), omega)
        .step(0.5)
        .chart(ChartKind::Cayley)
        .matching(Matching::Paper)
        .build()
        .unwrap();
    assert_eq!(it.settings().nodes(), 10);
    assert_eq!(it.settings().chart(), ChartKind::Cayley);
    assert_eq!(it.settings().matching(), Matching::Paper);
    assert!(it.settings().adaptive().is_none());
}

/// A run built by the builder is the run built by hand from the same settings, bit for bit.
#[test]
fn a_built_run_is_the_run_built_by_hand() {
    let body = RigidBody::new(Inertia::from_paper_jd([1.3, 2.1, 1.2]).unwrap());
    let omega = Vector3::new(-2.0, 1.9, -1.0);
    let mut built = Integrator::builder(body)
        .start(SO3::identity(), omega)
        .step(0.5)
        .nodes(8)
        .build()
        .unwrap();
    let settings = StepSettings::new(0.5, 8).unwrap();
    let mut by_hand = Integrator::new(body, settings, SO3::identity(), omega).unwrap();
    assert_eq!(built.run(10, 1).unwrap(), by_hand.run(10, 1).unwrap());
    // A start at another time counts the steps from there.
    let mut later = Integrator::builder(body)
        .start_at(3.0, SO3::identity(), omega)
        .step(0.5)
        .nodes(8)
        .build()
        .unwrap();
    let trajectory = later.run_until(4.0, 1).unwrap();
    assert_eq!(trajectory.states.last().unwrap().time, 4.0);
    assert_eq!(trajectory.states.len(), 3);
}

/// Every missing or bad input is an error naming the setting, never a panic.
#[test]
fn missing_or_bad_inputs_name_the_setting() {
    let body = RigidBody::new(Inertia::from_principal_moments([1.0, 2.0, 2.5]).unwrap());
    let omega = Vector3::new(0.1, 0.2, 0.3);
    let name = |result: Result<Integrator<RigidBody>, MechanicsError>| match result {
        Err(MechanicsError::InvalidSetting { name, .. }) => name,
        Err(other) => panic!("expected an invalid setting, got {other}"),
        Ok(_) => panic!("expected an error"),
    };
    let base = || Integrator::builder(body);
    assert_eq!(name(base().step(0.5).build()), "start");
    assert_eq!(name(base().start(SO3::identity(), omega).build()), "step");
    let start = || base().start(SO3::identity(), omega);
    assert_eq!(name(start().tolerance(1e-8).build()), "horizon");
    for horizon in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(
            name(start().tolerance(1e-8).horizon(horizon).build()),
            "horizon"
        );
    }
    for tol in [0.0, -1e-8, f64::NAN] {
        assert_eq!(
            name(start().tolerance(tol).horizon(10.0).build()),
            "tolerance"
        );
    }
    let (least, most) = DEFAULT_ADAPTIVE_NODES;
    for n in [least - 1, most + 1] {
        assert_eq!(
            name(start().tolerance(1e-8).horizon(10.0).nodes(n).build()),
            "nodes"
        );
    }
    assert_eq!(name(start().step(0.5).nodes(1).build()), "nodes");
    assert_eq!(name(start().step(f64::NAN).build()), "h");
    // Below the rounding of the run's steps (4ε each).
    assert_eq!(name(start().tolerance(1e-17).horizon(10.0).build()), "tol");
    // A start off the group or not finite.
    let bad = Integrator::builder(body)
        .start(SO3::identity(), Vector3::new(f64::NAN, 0.0, 0.0))
        .step(0.5)
        .build();
    assert!(matches!(bad, Err(MechanicsError::NonFinite { .. })));
}

/// A checked tolerance run that cannot meet its tolerance within the runs allowed is an
/// error that says so, with what it reached.
#[test]
fn a_tolerance_no_run_meets_is_refused_with_what_was_reached() {
    let inertia = Inertia::from_principal_moments([3.3, 2.5, 3.4]).unwrap();
    // A fast spin near the intermediate axis amplifies even the rounding of every step
    // past the tolerance (the command line: "differs by 1.6e-8 … at the rounding of every
    // step").
    let mut run = Integrator::builder(RigidBody::new(inertia))
        .start(SO3::identity(), Vector3::new(30.0, 0.1, 0.1))
        .tolerance(1e-12)
        .horizon(10.0)
        .step(0.1)
        .build_checked()
        .unwrap();
    match run.run_until(10.0, 1) {
        Err(MechanicsError::ToleranceNotChecked { .. })
        | Err(MechanicsError::ToleranceNotMet { .. }) => {}
        Err(other) => panic!("expected the tolerance refused, got {other}"),
        Ok(_) => panic!(
            "expected the tolerance refused, got {:e}",
            run.estimated_error()
        ),
    }
}
