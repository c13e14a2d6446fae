//! Steps a chart cannot follow. A Cayley chart covers each rotation once (angles below a
//! half turn), so a step whose motion turns the body further has no faithful
//! representation; Newton used to converge anyway, to an aliased root that conserves
//! energy and momenta to rounding while the attitude is wrong by O(1). The integrator now
//! checks each step against the system's own flow (and, where that cannot be integrated,
//! against the present angular speed) and refuses such steps with a typed error.

use lgsvi_lie::{ChartKind, SO3};
use lgsvi_mechanics::Stepper;
use lgsvi_mechanics::{Inertia, Integrator, MechanicsError, RigidBody, StepSettings};
use nalgebra::Vector3;

/// The paper's rigid body (case A): |Ω(0)| = 2.93 rad/s.
fn case_a(h: f64, n: usize, chart: ChartKind, omega: Vector3<f64>) -> Integrator<RigidBody> {
    let body = RigidBody::new(Inertia::from_principal_moments([3.3, 2.5, 3.4]).unwrap());
    let settings = StepSettings::new(h, n).unwrap().with_chart(chart);
    Integrator::new(body, settings, SO3::identity(), omega).unwrap()
}

fn omega_a() -> Vector3<f64> {
    Vector3::new(-2.0, 1.9, -1.0)
}

#[test]
fn a_step_turning_past_the_cayley_half_turn_is_refused() {
    // h = 5: the flow turns the body by ~14.6 rad; it reaches π about 1.07 s into the step.
    let mut it = case_a(5.0, 8, ChartKind::Cayley, omega_a());
    match it.step() {
        Err(MechanicsError::StepTooLong {
            step: 0,
            rotation,
            limit,
            suggested,
            ..
        }) => {
            assert!(rotation >= std::f64::consts::PI && limit == std::f64::consts::PI);
            // |Ω| varies little along case A's motion: π/|Ω| ≈ 1.07 s.
            assert!((0.9..1.2).contains(&suggested), "{suggested}");
        }
        other => panic!("expected StepTooLong, got {other:?}"),
    }
    // The state is untouched: the caller can change h and go on.
    assert_eq!(it.state().time, 0.0);
}

#[test]
fn a_step_too_fast_for_the_flow_is_refused_by_its_speed() {
    // 1000 rad/s about x for h = 0.5: 500 rad per step, more substeps than the flow
    // predictor takes; the Cayley step used to return R = I for ever.
    let mut it = case_a(0.5, 10, ChartKind::Cayley, Vector3::new(1e3, 0.0, 0.0));
    assert!(matches!(
        it.step(),
        Err(MechanicsError::StepTooLong { step: 0, rotation, .. }) if rotation == 500.0
    ));
    // The exp chart refuses it too (its reach is 2π).
    let mut it = case_a(0.5, 10, ChartKind::Exp, Vector3::new(1e3, 0.0, 0.0));
    assert!(it.step().is_err());
}

#[test]
fn an_aliased_root_is_detected_against_the_flow() {
    // h = 1 turns case A by ~2.9 rad, inside the Cayley chart's reach, but with 4 nodes
    // Newton converges to a root 1.7 rad away from the motion (measured against the exact
    // solution: the run used to end 1.3 rad off at T = 10 without a word).
    let mut it = case_a(1.0, 4, ChartKind::Cayley, omega_a());
    match it.step() {
        Err(
            error @ MechanicsError::AliasedRoot {
                step: 0, distance, ..
            },
        ) => {
            assert!(distance > 1.0, "{distance}");
            // The message names the step, the chart and the remedies (h, another chart).
            let text = error.to_string();
            assert!(
                text.contains("step 0")
                    && text.contains("aliased root of the cayley chart")
                    && text.contains("take a smaller step h"),
                "{text}"
            );
        }
        other => panic!("expected AliasedRoot, got {other:?}"),
    }
    // The same step in the exp chart is the motion's continuation.
    let mut it = case_a(1.0, 4, ChartKind::Exp, omega_a());
    it.run(10, 1).unwrap();
    // Steps well inside the chart pass the check: the paper's setting.
    let mut it = case_a(0.5, 8, ChartKind::CayleyUnscaled, omega_a());
    it.run(40, 1).unwrap();
}
