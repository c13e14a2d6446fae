//! A quadrotor on SE(3) flying to a waypoint under a geometric controller.
//!
//! The vehicle (mass 0.75 kg, inertia about 5e-3 kg·m²) is a rigid body on SE(3) in
//! uniform gravity. Its inputs are the collective thrust `T` along the body z axis and a
//! body torque `τ`, set every 10 ms from the state (zero-order hold): a position PD loop
//! gives the wanted force `F = m(−k_x e_x − k_v e_v + g e₃)`, the thrust is `F·(R e₃)` and
//! the wanted attitude points the body z axis along `F` with the body x axis towards world
//! x; an attitude PD loop gives `τ = −k_R e_R − k_Ω Ω + Ω × JΩ` (Lee, Leok and McClamroch,
//! 2010). The control input is the body wrench `(τ, (0, 0, T))`.
//!
//! Demonstrates: SE(3) with a six-dimensional control input, `BodyInField` with a
//! potential of your own, and a closed loop that reaches the waypoint.
//!
//! Run: `cargo run --release -p lgsvi-mechanics --example quadrotor`

use lgsvi_mechanics::lie::so3::vee;
use lgsvi_mechanics::lie::SE3;
use lgsvi_mechanics::{BodyInField, FieldPotential, Inertia, Integrator, StepSettings};
use nalgebra::{Matrix3, RealField, SVector, Vector3};

const MASS: f64 = 0.75;
const G: f64 = 9.81;

/// Uniform gravity: `V = m g x_z`.
struct Gravity;
impl FieldPotential for Gravity {
    fn potential<T: RealField + Copy>(&self, _t: f64, _r: &Matrix3<T>, x: &Vector3<T>) -> T {
        x.z * nalgebra::convert::<f64, T>(MASS * G)
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let j = Matrix3::from_diagonal(&Vector3::new(4.9e-3, 4.9e-3, 8.8e-3));
    let vehicle = BodyInField::new(Inertia::from_tensor(j)?, MASS, Gravity)?;
    let waypoint = Vector3::new(1.0, -0.5, 2.0);
    let (k_x, k_v, k_r, k_w) = (4.0, 3.0, 0.5, 0.08);
    let h = 0.01;
    let mut integrator = Integrator::new(
        vehicle,
        StepSettings::new(h, 4)?,
        SE3::identity(),
        SVector::<f64, 6>::zeros(),
    )?;
    println!(
        "quadrotor: from rest at the origin to the waypoint ({}, {}, {}) m",
        waypoint.x, waypoint.y, waypoint.z
    );
    println!(
        "{:>5} {:>28} {:>10} {:>10}",
        "t (s)", "position (m)", "thrust (N)", "tilt (°)"
    );
    let mut lowest = 0.0f64;
    for k in 0..=800 {
        let s = integrator.state();
        let r = s.attitude().matrix();
        let (x, v, w) = (s.position(), s.linear_velocity(), s.angular_velocity());
        let force = (-(x - waypoint) * k_x - v * k_v + Vector3::z() * G) * MASS;
        let thrust = force.dot(&r.column(2));
        // Wanted attitude: b₃ along the force, b₁ as close to world x as it allows.
        let b3 = force.normalize();
        let b2 = b3.cross(&Vector3::x()).normalize();
        let wanted = Matrix3::from_columns(&[b2.cross(&b3), b2, b3]);
        let e_r = vee(&(wanted.transpose() * r - r.transpose() * wanted)) * 0.5;
        let torque = -e_r * k_r - w * k_w + w.cross(&(j * w));
        lowest = lowest.min(x.z);
        if k % 100 == 0 {
            let tilt = r[(2, 2)].clamp(-1.0, 1.0).acos().to_degrees();
            println!(
                "{:>5.2} [{:>7.4}, {:>7.4}, {:>7.4}] {:>10.4} {:>10.3}",
                s.time, x.x, x.y, x.z, thrust, tilt
            );
        }
        if k < 800 {
            integrator.set_input(SVector::<f64, 6>::new(
                torque.x, torque.y, torque.z, 0.0, 0.0, thrust,
            ))?;
            integrator.step()?;
        }
    }
    let s = integrator.state();
    let miss = (s.position() - waypoint).norm();
    println!(
        "after {:.1} s: {:.2e} m from the waypoint, speed {:.2e} m/s, lowest altitude {lowest:.3} m, ‖RᵀR − I‖ = {:.1e}",
        s.time,
        miss,
        s.linear_velocity().norm(),
        s.attitude().orthogonality_error()
    );
    assert!(miss < 5e-3, "missed the waypoint by {miss} m");
    assert!(lowest > -0.05, "dipped to {lowest} m");
    assert!(s.attitude().orthogonality_error() < 1e-13);
    Ok(())
}
