//! The exact linearisation of a step against central finite differences through the
//! public stepping API (an independent reference: it only takes steps), and against the
//! laws it must satisfy: the zero-order hold at rest, unit determinant and the
//! symplectic form for conservative systems.
//!
//! `cargo test -p lgsvi-mechanics --release --test linearize -- --nocapture` prints the
//! comparison table.

use lgsvi_mechanics::forces::{AngularDamping, BodyTorque, ForceOfTime, SpaceForce};
use lgsvi_mechanics::group::{ConfigurationGroup, GroupChart, Rotations};
use lgsvi_mechanics::lie::{ChartKind, SE3, SO3};
use lgsvi_mechanics::linearization::{Coordinates, StepLinearization};
use lgsvi_mechanics::{
    Forced, FreeBody, GroupLagrangian, HeavyTop, Inertia, Integrator, Matching, MechanicsError,
    OrbitingBody, Potential, RigidBody, RigidBodyInPotential, State, StepSettings, System,
};
use nalgebra::{DMatrix, Matrix3, RealField, SVector, Vector3};

/// The group perturbation of the linearisation's coordinates, `g exp(θ)`, and its
/// inverse, written with the groups' own exponential and logarithm.
trait Perturb<const D: usize>: Copy {
    fn perturbed(&self, theta: &SVector<f64, D>) -> Self;
    fn difference(&self, from: &Self) -> SVector<f64, D>;
}

impl Perturb<3> for SO3 {
    fn perturbed(&self, theta: &Vector3<f64>) -> Self {
        self.compose(&SO3::exp(theta))
    }
    fn difference(&self, from: &Self) -> Vector3<f64> {
        from.inverse().compose(self).log()
    }
}

impl Perturb<6> for SE3 {
    fn perturbed(&self, theta: &SVector<f64, 6>) -> Self {
        self.compose(&SE3::exp(theta))
    }
    fn difference(&self, from: &Self) -> SVector<f64, 6> {
        from.inverse().compose(self).log()
    }
}

use lgsvi_mechanics::lie::LieGroup;

/// Central differences of one step in velocity coordinates `(θ, ω)` and the input:
/// `(A, B)`. The step `ε = 1e-5` balances the truncation (`ε²` times third derivatives of
/// order one: ~1e-10) against the rounding of the step's end state (~1e-15 / ε = 1e-10).
fn differences<S, C, const D: usize>(
    integrator: &mut Integrator<S, C, D>,
) -> (DMatrix<f64>, DMatrix<f64>)
where
    S: System<D>,
    C: GroupChart<S::Group, D>,
    <S::Group as ConfigurationGroup<D>>::Element<f64>: Perturb<D>,
{
    const EPS: f64 = 1e-5;
    let start = *integrator.state();
    let input = *integrator.input();
    let mut run = |theta: SVector<f64, D>, omega: SVector<f64, D>, u: SVector<f64, D>| {
        integrator
            .reset(
                start.time,
                start.configuration.perturbed(&theta),
                start.velocity + omega,
            )
            .unwrap();
        integrator.set_input(input + u).unwrap();
        integrator.step().unwrap();
        let end = *integrator.state();
        (end.configuration, end.velocity)
    };
    let zero = SVector::<f64, D>::zeros();
    let (g_ref, v_ref) = run(zero, zero, zero);
    let mut a = DMatrix::zeros(2 * D, 2 * D);
    let mut b = DMatrix::zeros(2 * D, D);
    for col in 0..3 * D {
        let mut out = [SVector::<f64, D>::zeros(); 4];
        for (side, sign) in [1.0, -1.0].into_iter().enumerate() {
            let mut e = [zero; 3];
            e[col / D][col % D] = sign * EPS;
            let (g, v) = run(e[0], e[1], e[2]);
            out[2 * side] = g.difference(&g_ref);
            out[2 * side + 1] = v - v_ref;
        }
        for r in 0..D {
            let dtheta = (out[0][r] - out[2][r]) / (2.0 * EPS);
            let domega = (out[1][r] - out[3][r]) / (2.0 * EPS);
            if col < 2 * D {
                a[(r, col)] = dtheta;
                a[(D + r, col)] = domega;
            } else {
                b[(r, col - 2 * D)] = dtheta;
                b[(D + r, col - 2 * D)] = domega;
            }
        }
    }
    integrator
        .reset(start.time, start.configuration, start.velocity)
        .unwrap();
    integrator.set_input(input).unwrap();
    (a, b)
}

/// `max |X − Y| / max(max |Y|, 1)`.
fn relative(x: &DMatrix<f64>, y: &DMatrix<f64>) -> f64 {
    (x - y).amax() / y.amax().max(1.0)
}

/// The linearisation against central differences, for one system in the charts and
/// node counts of the goal; returns the worst relative difference of `A` and `B`.
fn compare<S, const D: usize>(
    name: &str,
    make: impl Fn(StepSettings) -> Integrator<S, ChartKind, D>,
) -> f64
where
    S: System<D>,
    ChartKind: GroupChart<S::Group, D>,
    <S::Group as ConfigurationGroup<D>>::Element<f64>: Perturb<D>,
{
    let mut worst = 0.0f64;
    let mut chord_steps = 0;
    for chart in [ChartKind::Exp, ChartKind::Cayley] {
        for n in [4, 8, 12] {
            let settings = StepSettings::new(0.25, n).unwrap().with_chart(chart);
            let mut integrator = make(settings);
            // One step first, so that the linearised step starts from a moving state
            // with a predictor that has a last curve (chord iterations included).
            integrator.step().unwrap();
            let (a_fd, b_fd) = differences(&mut integrator);
            let before = *integrator.statistics();
            let exact = integrator.step_linearized().unwrap();
            let after = integrator.statistics();
            let iterations = after.newton_iterations - before.newton_iterations;
            let chord = iterations - (after.factorizations - before.factorizations);
            chord_steps += usize::from(chord > 0);
            let (da, db) = (
                relative(exact.a(Coordinates::Velocity), &a_fd),
                relative(exact.b(Coordinates::Velocity), &b_fd),
            );
            println!("| {name} | {chart:?} | {n} | {iterations} ({chord}) | {da:.1e} | {db:.1e} |");
            // The differences' own error is ~1e-10 (see `differences`); the goal is 1e-7.
            assert!(
                da < 1e-7 && db < 1e-7,
                "{name} {chart:?} n = {n}: A {da:e}, B {db:e}"
            );
            worst = worst.max(da).max(db);
        }
    }
    // The linearisation must not depend on how Newton ended: steps that ended on chord
    // iterations (a kept, older matrix) are among those checked for every system.
    assert!(
        chord_steps > 0,
        "{name}: no linearised step ended on a chord iteration"
    );
    worst
}

fn inertia() -> Inertia {
    Inertia::from_principal_moments([0.5, 0.9, 0.7]).unwrap()
}

/// A dipole along body x in a field along world z.
#[derive(Clone, Copy)]
struct Dipole;
impl Potential for Dipole {
    fn potential<T: RealField + Copy>(&self, r: &Matrix3<T>) -> T {
        -r[(2, 0)] * nalgebra::convert::<f64, T>(0.3)
    }
}

/// A Lagrangian whose momentum depends on the attitude (`∂²ℓ/∂R∂Ω ≠ 0`, through the
/// default dual-number derivatives): the Legendre transform's mixed block at work.
#[derive(Clone, Copy)]
struct Coupled;
impl GroupLagrangian<3> for Coupled {
    type Group = Rotations;
    fn lagrangian<T: RealField + Copy>(&self, _t: f64, g: &SO3<T>, w: &Vector3<T>) -> T {
        let c = |x: f64| -> T { nalgebra::convert(x) };
        let r = g.matrix();
        let up = r.transpose() * Vector3::new(c(0.2), c(-0.1), c(1.0));
        c(0.5) * (w.x * w.x * c(1.2) + w.y * w.y * c(2.1) + w.z * w.z * c(2.7))
            + up.dot(w) * c(0.3)
            + r[(0, 1)] * r[(2, 2)] * c(1.7)
    }
}

fn so3<S: System<3, Group = Rotations> + Clone>(
    system: S,
    input: Vector3<f64>,
) -> impl Fn(StepSettings) -> Integrator<S, ChartKind, 3> {
    move |settings| {
        let start = SO3::exp(&Vector3::new(0.2, -0.1, 0.3));
        let mut integrator = Integrator::new(
            system.clone(),
            settings,
            start,
            Vector3::new(0.6, 0.1, -0.4),
        )
        .unwrap();
        integrator.set_input(input).unwrap();
        integrator
    }
}

#[test]
fn so3_systems_match_central_differences() {
    println!(
        "| system | chart | n | Newton iterations (chord) | A | B |\n|---|---|---|---|---|---|"
    );
    let torque = Vector3::new(0.05, -0.02, 0.03);
    compare(
        "free body",
        so3(RigidBody::new(inertia()), Vector3::zeros()),
    );
    compare(
        "free body, torque input",
        so3(RigidBody::new(inertia()), torque),
    );
    let top = HeavyTop::new(inertia(), 1.0, 0.3, Vector3::z(), Vector3::z()).unwrap();
    compare("heavy top", so3(top, torque));
    compare(
        "damped body",
        so3(
            Forced::new(RigidBody::new(inertia()), AngularDamping(0.3)),
            torque,
        ),
    );
    compare(
        "torque profile",
        so3(
            Forced::new(
                RigidBody::new(inertia()),
                ForceOfTime(|t: f64| Vector3::new(0.1 * t.sin(), 0.02, -0.1 * t.cos())),
            ),
            Vector3::zeros(),
        ),
    );
    compare(
        "constant body torque",
        so3(
            Forced::new(RigidBody::new(inertia()), BodyTorque(torque)),
            Vector3::zeros(),
        ),
    );
    compare(
        "user potential",
        so3(RigidBodyInPotential::new(inertia(), Dipole), torque),
    );
    compare("attitude–velocity coupling", so3(Coupled, torque));
}

#[test]
fn se3_systems_match_central_differences() {
    println!(
        "| system | chart | n | Newton iterations (chord) | A | B |\n|---|---|---|---|---|---|"
    );
    let xi = SVector::<f64, 6>::new(0.6, 0.1, -0.4, 0.1, -0.2, 0.05);
    let wrench = SVector::<f64, 6>::new(0.02, 0.0, -0.01, 0.1, 0.05, 0.0);
    let free = FreeBody::new(inertia(), 1.3).unwrap();
    compare("free body in space", |settings| {
        let mut i = Integrator::new(free, settings, SE3::exp(&(xi * 0.5)), xi).unwrap();
        i.set_input(wrench).unwrap();
        i
    });
    compare("body in space, space force", |settings| {
        let system = Forced::new(free, SpaceForce(Vector3::new(0.0, 0.1, -0.2)));
        Integrator::new(system, settings, SE3::exp(&(xi * 0.5)), xi).unwrap()
    });
    let orbit = OrbitingBody::new(inertia(), 1.0, 1.0).unwrap();
    compare("orbiting body", |settings| {
        let start = SE3::new(
            SO3::exp(&Vector3::new(0.1, 0.2, 0.0)),
            Vector3::new(3.0, 0.0, 0.5),
        );
        let v = SVector::<f64, 6>::new(0.6, 0.1, -0.4, 0.0, 0.55, 0.05);
        let mut i = Integrator::new(orbit, settings, start, v).unwrap();
        i.set_input(wrench).unwrap();
        i
    });
}

/// The world-frame coordinates of a body in space against differences taken in them.
#[test]
fn world_frame_of_an_orbiting_body_matches_differences() {
    const EPS: f64 = 1e-5;
    let orbit = OrbitingBody::new(inertia(), 1.0, 1.0).unwrap();
    let start = SE3::new(
        SO3::exp(&Vector3::new(0.1, 0.2, 0.0)),
        Vector3::new(3.0, 0.0, 0.5),
    );
    let v = SVector::<f64, 6>::new(0.6, 0.1, -0.4, 0.0, 0.55, 0.05);
    let mut integrator =
        Integrator::new(orbit, StepSettings::new(0.5, 8).unwrap(), start, v).unwrap();
    let exact = integrator.linearize().unwrap();
    let (a, _) = exact.world_frame();
    // World state: attitude by R exp(θ̂), position, body angular velocity, ẋ = R v.
    let world = |g: &SE3, xi: &SVector<f64, 6>| {
        let r = g.rotation().to_matrix();
        let xdot = r * xi.fixed_rows::<3>(3);
        (
            *g,
            *g.translation(),
            xi.fixed_rows::<3>(0).into_owned(),
            xdot,
        )
    };
    let run = |integrator: &mut Integrator<OrbitingBody, ChartKind, 6>, s: &SVector<f64, 12>| {
        let r0 = start
            .rotation()
            .compose(&SO3::exp(&s.fixed_rows::<3>(0).into_owned()));
        let x0 = start.translation() + s.fixed_rows::<3>(3);
        let w0 = v.fixed_rows::<3>(0) + s.fixed_rows::<3>(6);
        let xdot0 = start.rotation().to_matrix() * v.fixed_rows::<3>(3) + s.fixed_rows::<3>(9);
        let body_v = r0.to_matrix().transpose() * xdot0;
        let mut xi0 = SVector::<f64, 6>::zeros();
        xi0.fixed_rows_mut::<3>(0).copy_from(&w0);
        xi0.fixed_rows_mut::<3>(3).copy_from(&body_v);
        integrator.reset(0.0, SE3::new(r0, x0), xi0).unwrap();
        integrator.step().unwrap();
        let e = *integrator.state();
        world(&e.configuration, &e.velocity)
    };
    let reference = run(&mut integrator, &SVector::zeros());
    let mut fd = DMatrix::<f64>::zeros(12, 12);
    for col in 0..12 {
        let mut sides = Vec::new();
        for sign in [1.0, -1.0] {
            let mut s = SVector::<f64, 12>::zeros();
            s[col] = sign * EPS;
            let (g, x, w, xdot) = run(&mut integrator, &s);
            let theta = (reference.0.rotation().inverse().compose(g.rotation())).log();
            let mut out = SVector::<f64, 12>::zeros();
            out.fixed_rows_mut::<3>(0).copy_from(&theta);
            out.fixed_rows_mut::<3>(3).copy_from(&(x - reference.1));
            out.fixed_rows_mut::<3>(6).copy_from(&(w - reference.2));
            out.fixed_rows_mut::<3>(9).copy_from(&(xdot - reference.3));
            sides.push(out);
        }
        let column = (sides[0] - sides[1]) / (2.0 * EPS);
        for r in 0..12 {
            fd[(r, col)] = column[r];
        }
    }
    let difference = relative(&a, &fd);
    assert!(difference < 1e-7, "world frame: {difference:e}");
}

/// At rest with zero input the step is the exact zero-order hold of `θ̈ = J⁻¹u` for any
/// `n ≥ 3` (the Galerkin curve holds the quadratic exactly): `A = [[I, hI], [0, I]]`,
/// `B = [[h²/2 J⁻¹], [h J⁻¹]]` to rounding.
#[test]
fn a_body_at_rest_is_the_zero_order_hold() {
    let j = Matrix3::new(0.5, 0.1, 0.0, 0.1, 0.9, -0.05, 0.0, -0.05, 0.7);
    let inertia = Inertia::from_tensor(j).unwrap();
    let j_inv = j.try_inverse().unwrap();
    let h = 0.3;
    for chart in [ChartKind::Exp, ChartKind::Cayley] {
        for n in 3..=10 {
            let settings = StepSettings::new(h, n).unwrap().with_chart(chart);
            let mut integrator = Integrator::new(
                RigidBody::new(inertia),
                settings,
                SO3::exp(&Vector3::new(0.3, 0.2, -1.0)),
                Vector3::zeros(),
            )
            .unwrap();
            let step = integrator.step_linearized().unwrap();
            let mut a = DMatrix::<f64>::identity(6, 6);
            let mut b = DMatrix::<f64>::zeros(6, 3);
            for i in 0..3 {
                a[(i, 3 + i)] = h;
            }
            b.view_mut((0, 0), (3, 3))
                .copy_from(&(j_inv * (0.5 * h * h)));
            b.view_mut((3, 0), (3, 3)).copy_from(&(j_inv * h));
            let da = (step.a(Coordinates::Velocity) - &a).amax();
            let db = (step.b(Coordinates::Velocity) - &b).amax();
            // Entries of order one, a handful of operations each: 1e-14 absolute.
            assert!(
                da < 1e-14 && db < 1e-14,
                "{chart:?} n = {n}: A {da:e}, B {db:e}"
            );
        }
    }
}

/// A conservative step preserves volume (`det A = 1`) and the left-trivialised
/// symplectic form (`Aᵀ W(μ₊) A = W(μ)` in momentum coordinates), to rounding.
#[test]
fn conservative_steps_are_symplectic() {
    let top = HeavyTop::new(
        inertia(),
        1.0,
        0.3,
        Vector3::z(),
        Vector3::new(0.0, 0.3, 1.0).normalize(),
    )
    .unwrap();
    let checks = |step: &StepLinearization<SO3, 3>, what: &str| {
        let a = step.a(Coordinates::Momentum);
        let w_in = StepLinearization::<SO3, 3>::symplectic_form::<Rotations>(&step.start.momentum);
        let w_out = StepLinearization::<SO3, 3>::symplectic_form::<Rotations>(&step.end.momentum);
        let defect = (a.transpose() * w_out * a - w_in).amax();
        let det = a.determinant();
        let det_velocity = step.a(Coordinates::Velocity).determinant();
        // Products of 6 × 6 matrices with entries of order one: ~1e-14; the goal's 1e-12.
        assert!(defect < 1e-12, "{what}: symplectic defect {defect:e}");
        assert!((det - 1.0).abs() < 1e-12, "{what}: det A = {det}");
        // Constant L_ξξ = J: the velocity coordinates keep the volume too.
        assert!(
            (det_velocity - 1.0).abs() < 1e-12,
            "{what}: det A (velocity) = {det_velocity}"
        );
    };
    for chart in [ChartKind::Exp, ChartKind::Cayley] {
        for n in [4, 8, 12] {
            let settings = StepSettings::new(0.5, n).unwrap().with_chart(chart);
            let mut body = Integrator::new(
                RigidBody::new(inertia()),
                settings,
                SO3::identity(),
                Vector3::new(0.6, 0.1, -0.4),
            )
            .unwrap();
            let mut top =
                Integrator::new(top, settings, SO3::identity(), Vector3::new(0.6, 0.1, -0.4))
                    .unwrap();
            for _ in 0..3 {
                checks(&body.step_linearized().unwrap(), "free body");
                checks(&top.step_linearized().unwrap(), "heavy top");
            }
        }
    }
}

/// The step taken by `step_linearized` is the step `step` takes (measured gaps on the
/// configured systems below: at most 3.3e-16).
#[test]
fn step_linearized_takes_the_same_step() {
    let settings = StepSettings::new(0.5, 8).unwrap();
    let make = || {
        Integrator::new(
            RigidBody::new(inertia()),
            settings,
            SO3::identity(),
            Vector3::new(0.6, 0.1, -0.4),
        )
        .unwrap()
    };
    let (mut plain, mut linearised) = (make(), make());
    let before = *linearised.state();
    linearised.linearize().unwrap();
    assert_eq!(
        *linearised.state(),
        before,
        "linearize must not take the step"
    );
    assert_eq!(linearised.statistics().steps, 0);
    for _ in 0..5 {
        plain.step().unwrap();
        let step = linearised.step_linearized().unwrap();
        assert_eq!(plain.state(), linearised.state());
        assert_eq!(step.end, *linearised.state());
    }
    // A step to be linearised keeps its last assembly's Hessians. With configuration
    // terms, an assembly with Hessians forms the matching's transport as a matrix where
    // one without applies it from the chart's coefficients: the momentum `w` of the two
    // differs in its last bits, so steps agree to rounding (a few ulps of the state, which
    // 20 steps of a regular motion do not amplify), not bit for bit: a configured system
    // under an input and an orbiting body under a wrench.
    let top = HeavyTop::new(inertia(), 1.0, 0.3, Vector3::z(), Vector3::z()).unwrap();
    let make = || {
        let mut i =
            Integrator::new(top, settings, SO3::identity(), Vector3::new(0.6, 0.1, -0.4)).unwrap();
        i.set_input(Vector3::new(0.02, -0.01, 0.03)).unwrap();
        i
    };
    let (mut plain, mut linearised) = (make(), make());
    for _ in 0..20 {
        plain.step().unwrap();
        linearised.step_linearized().unwrap();
        close_states(plain.state(), linearised.state());
    }
    let orbit = OrbitingBody::new(inertia(), 1.0, 1.0).unwrap();
    let make = || {
        let start = SE3::new(
            SO3::exp(&Vector3::new(0.1, 0.2, 0.0)),
            Vector3::new(3.0, 0.0, 0.5),
        );
        let v = SVector::<f64, 6>::new(0.6, 0.1, -0.4, 0.0, 0.55, 0.05);
        let mut i = Integrator::new(orbit, settings, start, v).unwrap();
        i.set_input(SVector::<f64, 6>::new(0.02, 0.0, -0.01, 0.1, 0.05, 0.0))
            .unwrap();
        i
    };
    let (mut plain, mut linearised) = (make(), make());
    for _ in 0..20 {
        plain.step().unwrap();
        linearised.step_linearized().unwrap();
        close_states(plain.state(), linearised.state());
    }
}

/// Two states of one step to rounding: the same time, configurations within 1e-14 (the
/// group's matrix entries are at most 1 in size; a few ulps, with room for 20 steps) and
/// velocities and momenta within 1e-14 of their size.
fn close_states<E: Perturb<D>, const D: usize>(a: &State<E, D>, b: &State<E, D>) {
    assert_eq!(a.time, b.time);
    let distance = a.configuration.difference(&b.configuration).amax();
    assert!(distance <= 1e-14, "configurations {distance:e} apart");
    for (x, y, what) in [
        (a.momentum, b.momentum, "momenta"),
        (a.velocity, b.velocity, "velocities"),
    ] {
        let gap = (x - y).amax();
        assert!(gap <= 1e-14 * x.amax().max(1.0), "{what} {gap:e} apart");
    }
}

/// The paper's matching is refused with a typed error that names the remedy.
#[test]
fn the_paper_matching_is_refused() {
    let settings = StepSettings::new(0.5, 8)
        .unwrap()
        .with_matching(Matching::Paper);
    let mut integrator = Integrator::new(
        RigidBody::new(inertia()),
        settings,
        SO3::identity(),
        Vector3::new(0.6, 0.1, -0.4),
    )
    .unwrap();
    match integrator.linearize() {
        Err(MechanicsError::InvalidSetting { name, reason, .. }) => {
            assert_eq!(name, "matching");
            assert!(reason.contains("exact matching"), "{reason}");
        }
        other => panic!("expected InvalidSetting, got {other:?}"),
    }
}

/// The configurations at the Gauss points, `∂θ_j/∂(θ, ω, u)`, against central differences
/// of whole steps read on their Galerkin curves (the dense output) at the points: an
/// orbiting body with a wrench at each point (its gravity gradient couples attitude and
/// orbit), a rigid body with a torque held over the step. `ε = 1e-5` as in
/// [`differences`]: truncation ~1e-10, rounding ~1e-15/ε = 1e-10; the columns are of
/// order one, so 1e-7 is the bound the other Jacobians are held to.
#[test]
fn the_configurations_at_the_points_match_differences() {
    fn check<S, const D: usize>(
        name: &str,
        make: impl Fn() -> Integrator<S, ChartKind, D>,
        inputs: Option<Vec<SVector<f64, D>>>,
    ) where
        S: System<D>,
        ChartKind: GroupChart<S::Group, D>,
        <S::Group as ConfigurationGroup<D>>::Element<f64>: Perturb<D>,
    {
        const EPS: f64 = 1e-5;
        let mut it = make();
        let start = *it.state();
        let nodes = it.quadrature_nodes();
        let h = it.settings().h();
        let points = inputs.as_ref().map_or(1, Vec::len);
        // A whole step from the perturbed start under the perturbed inputs: the
        // configurations on its curve at the Gauss points.
        let run = |theta: SVector<f64, D>, omega: SVector<f64, D>, u: &[SVector<f64, D>]| {
            let mut it = make();
            it.reset(
                start.time,
                start.configuration.perturbed(&theta),
                start.velocity + omega,
            )
            .unwrap();
            match &inputs {
                Some(_) => it.set_input_at_points(u).unwrap(),
                None => it.set_input(*it.input() + u[0]).unwrap(),
            }
            it.step().unwrap();
            let curve = it.last_curve().unwrap();
            nodes
                .iter()
                .map(|c| curve.at(c * h).unwrap().0)
                .collect::<Vec<_>>()
        };
        let base_inputs = inputs.clone().unwrap_or(vec![SVector::zeros()]);
        if let Some(u) = &inputs {
            it.set_input_at_points(u).unwrap();
        }
        let exact = it.step_linearized().unwrap();
        let exact = exact.point_configurations(Coordinates::Velocity);
        assert_eq!(exact.len(), nodes.len());
        let zero = SVector::<f64, D>::zeros();
        let mut worst = 0.0f64;
        for col in 0..(2 + points) * D {
            let mut sides = Vec::new();
            for sign in [1.0, -1.0] {
                let (mut theta, mut omega, mut u) = (zero, zero, base_inputs.clone());
                match col / D {
                    0 => theta[col % D] = sign * EPS,
                    1 => omega[col % D] = sign * EPS,
                    i => u[i - 2][col % D] += sign * EPS,
                }
                sides.push(run(theta, omega, &u));
            }
            for (j, matrix) in exact.iter().enumerate() {
                let difference = sides[0][j].difference(&sides[1][j]) / (2.0 * EPS);
                for r in 0..D {
                    let error = (matrix[(r, col)] - difference[r]).abs();
                    worst = worst.max(error);
                    assert!(
                        error < 1e-7,
                        "{name}: point {j}, row {r}, column {col}: {} against {}",
                        matrix[(r, col)],
                        difference[r]
                    );
                }
            }
        }
        println!("{name}: largest difference {worst:.1e}");
    }
    let orbit = OrbitingBody::new(inertia(), 1.0, 1.0).unwrap();
    let make_orbit = || {
        let start = SE3::new(
            SO3::exp(&Vector3::new(0.1, 0.2, 0.0)),
            Vector3::new(3.0, 0.0, 0.5),
        );
        let v = SVector::<f64, 6>::new(0.6, 0.1, -0.4, 0.0, 0.55, 0.05);
        let settings = StepSettings::new(0.4, 7).unwrap();
        Integrator::new(orbit, settings, start, v).unwrap()
    };
    let m = make_orbit().quadrature_nodes().len();
    let wrenches = (0..m)
        .map(|j| {
            let s = j as f64;
            SVector::<f64, 6>::new(0.02 * s, -0.01, 0.03, 0.1 - 0.02 * s, 0.05, 0.01 * s)
        })
        .collect();
    check(
        "orbiting body, wrenches at the points",
        make_orbit,
        Some(wrenches),
    );
    let make_rigid = || {
        let settings = StepSettings::new(0.3, 8)
            .unwrap()
            .with_chart(ChartKind::Cayley);
        let mut it = Integrator::new(
            RigidBody::new(inertia()),
            settings,
            SO3::exp(&Vector3::new(0.2, -0.1, 0.3)),
            Vector3::new(0.6, 0.1, -0.4),
        )
        .unwrap();
        it.set_input(Vector3::new(0.05, -0.02, 0.01)).unwrap();
        it
    };
    check("rigid body, torque held", make_rigid, None);
}
