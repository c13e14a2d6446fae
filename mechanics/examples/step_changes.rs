//! What choosing nodes and steps per step costs over long runs, on the heavy top (the
//! paper's case B, whose local error varies along the motion):
//!
//! 1. fixed `h = 0.5`, `n = 8`;
//! 2. fixed `h = 0.5`, nodes chosen per step (5 to 30) for 6e-13 per unit time, rising
//!    only (the default): from 6 to 8 within the first steps;
//! 3. the same with falling nodes allowed (`with_falling_nodes`): they move between 7 and
//!    8 all along;
//! 4. fixed `h = 0.5`, nodes in 6..8, for 1e-10 per unit time;
//! 5. nodes in 5..6 only, for 1e-10 per unit time, with the step allowed to change
//!    (`StepSettings::with_step_changes`): six nodes cannot meet 1e-10 at `h = 0.5` (a
//!    fixed step would stop with `ToleranceNotMet` at the first step), so the step moves
//!    between 0.25 and 0.5.
//!
//! Prints the energy error's size in each half of the run and its trend (a least-squares
//! slope), the step sizes and nodes used, and checks that the symmetry's momentum `π₃` is
//! conserved to rounding in every run, that the energy errors of the fixed-step runs whose
//! nodes do not fall stay bounded, and that the nodes fell in run 3 and the step changed
//! in run 5 (or they would measure nothing).
//!
//! `cargo run --release -p lgsvi-mechanics --example step_changes [STEPS]` (default 10⁵).

use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::{HeavyTop, Inertia, Integrator, StepSettings};
use nalgebra::Vector3;

struct Record {
    label: &'static str,
    /// `(t, relative energy error)` at 1000 times.
    energy: Vec<(f64, f64)>,
    momentum_drift: f64,
    steps: usize,
    h_range: (f64, f64),
    nodes: Vec<(usize, usize)>,
}

fn run(
    label: &'static str,
    settings: StepSettings,
    steps: usize,
) -> Result<Record, Box<dyn std::error::Error>> {
    let top = HeavyTop::paper(Inertia::from_paper_jd([1.0, 2.8, 2.0])?)?;
    let mut it = Integrator::new(top, settings, SO3::identity(), Vector3::new(0.5, -0.5, 0.4))?;
    let e0 = it.state().energy(&top);
    let p0 = it.state().spatial_momentum().z;
    let mut energy = Vec::new();
    let (mut momentum_drift, mut lo, mut hi) = (0.0f64, f64::INFINITY, 0.0f64);
    let every = (steps / 1000).max(1);
    for k in 1..=steps {
        it.step()?;
        let h = it.settings().h();
        lo = lo.min(h);
        hi = hi.max(h);
        let s = it.state();
        momentum_drift = momentum_drift.max((s.spatial_momentum().z - p0).abs());
        if k % every == 0 {
            energy.push((s.time, (s.energy(&top) - e0) / e0.abs()));
        }
    }
    let nodes = it.nodes_used().collect();
    Ok(Record {
        label,
        energy,
        momentum_drift,
        steps: it.statistics().steps,
        h_range: (lo, hi),
        nodes,
    })
}

/// Largest |error| in the first and second half, and the least-squares slope per 10⁵ time
/// units.
fn summary(energy: &[(f64, f64)]) -> (f64, f64, f64) {
    let mid = energy.len() / 2;
    let max = |v: &[(f64, f64)]| v.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    let n = energy.len() as f64;
    let (mt, me) = (
        energy.iter().map(|p| p.0).sum::<f64>() / n,
        energy.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for &(t, e) in energy {
        sxy += (t - mt) * (e - me);
        sxx += (t - mt) * (t - mt);
    }
    (max(&energy[..mid]), max(&energy[mid..]), 1e5 * sxy / sxx)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let steps: usize = match std::env::args().nth(1) {
        Some(text) => text.parse()?,
        None => 100_000,
    };
    let fixed_step = StepSettings::new(0.5, 6)?
        .with_tolerance(1e-10)?
        .with_node_range(6, 8)?;
    let narrow = StepSettings::new(0.5, 6)?
        .with_tolerance(1e-10)?
        .with_node_range(5, 6)?;
    let records = [
        run("fixed h = 0.5, n = 8", StepSettings::new(0.5, 8)?, steps)?,
        run(
            "fixed h = 0.5, n rising (6e-13)",
            StepSettings::new(0.5, 6)?.with_tolerance(6e-13)?,
            steps,
        )?,
        run(
            "fixed h = 0.5, n rising and falling (6e-13)",
            StepSettings::new(0.5, 6)?
                .with_tolerance(6e-13)?
                .with_falling_nodes(true),
            steps,
        )?,
        run(
            "fixed h = 0.5, n per step in 6..8 (1e-10)",
            fixed_step,
            steps,
        )?,
        run(
            "h and n in 5..6 per step, h ≤ 0.5 (1e-10)",
            narrow.with_step_changes(true),
            steps,
        )?,
    ];
    println!("heavy top (case B), {steps} steps; the error allowed per unit time in parentheses");
    println!(
        "{:44} {:>9} {:>9} {:>11} {:>9} {:>15}  nodes (n, steps)",
        "run", "|ΔE| 1st", "|ΔE| 2nd", "slope/1e5", "|Δπ₃|", "h range"
    );
    for r in &records {
        let (first, second, slope) = summary(&r.energy);
        println!(
            "{:44} {:9.2e} {:9.2e} {:+11.2e} {:9.2e} {:>7.4}..{:<6.4}  {:?}",
            r.label, first, second, slope, r.momentum_drift, r.h_range.0, r.h_range.1, r.nodes
        );
    }
    // π₃ is the symmetry of the top: every step is a map of the exact matching, whatever
    // its h and n, so it is conserved to rounding (a random walk of ~ε|π| per step).
    for r in &records {
        assert!(
            r.momentum_drift < 1e-15 * (r.steps as f64).sqrt() * 100.0,
            "{}: π₃ drifted {:e}",
            r.label,
            r.momentum_drift
        );
    }
    // At a fixed step with nodes that do not fall, the energy error is bounded: the second
    // half no larger than a few times the first.
    for r in [&records[0], &records[1], &records[3]] {
        let (first, second, _) = summary(&r.energy);
        assert!(
            second < 5.0 * first.max(1e-14),
            "{}: {first:e} then {second:e}",
            r.label
        );
    }
    // The nodes moved both ways in the third run and the step in the last.
    assert!(records[2].nodes.len() >= 2 && records[2].nodes[0].1 > 100);
    assert!(records[4].h_range.0 < records[4].h_range.1);
    Ok(())
}
