//! JSON and CSV output of a run, written straight to a file or standard output: no copy
//! of the document is built in memory, so a run of millions of recorded states needs
//! only its states (16 numbers each) besides the output itself.

use crate::Run;
use lgsvi_mechanics::State;
use std::io::{self, Write};

/// `x` as JSON writes it (shortest round-trip form; finite by the run's checks).
fn number<W: Write + ?Sized>(out: &mut W, x: f64) -> io::Result<()> {
    serde_json::to_writer(&mut *out, &x).map_err(io::Error::other)
}

/// `[x, y, …]`.
fn vector<W: Write + ?Sized>(out: &mut W, xs: &[f64]) -> io::Result<()> {
    out.write_all(b"[")?;
    for (i, &x) in xs.iter().enumerate() {
        if i > 0 {
            out.write_all(b",")?;
        }
        number(out, x)?;
    }
    out.write_all(b"]")
}

/// `"key":[item(s₀),item(s₁),…]` over the recorded states.
fn column<W: Write + ?Sized>(
    out: &mut W,
    key: &str,
    states: &[State],
    mut item: impl FnMut(&mut W, usize, &State) -> io::Result<()>,
) -> io::Result<()> {
    write!(out, "\"{key}\":[")?;
    for (k, s) in states.iter().enumerate() {
        if k > 0 {
            out.write_all(b",")?;
        }
        item(out, k, s)?;
    }
    out.write_all(b"]")
}

/// The JSON document, one line: the field names are part of the command-line contract,
/// in alphabetical order (as earlier versions wrote them).
pub fn write_json<W: Write + ?Sized>(run: &Run, out: &mut W) -> io::Result<()> {
    let states = &run.trajectory.states;
    out.write_all(b"{")?;
    column(out, "R", states, |o, _, s| {
        vector(o, &s.attitude().to_row_major())
    })?;
    out.write_all(b",")?;
    column(out, "casimir", states, |o, _, s| number(o, s.casimir()))?;
    out.write_all(b",\"description\":")?;
    serde_json::to_writer(&mut *out, &run.description).map_err(io::Error::other)?;
    out.write_all(b",")?;
    column(out, "energy", states, |o, k, _| number(o, run.energies[k]))?;
    out.write_all(b",")?;
    column(out, "momentum", states, |o, _, s| {
        vector(o, s.momentum.as_slice())
    })?;
    out.write_all(b",")?;
    column(out, "newton_iterations_per_step", states, |o, k, _| {
        write!(o, "{}", run.trajectory.newton_iterations[k])
    })?;
    out.write_all(b",")?;
    column(out, "omega", states, |o, _, s| {
        vector(o, s.velocity.as_slice())
    })?;
    if let Some(motion) = &run.motion {
        out.write_all(b",")?;
        column(out, "position", states, |o, k, _| {
            vector(o, motion[k].position.as_slice())
        })?;
    }
    out.write_all(b",")?;
    column(out, "spatial_momentum", states, |o, k, s| {
        match &run.motion {
            Some(motion) => vector(o, motion[k].spatial_momentum.as_slice()),
            None => vector(o, s.spatial_momentum().as_slice()),
        }
    })?;
    let mut stats = serde_json::json!({
        "steps": run.steps,
        "newton_iterations": run.newton_iterations,
        "max_newton_iterations": run.max_newton_iterations,
        "factorizations": run.factorizations,
        "wall_time_s": run.wall_time_s,
    });
    if let Some(estimates) = &run.estimates {
        stats["estimated_error"] = estimates.global.into();
        stats["nodes_histogram"] = estimates
            .nodes
            .iter()
            .map(|&(n, count)| serde_json::json!([n, count]))
            .collect::<Vec<_>>()
            .into();
        stats["rejected_steps"] = estimates.rejected.into();
        if let Some(check) = &estimates.check {
            stats["check"] = serde_json::json!({
                "largest_difference": check.largest.value,
                "largest_at_time": check.largest.time,
                "local_estimates_sum": check.local_sum,
                "runs": check.attempts,
                "share_tightened": check.tightened,
                "companion_extra_nodes": lgsvi_mechanics::CHECK_EXTRA_NODES,
            });
        }
    }
    out.write_all(b",\"stats\":")?;
    serde_json::to_writer(&mut *out, &stats).map_err(io::Error::other)?;
    out.write_all(b",")?;
    column(out, "times", states, |o, _, s| number(o, s.time))?;
    if let Some(motion) = &run.motion {
        out.write_all(b",")?;
        column(out, "velocity", states, |o, k, _| {
            vector(o, motion[k].velocity.as_slice())
        })?;
    }
    if let Some(wheels) = &run.wheels {
        out.write_all(b",")?;
        column(out, "wheel_angles", states, |o, k, _| {
            vector(o, &wheels[k].angles)
        })?;
        out.write_all(b",")?;
        column(out, "wheel_momentum", states, |o, k, _| {
            vector(o, &wheels[k].momenta)
        })?;
        out.write_all(b",")?;
        column(out, "wheel_speeds", states, |o, k, _| {
            vector(o, &wheels[k].speeds)
        })?;
    }
    if let Some(work) = &run.work {
        out.write_all(b",")?;
        column(out, "work", states, |o, k, _| number(o, work[k]))?;
    }
    out.write_all(b"}\n")
}

/// One row per recorded state: for an SE(3) run `pi` is the angular momentum about the
/// world origin and the row goes on with the position, the velocity `ẋ` and the linear
/// momentum; a gyrostat's rows go on with its wheels' angles, rates and axial momenta;
/// a forced run's rows end with the work done.
pub fn write_csv<W: Write + ?Sized>(run: &Run, out: &mut W) -> io::Result<()> {
    out.write_all(
        b"t,R11,R12,R13,R21,R22,R23,R31,R32,R33,omega_x,omega_y,omega_z,mu_x,mu_y,mu_z,energy,casimir,pi_x,pi_y,pi_z,newton_iterations",
    )?;
    if run.motion.is_some() {
        out.write_all(b",x,y,z,xdot_x,xdot_y,xdot_z,p_x,p_y,p_z")?;
    }
    if let Some(wheels) = &run.wheels {
        // One column per wheel and quantity: phi_i, phidot_i, p_i.
        for name in ["phi", "phidot", "p_wheel"] {
            for i in 1..=wheels.first().map_or(0, |w| w.angles.len()) {
                write!(out, ",{name}_{i}")?;
            }
        }
    }
    if run.work.is_some() {
        out.write_all(b",work")?;
    }
    out.write_all(b"\n")?;
    for (k, s) in run.trajectory.states.iter().enumerate() {
        write!(out, "{}", s.time)?;
        let pi = match &run.motion {
            Some(motion) => motion[k].spatial_momentum.fixed_rows::<3>(0).into_owned(),
            None => s.spatial_momentum(),
        };
        let values = s
            .attitude()
            .to_row_major()
            .into_iter()
            .chain(s.velocity.iter().copied())
            .chain(s.momentum.iter().copied())
            .chain([run.energies[k], s.casimir()])
            .chain(pi.iter().copied());
        for x in values {
            write!(out, ",{x}")?;
        }
        write!(out, ",{}", run.trajectory.newton_iterations[k])?;
        if let Some(motion) = &run.motion {
            let m = &motion[k];
            let linear = m.spatial_momentum.fixed_rows::<3>(3);
            for x in m
                .position
                .iter()
                .chain(m.velocity.iter())
                .chain(linear.iter())
            {
                write!(out, ",{x}")?;
            }
        }
        if let Some(wheels) = &run.wheels {
            let w = &wheels[k];
            for x in w.angles.iter().chain(&w.speeds).chain(&w.momenta) {
                write!(out, ",{x}")?;
            }
        }
        if let Some(work) = &run.work {
            write!(out, ",{}", work[k])?;
        }
        writeln!(out)?;
    }
    Ok(())
}
