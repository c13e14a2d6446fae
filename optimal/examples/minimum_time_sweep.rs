//! The minimum-time solver over a sweep of problems, as a regression record of its
//! robustness: 84 slews (three bodies, seven turns, 10 to 80 steps of 8 nodes, rest to
//! rest) and six manoeuvres in space (bodies from spherical to asymmetric, 1 to 10 kg,
//! turns and moves of both sizes, `|τ_i| ≤ 0.1` N·m and `|f_i| ≤ 0.2` N, 20 steps). Prints a
//! line per problem (final time, SQP iterations, solve time) and the totals; asserts that
//! every problem converges and that each manoeuvre's wrenches, replayed by the integrator,
//! land on the target (pose and velocity to 1e-8) within the bounds.
//!
//! `cargo run --release -p lgsvi-optimal --example minimum_time_sweep` (about 30 s).

use lgsvi_mechanics::lie::{LieGroup, SE3, SO3};
use lgsvi_mechanics::{FreeBody, Inertia, Integrator, StepSettings};
use lgsvi_optimal::{eigen_axis_time, Cost, Manoeuvre, Slew};
use nalgebra::{Vector3, Vector6};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let bodies = [
        ([3.3, 2.5, 3.4], 1.0),
        ([3.0, 4.0, 5.0], 0.05),
        ([3.0, 4.0, 5.5], 0.06),
    ];
    let turns = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.5, 0.2],
        [1.5, 0.4, -0.9],
        [0.5, 0.3, 1.0],
        [3.0, 0.0, 0.0],
    ];
    let (mut iterations, clock) = (0, Instant::now());
    for (moments, bound) in bodies {
        let inertia = Inertia::from_principal_moments(moments)?;
        for turn in turns {
            let target = SO3::exp(&Vector3::from(turn));
            let guess = eigen_axis_time(&inertia, &target, [bound; 3]).expect("a turn");
            for steps in [10, 20, 40, 80] {
                let solution = Slew::new(inertia, guess)
                    .to(target, Vector3::zeros())
                    .torque_max([bound; 3])
                    .steps(steps)
                    .nodes(8)
                    .cost(Cost::Time)
                    .solve()?;
                iterations += solution.statistics.iterations;
                println!(
                    "slew J = {moments:?}, |u| ≤ {bound}, turn {turn:?}, K = {steps}: \
                     T = {:.10} s, {} iterations",
                    solution.t_end, solution.statistics.iterations
                );
            }
        }
    }
    println!(
        "slews: 84 of 84 converged, {iterations} iterations, {:.1} s",
        clock.elapsed().as_secs_f64()
    );

    let manoeuvres = [
        ([3.0, 4.0, 5.5], 10.0, [1.5, 0.4, -0.9], [2.0, 1.0, 0.0]),
        ([3.0, 4.0, 5.5], 1.0, [1.5, 0.4, -0.9], [2.0, 1.0, 0.0]),
        ([3.0, 4.0, 5.5], 10.0, [0.3, -0.2, 0.1], [2.0, 1.0, 0.0]),
        ([5.0, 2.0, 3.0], 4.0, [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
        (
            [1.0, 1.5, 2.0],
            10.0,
            [0.0, 0.0, std::f64::consts::FRAC_PI_2],
            [2.0, 0.0, 0.0],
        ),
        ([2.0, 2.0, 2.0], 5.0, [0.4, 0.8, 0.8], [0.6, -0.3, 0.2]),
    ];
    let (torque, force, nodes) = (0.1, 0.2, 8);
    let (mut iterations, clock) = (0, Instant::now());
    for (moments, mass, turn, position) in manoeuvres {
        let body = FreeBody::new(Inertia::from_principal_moments(moments)?, mass)?;
        let target = SE3::new(SO3::exp(&Vector3::from(turn)), Vector3::from(position));
        let solution = Manoeuvre::new(body, 20.0)
            .to(target, Vector6::zeros())
            .torque_max([torque; 3])
            .force_max([force; 3])
            .steps(20)
            .nodes(nodes)
            .cost(Cost::Time)
            .solve()?;
        iterations += solution.statistics.iterations;
        // Replayed: the wrenches within their bounds land on the target.
        let settings = StepSettings::new(solution.h, nodes)?;
        let mut it = Integrator::new(body, settings, SE3::identity(), Vector6::zeros())?;
        for u in &solution.inputs {
            let within = (0..6).all(|i| u[i].abs() <= if i < 3 { torque } else { force });
            assert!(within, "a wrench beyond its bounds: {u:?}");
            it.set_input(*u)?;
            it.step()?;
        }
        let miss = it
            .state()
            .configuration
            .inverse()
            .compose(&target)
            .log()
            .amax()
            .max(it.state().velocity.amax());
        assert!(miss < 1e-8, "the replay misses the target by {miss:e}");
        println!(
            "manoeuvre J = {moments:?}, m = {mass}, turn {turn:?}, move {position:?}: \
             T = {:.10} s, {} iterations, {:.2} s, replay within {miss:.1e}",
            solution.t_end, solution.statistics.iterations, solution.statistics.time_s
        );
    }
    println!(
        "manoeuvres: 6 of 6 converged, {iterations} iterations, {:.1} s",
        clock.elapsed().as_secs_f64()
    );
    Ok(())
}
