//! `lgsvi linearize`: the exact linearisation of one step from simulate's initial state,
//! as JSON (`a`, `b` as lists of rows, the coordinates in words, the states before and
//! after the step).

use crate::config::SimulateOptions;
use crate::error::{CliError, Result};
use crate::files;
use crate::problem::Problem;
use clap::Args;
use lgsvi_mechanics::lie::{LieGroup, SE3, SO3};
use lgsvi_mechanics::{Coordinates, State, StepLinearization};
use nalgebra::DMatrix;
use serde_json::{json, Value};

/// The options of `lgsvi linearize`: simulate's system, initial state and step flags.
#[derive(Debug, Args)]
pub struct LinearizeOptions {
    #[command(flatten)]
    pub base: SimulateOptions,
    /// Write the matrices in momentum coordinates (θ, δμ) instead of (θ, ω).
    #[arg(long)]
    pub momentum: bool,
}

/// What the state and input coordinates are, in words.
const SO3_COORDINATES: &str = "state x = (θ, ω): the attitude perturbation θ in the body frame, \
    R = R̄ exp(θ̂), then the body angular velocity perturbation ω, Ω = Ω̄ + ω; input u: a body \
    torque added to --torque (the nominal input), held over the step. x₊ ≈ A x + B u.";
const SO3_MOMENTUM: &str = "state x = (θ, δμ): the attitude perturbation θ in the body frame, \
    R = R̄ exp(θ̂), then the body angular momentum perturbation δμ, μ = μ̄ + δμ; input u: a body \
    torque added to --torque (the nominal input), held over the step. x₊ ≈ A x + B u.";
const SE3_COORDINATES: &str = "state x = (θ_R, δx, δΩ, δẋ): the attitude perturbation θ_R in \
    the body frame, R = R̄ exp(θ̂_R); the position x of the centre of mass, world frame; the body \
    angular velocity Ω; the velocity ẋ of the centre of mass, world frame. Input u = (τ, f): a \
    body wrench (torque, then force, body frame; τ added to --torque, the nominal input), held \
    over the step. x₊ ≈ A x + B u.";
const SE3_MOMENTUM: &str = "state x = (θ_R, θ_x, δμ): the perturbation g = ḡ exp(θ) of the pose \
    in the body frame (θ = (θ_R, θ_x), x = x̄ + R θ_x to first order), then the body momentum \
    perturbation δμ (angular, then linear); input u = (τ, f): a body wrench (torque, then force, \
    body frame; τ added to --torque, the nominal input), held over the step. x₊ ≈ A x + B u.";

const GYROSTAT_COORDINATES: &str = "state x = (θ, δφ, ω, δφ̇): the attitude perturbation θ in \
    the body frame, R = R̄ exp(θ̂); the wheel angles φ = φ̄ + δφ; the body angular velocity \
    Ω = Ω̄ + ω; the wheel rates (relative to the body) φ̇ = φ̄̇ + δφ̇. Input u = (τ, τ_m): an \
    external body torque, then the wheels' motor torques (added to --wheel-torque, the nominal \
    input), held over the step. x₊ ≈ A x + B u.";
const GYROSTAT_MOMENTUM: &str = "state x = (θ, δφ, δh, δp): the attitude perturbation θ in the \
    body frame, R = R̄ exp(θ̂); the wheel angles φ = φ̄ + δφ; the total angular momentum h in the \
    body frame; the wheels' axial momenta p. Input u = (τ, τ_m): an external body torque, then \
    the wheels' motor torques (added to --wheel-torque, the nominal input), held over the step. \
    x₊ ≈ A x + B u.";

/// Runs `lgsvi linearize`.
pub fn run(options: LinearizeOptions) -> Result<()> {
    let base = &options.base;
    for (flag, given, why) in [
        (
            "--t-end",
            base.t_end.is_some(),
            "linearize takes one step of --h",
        ),
        ("--every", base.every.is_some(), "linearize takes one step"),
        ("--format", base.format.is_some(), "linearize writes JSON"),
        ("--plot", base.plot.is_some(), "linearize draws nothing"),
        (
            "--exact",
            base.exact,
            "linearize linearises the integrator's step",
        ),
        (
            "--check",
            base.check,
            "linearize takes one step and measures nothing",
        ),
        (
            "--no-check",
            base.no_check,
            "linearize takes one step of fixed --h and --nodes",
        ),
        (
            "--tol",
            base.tol.is_some(),
            "linearize takes one step of fixed --h and --nodes",
        ),
    ] {
        if given {
            return Err(CliError::SimulateOnly { flag, why });
        }
    }
    let out = base.out.clone();
    let momentum = options.momentum;
    let (problem, _) = Problem::resolve(options.base)?;
    let coordinates = if momentum {
        Coordinates::Momentum
    } else {
        Coordinates::Velocity
    };
    let mut report = json!({
        "command": "linearize",
        "description": problem.description,
        "settings": Problem::settings_json(&problem.settings, problem.settings.step(), 1),
        "coordinates_kind": if momentum { "momentum" } else { "velocity" },
    });
    if let Some(wheels) = &problem.wheels {
        use crate::problem::AnyGyrostat;
        macro_rules! linearise {
            ($craft:expr, $k:literal, $d:literal) => {{
                let step = wheels
                    .integrator::<$k, $d>(
                        $craft,
                        problem.settings,
                        problem.attitude0,
                        problem.omega0,
                    )?
                    .linearize()?;
                report["a"] = rows(step.a(coordinates));
                report["b"] = rows(step.b(coordinates));
                report["before"] = gyrostat_state(&step.start);
                report["after"] = gyrostat_state(&step.end);
                report["step"] = step_json(&step);
            }};
        }
        match wheels.system {
            AnyGyrostat::One(craft) => linearise!(craft, 1, 4),
            AnyGyrostat::Two(craft) => linearise!(craft, 2, 5),
            AnyGyrostat::Three(craft) => linearise!(craft, 3, 6),
            AnyGyrostat::Four(craft) => linearise!(craft, 4, 7),
        }
        report["coordinates"] = if momentum {
            GYROSTAT_MOMENTUM
        } else {
            GYROSTAT_COORDINATES
        }
        .into();
    } else if let Some(motion) = &problem.motion {
        let step = motion.integrator(problem.settings)?.linearize()?;
        let (a, b) = if momentum {
            (step.a(coordinates).clone(), step.b(coordinates).clone())
        } else {
            step.world_frame()
        };
        report["coordinates"] = if momentum {
            SE3_MOMENTUM
        } else {
            SE3_COORDINATES
        }
        .into();
        report["a"] = rows(&a);
        report["b"] = rows(&b);
        report["before"] = se3_state(&step.start);
        report["after"] = se3_state(&step.end);
        report["step"] = step_json(&step);
    } else {
        let step = problem.integrator(problem.settings)?.linearize()?;
        report["coordinates"] = if momentum {
            SO3_MOMENTUM
        } else {
            SO3_COORDINATES
        }
        .into();
        report["a"] = rows(step.a(coordinates));
        report["b"] = rows(step.b(coordinates));
        report["before"] = so3_state(&step.start);
        report["after"] = so3_state(&step.end);
        report["step"] = step_json(&step);
    }
    let text = serde_json::to_string_pretty(&report)? + "\n";
    match &out {
        Some(path) => files::write(path, text.as_bytes()),
        None => {
            use std::io::Write;
            let stdout = std::io::stdout();
            let mut lock = stdout.lock();
            lock.write_all(text.as_bytes())
                .and_then(|()| lock.flush())
                .map_err(CliError::Stdout)
        }
    }
}

/// The step's size, for the record.
fn step_json<E, const D: usize>(step: &StepLinearization<E, D>) -> Value {
    json!({ "h": step.h, "nodes": step.nodes })
}

/// A matrix as a list of rows.
fn rows(m: &DMatrix<f64>) -> Value {
    Value::Array(
        m.row_iter()
            .map(|row| row.iter().copied().collect::<Vec<f64>>().into())
            .collect(),
    )
}

/// `R` row-major.
fn attitude(r: &SO3) -> Vec<f64> {
    let m = r.matrix();
    (0..9).map(|i| m[(i / 3, i % 3)]).collect()
}

fn so3_state(s: &State<SO3, 3>) -> Value {
    json!({
        "t": s.time,
        "attitude": attitude(&s.configuration),
        "omega": s.velocity.as_slice(),
        "momentum": s.momentum.as_slice(),
    })
}

fn se3_state(s: &State<SE3, 6>) -> Value {
    let r = s.configuration.rotation();
    let v = s.velocity.fixed_rows::<3>(3).into_owned();
    let xdot = r.to_matrix() * v;
    json!({
        "t": s.time,
        "attitude": attitude(r),
        "position": s.configuration.translation().as_slice(),
        "omega": s.velocity.fixed_rows::<3>(0).iter().copied().collect::<Vec<f64>>(),
        "velocity": xdot.as_slice(),
        "momentum": s.momentum.as_slice(),
    })
}

fn gyrostat_state<const K: usize, const D: usize>(
    s: &State<lgsvi_mechanics::gyrostat::BodyWheels<f64, K>, D>,
) -> Value {
    json!({
        "t": s.time,
        "attitude": attitude(&s.configuration.attitude),
        "wheel_angles": s.configuration.wheels.as_slice(),
        "omega": s.velocity.fixed_rows::<3>(0).iter().copied().collect::<Vec<f64>>(),
        "wheel_speeds": s.velocity.iter().skip(3).copied().collect::<Vec<f64>>(),
        "momentum": s.momentum.as_slice(),
    })
}
