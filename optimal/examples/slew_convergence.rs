//! The minimum-energy slew's optimal cost under h-refinement, constant torque per step:
//! a spherical body `J = 2I` turning 1.2 rad about `(1, 2, 2)/3`, rest to rest in 10 s,
//! against the continuous optimum `J* = 12 j²θ²/T³`; then an asymmetric body's oblique
//! slew with its SQP iterations; then that body's unbounded slew against the indirect
//! (Pontryagin) optimum with torques constant per step and polynomial within a step.
//! Asserts the orders it prints (2, and 2(n − 1)).
//!
//! `cargo run --release -p lgsvi-optimal --example slew_convergence`

use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::Inertia;
use lgsvi_optimal::{Inputs, Slew};
use nalgebra::Vector3;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (j, theta, t_end): (f64, f64, f64) = (2.0, 1.2, 10.0);
    let continuous = 12.0 * j * j * theta * theta / t_end.powi(3);
    let axis = Vector3::new(1.0, 2.0, 2.0) / 3.0;
    println!("spherical body, J* = 12 j²θ²/T³ = {continuous:.15}");
    println!("| K | cost | relative error | order |");
    println!("|---|---|---|---|");
    let mut previous: Option<f64> = None;
    for k in [5, 10, 20, 40, 80, 160] {
        let solution = Slew::new(Inertia::from_principal_moments([j; 3])?, t_end)
            .to(SO3::exp(&(axis * theta)), Vector3::zeros())
            .steps(k)
            .nodes(6)
            .solve()?;
        let error = (solution.cost - continuous) / continuous;
        let order = previous.map_or(String::from("–"), |p| {
            format!("{:.3}", (p / error).log2())
        });
        println!("| {k} | {:.15} | {error:.3e} | {order} |", solution.cost);
        if let Some(p) = previous {
            assert!(((p / error).log2() - 2.0).abs() < 0.05);
        }
        previous = Some(error);
    }
    let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5])?;
    let target = SO3::exp(&Vector3::new(1.5, 0.4, -0.9));
    let solution = Slew::new(inertia, 30.0)
        .to(target, Vector3::zeros())
        .steps(30)
        .nodes(10)
        .torque_max([0.06; 3])
        .solve()?;
    println!(
        "\nasymmetric body J = diag(3, 4, 5.5), a {:.1}° slew in 30 s, |u_i| ≤ 0.06 N·m, \
         30 steps of 10 nodes: cost {:.12}, {} SQP iterations, {:.1} ms",
        target.log().norm().to_degrees(),
        solution.cost,
        solution.statistics.iterations,
        1e3 * solution.statistics.time_s
    );
    let residuals: Vec<String> = solution
        .statistics
        .kkt_residuals
        .iter()
        .map(|r| format!("{r:.1e}"))
        .collect();
    println!("scaled KKT residual per iterate: {}", residuals.join(", "));
    assert!(solution.converged);
    polynomial_against_pontryagin()
}

/// The asymmetric body's unbounded slew (`J = diag(3, 4, 5.5)`, 102.8° in 30 s, rest to
/// rest) against the indirect (Pontryagin) optimum of `optimal/tests/data/pontryagin_slew.py`:
/// constant torques per step converge at order 2, torques polynomial within a step at the
/// integrator's order 2(n − 1).
fn polynomial_against_pontryagin() -> Result<(), Box<dyn std::error::Error>> {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/pontryagin_slew.json"
    ))?;
    let reference: f64 = text
        .lines()
        .find_map(|l| l.trim().strip_prefix("\"cost\": "))
        .and_then(|v| v.trim_end_matches(',').parse().ok())
        .ok_or("no cost in pontryagin_slew.json")?;
    let inertia = Inertia::from_principal_moments([3.0, 4.0, 5.5])?;
    let target = SO3::exp(&Vector3::new(1.5, 0.4, -0.9));
    println!("\nasymmetric body, unbounded, against Pontryagin's optimum {reference:.16}");
    println!("| inputs | n | K | cost | relative error | order |");
    println!("|---|---|---|---|---|---|");
    for (inputs, n, steps, expected) in [
        (Inputs::Constant, 8, [10, 20, 40, 80], 2.0),
        (Inputs::Polynomial, 3, [5, 10, 20, 40], 4.0),
        (Inputs::Polynomial, 4, [5, 10, 20, 40], 6.0),
        (Inputs::Polynomial, 5, [4, 8, 16, 32], 8.0),
    ] {
        let mut previous: Option<f64> = None;
        for k in steps {
            let solution = Slew::new(inertia, 30.0)
                .to(target, Vector3::zeros())
                .steps(k)
                .nodes(n)
                .inputs(inputs)
                .solve()?;
            let error = (solution.cost - reference).abs() / reference;
            let order = previous.map_or(String::from("–"), |p| {
                format!("{:.2}", (p / error).log2())
            });
            println!(
                "| {} | {n} | {k} | {:.16} | {error:.3e} | {order} |",
                if inputs == Inputs::Constant {
                    "constant"
                } else {
                    "polynomial"
                },
                solution.cost
            );
            // The order where the error is above rounding (1e-12).
            if let Some(p) = previous.filter(|_| error > 1e-12) {
                let measured = (p / error).log2();
                assert!(
                    (measured - expected).abs() < 0.5,
                    "order {measured} against {expected}"
                );
            }
            previous = Some(error);
        }
    }
    Ok(())
}
