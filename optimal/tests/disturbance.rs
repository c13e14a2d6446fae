//! Slews under a known constant disturbance torque `d` (body frame), against references
//! that do not come from the solver.
//!
//! A spherical body `J = jI` turning by `θ` about a fixed axis `a`, rest to rest, with `d`
//! along `a`: the body obeys `j Ω̇ = v` with `v = u + d`, and the cost is
//! `Σ h |v_k − d|² = Σ h |v_k|² − 2 d·Σ h v_k + |d|² T`. Along the turn the discrete map
//! moves the momentum's `a` component by exactly `h (a·v_k)` a step (the step's rotations
//! are about `a`, which they leave fixed), so on every torque sequence that reaches the
//! target at rest, to first order about the turn, `a·Σ h v_k = j a·(Ω_K − Ω_0) = 0`: the
//! linear term neither changes the cost at the optimum nor moves it. The optimum is the
//! undisturbed one in `v`, its torques `u_k = v_k − d`, its cost the undisturbed discrete
//! optimum (`common::discrete_optimum`) plus `|d|² T`. With reaction wheels (`J_b = jI`
//! the body with its wheels free) the body obeys `j Ω̇ = d − τ`, the same problem in
//! `v = d − τ`: the cost as above, and the spacecraft's total angular momentum grows by
//! `d T`, which at rest is all in the wheels: their momenta end at `I(Ω + φ̇) = |d| T a`.
//! Off the turn's axis there is no closed form: `slews.rs` and `wheels.rs` replay slews
//! under a disturbance onto their targets.

use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::Inertia;
use lgsvi_optimal::{OptimalError, Slew, Wheels};
use nalgebra::Vector3;

mod common;
use common::discrete_optimum;

/// The turn's axis.
fn axis() -> Vector3<f64> {
    Vector3::new(1.0, 2.0, 2.0) / 3.0
}

/// Three wheels along the body axes, axial inertia `i` each, at rest.
fn body_axis_wheels(i: f64) -> Wheels {
    Wheels {
        axes: [Vector3::x(), Vector3::y(), Vector3::z()],
        inertia: [i; 3],
        speeds: Vector3::zeros(),
    }
}

#[test]
fn a_disturbance_along_the_turn_shifts_the_optimum_by_itself() {
    let (j, theta, t_end) = (2.0, 1.2, 10.0);
    let d = 0.03 * axis();
    for k in [5, 20] {
        let slew = Slew::new(Inertia::from_principal_moments([j; 3]).unwrap(), t_end)
            .to(SO3::exp(&(axis() * theta)), Vector3::zeros())
            .steps(k)
            .nodes(6);
        let free = slew.clone().solve().unwrap();
        let disturbed = slew.disturbance(d.into()).solve().unwrap();
        // The integrator is exact for this motion, so the optimum is the discrete
        // problem's to rounding: 1e-12 relative allows the KKT tolerance (1e-10 on the
        // scaled residual) squared through the cost, and the solves' rounding.
        let exact = discrete_optimum(j, theta, t_end, k) + d.norm_squared() * t_end;
        assert!(
            (disturbed.cost - exact).abs() <= 1e-12 * exact,
            "K = {k}: {} against {exact}",
            disturbed.cost
        );
        // The torques are the undisturbed ones less d: each solve's torques are within
        // its KKT tolerance of the optimum, 1e-10 relative to the torques (~0.01).
        let shift = free
            .inputs
            .iter()
            .zip(&disturbed.inputs)
            .map(|(f, u)| (f - (u + d)).amax())
            .fold(0.0, f64::max);
        assert!(shift <= 1e-11, "K = {k}: {shift:e}");
    }
}

#[test]
fn wheels_take_up_a_disturbances_momentum() {
    let (j, i, theta, t_end, k) = (2.0, 0.25, 1.2, 10.0, 20);
    let d = 0.03 * axis();
    let solution = Slew::new(Inertia::from_principal_moments([j + i; 3]).unwrap(), t_end)
        .wheels(body_axis_wheels(i))
        .to(SO3::exp(&(axis() * theta)), Vector3::zeros())
        .steps(k)
        .nodes(6)
        .disturbance(d.into())
        .solve()
        .unwrap();
    let exact = discrete_optimum(j, theta, t_end, k) + d.norm_squared() * t_end;
    assert!(
        (solution.cost - exact).abs() <= 1e-12 * exact,
        "{} against {exact}",
        solution.cost
    );
    // The total angular momentum (body frame, the states' momentum with wheels) grows by
    // exactly h d a step along the turn (as above): d T to rounding, 1e-12 relative. At
    // rest at the end the wheels hold it: their momenta I(Ω + φ̇) are the total less the
    // body's j Ω_K, whose rates miss rest by the solve's tolerance (1e-10 scaled; 1e-9
    // leaves room).
    let last = solution.states.last().unwrap();
    let expected = d * t_end;
    assert!(
        (last.momentum - expected).amax() <= 1e-12 * expected.amax(),
        "{:?} against {expected:?}",
        last.momentum
    );
    let speeds = solution.wheel_speeds.last().unwrap();
    let momenta = i * (last.velocity + speeds);
    assert!(
        (momenta - expected).amax() <= 1e-9 * expected.amax(),
        "{momenta:?} against {expected:?}"
    );
}

#[test]
fn a_disturbance_that_is_not_finite_is_named() {
    let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.0]).unwrap();
    let error = Slew::new(inertia, 10.0)
        .disturbance([0.0, f64::NAN, 0.0])
        .solve()
        .unwrap_err();
    assert!(
        matches!(
            error,
            OptimalError::InvalidSetting {
                name: "disturbance",
                ..
            }
        ),
        "{error}"
    );
    assert!(error.to_string().contains("disturbance"), "{error}");
}
