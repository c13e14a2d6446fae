//! A step's linearisation as `lgsvi linearize` writes it: `a` and `b` as lists of rows, the
//! coordinates in words, and the states before and after the step, for the rigid body on
//! SO(3), the body in space on SE(3) and the gyrostat on SO(3) × ℝᴷ.

use lgsvi_experiments::scenario::Scenario;
use lgsvi_experiments::Subject;
use lgsvi_mechanics::gyrostat::BodyWheels;
use lgsvi_mechanics::lie::{LieGroup, SE3, SO3};
use lgsvi_mechanics::linearization::{Coordinates, StepLinearization};
use lgsvi_mechanics::{MechanicsError, State, StepSettings};
use nalgebra::DMatrix;
use serde_json::{json, Value};

/// A configuration whose states `lgsvi linearize` writes, with its coordinates in words.
pub trait Described: Sized {
    /// The state as JSON: time, attitude (row-major), the group's other coordinates, the
    /// velocities and the momentum.
    fn state_json<const D: usize>(state: &State<Self, D>) -> Value;

    /// What `x` and `u` of `x₊ ≈ A x + B u` are: in velocity coordinates, or (with
    /// `momentum`) in momentum coordinates.
    fn coordinates(momentum: bool) -> &'static str;
}

/// `R` row-major.
fn attitude(r: &SO3) -> Vec<f64> {
    let m = r.matrix();
    (0..9).map(|i| m[(i / 3, i % 3)]).collect()
}

impl Described for SO3 {
    fn state_json<const D: usize>(s: &State<SO3, D>) -> Value {
        json!({
            "t": s.time,
            "attitude": attitude(&s.configuration),
            "omega": s.velocity.as_slice(),
            "momentum": s.momentum.as_slice(),
        })
    }

    fn coordinates(momentum: bool) -> &'static str {
        if momentum {
            "state x = (θ, δμ): the attitude perturbation θ in the body frame, \
             R = R̄ exp(θ̂), then the body angular momentum perturbation δμ, μ = μ̄ + δμ; input \
             u: a body torque added to --torque (the nominal input), held over the step. \
             x₊ ≈ A x + B u."
        } else {
            "state x = (θ, ω): the attitude perturbation θ in the body frame, R = R̄ exp(θ̂), \
             then the body angular velocity perturbation ω, Ω = Ω̄ + ω; input u: a body torque \
             added to --torque (the nominal input), held over the step. x₊ ≈ A x + B u."
        }
    }
}

impl Described for SE3 {
    fn state_json<const D: usize>(s: &State<SE3, D>) -> Value {
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

    fn coordinates(momentum: bool) -> &'static str {
        if momentum {
            "state x = (θ_R, θ_x, δμ): the perturbation g = ḡ exp(θ) of the pose in the body \
             frame (θ = (θ_R, θ_x), x = x̄ + R θ_x to first order), then the body momentum \
             perturbation δμ (angular, then linear); input u = (τ, f): a body wrench (torque, \
             then force, body frame; τ added to --torque, the nominal input), held over the \
             step. x₊ ≈ A x + B u."
        } else {
            "state x = (θ_R, δx, δΩ, δẋ): the attitude perturbation θ_R in the body frame, \
             R = R̄ exp(θ̂_R); the position x of the centre of mass, world frame; the body \
             angular velocity Ω; the velocity ẋ of the centre of mass, world frame. Input \
             u = (τ, f): a body wrench (torque, then force, body frame; τ added to --torque, \
             the nominal input), held over the step. x₊ ≈ A x + B u."
        }
    }
}

impl<const K: usize> Described for BodyWheels<f64, K> {
    fn state_json<const D: usize>(s: &State<Self, D>) -> Value {
        json!({
            "t": s.time,
            "attitude": attitude(&s.configuration.attitude),
            "wheel_angles": s.configuration.wheels.as_slice(),
            "omega": s.velocity.fixed_rows::<3>(0).iter().copied().collect::<Vec<f64>>(),
            "wheel_speeds": s.velocity.iter().skip(3).copied().collect::<Vec<f64>>(),
            "momentum": s.momentum.as_slice(),
        })
    }

    fn coordinates(momentum: bool) -> &'static str {
        if momentum {
            "state x = (θ, δφ, δh, δp): the attitude perturbation θ in the body frame, \
             R = R̄ exp(θ̂); the wheel angles φ = φ̄ + δφ; the total angular momentum h in the \
             body frame; the wheels' axial momenta p. Input u = (τ, τ_m): an external body \
             torque, then the wheels' motor torques (added to --wheel-torque, the nominal \
             input), held over the step. x₊ ≈ A x + B u."
        } else {
            "state x = (θ, δφ, ω, δφ̇): the attitude perturbation θ in the body frame, \
             R = R̄ exp(θ̂); the wheel angles φ = φ̄ + δφ; the body angular velocity Ω = Ω̄ + ω; \
             the wheel rates (relative to the body) φ̇ = φ̄̇ + δφ̇. Input u = (τ, τ_m): an \
             external body torque, then the wheels' motor torques (added to --wheel-torque, \
             the nominal input), held over the step. x₊ ≈ A x + B u."
        }
    }
}

/// A matrix as a list of rows.
pub fn rows(m: &DMatrix<f64>) -> Value {
    Value::Array(
        m.row_iter()
            .map(|row| row.iter().copied().collect::<Vec<f64>>().into())
            .collect(),
    )
}

/// Writes `step`'s `a`, `b` and `p` (as given: the caller picks the coordinates), the
/// parameters' names, the coordinates in words, the states before and after, and the
/// step's size into `report`.
pub fn fill<E: Described, const D: usize>(
    report: &mut Value,
    step: &StepLinearization<E, D>,
    (a, b, p): (&DMatrix<f64>, &DMatrix<f64>, Option<&DMatrix<f64>>),
    momentum: bool,
) {
    report["a"] = rows(a);
    report["b"] = rows(b);
    if let Some(p) = p {
        report["p"] = rows(p);
        report["parameters"] = step.parameter_names().into();
    }
    report["before"] = E::state_json(&step.start);
    report["after"] = E::state_json(&step.end);
    report["step"] = json!({ "h": step.h, "nodes": step.nodes });
    let mut coordinates = E::coordinates(momentum).to_string();
    if p.is_some() {
        coordinates.push_str(
            " With the system's physical parameters (\"parameters\": the body-frame inertia \
             tensor's entries, J_xy moving both of its symmetric places, then, where the \
             system has them, the mass or the wheels' inertias), x₊ ≈ A x + B u + P δp, \
             P = \"p\" (the start state held in these coordinates).",
        );
    }
    report["coordinates"] = coordinates.into();
}

/// Linearises one step of `scenario` with `settings` from its start and writes it into
/// `report` ([`fill`]): in momentum coordinates with `momentum`, else in velocity
/// coordinates (an SE(3) body's in the world frame, [`StepLinearization::world_frame`]).
///
/// # Errors
/// The integrator's construction or the step's.
pub fn linearize(
    scenario: &Scenario,
    settings: StepSettings,
    momentum: bool,
    report: &mut Value,
) -> Result<(), MechanicsError> {
    let coordinates = match momentum {
        true => Coordinates::Momentum,
        false => Coordinates::Velocity,
    };
    let (attitude, omega) = (scenario.attitude0, scenario.omega0);
    if let Some(wheels) = &scenario.wheels {
        lgsvi_experiments::each_gyrostat!(wheels.system, (craft, K, D) => {
            let step = wheels
                .integrator::<K, D>(craft, settings, attitude, omega)?
                .linearize_with_parameters()?;
            fill(
                report,
                &step,
                (step.a(coordinates), step.b(coordinates), step.p(coordinates)),
                momentum,
            );
        });
    } else if let Some(motion) = &scenario.motion {
        let step = motion.integrator(settings)?.linearize_with_parameters()?;
        let (a, b, p) = match momentum {
            true => (
                step.a(coordinates).clone(),
                step.b(coordinates).clone(),
                step.p(coordinates).cloned(),
            ),
            false => {
                let (a, b) = step.world_frame();
                (a, b, step.world_frame_parameters())
            }
        };
        fill(report, &step, (&a, &b, p.as_ref()), momentum);
    } else {
        let step = Subject::integrator(scenario, settings)?.linearize_with_parameters()?;
        fill(
            report,
            &step,
            (
                step.a(coordinates),
                step.b(coordinates),
                step.p(coordinates),
            ),
            momentum,
        );
    }
    Ok(())
}
