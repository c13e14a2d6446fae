//! The attitude spring `τ = −k log(R_targetᵀR)` (with `AngularDamping`, the PD attitude
//! law) against references that do not come from the integrator: its closed-form jet
//! against central differences of its own torque; the damped oscillator a sphere turned
//! about one axis obeys, in closed form; the conservation of `E + ½k|θ|²` (the spring is
//! conservative) on an asymmetric body; the same law on SE(3), where the rotation of a free
//! body in space does not feel its translation. Only the first checks the jet: a wrong jet
//! changes Newton's matrix, not the converged step, so the closed forms cannot see it.

use lgsvi_lie::{SE3, SO3};
use lgsvi_mechanics::forces::{AngularDamping, AttitudeSpring, Forcing};
use lgsvi_mechanics::group::Rotations;
use lgsvi_mechanics::{Forced, FreeBody, Inertia, Integrator, RigidBody, StepSettings};
use nalgebra::{SVector, Vector3};

/// A target away from the identity (the tests start their bodies within a half-turn of it,
/// where the law is smooth).
fn target() -> SO3 {
    SO3::exp(&Vector3::new(0.4, -0.7, 1.1))
}

#[test]
fn the_springs_jet_is_its_torques_derivative() {
    let spring = AttitudeSpring::new(target(), 1.7).unwrap();
    let w = Vector3::new(0.3, -0.2, 0.5);
    for turn in [
        Vector3::new(0.1, 0.2, -0.1),
        Vector3::new(1.2, -0.9, 0.8),
        Vector3::new(0.0, 0.0, 3.0),
    ] {
        let g = *spring.target() * SO3::exp(&turn);
        let jet = Forcing::<Rotations, 3>::jet(&spring, 0.0, &g, &w);
        let value: Vector3<f64> = Forcing::<Rotations, 3>::force(&spring, 0.0, &g, &w);
        assert_eq!(jet.value, value);
        assert!((jet.value + turn * 1.7).norm() < 1e-14, "τ = −kθ");
        // Central differences in η (g exp(±εe_i)): truncation ε² |τ'''| ~ 1e-10 and
        // rounding 1e-16/ε ~ 1e-11 at ε = 1e-5.
        let eps = 1e-5;
        for i in 0..3 {
            let e = Vector3::ith(i, eps);
            let f = |s: f64| -> Vector3<f64> {
                Forcing::<Rotations, 3>::force(&spring, 0.0, &(g * SO3::exp(&(e * s))), &w)
            };
            let column = (f(1.0) - f(-1.0)) / (2.0 * eps);
            assert!(
                (jet.configuration.column(i) - column).norm() < 1e-8,
                "column {i} at θ = {turn:?}: {} against {column}",
                jet.configuration.column(i)
            );
        }
        assert_eq!(jet.velocity, nalgebra::Matrix3::zeros());
    }
}

/// A sphere (`J = jI`) turned by `θ₀` about a fixed axis from the target, at rest: the
/// torque stays on the axis, so `j θ'' + c θ' + k θ = 0`, underdamped here:
/// `θ(t) = θ₀ e^(−at) (cos βt + (a/β) sin βt)`, `a = c/2j`, `β = √(k/j − a²)`.
#[test]
fn a_sphere_under_the_pd_law_is_a_damped_oscillator() {
    let (j, k, c, theta0) = (2.5, 3.0, 0.8, 1.3);
    let axis = Vector3::new(1.0, -2.0, 2.0).normalize();
    let spring = AttitudeSpring::new(target(), k).unwrap();
    let body = Forced::new(
        RigidBody::new(Inertia::from_principal_moments([j, j, j]).unwrap()),
        (spring, AngularDamping(c)),
    );
    let start = target() * SO3::exp(&(axis * theta0));
    let mut it = Integrator::new(
        body,
        StepSettings::new(0.2, 12).unwrap(),
        start,
        Vector3::zeros(),
    )
    .unwrap();
    let (a, beta) = (c / (2.0 * j), (k / j - (c / (2.0 * j)).powi(2)).sqrt());
    let mut worst = 0.0f64;
    for _ in 0..100 {
        it.step().unwrap();
        let t = it.state().time;
        let exact = theta0 * (-a * t).exp() * ((beta * t).cos() + a / beta * (beta * t).sin());
        let rate = -theta0 * (-a * t).exp() * (a * a / beta + beta) * (beta * t).sin();
        let theta = spring.error(it.state().attitude());
        worst = worst
            .max((theta - axis * exact).norm())
            .max((it.state().velocity - axis * rate).norm());
    }
    // A step of 0.2 with 12 nodes resolves e^(−at)cos(βt) (β ≈ 1.08) to rounding; the
    // 100 steps' rounding adds up to ~1e-14.
    assert!(
        worst < 1e-13,
        "largest departure from the closed form {worst:e}"
    );
}

/// The spring alone is conservative: `E + ½k|θ|²` is the energy of `ℓ = ½ΩᵀJΩ − V(R)`,
/// which a variational integrator keeps to a bounded error: at h = 0.25, n = 10 the
/// method's own energy error is below rounding, so over 2000 steps of an asymmetric body's
/// tumbling libration about the target only rounding is left.
#[test]
fn the_spring_alone_conserves_kinetic_plus_potential_energy() {
    let spring = AttitudeSpring::new(target(), 0.6).unwrap();
    let inertia = Inertia::from_principal_moments([1.0, 2.0, 2.6]).unwrap();
    let body = Forced::new(RigidBody::new(inertia), spring);
    let start = target() * SO3::exp(&Vector3::new(0.8, 0.3, -0.5));
    let mut it = Integrator::new(
        body,
        StepSettings::new(0.25, 10).unwrap(),
        start,
        Vector3::new(0.2, -0.4, 0.3),
    )
    .unwrap();
    let total = |it: &Integrator<Forced<RigidBody, AttitudeSpring>>| {
        it.state().energy(&RigidBody::new(inertia)) + spring.potential(it.state().attitude())
    };
    let e0 = total(&it);
    let mut drift = 0.0f64;
    let mut largest_turn = 0.0f64;
    for _ in 0..2000 {
        it.step().unwrap();
        drift = drift.max((total(&it) - e0).abs());
        largest_turn = largest_turn.max(spring.error(it.state().attitude()).norm());
    }
    // A precondition, not a check: E + V ≈ 0.59 bounds ½k|θ|², so |θ| ≤ 1.4 and the
    // motion stays within the half-turn where the law is smooth.
    assert!(
        largest_turn < 1.5,
        "turned {largest_turn} rad from the target"
    );
    // Rounding of E + V (~0.6) per step, accumulated as a random walk: ~1e-16 √2000 ≈
    // 5e-15 (measured 3.2e-15); 1e-13 leaves a factor 20.
    assert!(drift < 1e-13, "E + V drifted by {drift:e}");
    // And it is a spring: the work it did is minus the potential's change (measured to
    // 2.6e-15; the work's sum over 2000 steps rounds like E + V).
    let work = it.work_done();
    let balance = work + spring.potential(it.state().attitude()) - spring.potential(&start);
    assert!(
        balance.abs() < 1e-13,
        "work against the potential's drop: {balance:e}"
    );
}

/// On SE(3) the spring turns the body as on SO(3): a free body in space, turned from the
/// target and moving, follows the SO(3) run's attitude and keeps its straight-line motion.
#[test]
fn on_se3_the_spring_turns_the_body_as_on_so3() {
    let inertia = Inertia::from_principal_moments([1.0, 2.0, 2.6]).unwrap();
    let spring = AttitudeSpring::new(target(), 0.9).unwrap();
    let law = (spring, AngularDamping(0.3));
    let w0 = Vector3::new(0.2, -0.4, 0.3);
    let start = target() * SO3::exp(&Vector3::new(0.8, 0.3, -0.5));
    let settings = StepSettings::new(0.25, 10).unwrap();
    let mut rotation = Integrator::new(
        Forced::new(RigidBody::new(inertia), law),
        settings,
        start,
        w0,
    )
    .unwrap();
    let space = Forced::new(FreeBody::new(inertia, 2.0).unwrap(), law);
    let v = start.matrix().transpose() * Vector3::new(0.5, 0.1, -0.2);
    let x0 = Vector3::new(1.0, 2.0, 3.0);
    let mut motion = Integrator::<_, _, 6>::new(
        space,
        settings,
        SE3::new(start, x0),
        SVector::<f64, 6>::new(w0.x, w0.y, w0.z, v.x, v.y, v.z),
    )
    .unwrap();
    for _ in 0..80 {
        rotation.step().unwrap();
        motion.step().unwrap();
    }
    let r = motion.state().configuration.rotation().matrix() - rotation.state().attitude().matrix();
    // Two runs of the same rotational equations by different code paths (3 × 3 blocks on
    // SE(3)): they agree to rounding amplified by 80 steps of a tumbling body (measured
    // 5.4e-16; the position's 7.4e-15 is the rounding of |x| ≈ 20).
    assert!(r.norm() < 1e-13, "attitudes differ by {:e}", r.norm());
    let x = motion.state().configuration.translation() - (x0 + Vector3::new(0.5, 0.1, -0.2) * 20.0);
    assert!(
        x.norm() < 1e-12,
        "the centre of mass left its line by {:e}",
        x.norm()
    );
}

/// A stiff law brings the body onto its target and holds it there: every step of the hold
/// converges. At rest on the target the equations' own terms fall to rounding, but the
/// spring's torque still carries the rounding of `R_targetᵀ R`'s entries (`~ε k`), which
/// Newton's stopping test counts (`Forcing::rounding_scale`); without it the steps of the
/// hold were refused as not converging at a residual of 8e-16.
#[test]
fn a_body_held_on_its_target_keeps_stepping() {
    let inertia = Inertia::from_principal_moments([2.0, 3.0, 4.0]).unwrap();
    let law = (
        AttitudeSpring::new(target(), 100.0).unwrap(),
        AngularDamping(5.0),
    );
    let start = target() * SO3::exp(&Vector3::new(0.3, -0.2, 0.1));
    let mut it = Integrator::new(
        Forced::new(RigidBody::new(inertia), law),
        StepSettings::new(0.5, 10).unwrap(),
        start,
        Vector3::new(0.1, 0.0, 0.0),
    )
    .unwrap();
    let mut most = 0;
    for _ in 0..200 {
        most = most.max(it.step().unwrap());
    }
    // The slowest mode decays as e^(−C t / 2J) ≈ e^(−0.63 t): at rest on the target to
    // rounding long before t = 100.
    let theta = law.0.error(it.state().attitude()).norm();
    assert!(theta < 1e-14, "θ = {theta:e} after 100 s");
    assert!(it.state().velocity.norm() < 1e-14);
    assert!(most <= 10, "{most} Newton iterations in a step");
}
