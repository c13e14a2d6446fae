//! The parallel ensemble gives each member exactly what a sequential run gives, keeps the
//! input order, and reports a failing member without stopping the others.

use lgsvi_mechanics::ensemble::{run_ensemble, InitialCondition};
use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::Stepper;
use lgsvi_mechanics::{HeavyTop, Inertia, Integrator, StepSettings};
use nalgebra::Vector3;

fn top() -> HeavyTop {
    HeavyTop::paper(Inertia::from_paper_jd([1.0, 2.8, 2.0]).unwrap()).unwrap()
}

fn initial() -> Vec<InitialCondition> {
    (0..12)
        .map(|k| InitialCondition {
            configuration: SO3::exp(&Vector3::new(0.1 * k as f64, -0.05 * k as f64, 0.2)),
            velocity: Vector3::new(0.5, -0.3 + 0.1 * k as f64, 0.4),
        })
        .collect()
}

#[test]
fn members_match_sequential_runs_bit_for_bit_on_any_number_of_threads() {
    let settings = StepSettings::new(0.5, 8).unwrap();
    let initial = initial();
    let run_on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run_ensemble(&top(), &settings, &initial, 15))
    };
    let (one, two) = (run_on(1), run_on(2));
    for (k, start) in initial.iter().enumerate() {
        let mut sequential =
            Integrator::new(top(), settings, start.configuration, start.velocity).unwrap();
        sequential.run(15, 15).unwrap();
        for parallel in [&one[k], &two[k]] {
            let member = parallel.as_ref().unwrap();
            // Same arithmetic in the same order: equality, not a tolerance.
            assert_eq!(member.state, *sequential.state(), "member {k}");
            assert_eq!(member.statistics, *sequential.statistics(), "member {k}");
        }
    }
}

#[test]
fn a_failing_member_is_reported_in_its_place() {
    let settings = StepSettings::new(0.5, 8).unwrap();
    let mut initial = initial();
    // 40 rad/s over h = 0.5 is 20 rad per step: beyond the exp chart (|ξ| < 2π).
    initial[3].velocity = Vector3::new(40.0, 0.0, 0.0);
    initial[7].velocity = Vector3::new(f64::NAN, 0.0, 0.0);
    let results = run_ensemble(&top(), &settings, &initial, 5);
    for (k, result) in results.iter().enumerate() {
        match k {
            3 | 7 => assert!(result.is_err(), "member {k} should fail"),
            _ => assert!(result.is_ok(), "member {k}: {result:?}"),
        }
    }
    let message = results[7].as_ref().unwrap_err().to_string();
    assert!(message.contains("initial angular velocity"), "{message}");
}

#[test]
fn bodies_in_space_run_as_an_ensemble_too() {
    // The ensemble is generic over the group: orbiting bodies on SE(3), each member as its
    // own sequential run gives it, bit for bit.
    use lgsvi_mechanics::lie::SE3;
    use lgsvi_mechanics::OrbitingBody;
    use nalgebra::SVector;
    let body = OrbitingBody::new(
        Inertia::from_principal_moments([0.3, 0.2, 0.4]).unwrap(),
        1.0,
        1.0,
    )
    .unwrap();
    let settings = StepSettings::new(1.0, 8).unwrap();
    let initial: Vec<InitialCondition<SE3, 6>> = (0..4)
        .map(|k| InitialCondition {
            configuration: SE3::new(
                SO3::identity(),
                Vector3::new(3.0 + 0.1 * k as f64, 0.0, 0.0),
            ),
            velocity: SVector::<f64, 6>::new(0.2, -0.3, 0.5, 0.0, 0.55, 0.05),
        })
        .collect();
    let results = run_ensemble(&body, &settings, &initial, 10);
    for (k, start) in initial.iter().enumerate() {
        let mut sequential =
            Integrator::new(body, settings, start.configuration, start.velocity).unwrap();
        sequential.run(10, 10).unwrap();
        assert_eq!(
            results[k].as_ref().unwrap().state,
            *sequential.state(),
            "member {k}"
        );
    }
}
