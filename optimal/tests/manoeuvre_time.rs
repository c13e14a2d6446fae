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
/// move). The two problems share every torque step but not the step's chart (SO(3)'s
/// against SE(3)'s rotation–translation chart), so they agree to the integrator's error
/// at these steps, far below the published value's 1e-4.
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
    assert!(error < 1e-9, "{error:e}");
    assert!((manoeuvre.t_end - 28.6304077).abs() / 28.6304077 < 2e-3);
}
