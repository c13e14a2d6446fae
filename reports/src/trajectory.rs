//! A recorded run ([`lgsvi_experiments::record::Recording`]) as `lgsvi simulate` writes
//! it: one JSON document (through serde, streamed: no copy of the document is built in
//! memory, so a run of millions of recorded states needs only its states besides the
//! output), CSV rows (through the `csv` crate), and the conservation figure.
//!
//! The JSON field names and the CSV columns are the command line's output contract
//! (`docs/design.md` §4); numbers are written in their shortest round-trip form.
//!
//! ```
//! use lgsvi_experiments::record::record;
//! use lgsvi_mechanics::lie::SO3;
//! use lgsvi_mechanics::{Inertia, Integrator, RigidBody, StepSettings};
//! use lgsvi_reports::trajectory::{write_csv, write_json};
//! use nalgebra::Vector3;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let body = RigidBody::new(Inertia::from_principal_moments([3.3, 2.5, 3.4])?);
//! let mut integrator =
//!     Integrator::new(body, StepSettings::new(0.5, 8)?, SO3::identity(), Vector3::new(-2.0, 1.9, -1.0))?;
//! let run = record(&mut integrator, 2.0, 1, &mut |_| {})?;
//! let mut json = Vec::new();
//! write_json(&run, &serde_json::json!({"system": "rigid-body"}), &mut json)?;
//! let document: serde_json::Value = serde_json::from_slice(&json)?;
//! assert_eq!(document["times"].as_array().unwrap().len(), 5);
//! assert_eq!(document["stats"]["steps"], 4);
//! let mut csv = Vec::new();
//! write_csv(&run, &mut csv)?;
//! let text = String::from_utf8(csv)?;
//! assert_eq!(text.lines().count(), 1 + 5); // the header and one row per recorded state
//! assert!(text.starts_with("t,R11,R12,R13,"));
//! # Ok(())
//! # }
//! ```

use lgsvi_experiments::record::Recording;
use lgsvi_experiments::scenario::{Motion, Scenario};
use lgsvi_mechanics::built_in::{BuiltInSe3, BuiltInSo3};
use lgsvi_mechanics::settings::NewtonJacobian;
use lgsvi_mechanics::StepSettings;
use lgsvi_plot::{Figure, Series, Style};
use nalgebra::Vector3;
use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;
use std::fmt::Write as _;
use std::io::{self, Write};

/// A sequence serialised as it is produced: `f()` is iterated while writing.
struct Lazy<F>(F);

impl<F, I> Serialize for Lazy<F>
where
    F: Fn() -> I,
    I: IntoIterator,
    I::Item: Serialize,
{
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq((self.0)())
    }
}

/// The JSON document of a run: its columns, `description` as given, and `stats`.
struct Document<'a> {
    run: &'a Recording,
    description: &'a serde_json::Value,
}

impl Document<'_> {
    /// The integrator's statistics and error accounting.
    fn stats(&self) -> serde_json::Value {
        let run = self.run;
        let mut stats = serde_json::json!({
            "steps": run.steps,
            "newton_iterations": run.newton_iterations_total,
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
                    "companion_extra_nodes": lgsvi_mechanics::tolerance::CHECK_EXTRA_NODES,
                });
            }
        }
        stats
    }
}

/// The fields in alphabetical order, as the command line has always written them.
impl Serialize for Document<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let run = self.run;
        let states = &run.states;
        let mut map = serializer.serialize_map(None)?;
        map.serialize_entry(
            "R",
            &Lazy(|| states.iter().map(|s| s.attitude().to_row_major())),
        )?;
        map.serialize_entry("casimir", &Lazy(|| states.iter().map(|s| s.casimir())))?;
        map.serialize_entry("description", self.description)?;
        map.serialize_entry("energy", &run.energies)?;
        map.serialize_entry(
            "momentum",
            &Lazy(|| states.iter().map(|s| s.momentum.as_slice())),
        )?;
        map.serialize_entry("newton_iterations_per_step", &run.newton_iterations)?;
        map.serialize_entry(
            "omega",
            &Lazy(|| states.iter().map(|s| s.velocity.as_slice())),
        )?;
        if let Some(motion) = &run.motion {
            map.serialize_entry(
                "position",
                &Lazy(|| motion.iter().map(|m| m.position.as_slice())),
            )?;
        }
        match &run.motion {
            Some(motion) => map.serialize_entry(
                "spatial_momentum",
                &Lazy(|| motion.iter().map(|m| m.spatial_momentum.as_slice())),
            )?,
            None => map.serialize_entry(
                "spatial_momentum",
                &Lazy(|| {
                    states
                        .iter()
                        .map(|s| <[f64; 3]>::from(s.spatial_momentum()))
                }),
            )?,
        }
        map.serialize_entry("stats", &self.stats())?;
        map.serialize_entry("times", &Lazy(|| states.iter().map(|s| s.time)))?;
        if let Some(motion) = &run.motion {
            map.serialize_entry(
                "velocity",
                &Lazy(|| motion.iter().map(|m| m.velocity.as_slice())),
            )?;
        }
        if let Some(wheels) = &run.wheels {
            map.serialize_entry("wheel_angles", &Lazy(|| wheels.iter().map(|w| &w.angles)))?;
            map.serialize_entry(
                "wheel_momentum",
                &Lazy(|| wheels.iter().map(|w| &w.momenta)),
            )?;
            map.serialize_entry("wheel_speeds", &Lazy(|| wheels.iter().map(|w| &w.speeds)))?;
        }
        if let Some(work) = &run.work {
            map.serialize_entry("work", work)?;
        }
        map.end()
    }
}

/// Refuses a recording whose columns do not have one entry per state.
fn consistent(run: &Recording) -> io::Result<()> {
    if run.is_consistent() {
        Ok(())
    } else {
        Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "a recording's columns must have one entry per recorded state (Recording::is_consistent)",
        ))
    }
}

/// A run's step settings as the `settings` of its JSON description: `h`, `nodes`, `degree`,
/// `quadrature_points`, `chart`, `matching`, `jacobian`, `t_end`, `every`; with adaptive
/// nodes, the first step's count, `nodes_histogram`'s pointer, the error per unit time and
/// the node range.
pub fn settings_json(settings: &StepSettings, t_end: f64, every: usize) -> serde_json::Value {
    let mut json = serde_json::json!({
        "h": settings.h(), "nodes": settings.nodes(), "degree": settings.degree(),
        "quadrature_points": settings.quadrature_points(), "chart": settings.chart().to_string(),
        "matching": format!("{:?}", settings.matching()).to_lowercase(),
        "jacobian": match settings.jacobian() { NewtonJacobian::Exact => "exact", _ => "finite-difference" },
        "t_end": t_end, "every": every,
    });
    if let Some(adaptive) = settings.adaptive() {
        // The nodes vary per step: the first step's count is only where the run began
        // (the steps per count are `stats.nodes_histogram`).
        json["first_nodes"] = settings.nodes().into();
        json["nodes"] = "per step: stats.nodes_histogram".into();
        json["error_per_unit_time"] = adaptive.rate.into();
        json["node_range"] = serde_json::json!([adaptive.min_nodes, adaptive.max_nodes]);
    }
    json
}

/// Writes the run as one JSON document on one line, ending in a newline: the recorded
/// states' columns (`R` row-major, `omega`, `momentum`, `energy`, `casimir`,
/// `spatial_momentum`, `times`, `newton_iterations_per_step`; `position` and `velocity`
/// for a body in space, the `wheel_*` columns for a gyrostat, `work` for a forced run),
/// `description` as given, and `stats` (steps, Newton iterations and matrices, wall time,
/// the error estimates and a checked run's measurement).
///
/// # Errors
/// Writing to `out`; [`io::ErrorKind::InvalidInput`] for a recording that is not
/// [`Recording::is_consistent`].
pub fn write_json<W: Write + ?Sized>(
    run: &Recording,
    description: &serde_json::Value,
    out: &mut W,
) -> io::Result<()> {
    consistent(run)?;
    let document = Document { run, description };
    serde_json::to_writer(&mut *out, &document).map_err(io::Error::other)?;
    out.write_all(b"\n")
}

/// Writes the run as CSV, one row per recorded state: for a body in space `pi` is the
/// angular momentum about the world origin and the row goes on with the position, the
/// velocity `ẋ` and the linear momentum; a gyrostat's rows go on with its wheels' angles,
/// rates and axial momenta; a forced run's rows end with the work done.
///
/// # Errors
/// Writing to `out`; [`io::ErrorKind::InvalidInput`] for a recording that is not
/// [`Recording::is_consistent`].
pub fn write_csv<W: Write + ?Sized>(run: &Recording, out: &mut W) -> io::Result<()> {
    consistent(run)?;
    let mut csv = csv::Writer::from_writer(&mut *out);
    let failed = |e: csv::Error| io::Error::other(e);
    let mut header: Vec<String> = "t,R11,R12,R13,R21,R22,R23,R31,R32,R33,omega_x,omega_y,\
                                   omega_z,mu_x,mu_y,mu_z,energy,casimir,pi_x,pi_y,pi_z,\
                                   newton_iterations"
        .split(',')
        .map(String::from)
        .collect();
    if run.motion.is_some() {
        header.extend(
            "x,y,z,xdot_x,xdot_y,xdot_z,p_x,p_y,p_z"
                .split(',')
                .map(String::from),
        );
    }
    if let Some(wheels) = &run.wheels {
        // One column per wheel and quantity: phi_i, phidot_i, p_wheel_i.
        for name in ["phi", "phidot", "p_wheel"] {
            for i in 1..=wheels.first().map_or(0, |w| w.angles.len()) {
                header.push(format!("{name}_{i}"));
            }
        }
    }
    if run.work.is_some() {
        header.push("work".into());
    }
    csv.write_record(&header).map_err(failed)?;
    // Numbers as Rust writes them (`Display`: shortest round-trip digits, no exponent).
    let mut field = String::new();
    let mut put = |csv: &mut csv::Writer<&mut W>, x: &dyn std::fmt::Display| {
        field.clear();
        let _ = write!(field, "{x}");
        csv.write_field(&field)
    };
    for (k, s) in run.states.iter().enumerate() {
        put(&mut csv, &s.time).map_err(failed)?;
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
            put(&mut csv, &x).map_err(failed)?;
        }
        put(&mut csv, &run.newton_iterations[k]).map_err(failed)?;
        if let Some(motion) = &run.motion {
            let m = &motion[k];
            let linear = m.spatial_momentum.fixed_rows::<3>(3);
            for x in m
                .position
                .iter()
                .chain(m.velocity.iter())
                .chain(linear.iter())
            {
                put(&mut csv, x).map_err(failed)?;
            }
        }
        if let Some(wheels) = &run.wheels {
            let w = &wheels[k];
            for x in w.angles.iter().chain(&w.speeds).chain(&w.momenta) {
                put(&mut csv, x).map_err(failed)?;
            }
        }
        if let Some(work) = &run.work {
            put(&mut csv, &work[k]).map_err(failed)?;
        }
        csv.write_record(None::<&[u8]>).map_err(failed)?;
    }
    csv.flush()
}

/// Which momenta an unforced run conserves, for [`conservation_figure`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Conserved {
    /// All of the spatial momentum: `Rμ` for a free body on SO(3), all six of
    /// `(RJΩ + x × mẋ, mẋ)` for a free body in space.
    Spatial,
    /// The angular momentum about the world origin (the first three of a body in space's
    /// spatial momentum): an orbiting body.
    AngularAboutOrigin,
    /// The component `d·Rμ` along a spatial direction (a heavy top's gravity direction).
    Along(Vector3<f64>),
}

impl Conserved {
    /// What a built-in scenario conserves when unforced: the orbiting body its angular
    /// momentum about the attracting centre, the heavy top the component along its own
    /// gravity direction, the free bodies all of their spatial momentum.
    pub fn of(scenario: &Scenario) -> Self {
        let orbit = |m: &Motion| matches!(m.system.system, BuiltInSe3::Orbit(_));
        match (&scenario.motion, &scenario.system.system) {
            (Some(motion), _) if orbit(motion) => Conserved::AngularAboutOrigin,
            (None, BuiltInSo3::Top(top)) => Conserved::Along(*top.gravity_direction()),
            _ => Conserved::Spatial,
        }
    }
}

/// The conservation figure of a run: `|E − E₀ − W|/|E₀|` (the energy balance; `W = 0`
/// unforced) and, for an unforced run, the drift of the spatial momentum's `conserved`
/// components relative to their size.
pub fn conservation_figure(run: &Recording, name: &str, conserved: Conserved) -> Figure {
    let states = &run.states;
    let mut figure = Figure {
        title: format!("{name}: conservation over {} steps", run.steps),
        x_label: "time t".into(),
        y_label: "relative error".into(),
        x_log: false,
        y_log: true,
        series: vec![],
        hlines: vec![],
    };
    // An empty or inconsistent recording (not one `record` makes) draws no series.
    if states.is_empty() || !run.is_consistent() {
        return figure;
    }
    let e0 = run.energies[0];
    let scale = e0.abs().max(f64::MIN_POSITIVE);
    let work = |k: usize| run.work.as_ref().map_or(0.0, |w| w[k]);
    let balance: Vec<(f64, f64)> = states
        .iter()
        .enumerate()
        .skip(1)
        .map(|(k, s)| (s.time, (run.energies[k] - e0 - work(k)).abs() / scale))
        .collect();
    let label = if run.work.is_some() {
        "energy balance |E − E₀ − W|/|E₀|"
    } else {
        "energy error |E − E₀|/|E₀|"
    };
    let mut series = vec![Series {
        label: label.into(),
        points: balance,
        style: Style::Line,
        color: 0,
    }];
    if run.work.is_none() {
        let components = |k: usize| -> Vec<f64> {
            match (&run.motion, conserved) {
                (Some(m), Conserved::AngularAboutOrigin) => {
                    m[k].spatial_momentum.iter().take(3).copied().collect()
                }
                (Some(m), _) => m[k].spatial_momentum.iter().copied().collect(),
                (None, Conserved::Along(d)) => vec![states[k].spatial_momentum().dot(&d)],
                (None, _) => states[k].spatial_momentum().iter().copied().collect(),
            }
        };
        let p0 = components(0);
        let size = p0.iter().map(|x| x.abs()).fold(f64::MIN_POSITIVE, f64::max);
        let drift = (1..states.len())
            .map(|k| {
                let d = components(k)
                    .iter()
                    .zip(&p0)
                    .map(|(p, q)| (p - q).abs())
                    .fold(0.0, f64::max);
                (states[k].time, d / size)
            })
            .collect();
        series.push(Series {
            label: "momentum drift (conserved components)".into(),
            points: drift,
            style: Style::Line,
            color: 1,
        });
    }
    figure.series = series;
    figure
}

#[cfg(test)]
mod tests {
    use super::*;
    use lgsvi_experiments::record::record;
    use lgsvi_mechanics::lie::SO3;
    use lgsvi_mechanics::{Forced, Inertia, Integrator, RigidBody, StepSettings};

    fn torqued_run() -> Recording {
        let body = RigidBody::new(Inertia::from_principal_moments([3.3, 2.5, 3.4]).unwrap());
        let system = Forced::new(
            body,
            lgsvi_mechanics::forces::BodyTorque(Vector3::new(0.1, -0.2, 0.05)),
        );
        let mut it = Integrator::new(
            system,
            StepSettings::new(0.5, 8).unwrap(),
            SO3::identity(),
            Vector3::new(-2.0, 1.9, -1.0),
        )
        .unwrap();
        record(&mut it, 3.0, 2, &mut |_| {}).unwrap()
    }

    #[test]
    fn every_number_comes_back_from_the_json_and_the_csv() {
        let run = torqued_run();
        let mut json = Vec::new();
        write_json(&run, &serde_json::json!({}), &mut json).unwrap();
        let doc: serde_json::Value = serde_json::from_slice(&json).unwrap();
        // Shortest round-trip digits: each number parses back to the same bits.
        for (k, s) in run.states.iter().enumerate() {
            assert_eq!(doc["times"][k].as_f64().unwrap(), s.time);
            for c in 0..3 {
                assert_eq!(doc["omega"][k][c].as_f64().unwrap(), s.velocity[c]);
            }
            assert_eq!(
                doc["work"][k].as_f64().unwrap(),
                run.work.as_ref().unwrap()[k]
            );
        }
        let mut csv = Vec::new();
        write_csv(&run, &mut csv).unwrap();
        let text = String::from_utf8(csv).unwrap();
        let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
        let work = header.iter().position(|h| *h == "work").unwrap();
        for (k, line) in text.lines().skip(1).enumerate() {
            let cells: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
            assert_eq!(cells[0], run.states[k].time);
            assert_eq!(cells[work], run.work.as_ref().unwrap()[k]);
        }
    }

    #[test]
    fn an_inconsistent_recording_is_refused_not_a_panic() {
        let mut run = torqued_run();
        run.energies.pop();
        let mut out = Vec::new();
        let error = write_csv(&run, &mut out).unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::InvalidInput);
        let error = write_json(&run, &serde_json::json!({}), &mut out).unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::InvalidInput);
        assert!(conservation_figure(&run, "x", Conserved::Spatial)
            .series
            .is_empty());
        run.states.clear();
        run.energies.clear();
        run.newton_iterations.clear();
        run.work = None;
        assert!(conservation_figure(&run, "x", Conserved::Spatial)
            .series
            .is_empty());
    }
}
