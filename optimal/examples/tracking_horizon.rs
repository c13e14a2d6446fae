//! A tracking slew over ever more steps: an asymmetric body follows a steady turn for 20 s
//! (a reference it cannot follow exactly: its torques cost energy and its end is pinned
//! at rest), `K = 50 … 1600` steps. Prints the SQP iterations, the solve time and the time
//! per step and iteration, which stays flat: the subproblem keeps the states among its
//! variables (banded rows, a block-diagonal Hessian), so an iteration costs a fixed amount
//! a step. Asserts that every solve converges within ten iterations and that the optimal
//! cost converges at second order in `h` (torques held over each step).
//!
//! `cargo run --release -p lgsvi-optimal --example tracking_horizon`

use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::Inertia;
use lgsvi_optimal::Slew;
use nalgebra::Vector3;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let inertia = Inertia::from_principal_moments([3.0, 2.0, 1.5])?;
    let (t_end, theta) = (20.0, 1.5);
    let axis = Vector3::new(1.0, 2.0, 2.0) / 3.0;
    let rate = theta / t_end;
    println!("J = diag(3, 2, 1.5), tracking a turn of {theta} rad about (1, 2, 2)/3 in {t_end} s, rest at the end");
    println!("| K | SQP iterations | solve (ms) | µs per step and iteration | cost |");
    println!("|---|---|---|---|---|");
    let mut costs = Vec::new();
    for k in [50usize, 100, 200, 400, 800, 1600] {
        let h = t_end / k as f64;
        let reference: Vec<(SO3, Vector3<f64>)> = (1..=k)
            .map(|i| (SO3::exp(&(axis * rate * i as f64 * h)), axis * rate))
            .collect();
        let solution = Slew::new(inertia, t_end)
            .to(SO3::exp(&(axis * theta)), Vector3::zeros())
            .steps(k)
            .nodes(6)
            .track(reference, [3.0, 0.5])
            .solve()?;
        let iterations = solution.statistics.iterations;
        let time = solution.statistics.time_s;
        println!(
            "| {k} | {iterations} | {:.1} | {:.1} | {:.12} |",
            1e3 * time,
            1e6 * time / (k * iterations) as f64,
            solution.cost
        );
        assert!(solution.converged && iterations <= 10, "K = {k}");
        costs.push(solution.cost);
    }
    // Successive differences fall by four per halving of h.
    for w in costs.windows(3) {
        let order = ((w[0] - w[1]) / (w[1] - w[2])).log2();
        assert!((order - 2.0).abs() < 0.1, "order {order}");
    }
    Ok(())
}
