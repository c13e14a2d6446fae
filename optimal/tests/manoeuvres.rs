//! Manoeuvres of a body in space (SE(3)) at the least input energy, against closed forms,
//! the independent Pontryagin solution of the attitude slew, and laws.
//!
//! The free body's minimum-energy problem splits exactly: the world-frame force
//! `F = R f` moves the centre of mass by `m ẍ = F` whatever the body does, and costs
//! `|F|² = |f|²`, so the least `∫|f|² dt` moving it by `d` rest to rest is the single-axis
//! cubic `12 m² |d|²/T³` (`F` linear in time), independently of the attitude's slew, whose
//! least `∫|τ|² dt` is the rigid body's. In the step's rotation–translation chart the
//! split holds for the discrete problem too when the wrench is given at the Gauss points
//! (each point's world force `R(t_j) f_j` is then free), so polynomial inputs meet the sum
//! of the two optima.

use lgsvi_mechanics::lie::{LieGroup, SE3, SO3};
use lgsvi_mechanics::{FreeBody, Inertia, Integrator, OrbitingBody, StepSettings, Stepper};
use lgsvi_optimal::{Inputs, Manoeuvre, ManoeuvreSolution, OptimalError};
use nalgebra::{Vector3, Vector6};

/// `12 (j²θ² + m²|d|²)/T³`: a spherical body's turn by `θ` and its move by `d`, rest to
/// rest in `T` (the two single-axis cubics).
fn split_optimum(j: f64, theta: f64, m: f64, d: f64, t_end: f64) -> f64 {
    12.0 * (j * j * theta * theta + m * m * d * d) / t_end.powi(3)
}

/// The pose and velocity an integrator reaches from `start` under the solution's
/// wrenches (held, or at the Gauss points), at the solution's `h`.
fn replay<S>(body: S, nodes: usize, solution: &ManoeuvreSolution, start: SE3) -> (SE3, Vector6<f64>)
where
    S: lgsvi_mechanics::System<6, Group = lgsvi_mechanics::group::RigidMotions>,
{
    let mut it = Integrator::new(
        body,
        StepSettings::new(solution.h, nodes).unwrap(),
        start,
        solution.states[0].velocity,
    )
    .unwrap();
    if solution.inputs_at_points.is_empty() {
        for u in &solution.inputs {
            it.set_input(*u).unwrap();
            it.step().unwrap();
        }
    } else {
        for points in &solution.inputs_at_points {
            it.set_input_at_points(points).unwrap();
            it.step().unwrap();
        }
    }
    (it.state().configuration, it.state().velocity)
}

/// The distance between two poses and velocities: the largest entry of SE(3)'s log of
/// one relative to the other and of the velocities' difference.
fn distance(a: &(SE3, Vector6<f64>), b: &(SE3, Vector6<f64>)) -> f64 {
    a.0.inverse()
        .compose(&b.0)
        .log()
        .amax()
        .max((a.1 - b.1).amax())
}

/// A spherical body's turn and move with the wrench a polynomial within each step: the
/// optimum splits (module documentation) and the optimal torque and world force are
/// linear in time, so the discrete problem's optimum is `12 (j²θ² + m²|d|²)/T³` to
/// rounding at any step count (measured 7.7e-16, 3.9e-16, 2.6e-16 relative; asserted to
/// 1e-13, a few hundred roundings of the cost's sum); the solution
/// replays onto the target (the SQP's tolerance, 1e-10, on the miss).
#[test]
fn polynomial_wrenches_meet_the_split_optimum_and_replay() {
    let (j, m, t_end) = (2.0, 5.0, 10.0);
    let theta = 1.2;
    let axis = Vector3::new(1.0, 2.0, 2.0) / 3.0;
    let d = Vector3::new(0.6, -0.3, 0.2);
    let target = SE3::new(SO3::exp(&(axis * theta)), d);
    let body = FreeBody::new(Inertia::from_principal_moments([j; 3]).unwrap(), m).unwrap();
    let optimum = split_optimum(j, theta, m, d.norm(), t_end);
    for (k, n) in [(2, 4), (5, 6), (10, 8)] {
        let solution = Manoeuvre::new(body, t_end)
            .to(target, Vector6::zeros())
            .steps(k)
            .nodes(n)
            .inputs(Inputs::Polynomial)
            .solve()
            .unwrap();
        assert!(solution.converged);
        let error = (solution.cost - optimum).abs() / optimum;
        assert!(
            error <= 1e-13,
            "K = {k}, n = {n}: {} against {optimum}",
            solution.cost
        );
        let end = replay(body, n, &solution, SE3::identity());
        assert!(distance(&end, &(target, Vector6::zeros())) <= 1e-10);
        // The body-frame force turns with the body: not the world force's direction.
        let last = &solution.inputs_at_points[k - 1][0];
        assert!(
            last.fixed_rows::<3>(3)
                .normalize()
                .dot(&d.normalize())
                .abs()
                < 0.99
        );
    }
}

/// A known disturbance wrench `(τ_d a, f_d a)` (body frame) along the turn's axis `a`, the
/// move along `a` too: the body turns about `a`, which stays put (`R a = a`), so the
/// disturbance is the same in the world frame, and each single-axis problem is the
/// undisturbed one in `u + d` (its linear term `−2 d·Σ h_j (u_j + d)` is `−2 d·m Δẋ` or
/// `−2 d·j ΔΩ` along `a`, zero rest to rest): the optimum costs the split optimum plus `|d|² T`, its
/// wrenches are the undisturbed ones less `d`. Polynomial wrenches meet the split optimum
/// to rounding (above), so both hold to 1e-12 relative (the cost) and 1e-10 (the wrenches,
/// the SQP's tolerance); the wrenches plus `d` replay onto the target.
#[test]
fn a_disturbance_along_the_manoeuvre_adds_its_square() {
    let (j, m, t_end, theta, length) = (2.0, 5.0, 10.0, 1.2, 0.8);
    let axis = Vector3::new(1.0, 2.0, 2.0) / 3.0;
    let target = SE3::new(SO3::exp(&(axis * theta)), axis * length);
    let body = FreeBody::new(Inertia::from_principal_moments([j; 3]).unwrap(), m).unwrap();
    let (tau, force) = (0.02 * axis, -0.05 * axis);
    let manoeuvre = Manoeuvre::new(body, t_end)
        .to(target, Vector6::zeros())
        .steps(5)
        .nodes(6)
        .inputs(Inputs::Polynomial);
    let free = manoeuvre.clone().solve().unwrap();
    let disturbed = manoeuvre
        .disturbance(tau.into(), force.into())
        .solve()
        .unwrap();
    let expected = split_optimum(j, theta, m, length, t_end)
        + (tau.norm_squared() + force.norm_squared()) * t_end;
    assert!(
        (disturbed.cost - expected).abs() <= 1e-12 * expected,
        "{} against {expected}",
        disturbed.cost
    );
    let d = Vector6::new(tau.x, tau.y, tau.z, force.x, force.y, force.z);
    let shift = free
        .inputs_at_points
        .iter()
        .flatten()
        .zip(disturbed.inputs_at_points.iter().flatten())
        .map(|(f, u)| (f - (u + d)).amax())
        .fold(0.0, f64::max);
    assert!(shift <= 1e-10, "{shift:e}");
    let replayed = ManoeuvreSolution {
        inputs_at_points: disturbed
            .inputs_at_points
            .iter()
            .map(|step| step.iter().map(|u| u + d).collect())
            .collect(),
        ..disturbed.clone()
    };
    let end = replay(body, 6, &replayed, SE3::identity());
    assert!(distance(&end, &(target, Vector6::zeros())) <= 1e-10);
}

/// An asymmetric body's turn and move under a disturbance wrench off every axis (its force
/// turns with the body, a curvature the world-frame metric leaves out), at the least energy
/// and in the least time: no closed form, so the check is that a fresh integrator given
/// the wrenches plus the disturbance lands on the target (the energy's tolerance 1e-10 on
/// the miss; the least time's, whose final time is a first-order quantity of the residual,
/// 1e-8), within a bounded number of iterations (measured: 11 and 6; `docs/notes/optimal.md`).
#[test]
fn a_manoeuvre_under_a_disturbance_off_its_axes_replays_onto_its_target() {
    let body = FreeBody::new(
        Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap(),
        7.0,
    )
    .unwrap();
    let target = SE3::new(
        SO3::exp(&Vector3::new(0.6, -0.4, 0.9)),
        Vector3::new(1.0, -0.5, 0.3),
    );
    let (tau, force) = (
        Vector3::new(0.004, -0.003, 0.005),
        Vector3::new(0.02, 0.01, -0.015),
    );
    let d = Vector6::new(tau.x, tau.y, tau.z, force.x, force.y, force.z);
    let manoeuvre = Manoeuvre::new(body, 20.0)
        .to(target, Vector6::zeros())
        .steps(20)
        .nodes(8)
        .disturbance(tau.into(), force.into());
    let energy = manoeuvre.clone().solve().unwrap();
    let time = manoeuvre
        .torque_max([0.05; 3])
        .force_max([0.1; 3])
        .cost(lgsvi_optimal::Cost::Time)
        .solve()
        .unwrap();
    for (solution, tolerance, iterations) in [(&energy, 1e-10, 30), (&time, 1e-8, 60)] {
        assert!(
            solution.statistics.iterations <= iterations,
            "{} iterations",
            solution.statistics.iterations
        );
        let replayed = ManoeuvreSolution {
            inputs: solution.inputs.iter().map(|u| u + d).collect(),
            ..solution.clone()
        };
        let end = replay(body, 8, &replayed, SE3::identity());
        let miss = distance(&end, &(target, Vector6::zeros()));
        assert!(
            miss <= tolerance,
            "miss {miss:e} (t_end {})",
            solution.t_end
        );
    }
}

/// With the wrench held over each step (zero-order hold) the discrete optimum converges
/// to the continuous one at second order in `h`, whatever the integrator's order: the
/// observed order between K = 10, 20 and 40 is 2 within 0.1 (measured 2.01 and 2.00).
#[test]
fn held_wrenches_converge_at_second_order() {
    let (j, m, t_end) = (2.0, 5.0, 10.0);
    let theta = 1.2;
    let d = Vector3::new(0.6, -0.3, 0.2);
    let target = SE3::new(SO3::exp(&(Vector3::new(1.0, 2.0, 2.0) / 3.0 * theta)), d);
    let body = FreeBody::new(Inertia::from_principal_moments([j; 3]).unwrap(), m).unwrap();
    let optimum = split_optimum(j, theta, m, d.norm(), t_end);
    let errors: Vec<f64> = [10, 20, 40]
        .iter()
        .map(|&k| {
            let solution = Manoeuvre::new(body, t_end)
                .to(target, Vector6::zeros())
                .steps(k)
                .nodes(6)
                .solve()
                .unwrap();
            (solution.cost - optimum).abs() / optimum
        })
        .collect();
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        assert!((order - 2.0).abs() < 0.1, "order {order}: {errors:?}");
    }
}

/// An asymmetric body's turn and move: the split (module documentation) makes the optimum
/// the rigid body's slew, computed independently of lgsvi through Pontryagin's principle
/// (`tests/data/pontryagin_slew.py`, scipy's `solve_bvp` and DOP853 at rtol 1e-13), plus
/// the centre of mass's cubic `12 m²|d|²/T³` (here a third of the slew's cost). With
/// polynomial wrenches, 8 nodes and 10 steps meet it to 1e-12 relative (measured 5.1e-14;
/// the reference itself is good to ~1e-13: its shooting's terminal miss 1.3e-14).
///
/// With a 40 kg body the translation is 511 times the slew's cost: measured in the world
/// frame's metric (`Manoeuvre`'s documentation) the iteration still takes about as many
/// iterations as with the 1 kg body (measured 10 and 10; the body frame's Gauss–Newton
/// took 617), and at most 20 are allowed here.
#[test]
fn an_asymmetric_manoeuvre_meets_pontryagin_plus_the_cubic() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/pontryagin_slew.json"
    ))
    .unwrap();
    let reference: serde_json::Value = serde_json::from_str(&text).unwrap();
    let numbers = |key: &str| -> Vec<f64> {
        reference[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let inertia = numbers("inertia");
    let attitude = Vector3::from_iterator(numbers("attitude_final"));
    let t_end = reference["t_end"].as_f64().unwrap();
    let d = Vector3::new(3.0, -1.0, 2.0);
    for m in [1.0, 40.0] {
        let optimum =
            reference["cost"].as_f64().unwrap() + 12.0 * m * m * d.norm_squared() / t_end.powi(3);
        let body = FreeBody::new(
            Inertia::from_principal_moments([inertia[0], inertia[1], inertia[2]]).unwrap(),
            m,
        )
        .unwrap();
        let target = SE3::new(SO3::exp(&attitude), d);
        let solution = Manoeuvre::new(body, t_end)
            .to(target, Vector6::zeros())
            .steps(10)
            .nodes(8)
            .inputs(Inputs::Polynomial)
            .solve()
            .unwrap();
        let error = (solution.cost - optimum).abs() / optimum;
        println!(
            "m = {m}: {} against {optimum}: {error:.1e} in {} iterations",
            solution.cost, solution.statistics.iterations
        );
        assert!(
            error <= 1e-12,
            "m = {m}: {} against {optimum}: {error:e}",
            solution.cost
        );
        assert!(
            solution.statistics.iterations <= 20,
            "m = {m}: {} iterations",
            solution.statistics.iterations
        );
        let end = replay(body, 8, &solution, SE3::identity());
        assert!(distance(&end, &(target, Vector6::zeros())) <= 1e-10);
    }
}

/// Bounds on the torque and the force hold at every step and cost more than none, a
/// manoeuvre that needs more than they allow is infeasible (a typed error with the miss
/// it reached), and moving states are reached as well as rest.
#[test]
fn bounds_hold_and_too_tight_ones_are_infeasible() {
    let body = FreeBody::new(
        Inertia::from_principal_moments([1.0, 1.5, 2.0]).unwrap(),
        10.0,
    )
    .unwrap();
    let start = (
        SE3::new(
            SO3::exp(&Vector3::new(0.1, 0.0, -0.2)),
            Vector3::new(0.0, 1.0, 0.0),
        ),
        Vector6::new(0.01, 0.0, 0.0, 0.05, 0.0, 0.0),
    );
    let target = (
        SE3::new(
            SO3::exp(&Vector3::new(0.0, 0.0, 1.5)),
            Vector3::new(2.0, 0.0, 0.5),
        ),
        Vector6::new(0.0, 0.0, 0.02, 0.0, 0.0, 0.0),
    );
    // Unbounded, the world-frame force's metric converges in 13 iterations; with the force
    // bounded too (the subproblem's banded form keeps the bounds as bounds), in 26 with
    // both bounds and 25 with the force's alone, each counting the unbounded solve it
    // starts from. Measured in the body frame instead, the Gauss–Newton iteration
    // converges linearly (the force's direction turns with the attitude): 94 and 93.
    let manoeuvre = Manoeuvre::new(body, 30.0)
        .from(start.0, start.1)
        .to(target.0, target.1)
        .steps(30)
        .nodes(6)
        .tolerance(1e-9)
        .max_iterations(300);
    let free = manoeuvre.clone().solve().unwrap();
    let peak = |range: std::ops::Range<usize>| {
        free.inputs
            .iter()
            .map(|u| u.rows(range.start, range.len()).amax())
            .fold(0.0, f64::max)
    };
    let (torque, force) = (0.8 * peak(0..3), 0.8 * peak(3..6));
    let solution = manoeuvre
        .clone()
        .torque_max([torque; 3])
        .force_max([force; 3])
        .solve()
        .unwrap();
    for u in &solution.inputs {
        assert!(u.fixed_rows::<3>(0).amax() <= torque * (1.0 + 1e-9), "{u}");
        assert!(u.fixed_rows::<3>(3).amax() <= force * (1.0 + 1e-9), "{u}");
    }
    // Bounds are active, and the bounded optimum costs more.
    let on_bound = |u: &Vector6<f64>| {
        (u.fixed_rows::<3>(0).amax() - torque).abs() < 1e-6 * torque
            || (u.fixed_rows::<3>(3).amax() - force).abs() < 1e-6 * force
    };
    assert!(solution.inputs.iter().any(on_bound));
    assert!(solution.cost > free.cost);
    let end = replay(body, 6, &solution, start.0);
    assert!(
        distance(&end, &target) <= 1e-9,
        "{}",
        distance(&end, &target)
    );
    // The force alone bounded: the torque is free (its bound infinite).
    let forced = manoeuvre.clone().force_max([force; 3]).solve().unwrap();
    assert!(forced
        .inputs
        .iter()
        .all(|u| u.fixed_rows::<3>(3).amax() <= force * (1.0 + 1e-9)));
    assert!(forced.cost > free.cost && forced.cost < solution.cost);
    // The world frame's metric with the bounds: well under the body frame's 94.
    for (name, run) in [("both bounds", &solution), ("force bounded", &forced)] {
        assert!(
            run.statistics.iterations <= 40,
            "{name}: {} iterations",
            run.statistics.iterations
        );
    }
    println!(
        "iterations: free {}, bounded {}, force bounded {}",
        free.statistics.iterations, solution.statistics.iterations, forced.statistics.iterations
    );
    let tight = manoeuvre.force_max([0.05 * force; 3]).solve().unwrap_err();
    assert!(
        matches!(tight, OptimalError::Infeasible { bounded: true, .. }),
        "{tight:?}"
    );
    assert!(tight.to_string().contains("infeasible"), "{tight}");
}

/// A body in orbit (μ = 1, a circular orbit of radius 1): a manoeuvre to the state its
/// free drift reaches costs nothing, and one to that state turned by δ about the orbit's
/// axis (position and velocity; phasing along the orbit) costs `c δ² + O(δ³)` — the law
/// the problem's smoothness gives, so doubling δ quadruples the cost to within 2%. Each
/// replays onto its target.
#[test]
fn an_orbiting_body_phases_along_its_orbit() {
    // A body small against its orbit (radius of gyration 0.13), so that MacCullagh's
    // far-field potential holds.
    let body = OrbitingBody::new(
        Inertia::from_principal_moments([0.01, 0.012, 0.014]).unwrap(),
        1.0,
        1.0,
    )
    .unwrap();
    let t_end = 2.0;
    let start = (
        SE3::new(SO3::identity(), Vector3::x()),
        Vector6::new(0.0, 0.0, 0.0, 0.0, 1.0, 0.0),
    );
    // The free drift's end.
    let settings = StepSettings::new(t_end / 20.0, 8).unwrap();
    let mut drift = Integrator::new(body, settings, start.0, start.1).unwrap();
    drift.run(20, 1).unwrap();
    let free_end = (drift.state().configuration, drift.state().velocity);
    let solve = |target: (SE3, Vector6<f64>)| {
        Manoeuvre::new(body, t_end)
            .from(start.0, start.1)
            .to(target.0, target.1)
            .steps(20)
            .nodes(8)
            .solve()
            .unwrap()
    };
    let none = solve(free_end);
    assert!(none.cost < 1e-18, "{}", none.cost);
    // The drift's end turned by δ about the orbit's axis z, attitude and rates kept.
    let ahead = |delta: f64| {
        let turn = SO3::exp(&(Vector3::z() * delta));
        let x = turn.matrix() * free_end.0.translation();
        let attitude = *free_end.0.rotation();
        let world_velocity = turn.matrix() * attitude.matrix() * free_end.1.fixed_rows::<3>(3);
        let v = attitude.matrix().transpose() * world_velocity;
        let omega = free_end.1.fixed_rows::<3>(0);
        (
            SE3::new(attitude, x),
            Vector6::new(omega[0], omega[1], omega[2], v.x, v.y, v.z),
        )
    };
    let costs: Vec<f64> = [0.005, 0.01]
        .iter()
        .map(|&delta| {
            let target = ahead(delta);
            let solution = solve(target);
            let end = replay(body, 8, &solution, start.0);
            assert!(distance(&end, &target) <= 1e-9);
            solution.cost
        })
        .collect();
    let ratio = costs[1] / costs[0];
    println!("{costs:?}: ratio {ratio}");
    assert!((ratio - 4.0).abs() < 0.08, "{costs:?}: ratio {ratio}");
}

/// Settings out of range are refused, naming themselves.
#[test]
fn bad_settings_name_themselves() {
    let body = FreeBody::new(
        Inertia::from_principal_moments([1.0, 1.5, 2.0]).unwrap(),
        10.0,
    )
    .unwrap();
    let cases: Vec<(Manoeuvre, &str)> = vec![
        (Manoeuvre::new(body, 0.0), "t_end"),
        (Manoeuvre::new(body, f64::NAN), "t_end"),
        (Manoeuvre::new(body, 10.0).steps(1), "steps"),
        (
            Manoeuvre::new(body, 10.0).torque_max([0.1, -1.0, 0.1]),
            "torque_max",
        ),
        (
            Manoeuvre::new(body, 10.0).force_max([0.1, 0.0, 0.1]),
            "force_max",
        ),
        (Manoeuvre::new(body, 10.0).tolerance(0.0), "tolerance"),
        (
            Manoeuvre::new(body, 10.0).to(
                SE3::new(SO3::identity(), Vector3::new(f64::NAN, 0.0, 0.0)),
                Vector6::zeros(),
            ),
            "target",
        ),
        (
            Manoeuvre::new(body, 10.0).from(SE3::identity(), Vector6::repeat(f64::INFINITY)),
            "start",
        ),
        (
            Manoeuvre::new(body, 10.0).warm_start(vec![Vector6::zeros(); 3]),
            "warm_start",
        ),
        (
            Manoeuvre::new(body, 10.0)
                .steps(4)
                .track(vec![(SE3::identity(), Vector6::zeros()); 3], [1.0; 4]),
            "track",
        ),
        (
            Manoeuvre::new(body, 10.0).steps(2).track(
                vec![(SE3::identity(), Vector6::zeros()); 2],
                [1.0, -1.0, 1.0, 1.0],
            ),
            "track",
        ),
        (
            Manoeuvre::new(body, 10.0).terminal_cost([1.0, f64::NAN, 1.0, 1.0]),
            "terminal_cost",
        ),
    ];
    for (manoeuvre, name) in cases {
        let error = manoeuvre.solve().unwrap_err();
        assert!(
            matches!(&error, OptimalError::InvalidSetting { name: n, .. } if *n == name),
            "{name}: {error:?}"
        );
        assert!(error.to_string().contains(name), "{error}");
    }
    let error = Manoeuvre::new(body, 10.0).nodes(1).solve().unwrap_err();
    assert!(matches!(error, OptimalError::Mechanics(_)), "{error:?}");
    assert!(error.to_string().contains("nodes"), "{error}");
}

/// A free body 7000 km from the origin (an orbit's radius in SI units, without the
/// orbit), moved by 1 m and turned by 0.5 rad in 10 s, reaches the optimum it has at the
/// origin (the free body's manoeuvre does not depend on where it starts) to 1e-8
/// relative: the position's rounding `ε|x| ≈ 1.6e-9` m over the 1 m move, accumulated
/// over the steps and doubled in the cost (measured 1.2e-9). Its miss is measured in
/// units of `L = 7e6` m (`Manoeuvre`'s documentation), the multipliers scaled back.
#[test]
fn a_body_far_from_the_origin_converges_to_its_own_precision() {
    let body = FreeBody::new(
        Inertia::from_principal_moments([1.0, 1.5, 2.0]).unwrap(),
        2.0,
    )
    .unwrap();
    let solve = |origin: Vector3<f64>| {
        Manoeuvre::new(body, 10.0)
            .from(SE3::new(SO3::identity(), origin), Vector6::zeros())
            .to(
                SE3::new(
                    SO3::exp(&Vector3::new(0.0, 0.3, 0.4)),
                    origin + Vector3::new(1.0, 0.0, 0.0),
                ),
                Vector6::zeros(),
            )
            .steps(10)
            .nodes(6)
            .solve()
            .unwrap()
    };
    let (near, far) = (
        solve(Vector3::zeros()),
        solve(Vector3::new(7.0e6, 0.0, 0.0)),
    );
    assert!(
        (far.cost - near.cost).abs() <= 1e-8 * near.cost,
        "{} against {}",
        far.cost,
        near.cost
    );
    let end = far.states.last().unwrap();
    assert!((end.position() - Vector3::new(7.0e6 + 1.0, 0.0, 0.0)).amax() <= 1e-9 * 7.0e6);
    // The multipliers `∂J*/∂e` do not depend on where the body is either (to the same
    // rounding, relative to the largest).
    let largest = near.multipliers.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    for (a, b) in far.multipliers.iter().zip(&near.multipliers) {
        assert!(
            (a - b).abs() <= 1e-6 * largest,
            "{:?} against {:?}",
            far.multipliers,
            near.multipliers
        );
    }
}

/// The true cost of held wrenches `inputs` from `start` (`Σ h |u_k|²`, the tracking terms
/// `h Σ_k (q_θ |log(R_refᵀ R_k)|² + q_x |x_k − x_ref|² + q_ω |Ω_k − Ω_ref|² +
/// q_v |ẋ_k − ẋ_ref|²)` and the terminal ones with `q_f`), by a replay: the integrator's
/// steps and the group's log, nothing of the solver's.
#[allow(clippy::type_complexity)]
fn true_cost(
    body: FreeBody,
    h: f64,
    inputs: &[Vector6<f64>],
    reference: &[(SE3, Vector6<f64>)],
    target: (SE3, Vector6<f64>),
    q: [f64; 4],
    q_f: [f64; 4],
) -> f64 {
    let mut it = Integrator::new(
        body,
        StepSettings::new(h, 8).unwrap(),
        SE3::identity(),
        Vector6::zeros(),
    )
    .unwrap();
    let terms = |g: &SE3, xi: &Vector6<f64>, (pose, v): &(SE3, Vector6<f64>), q: [f64; 4]| {
        let world = |g: &SE3, xi: &Vector6<f64>| g.rotation().matrix() * xi.fixed_rows::<3>(3);
        let parts = [
            pose.rotation().inverse().compose(g.rotation()).log(),
            g.translation() - pose.translation(),
            xi.fixed_rows::<3>(0) - v.fixed_rows::<3>(0),
            world(g, xi) - world(pose, v),
        ];
        parts
            .iter()
            .zip(q)
            .map(|(p, q)| q * p.norm_squared())
            .sum::<f64>()
    };
    let mut cost = 0.0;
    for (u, reference) in inputs.iter().zip(reference) {
        it.set_input(*u).unwrap();
        it.step().unwrap();
        let s = it.state();
        cost += h * u.norm_squared() + h * terms(&s.configuration, &s.velocity, reference, q);
    }
    let s = it.state();
    cost + terms(&s.configuration, &s.velocity, &target, q_f)
}

/// Tracking and a soft target: at the solution the true cost (`true_cost`, a replay) is
/// the solver's and is stationary, its central differences along four directions of the
/// wrenches below 1e-8 of the cost's scale. The differences' own error at `ε = 1e-6` is
/// their truncation `ε² ∂³J` ≈ 3e-9 (measured: the slope scales as `ε²`, 2.8e-5 at
/// `ε = 1e-4`, 2.8e-7 at 1e-5, 3e-9 at 1e-6) and their rounding `1e-16 J/ε` ≈ 5e-10. The reference turns the body and
/// moves it along a curve it cannot follow exactly (velocities off the positions' slope),
/// so the residuals do not vanish and the Gauss–Newton model is not exact; the force is
/// free, so the world-frame metric is on.
#[test]
fn a_tracking_manoeuvre_is_stationary_for_the_true_cost() {
    let body = FreeBody::new(
        Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap(),
        2.0,
    )
    .unwrap();
    let (t_end, k_steps) = (20.0, 12usize);
    let h = t_end / k_steps as f64;
    let target = (
        SE3::new(
            SO3::exp(&Vector3::new(1.2, 0.4, -0.7)),
            Vector3::new(3.0, -1.0, 0.5),
        ),
        Vector6::zeros(),
    );
    let reference: Vec<(SE3, Vector6<f64>)> = (1..=k_steps)
        .map(|k| {
            let s = k as f64 / k_steps as f64;
            (
                SE3::new(
                    SO3::exp(&(Vector3::new(0.2, 1.0, 0.4) * s)),
                    Vector3::new(3.0 * s, (3.0 * s).sin(), 0.0),
                ),
                Vector6::new(0.0, 0.05, 0.0, 0.1, 0.0, 0.0),
            )
        })
        .collect();
    let (q, q_f) = ([0.4, 0.3, 2.0, 1.0], [5.0, 4.0, 5.0, 3.0]);
    let solution = Manoeuvre::new(body, t_end)
        .to(target.0, target.1)
        .steps(k_steps)
        .nodes(8)
        .track(reference.clone(), q)
        .terminal_cost(q_f)
        .solve()
        .unwrap();
    println!(
        "tracking: cost {} in {} iterations",
        solution.cost, solution.statistics.iterations
    );
    let base = true_cost(body, h, &solution.inputs, &reference, target, q, q_f);
    assert!(
        (base - solution.cost).abs() <= 1e-12 * base,
        "{base} against {}",
        solution.cost
    );
    let eps = 1e-6;
    let scale: f64 = solution.inputs.iter().map(|u| 2.0 * h * u.norm()).sum();
    for d in 0..4 {
        let direction: Vec<Vector6<f64>> = (0..k_steps)
            .map(|k| {
                let x = (k * 7 + d * 3) as f64;
                Vector6::from_fn(|i, _| (x * 0.7 + i as f64 * 1.1 + d as f64).sin())
            })
            .collect();
        let moved = |sign: f64| -> Vec<Vector6<f64>> {
            solution
                .inputs
                .iter()
                .zip(&direction)
                .map(|(u, v)| u + v * (sign * eps))
                .collect()
        };
        let slope = (true_cost(body, h, &moved(1.0), &reference, target, q, q_f)
            - true_cost(body, h, &moved(-1.0), &reference, target, q, q_f))
            / (2.0 * eps);
        println!("direction {d}: slope {slope:.1e} (scale {scale:.2})");
        assert!(
            slope.abs() <= 1e-8 * scale.max(1e-3),
            "direction {d}: slope {slope:e}"
        );
    }
}

/// A soft target with weights growing tends to the exact one: the terminal miss falls as
/// the weights rise, and costs less than the exact target's. Heavy weights make the least
/// squares stiff: at q = 1e4 the Gauss–Newton Hessian's largest entries reach ~1e6 (the
/// position's sensitivity to the force, ~10 m/N over 30 s, times √q = 100, squared), so
/// a wrench rounded to its last bit moves the gradient by ~1e6 · 1e-16 and the scaled
/// stationarity cannot be certified below ~1e-9 in double precision (measured: it
/// reaches 1e-9 in 250 iterations and then wanders between 3e-10 and 2e-9). That case is
/// solved to 1e-8; q = 1 and 100 to the default 1e-10 (10 and 11 iterations).
#[test]
fn a_soft_target_tends_to_the_exact_one() {
    let body = FreeBody::new(
        Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap(),
        10.0,
    )
    .unwrap();
    let target = (
        SE3::new(
            SO3::exp(&Vector3::new(1.5, 0.4, -0.9)),
            Vector3::new(3.0, -1.0, 2.0),
        ),
        Vector6::zeros(),
    );
    let manoeuvre = Manoeuvre::new(body, 30.0).to(target.0, target.1).steps(10);
    let exact = manoeuvre.clone().solve().unwrap();
    let mut previous = f64::INFINITY;
    for q in [1.0, 100.0, 10_000.0] {
        let tolerance = if q > 1e3 { 1e-8 } else { 1e-10 };
        let soft = manoeuvre
            .clone()
            .terminal_cost([q; 4])
            .tolerance(tolerance)
            .solve()
            .unwrap();
        let end = soft.states.last().unwrap();
        let miss = distance(&(end.configuration, end.velocity), &target);
        println!(
            "q = {q}: miss {miss:.2e}, cost {} against {}, {} iterations",
            soft.cost, exact.cost, soft.statistics.iterations
        );
        assert!(
            miss < previous && soft.cost < exact.cost,
            "q = {q}: miss {miss}"
        );
        assert!(soft.multipliers.iter().all(|m| *m == 0.0));
        previous = miss;
    }
    assert!(previous < 1e-3, "{previous}");
}
