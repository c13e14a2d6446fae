//! Minimum-energy slews against references that do not come from the solver: the exact
//! optimum of the discrete problem for a spherical body (a double integrator about a fixed
//! axis, whose least-norm torques follow from two linear conditions), the continuous
//! optimum `J* = 12 j²θ²/T³` (the single-axis cubic, derived in `docs/guide/optimal.md`) and its
//! second-order convergence under constant torques per step, the replay of a solution by
//! the integrator, the bounds, and the errors.

use lgsvi_mechanics::lie::{LieGroup, SO3};
use lgsvi_mechanics::{Inertia, Integrator, RigidBody, StepSettings};
use lgsvi_optimal::{Inputs, OptimalError, Slew};
use nalgebra::Vector3;

mod common;
use common::discrete_optimum;

fn spherical(j: f64, theta: f64, t_end: f64, k: usize) -> f64 {
    let axis = Vector3::new(1.0, 2.0, 2.0) / 3.0;
    let solution = Slew::new(Inertia::from_principal_moments([j; 3]).unwrap(), t_end)
        .to(SO3::exp(&(axis * theta)), Vector3::zeros())
        .steps(k)
        .nodes(6)
        .solve()
        .unwrap();
    assert!(solution.converged);
    solution.cost
}

#[test]
fn a_spherical_body_meets_the_discrete_problems_exact_optimum() {
    // The integrator is exact for this motion (the chart curve is quadratic in time), so
    // the solver's optimum is the discrete problem's to rounding: 1e-12 relative allows
    // the KKT tolerance (1e-10 on the scaled residual) squared through the cost, and the
    // solves' rounding.
    let (j, theta, t_end) = (2.0, 1.2, 10.0);
    for k in [5, 20] {
        let ours = spherical(j, theta, t_end, k);
        let exact = discrete_optimum(j, theta, t_end, k);
        assert!(
            (ours - exact).abs() <= 1e-12 * exact,
            "K = {k}: {ours} against {exact}"
        );
    }
}

#[test]
fn constant_torques_converge_to_the_continuous_optimum_at_second_order() {
    let (j, theta, t_end): (f64, f64, f64) = (2.0, 1.2, 10.0);
    let continuous = 12.0 * j * j * theta * theta / t_end.powi(3);
    let errors: Vec<f64> = [10, 20, 40]
        .iter()
        .map(|&k| (spherical(j, theta, t_end, k) - continuous).abs() / continuous)
        .collect();
    // The discrete cost lies above the continuous one by O(h²): halving h divides the
    // error by 4 (to within 2% at these K).
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        assert!((order - 2.0).abs() < 0.05, "order {order}: {errors:?}");
    }
}

/// An asymmetric body's slew between moving states, without and with a disturbance torque
/// off every axis of the turn (no closed form there): a fresh integrator given the torques
/// (plus the disturbance) lands on the target.
#[test]
fn an_asymmetric_slew_replays_onto_its_target() {
    let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap();
    let start = SO3::exp(&Vector3::new(0.1, -0.2, 0.3));
    let target = SO3::exp(&Vector3::new(1.5, 0.4, -0.9));
    let (w0, wf) = (Vector3::new(0.02, 0.0, -0.01), Vector3::new(0.0, 0.01, 0.0));
    let slew = Slew::new(inertia, 30.0)
        .from(start, w0)
        .to(target, wf)
        .steps(30)
        .nodes(10);
    let d = Vector3::new(0.01, -0.02, 0.015);
    let free = slew.clone().solve().unwrap();
    let disturbed = slew.disturbance(d.into()).solve().unwrap();
    for (solution, disturbance) in [(&free, Vector3::zeros()), (&disturbed, d)] {
        assert!(solution.converged);
        assert!(*solution.statistics.kkt_residuals.last().unwrap() <= 1e-10);
        let mut it = Integrator::new(
            RigidBody::new(inertia),
            StepSettings::new(solution.h, 10).unwrap(),
            start,
            w0,
        )
        .unwrap();
        for u in &solution.inputs {
            it.set_input(u + disturbance).unwrap();
            it.step().unwrap();
        }
        let end = it.state();
        let miss = end.configuration.inverse().compose(&target).log().amax();
        assert!(
            miss <= 1e-10,
            "attitude miss {miss}, disturbance {disturbance:?}"
        );
        assert!((end.velocity - wf).amax() <= 1e-10);
        assert_eq!(solution.states.len(), 31);
    }
    // The disturbance is worked against: the torques move by about d.
    let apart = free
        .inputs
        .iter()
        .zip(&disturbed.inputs)
        .map(|(f, u)| (f - u).amax())
        .fold(0.0, f64::max);
    assert!(apart > 0.5 * d.amax(), "{apart:e}");
}

#[test]
fn bounds_hold_and_too_tight_ones_are_infeasible() {
    let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.0]).unwrap();
    let target = SO3::exp(&Vector3::new(0.0, 0.0, 1.0));
    let free = Slew::new(inertia, 10.0)
        .to(target, Vector3::zeros())
        .steps(20)
        .solve()
        .unwrap();
    let peak = free.inputs.iter().map(|u| u.amax()).fold(0.0, f64::max);
    // Bounded at 80% of the free optimum's peak: the bound is active, the cost higher.
    let bound = 0.8 * peak;
    let bounded = Slew::new(inertia, 10.0)
        .to(target, Vector3::zeros())
        .steps(20)
        .torque_max([bound; 3])
        .solve()
        .unwrap();
    let largest = bounded.inputs.iter().map(|u| u.amax()).fold(0.0, f64::max);
    assert!(largest <= bound * (1.0 + 1e-9) && largest >= bound * (1.0 - 1e-6));
    assert!(bounded.cost > free.cost);
    // A rest-to-rest turn of 1 rad about z in 10 s needs a peak torque of at least
    // 4 J₃ θ / T² = 0.2 N·m (bang-bang); 0.05 cannot.
    let error = Slew::new(inertia, 10.0)
        .to(target, Vector3::zeros())
        .steps(20)
        .torque_max([0.05; 3])
        .solve()
        .unwrap_err();
    assert!(matches!(error, OptimalError::Infeasible { .. }), "{error}");
    assert!(error.to_string().contains("infeasible"));
}

#[test]
fn bad_settings_name_themselves() {
    let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.0]).unwrap();
    for (slew, word) in [
        (Slew::new(inertia, -1.0), "t_end"),
        (Slew::new(inertia, 1.0).steps(0), "steps"),
        (
            Slew::new(inertia, 1.0).torque_max([1.0, 0.0, 1.0]),
            "torque_max",
        ),
        (Slew::new(inertia, 1.0).tolerance(0.0), "tolerance"),
        (
            Slew::new(inertia, 1.0).warm_start(vec![Vector3::zeros(); 3]),
            "warm_start",
        ),
    ] {
        let error = slew.solve().unwrap_err();
        assert!(error.to_string().contains(word), "{word}: {error}");
    }
    // An oblique turn is nonlinear in the torques: one iteration does not settle it.
    let error = Slew::new(inertia, 10.0)
        .to(SO3::exp(&Vector3::new(1.5, 0.4, -0.9)), Vector3::zeros())
        .max_iterations(1)
        .solve()
        .unwrap_err();
    assert!(
        matches!(error, OptimalError::NotConverged { .. }),
        "{error}"
    );
}

/// A step setting the integrator refuses comes back as the integrator's error, naming it.
#[test]
fn an_integrator_setting_out_of_range_is_named() {
    let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.0]).unwrap();
    let error = Slew::new(inertia, 10.0).nodes(1).solve().unwrap_err();
    assert!(matches!(error, OptimalError::Mechanics(_)), "{error:?}");
    assert!(error.to_string().contains("nodes"), "{error}");
}

/// Check 3 of the issue: the asymmetric body's minimum-energy slew against an indirect
/// solution through Pontryagin's principle, computed independently of lgsvi by
/// `tests/data/pontryagin_slew.py` (scipy's `solve_bvp`, then single shooting with DOP853
/// at rtol 1e-13: its terminal miss 1.3e-14). With the torque a polynomial within each
/// step (its values at the Gauss points), 8 nodes and 10 steps meet it to 1e-9 relative
/// (measured 7e-14: the discrete optimum converges at the integrator's order, `h^14`).
#[test]
fn polynomial_inputs_meet_pontryagins_optimum() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/pontryagin_slew.json"
    ))
    .unwrap();
    let reference: serde_json::Value = serde_json::from_str(&text).unwrap();
    let cost = reference["cost"].as_f64().unwrap();
    let target = Vector3::from_iterator(
        reference["attitude_final"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap()),
    );
    let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap();
    let solve = |k: usize, n: usize| {
        Slew::new(inertia, reference["t_end"].as_f64().unwrap())
            .to(SO3::exp(&target), Vector3::zeros())
            .steps(k)
            .nodes(n)
            .inputs(Inputs::Polynomial)
            .solve()
            .unwrap()
    };
    let solution = solve(10, 8);
    assert!(solution.converged);
    let error = (solution.cost - cost).abs() / cost;
    assert!(error <= 1e-9, "{} against {cost}: {error:e}", solution.cost);
    // Order 2(n − 1) = 6 with 4 nodes (measured 6.07 and 6.02 at K = 5 → 10 → 20).
    let errors: Vec<f64> = [5, 10, 20]
        .iter()
        .map(|&k| (solve(k, 4).cost - cost).abs() / cost)
        .collect();
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        assert!((order - 6.0).abs() < 0.3, "order {order}: {errors:?}");
    }
}

/// Check 1 with polynomial inputs: the single-axis turn's optimal torque is linear in
/// time, so a polynomial within each step holds it and the discrete optimum is the
/// continuous `12 j²θ²/T³` to rounding (1e-13 relative) at any step count; its torques,
/// given at the Gauss points, replay onto the target.
#[test]
fn polynomial_inputs_hold_the_single_axis_optimum() {
    let (j, theta, t_end): (f64, f64, f64) = (2.0, 1.2, 10.0);
    let continuous = 12.0 * j * j * theta * theta / t_end.powi(3);
    let target = SO3::exp(&(Vector3::new(1.0, 2.0, 2.0) / 3.0 * theta));
    for k in [2, 5, 20] {
        let solution = Slew::new(Inertia::from_principal_moments([j; 3]).unwrap(), t_end)
            .to(target, Vector3::zeros())
            .steps(k)
            .nodes(4)
            .inputs(Inputs::Polynomial)
            .solve()
            .unwrap();
        assert!(
            (solution.cost - continuous).abs() <= 1e-13 * continuous,
            "K = {k}: {}",
            solution.cost
        );
        let mut it = Integrator::new(
            RigidBody::new(Inertia::from_principal_moments([j; 3]).unwrap()),
            StepSettings::new(solution.h, 4).unwrap(),
            SO3::identity(),
            Vector3::zeros(),
        )
        .unwrap();
        assert_eq!(it.quadrature_nodes(), solution.quadrature_nodes);
        for inputs in &solution.inputs_at_points {
            it.set_input_at_points(inputs).unwrap();
            it.step().unwrap();
        }
        let end = it.state();
        assert!(end.configuration.inverse().compose(&target).log().amax() <= 1e-10);
        assert!(end.velocity.amax() <= 1e-10);
        // The multipliers are the optimum's sensitivity to the miss
        // `e = (log(R_Kᵀ R_f), Ω_f − Ω_K)`: with a final rate `ω` about the axis the
        // single-axis optimum is `4 j² (3θ² − 3θωT + ω²T²)/T³`, so along the axis
        // `∂J*/∂θ = 24 j²θ/T³` and `∂J*/∂ω = −12 j²θ/T²` at `ω = 0`.
        let axis = Vector3::new(1.0, 2.0, 2.0) / 3.0;
        let m = &solution.multipliers;
        let along = |i: usize| Vector3::new(m[i], m[i + 1], m[i + 2]).dot(&axis);
        let (d_theta, d_omega) = (
            24.0 * j * j * theta / t_end.powi(3),
            -12.0 * j * j * theta / t_end.powi(2),
        );
        assert!((along(0) - d_theta).abs() <= 1e-9 * d_theta, "{m:?}");
        assert!((along(3) - d_omega).abs() <= 1e-9 * d_omega.abs(), "{m:?}");
    }
}

/// The heavy top of `tests/data/pontryagin_heavy_top.json` (its inertia, mass, gravity,
/// centre of mass and direction), and the reference.
fn heavy_top_reference() -> (Inertia, lgsvi_optimal::Gravity, serde_json::Value) {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/pontryagin_heavy_top.json"
    ))
    .unwrap();
    let reference: serde_json::Value = serde_json::from_str(&text).unwrap();
    let vector = |key: &str| {
        Vector3::from_iterator(
            reference[key]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap()),
        )
    };
    let moments = vector("inertia");
    let inertia = Inertia::from_principal_moments([moments.x, moments.y, moments.z]).unwrap();
    let gravity = lgsvi_optimal::Gravity {
        mass: reference["mass"].as_f64().unwrap(),
        gravity: reference["gravity"].as_f64().unwrap(),
        center_of_mass: vector("com"),
        direction: vector("gravity_direction"),
    };
    (inertia, gravity, reference)
}

/// A heavy top's minimum-energy slew (#57: states on SO(3) for the heavy top too) against
/// an indirect solution through Pontryagin's principle with the gravity torque, computed
/// independently of lgsvi by `tests/data/pontryagin_slew.py` (its derivatives of the
/// Hamiltonian checked against differences; solve_bvp, then single shooting with DOP853 at
/// rtol 1e-13: terminal miss 2.8e-14). The gravity torque is about half the torques the
/// slew needs and holds at the target. With polynomial torques, 8 nodes and 10 steps meet
/// it to 1e-9 relative, as the free body's check 3 does; the torques replay through the
/// heavy top's integrator onto the target.
#[test]
fn a_heavy_tops_slew_meets_pontryagins_optimum() {
    let (inertia, gravity, reference) = heavy_top_reference();
    let cost = reference["cost"].as_f64().unwrap();
    let t_end = reference["t_end"].as_f64().unwrap();
    let target = SO3::exp(&Vector3::from_iterator(
        reference["attitude_final"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap()),
    ));
    let slew = |k: usize, n: usize, inputs: Inputs| {
        Slew::new(inertia, t_end)
            .gravity(gravity)
            .to(target, Vector3::zeros())
            .steps(k)
            .nodes(n)
            .inputs(inputs)
            .solve()
            .unwrap()
    };
    // Measured 6.1e-14 in 14 iterations.
    let solution = slew(10, 8, Inputs::Polynomial);
    assert!(solution.converged);
    let error = (solution.cost - cost).abs() / cost;
    assert!(error <= 1e-9, "{} against {cost}: {error:e}", solution.cost);
    // Order 2(n − 1) = 6 with 4 nodes (measured 1.3e-6, 2.0e-8, 3.1e-10 at K = 5, 10,
    // 20: 6.00 and 6.00).
    let errors: Vec<f64> = [5, 10, 20]
        .iter()
        .map(|&k| (slew(k, 4, Inputs::Polynomial).cost - cost).abs() / cost)
        .collect();
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        assert!((order - 6.0).abs() < 0.3, "order {order}: {errors:?}");
    }
    // The free body's optimum of the same turn differs by far more: gravity is felt.
    let free = Slew::new(inertia, t_end)
        .to(target, Vector3::zeros())
        .steps(10)
        .nodes(8)
        .inputs(Inputs::Polynomial)
        .solve()
        .unwrap();
    assert!(
        (free.cost - cost).abs() > 0.1 * cost,
        "{} against {cost}",
        free.cost
    );
    // Replayed through the heavy top's own integrator, the torques at the points land on
    // the target (to the solver's tolerance on the miss).
    let mut it = heavy_top_integrator(inertia, gravity, solution.h);
    for points in &solution.inputs_at_points {
        it.set_input_at_points(points).unwrap();
        it.step().unwrap();
    }
    let end = it.state();
    assert!((end.configuration.inverse().compose(&target)).log().norm() < 1e-10);
    assert!(end.velocity.norm() < 1e-10, "{}", end.velocity);
    // Torques held over each step: second order in h whatever the integrator's order
    // (measured 2.0e-3, 4.9e-4, 1.2e-4 at K = 20, 40, 80: 2.00 and 2.00).
    let errors: Vec<f64> = [20, 40, 80]
        .iter()
        .map(|&k| (slew(k, 8, Inputs::Constant).cost - cost).abs() / cost)
        .collect();
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        assert!((order - 2.0).abs() < 0.2, "order {order}: {errors:?}");
    }
}

/// A minimum-time slew of a heavy top is refused, naming the cost: its derivative in the
/// step length rests on the free body's time scaling, which gravity breaks.
/// A heavy top's minimum-time slew, checked by a route that does not use the step's
/// derivative in its length: below the least time `T*` no torques within the bounds reach
/// the target, and in any longer time some do. So the fixed-time minimum-energy solver
/// (the same steps, no time variable), started from the minimum-time torques, must find
/// bounded torques that reach the target at `T*(1 + 1e-3)` on the same step count, and
/// find the target out of reach at `T*(1 − 1e-3)` (its subproblem infeasible near the
/// optimum: a local certificate, the one a Newton-type method gives).
#[test]
fn a_heavy_tops_minimum_time_is_the_edge_of_feasibility() {
    let (inertia, gravity, _) = heavy_top_reference();
    let target = SO3::exp(&Vector3::new(1.0, 0.0, 0.0));
    let slew = Slew::new(inertia, 30.0)
        .gravity(gravity)
        .to(target, Vector3::zeros())
        .steps(40)
        .nodes(8)
        .torque_max([0.1; 3]);
    let fastest = slew
        .clone()
        .cost(lgsvi_optimal::Cost::Time)
        .max_iterations(60)
        .solve()
        .unwrap();
    assert!(fastest.converged);
    // The weightless start and the slew under gravity share the iteration budget, and the
    // statistics record both: a residual per iterate and one at each stage's start.
    let record = &fastest.statistics;
    assert!(record.iterations <= 60, "{}", record.iterations);
    assert_eq!(record.kkt_residuals.len(), record.terminal_misses.len());
    assert!(record.kkt_residuals.len() > record.iterations);
    let t_star = fastest.t_end;
    let at = |t: f64| {
        Slew::new(inertia, t)
            .gravity(gravity)
            .to(target, Vector3::zeros())
            .steps(40)
            .nodes(8)
            .torque_max([0.1; 3])
            .warm_start(fastest.inputs.clone())
            .solve()
    };
    let longer = at(t_star * (1.0 + 1e-3)).unwrap();
    assert!(longer.converged);
    match at(t_star * (1.0 - 1e-3)) {
        Err(OptimalError::Infeasible { bounded: true, .. }) => {}
        other => panic!("T* = {t_star}: shorter time {other:?}"),
    }
    // The torques replay through the heavy top's integrator onto the target.
    let mut it = heavy_top_integrator(inertia, gravity, fastest.h);
    for u in &fastest.inputs {
        it.set_input(*u).unwrap();
        it.step().unwrap();
    }
    let miss = it.state().attitude().inverse().compose(&target).log();
    assert!(miss.amax() < 1e-8, "{miss}");
    // Gravity of a negative mass is the heavy top's own refusal, naming the mass.
    let bad = lgsvi_optimal::Gravity {
        mass: -1.0,
        ..gravity
    };
    let error = Slew::new(inertia, 30.0).gravity(bad).solve().unwrap_err();
    assert!(error.to_string().contains("mass"), "{error}");
}

/// The heavy top of `gravity` at rest at the identity, stepped by `h` with 8 nodes (the
/// slews' own steps), to replay a solution's torques.
fn heavy_top_integrator(
    inertia: Inertia,
    gravity: lgsvi_optimal::Gravity,
    h: f64,
) -> Integrator<lgsvi_mechanics::HeavyTop, lgsvi_mechanics::lie::ChartKind, 3> {
    let top = lgsvi_mechanics::HeavyTop::new(
        inertia,
        gravity.mass,
        gravity.gravity,
        gravity.center_of_mass,
        gravity.direction,
    )
    .unwrap();
    Integrator::new(
        top,
        StepSettings::new(h, 8).unwrap(),
        SO3::identity(),
        Vector3::zeros(),
    )
    .unwrap()
}
