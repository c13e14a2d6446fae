//! The integrator's edges: starting states off the group, horizons in the past or out of
//! reach, ends between steps, dense output outside its step, and tolerances no step can
//! meet. Each is an error that says what to change, or (an end between steps) exactly
//! what was asked.

use lgsvi_mechanics::exact::FreeRigidBodyExact;
use lgsvi_mechanics::group::Rotations;
use lgsvi_mechanics::lie::{LieError, SE3, SO3};
use lgsvi_mechanics::{FreeBody, Inertia, Integrator, MechanicsError, RigidBody, StepSettings};
use lgsvi_mechanics::{GroupLagrangian, Stepper};
use nalgebra::{Matrix3, SVector, Vector3};

fn inertia() -> Inertia {
    Inertia::from_principal_moments([0.5, 0.9, 0.7]).unwrap()
}

fn omega0() -> Vector3<f64> {
    Vector3::new(0.6, 0.1, -0.4)
}

/// Steps until the first failure, which must come before `horizon`.
fn first_failure<S, C, const D: usize>(it: &mut Integrator<S, C, D>, horizon: f64) -> MechanicsError
where
    S: lgsvi_mechanics::System<D>,
    C: lgsvi_mechanics::group::GroupChart<S::Group, D>,
{
    loop {
        match it.step() {
            Ok(_) => assert!(it.state().time < horizon, "no failure before t = {horizon}"),
            Err(error) => return error,
        }
    }
}

fn integrator(h: f64, n: usize) -> Integrator<RigidBody> {
    Integrator::new(
        RigidBody::new(inertia()),
        StepSettings::new(h, n).unwrap(),
        SO3::identity(),
        omega0(),
    )
    .unwrap()
}

#[test]
fn an_attitude_that_is_not_a_rotation_is_refused_at_start_and_reset() {
    let body = RigidBody::new(inertia());
    let settings = StepSettings::new(0.1, 6).unwrap();
    let scaled = SO3::from_matrix_unchecked(Matrix3::identity() * 2.0);
    let reflection =
        SO3::from_matrix_unchecked(Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0)));
    for (bad, orthogonal) in [(scaled, false), (reflection, true)] {
        let Err(error) = Integrator::new(body, settings, bad, omega0()) else {
            panic!("accepted")
        };
        match (&error, orthogonal) {
            (
                MechanicsError::NotOnGroup {
                    source: LieError::NotOrthogonal { .. },
                    ..
                },
                false,
            )
            | (
                MechanicsError::NotOnGroup {
                    source: LieError::NotProperRotation { .. },
                    ..
                },
                true,
            ) => {}
            _ => panic!("{error}"),
        }
        assert!(error
            .to_string()
            .starts_with("initial configuration: not a rotation"));
        let mut it = integrator(0.1, 6);
        let before = *it.state();
        let error = it.reset(0.0, bad, omega0()).unwrap_err();
        assert!(
            matches!(error, MechanicsError::NotOnGroup { .. }),
            "{error}"
        );
        assert_eq!(*it.state(), before, "a refused reset changes nothing");
    }
    // A body in space: the attitude block is checked.
    let free = FreeBody::new(inertia(), 1.0).unwrap();
    let pose = SE3::new(scaled, Vector3::zeros());
    let xi = SVector::<f64, 6>::zeros();
    assert!(matches!(
        Integrator::new(free, settings, pose, xi),
        Err(MechanicsError::NotOnGroup { .. })
    ));
    // Rounding of a rotation given to ten digits (‖RᵀR − I‖ ~ 1e-10) is accepted.
    let r = SO3::exp(&Vector3::new(0.3, -0.2, 0.9)).matrix() * (1.0 + 3e-11);
    assert!(Integrator::new(body, settings, SO3::from_matrix_unchecked(r), omega0()).is_ok());
}

/// `run_until` lands on the requested time with a last, shorter step, and the steps after
/// it take `h` again. The shorter step is a variational step of its own: the state at
/// 0.35 agrees with the exact solution as the whole steps do (the method's error at
/// `h = 0.1`, `n = 8` on this slow body is at rounding, ~1e-15; 1e-13 leaves room for the
/// rounding of 4 steps).
#[test]
fn run_until_lands_on_the_time_asked() {
    let exact = FreeRigidBodyExact::new(inertia(), SO3::identity(), omega0()).unwrap();
    let mut it = integrator(0.1, 8);
    let trajectory = it.run_until(0.35, 1).unwrap();
    assert_eq!(it.state().time, 0.35);
    assert_eq!(trajectory.states.last().unwrap().time, 0.35);
    assert_eq!(trajectory.states.len(), 5, "0, 0.1, 0.2, 0.3, 0.35");
    let reference = exact.state(0.35).unwrap();
    let error = (it.state().configuration.matrix() - reference.configuration.matrix()).amax();
    assert!(error < 1e-13, "{error:e}");
    it.step().unwrap();
    assert!(
        (it.state().time - 0.45).abs() < 1e-15,
        "{}",
        it.state().time
    );
    assert_eq!(it.settings().h(), 0.1);
    // A whole number of steps away: no extra step.
    let mut it = integrator(0.1, 8);
    let trajectory = it.run_until(0.3, 1).unwrap();
    assert_eq!(trajectory.states.len(), 4);
    assert!((it.state().time - 0.3).abs() < 1e-15);
}

#[test]
fn horizons_in_the_past_or_out_of_reach_are_refused() {
    let mut it = integrator(0.5, 6);
    it.run_until(5.0, 1).unwrap();
    let before = *it.state();
    for error in [
        it.run_until(2.0, 1).unwrap_err(),
        it.steps_until(2.0).unwrap_err(),
    ] {
        assert!(
            error.to_string().contains("before the current time"),
            "{error}"
        );
    }
    assert_eq!(*it.state(), before);
    for error in [
        it.steps_until(1e300).unwrap_err(),
        it.run_until(1e300, 1).unwrap_err(),
    ] {
        assert!(error.to_string().contains("2^53 steps"), "{error}");
    }
    // The current time itself is no step at all.
    assert_eq!(it.steps_until(5.0).unwrap(), 0);
    assert_eq!(it.run_until(5.0, 1).unwrap().states.len(), 1);
}

#[test]
fn the_galerkin_curve_answers_within_its_step_only() {
    let mut it = integrator(0.5, 6);
    it.step().unwrap();
    let curve = it.last_curve().unwrap();
    let (end, _) = curve.at(0.5).unwrap();
    assert!((end.matrix() - it.state().configuration.matrix()).amax() < 1e-14);
    assert!(curve.at(0.0).is_ok());
    for t in [1e300, -1e-3, 0.5 + 1e-6, f64::NAN, f64::INFINITY] {
        let error = curve.at(t).unwrap_err();
        assert!(
            matches!(error, MechanicsError::InvalidSetting { name: "t", .. }),
            "{t}: {error}"
        );
    }
}

/// A tolerance no step can meet ends the run with an error naming the step, the time and
/// what to change, instead of accepting steps above their share of it: with the nodes
/// capped (no step changes), at the first step; with step changes, after the bounded
/// halvings of that step (before: every step halved 30 times, accepted anyway, and grew
/// back, 10⁵ steps to cross a nanosecond).
#[test]
fn an_unreachable_tolerance_is_an_error_not_a_quiet_miss() {
    let body = RigidBody::new(inertia());
    // h = 2: at 6 nodes the error is ~1e-9, far above the step's share of 1e-14.
    let capped = StepSettings::new(2.0, 6)
        .unwrap()
        .with_node_range(5, 6)
        .unwrap()
        .with_tolerance(1e-14)
        .unwrap();
    let mut it = Integrator::new(body, capped, SO3::identity(), omega0()).unwrap();
    let error = it.run_until(4.0, 1).unwrap_err();
    match &error {
        MechanicsError::ToleranceNotMet {
            step: 0, nodes: 6, ..
        } => {}
        _ => panic!("{error}"),
    }
    assert!(error.to_string().contains("raise the tolerance"), "{error}");
    assert_eq!(it.state().time, 0.0, "the last good state is kept");

    // A rate allowed at h = 2 (its share 2e-15 is above the rounding floor 4ε) but not
    // reachable at 6 nodes there, nor at the shorter steps, whose shares fall below 4ε.
    let halving = StepSettings::new(2.0, 6)
        .unwrap()
        .with_node_range(5, 6)
        .unwrap()
        .with_tolerance(1e-15)
        .unwrap()
        .with_step_changes(true);
    let mut it = Integrator::new(body, halving, SO3::identity(), omega0()).unwrap();
    let error = it.run_until(1.0, 1).unwrap_err();
    assert!(
        matches!(error, MechanicsError::ToleranceNotMet { step: 0, .. }),
        "{error}"
    );
    assert!(
        error.to_string().contains("halving the step 30 times"),
        "{error}"
    );
    assert!(it.statistics().steps == 0);
}

/// A tolerance whose share of a step is below the rounding of one step (4ε) is refused
/// up front, with the least rate this step can reach; and the estimate never claims less
/// than that rounding (the spectral estimate alone reads 1e-24 at 8 nodes here, against a
/// true error of 5e-16).
#[test]
fn tolerances_below_the_rounding_floor_are_refused_and_estimates_floored() {
    let settings = StepSettings::new(0.5, 8).unwrap();
    for rate in [1e-16, 1e-20, 1e-300] {
        let error = settings.with_tolerance(rate).unwrap_err();
        let text = error.to_string();
        assert!(
            text.contains("below what double precision can deliver"),
            "{text}"
        );
        assert!(text.contains("at least 1.7763568394002505e-15"), "{text}");
    }
    assert!(settings.with_tolerance(2e-15).is_ok());
    let mut it = integrator(0.5, 8);
    it.run(10, 10).unwrap();
    assert_eq!(
        it.error_estimate(),
        lgsvi_mechanics::settings::ROUNDING_FLOOR
    );
    assert!(
        it.estimated_global_error() >= 10.0 * lgsvi_mechanics::settings::ROUNDING_FLOOR * 0.999
    );
}

/// A principal moment below ε times the largest is refused with its cause (before: the
/// run overflowed at its first step and advised lowering the inertia, the wrong way).
#[test]
fn an_inertia_thinner_than_double_precision_is_refused() {
    for moments in [[1.0, 1.0, 1e-300], [1e-17, 1.0, 1.0]] {
        let error = Inertia::from_principal_moments(moments).unwrap_err();
        let text = error.to_string();
        assert!(text.contains("below ε times the largest"), "{text}");
    }
    let tensor = Matrix3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1e-300);
    assert!(Inertia::from_tensor(tensor).is_err());
    // Thin but resolvable: accepted.
    assert!(Inertia::from_principal_moments([1.0, 1.0, 1e-12]).is_ok());
}

/// A user's force that returns NaN from t = 1 on: the error names the step, its time and
/// the force (before: "momentum after the step is not finite", nothing else).
#[test]
fn a_non_finite_force_is_named_with_its_step() {
    use lgsvi_mechanics::forces::ForceOfTime;
    use lgsvi_mechanics::Forced;
    let force = ForceOfTime(|t: f64| {
        if t > 1.0 {
            Vector3::new(f64::NAN, 0.0, 0.0)
        } else {
            Vector3::zeros()
        }
    });
    let body = Forced::new(RigidBody::new(inertia()), force);
    let mut it = Integrator::new(
        body,
        StepSettings::new(0.5, 6).unwrap(),
        SO3::identity(),
        omega0(),
    )
    .unwrap();
    let error = it.run(10, 1).unwrap_err();
    let text = error.to_string();
    assert!(
        matches!(error, MechanicsError::NonFiniteStep { step: 2, .. }),
        "{text}"
    );
    assert!(
        text.contains("(t = 1)") && text.contains("the force"),
        "{text}"
    );
    assert_eq!(it.state().time, 1.0, "the last good state is kept");
}

/// A user's body whose moments the control code may change between steps.
#[derive(Clone, Copy)]
struct Tunable {
    moments: [f64; 3],
}
impl GroupLagrangian<3> for Tunable {
    type Group = Rotations;
    fn lagrangian<T: nalgebra::RealField + Copy>(&self, _t: f64, _r: &SO3<T>, w: &Vector3<T>) -> T {
        let c = |x: f64| -> T { nalgebra::convert(x) };
        c(0.5)
            * (w.x * w.x * c(self.moments[0])
                + w.y * w.y * c(self.moments[1])
                + w.z * w.z * c(self.moments[2]))
    }
}

/// [`Tunable`] modelled only below a spin rate (a flexible body that the rigid model
/// describes only while it spins slowly, say).
#[derive(Clone, Copy)]
struct SlowSpinner(Tunable);
impl GroupLagrangian<3> for SlowSpinner {
    type Group = Rotations;
    fn lagrangian<T: nalgebra::RealField + Copy>(&self, t: f64, r: &SO3<T>, w: &Vector3<T>) -> T {
        GroupLagrangian::lagrangian(&self.0, t, r, w)
    }
    fn model_breakdown(&self, _t: f64, _r: &SO3, w: &Vector3<f64>) -> Option<String> {
        (w.norm() > 5.0).then(|| format!("|Ω| = {:.1} exceeds the model's 5 rad/s", w.norm()))
    }
}

/// A user's SO(3) Lagrangian reports where its model ends as the SE(3) systems do: a step
/// that fails there is `OutsideModel`, with the step's own failure as its source; below the
/// bound the same failure keeps its own error.
#[test]
fn a_user_lagrangian_names_where_its_model_ends() {
    use std::error::Error;
    let settings = StepSettings::new(40.0, 6)
        .unwrap()
        .with_chart(lgsvi_mechanics::lie::ChartKind::CayleyUnscaled);
    let body = SlowSpinner(Tunable {
        moments: [0.5, 0.9, 0.7],
    });
    // |Ω₀| ≈ 7.3 rad/s over h = 40: far past what the Cayley chart follows in a step.
    let mut it = Integrator::new(body, settings, SO3::identity(), omega0() * 10.0).unwrap();
    let error = it.step().unwrap_err();
    match &error {
        MechanicsError::OutsideModel {
            step: 0, reason, ..
        } => {
            assert!(reason.contains("|Ω| = 7.3"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    let source = error.source().expect("the step's own failure").to_string();
    assert!(source.contains("step 0"), "{source}");
    // Slow enough for the model, the same kind of failure stays what it is.
    let mut it = Integrator::new(body, settings, SO3::identity(), omega0() * 5.0).unwrap();
    let error = it.step().unwrap_err();
    assert!(
        !matches!(error, MechanicsError::OutsideModel { .. }),
        "{error}"
    );
}

/// `system_mut` making moments zero: the failed step says the Lagrangian is not strictly
/// convex in the velocity, with its eigenvalues, and that no step h mends it (before: "take
/// a smaller step h"). (A negative moment leaves an indefinite `ℓ` whose steps may still
/// solve: the step does not read `ℓ`'s Hessian on success.) A valid body's failure keeps
/// its own error.
#[test]
fn a_degenerate_lagrangian_is_named_as_the_cause() {
    for (j1, j2) in [(0.0, 0.9), (0.0, 0.0)] {
        let mut integrator = Integrator::new(
            Tunable {
                moments: [0.5, 0.9, 0.7],
            },
            StepSettings::new(0.5, 8).unwrap(),
            SO3::identity(),
            omega0(),
        )
        .unwrap();
        integrator.step().unwrap();
        integrator.system_mut().moments[0] = j1;
        integrator.system_mut().moments[1] = j2;
        match integrator.step() {
            Err(error @ MechanicsError::DegenerateLagrangian { step, least, .. }) => {
                assert_eq!(step, 1);
                assert!(least.abs() <= 1e-12, "{least}");
                let text = error.to_string();
                assert!(
                    text.contains("not strictly convex") && text.contains("no step h"),
                    "{text}"
                );
            }
            other => panic!("J₁ = {j1}: {other:?}"),
        }
        assert_eq!(integrator.state().time, 0.5);
    }
    // A valid body on a Cayley chart that cannot follow a long step: not degenerate.
    let mut integrator = Integrator::new(
        Tunable {
            moments: [0.5, 0.9, 0.7],
        },
        StepSettings::new(40.0, 6)
            .unwrap()
            .with_chart(lgsvi_mechanics::lie::ChartKind::CayleyUnscaled),
        SO3::identity(),
        omega0() * 10.0,
    )
    .unwrap();
    let error = integrator.step().unwrap_err();
    assert!(
        !matches!(error, MechanicsError::DegenerateLagrangian { .. }),
        "{error}"
    );
}

/// A step Newton cannot solve says what to change, and never suggests the chart the run
/// already takes: the Cayley charts suggest exp (which follows up to 2π per step), exp
/// suggests nothing beyond a smaller step or more nodes. (One iteration allowed: no step
/// converges in it.)
#[test]
fn a_failed_solve_suggests_another_chart_only_where_there_is_one() {
    use lgsvi_mechanics::lie::ChartKind;
    for (chart, suggests_exp) in [
        (ChartKind::Exp, false),
        (ChartKind::Cayley, true),
        (ChartKind::CayleyUnscaled, true),
    ] {
        let settings = StepSettings::new(0.5, 8)
            .unwrap()
            .with_chart(chart)
            .with_max_newton_iterations(1);
        let body = RigidBody::new(inertia());
        let mut integrator = Integrator::new(body, settings, SO3::identity(), omega0()).unwrap();
        let error = integrator.step().unwrap_err();
        assert!(
            matches!(error, MechanicsError::NewtonDiverged { .. }),
            "{error}"
        );
        let message = error.to_string();
        assert!(
            message.contains("smaller step h or more nodes"),
            "{message}"
        );
        assert_eq!(
            message.contains("exp chart"),
            suggests_exp,
            "{chart:?}: {message}"
        );
        // The library's words: no command line flag (the command line and Python add
        // their own).
        assert!(!message.contains("--"), "{message}");
    }
}

/// An orbit that falls onto the attracting point: the first step that ends within twice the
/// body's radius of gyration (where the attracting point lies within the body's mass and
/// MacCullagh's potential does not hold) is refused, the state kept at the last one the model
/// holds at, and the message says that the orbit or the body must change (before the
/// check at each step's end, the run went on until a step failed at t ≈ 43, whatever h;
/// a fall from rest went through the region and was flung out with its energy multiplied
/// a thousandfold, no error raised). A failure far from the centre keeps its own error.
#[test]
fn an_orbit_falling_onto_the_centre_is_named_as_the_cause() {
    use lgsvi_mechanics::OrbitingBody;
    // The CLI's orbiting body with the inertia of this file's rigid body: the coupling
    // drains the orbit's angular momentum until it falls in.
    let body = OrbitingBody::new(inertia(), 1.0, 1.0).unwrap();
    let start = SE3::new(SO3::identity(), Vector3::new(3.0, 0.0, 0.0));
    let velocity = SVector::<f64, 6>::new(0.6, 0.1, -0.4, 0.0, 0.55, 0.05);
    let mut it =
        Integrator::new(body, StepSettings::new(0.5, 8).unwrap(), start, velocity).unwrap();
    let error = first_failure(&mut it, 60.0);
    let r = it.state().configuration.translation().norm();
    // √(tr J / 2m) = √1.05 ≈ 1.025: the state kept lies outside r = 2.05.
    let two_k = 2.0 * 1.05f64.sqrt();
    assert!(r >= two_k, "kept r = {r}");
    match &error {
        MechanicsError::LeftModel { time, reason, .. } => {
            assert_eq!(*time, it.state().time);
            assert!(reason.contains("wider orbit"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    let text = error.to_string();
    assert!(!text.contains("smaller step"), "{text}");

    // A fall from rest at r = 3 (2k = 2√1.75 = 2.65): the energy holds to the last step
    // taken, which ends outside 2k; the step into the body is refused.
    let body = OrbitingBody::new(
        Inertia::from_principal_moments([1.0, 1.0, 1.5]).unwrap(),
        1.0,
        1.0,
    )
    .unwrap();
    let mut it = Integrator::new(
        body,
        StepSettings::new(0.5, 8).unwrap(),
        start,
        SVector::<f64, 6>::zeros(),
    )
    .unwrap();
    let energy = |it: &Integrator<OrbitingBody, lgsvi_mechanics::lie::ChartKind, 6>| {
        let s = it.state();
        s.momentum.dot(&s.velocity)
            - lgsvi_mechanics::System::lagrangian(
                it.system(),
                s.time,
                &s.configuration,
                &s.velocity,
            )
    };

    let e0 = energy(&it);
    let error = first_failure(&mut it, 20.0);
    assert!(matches!(error, MechanicsError::LeftModel { .. }), "{error}");
    let r = it.state().configuration.translation().norm();
    assert!(r >= 2.0 * 1.75f64.sqrt() && r < 3.0, "kept r = {r}");
    // The variational step's energy error at h = 0.5, n = 8 on this fall: well below 1e-6.
    assert!(
        (energy(&it) - e0).abs() < 1e-6 * e0.abs(),
        "{} against {e0}",
        energy(&it)
    );

    // Far from the centre (r = 3 against 2k ≈ 2.05), a step the chart cannot follow
    // keeps its own error.
    let mut it = Integrator::new(
        body,
        StepSettings::new(40.0, 6)
            .unwrap()
            .with_chart(lgsvi_mechanics::lie::ChartKind::CayleyUnscaled),
        start,
        velocity * 10.0,
    )
    .unwrap();
    let error = it.step().unwrap_err();
    assert!(
        !matches!(error, MechanicsError::OutsideModel { .. }),
        "{error}"
    );
}

/// A thin rod, `J = (δ, 1, 1)`: where its step fails, the cause is the inertia's
/// conditioning (the velocity follows from the momentum only to `ε/δ`), named with its
/// eigenvalues, not "take a smaller step h or more nodes"; the step's own failure is kept.
/// A rod of `δ = 1e-5` is an ordinary body whose steps converge.
#[test]
fn a_step_that_fails_on_an_ill_conditioned_inertia_names_the_conditioning() {
    use std::error::Error;
    let start = Vector3::new(-2.0, 1.9, -1.0);
    let rod = |delta: f64| {
        let body = RigidBody::new(Inertia::from_principal_moments([delta, 1.0, 1.0]).unwrap());
        Integrator::new(
            body,
            StepSettings::new(0.5, 10).unwrap(),
            SO3::identity(),
            start,
        )
        .unwrap()
    };
    for delta in [3e-9, 1e-10] {
        let mut it = rod(delta);
        let error = first_failure(&mut it, 10.0);
        match &error {
            MechanicsError::IllConditioned { least, most, .. } => {
                assert_eq!((*least, *most), (delta, 1.0), "δ = {delta:e}");
            }
            other => panic!("δ = {delta:e}: {other}"),
        }
        let text = error.to_string();
        assert!(
            text.contains("ill-conditioned") && text.contains("condition"),
            "{text}"
        );
        assert!(!text.contains("take a smaller step"), "{text}");
        assert!(error.source().is_some(), "the step's own failure is kept");
    }
    let mut it = rod(1e-5);
    for _ in 0..20 {
        it.step().unwrap();
    }
}

/// Convexity does not depend on units: an orbiting body of mass 1e-30 beside an inertia
/// of order 1 has a convex Lagrangian (its Hessian's eigenvalues 1e-30 … 1), and its failed
/// step is put down to what is wrong, the attracting point inside its radius of gyration,
/// not to "a zero or negative inertia or mass".
#[test]
fn a_badly_scaled_but_convex_lagrangian_is_not_called_degenerate() {
    use lgsvi_mechanics::OrbitingBody;
    let body = OrbitingBody::new(inertia(), 1e-30, 1.0).unwrap();
    let start = SE3::new(SO3::identity(), Vector3::new(3.0, 0.0, 0.0));
    let velocity = SVector::<f64, 6>::new(0.6, 0.1, -0.4, 0.0, 0.55, 0.05);
    let mut it =
        Integrator::new(body, StepSettings::new(0.5, 10).unwrap(), start, velocity).unwrap();
    let error = first_failure(&mut it, 10.0);
    match &error {
        MechanicsError::OutsideModel { reason, .. } => {
            assert!(reason.contains("radius of gyration"), "{reason}");
        }
        other => panic!("{other}"),
    }
}

/// A Lagrangian whose momentum is bounded in one direction, `ℓ = sin Ω₁ + ½(Ω₂² + Ω₃²)`
/// (`∂ℓ/∂Ω₁ = cos Ω₁ ∈ [−1, 1]`): a momentum `μ₁ = 2` has no velocity, and the inverse
/// Legendre transform says so, naming the kinetic energy as what to check.
#[test]
fn a_momentum_without_a_velocity_names_the_kinetic_energy() {
    #[derive(Clone, Copy)]
    struct Bounded;
    impl GroupLagrangian<3> for Bounded {
        type Group = Rotations;
        fn lagrangian<T: nalgebra::RealField + Copy>(
            &self,
            _: f64,
            _: &SO3<T>,
            w: &Vector3<T>,
        ) -> T {
            let half: T = nalgebra::convert(0.5);
            w.x.sin() + half * (w.y * w.y + w.z * w.z)
        }
    }
    let error = lgsvi_mechanics::state::body_velocity(
        &Bounded,
        0.0,
        &SO3::identity(),
        &Vector3::new(2.0, 0.1, 0.0),
        &Vector3::zeros(),
    )
    .unwrap_err();
    assert!(
        matches!(error, MechanicsError::InverseLegendre { .. }),
        "{error:?}"
    );
    let text = error.to_string();
    assert!(
        text.contains("strictly convex in the velocity") && text.contains("kinetic energy"),
        "{text}"
    );
}

/// A checked run whose companion (two more nodes) fails where the run itself does not:
/// `CheckFailed`, naming the step and what to change, with the companion's own failure in
/// its message. The force is NaN only near the Gauss points of the companion's first
/// step (8 points on [0, 0.5]), which the run's 6 points miss.
#[test]
fn a_companion_that_fails_is_named_as_the_check() {
    use lgsvi_mechanics::forces::ForceOfTime;
    use lgsvi_mechanics::Forced;
    let rule = lgsvi_quadrature::gauss_legendre(8).unwrap();
    let mut companion_times = [0.0; 8];
    for (t, x) in companion_times.iter_mut().zip(rule.nodes()) {
        *t = 0.25 * (1.0 + x);
    }
    let force = ForceOfTime(move |t: f64| {
        if companion_times.iter().any(|s| (t - s).abs() < 1e-9) {
            Vector3::new(f64::NAN, 0.0, 0.0)
        } else {
            Vector3::zeros()
        }
    });
    let body = Forced::new(RigidBody::new(inertia()), force);
    let mut run = Integrator::builder(body)
        .start(SO3::identity(), omega0())
        .step(0.5)
        .nodes(6)
        .build_checked()
        .unwrap();
    let error = run.step().unwrap_err();
    let text = error.to_string();
    assert!(
        matches!(error, MechanicsError::CheckFailed { step: 0, .. }),
        "{text}"
    );
    assert!(
        text.contains("the check of the run (the same step with more nodes) failed")
            && text.contains("the force")
            && text.contains("shorten the step h"),
        "{text}"
    );
}

/// A Lagrangian `ℓ = ¼|Ω|⁴` has no velocity Hessian at rest: the step from rest is fine
/// (the body stays at rest), but its linearisation has no velocity coordinates there. It
/// was reported as "singular Newton system; take a smaller step h", which no step mends;
/// it is named as the Lagrangian's, with the Hessian's eigenvalues.
#[test]
fn a_linearisation_where_the_lagrangian_is_flat_names_the_lagrangian() {
    #[derive(Clone, Copy)]
    struct Quartic;
    impl GroupLagrangian<3> for Quartic {
        type Group = Rotations;
        fn lagrangian<T: nalgebra::RealField + Copy>(
            &self,
            _: f64,
            _: &SO3<T>,
            w: &Vector3<T>,
        ) -> T {
            let quarter: T = nalgebra::convert(0.25);
            let n = w.x * w.x + w.y * w.y + w.z * w.z;
            quarter * n * n
        }
    }
    let mut it = Integrator::new(
        Quartic,
        StepSettings::new(0.5, 6).unwrap(),
        SO3::identity(),
        Vector3::zeros(),
    )
    .unwrap();
    it.step().unwrap();
    for error in [
        it.linearize().unwrap_err(),
        it.step_linearized().unwrap_err(),
    ] {
        let text = error.to_string();
        assert!(
            matches!(error, MechanicsError::DegenerateLagrangian { .. }),
            "{text}"
        );
        assert!(
            text.contains("not strictly convex") && text.contains("your own Lagrangian"),
            "{text}"
        );
        assert!(!text.contains("smaller step"), "{text}");
    }
}

/// `OrbitingBody::check_position`: the start's distance from the attracting point where
/// the far-field potential holds; a typed refusal at the centre, inside twice the radius
/// of gyration, or where the gravity gradient overflows.
#[test]
fn an_orbit_start_outside_the_far_field_model_is_refused() {
    use lgsvi_mechanics::OrbitingBody;
    // tr J / 2m = (3.3 + 2.5 + 3.4) / 2 = 4.6: the radius of gyration √4.6 = 2.1448.
    let body = OrbitingBody::new(
        Inertia::from_principal_moments([3.3, 2.5, 3.4]).unwrap(),
        1.0,
        1.0,
    )
    .unwrap();
    assert!((body.radius_of_gyration() - 4.6f64.sqrt()).abs() < 1e-15);
    let r = body.check_position(&Vector3::new(3.0, 4.0, 12.0)).unwrap();
    assert_eq!(r, 13.0);
    for (x, words) in [
        (Vector3::zeros(), "attracting centre"),
        (Vector3::new(3.0, 0.0, 0.0), "radius of gyration"),
        (Vector3::new(4.28, 0.0, 0.0), "radius of gyration"),
        (Vector3::new(1e76, 0.0, 0.0), "overflow"),
    ] {
        match body.check_position(&x) {
            Err(MechanicsError::InvalidStart { reason, .. }) => {
                assert!(reason.contains(words), "{x:?}: {reason}")
            }
            other => panic!("{x:?}: {other:?}"),
        }
    }
    // Twice the radius of gyration is 4.2895: just outside it is taken.
    assert!(body.check_position(&Vector3::new(4.3, 0.0, 0.0)).is_ok());
    // Without gravity any start is taken.
    let free = OrbitingBody::new(
        Inertia::from_principal_moments([3.3, 2.5, 3.4]).unwrap(),
        1.0,
        0.0,
    )
    .unwrap();
    assert_eq!(free.check_position(&Vector3::zeros()).unwrap(), 0.0);
}
