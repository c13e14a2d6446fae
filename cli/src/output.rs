//! JSON and CSV output, and the main job's report.

use crate::Run;
use std::fmt::Write;

/// The JSON document: the field names are part of the command-line contract.
pub fn json(run: &Run) -> String {
    let states = &run.trajectory.states;
    let document = serde_json::json!({
        "description": run.description,
        "times": states.iter().map(|s| s.time).collect::<Vec<_>>(),
        "R": states.iter().map(|s| s.attitude.to_row_major().to_vec()).collect::<Vec<_>>(),
        "omega": states.iter().map(|s| s.velocity.as_slice().to_vec()).collect::<Vec<_>>(),
        "momentum": states.iter().map(|s| s.momentum.as_slice().to_vec()).collect::<Vec<_>>(),
        "energy": run.energies,
        "casimir": states.iter().map(|s| s.casimir()).collect::<Vec<_>>(),
        "spatial_momentum": states.iter().map(|s| s.spatial_momentum().as_slice().to_vec()).collect::<Vec<_>>(),
        "newton_iterations_per_step": run.trajectory.newton_iterations,
        "stats": {
            "steps": run.steps,
            "newton_iterations": run.newton_iterations,
            "max_newton_iterations": run.max_newton_iterations,
            "wall_time_s": run.wall_time_s,
        },
    });
    let mut text = serde_json::to_string(&document).expect("JSON of numbers and strings");
    text.push('\n');
    text
}

/// One row per recorded state.
pub fn csv(run: &Run) -> String {
    let mut out = String::from(
        "t,R11,R12,R13,R21,R22,R23,R31,R32,R33,omega_x,omega_y,omega_z,mu_x,mu_y,mu_z,energy,casimir,pi_x,pi_y,pi_z,newton_iterations\n",
    );
    for (k, s) in run.trajectory.states.iter().enumerate() {
        let mut row: Vec<String> = vec![s.time.to_string()];
        row.extend(s.attitude.to_row_major().iter().map(f64::to_string));
        row.extend(s.velocity.iter().map(f64::to_string));
        row.extend(s.momentum.iter().map(f64::to_string));
        row.push(run.energies[k].to_string());
        row.push(s.casimir().to_string());
        row.extend(s.spatial_momentum().iter().map(f64::to_string));
        row.push(run.trajectory.newton_iterations[k].to_string());
        let _ = writeln!(out, "{}", row.join(","));
    }
    out
}
