//! A sampled PD attitude law with a torque limit in the loop (`control::PdLaw`, held
//! between samples by `experiments::control::SampledLaw`), against references that do not
//! come from the integrator: the exact motion of a sphere turned about a fixed axis under a
//! piecewise-constant torque (a quadratic in time between samples, the saturation applied
//! by hand); and, on an asymmetric body, the same law written as a regulator
//! (`control::Regulator` with the gain `[K I, C I]`) stepped by a hand loop of `set_input`.

use lgsvi_experiments::control::SampledLaw;
use lgsvi_experiments::record::Check;
use lgsvi_experiments::scenario::{Model, Scenario, Space, Wheels};
use lgsvi_experiments::stop::Watch;
use lgsvi_experiments::ExperimentError;
use lgsvi_lie::{LieGroup, SO3};
use lgsvi_mechanics::control::{PdLaw, Regulator};
use lgsvi_mechanics::{Inertia, Integrator, RigidBody, State, StepSettings};
use nalgebra::{DMatrix, Vector3};

fn target() -> SO3 {
    SO3::exp(&Vector3::new(0.4, -0.7, 1.1))
}

/// A sphere (`J = jI`) turned by `θ₀` about a fixed axis from the target, at rest: the
/// torque stays on the axis, so between samples `j θ'' = u` with `u` held, and
/// `θ(t_s + s) = θ_s + s ω_s + s² u_s / 2j`, `ω(t_s + s) = ω_s + s u_s / j`, with
/// `u_s = −sat_L(k θ_s + c ω_s)`. The step is exact for this motion up to rounding: about
/// a fixed axis the curve in the chart is the exponential chart's quadratic (the Cayley
/// chart's smooth image of it), which the spectral step resolves to rounding with 10
/// nodes over steps of 0.25.
#[test]
fn a_sphere_under_the_sampled_law_follows_the_held_torques_closed_form() {
    let (j, k, c, limit, theta0) = (2.5, 3.0, 2.5, 1.0, 2.0);
    let (h, period) = (0.25, 0.5);
    let axis = Vector3::new(1.0, -2.0, 2.0).normalize();
    let inertia = Inertia::from_principal_moments([j, j, j]).unwrap();
    let start = target() * SO3::exp(&(axis * theta0));
    let law = PdLaw::new(target(), k, c)
        .unwrap()
        .with_limit(limit)
        .unwrap();
    let scenario = Scenario::new(Model::RigidBody, inertia, start, Vector3::zeros())
        .unwrap()
        .with_control(SampledLaw::new(law, period).unwrap())
        .unwrap();
    let settings = StepSettings::new(h, 10).unwrap();
    let run = scenario
        .record(settings, Check::None, 20.0, 1, &Watch::NOTHING, &mut |_| {})
        .unwrap();
    assert_eq!(run.states.len(), 81);
    // The closed form, sample by sample.
    let (mut theta, mut omega) = (theta0, 0.0f64);
    let (mut saturated, mut linear) = (0, 0);
    let mut worst = 0.0f64;
    for sample in 0..40 {
        let demand = k * theta + c * omega;
        let u = -demand.clamp(-limit, limit);
        if demand.abs() > limit {
            saturated += 1;
        } else {
            linear += 1;
        }
        for sub in 0..=2 {
            let s = sub as f64 * h;
            let state = &run.states[2 * sample + sub];
            let exact_theta = theta + s * omega + s * s * u / (2.0 * j);
            let exact_omega = omega + s * u / j;
            let exact = target() * SO3::exp(&(axis * exact_theta));
            let attitude = (exact.inverse() * state.configuration).log().norm();
            let rate = (state.velocity - axis * exact_omega).norm();
            worst = worst.max(attitude).max(rate);
        }
        theta += period * omega + period * period * u / (2.0 * j);
        omega += period * u / j;
    }
    // Both regimes are exercised: the limit holds the first samples, the law then acts
    // linearly.
    assert!(
        saturated >= 3 && linear >= 20,
        "{saturated} saturated, {linear} linear"
    );
    // Rounding over 80 steps of order-one quantities: a few hundred ε.
    assert!(worst < 1e-13, "largest departure {worst:e}");
    // The closed form itself settles near the target by t = 20 (2e-3 rad: the sampled law
    // is stable at this period).
    assert!(theta.abs() < 1e-2, "θ(20) = {theta}");
}

/// The same law, unlimited, as a regulator about the target at rest: `u = −K (θ, Ω)` with
/// `K = [k I, c I]`, handed to `set_input` every third step by a hand loop. The sampled
/// run of `Scenario::record` must take the same steps with the same inputs.
#[test]
fn the_sampled_law_matches_a_regulator_stepped_by_hand() {
    let (k, c, h) = (1.5, 2.0, 0.2);
    let inertia = Inertia::from_principal_moments([2.0, 3.0, 4.5]).unwrap();
    let omega0 = Vector3::new(0.3, -0.5, 0.2);
    let law = PdLaw::new(target(), k, c).unwrap();
    let settings = StepSettings::new(h, 10).unwrap();
    let scenario = Scenario::new(Model::RigidBody, inertia, SO3::identity(), omega0)
        .unwrap()
        .with_control(SampledLaw::new(law, 3.0 * h).unwrap())
        .unwrap();
    let run = scenario
        .record(settings, Check::None, 30.0, 1, &Watch::NOTHING, &mut |_| {})
        .unwrap();

    let mut gain = DMatrix::zeros(3, 6);
    for i in 0..3 {
        gain[(i, i)] = k;
        gain[(i, i + 3)] = c;
    }
    let at_target = State {
        time: 0.0,
        configuration: target(),
        momentum: Vector3::zeros(),
        velocity: Vector3::zeros(),
    };
    let regulator = Regulator::new(at_target, Vector3::zeros(), gain).unwrap();
    let mut it =
        Integrator::new(RigidBody::new(inertia), settings, SO3::identity(), omega0).unwrap();
    let mut worst = 0.0f64;
    for step in 0..150 {
        if step % 3 == 0 {
            it.set_input(regulator.input(it.state())).unwrap();
        }
        it.step().unwrap();
        let state = &run.states[step + 1];
        let attitude = (it.state().configuration.inverse() * state.configuration)
            .log()
            .norm();
        worst = worst
            .max(attitude)
            .max((it.state().velocity - state.velocity).norm());
    }
    // The same steps from inputs formed in two ways (the law's `−kθ − cΩ` and the
    // regulator's matrix product), which may differ by rounding, a few ε per input,
    // carried by a stable loop (measured: identical to the last bit).
    assert!(worst < 1e-13, "largest difference {worst:e}");
    // And the loop points the body at its target (measured: 1.1e-3 rad left at t = 30).
    let left = law.error_angle(&it.state().configuration);
    assert!(left < 1e-2, "error left {left}");
}

#[test]
fn bad_controllers_are_refused_saying_what_to_change() {
    let message = |e: lgsvi_mechanics::MechanicsError| e.to_string();
    assert!(message(PdLaw::new(target(), -1.0, 1.0).unwrap_err()).contains("non-negative"));
    assert!(message(PdLaw::new(target(), 1.0, f64::NAN).unwrap_err()).contains("rate gain"));
    let law = PdLaw::new(target(), 1.0, 1.0).unwrap();
    for limit in [0.0, -1.0, f64::NAN] {
        assert!(message(law.with_limit(limit).unwrap_err()).contains("largest torque"));
    }
    assert!(SampledLaw::new(law, 0.0).is_err());
    assert!(SampledLaw::new(law, f64::INFINITY).is_err());

    // A period that is not a whole number of steps.
    let inertia = Inertia::from_principal_moments([2.0, 3.0, 4.0]).unwrap();
    let scenario = Scenario::new(Model::RigidBody, inertia, SO3::identity(), Vector3::zeros())
        .unwrap()
        .with_control(SampledLaw::new(law, 0.3).unwrap())
        .unwrap();
    let settings = StepSettings::new(0.2, 8).unwrap();
    let error = scenario
        .record(settings, Check::None, 1.0, 1, &Watch::NOTHING, &mut |_| {})
        .unwrap_err();
    assert!(
        matches!(
            error,
            ExperimentError::Parameter {
                parameter: "control",
                ..
            }
        ) && error.to_string().contains("whole number of steps"),
        "{error}"
    );

    // A gyrostat turns by its wheels.
    let wheels = Wheels::on(vec![Vector3::x(), Vector3::y(), Vector3::z()]);
    let gyrostat = Scenario::new(
        Model::Gyrostat(wheels),
        inertia,
        SO3::identity(),
        Vector3::zeros(),
    )
    .unwrap();
    let error = gyrostat
        .with_control(SampledLaw::new(law, 0.4).unwrap())
        .unwrap_err();
    assert!(error.to_string().contains("wheels"), "{error}");
}

/// On SE(3) the torque goes to the rotational inputs: a free body in space turns under the
/// law exactly as on SO(3) (its rotation does not feel its translation).
#[test]
fn on_se3_the_sampled_law_turns_the_body_as_on_so3() {
    let inertia = Inertia::from_principal_moments([2.0, 3.0, 4.5]).unwrap();
    let omega0 = Vector3::new(0.3, -0.5, 0.2);
    let law = PdLaw::new(target(), 1.5, 2.0)
        .unwrap()
        .with_limit(0.5)
        .unwrap();
    let control = SampledLaw::new(law, 0.4).unwrap();
    let settings = StepSettings::new(0.2, 10).unwrap();
    let space = Model::FreeInSpace(Space {
        mass: 3.0,
        position: Vector3::new(1.0, 2.0, 3.0),
        velocity: Vector3::new(0.1, 0.0, -0.2),
    });
    let record = |model| {
        Scenario::new(model, inertia, SO3::identity(), omega0)
            .unwrap()
            .with_control(control)
            .unwrap()
            .record(settings, Check::None, 8.0, 1, &Watch::NOTHING, &mut |_| {})
            .unwrap()
    };
    let (so3, se3) = (record(Model::RigidBody), record(space));
    let mut worst = 0.0f64;
    for (a, b) in so3.states.iter().zip(&se3.states) {
        worst = worst.max((a.configuration.inverse() * b.configuration).log().norm());
    }
    // The same rotational equations, solved beside a translation: rounding apart.
    assert!(worst < 1e-13, "largest difference {worst:e}");
    // The translation is free: straight and uniform.
    let motion = se3.motion.unwrap();
    let last = motion.last().unwrap();
    let expected = Vector3::new(1.0, 2.0, 3.0) + Vector3::new(0.1, 0.0, -0.2) * 8.0;
    assert!((last.position - expected).norm() < 1e-12);
}

/// A run checked against its companion (`Check::Measure`) takes the controller too: the
/// primary run is the unchecked run, bit for bit, and the companion's measured difference
/// is the integrator's error (the companion steps with the same held torques).
#[test]
fn a_checked_run_samples_the_law_in_both_runs() {
    let inertia = Inertia::from_principal_moments([2.0, 3.0, 4.5]).unwrap();
    let law = PdLaw::new(target(), 1.5, 2.0)
        .unwrap()
        .with_limit(0.5)
        .unwrap();
    let scenario = Scenario::new(
        Model::RigidBody,
        inertia,
        SO3::identity(),
        Vector3::new(0.3, -0.5, 0.2),
    )
    .unwrap()
    .with_control(SampledLaw::new(law, 0.5).unwrap())
    .unwrap();
    let settings = StepSettings::new(0.25, 10).unwrap();
    let record = |check| {
        scenario
            .record(settings, check, 10.0, 1, &Watch::NOTHING, &mut |_| {})
            .unwrap()
    };
    let (plain, checked) = (record(Check::None), record(Check::Measure));
    assert_eq!(plain.states, checked.states);
    let report = checked.estimates.unwrap().check.unwrap();
    // The companion (more nodes) steps with the same held torques: the two differ by the
    // integrator's error, far below the torques' effect on the motion (order 0.1 rad).
    assert!(report.difference < 1e-10, "{}", report.difference);
    assert!(plain.work.is_some(), "a controlled run records its work");
}
