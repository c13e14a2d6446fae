//! Minimum-time slews: the time scaling the step-length derivative rests on, and Betts's
//! minimum-time reorientation against its published optimum.

use lgsvi_mechanics::lie::{LieGroup, SO3};
use lgsvi_mechanics::{Inertia, Integrator, RigidBody, StepSettings};
use lgsvi_optimal::{Cost, OptimalError, Slew};
use nalgebra::Vector3;

/// The Euler equations are invariant under `t ↦ ct`, `Ω ↦ Ω/c`, `u ↦ u/c²`, and so is
/// lgsvi's discrete action term by term (the kinetic term scales as `1/h`, the forcing as
/// `h u`): a step of length `ch` from `(R, Ω)` under `u` equals the step of length `h` from
/// `(R, cΩ)` under `c²u`, its end rates divided by `c`. The two runs solve different
/// Newton systems, so they agree to the solves' rounding (1e-13 on rates of order 1 over
/// five steps), not bit for bit.
#[test]
fn the_step_is_invariant_under_time_scaling() {
    let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap();
    let attitude = SO3::exp(&Vector3::new(0.3, -0.1, 0.7));
    let omega = Vector3::new(0.4, -0.9, 0.6);
    let u = Vector3::new(0.2, 0.5, -0.3);
    let (h, c) = (0.3, 1.7);
    let run = |h: f64, omega: Vector3<f64>, u: Vector3<f64>| {
        let mut it = Integrator::new(
            RigidBody::new(inertia),
            StepSettings::new(h, 9).unwrap(),
            attitude,
            omega,
        )
        .unwrap();
        it.set_input(u).unwrap();
        for _ in 0..5 {
            it.step().unwrap();
        }
        *it.state()
    };
    let long = run(c * h, omega, u);
    let scaled = run(h, c * omega, c * c * u);
    let rotation = long
        .configuration
        .inverse()
        .compose(&scaled.configuration)
        .log();
    assert!(rotation.amax() < 1e-13, "{rotation}");
    assert!((long.velocity - scaled.velocity / c).amax() < 1e-13);
}

/// Betts's test problem as solved by Fleming, Sekhavat & Ross (2008): the asymmetric body
/// `J = diag(5621, 4547, 2364)` kg·m², `|u_i| ≤ 50` N·m, rest to rest, 150° about the body
/// x axis, `t_f* = 28.6304077` s. The torques are constant over each step, so a switch of
/// the bang-bang optimum falls inside a step whose torque takes an intermediate value:
/// the discrete optimum's final time lies above the continuous one by `O(h²)` (measured
/// in `docs/guide/optimal.md`: 7.5e-5 relative at K = 100, 2.0e-5 at K = 200).
#[test]
fn betts_reorientation_meets_its_published_minimum_time() {
    let reference = 28.6304077;
    let inertia = Inertia::from_principal_moments([5621.0, 4547.0, 2364.0]).unwrap();
    let target = SO3::exp(&(Vector3::x() * 150f64.to_radians()));
    let solution = Slew::new(inertia, 34.0)
        .to(target, Vector3::zeros())
        .steps(100)
        .nodes(8)
        .torque_max([50.0; 3])
        .cost(Cost::Time)
        .solve()
        .unwrap();
    assert!(solution.converged);
    assert!(*solution.statistics.kkt_residuals.last().unwrap() <= 1e-10);
    let error = (solution.t_end - reference) / reference;
    assert!(
        error > 0.0 && error < 1e-4,
        "t_f = {}: {error:e}",
        solution.t_end
    );
    assert_eq!(solution.cost, solution.t_end);
    // Bang-bang: every torque within its bound, and all but the switching steps' on it
    // (six free values meet the six terminal conditions with the step length).
    let flat: Vec<f64> = solution
        .inputs
        .iter()
        .flat_map(|u| [u.x, u.y, u.z])
        .collect();
    assert!(flat.iter().all(|u| u.abs() <= 50.0));
    let interior = flat.iter().filter(|u| u.abs() < 50.0).count();
    assert!(interior <= 6, "{interior} torques inside their bounds");
    // Replayed by a fresh integrator at the solution's step, the torques land on the
    // target.
    let mut it = Integrator::new(
        RigidBody::new(inertia),
        StepSettings::new(solution.h, 8).unwrap(),
        SO3::identity(),
        Vector3::zeros(),
    )
    .unwrap();
    for u in &solution.inputs {
        it.set_input(*u).unwrap();
        it.step().unwrap();
    }
    let end = it.state();
    assert!(end.configuration.inverse().compose(&target).log().amax() <= 1e-10);
    assert!(end.velocity.amax() <= 1e-10);
}

/// A first guess too short for the bounds is lengthened until a motion exists; a guess
/// too long is shortened. Both find the same minimum, rest to rest and between moving
/// states. The iterations end at a scaled KKT residual of 1e-10, and the minimum is
/// isolated (its active set is a vertex), so the final times agree to about that.
#[test]
fn the_first_guess_of_the_time_does_not_matter() {
    let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap();
    let target = SO3::exp(&Vector3::new(1.5, 0.4, -0.9));
    for rates in [Vector3::zeros(), Vector3::new(0.05, 0.0, -0.02)] {
        let solve = |guess: f64| {
            Slew::new(inertia, guess)
                .from(SO3::identity(), rates)
                .to(target, 0.3 * rates)
                .steps(40)
                .torque_max([0.06; 3])
                .cost(Cost::Time)
                .solve()
                .unwrap()
                .t_end
        };
        let (short, long) = (solve(5.0), solve(80.0));
        assert!(
            (short - long).abs() <= 1e-9 * short,
            "{short} against {long}"
        );
    }
}

#[test]
fn a_minimum_time_slew_needs_a_torque_bound() {
    let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap();
    let error = Slew::new(inertia, 10.0)
        .to(SO3::exp(&Vector3::new(0.0, 0.0, 1.0)), Vector3::zeros())
        .cost(Cost::Time)
        .solve()
        .unwrap_err();
    assert!(
        matches!(
            error,
            OptimalError::InvalidSetting {
                name: "torque_max",
                ..
            }
        ),
        "{error}"
    );
}
