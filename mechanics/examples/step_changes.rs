//! What changing the step costs: the heavy top (the paper's case B) over 10⁵ steps with
//! the nodes chosen per step at a fixed step, and with the step allowed to change too
//! (`StepSettings::with_step_changes`, the node range narrowed to 5–6 so that the step
//! has to move). Prints the energy error's size in each half of the run and its trend (a
//! least-squares slope), the steps taken and the step sizes used, and checks that the
//! symmetry's momentum `π₃` is conserved to rounding in both runs and that the fixed-step
//! run's energy error stays bounded.
//!
//! `cargo run --release -p lgsvi-mechanics --example step_changes`

use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::{HeavyTop, Inertia, Integrator, StepSettings};
use nalgebra::Vector3;

const STEPS: usize = 100_000;

struct Record {
    label: &'static str,
    /// `(t, relative energy error)` every 100 steps.
    energy: Vec<(f64, f64)>,
    momentum_drift: f64,
    steps: usize,
    h_range: (f64, f64),
    nodes: Vec<(usize, usize)>,
}

fn run(label: &'static str, settings: StepSettings) -> Result<Record, Box<dyn std::error::Error>> {
    let top = HeavyTop::paper(Inertia::from_paper_jd([1.0, 2.8, 2.0])?)?;
    let mut it = Integrator::new(top, settings, SO3::identity(), Vector3::new(0.5, -0.5, 0.4))?;
    let e0 = it.state().energy(&top);
    let p0 = it.state().spatial_momentum().z;
    let mut energy = Vec::new();
    let (mut momentum_drift, mut lo, mut hi) = (0.0f64, f64::INFINITY, 0.0f64);
    for k in 1..=STEPS {
        it.step()?;
        let h = it.settings().step();
        lo = lo.min(h);
        hi = hi.max(h);
        let s = it.state();
        momentum_drift = momentum_drift.max((s.spatial_momentum().z - p0).abs());
        if k % 100 == 0 {
            energy.push((s.time, (s.energy(&top) - e0) / e0.abs()));
        }
    }
    let nodes = it
        .nodes_histogram()
        .iter()
        .enumerate()
        .filter(|(_, &c)| c > 0)
        .map(|(n, &c)| (n, c))
        .collect();
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
    let fixed = StepSettings::new(0.5, 6)?
        .with_tolerance(1e-10)?
        .with_node_range(5, 6)?;
    let records = [
        run("nodes per step, fixed h = 0.5", fixed)?,
        run(
            "nodes and step per step (h ≤ 0.5)",
            fixed.with_step_changes(true),
        )?,
    ];
    println!("heavy top (case B), {STEPS} steps, error allowed 1e-10 per unit time, n in 5..6");
    println!(
        "{:38} {:>9} {:>9} {:>11} {:>9} {:>17}  nodes",
        "run", "|ΔE| 1st", "|ΔE| 2nd", "slope/1e5", "|Δπ₃|", "h range"
    );
    for r in &records {
        let (first, second, slope) = summary(&r.energy);
        println!(
            "{:38} {:9.2e} {:9.2e} {:+11.2e} {:9.2e} {:>8.4}..{:<8.4}  {:?} over {} steps",
            r.label,
            first,
            second,
            slope,
            r.momentum_drift,
            r.h_range.0,
            r.h_range.1,
            r.nodes,
            r.steps
        );
    }
    // π₃ is the symmetry of the top: every step is a map of the exact matching, whatever
    // its h and n, so it is conserved to rounding (10⁵ steps of ~ε |π| random walk).
    for r in &records {
        assert!(
            r.momentum_drift < 1e-12,
            "{}: π₃ drifted {:e}",
            r.label,
            r.momentum_drift
        );
    }
    // At a fixed step the energy error is bounded: the second half no larger than a few
    // times the first.
    let (first, second, _) = summary(&records[0].energy);
    assert!(
        second < 5.0 * first.max(1e-14),
        "fixed step: {first:e} then {second:e}"
    );
    // The step did change in the second run (otherwise it measures nothing).
    assert!(records[1].h_range.0 < records[1].h_range.1);
    Ok(())
}
