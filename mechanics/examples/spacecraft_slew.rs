//! A spacecraft attitude slew under a PD controller, driven from a control loop.
//!
//! The spacecraft (a full, non-diagonal inertia tensor) starts at rest and turns by 90°
//! about a tilted axis to a target attitude `R_d`. Every 0.1 s the controller reads the
//! state and sets the body torque for the next step (zero-order hold):
//! `τ = −k_R e_R − k_Ω Ω`, with the geometric attitude error
//! `e_R = ½ (R_dᵀR − RᵀR_d)^∨` of Lee, Leok and McClamroch. The integrator is built once;
//! the step is the discrete Lagrange–d'Alembert step with the torque as its force.
//!
//! Demonstrates: `Integrator::set_input`, `Integrator::state`, full inertia tensors, and
//! that without torque the same integrator conserves energy and angular momentum.
//!
//! Run: `cargo run --release -p lgsvi-mechanics --example spacecraft_slew`

use lgsvi_mechanics::lie::so3::vee;
use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::Stepper;
use lgsvi_mechanics::{Inertia, Integrator, RigidBody, StepSettings};
use nalgebra::{Matrix3, Unit, Vector3};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let inertia = Inertia::from_tensor(Matrix3::new(
        120.0, 4.0, -2.5, //
        4.0, 95.0, 3.0, //
        -2.5, 3.0, 150.0,
    ))?;
    let body = RigidBody::new(inertia);
    let axis = Unit::new_normalize(Vector3::new(1.0, 2.0, -0.5));
    let target = SO3::from_axis_angle(&axis, std::f64::consts::FRAC_PI_2);
    let (k_r, k_w) = (40.0, 120.0); // N·m/rad, N·m·s/rad
    let h = 0.1;
    let mut integrator = Integrator::new(
        body,
        StepSettings::new(h, 6)?,
        SO3::identity(),
        Vector3::zeros(),
    )?;
    let error_of = |r: &SO3| {
        let m = target.matrix().transpose() * r.matrix() - r.matrix().transpose() * target.matrix();
        vee(&m) * 0.5
    };
    println!(
        "spacecraft slew: 90° about ({:.3}, {:.3}, {:.3}), PD gains k_R = {k_r}, k_Ω = {k_w}",
        axis.x, axis.y, axis.z
    );
    println!(
        "{:>6} {:>14} {:>14} {:>12}",
        "t (s)", "|e_R|", "|Ω| (rad/s)", "|τ| (N·m)"
    );
    let mut peak_torque = 0.0f64;
    for k in 0..=1200 {
        let state = integrator.state();
        let e_r = error_of(state.attitude());
        let torque = -e_r * k_r - state.velocity * k_w;
        peak_torque = peak_torque.max(torque.norm());
        if k % 100 == 0 {
            println!(
                "{:>6.1} {:>14.3e} {:>14.3e} {:>12.3e}",
                state.time,
                e_r.norm(),
                state.velocity.norm(),
                torque.norm()
            );
        }
        if k < 1200 {
            integrator.set_input(torque)?;
            integrator.step()?;
        }
    }
    let state = *integrator.state();
    let final_error =
        SO3::from_matrix_unchecked(target.matrix().transpose() * state.attitude().matrix()).angle();
    println!("after {} s: attitude error {final_error:.2e} rad, |Ω| {:.2e} rad/s, peak torque {peak_torque:.1} N·m", state.time, state.velocity.norm());
    assert!(
        final_error < 1e-4,
        "the slew did not converge: {final_error:e} rad"
    );
    assert!(state.velocity.norm() < 1e-4);

    // The same integrator, torque off, spinning freely: energy and π = RJΩ conserved.
    integrator.set_input(Vector3::zeros())?;
    integrator.reset(
        state.time,
        *state.attitude(),
        Vector3::new(0.02, -0.05, 0.01),
    )?;
    let start = *integrator.state();
    integrator.run(10_000, 10_000)?;
    let end = integrator.state();
    let energy_error = (end.energy(&body) - start.energy(&body)).abs() / start.energy(&body);
    let momentum_error = (end.spatial_momentum() - start.spatial_momentum()).norm()
        / start.spatial_momentum().norm();
    println!("free spin, 10⁴ steps: relative energy error {energy_error:.1e}, angular momentum {momentum_error:.1e}");
    assert!(energy_error < 1e-9 && momentum_error < 1e-13);
    Ok(())
}
