//! A rigid body orbiting a planet, librating in pitch under the gravity-gradient torque.
//!
//! The body (`J = diag(1, 2, 2.5)` kg·m² about its axes: radial, along-track, orbit normal)
//! is on a circular orbit of radius `r` about a point mass (`μ = GM`), turning once per
//! orbit so that it keeps facing the planet, with a small pitch offset. MacCullagh's
//! potential couples attitude and orbit on SE(3); the linearised pitch motion is a
//! pendulum of frequency `ω_p = n √(3 (J_y − J_x) / J_z)` (`n = √(μ/r³)` the mean motion).
//!
//! Demonstrates: `OrbitingBody` on SE(3), the libration period against that formula, and
//! conservation of energy and total angular momentum `m x × ẋ + RJΩ`.
//!
//! Run: `cargo run --release -p lgsvi-mechanics --example orbit_libration`

use lgsvi_mechanics::lie::{SE3, SO3};
use lgsvi_mechanics::{Inertia, Integrator, OrbitingBody, StepSettings};
use nalgebra::{SVector, Vector3};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (gm, mass, radius) = (1.0f64, 1.0, 3.0f64);
    let (jx, jy, jz) = (1.0e-3, 2.0e-3, 2.5e-3);
    let body = OrbitingBody::new(Inertia::from_principal_moments([jx, jy, jz])?, mass, gm)?;
    let mean_motion = (gm / radius.powi(3)).sqrt();
    let pitch0 = 0.05; // rad
                       // x along the radius, the orbit in the x–y plane; the body turns at the orbit rate.
    let start = SE3::new(SO3::about_z(pitch0), Vector3::new(radius, 0.0, 0.0));
    let speed = mean_motion * radius;
    let body_velocity = SO3::about_z(pitch0).matrix().transpose() * Vector3::new(0.0, speed, 0.0);
    let xi = SVector::<f64, 6>::new(
        0.0,
        0.0,
        mean_motion,
        body_velocity.x,
        body_velocity.y,
        body_velocity.z,
    );
    let h = 0.5;
    let mut integrator = Integrator::new(body, StepSettings::new(h, 8)?, start, xi)?;
    let (e0, l0) = (
        integrator.state().energy(&body),
        integrator.state().spatial_momentum(),
    );
    let orbit_period = std::f64::consts::TAU / mean_motion;
    let theory = std::f64::consts::TAU / (mean_motion * (3.0 * (jy - jx) / jz).sqrt());
    println!("orbit period {orbit_period:.3} s; linear pitch libration period {theory:.3} s");
    // Pitch: the angle from the radial direction to the body x axis, about the orbit normal.
    let pitch = |s: &lgsvi_mechanics::State<SE3, 6>| {
        let x = s.position();
        let bx = s.attitude().matrix().column(0).into_owned();
        x.cross(&bx).z.atan2(x.dot(&bx))
    };
    let mut crossings = Vec::new();
    let mut last = pitch(integrator.state());
    let mut worst_energy = 0.0f64;
    let steps = (3.0 * orbit_period / h).ceil() as usize;
    for k in 1..=steps {
        integrator.step()?;
        let s = integrator.state();
        let p = pitch(s);
        if last > 0.0 && p <= 0.0 {
            // Downward zero crossing, by linear interpolation within the step.
            crossings.push(s.time - h * p / (p - last));
        }
        last = p;
        worst_energy = worst_energy.max((s.energy(&body) - e0).abs());
        if k % 20 == 0 {
            println!(
                "t = {:7.2}  r = {:.6}  pitch = {:+.5} rad",
                s.time,
                s.position().norm(),
                p
            );
        }
    }
    let periods: Vec<f64> = crossings.windows(2).map(|w| w[1] - w[0]).collect();
    let measured = periods.iter().sum::<f64>() / periods.len() as f64;
    let l_error = (integrator.state().spatial_momentum() - l0)
        .fixed_rows::<3>(0)
        .norm();
    println!(
        "measured libration period {measured:.3} s ({} periods), theory {theory:.3} s",
        periods.len()
    );
    println!("energy error {worst_energy:.1e}, angular momentum drift {l_error:.1e}");
    assert!(periods.len() >= 2);
    assert!(
        (measured - theory).abs() < 0.01 * theory,
        "{measured} vs {theory}"
    );
    assert!(worst_energy < 1e-10 * e0.abs() && l_error < 1e-13 * l0.norm());
    Ok(())
}
