//! A step's exact derivatives in the system's physical parameters
//! (`Integrator::linearize_with_parameters`, `StepLinearization::p`) against central
//! finite differences through the public API: the same step taken by systems built with
//! each parameter moved up and down (an independent reference: it only builds systems and
//! takes steps). Both coordinates: the start's velocity held, or its momentum held.
//!
//! `cargo test -p lgsvi-mechanics --release --test parameters -- --nocapture` prints the
//! comparison table.

use lgsvi_mechanics::forces::{AngularDamping, SpaceForce};
use lgsvi_mechanics::group::{ConfigurationGroup, GroupChart, Rotations};
use lgsvi_mechanics::gyrostat::{BodyWheels, Gyrostat};
use lgsvi_mechanics::inertia::INERTIA_PARAMETERS;
use lgsvi_mechanics::lie::{ChartKind, LieGroup, SE3, SO3};
use lgsvi_mechanics::linearization::Coordinates;
use lgsvi_mechanics::state::body_velocity;
use lgsvi_mechanics::{
    BodyInField, FieldPotential, Forced, FreeBody, GroupLagrangian, HeavyTop, Inertia, Integrator,
    OrbitingBody, Potential, RigidBody, RigidBodyInPotential, StepSettings, System,
};
use nalgebra::{DMatrix, Matrix3, RealField, SVector, Vector3};

type Element<S, const D: usize> = <<S as System<D>>::Group as ConfigurationGroup<D>>::Element<f64>;

/// `θ` with `g = from · exp(θ)`, by the groups' own logarithms.
trait Difference<const D: usize>: Copy {
    fn difference(&self, from: &Self) -> SVector<f64, D>;
}
impl Difference<3> for SO3 {
    fn difference(&self, from: &Self) -> Vector3<f64> {
        from.inverse().compose(self).log()
    }
}
impl Difference<6> for SE3 {
    fn difference(&self, from: &Self) -> SVector<f64, 6> {
        from.inverse().compose(self).log()
    }
}
impl Difference<6> for BodyWheels<f64, 3> {
    fn difference(&self, from: &Self) -> SVector<f64, 6> {
        let turn = from.attitude.inverse().compose(&self.attitude).log();
        let wheels = self.wheels - from.wheels;
        SVector::<f64, 6>::new(turn.x, turn.y, turn.z, wheels.x, wheels.y, wheels.z)
    }
}

/// The nominal inertia tensor: principal moments off the body axes, so that every entry
/// of `J` is non-zero.
fn tensor() -> Matrix3<f64> {
    let axes = SO3::exp(&Vector3::new(0.3, -0.2, 0.4));
    let r = axes.matrix();
    r * Matrix3::from_diagonal(&Vector3::new(0.5, 0.9, 0.7)) * r.transpose()
}

/// The documented convention, written out here (not read from the library): parameter
/// `k < 6` is the entry `(a, b)` of `J`, moved in both of its symmetric places.
const PLACES: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];

/// `J` (the nominal tensor times `scale`) moved by `δ` along each inertia parameter.
fn moved(scale: f64, delta: &[f64]) -> Matrix3<f64> {
    let mut j = tensor() * scale;
    for (&(a, b), d) in PLACES.iter().zip(delta) {
        j[(a, b)] += d;
        if a != b {
            j[(b, a)] += d;
        }
    }
    j
}

/// The nominal inertia moved by `δ`.
fn inertia(delta: &[f64]) -> Inertia {
    Inertia::from_tensor(moved(1.0, delta)).unwrap()
}

/// A dipole along body x in a field along world z.
#[derive(Clone, Copy)]
struct Dipole;
impl Potential for Dipole {
    fn potential<T: RealField + Copy>(&self, r: &Matrix3<T>) -> T {
        -r[(2, 0)] * nalgebra::convert::<f64, T>(0.3)
    }
}

/// A field on the position that grows in time and a dipole on the attitude, mass included
/// in `V` (held by the parameters: `BodyInField`'s mass is the kinetic energy's).
#[derive(Clone, Copy)]
struct Field;
impl FieldPotential for Field {
    fn potential<T: RealField + Copy>(&self, t: f64, r: &Matrix3<T>, x: &Vector3<T>) -> T {
        let c = |v: f64| -> T { nalgebra::convert(v) };
        x.z * c(0.8 + 0.5 * t) - r[(2, 0)] * c(0.3)
    }
}

/// A Lagrangian without parameters (the trait's defaults).
#[derive(Clone, Copy)]
struct Plain;
impl GroupLagrangian<3> for Plain {
    type Group = Rotations;
    fn lagrangian<T: RealField + Copy>(&self, _t: f64, _r: &SO3<T>, w: &Vector3<T>) -> T {
        w.dot(w) * nalgebra::convert::<f64, T>(0.5)
    }
}

/// Central differences of one step in the parameters: `(∂x₊/∂p)` with the start's velocity
/// held (velocity coordinates) and with its momentum held (momentum coordinates). The
/// step `ε = 1e-5` relative to the parameter's size: truncation ~ε² and rounding
/// ~1e-15/ε, both ~1e-10.
fn differences<S, const D: usize>(
    make: &impl Fn(&[f64]) -> S,
    count: usize,
    scales: &[f64],
    settings: StepSettings,
    start: (f64, Element<S, D>, SVector<f64, D>, SVector<f64, D>),
    input: SVector<f64, D>,
) -> (DMatrix<f64>, DMatrix<f64>)
where
    S: System<D>,
    ChartKind: GroupChart<S::Group, D>,
    Element<S, D>: Difference<D>,
{
    let (time, g, velocity, momentum) = start;
    // End (configuration, velocity, momentum) of one step of the system with `delta`,
    // from the start's velocity (`hold_momentum` false) or momentum, at the start's time.
    let run = |delta: &[f64], hold_momentum: bool| {
        let system = make(delta);
        let v = if hold_momentum {
            body_velocity(&system, time, &g, &momentum, &velocity).unwrap()
        } else {
            velocity
        };
        let mut integrator = Integrator::new(system, settings, g, v).unwrap();
        integrator.reset(time, g, v).unwrap();
        integrator.set_input(input).unwrap();
        integrator.step().unwrap();
        *integrator.state()
    };
    let mut result = [DMatrix::zeros(2 * D, count), DMatrix::zeros(2 * D, count)];
    for (which, hold_momentum) in [false, true].into_iter().enumerate() {
        let reference = run(&vec![0.0; count], hold_momentum);
        for k in 0..count {
            let eps = 1e-5 * scales[k];
            let mut sides = Vec::new();
            for sign in [1.0, -1.0] {
                let mut delta = vec![0.0; count];
                delta[k] = sign * eps;
                let end = run(&delta, hold_momentum);
                let theta = end.configuration.difference(&reference.configuration);
                let second = if hold_momentum {
                    end.momentum - reference.momentum
                } else {
                    end.velocity - reference.velocity
                };
                sides.push((theta, second));
            }
            for r in 0..D {
                result[which][(r, k)] = (sides[0].0[r] - sides[1].0[r]) / (2.0 * eps);
                result[which][(D + r, k)] = (sides[0].1[r] - sides[1].1[r]) / (2.0 * eps);
            }
        }
    }
    let [velocity_columns, momentum_columns] = result;
    (velocity_columns, momentum_columns)
}

/// `max |X − Y| / max(max |Y|, 1)`.
fn relative(x: &DMatrix<f64>, y: &DMatrix<f64>) -> f64 {
    (x - y).amax() / y.amax().max(1.0)
}

/// The exact parameter columns against differences for one system, both charts,
/// `n = 4, 8`, the linearised step taken after one step (a moving start); returns the
/// worst relative difference.
fn compare<S, const D: usize>(
    name: &str,
    make: impl Fn(&[f64]) -> S,
    scales: &[f64],
    start: (Element<S, D>, SVector<f64, D>),
    input: SVector<f64, D>,
) -> f64
where
    S: System<D>,
    ChartKind: GroupChart<S::Group, D>,
    Element<S, D>: Difference<D>,
{
    let system = make(&vec![0.0; scales.len()]);
    let names = system.parameter_names();
    assert_eq!(names.len(), scales.len(), "{name}: {names:?}");
    let mut worst = 0.0f64;
    for chart in [ChartKind::Exp, ChartKind::Cayley] {
        for n in [4, 8] {
            let settings = StepSettings::new(0.25, n).unwrap().with_chart(chart);
            let mut integrator =
                Integrator::new(make(&vec![0.0; scales.len()]), settings, start.0, start.1)
                    .unwrap();
            integrator.set_input(input).unwrap();
            integrator.step().unwrap();
            let s = *integrator.state();
            let (p_velocity, p_momentum) = differences(
                &make,
                names.len(),
                scales,
                settings,
                (s.time, s.configuration, s.velocity, s.momentum),
                input,
            );
            let exact = integrator.step_linearized_with_parameters().unwrap();
            assert_eq!(exact.parameter_names(), &names[..]);
            let dv = relative(exact.p(Coordinates::Velocity).unwrap(), &p_velocity);
            let dm = relative(exact.p(Coordinates::Momentum).unwrap(), &p_momentum);
            println!(
                "| {name} | {chart:?} | {n} | {} | {dv:.1e} | {dm:.1e} |",
                names.len()
            );
            // The differences' own error is ~1e-10 (see `differences`); #27's goal for
            // A and B is 1e-7, kept here.
            assert!(
                dv < 1e-7 && dm < 1e-7,
                "{name} {chart:?} n = {n}: velocity {dv:e}, momentum {dm:e}"
            );
            worst = worst.max(dv).max(dm);
        }
    }
    worst
}

#[test]
fn parameter_derivatives_match_central_differences() {
    println!(
        "| system | chart | n | parameters | ∂x₊/∂p, velocity held | momentum held |\n|---|---|---|---|---|---|"
    );
    let inertia_scales = [0.5; 6];
    let with_mass = [0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 1.0];
    let so3_start = (
        SO3::exp(&Vector3::new(0.2, -0.1, 0.3)),
        Vector3::new(0.6, 0.1, -0.4),
    );
    let torque = Vector3::new(0.05, -0.02, 0.03);
    let mut worst = 0.0f64;
    worst = worst.max(compare(
        "free body",
        |d| RigidBody::new(inertia(d)),
        &inertia_scales,
        so3_start,
        torque,
    ));
    worst = worst.max(compare(
        "heavy top",
        |d| HeavyTop::new(inertia(d), 1.0 + d[6], 0.3, Vector3::z(), Vector3::z()).unwrap(),
        &with_mass,
        so3_start,
        torque,
    ));
    worst = worst.max(compare(
        "body in a potential",
        |d| RigidBodyInPotential::new(inertia(d), Dipole),
        &inertia_scales,
        so3_start,
        torque,
    ));
    worst = worst.max(compare(
        "damped body",
        |d| Forced::new(RigidBody::new(inertia(d)), AngularDamping(0.3)),
        &inertia_scales,
        so3_start,
        Vector3::zeros(),
    ));
    let xi = SVector::<f64, 6>::new(0.6, 0.1, -0.4, 0.1, -0.2, 0.05);
    let wrench = SVector::<f64, 6>::new(0.02, 0.0, -0.01, 0.1, 0.05, 0.0);
    worst = worst.max(compare(
        "free body in space",
        |d| FreeBody::new(inertia(d), 1.3 + d[6]).unwrap(),
        &with_mass,
        (SE3::exp(&(xi * 0.5)), xi),
        wrench,
    ));
    worst = worst.max(compare(
        "body in space, space force",
        |d| {
            Forced::new(
                FreeBody::new(inertia(d), 1.3 + d[6]).unwrap(),
                SpaceForce(Vector3::new(0.0, 0.1, -0.2)),
            )
        },
        &with_mass,
        (SE3::exp(&(xi * 0.5)), xi),
        wrench,
    ));
    worst = worst.max(compare(
        "body in a field",
        |d| BodyInField::new(inertia(d), 1.3 + d[6], Field).unwrap(),
        &with_mass,
        (SE3::exp(&(xi * 0.5)), xi),
        wrench,
    ));
    let orbit_start = SE3::new(
        SO3::exp(&Vector3::new(0.1, 0.2, 0.0)),
        Vector3::new(3.0, 0.0, 0.5),
    );
    let orbit_velocity = SVector::<f64, 6>::new(0.6, 0.1, -0.4, 0.0, 0.55, 0.05);
    worst = worst.max(compare(
        "orbiting body",
        |d| OrbitingBody::new(inertia(d), 1.0 + d[6], 1.0 + d[7]).unwrap(),
        &[0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 1.0, 1.0],
        (orbit_start, orbit_velocity),
        wrench,
    ));
    let axes = [Vector3::x(), Vector3::y(), Vector3::new(0.0, 0.6, 0.8)];
    worst = worst.max(compare(
        "gyrostat, three wheels",
        |d| Gyrostat::new(moved(10.0, d), axes, [0.1 + d[6], 0.2 + d[7], 0.15 + d[8]]).unwrap(),
        &[5.0, 5.0, 5.0, 5.0, 5.0, 5.0, 0.1, 0.1, 0.1],
        (
            BodyWheels {
                attitude: SO3::exp(&Vector3::new(0.2, -0.1, 0.3)),
                wheels: SVector::<f64, 3>::new(0.1, -0.2, 0.05),
            },
            SVector::<f64, 6>::new(0.06, 0.01, -0.04, 0.5, -0.3, 0.8),
        ),
        SVector::<f64, 6>::new(0.01, 0.0, 0.0, 0.02, -0.01, 0.005),
    ));
    println!("worst: {worst:.1e}");
}

/// The names: the inertia tensor's entries first, then the mass (the gyrostat: its
/// wheels; the orbiting body: the mass and the gravitational parameter); a system without
/// parameters has none and `p` says so only when asked.
#[test]
fn parameters_are_named_and_only_computed_when_asked() {
    let body = RigidBody::new(inertia(&[]));
    assert_eq!(
        System::<3>::parameter_names(&body),
        INERTIA_PARAMETERS.to_vec()
    );
    let orbit = OrbitingBody::new(inertia(&[]), 1.0, 1.0).unwrap();
    assert_eq!(orbit.parameter_names()[6..], ["mass", "mu"]);
    let mut integrator = Integrator::new(
        body,
        StepSettings::new(0.25, 6).unwrap(),
        SO3::identity(),
        Vector3::new(0.6, 0.1, -0.4),
    )
    .unwrap();
    let plain = integrator.linearize().unwrap();
    assert!(plain.p(Coordinates::Velocity).is_none() && plain.parameter_names().is_empty());
    // No parameters: an empty P, not an error.
    let mut bare = Integrator::new(
        Plain,
        StepSettings::new(0.25, 6).unwrap(),
        SO3::identity(),
        Vector3::new(0.6, 0.1, -0.4),
    )
    .unwrap();
    let none = bare.linearize_with_parameters().unwrap();
    assert_eq!(none.p(Coordinates::Velocity).unwrap().shape(), (6, 0));
    assert!(none.parameter_names().is_empty());
    let with = integrator.linearize_with_parameters().unwrap();
    assert_eq!(with.p(Coordinates::Momentum).unwrap().shape(), (6, 6));
    // The same A and B either way: the parameters add columns, nothing else.
    assert_eq!(
        with.a(Coordinates::Velocity),
        plain.a(Coordinates::Velocity)
    );
    assert_eq!(
        with.b(Coordinates::Velocity),
        plain.b(Coordinates::Velocity)
    );
}

/// A body at rest under a constant torque `u` along a principal axis `e_a` turns about
/// that axis alone (`Ω × JΩ = 0` all along), so the exp chart's step is the exact
/// zero-order hold of `θ̈ = u/J_a` (for `n ≥ 3`: the rotation vector `θ(t) e_a` is a
/// quadratic, which the Galerkin curve holds exactly; in the Cayley chart it is
/// `2 tan(θ/2) e_a`, not a polynomial, and the step has the method's error), and so is
/// every step of a body whose diagonal entries are moved (the axes stay): `∂ω₊/∂J_bb =
/// −h u_a δ_ab / J_a²` and `∂θ₊/∂J_bb = −(h²/2) u_a δ_ab / J_a²` (velocity coordinates; a
/// start at rest has no momentum to move). Every axis; to rounding (1e-14
/// against entries of order 0.1). The off-diagonal entries turn the axes (no closed form):
/// the differences above check them.
#[test]
fn a_body_at_rest_under_a_torque_has_the_zero_order_holds_derivatives() {
    let moments = [0.5, 0.9, 0.7];
    let j = Inertia::from_principal_moments(moments).unwrap();
    let h = 0.2;
    let chart = ChartKind::Exp;
    for n in [3, 6, 10] {
        for (a, moment) in moments.into_iter().enumerate() {
            let u = Vector3::ith(a, 0.3);
            let settings = StepSettings::new(h, n).unwrap().with_chart(chart);
            let mut integrator = Integrator::new(
                RigidBody::new(j),
                settings,
                SO3::identity(),
                Vector3::zeros(),
            )
            .unwrap();
            integrator.set_input(u).unwrap();
            let step = integrator.linearize_with_parameters().unwrap();
            let p = step.p(Coordinates::Velocity).unwrap();
            for b in 0..3 {
                let turn = if a == b {
                    -0.3 / (moment * moment)
                } else {
                    0.0
                };
                for r in 0..3 {
                    let expected = if r == a { turn } else { 0.0 };
                    let (theta, omega) = (p[(r, b)], p[(3 + r, b)]);
                    assert!(
                        (theta - 0.5 * h * h * expected).abs() < 1e-14
                            && (omega - h * expected).abs() < 1e-14,
                        "{chart:?} n = {n}, u along {a}, {}: row {r}: {theta:e}, {omega:e}",
                        INERTIA_PARAMETERS[b],
                    );
                }
            }
        }
    }
}
