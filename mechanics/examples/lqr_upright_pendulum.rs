//! The 3D pendulum held upright by discrete LQR gains computed from the exact
//! linearisation of one step.
//!
//! A rigid pendulum on a pivot (centre of mass 1 m above it, gravity 9.81 pulling down)
//! is unstable upright. `Integrator::linearize` gives the exact `A = ∂x₊/∂x`,
//! `B = ∂x₊/∂u` of the step at the upright equilibrium in the coordinates
//! `x = (θ, ω)`, `R = exp(θ̂)`, `Ω = ω`, with `u` a body torque held over the step;
//! `control::lqr` solves the discrete algebraic Riccati equation for the gain `K`; a
//! `control::Regulator` then sets `u = −K x` every step (zero-order hold, h = 0.05 s),
//! the error state taken by SO(3)'s logarithm. Started 20° from upright, at rest.
//!
//! Demonstrates: `Integrator::linearize`, `StepLinearization`, `control::lqr`,
//! `control::Regulator`; asserts that the closed loop of the linearisation is stable
//! and that the nonlinear pendulum returns upright to 1e-8.
//!
//! Run: `cargo run --release -p lgsvi-mechanics --example lqr_upright_pendulum`

use lgsvi_mechanics::control::{error_state, lqr, Regulator};
use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::linearization::Coordinates;
use lgsvi_mechanics::{HeavyTop, Inertia, Integrator, StepSettings};
use nalgebra::{DMatrix, DVector, Vector3};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let inertia = Inertia::from_principal_moments([1.0, 1.2, 0.8])?;
    // ℓ = ½ΩᵀJΩ + m g ⟨d, Rρ⟩ with gravity pulling along d = −e₃ and ρ = e₃: R = I is
    // the upright (unstable) equilibrium.
    let top = HeavyTop::new(inertia, 1.0, 9.81, Vector3::z(), -Vector3::z())?;
    let h = 0.05;
    let mut integrator = Integrator::new(
        top,
        StepSettings::new(h, 6)?,
        SO3::identity(),
        Vector3::zeros(),
    )?;
    let upright = *integrator.state();

    let step = integrator.linearize()?;
    let (a, b) = (step.a(Coordinates::Velocity), step.b(Coordinates::Velocity));
    let q = DMatrix::from_diagonal(&DVector::from_vec(vec![10.0, 10.0, 10.0, 1.0, 1.0, 1.0]));
    let r = DMatrix::identity(3, 3) * 0.1;
    let design = lqr(a, b, &q, &r)?;
    let open = spectral_radius(a);
    let closed = spectral_radius(&(a - b * &design.gain));
    println!(
        "upright, h = {h} s: spectral radius of A {open:.4} (unstable), of A − BK {closed:.4}"
    );
    assert!(open > 1.0 && closed < 1.0);
    println!("K =\n{:.3}", design.gain);

    let regulator = Regulator::new(upright, Vector3::zeros(), design.gain)?;
    let tilt = 20f64.to_radians();
    integrator.reset(
        0.0,
        SO3::exp(&Vector3::new(tilt, 0.0, 0.0)),
        Vector3::zeros(),
    )?;
    println!("    t [s]   tilt [deg]    |x|        |u| [N·m]");
    let mut largest_torque = 0.0f64;
    for k in 0..=400 {
        let state = *integrator.state();
        let u = regulator.input(&state);
        largest_torque = largest_torque.max(u.norm());
        if k % 40 == 0 {
            // The tilt: the angle between the body's axis Rρ and the upward vertical
            // (by atan2, exact for small angles where acos of a cosine is not).
            let axis = state.attitude().matrix() * Vector3::z();
            let degrees = axis.xy().norm().atan2(axis.z).to_degrees();
            let error = error_state(&state, &upright).norm();
            println!(
                "{:9.2} {degrees:12.3e} {error:10.3e} {:12.3e}",
                state.time,
                u.norm()
            );
        }
        if k == 400 {
            break;
        }
        integrator.set_input(u)?;
        integrator.step()?;
    }
    let error = error_state(integrator.state(), &upright).norm();
    println!("largest torque {largest_torque:.2} N·m; error after 20 s {error:.1e}");
    assert!(
        error < 1e-8,
        "the pendulum did not return upright: {error:e}"
    );
    Ok(())
}

fn spectral_radius(m: &DMatrix<f64>) -> f64 {
    m.complex_eigenvalues()
        .iter()
        .fold(0.0f64, |largest, e| largest.max(e.norm()))
}
