//! `lgsvi optimize --space`: a body in space (SE(3)) driven from a pose and velocity to
//! others by a body wrench at the least input energy or in the least time
//! ([`lgsvi_optimal::Manoeuvre`]),
//! written as JSON with optional figures of the torques, the forces, the centre of mass
//! and the attitude error.

use crate::error::{CliError, Result};
use crate::optimize::{input_series, InputShape, OptimizeOptions};
use lgsvi_mechanics::built_in::BuiltInSe3;
use lgsvi_mechanics::lie::{LieGroup, SE3, SO3};
use lgsvi_mechanics::{FreeBody, MechanicsError, OrbitingBody};
use lgsvi_optimal::{Manoeuvre, ManoeuvreSolution, OptimalError};
use nalgebra::{Vector3, Vector6};
use serde_json::json;

/// Runs `lgsvi optimize --space`.
pub fn run(options: &OptimizeOptions) -> Result<()> {
    refuse_slew_only(options)?;
    let minimum_time = options.cost == Some(crate::optimize::Cost::Time);
    if minimum_time {
        for (flag, given) in [
            ("--torque-max", options.torque_max.is_some()),
            ("--force-max", options.force_max.is_some()),
        ] {
            if !given {
                return Err(CliError::invalid(
                    flag,
                    "(none)",
                    "a minimum-time manoeuvre needs bounds on both the torque and the force \
                     (without one, the motion it drives takes no time): give --torque-max U \
                     (N·m) and --force-max F (N), one value or X,Y,Z",
                ));
            }
        }
    } else if options.t_end.is_none() {
        return Err(CliError::invalid(
            "--t-end",
            "(none)",
            "a minimum-energy manoeuvre takes a fixed duration: give --t-end T in seconds (or \
             --cost time with --torque-max and --force-max for the least time)",
        ));
    }
    let inertia = crate::optimize::inertia(options)?;
    let mass = options.mass.unwrap_or(1.0);
    let body_error = |error: MechanicsError| match &error {
        MechanicsError::InvalidSetting { name: "mu", .. }
        | MechanicsError::NonFinite { what: "mu", .. } => {
            CliError::invalid("--mu", format!("{:?}", options.mu), error.to_string())
        }
        _ => CliError::invalid("--mass", format!("{mass:?}"), error.to_string()),
    };
    let position0 = Vector3::from(options.position0.unwrap_or([0.0; 3]));
    let position_final = options.position_final.map_or(position0, Vector3::from);
    let body: BuiltInSe3 = match options.mu {
        None => FreeBody::new(inertia, mass).map_err(body_error)?.into(),
        Some(mu) => {
            let body = OrbitingBody::new(inertia, mass, mu).map_err(body_error)?;
            for (flag, position) in [
                ("--position0", position0),
                ("--position-final", position_final),
            ] {
                body.check_position(&position).map_err(|e| {
                    CliError::invalid(flag, format!("{:?}", position.as_slice()), e.to_string())
                })?;
            }
            body.into()
        }
    };
    let attitude0 = SO3::exp(&Vector3::from(options.attitude0.unwrap_or([0.0; 3])));
    let attitude_final = options
        .attitude_final
        .map_or(attitude0, |a| SO3::exp(&Vector3::from(a)));
    // The body velocity (Ω, v) with v = Rᵀ ẋ from the world-frame ẋ the flags give.
    let body_velocity = |attitude: &SO3, omega: Option<[f64; 3]>, velocity: Option<[f64; 3]>| {
        let v = attitude.matrix().transpose() * Vector3::from(velocity.unwrap_or([0.0; 3]));
        let w = omega.unwrap_or([0.0; 3]);
        Vector6::new(w[0], w[1], w[2], v.x, v.y, v.z)
    };
    let start = (
        SE3::new(attitude0, position0),
        body_velocity(&attitude0, options.omega0, options.velocity0),
    );
    let target = (
        SE3::new(attitude_final, position_final),
        body_velocity(&attitude_final, options.omega_final, options.velocity_final),
    );
    let (steps, nodes) = (options.steps.unwrap_or(40), options.nodes.unwrap_or(10));
    let t_end = match options.t_end {
        Some(t_end) => t_end,
        // The least time's first guess; where it has none (a bound refused, the target
        // being the start) the solver's check names the setting.
        None => lgsvi_optimal::separate_bang_bang_time(
            &inertia,
            mass,
            &start,
            &target,
            options.torque_max.unwrap_or([0.0; 3]),
            options.force_max.unwrap_or([0.0; 3]),
        )
        .unwrap_or(1.0),
    };
    let mut manoeuvre = Manoeuvre::new(body, t_end)
        .from(start.0, start.1)
        .to(target.0, target.1)
        .steps(steps)
        .nodes(nodes)
        .cost(if minimum_time {
            lgsvi_optimal::Cost::Time
        } else {
            lgsvi_optimal::Cost::Energy
        });
    if let Some(bound) = options.torque_max {
        manoeuvre = manoeuvre.torque_max(bound);
    }
    if let Some(bound) = options.force_max {
        manoeuvre = manoeuvre.force_max(bound);
    }
    if options.disturbance.is_some() || options.disturbance_force.is_some() {
        manoeuvre = manoeuvre.disturbance(
            options.disturbance.unwrap_or([0.0; 3]),
            options.disturbance_force.unwrap_or([0.0; 3]),
        );
    }
    if options.inputs == Some(InputShape::Polynomial) {
        manoeuvre = manoeuvre.inputs(lgsvi_optimal::Inputs::Polynomial);
    }
    if let Some(tolerance) = options.tolerance {
        manoeuvre = manoeuvre.tolerance(tolerance);
    }
    if let Some(iterations) = options.max_iterations {
        manoeuvre = manoeuvre.max_iterations(iterations);
    }
    let with_space = "with --space";
    if let Some(weights) = &options.terminal_cost {
        manoeuvre = manoeuvre.terminal_cost(crate::optimize::weight_count(
            "--terminal-cost",
            &weights.0,
            with_space,
        )?);
    }
    if let Some((reference, weights)) = crate::optimize::tracking(
        options,
        steps,
        crate::optimize::reference_motion_in_space,
        with_space,
    )? {
        manoeuvre = manoeuvre.track(reference, weights);
    }
    if !options.quiet {
        let angle = attitude0
            .inverse()
            .compose(&attitude_final)
            .log()
            .norm()
            .to_degrees();
        let distance = (position_final - position0).norm();
        let time = if minimum_time {
            format!("in the least time (first guess {t_end:.6} s)")
        } else {
            format!("in {t_end} s")
        };
        eprintln!(
            "optimize: a manoeuvre in space ({distance:.6} m, {angle:.1}°) {time}, \
             {steps} steps of {nodes} nodes …"
        );
    }
    let solution = manoeuvre
        .solve()
        .map_err(|error| named(error, options, t_end))?;
    if !options.quiet {
        let unit = if minimum_time { " s" } else { "" };
        crate::optimize::report(solution.cost, unit, &solution.statistics);
    }
    let times: Vec<f64> = solution.states.iter().map(|s| s.time).collect();
    let error_deg: Vec<f64> = solution
        .states
        .iter()
        .map(|s| {
            s.attitude()
                .inverse()
                .compose(&attitude_final)
                .log()
                .norm()
                .to_degrees()
        })
        .collect();
    let vector = |v: Vector3<f64>| [v.x, v.y, v.z];
    let wrench = |u: &Vector6<f64>| [u[0], u[1], u[2], u[3], u[4], u[5]];
    let output = json!({
        "command": "optimize",
        "system": if options.mu.is_some() { "orbiting-body" } else { "se3-body" },
        "cost": solution.cost,
        "cost_kind": if minimum_time { "time: the final time in s" } else { "energy: the integral of |tau|^2 + |f|^2 dt" },
        "t_end": solution.t_end,
        "h": solution.h,
        "steps": steps,
        "nodes": nodes,
        "converged": solution.converged,
        "iterations": solution.statistics.iterations,
        "kkt_residuals": solution.statistics.kkt_residuals,
        "time_s": solution.statistics.time_s,
        "mass": mass,
        "mu": options.mu,
        "torque_max": options.torque_max,
        "force_max": options.force_max,
        "disturbance": options.disturbance,
        "disturbance_force": options.disturbance_force,
        "multipliers": solution.multipliers,
        "t": times,
        "inputs": solution.inputs.iter().map(wrench).collect::<Vec<_>>(),
        "inputs_at_points": solution.inputs_at_points.iter().map(|step| step.iter().map(wrench).collect::<Vec<_>>()).collect::<Vec<_>>(),
        "inputs_kind": "body wrench (tau_1, tau_2, tau_3, f_1, f_2, f_3), body frame, N·m and N",
        "quadrature_nodes": solution.quadrature_nodes,
        "R": solution.states.iter().map(|s| s.attitude().to_row_major()).collect::<Vec<_>>(),
        "omega": solution.states.iter().map(|s| vector(s.angular_velocity())).collect::<Vec<_>>(),
        "x": solution.states.iter().map(|s| vector(s.position())).collect::<Vec<_>>(),
        "velocity": solution.states.iter().map(|s| vector(s.linear_velocity())).collect::<Vec<_>>(),
        "attitude_error_deg": error_deg,
        "position_error": solution.states.iter().map(|s| (position_final - s.position()).norm()).collect::<Vec<_>>(),
    });
    let drawn = match options.plot {
        Some(_) => figures(&solution, &times, &error_deg),
        None => Vec::new(),
    };
    crate::optimize::write(options, &output, drawn)
}

/// The slew's flags, which a manoeuvre in space does not take.
fn refuse_slew_only(options: &OptimizeOptions) -> Result<()> {
    let given = [
        ("--gravity", options.gravity.is_some()),
        ("--com", options.com.is_some()),
        ("--gravity-direction", options.gravity_direction.is_some()),
        ("--wheels", options.wheels),
        ("--wheel-axes", options.wheel_axes.is_some()),
        ("--wheel-inertia", options.wheel_inertia.is_some()),
        ("--wheel-speeds0", options.wheel_speeds0.is_some()),
    ];
    for (flag, given) in given {
        if given {
            return Err(CliError::invalid(
                flag,
                "with --space",
                "a manoeuvre in space drives a free or orbiting body by a body wrench; drop \
                 this flag (or --space for a slew)",
            ));
        }
    }
    Ok(())
}

/// The space flags, which a slew does not take.
pub fn refuse_space_only(options: &OptimizeOptions) -> Result<()> {
    let given = [
        ("--mu", options.mu.is_some()),
        ("--position0", options.position0.is_some()),
        ("--position-final", options.position_final.is_some()),
        ("--velocity0", options.velocity0.is_some()),
        ("--velocity-final", options.velocity_final.is_some()),
        ("--force-max", options.force_max.is_some()),
        ("--disturbance-force", options.disturbance_force.is_some()),
    ];
    for (flag, given) in given {
        if given {
            return Err(CliError::invalid(
                flag,
                "given",
                "it describes a body in space: give --space as well",
            ));
        }
    }
    Ok(())
}

/// A solver's error naming the flag to change (`t_end`: the time given, or the first guess).
fn named(error: OptimalError, options: &OptimizeOptions, t_end: f64) -> CliError {
    let list = |v: Option<[f64; 3]>| {
        v.map_or("(none)".to_string(), |v| {
            v.iter()
                .map(|x| format!("{x:?}"))
                .collect::<Vec<_>>()
                .join(",")
        })
    };
    let (flag, value): (&'static str, String) = match &error {
        OptimalError::InvalidSetting { name, value, .. } => match *name {
            "t_end" => ("--t-end", value.clone()),
            "steps" => ("--steps", value.clone()),
            "torque_max" => ("--torque-max", list(options.torque_max)),
            "force_max" => ("--force-max", list(options.force_max)),
            "disturbance" => (
                "--disturbance/--disturbance-force",
                format!(
                    "{}; {}",
                    list(options.disturbance),
                    list(options.disturbance_force)
                ),
            ),
            "tolerance" => ("--tolerance", value.clone()),
            "start" => (
                "--attitude0/--omega0/--position0/--velocity0",
                value.clone(),
            ),
            "target" => (
                "--attitude-final/--omega-final/--position-final/--velocity-final",
                value.clone(),
            ),
            "terminal_cost" => ("--terminal-cost", value.clone()),
            "track" => ("--track/--track-weights", value.clone()),
            "cost" => ("--cost", "time".into()),
            "inputs" => ("--inputs", "polynomial".into()),
            _ => ("--steps", value.clone()),
        },
        OptimalError::Infeasible { bounded: true, .. } => (
            "--torque-max/--force-max",
            format!("{}; {}", list(options.torque_max), list(options.force_max)),
        ),
        OptimalError::Infeasible { .. } | OptimalError::Subproblem(_) => (
            "--t-end/--mass/--steps",
            format!(
                "{:?}, {:?}, {}",
                t_end,
                options.mass.unwrap_or(1.0),
                options.steps.unwrap_or(40)
            ),
        ),
        OptimalError::NotConverged { .. } => (
            "--max-iterations",
            options.max_iterations.unwrap_or(500).to_string(),
        ),
        OptimalError::Mechanics(MechanicsError::InvalidSetting { name: "nodes", .. }) => {
            ("--nodes", options.nodes.unwrap_or(10).to_string())
        }
        OptimalError::Mechanics(MechanicsError::LeftModel { .. }) => {
            ("--position0/--position-final/--t-end", String::new())
        }
        _ => ("--steps", options.steps.unwrap_or(40).to_string()),
    };
    let reason = crate::optimize::recalling_disturbances(
        &error,
        &[
            ("--disturbance", options.disturbance),
            ("--disturbance-force", options.disturbance_force),
        ],
    );
    CliError::invalid(flag, value, reason)
}

/// The torques, the forces, the centre of mass and the attitude error over time.
fn figures(
    solution: &ManoeuvreSolution,
    times: &[f64],
    error_deg: &[f64],
) -> Vec<(&'static str, lgsvi_plot::Figure)> {
    let figure = |title: &str, y: &str, series| lgsvi_plot::Figure {
        title: title.into(),
        x_label: "t (s)".into(),
        y_label: y.into(),
        x_log: false,
        y_log: false,
        series,
        hlines: vec![],
    };
    let shape = if solution.inputs_at_points.is_empty() {
        "held over each step"
    } else {
        "at each step's Gauss points"
    };
    let inputs = |offset: usize, name: &str| {
        (0..3)
            .map(|i| {
                input_series(
                    &solution.inputs,
                    &solution.inputs_at_points,
                    &solution.quadrature_nodes,
                    solution.h,
                    times,
                    offset + i,
                    i,
                    name,
                )
            })
            .collect()
    };
    let line = |label: String, points: Vec<(f64, f64)>, color: usize| lgsvi_plot::Series {
        label,
        points,
        style: lgsvi_plot::Style::Line,
        color,
    };
    let position = (0..3)
        .map(|i| {
            let points = solution
                .states
                .iter()
                .map(|s| (s.time, s.position()[i]))
                .collect();
            line(format!("x_{}", i + 1), points, i)
        })
        .collect();
    let error = vec![line(
        "angle to the target".into(),
        times
            .iter()
            .copied()
            .zip(error_deg.iter().copied())
            .collect(),
        0,
    )];
    vec![
        (
            "_torques",
            figure(
                &format!("optimal body torques ({shape})"),
                "τ (N·m)",
                inputs(0, "tau"),
            ),
        ),
        (
            "_forces",
            figure(
                &format!("optimal body forces ({shape})"),
                "f (N)",
                inputs(3, "f"),
            ),
        ),
        (
            "_position",
            figure("centre of mass (world frame)", "x (m)", position),
        ),
        (
            "_attitude_error",
            figure("attitude error", "angle to the target (deg)", error),
        ),
    ]
}
