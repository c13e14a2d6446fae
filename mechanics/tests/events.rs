//! Events located on the steps' curves against closed forms: an axisymmetric body's
//! `Ω₁(t) = a cos(λt)`, a spherical body's rotation angle, and a function of time alone
//! with several crossings per step.

use lgsvi_mechanics::events::{Direction, Event, Events};
use lgsvi_mechanics::prelude::*;
use lgsvi_mechanics::stepper::Recorder;
use std::f64::consts::PI;

/// The located times' relative error allowed: the 1e-12. The curves resolve the
/// motion to ~1e-15 at these settings, and the root of the fitted series is polished to a
/// few ulps, so the error is the state's error over the function's slope.
const TIME_TOLERANCE: f64 = 1e-12;

/// `J = diag(1, 1, 2)`, `Ω₀ = (0.3, 0, 1.5)`: `Ω₁ = 0.3 cos(λt)`, `λ = (J₃ − J₁)Ω₃/J₁ = 1.5`.
fn axisymmetric(h: f64, n: usize) -> Result<Integrator<RigidBody>, MechanicsError> {
    let body = RigidBody::new(Inertia::from_principal_moments([1.0, 1.0, 2.0])?);
    Integrator::new(
        body,
        StepSettings::new(h, n)?,
        SO3::identity(),
        Vector3::new(0.3, 0.0, 1.5),
    )
}

const LAMBDA: f64 = 1.5;

#[test]
fn every_crossing_of_an_axisymmetric_bodys_rate_is_located() -> Result<(), MechanicsError> {
    // t_end = 20 is not a whole number of steps (66 of 0.3 reach 19.8): the last step,
    // shortened to 0.2, holds the crossing at (π/2 + 9π)/λ = 19.897.
    let mut integrator = axisymmetric(0.3, 14)?;
    let mut events = Events::new(vec![Event::new(
        "omega_1",
        |_, _: &SO3, w: &Vector3<f64>| w.x,
    )]);
    integrator.drive_until(20.0, &mut events)?;
    let hits = events.hits();
    assert_eq!(hits.len(), 10, "crossings at (π/2 + kπ)/λ, k = 0..9");
    for (k, hit) in hits.iter().enumerate() {
        let exact = (PI / 2.0 + k as f64 * PI) / LAMBDA;
        assert!(
            (hit.time - exact).abs() <= TIME_TOLERANCE * exact,
            "crossing {k}: {} against {exact}",
            hit.time
        );
        let expected = if k % 2 == 0 {
            Direction::Falling
        } else {
            Direction::Rising
        };
        assert_eq!(hit.direction, expected);
        assert!(hit.velocity.x.abs() < 1e-14);
        assert_eq!(hit.event, 0);
    }
    assert!(!events.stopped());
    assert!((integrator.state().time - 20.0).abs() < 1e-12);
    assert!(hits[9].time > 19.8);
    Ok(())
}

#[test]
fn directions_filter_and_a_terminal_event_stops_after_its_step() -> Result<(), MechanicsError> {
    let mut integrator = axisymmetric(0.5, 14)?;
    let mut events = Events::new(vec![
        Event::new("omega_1 rises", |_, _: &SO3, w: &Vector3<f64>| w.x).rising(),
        Event::new("omega_2 falls", |_, _: &SO3, w: &Vector3<f64>| w.y)
            .falling()
            .terminal(),
    ]);
    // Ω₂ = 0.3 sin(λt) falls through 0 at π/λ = 2.094; Ω₁ rises at 3π/(2λ) = 3.14 (after).
    let mut recorder = Recorder::new(integrator.state(), 0, 1);
    let taken = integrator.drive_until(10.0, &mut (&mut recorder, &mut events))?;
    assert!(events.stopped());
    let hits = events.hits();
    assert_eq!(hits.len(), 1, "{hits:?}");
    let exact = PI / LAMBDA;
    assert_eq!(hits[0].event, 1);
    assert!((hits[0].time - exact).abs() <= TIME_TOLERANCE * exact);
    // The run stopped after the step holding the event: t = 2.5, five steps.
    assert_eq!(taken, 5);
    assert_eq!(integrator.state().time, 2.5);
    assert_eq!(recorder.trajectory().states.len(), 6);
    Ok(())
}

#[test]
fn a_configuration_event_of_a_spherical_body() -> Result<(), MechanicsError> {
    // J = I, Ω = (0, 0, w): R(t) = exp(t w ẑ), R₁₁ = cos(wt) falls through 0 at π/(2w).
    let w = 0.9;
    let body = RigidBody::new(Inertia::from_principal_moments([1.0, 1.0, 1.0])?);
    let mut integrator = Integrator::new(
        body,
        StepSettings::new(0.7, 10)?,
        SO3::identity(),
        Vector3::new(0.0, 0.0, w),
    )?;
    let mut events = Events::new(vec![Event::new("R_11", |_, r: &SO3, _: &Vector3<f64>| {
        r.matrix()[(0, 0)]
    })
    .falling()]);
    integrator.drive_until(8.0, &mut events)?;
    let exact = PI / (2.0 * w);
    let hit = &events.hits()[0];
    assert!((hit.time - exact).abs() <= TIME_TOLERANCE * exact);
    assert!(hit.configuration.matrix()[(0, 0)].abs() < 1e-14);
    // cos(wt) falls again at 5π/(2w) = 8.73 > 8: one hit.
    assert_eq!(events.hits().len(), 1);
    Ok(())
}

#[test]
fn several_crossings_within_one_step_are_each_found() -> Result<(), MechanicsError> {
    // g(t) = sin(15 t) crosses zero at kπ/15, about 2.4 times per step of h = 0.5; the
    // samples are h/12 = 0.042 apart, finer than the spacing 0.21 of the crossings.
    let mut integrator = axisymmetric(0.5, 12)?;
    let mut events = Events::new(vec![Event::new("sin", |t, _: &SO3, _: &Vector3<f64>| {
        (15.0 * t).sin()
    })]);
    integrator.drive_until(3.0, &mut events)?;
    let hits = events.hits();
    // Crossings at kπ/15 for k = 1..14 (k = 0 is the start, where g starts at 0; 14π/15 =
    // 2.93 < 3 < 15π/15).
    assert_eq!(
        hits.len(),
        14,
        "{:?}",
        hits.iter().map(|h| h.time).collect::<Vec<_>>()
    );
    for (k, hit) in hits.iter().enumerate() {
        let exact = (k + 1) as f64 * PI / 15.0;
        assert!(
            (hit.time - exact).abs() <= 4.0 * f64::EPSILON * exact,
            "{k}: {} against {exact}",
            hit.time
        );
    }
    Ok(())
}

#[test]
fn a_function_that_is_not_finite_is_an_error_naming_the_event() -> Result<(), MechanicsError> {
    let mut integrator = axisymmetric(0.5, 8)?;
    let mut events = Events::new(vec![Event::new("bad", |t, _: &SO3, _: &Vector3<f64>| {
        if t > 1.2 {
            f64::NAN
        } else {
            1.0
        }
    })]);
    let error = integrator.drive_until(3.0, &mut events).unwrap_err();
    let message = error.to_string();
    assert!(
        message.contains("event") && message.contains("\"bad\""),
        "{message}"
    );
    // The run stopped at the step whose curve gave the NaN (from t = 1.0).
    assert_eq!(integrator.state().time, 1.5);
    Ok(())
}

#[test]
fn long_steps_locate_through_the_methods_own_steps() -> Result<(), MechanicsError> {
    // h = 5/3 with 10 nodes: the step ends are accurate to ~4e-13 but the curve between
    // its nodes only to ~3e-7 in Ω₁ (a lower-order approximation there); the crossings are
    // refined by variational steps of the found length from each step's start, so they
    // meet the same 1e-12.
    let mut integrator = axisymmetric(5.0 / 3.0, 10)?;
    let mut events = Events::new(vec![Event::new(
        "omega_1",
        |_, _: &SO3, w: &Vector3<f64>| w.x,
    )]);
    integrator.drive_until(5.0, &mut events)?;
    let hits = events.hits();
    assert_eq!(hits.len(), 2);
    for (k, hit) in hits.iter().enumerate() {
        let exact = (PI / 2.0 + k as f64 * PI) / LAMBDA;
        assert!(
            (hit.time - exact).abs() <= TIME_TOLERANCE * exact,
            "{k}: {} against {exact}",
            hit.time
        );
        assert!(hit.velocity.x.abs() < 1e-12);
    }
    Ok(())
}

#[test]
fn a_function_that_is_not_finite_between_its_samples_is_named_too() -> Result<(), MechanicsError> {
    // NaN only on (0.61, 0.62), between the samples of the step [0.5, 1.0] (12 pieces of
    // 0.0417), where the function changes sign: the fit along the curve meets it.
    let mut integrator = axisymmetric(0.5, 12)?;
    let mut events = Events::new(vec![Event::new("odd", |t, _: &SO3, _: &Vector3<f64>| {
        if t > 0.61 && t < 0.62 {
            f64::NAN
        } else {
            t - 0.615
        }
    })]);
    let error = integrator.drive_until(3.0, &mut events).unwrap_err();
    let message = error.to_string();
    assert!(
        matches!(error, MechanicsError::NonFinite { .. })
            && message.contains("\"odd\"")
            && message.contains("between t = "),
        "{message}"
    );
    Ok(())
}

#[test]
fn a_function_that_jumps_through_zero_is_located_by_bisection() -> Result<(), MechanicsError> {
    // A switch at t = 0.6137 (no Chebyshev series resolves a jump): located to adjacent
    // doubles, and refined by the method's steps (the function of time is the same there).
    let switch = 0.6137;
    let mut integrator = axisymmetric(0.5, 12)?;
    let mut events = Events::new(vec![Event::new(
        "switch",
        move |t, _: &SO3, _: &Vector3<f64>| if t < switch { -1.0 } else { 1.0 },
    )]);
    integrator.drive_until(2.0, &mut events)?;
    let hits = events.hits();
    assert_eq!(hits.len(), 1);
    assert!(
        (hits[0].time - switch).abs() <= 4.0 * f64::EPSILON,
        "{}",
        hits[0].time
    );
    Ok(())
}
