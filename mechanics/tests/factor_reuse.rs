//! A step that starts from the Newton matrix an earlier step factored
//! (`StepSettings::with_factor_reuse`, the default): at a control loop's short steps it
//! must serve most steps (fewer factorisations than steps), solve them to the rounding
//! floor (the same trajectory as fresh Newton matrices to rounding, the exact free body
//! to the method's error, Noether's momenta to rounding), and leave longer steps alone.

use lgsvi_mechanics::exact::FreeRigidBodyExact;
use lgsvi_mechanics::group::GroupChart;
use lgsvi_mechanics::gyrostat::{BodyWheels, Gyrostat};
use lgsvi_mechanics::lie::{SE3, SO3};
use lgsvi_mechanics::linearization::Coordinates;
use lgsvi_mechanics::Stepper;
use lgsvi_mechanics::{
    HeavyTop, Inertia, Integrator, OrbitingBody, RigidBody, StepSettings, System,
};
use nalgebra::{Matrix3, SVector, Vector3};

fn inertia() -> Inertia {
    Inertia::from_principal_moments([0.5, 0.9, 0.7]).unwrap()
}

fn omega0() -> Vector3<f64> {
    Vector3::new(0.6, 0.1, -0.4)
}

/// Runs `steps` steps of `make(reuse)` with and without reuse; returns the two
/// integrators.
fn both<S, C, const D: usize>(
    make: impl Fn(bool) -> Integrator<S, C, D>,
    steps: usize,
) -> (Integrator<S, C, D>, Integrator<S, C, D>)
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
{
    let (mut reused, mut fresh) = (make(true), make(false));
    reused.run(steps, steps).unwrap();
    fresh.run(steps, steps).unwrap();
    (reused, fresh)
}

fn largest_difference<const D: usize>(a: &SVector<f64, D>, b: &SVector<f64, D>) -> f64 {
    (a - b).amax()
}

/// Short steps on SO(3), SE(3) and SO(3) × ℝ³: most steps are served by carried factors,
/// fresh matrices solve every step, and the two runs agree to rounding.
#[test]
fn short_steps_reuse_factors_and_take_the_same_trajectory() {
    let steps = 200;
    let top = HeavyTop::new(inertia(), 1.0, 0.3, Vector3::z(), Vector3::z()).unwrap();
    let (reused, fresh) = both(
        |reuse| {
            let settings = StepSettings::new(0.05, 8).unwrap().with_factor_reuse(reuse);
            let mut it = Integrator::new(top, settings, SO3::identity(), omega0()).unwrap();
            it.set_input(Vector3::new(0.001, 0.002, -0.001)).unwrap();
            it
        },
        steps,
    );
    let (r, f) = (reused.statistics(), fresh.statistics());
    // Measured: 18 factorisations in 200 steps (the guess drifts past 5e-3 of the factors'
    // unknowns about every tenth step); fresh: one a step.
    assert_eq!(f.factorizations, steps);
    assert!(r.factorizations <= steps / 4, "{r:?}");
    let gap = (reused.state().attitude().matrix() - fresh.state().attitude().matrix()).amax();
    let rates = largest_difference(&reused.state().velocity, &fresh.state().velocity);
    // Both runs are solved to the rounding floor at every step; their difference is 200
    // steps of rounding (a few ulps each), far below the method's error (1e-13 here).
    assert!(gap < 1e-13 && rates < 1e-13, "{gap:e} {rates:e}");

    let orbit = OrbitingBody::new(inertia(), 1.0, 1.0).unwrap();
    let start = SE3::new(SO3::identity(), Vector3::new(3.0, 0.0, 0.0));
    let w = omega0();
    let xi = SVector::<f64, 6>::new(w.x, w.y, w.z, 0.0, 0.55, 0.05);
    let (reused, fresh) = both(
        |reuse| {
            let settings = StepSettings::new(0.1, 8).unwrap().with_factor_reuse(reuse);
            Integrator::new(orbit, settings, start, xi).unwrap()
        },
        steps,
    );
    // Measured: 113 factorisations in 200 steps (h = 0.1: the guess drifts past the
    // factors' unknowns about every other step).
    assert!(
        reused.statistics().factorizations <= 3 * steps / 4,
        "{:?}",
        reused.statistics()
    );
    let position = (reused.state().position() - fresh.state().position()).amax();
    let velocity = largest_difference(&reused.state().velocity, &fresh.state().velocity);
    assert!(
        position < 1e-12 && velocity < 1e-13,
        "{position:e} {velocity:e}"
    );
    // The orbiting body conserves its spatial angular momentum about the attracting
    // centre: to rounding along 200 steps with carried factors.
    let initial = Integrator::new(orbit, StepSettings::new(0.1, 8).unwrap(), start, xi)
        .unwrap()
        .state()
        .spatial_momentum();
    let drift = (reused.state().spatial_momentum() - initial)
        .fixed_rows::<3>(0)
        .amax();
    assert!(drift < 1e-13, "{drift:e}");

    let j = Matrix3::new(10.0, 0.3, -0.2, 0.3, 12.0, 0.4, -0.2, 0.4, 8.0);
    let craft = Gyrostat::new(j, [Vector3::x(), Vector3::y(), Vector3::z()], [0.05; 3]).unwrap();
    let start = BodyWheels {
        attitude: SO3::identity(),
        wheels: Vector3::zeros(),
    };
    let velocity = SVector::<f64, 6>::new(0.3, -0.2, 0.4, 5.0, -3.0, 2.0);
    let (reused, fresh) = both(
        |reuse| {
            let settings = StepSettings::new(0.05, 6).unwrap().with_factor_reuse(reuse);
            let mut it = Integrator::new(craft, settings, start, velocity).unwrap();
            it.set_input(SVector::<f64, 6>::new(0.0, 0.0, 0.0, 0.01, 0.0, -0.02))
                .unwrap();
            it
        },
        steps,
    );
    assert!(
        reused.statistics().factorizations < steps,
        "{:?}",
        reused.statistics()
    );
    // The total angular momentum `Rh` is conserved under any motor torques: to rounding
    // along the run with carried factors (its start is the fresh run's).
    let h0 = fresh.state().spatial_momentum();
    let h = reused.state().spatial_momentum();
    assert!((h - h0).fixed_rows::<3>(0).amax() < 1e-13, "{h} {h0}");
}

/// The free body at a control loop's step against its closed form: carried factors reach
/// the accuracy fresh ones do (rounding at h = 0.05, n = 6, after 400 steps), and the
/// momentum `Rμ` is conserved to rounding.
#[test]
fn reused_factors_keep_the_method_s_accuracy() {
    let body = RigidBody::new(inertia());
    let exact = FreeRigidBodyExact::new(inertia(), SO3::identity(), omega0()).unwrap();
    let mut errors = Vec::new();
    for reuse in [true, false] {
        let settings = StepSettings::new(0.05, 6).unwrap().with_factor_reuse(reuse);
        let mut it = Integrator::new(body, settings, SO3::identity(), omega0()).unwrap();
        let pi0 = it.state().spatial_momentum();
        it.run(400, 400).unwrap();
        let s = it.state();
        let truth = exact.state(s.time).unwrap();
        errors.push((s.attitude().matrix() - truth.attitude().matrix()).amax());
        let drift = largest_difference(&s.spatial_momentum(), &pi0);
        assert!(drift < 1e-14, "reuse {reuse}: Rμ drifted by {drift:e}");
        if reuse {
            assert!(
                it.statistics().factorizations < 100,
                "{:?}",
                it.statistics()
            );
        }
    }
    // Both at the method's error for (h, n) = (0.05, 6), which is rounding here (measured
    // 1.3e-14 with reuse, 1.7e-15 without: 400 steps of rounding either way).
    assert!(errors[0] < 1e-12 && errors[1] < 1e-12, "{errors:?}");
    assert!((errors[0] - errors[1]).abs() < 1e-13, "{errors:?}");
}

/// Long steps never try carried factors (the guess lies too far from them): the run is
/// the fresh run bit for bit, and every step factors its own matrix.
#[test]
fn long_steps_leave_the_factors_alone() {
    let body = RigidBody::new(inertia());
    let (reused, fresh) = both(
        |reuse| {
            let settings = StepSettings::new(0.5, 8).unwrap().with_factor_reuse(reuse);
            Integrator::new(body, settings, SO3::identity(), omega0()).unwrap()
        },
        100,
    );
    assert_eq!(reused.state(), fresh.state());
    assert_eq!(reused.statistics(), fresh.statistics());
    assert_eq!(reused.statistics().factorizations, 100);
}

/// `linearize` is a function of the state: the same `A` twice, whatever came before, and
/// the run after it is the run without it, bit for bit (no factors in or out).
#[test]
fn a_linearisation_at_the_state_leaves_the_run_alone() {
    let top = HeavyTop::new(inertia(), 1.0, 0.3, Vector3::z(), Vector3::z()).unwrap();
    let settings = StepSettings::new(0.05, 8).unwrap();
    let make = || Integrator::new(top, settings, SO3::identity(), omega0()).unwrap();
    let (mut plain, mut probed) = (make(), make());
    plain.run(10, 10).unwrap();
    probed.run(10, 10).unwrap();
    let first = probed.linearize().unwrap();
    let second = probed.linearize().unwrap();
    assert_eq!(
        first.a(Coordinates::Velocity),
        second.a(Coordinates::Velocity)
    );
    let mut fresh = Integrator::new(
        top,
        settings,
        *probed.state().attitude(),
        probed.state().velocity,
    )
    .unwrap();
    fresh
        .reset(
            probed.state().time,
            probed.state().configuration,
            probed.state().velocity,
        )
        .unwrap();
    assert_eq!(
        fresh.linearize().unwrap().a(Coordinates::Velocity),
        first.a(Coordinates::Velocity)
    );
    for _ in 0..10 {
        plain.step().unwrap();
        probed.step().unwrap();
        assert_eq!(plain.state(), probed.state());
    }
    // `reset` starts afresh: the steps after it are those of a new integrator.
    let state = *plain.state();
    plain
        .reset(state.time, state.configuration, state.velocity)
        .unwrap();
    let mut new = Integrator::new(top, settings, *state.attitude(), state.velocity).unwrap();
    new.reset(state.time, state.configuration, state.velocity)
        .unwrap();
    for _ in 0..5 {
        plain.step().unwrap();
        new.step().unwrap();
        assert_eq!(plain.state(), new.state());
    }
}

/// Noether and the energy over 2·10⁴ steps served by carried factors: the spatial momentum
/// `Rμ` stays at rounding and the energy error bounded at rounding, as with fresh matrices
/// (measured over 2·10⁴ steps: energy within 3.6e-15 with reuse, 2.7e-15 without; over
/// 2·10⁵ steps 1.7e-14 and 6.3e-15, no trend in either).
#[test]
fn reused_factors_keep_noether_and_a_bounded_energy() {
    let body = RigidBody::new(inertia());
    let settings = StepSettings::new(0.05, 6).unwrap();
    let mut it = Integrator::new(body, settings, SO3::identity(), omega0()).unwrap();
    let (e0, pi0) = (it.state().energy(&body), it.state().spatial_momentum());
    let mut worst = 0.0f64;
    for _ in 0..20_000 {
        it.step().unwrap();
        worst = worst.max((it.state().energy(&body) - e0).abs());
    }
    // Most steps on carried factors (measured 716 factorisations in 2·10⁴ steps).
    assert!(
        it.statistics().factorizations < 2_000,
        "{:?}",
        it.statistics()
    );
    assert!(worst < 1e-14, "energy error {worst:e}");
    let drift = largest_difference(&it.state().spatial_momentum(), &pi0);
    assert!(drift < 1e-14, "Rμ drifted by {drift:e}");
}

/// What the distance test cannot see is caught by the contraction test: a control input
/// switched from nothing to a large torque changes the Newton matrix (the input's
/// `∂(A(x)ᵀu)/∂x`) while the guess stays close to the carried factors' unknowns. The
/// steps after it miss, form their own matrices and land where fresh matrices do; a run
/// to an end that is not a whole number of steps (a shorter last step, whose matrix scales
/// with `h`) does as well; and `step_linearized` on carried factors returns the `A` and
/// `B` of the same step on fresh ones.
#[test]
fn changes_the_distance_cannot_see_fall_back_to_fresh_matrices() {
    let top = HeavyTop::new(inertia(), 1.0, 0.3, Vector3::z(), Vector3::z()).unwrap();
    let make = |reuse: bool| {
        let settings = StepSettings::new(0.05, 8).unwrap().with_factor_reuse(reuse);
        let mut it = Integrator::new(top, settings, SO3::identity(), omega0()).unwrap();
        it.set_input(Vector3::new(0.001, 0.0, 0.0)).unwrap();
        it
    };
    let (mut reused, mut fresh) = (make(true), make(false));
    reused.run(20, 20).unwrap();
    fresh.run(20, 20).unwrap();
    let before = reused.statistics().factorizations;
    let kick = Vector3::new(40.0, -25.0, 30.0);
    reused.set_input(kick).unwrap();
    fresh.set_input(kick).unwrap();
    reused.run(20, 20).unwrap();
    fresh.run(20, 20).unwrap();
    // The kick spins the body up (the largest rate from 0.6 to 82 over the 20 steps): the
    // steps form their own matrices again (measured: 23 factorisations in 40 steps, 41
    // fresh).
    assert!(
        reused.statistics().factorizations > before + 5,
        "{:?}",
        reused.statistics()
    );
    let scale = fresh.state().velocity.amax();
    let gap = largest_difference(&reused.state().velocity, &fresh.state().velocity) / scale;
    let attitude = (reused.state().attitude().matrix() - fresh.state().attitude().matrix()).amax();
    // 40 steps solved to the rounding floor either way (measured 5.8e-16 relative in the
    // rates, 1.1e-15 in R).
    assert!(gap < 1e-13 && attitude < 1e-13, "{gap:e} {attitude:e}");

    // A run to t = 2.02 at h = 0.05: 40 whole steps and a last one of 0.02.
    let (mut reused, mut fresh) = (make(true), make(false));
    reused.run_until(2.02, 1).unwrap();
    fresh.run_until(2.02, 1).unwrap();
    assert!((reused.state().time - 2.02).abs() < 1e-12);
    let gap = largest_difference(&reused.state().velocity, &fresh.state().velocity);
    // Measured 1.1e-16.
    assert!(gap < 1e-14, "{gap:e}");

    // Linearised steps on carried factors: the same A and B as on fresh ones (both are
    // formed from a Newton matrix factored at the converged step).
    let (mut reused, mut fresh) = (make(true), make(false));
    for _ in 0..15 {
        let (a, b) = (
            reused.step_linearized().unwrap(),
            fresh.step_linearized().unwrap(),
        );
        let da = (a.a(Coordinates::Velocity) - b.a(Coordinates::Velocity)).amax();
        let db = (a.b(Coordinates::Velocity) - b.b(Coordinates::Velocity)).amax();
        // The two converged steps differ at rounding; A and B follow them (measured at
        // most 8.7e-18 and 8.7e-19, entries of order one and h).
        assert!(da < 1e-14 && db < 1e-14, "{da:e} {db:e}");
    }
    assert!(reused.statistics().factorizations < fresh.statistics().factorizations);
}
