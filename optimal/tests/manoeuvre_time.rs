//! Manoeuvres of a body in space (SE(3)) in the least time, against a closed form.
//!
//! **The closed form.** A spherical body (`J = jI`, mass `m`) with each body-axis entry of
//! the torque bounded by `τ` and of the force by `f`, turned by `θ` about the diagonal
//! `a = (1, 1, 1)/√3` and moved by `d` along it, rest to rest. Whatever the attitude, the
//! box holds `|u| ≤ √3 τ` and `|F| = |f_body| ≤ √3 f`; rest to rest, the rates' size is at
//! most `√3 τ min(t, T − t)/j`, so the angle turned (the geodesic distance, at most
//! `∫|Ω| dt`) is at most `√3 τ T²/(4j)`, and likewise the distance moved at most
//! `√3 f T²/(4m)`. Both bounds are met together by the eigen-axis bang-bang, torque
//! `±τ(1, 1, 1)` and body force `±f(1, 1, 1)` switched at `T/2` (a turn about `a` keeps
//! the body's diagonal on the world's, so the world force stays along `a`). The least time
//! is therefore `T* = max(2√(jθ/(√3τ)), 2√(md/(√3f)))`, and with an even step count the
//! switch falls on a step boundary, where a wrench held over each step resolves it: the
//! integrator reproduces the bang-bang's quadratic angle and position exactly (the chart's
//! curve is the angle times `a`, a polynomial of degree two), so the discrete least time
//! is `T*` to rounding.

use lgsvi_mechanics::lie::{SE3, SO3};
use lgsvi_mechanics::{FreeBody, Inertia};
use lgsvi_optimal::{Cost, Manoeuvre};
use nalgebra::{Vector3, Vector6};

#[test]
fn the_diagonal_turn_and_move_meet_the_closed_form() {
    let (j, m, tau, f) = (2.0, 5.0, 0.1, 0.2);
    let axis = Vector3::repeat(1.0 / 3f64.sqrt());
    let sqrt3 = 3f64.sqrt();
    for (theta, d) in [(1.2, 0.96), (1.2, 0.3), (0.4, 0.96)] {
        let exact = f64::max(
            2.0 * (j * theta / (sqrt3 * tau)).sqrt(),
            2.0 * (m * d / (sqrt3 * f)).sqrt(),
        );
        let body = FreeBody::new(Inertia::from_principal_moments([j; 3]).unwrap(), m).unwrap();
        let target = SE3::new(SO3::exp(&(axis * theta)), axis * d);
        let clock = std::time::Instant::now();
        let solution = Manoeuvre::new(body, 10.0)
            .to(target, Vector6::zeros())
            .torque_max([tau; 3])
            .force_max([f; 3])
            .steps(10)
            .nodes(6)
            .cost(Cost::Time)
            .solve()
            .unwrap();
        let error = (solution.t_end - exact).abs() / exact;
        eprintln!(
            "θ = {theta}, d = {d}: T = {:.15} against {exact:.15}, {error:.1e}, {} iterations, {:.2} s",
            solution.t_end,
            solution.statistics.iterations,
            clock.elapsed().as_secs_f64()
        );
        assert!(error < 1e-10, "θ = {theta}, d = {d}: {error:e}");
        // Where the turn binds and the move does not, the multipliers are the least time's
        // sensitivity: along the axis `∂T*/∂θ = T*/(2θ)`, none to the position's miss.
        if j * theta / tau > m * d / f {
            let along = Vector3::from_fn(|i, _| solution.multipliers[i]).dot(&axis);
            let position = Vector3::from_fn(|i, _| solution.multipliers[3 + i]);
            eprintln!(
                "  multipliers: along the axis {along} against {}, position {position:?}",
                exact / (2.0 * theta)
            );
            assert!(
                (along - exact / (2.0 * theta)).abs() < 1e-6 * exact,
                "{along}"
            );
            assert!(position.amax() < 1e-6 * exact, "{position:?}");
        }
        // The binding part's inputs are the bang-bang's, on their bounds.
        let binding = if j * theta / tau >= m * d / f { 0 } else { 3 };
        let bound = if binding == 0 { tau } else { f };
        for u in &solution.inputs {
            for i in binding..binding + 3 {
                assert!((u[i].abs() - bound).abs() < 1e-9 * bound, "{u:?}");
            }
        }
    }
}

/// Betts's reorientation (Fleming, Sekhavat & Ross 2008: `J = diag(5621, 4547, 2364)`
/// kg·m², `|τ_i| ≤ 50` N·m, 150° about body x, rest to rest) as a manoeuvre that does not
/// move: the free body's turn does not feel the force, so the least time is the slew's,
/// whatever the force (left free, and not unique: any force whose push adds up to no
/// move). SE(3)'s rotation–translation chart turns the attitude by SO(3)'s exp chart, the
/// slew's, so the two discrete problems are the same turn and agree to rounding (measured
/// 2.5e-16); both lie 1.3e-3 above the published time, the slew's own discretisation error
/// at 25 steps (`docs/guide/optimal.md`, Betts's table).
#[test]
fn betts_reorientation_in_space_takes_the_slews_time() {
    use lgsvi_optimal::Slew;
    let inertia = Inertia::from_principal_moments([5621.0, 4547.0, 2364.0]).unwrap();
    let turn = SO3::exp(&(Vector3::x() * 150f64.to_radians()));
    let (steps, nodes) = (25, 8);
    let slew = Slew::new(inertia, 30.0)
        .to(turn, Vector3::zeros())
        .torque_max([50.0; 3])
        .steps(steps)
        .nodes(nodes)
        .cost(Cost::Time)
        .solve()
        .unwrap();
    let body = FreeBody::new(inertia, 100.0).unwrap();
    let clock = std::time::Instant::now();
    let manoeuvre = Manoeuvre::new(body, 30.0)
        .to(SE3::new(turn, Vector3::zeros()), Vector6::zeros())
        .torque_max([50.0; 3])
        .force_max([1.0; 3])
        .steps(steps)
        .nodes(nodes)
        .cost(Cost::Time)
        .solve()
        .unwrap();
    let error = (manoeuvre.t_end - slew.t_end).abs() / slew.t_end;
    eprintln!(
        "slew {:.12} s, manoeuvre {:.12} s: {error:.1e}; {} iterations, {:.2} s",
        slew.t_end,
        manoeuvre.t_end,
        manoeuvre.statistics.iterations,
        clock.elapsed().as_secs_f64()
    );
    // The two solves stop at a KKT residual of 1e-10, not at rounding.
    assert!(error < 1e-12, "{error:e}");
    assert!((manoeuvre.t_end - 28.6304077).abs() / 28.6304077 < 2e-3);
}

/// An orbiting body's least time, checked by a route that does not use the step's
/// derivative in its length (whose `μ` term the orbit needs): below the least time `T*` no
/// wrench within the bounds reaches the target, and in a longer time some does. So the
/// fixed-time minimum-energy solver on the same steps, started from the least-time wrenches,
/// finds the target in reach at `T*(1 + 1e-3)` and out of reach at `T*(1 − 1e-3)` (a local
/// certificate, the one a Newton-type method gives). The diagonal turn and move of the
/// first test, from rest at `x = (10, 0, 0)` about a point mass of `μ = 0.01` (the body's
/// radius of gyration 0.63, far inside the far field): the pull towards the origin
/// lengthens the free body's 7.4448 s.
#[test]
fn an_orbiting_bodys_least_time_is_the_edge_of_reach() {
    use lgsvi_mechanics::lie::LieGroup;
    use lgsvi_mechanics::{Integrator, OrbitingBody, StepSettings};
    use lgsvi_optimal::OptimalError;
    let (j, m, tau, f, theta, d) = (2.0, 5.0, 0.1, 0.2, 1.2, 0.96);
    let axis = Vector3::repeat(1.0 / 3f64.sqrt());
    let body =
        OrbitingBody::new(Inertia::from_principal_moments([j; 3]).unwrap(), m, 0.01).unwrap();
    let x0 = Vector3::new(10.0, 0.0, 0.0);
    let start = SE3::new(SO3::identity(), x0);
    let target = SE3::new(SO3::exp(&(axis * theta)), x0 + axis * d);
    let manoeuvre = |t: f64| {
        Manoeuvre::new(body, t)
            .from(start, Vector6::zeros())
            .to(target, Vector6::zeros())
            .torque_max([tau; 3])
            .force_max([f; 3])
            .steps(10)
            .nodes(6)
    };
    let clock = std::time::Instant::now();
    let fastest = manoeuvre(10.0).cost(Cost::Time).solve().unwrap();
    let t_star = fastest.t_end;
    eprintln!(
        "T* = {t_star:.12} s, {} iterations, {:.2} s",
        fastest.statistics.iterations,
        clock.elapsed().as_secs_f64()
    );
    let free = 2.0 * (j * theta / (3f64.sqrt() * tau)).sqrt();
    assert!(
        t_star > free && t_star < 1.01 * free,
        "{t_star} against {free}"
    );
    let at = |t: f64| manoeuvre(t).warm_start(fastest.inputs.clone()).solve();
    assert!(at(t_star * (1.0 + 1e-3)).unwrap().converged);
    match at(t_star * (1.0 - 1e-3)) {
        Err(OptimalError::Infeasible { bounded: true, .. }) => {}
        other => panic!("T* = {t_star}: shorter time {other:?}"),
    }
    // The wrenches replay through the orbiting body's integrator onto the target.
    let settings = StepSettings::new(fastest.h, 6).unwrap();
    let mut it = Integrator::new(body, settings, start, Vector6::zeros()).unwrap();
    for u in &fastest.inputs {
        it.set_input(*u).unwrap();
        it.step().unwrap();
    }
    let miss = it
        .state()
        .configuration
        .inverse()
        .compose(&target)
        .log()
        .amax();
    assert!(miss < 1e-9 && it.state().velocity.amax() < 1e-9, "{miss:e}");
}
