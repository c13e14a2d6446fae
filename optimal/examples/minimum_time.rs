//! The minimum-time reorientation of an asymmetric body (Betts's test problem, solved by
//! Fleming, Sekhavat & Ross 2008): `J = diag(5621, 4547, 2364)` kg·m², `|u_i| ≤ 50` N·m,
//! rest to rest, 150° about the body's x axis; `t_f* = 28.6304077` s. Prints the final
//! time, its relative error, the SQP iterations and the solve time against the steps
//! (torques constant per step: the error falls as `h²`), then the Richardson value of the
//! last two; asserts the error at 100 steps (≤ 1e-4) and the order.
//!
//! `cargo run --release -p lgsvi-optimal --example minimum_time`

use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::Inertia;
use lgsvi_optimal::{Cost, Slew};
use nalgebra::Vector3;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let reference = 28.6304077;
    let inertia = Inertia::from_principal_moments([5621.0, 4547.0, 2364.0])?;
    let target = SO3::exp(&(Vector3::x() * 150f64.to_radians()));
    println!("Betts's reorientation, t_f* = {reference} s (Fleming, Sekhavat & Ross 2008)");
    println!("| K | t_f (s) | relative error | order | SQP iterations | solve (ms) |");
    println!("|---|---|---|---|---|---|");
    let mut previous: Option<(f64, f64)> = None;
    for k in [25, 50, 100, 200, 400] {
        let solution = Slew::new(inertia, 34.0)
            .to(target, Vector3::zeros())
            .steps(k)
            .nodes(8)
            .torque_max([50.0; 3])
            .cost(Cost::Time)
            .solve()?;
        let error = (solution.t_end - reference) / reference;
        let order = previous.map_or(String::from("–"), |(_, e)| {
            format!("{:.2}", (e / error).log2())
        });
        println!(
            "| {k} | {:.9} | {error:.3e} | {order} | {} | {:.0} |",
            solution.t_end,
            solution.statistics.iterations,
            1e3 * solution.statistics.time_s
        );
        if k == 100 {
            assert!(error > 0.0 && error <= 1e-4, "K = 100: {error:e}");
        }
        if let Some((t, e)) = previous {
            let order = (e / error).log2();
            assert!((1.8..2.5).contains(&order), "order {order} at K = {k}");
            if k == 400 {
                let extrapolated = solution.t_end - (t - solution.t_end) / 3.0;
                println!(
                    "\nRichardson (K = 200, 400, order 2): {extrapolated:.7} s, {:.1e} from the reference",
                    (extrapolated - reference) / reference
                );
            }
        }
        previous = Some((solution.t_end, error));
    }
    Ok(())
}
