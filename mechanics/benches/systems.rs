//! Per-step cost of every built-in system, side by side in one run: the same body
//! (`J = diag(0.5, 0.9, 0.7)`, `Ω₀ = (0.6, 0.1, −0.4)`), `h = 0.5`, `n = 8`, the exp
//! chart and the exact matching. Each iteration restarts from the same state and takes
//! [`STEPS`] steps (so a damped or forced body does not drift into an easier regime as
//! criterion repeats it); divide the reported time by [`STEPS`] for one step. Two more
//! entries take `lgsvi bench`'s torqued body F1 (its body, start and torque, `h = 1`,
//! `n = 9`: its best setting at ≤ 1e-10 over T = 10) with and without the torque.
//!
//! Entries ending in `_control_loop` take a control loop's short step (`h = 0.05` on
//! SO(3), `0.1` on SE(3)), where a step starts from the Newton matrix an earlier step
//! factored; their `_fresh` twins solve every step from its own
//! (`StepSettings::with_factor_reuse(false)`).
//!
//! `cargo bench -p lgsvi-mechanics --bench systems` (add `-- --quick` for a short run).
use criterion::{criterion_group, criterion_main, Criterion};
use lgsvi_mechanics::forces::{AngularDamping, BodyTorque, ForceOfTime, SpaceForce};
use lgsvi_mechanics::group::Screw;
use lgsvi_mechanics::gyrostat::{BodyAndWheels, BodyWheels, Gyrostat};
use lgsvi_mechanics::lie::ChartKind;
use lgsvi_mechanics::lie::{SE3, SO3};
use lgsvi_mechanics::system::LocalDerivatives;
use lgsvi_mechanics::{
    BodyInField, FieldPotential, Forced, FreeBody, HeavyTop, Inertia, Integrator, OrbitingBody,
    Potential, RigidBody, RigidBodyInPotential, StepSettings, System,
};
use nalgebra::{Matrix3, RealField, SMatrix, SVector, Vector3};

/// Steps per measured iteration.
const STEPS: usize = 20;

fn inertia() -> Inertia {
    Inertia::from_principal_moments([0.5, 0.9, 0.7]).unwrap()
}

fn omega0() -> Vector3<f64> {
    Vector3::new(0.6, 0.1, -0.4)
}

fn settings() -> StepSettings {
    StepSettings::new(0.5, 8).unwrap()
}

/// A dipole along body x in a field along world z: `V = −0.3 (R e₁)·e₃`.
struct Dipole;
impl Potential for Dipole {
    fn potential<T: RealField + Copy>(&self, r: &Matrix3<T>) -> T {
        -r[(2, 0)] * nalgebra::convert::<f64, T>(0.3)
    }
}

/// Uniform gravity on the centre of mass and a dipole: `V = 9.81 m x_z − 0.3 (R e₁)·e₃`.
struct GravityAndDipole;
impl FieldPotential for GravityAndDipole {
    fn potential<T: RealField + Copy>(&self, _t: f64, r: &Matrix3<T>, x: &Vector3<T>) -> T {
        x.z * nalgebra::convert::<f64, T>(9.81) - r[(2, 0)] * nalgebra::convert::<f64, T>(0.3)
    }
}

/// The free body in space on the product SO(3) × ℝ³ (the gyrostat's group with three
/// components, the position in the world frame, `ℓ = ½ΩᵀJΩ + ½m|ẋ|²`, `m = 1`): the same
/// discrete map as SE(3)'s rotation–translation chart, for comparing the two groups' cost.
#[derive(Debug, Clone, Copy)]
struct ProductFreeBody(Matrix3<f64>);
impl System<6> for ProductFreeBody {
    type Group = BodyAndWheels<3>;
    fn lagrangian<T: RealField + Copy>(
        &self,
        _t: f64,
        _g: &BodyWheels<T, 3>,
        xi: &SVector<T, 6>,
    ) -> T {
        let j: Matrix3<T> = self.0.map(nalgebra::convert);
        let (w, v) = (xi.fixed_rows::<3>(0), xi.fixed_rows::<3>(3));
        (w.dot(&(j * w)) + v.dot(&v)) * nalgebra::convert::<f64, T>(0.5)
    }
    fn is_left_invariant(&self) -> bool {
        true
    }
    fn velocity_from_momentum(
        &self,
        _t: f64,
        _g: &BodyWheels<f64, 3>,
        mu: &SVector<f64, 6>,
    ) -> Option<SVector<f64, 6>> {
        let w = self.0.try_inverse()? * mu.fixed_rows::<3>(0);
        Some(SVector::<f64, 6>::new(w.x, w.y, w.z, mu[3], mu[4], mu[5]))
    }
    fn local_derivatives(
        &self,
        _t: f64,
        _g: &BodyWheels<f64, 3>,
        xi: &SVector<f64, 6>,
        with_hessian: bool,
    ) -> Option<LocalDerivatives<6>> {
        let mut m = SMatrix::<f64, 6, 6>::identity();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.0);
        Some(LocalDerivatives {
            configuration_gradient: SVector::zeros(),
            momentum: m * xi,
            configuration_hessian: SMatrix::zeros(),
            velocity_hessian: if with_hessian { m } else { SMatrix::zeros() },
        })
    }
}

fn bench_steps<S: System<D>, C: lgsvi_mechanics::group::GroupChart<S::Group, D>, const D: usize>(
    c: &mut Criterion,
    name: &str,
    integrator: Integrator<S, C, D>,
) {
    bench_with(c, name, integrator, Linearized::No);
}

/// As [`bench_steps`], each step with its exact linearisation
/// ([`Integrator::step_linearized`]): the cost of `A` and `B` beside a plain step.
fn bench_linearized<
    S: System<D>,
    C: lgsvi_mechanics::group::GroupChart<S::Group, D>,
    const D: usize,
>(
    c: &mut Criterion,
    name: &str,
    integrator: Integrator<S, C, D>,
) {
    bench_with(c, name, integrator, Linearized::Yes);
}

/// As [`bench_steps`], each step with its exact linearisation and its derivatives in the
/// system's parameters ([`Integrator::step_linearized_with_parameters`]).
fn bench_with_parameters<
    S: System<D>,
    C: lgsvi_mechanics::group::GroupChart<S::Group, D>,
    const D: usize,
>(
    c: &mut Criterion,
    name: &str,
    integrator: Integrator<S, C, D>,
) {
    bench_with(c, name, integrator, Linearized::WithParameters);
}

/// What a benchmarked step returns besides the step.
#[derive(Clone, Copy, PartialEq)]
enum Linearized {
    No,
    Yes,
    WithParameters,
}

fn bench_with<S: System<D>, C: lgsvi_mechanics::group::GroupChart<S::Group, D>, const D: usize>(
    c: &mut Criterion,
    name: &str,
    mut integrator: Integrator<S, C, D>,
    linearized: Linearized,
) {
    let start = *integrator.state();
    c.bench_function(name, |b| {
        b.iter(|| {
            integrator
                .reset(0.0, start.configuration, start.velocity)
                .unwrap();
            for _ in 0..STEPS {
                match linearized {
                    Linearized::Yes => {
                        std::hint::black_box(integrator.step_linearized().unwrap());
                    }
                    Linearized::WithParameters => {
                        std::hint::black_box(integrator.step_linearized_with_parameters().unwrap());
                    }
                    Linearized::No => {
                        integrator.step().unwrap();
                    }
                }
            }
        })
    });
}

fn so3<S: System<3>>(system: S) -> Integrator<S, ChartKind, 3>
where
    ChartKind: lgsvi_mechanics::group::GroupChart<S::Group, 3>,
{
    let start = <S::Group as lgsvi_mechanics::group::ConfigurationGroup<3>>::exp(&Vector3::zeros());
    Integrator::new(system, settings(), start, omega0()).unwrap()
}

fn bench(c: &mut Criterion) {
    let body = RigidBody::new(inertia());
    let torque = Vector3::new(0.001, 0.002, -0.001);
    bench_steps(c, "so3_free", so3(body));
    bench_steps(c, "so3_torque", so3(Forced::new(body, BodyTorque(torque))));
    bench_steps(
        c,
        "so3_damping",
        so3(Forced::new(body, AngularDamping(0.01))),
    );
    bench_steps(
        c,
        "so3_force_of_time",
        so3(Forced::new(
            body,
            ForceOfTime(|t: f64| Vector3::new(0.001 * t.sin(), 0.002, -0.001 * t.cos())),
        )),
    );
    let mut controlled = so3(body);
    controlled.set_input(torque).unwrap();
    bench_steps(c, "so3_control_input", controlled);
    bench_linearized(c, "so3_free_linearized", so3(body));
    bench_with_parameters(c, "so3_free_linearized_parameters", so3(body));
    let mut controlled = so3(body);
    controlled.set_input(torque).unwrap();
    bench_linearized(c, "so3_control_input_linearized", controlled);
    // `lgsvi bench`'s torqued body F1 at its best (h, n) for ≤ 1e-10 at T = 10 (h = 1,
    // n = 9), and the same body without the torque: what the torque costs where lgsvi is
    // compared with DOP853.
    let f1 = RigidBody::new(Inertia::from_principal_moments([3.3, 2.5, 3.4]).unwrap());
    let f1_start = Vector3::new(-2.0, 1.9, -1.0);
    let f1_settings = StepSettings::new(1.0, 9).unwrap();
    let f1_torque = BodyTorque(Vector3::new(0.1, -0.2, 0.05));
    bench_steps(
        c,
        "so3_f1_free",
        Integrator::new(f1, f1_settings, SO3::identity(), f1_start).unwrap(),
    );
    bench_steps(
        c,
        "so3_f1_torque",
        Integrator::new(
            Forced::new(f1, f1_torque),
            f1_settings,
            SO3::identity(),
            f1_start,
        )
        .unwrap(),
    );
    let top = HeavyTop::new(inertia(), 1.0, 0.3, Vector3::z(), Vector3::z()).unwrap();
    bench_steps(c, "so3_heavy_top", so3(top));
    bench_linearized(c, "so3_heavy_top_linearized", so3(top));
    // A control loop's steps: short, so that the Newton matrix changes little from one
    // step to the next and a step can start from an earlier one's factors.
    for (suffix, reuse) in [("", true), ("_fresh", false)] {
        let short = StepSettings::new(0.05, 8).unwrap().with_factor_reuse(reuse);
        let start = SO3::identity();
        bench_steps(
            c,
            &format!("so3_free_control_loop{suffix}"),
            Integrator::new(body, short, start, omega0()).unwrap(),
        );
        let mut controlled = Integrator::new(top, short, start, omega0()).unwrap();
        controlled.set_input(torque).unwrap();
        bench_steps(
            c,
            &format!("so3_heavy_top_control_loop{suffix}"),
            controlled,
        );
        let mut controlled = Integrator::new(top, short, start, omega0()).unwrap();
        controlled.set_input(torque).unwrap();
        bench_linearized(
            c,
            &format!("so3_heavy_top_linearized_control_loop{suffix}"),
            controlled,
        );
    }
    bench_steps(
        c,
        "so3_user_potential",
        so3(RigidBodyInPotential::new(inertia(), Dipole)),
    );

    let w = omega0();
    let xi = SVector::<f64, 6>::new(w.x, w.y, w.z, 0.1, -0.2, 0.05);
    let free = FreeBody::new(inertia(), 1.0).unwrap();
    bench_steps(
        c,
        "space_free_body",
        Integrator::new(free, settings(), SE3::identity(), xi).unwrap(),
    );
    bench_steps(
        c,
        "space_free_body_space_force",
        Integrator::new(
            Forced::new(free, SpaceForce(Vector3::new(0.0, 0.0, -0.1))),
            settings(),
            SE3::identity(),
            xi,
        )
        .unwrap(),
    );
    let orbit = OrbitingBody::new(inertia(), 1.0, 1.0).unwrap();
    let orbit_start = SE3::new(SO3::identity(), Vector3::new(3.0, 0.0, 0.0));
    let orbit_xi = SVector::<f64, 6>::new(w.x, w.y, w.z, 0.0, 0.55, 0.05);
    bench_steps(
        c,
        "space_orbiting_body",
        Integrator::new(orbit, settings(), orbit_start, orbit_xi).unwrap(),
    );
    bench_linearized(
        c,
        "space_orbiting_body_linearized",
        Integrator::new(orbit, settings(), orbit_start, orbit_xi).unwrap(),
    );
    bench_with_parameters(
        c,
        "space_orbiting_body_linearized_parameters",
        Integrator::new(orbit, settings(), orbit_start, orbit_xi).unwrap(),
    );
    for (suffix, reuse) in [("", true), ("_fresh", false)] {
        let short = StepSettings::new(0.1, 8).unwrap().with_factor_reuse(reuse);
        bench_steps(
            c,
            &format!("space_orbiting_body_control_loop{suffix}"),
            Integrator::new(orbit, short, orbit_start, orbit_xi).unwrap(),
        );
        bench_linearized(
            c,
            &format!("space_orbiting_body_linearized_control_loop{suffix}"),
            Integrator::new(orbit, short, orbit_start, orbit_xi).unwrap(),
        );
    }
    // The same free body on the product SO(3) × ℝ³ (same discrete map, other group).
    let product_start = BodyWheels {
        attitude: SO3::identity(),
        wheels: Vector3::zeros(),
    };
    bench_steps(
        c,
        "space_free_body_on_product",
        Integrator::new(
            ProductFreeBody(inertia().matrix()),
            settings(),
            product_start,
            xi,
        )
        .unwrap(),
    );
    // A spacecraft with three reaction wheels along its axes (SO(3) × ℝ³), wheels spinning.
    let craft = Gyrostat::new(
        inertia().matrix(),
        [Vector3::x(), Vector3::y(), Vector3::z()],
        [0.01; 3],
    )
    .unwrap();
    let wheel_start = BodyWheels {
        attitude: SO3::identity(),
        wheels: Vector3::zeros(),
    };
    bench_steps(
        c,
        "gyrostat_three_wheels",
        Integrator::new(craft, settings(), wheel_start, xi).unwrap(),
    );
    // SE(3)'s own (screw-motion) chart, for comparison with the default
    // rotation–translation chart.
    bench_steps(
        c,
        "space_free_body_screw",
        Integrator::with_chart(free, Screw(ChartKind::Exp), settings(), SE3::identity(), xi)
            .unwrap(),
    );
    bench_steps(
        c,
        "space_orbiting_body_screw",
        Integrator::with_chart(
            orbit,
            Screw(ChartKind::Exp),
            settings(),
            orbit_start,
            orbit_xi,
        )
        .unwrap(),
    );
    let field = BodyInField::new(inertia(), 1.0, GravityAndDipole).unwrap();
    bench_steps(
        c,
        "space_user_potential",
        Integrator::new(field, settings(), SE3::identity(), xi).unwrap(),
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
