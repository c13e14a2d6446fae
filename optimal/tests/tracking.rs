//! Tracking and terminal costs: a spherical body's single-axis turn, where the discrete
//! problem is a linear least-squares one solved here independently; the stationarity of an
//! asymmetric body's solution under the true cost (differences of whole runs); the soft
//! target's limit; bad settings.

use lgsvi_mechanics::lie::{LieGroup, SO3};
use lgsvi_mechanics::{Inertia, Integrator, RigidBody, StepSettings};
use lgsvi_optimal::{Cost, OptimalError, Slew};
use nalgebra::{DMatrix, DVector, Vector3};

/// A spherical body `J = jI` from rest, torques along a fixed axis `a`: `φ_k` and `ω_k`
/// are linear in the torques (`φ_K = Σ_i (K − 1 − i + ½) h² u_i / j`, `ω_K = Σ_i h u_i / j`,
/// the step exact for this motion), so tracking a ramp `φ_ref(t) = θ t/T` with a soft
/// target `(θ, 0)` is the linear least squares
/// `Σ h u_i² + Σ_k h (q_θ (φ_k − φ_ref,k)² + q_ω (ω_k − ω_ref)²) + q_f (φ_K − θ)² + q_f ω_K²`,
/// solved here by its normal equations. The solver's torques lie along `a` and match them
/// to 1e-10 relative (the KKT tolerance; the problem is quadratic, so one Gauss–Newton
/// step solves it to the QP's accuracy). At 12 steps, and at 600, where the subproblem's
/// banded form (the states among its variables) is what keeps a solve linear in the step
/// count: the condensed Hessian `2GᵀG` would be 1800 × 1800 dense, formed from a
/// `3606 × 1800` Jacobian.
#[test]
fn single_axis_tracking_is_the_linear_least_squares() {
    for k_steps in [12usize, 600] {
        single_axis_tracking(k_steps);
    }
}

fn single_axis_tracking(k_steps: usize) {
    let (j, theta, t_end) = (2.0, 1.2, 10.0);
    let (q_theta, q_omega, q_f) = (3.0, 0.5, 40.0);
    let h = t_end / k_steps as f64;
    let axis = Vector3::new(1.0, 2.0, 2.0) / 3.0;
    let rate = theta / t_end;
    let reference: Vec<(SO3, Vector3<f64>)> = (1..=k_steps)
        .map(|k| (SO3::exp(&(axis * rate * k as f64 * h)), axis * rate))
        .collect();
    let solution = Slew::new(Inertia::from_principal_moments([j; 3]).unwrap(), t_end)
        .to(SO3::exp(&(axis * theta)), Vector3::zeros())
        .steps(k_steps)
        .nodes(6)
        .track(reference, [q_theta, q_omega])
        .terminal_cost([q_f, q_f])
        .solve()
        .unwrap();
    // Rows: each step's φ and ω, then the terminal φ and ω; least squares with the
    // torques' own weight h.
    let phi_row = |k: usize, i: usize| {
        if i < k {
            ((k - 1 - i) as f64 + 0.5) * h * h / j
        } else {
            0.0
        }
    };
    let omega_row = |k: usize, i: usize| if i < k { h / j } else { 0.0 };
    let rows = 2 * k_steps + 2 + k_steps;
    let mut a = DMatrix::<f64>::zeros(rows, k_steps);
    let mut y = DVector::<f64>::zeros(rows);
    for k in 1..=k_steps {
        let (wt, ww) = ((h * q_theta).sqrt(), (h * q_omega).sqrt());
        for i in 0..k_steps {
            a[(2 * (k - 1), i)] = wt * phi_row(k, i);
            a[(2 * (k - 1) + 1, i)] = ww * omega_row(k, i);
        }
        y[2 * (k - 1)] = wt * rate * k as f64 * h;
        y[2 * (k - 1) + 1] = ww * rate;
    }
    for i in 0..k_steps {
        a[(2 * k_steps, i)] = q_f.sqrt() * phi_row(k_steps, i);
        a[(2 * k_steps + 1, i)] = q_f.sqrt() * omega_row(k_steps, i);
        a[(2 * k_steps + 2 + i, i)] = h.sqrt();
    }
    y[2 * k_steps] = q_f.sqrt() * theta;
    // By QR, not the normal equations, whose condition number (the square of `a`'s)
    // would cost digits at 600 steps.
    let qr = a.clone().qr();
    let u = qr
        .r()
        .solve_upper_triangular(&(qr.q().transpose() * &y))
        .unwrap();
    let cost = (&a * &u - &y).norm_squared();
    for (i, torque) in solution.inputs.iter().enumerate() {
        assert!(
            (torque - axis * u[i]).amax() <= 1e-10 * u.amax(),
            "step {i}"
        );
    }
    assert!(
        (solution.cost - cost).abs() <= 1e-10 * cost,
        "{} against {cost}",
        solution.cost
    );
}

/// The true cost of torques `u` on the asymmetric body, from a fresh run of the integrator:
/// `Σ h |u_k|² + Σ_k h (q_θ |log(R_refᵀ R_k)|² + q_ω |Ω_k − Ω_ref|²) + q_f (|log(R_fᵀ R_K)|² + |Ω_K|²)`.
fn true_cost(
    inertia: Inertia,
    h: f64,
    u: &[Vector3<f64>],
    reference: &[(SO3, Vector3<f64>)],
    target: SO3,
    q: [f64; 3],
) -> f64 {
    let mut it = Integrator::new(
        RigidBody::new(inertia),
        StepSettings::new(h, 8).unwrap(),
        SO3::identity(),
        Vector3::zeros(),
    )
    .unwrap();
    let mut total = 0.0;
    for (k, torque) in u.iter().enumerate() {
        it.set_input(*torque).unwrap();
        it.step().unwrap();
        let s = it.state();
        let (r, w) = reference[k];
        total += h * torque.norm_squared()
            + h * (q[0] * r.inverse().compose(&s.configuration).log().norm_squared()
                + q[1] * (s.velocity - w).norm_squared());
    }
    let s = it.state();
    total
        + q[2]
            * (target
                .inverse()
                .compose(&s.configuration)
                .log()
                .norm_squared()
                + s.velocity.norm_squared())
}

/// At the solution of a problem with nonzero residuals (an oblique reference the body
/// cannot follow, a soft target), the true cost's directional derivatives vanish: central
/// differences of whole runs along four directions are below 1e-7 of the gradient's
/// scale (measured 1e-11 to 9e-10: the differences' rounding). The cost's gradient does
/// not see the log's `J_r(e)⁻¹` (`J_r(e)⁻ᵀ e = e`); the factor shapes the Gauss–Newton
/// Hessian, so this checks the states' sensitivities and the assembly of the cost.
#[test]
fn a_tracking_solution_is_stationary_for_the_true_cost() {
    let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap();
    let (t_end, k_steps) = (20.0, 16usize);
    let h = t_end / k_steps as f64;
    let target = SO3::exp(&Vector3::new(1.5, 0.4, -0.9));
    let reference: Vec<(SO3, Vector3<f64>)> = (1..=k_steps)
        .map(|k| {
            let s = k as f64 / k_steps as f64;
            (
                SO3::exp(&(Vector3::new(0.2, 1.3, 0.4) * s)),
                Vector3::new(0.0, 0.05, 0.0),
            )
        })
        .collect();
    let q = [0.4, 2.0, 5.0];
    let solution = Slew::new(inertia, t_end)
        .to(target, Vector3::zeros())
        .steps(k_steps)
        .nodes(8)
        .track(reference.clone(), [q[0], q[1]])
        .terminal_cost([q[2], q[2]])
        .solve()
        .unwrap();
    let base = true_cost(inertia, h, &solution.inputs, &reference, target, q);
    assert!((base - solution.cost).abs() <= 1e-12 * base);
    let eps = 1e-5;
    for d in 0..4 {
        let direction: Vec<Vector3<f64>> = (0..k_steps)
            .map(|k| {
                let x = (k * 7 + d * 3) as f64;
                Vector3::new((x * 0.7).sin(), (x * 1.3).cos(), (x * 0.3 + d as f64).sin())
            })
            .collect();
        let moved = |sign: f64| -> Vec<Vector3<f64>> {
            solution
                .inputs
                .iter()
                .zip(&direction)
                .map(|(u, v)| u + v * (sign * eps))
                .collect()
        };
        let slope = (true_cost(inertia, h, &moved(1.0), &reference, target, q)
            - true_cost(inertia, h, &moved(-1.0), &reference, target, q))
            / (2.0 * eps);
        // The cost's scale per unit torque: 2 h |u| summed, about 0.05 here.
        let scale: f64 = solution.inputs.iter().map(|u| 2.0 * h * u.norm()).sum();
        assert!(
            slope.abs() <= 1e-7 * scale.max(1e-3),
            "direction {d}: slope {slope:e}"
        );
    }
}

/// A soft target with weights growing tends to the exact one: the terminal miss falls as
/// the weights rise (about as 1/q).
#[test]
fn a_soft_target_tends_to_the_exact_one() {
    let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap();
    let target = SO3::exp(&Vector3::new(1.5, 0.4, -0.9));
    let exact = Slew::new(inertia, 30.0)
        .to(target, Vector3::zeros())
        .steps(20)
        .solve()
        .unwrap();
    let mut previous = f64::INFINITY;
    for q in [1.0, 100.0, 10_000.0] {
        let soft = Slew::new(inertia, 30.0)
            .to(target, Vector3::zeros())
            .steps(20)
            .terminal_cost([q, q])
            .solve()
            .unwrap();
        let end = soft.states.last().unwrap();
        let miss = target.inverse().compose(&end.configuration).log().norm();
        assert!(
            miss < previous && soft.cost < exact.cost,
            "q = {q}: miss {miss}"
        );
        previous = miss;
    }
    assert!(previous < 1e-3);
}

#[test]
fn tracking_settings_are_checked() {
    let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5]).unwrap();
    let target = SO3::exp(&Vector3::new(0.0, 0.0, 1.0));
    let error = Slew::new(inertia, 10.0)
        .to(target, Vector3::zeros())
        .steps(10)
        .track(vec![(SO3::identity(), Vector3::zeros()); 3], [1.0, 1.0])
        .solve()
        .unwrap_err();
    assert!(
        matches!(error, OptimalError::InvalidSetting { name: "track", .. }),
        "{error}"
    );
    let error = Slew::new(inertia, 10.0)
        .to(target, Vector3::zeros())
        .terminal_cost([-1.0, 1.0])
        .solve()
        .unwrap_err();
    assert!(matches!(
        error,
        OptimalError::InvalidSetting {
            name: "terminal_cost",
            ..
        }
    ));
    let error = Slew::new(inertia, 10.0)
        .to(target, Vector3::zeros())
        .torque_max([1.0; 3])
        .terminal_cost([1.0, 1.0])
        .cost(Cost::Time)
        .solve()
        .unwrap_err();
    assert!(matches!(
        error,
        OptimalError::InvalidSetting { name: "cost", .. }
    ));
}
