//! JSON and CSV output, and the main job's report.

use crate::config::SimulateOptions;
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

/// The paper's case A at t = 10, from the project's high-precision reference
/// (`tests/data/rigid_body_refs.json`, 40 significant digits, error < 1e-38).
const REFERENCE_R_AT_10: [&str; 9] = [
    "0.8534045038405297267554563353149854020303",
    "0.09905439807889165377399755899373542450557",
    "-0.5117508955008557171706381585401296622364",
    "0.3594623659014689573128084092117701879665",
    "0.5991396485395784918026581249544844637211",
    "0.7154149069235200160966427291778726879988",
    "0.3774752446521728268345854191840292643264",
    "-0.7944934913321183563696949746896901972665",
    "0.4757021462067240283038804347114401318482",
];

/// A JSON array of numbers as `(a, b, c)` with 12 significant digits at most.
fn short(value: &serde_json::Value) -> String {
    let parts: Vec<String> = value
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(|v| v.as_f64())
                .map(|x| format!("{}", (x * 1e12).round() / 1e12))
                .collect()
        })
        .unwrap_or_default();
    format!("({})", parts.join(", "))
}

/// The main job: the paper's rigid body on the defaults, a human-readable report.
pub fn main_job(result: Result<(Run, SimulateOptions), String>) -> Result<(), String> {
    let (run, _) = result?;
    let states = &run.trajectory.states;
    let (first, last) = (
        &states[0],
        states.last().expect("at least the initial state"),
    );
    let reference = nalgebra::Matrix3::from_row_slice(
        &REFERENCE_R_AT_10.map(|s| s.parse::<f64>().unwrap_or(f64::NAN)),
    );
    let error = (last.attitude.matrix() - reference).norm();
    let e0 = run.energies[0];
    let max_energy_error = run
        .energies
        .iter()
        .map(|e| (e - e0).abs() / e0.abs())
        .fold(0.0, f64::max);
    let pi0 = first.spatial_momentum();
    let max_pi_drift = states
        .iter()
        .map(|s| (s.spatial_momentum() - pi0).norm())
        .fold(0.0, f64::max)
        / pi0.norm();
    let settings = &run.description["settings"];
    println!("lgsvi — Lie group spectral variational integrator (Hall & Leok)");
    println!(
        "The paper's free rigid body: J = {} (from J_d = {}), Ω(0) = (−2, 1.9, −1), R(0) = I",
        short(&run.description["inertia_J"]),
        short(&run.description["inertia_Jd"])
    );
    println!(
        "{} chart, {} momentum matching, h = {}, n = {} nodes (degree {}), m = {} Gauss points, T = {}",
        settings["chart"].as_str().unwrap_or("?"),
        settings["matching"].as_str().unwrap_or("?"),
        settings["h"],
        settings["nodes"],
        settings["degree"],
        settings["quadrature_points"],
        settings["t_end"]
    );
    println!(
        "{:>6}  {:>22}  {:>22}  {:>22}",
        "t", "energy", "|μ|²", "(Rμ)_z"
    );
    for (k, s) in states.iter().enumerate() {
        if k % 4 == 0 || k + 1 == states.len() {
            println!(
                "{:>6.2}  {:>22.16}  {:>22.16}  {:>22.16}",
                s.time,
                run.energies[k],
                s.casimir(),
                s.spatial_momentum().z
            );
        }
    }
    println!("‖R(10) − R_exact(10)‖_F = {error:.2e} (against the high-precision reference)");
    println!("max relative energy error {max_energy_error:.1e}, max relative drift of Rμ {max_pi_drift:.1e}");
    println!(
        "{} steps, {} Newton iterations (at most {} in one step), {:.3} s of integration",
        run.steps, run.newton_iterations, run.max_newton_iterations, run.wall_time_s
    );
    println!("More: `lgsvi simulate --help`; trajectories as JSON or CSV with `lgsvi simulate --out FILE`.");
    Ok(())
}
