//! `m = n − 1` Gauss points against the default `m = n` on the free rigid body: cases A
//! and B over T = 100, at `h = 0.5` and `1` and `n = 6 … 12`. For each run it prints the
//! attitude's error against the exact free motion, the best of three wall-clock times and
//! the Newton iterations per step, so the table shows what one Gauss point fewer saves and
//! what it costs in accuracy. Run with
//! `cargo run --release -p lgsvi-mechanics --example quadrature_points` (the times mean
//! little in a debug build).
//!
//! Asserts what the table shows: one Gauss point fewer costs no accuracy. Every error with
//! `m = n − 1` is within 4× of the error with `m = n` (above the rounding floor the two
//! agree far more closely), or below 3e-13, the rounding floor of these runs: there two
//! runs whose steps differ only at rounding can end a few times apart, and the same run
//! can end at a different error in another build.
use lgsvi_mechanics::exact::FreeRigidBodyExact;
use lgsvi_mechanics::lie::{LieGroup, SO3};
use lgsvi_mechanics::{Inertia, Integrator, MechanicsError, RigidBody, StepSettings};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let t_end = 100.0;
    println!("case    h   n   m   error at T = 100   time (ms, best of 3)   iterations/step");
    for name in ["A", "B"] {
        let case = lgsvi_cases::case(name)?;
        let inertia = Inertia::from_tensor(case.inertia)?;
        let start = SO3::from_matrix_unchecked(case.attitude0);
        let end = FreeRigidBodyExact::new(inertia, start, case.omega0)?.state(t_end)?;
        for h in [0.5, 1.0] {
            for n in 6..=12 {
                let mut errors = [0.0; 2];
                for (k, m) in [n, n - 1].into_iter().enumerate() {
                    let settings = StepSettings::new(h, n)?.with_quadrature_points(m)?;
                    let steps = (t_end / h).round() as usize;
                    let mut best = f64::INFINITY;
                    let (mut error, mut iterations) = (0.0, 0);
                    for _ in 0..3 {
                        let clock = Instant::now();
                        let mut body =
                            Integrator::new(RigidBody::new(inertia), settings, start, case.omega0)?;
                        iterations = (0..steps)
                            .map(|_| body.step())
                            .sum::<Result<usize, MechanicsError>>()?;
                        best = best.min(clock.elapsed().as_secs_f64());
                        let state = body.state();
                        error = state
                            .configuration
                            .inverse()
                            .compose(&end.configuration)
                            .log()
                            .amax();
                    }
                    println!(
                        "{name:>4} {h:>4} {n:>3} {m:>3}   {error:>16.2e}   {:>20.2}   {:>15.2}",
                        best * 1e3,
                        iterations as f64 / steps as f64
                    );
                    errors[k] = error;
                }
                assert!(
                    errors[1] <= 4.0 * errors[0] || errors[1] < 3e-13,
                    "case {name}, h = {h}, n = {n}: m = n − 1 {:.2e} against m = n {:.2e}",
                    errors[1],
                    errors[0]
                );
            }
        }
    }
    Ok(())
}
