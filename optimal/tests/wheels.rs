//! Minimum-energy slews of a spacecraft by its reaction wheels, against references that do
//! not come from the solver.
//!
//! With the wheels along the body axes, axial inertia `I` each, the spacecraft's locked
//! inertia `J`, and everything at rest at the start, the total angular momentum
//! `h = JΩ + 𝐈φ̇` stays zero (the motors are internal torques), so the wheels' momenta
//! `p_i = I(Ω_i + φ̇_i)` are `p = −(J − I)Ω = −J_b Ω` and `ṗ = τ`: the body turns as a rigid
//! body of inertia `J_b = J − I` under the torque `−τ`, exactly, also for the discrete map
//! (which conserves `h` exactly and moves each `p_i` by `τ_i h` per step). For `J_b = jI` a
//! rest-to-rest turn by `θ` about a fixed axis is therefore the spherical body's problem:
//! the discrete optimum of `Σ h |τ_k|²` is the least-norm solution of two linear conditions
//! (`common::discrete_optimum`, shared with `slews.rs`), and with torques polynomial within a step the continuous optimum
//! `J* = 12 j²θ²/T³` (derived in `docs/guide/optimal.md`), since the integrator is exact for
//! this motion.

use lgsvi_mechanics::gyrostat::{BodyWheels, Gyrostat};
use lgsvi_mechanics::lie::{LieGroup, SO3};
use lgsvi_mechanics::{Inertia, Integrator, StepSettings};
use lgsvi_optimal::{Cost, Gravity, Inputs, OptimalError, Slew, Wheels};
use nalgebra::{SVector, Vector3};

mod common;
use common::discrete_optimum;

/// Three wheels along the body axes, axial inertia `i` each, at rest.
fn body_axis_wheels(i: f64) -> Wheels {
    Wheels {
        axes: [Vector3::x(), Vector3::y(), Vector3::z()],
        inertia: [i; 3],
        speeds: Vector3::zeros(),
    }
}

/// `J_b = jI`: the locked inertia is `(j + i) I`.
fn spherical_slew(j: f64, i: f64, theta: f64, t_end: f64, k: usize) -> Slew {
    let axis = Vector3::new(1.0, 2.0, 2.0) / 3.0;
    Slew::new(Inertia::from_principal_moments([j + i; 3]).unwrap(), t_end)
        .wheels(body_axis_wheels(i))
        .to(SO3::exp(&(axis * theta)), Vector3::zeros())
        .steps(k)
        .nodes(6)
}

#[test]
fn wheels_meet_the_discrete_problems_exact_optimum() {
    // The step is exact for this motion (the rates linear in time within a step), so the
    // optimum is the discrete problem's to rounding: 1e-12 relative allows the KKT
    // tolerance squared through the cost and the solves' rounding.
    let (j, i, theta, t_end) = (2.0, 0.25, 1.2, 10.0);
    for k in [5, 20] {
        let solution = spherical_slew(j, i, theta, t_end, k).solve().unwrap();
        assert!(solution.converged);
        let exact = discrete_optimum(j, theta, t_end, k);
        assert!(
            (solution.cost - exact).abs() <= 1e-12 * exact,
            "K = {k}: {} against {exact}",
            solution.cost
        );
        assert_eq!(solution.wheel_speeds.len(), k + 1);
    }
}

#[test]
fn polynomial_motor_torques_meet_the_continuous_optimum() {
    // The optimal torque is linear in time, which every step holds at its Gauss points:
    // J* to rounding at any step count (1e-12 as above).
    let (j, i, theta, t_end): (f64, f64, f64, f64) = (2.0, 0.25, 1.2, 10.0);
    let continuous = 12.0 * j * j * theta * theta / t_end.powi(3);
    for k in [2, 5, 20] {
        let solution = spherical_slew(j, i, theta, t_end, k)
            .inputs(Inputs::Polynomial)
            .solve()
            .unwrap();
        assert!(
            (solution.cost - continuous).abs() <= 1e-12 * continuous,
            "K = {k}: {} against {continuous}",
            solution.cost
        );
    }
}

/// Replays `solution`'s motor torques at the Gauss points through the integrator.
fn replay(
    craft: Gyrostat<3>,
    slew_nodes: usize,
    start: (SO3, Vector3<f64>),
    wheels: Vector3<f64>,
    solution: &lgsvi_optimal::Solution,
) -> Integrator<Gyrostat<3>, lgsvi_mechanics::lie::ChartKind, 6> {
    let g = BodyWheels {
        attitude: start.0,
        wheels: Vector3::zeros(),
    };
    let xi = SVector::<f64, 6>::from_iterator(start.1.iter().chain(wheels.iter()).copied());
    let mut it = Integrator::new(
        craft,
        StepSettings::new(solution.h, slew_nodes).unwrap(),
        g,
        xi,
    )
    .unwrap();
    for step in &solution.inputs_at_points {
        let at: Vec<SVector<f64, 6>> = step
            .iter()
            .map(|u| SVector::<f64, 6>::new(0.0, 0.0, 0.0, u.x, u.y, u.z))
            .collect();
        it.set_input_at_points(&at).unwrap();
        it.step().unwrap();
    }
    it
}

#[test]
fn an_asymmetric_craft_with_biased_skewed_wheels_replays_onto_its_target() {
    // A full locked inertia, three wheels on skewed axes spinning at the start (a momentum
    // bias: the body's motion is gyroscopically coupled), bounded motor torques.
    let locked = Inertia::from_principal_moments([8.0, 10.0, 6.0]).unwrap();
    let axes = [
        Vector3::new(1.0, 0.2, 0.0),
        Vector3::new(0.0, 1.0, 0.3),
        Vector3::new(0.2, 0.0, 1.0),
    ];
    let wheels = Wheels {
        axes,
        inertia: [0.05; 3],
        speeds: Vector3::new(20.0, -10.0, 5.0),
    };
    let start = (SO3::identity(), Vector3::zeros());
    let target = SO3::exp(&Vector3::new(0.6, -0.4, 0.9));
    let solution = Slew::new(locked, 30.0)
        .wheels(wheels)
        .to(target, Vector3::zeros())
        .steps(30)
        .nodes(8)
        .inputs(Inputs::Polynomial)
        .torque_max([0.05; 3])
        .solve()
        .unwrap();
    assert!(solution.converged);
    assert!(solution
        .inputs_at_points
        .iter()
        .flatten()
        .all(|u| u.amax() <= 0.05 * (1.0 + 1e-9)));
    let craft = Gyrostat::new(locked.matrix(), axes, [0.05; 3]).unwrap();
    let it = replay(craft, 8, start, wheels.speeds, &solution);
    let end = it.state();
    // The replay takes the solver's own steps: it lands where the solver's last state is,
    // which meets the target to the KKT tolerance (1e-10 on the scaled miss).
    let miss = end.configuration.attitude.inverse().compose(&target).log();
    assert!(miss.amax() < 1e-9, "attitude miss {miss}");
    assert!(end.velocity.fixed_rows::<3>(0).amax() < 1e-9);
    let last = solution.wheel_speeds.last().unwrap();
    assert!((end.velocity.fixed_rows::<3>(3) - last).amax() < 1e-9);
    // The spatial total angular momentum R h, conserved exactly by the discrete map under
    // any motor torques: to rounding over 30 steps of a momentum of size ~1.
    let h0 = craft_momentum(&craft, &SO3::identity(), &Vector3::zeros(), &wheels.speeds);
    let h1 = craft_momentum(
        &craft,
        &end.configuration.attitude,
        &end.velocity.fixed_rows::<3>(0).into_owned(),
        &end.velocity.fixed_rows::<3>(3).into_owned(),
    );
    assert!((h1 - h0).amax() < 1e-12 * h0.amax().max(1.0), "{h0} → {h1}");
}

/// `R (JΩ + Σ I_i a_i φ̇_i)`, the spatial total angular momentum.
fn craft_momentum(
    craft: &Gyrostat<3>,
    attitude: &SO3,
    omega: &Vector3<f64>,
    speeds: &Vector3<f64>,
) -> Vector3<f64> {
    let mut h = craft.inertia() * omega;
    for ((a, i), w) in craft
        .axes()
        .iter()
        .zip(craft.wheel_inertia())
        .zip(speeds.iter())
    {
        h += a * (i * w);
    }
    attitude.matrix() * h
}

#[test]
fn a_minimum_time_slew_by_wheels_is_the_rigid_bodys() {
    // J − I = jI at rest: the body obeys j Ω̇ = −τ exactly, as a spherical rigid body of
    // inertia j obeys j Ω̇ = u (its gyroscopic term Ω × jΩ vanishes), so the two minimum-time
    // problems are one, solved through two integrators (SO(3) × ℝ³ and SO(3)); their optima
    // agree to the solves' tolerance (KKT 1e-10; the final time is a first-order quantity
    // of the residual, 1e-8 relative leaves room).
    let (j, i) = (2.0, 0.25);
    let target = SO3::exp(&Vector3::new(1.2, -0.5, 0.4));
    let base = |inertia: f64| {
        Slew::new(Inertia::from_principal_moments([inertia; 3]).unwrap(), 10.0)
            .to(target, Vector3::zeros())
            .steps(40)
            .nodes(8)
            .torque_max([0.1; 3])
            .cost(Cost::Time)
    };
    let rigid = base(j).solve().unwrap();
    let wheels = base(j + i).wheels(body_axis_wheels(i)).solve().unwrap();
    assert!(rigid.converged && wheels.converged);
    assert!(
        (wheels.t_end - rigid.t_end).abs() <= 1e-8 * rigid.t_end,
        "wheels {} against the rigid body {}",
        wheels.t_end,
        rigid.t_end
    );
    // The motors' torques are minus the rigid body's.
    let largest = wheels
        .inputs
        .iter()
        .zip(&rigid.inputs)
        .map(|(w, r)| (w + r).amax())
        .fold(0.0, f64::max);
    assert!(largest < 1e-6, "{largest}");
}

/// A least-time slew by spinning wheels, without and with a disturbance torque (which the
/// motors then hold the body against on the way): a fresh integrator given the motors'
/// torques (and the disturbance as the gyrostat's body torque) lands on the target at rest.
#[test]
fn a_biased_minimum_time_slew_by_wheels_replays_onto_its_target() {
    let locked = Inertia::from_principal_moments([8.0, 10.0, 6.0]).unwrap();
    let wheels = Wheels {
        speeds: Vector3::new(20.0, -10.0, 5.0),
        ..body_axis_wheels(0.05)
    };
    let target = SO3::exp(&Vector3::new(0.6, -0.4, 0.9));
    let slew = Slew::new(locked, 30.0)
        .wheels(wheels)
        .to(target, Vector3::zeros())
        .steps(40)
        .nodes(8)
        .torque_max([0.05; 3])
        .cost(Cost::Time);
    let d = Vector3::new(0.004, -0.003, 0.005);
    for disturbance in [Vector3::zeros(), d] {
        let solution = if disturbance == d {
            slew.clone().disturbance(d.into())
        } else {
            slew.clone()
        }
        .solve()
        .unwrap();
        assert!(solution.converged && solution.t_end < 30.0);
        assert!(solution
            .inputs
            .iter()
            .all(|u| u.amax() <= 0.05 * (1.0 + 1e-9)));
        let craft = Gyrostat::new(locked.matrix(), wheels.axes, wheels.inertia).unwrap();
        let g = BodyWheels {
            attitude: SO3::identity(),
            wheels: Vector3::zeros(),
        };
        let xi = SVector::<f64, 6>::new(0.0, 0.0, 0.0, 20.0, -10.0, 5.0);
        let mut it =
            Integrator::new(craft, StepSettings::new(solution.h, 8).unwrap(), g, xi).unwrap();
        for u in &solution.inputs {
            let (b, m) = (disturbance, u);
            it.set_input(SVector::<f64, 6>::new(b.x, b.y, b.z, m.x, m.y, m.z))
                .unwrap();
            it.step().unwrap();
        }
        let end = it.state();
        let miss = end.configuration.attitude.inverse().compose(&target).log();
        assert!(
            miss.amax() < 1e-8,
            "attitude miss {miss}, disturbance {disturbance:?}"
        );
        assert!(end.velocity.fixed_rows::<3>(0).amax() < 1e-8);
    }
}

#[test]
fn wheels_with_gravity_are_refused() {
    let inertia = Inertia::from_principal_moments([8.0, 10.0, 6.0]).unwrap();
    let slew = Slew::new(inertia, 10.0).wheels(body_axis_wheels(0.05));
    let gravity = Gravity {
        mass: 1.0,
        gravity: 9.81,
        center_of_mass: Vector3::z(),
        direction: -Vector3::z(),
    };
    match slew.clone().gravity(gravity).solve() {
        Err(OptimalError::InvalidSetting { name: "wheels", .. }) => {}
        other => panic!("{other:?}"),
    }
    // A wheel whose axial inertia is not inside J's: the gyrostat's own refusal.
    let heavy = Wheels {
        inertia: [9.0; 3],
        ..body_axis_wheels(0.05)
    };
    let err = Slew::new(inertia, 10.0).wheels(heavy).solve().unwrap_err();
    assert!(err.to_string().contains("positive definite"), "{err}");
    let nan = Wheels {
        speeds: Vector3::new(f64::NAN, 0.0, 0.0),
        ..body_axis_wheels(0.05)
    };
    match Slew::new(inertia, 10.0).wheels(nan).solve() {
        Err(OptimalError::InvalidSetting {
            name: "wheel speeds",
            ..
        }) => {}
        other => panic!("{other:?}"),
    }
}

/// Tracking and terminal costs with wheels go through the gyrostat's state sensitivities
/// (its 12-dimensional chain read in the attitude and rate rows). Tracking the optimum's own
/// states leaves the optimum where it is (the tracking residuals vanish there, and their
/// Gauss–Newton term does not move it), and a soft target's miss falls as `1/q` with its
/// weight (the quadratic penalty's: the miss is the multiplier over `2q`).
#[test]
fn wheels_track_and_take_soft_targets() {
    let locked = Inertia::from_principal_moments([8.0, 10.0, 6.0]).unwrap();
    let wheels = Wheels {
        speeds: Vector3::new(20.0, -10.0, 5.0),
        ..body_axis_wheels(0.05)
    };
    let target = SO3::exp(&Vector3::new(0.6, -0.4, 0.9));
    let slew = Slew::new(locked, 30.0)
        .wheels(wheels)
        .to(target, Vector3::zeros())
        .steps(20)
        .nodes(8);
    let exact = slew.clone().solve().unwrap();
    let reference: Vec<lgsvi_optimal::Target> = exact.states[1..]
        .iter()
        .map(|s| (s.configuration, s.velocity))
        .collect();
    let tracked = slew.clone().track(reference, [1.0, 1.0]).solve().unwrap();
    let moved = tracked
        .inputs
        .iter()
        .zip(&exact.inputs)
        .map(|(a, b)| (a - b).amax())
        .fold(0.0, f64::max);
    assert!(moved < 1e-9, "{moved}");
    let miss = |q: f64| {
        let soft = slew.clone().terminal_cost([q, q]).solve().unwrap();
        let last = soft.states.last().unwrap();
        let e = last.configuration.inverse().compose(&target).log();
        e.amax().max(last.velocity.amax())
    };
    let (loose, tight) = (miss(1e2), miss(1e4));
    // 1/q: a hundredfold weight, a hundredfold smaller miss (within 20%: the penalty's
    // miss is 1/q only to first order).
    assert!(
        (loose / tight - 100.0).abs() < 20.0,
        "{loose:e} → {tight:e}"
    );
}

#[test]
fn wheel_axes_that_do_not_span_space_are_refused() {
    let inertia = Inertia::from_principal_moments([8.0, 10.0, 6.0]).unwrap();
    let flat = Wheels {
        axes: [Vector3::x(), Vector3::new(2.0, 0.0, 0.0), Vector3::z()],
        ..body_axis_wheels(0.05)
    };
    match Slew::new(inertia, 10.0).wheels(flat).solve() {
        Err(OptimalError::InvalidSetting {
            name: "wheel axes",
            reason,
            ..
        }) => {
            assert!(reason.contains("span"), "{reason}")
        }
        other => panic!("{other:?}"),
    }
    // A weightless "gravity" beside wheels is no gravity.
    let none = Gravity {
        mass: 1.0,
        gravity: 0.0,
        center_of_mass: Vector3::z(),
        direction: Vector3::z(),
    };
    let solution = Slew::new(inertia, 10.0)
        .wheels(body_axis_wheels(0.05))
        .gravity(none)
        .to(SO3::exp(&Vector3::new(0.0, 0.0, 0.3)), Vector3::zeros())
        .solve()
        .unwrap();
    assert!(solution.converged);
}
