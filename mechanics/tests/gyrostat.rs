//! The gyrostat (a body with reaction wheels, SO(3) × ℝᴷ): momentum exchange against the
//! closed form of a wheel spun up on a body at rest, exact conservation of the total
//! angular momentum under arbitrary motor torques, the energy balance, the linearisation
//! against central differences, and the refusals.

use lgsvi_mechanics::gyrostat::{BodyWheels, Gyrostat};
use lgsvi_mechanics::lie::{ChartKind, LieGroup, SO3};
use lgsvi_mechanics::linearization::Coordinates;
use lgsvi_mechanics::Stepper;
use lgsvi_mechanics::{Integrator, MechanicsError, StepSettings};
use nalgebra::{DMatrix, Matrix3, SVector, Vector3, Vector4};

fn craft3() -> Gyrostat<3> {
    let j = Matrix3::new(10.0, 0.3, -0.2, 0.3, 12.0, 0.4, -0.2, 0.4, 8.0);
    Gyrostat::new(
        j,
        [Vector3::x(), Vector3::y(), Vector3::z()],
        [0.05, 0.06, 0.04],
    )
    .unwrap()
}

/// One wheel along body z (a principal axis of `J`), body and wheel at rest, constant
/// motor torque `τ`: `p = τt`, and the total momentum stays zero, so `J_b Ω_z + p = 0`:
/// `Ω_z = −τt/J_b`, the body turns by `ψ = −τt²/(2J_b)` about z, `φ̇ = p/I − Ω_z`. The
/// motion is quadratic in time: every step with `n ≥ 3` holds it exactly, so the error
/// is rounding (~1e-15 relative after 100 steps).
#[test]
fn a_wheel_spun_up_turns_the_body_back() {
    let (jz, wheel, torque) = (8.0, 0.05, 0.02);
    let craft = Gyrostat::new(
        Matrix3::from_diagonal(&Vector3::new(10.0, 12.0, jz)),
        [Vector3::z()],
        [wheel],
    )
    .unwrap();
    let body = jz - wheel;
    for chart in [ChartKind::Exp, ChartKind::Cayley] {
        let settings = StepSettings::new(0.1, 4).unwrap().with_chart(chart);
        let start = BodyWheels {
            attitude: SO3::identity(),
            wheels: SVector::<f64, 1>::zeros(),
        };
        let mut integrator = Integrator::new(craft, settings, start, Vector4::zeros()).unwrap();
        integrator
            .set_input(Vector4::new(0.0, 0.0, 0.0, torque))
            .unwrap();
        integrator.run(100, 1).unwrap();
        let s = integrator.state();
        let t = s.time;
        let psi = -torque * t * t / (2.0 * body);
        let omega = -torque * t / body;
        let spin = torque * t / wheel - omega;
        let expected = SO3::exp(&Vector3::new(0.0, 0.0, psi));
        let attitude = expected
            .inverse()
            .compose(&s.configuration.attitude)
            .log()
            .norm();
        assert!(attitude < 1e-14, "{chart:?}: attitude off by {attitude:e}");
        assert!(
            (s.velocity[2] - omega).abs() < 1e-14 * omega.abs(),
            "{chart:?}: Ω_z"
        );
        assert!(
            (s.velocity[3] - spin).abs() < 1e-13 * spin.abs(),
            "{chart:?}: φ̇"
        );
        assert!(
            (s.momentum[3] - torque * t).abs() < 1e-14,
            "{chart:?}: wheel momentum"
        );
        assert!(
            s.momentum.fixed_rows::<3>(0).norm() < 1e-15,
            "{chart:?}: total momentum"
        );
        // The wheel angle: φ = τt²/(2I) − ψ.
        let angle = torque * t * t / (2.0 * wheel) - psi;
        assert!(
            (s.configuration.wheels[0] - angle).abs() < 1e-12 * angle,
            "{chart:?}: φ"
        );
    }
}

/// Arbitrary motor torques on three and four wheels (a pyramid), from a tumbling start:
/// the spatial angular momentum `Rh` is conserved to rounding (the motors act between
/// body and wheels), the wheel momenta change by `τh` per step, and the energy changes by
/// the motors' work.
#[test]
fn motor_torques_exchange_momentum_and_conserve_the_total() {
    fn check<const K: usize, const D: usize>(craft: Gyrostat<K>)
    where
        Gyrostat<K>:
            lgsvi_mechanics::System<D, Group = lgsvi_mechanics::gyrostat::BodyAndWheels<K>>,
        lgsvi_mechanics::gyrostat::BodyAndWheels<K>:
            lgsvi_mechanics::group::StepGroup<D, Element<f64> = BodyWheels<f64, K>>,
        ChartKind:
            lgsvi_mechanics::group::GroupChart<lgsvi_mechanics::gyrostat::BodyAndWheels<K>, D>,
        BodyWheels<f64, K>: LieGroup<
            Scalar = f64,
            Tangent = SVector<f64, D>,
            Jacobian = nalgebra::SMatrix<f64, D, D>,
        >,
    {
        let start = BodyWheels {
            attitude: SO3::exp(&Vector3::new(0.3, -0.2, 1.0)),
            wheels: SVector::<f64, K>::zeros(),
        };
        let velocity =
            SVector::<f64, D>::from_fn(|i, _| if i < 3 { [0.3, -0.2, 0.5][i] } else { 2.0 });
        let mut integrator =
            Integrator::new(craft, StepSettings::new(0.2, 8).unwrap(), start, velocity).unwrap();
        let first = *integrator.state();
        let spatial = |s: &lgsvi_mechanics::State<BodyWheels<f64, K>, D>| {
            s.configuration.attitude.matrix() * s.momentum.fixed_rows::<3>(0)
        };
        let h0 = spatial(&first);
        let e0 = first.energy(&craft);
        for k in 0..500 {
            let before = *integrator.state();
            let torques = SVector::<f64, D>::from_fn(|i, _| {
                if i < 3 {
                    0.0
                } else {
                    0.02 * ((k as f64) * 0.37 + i as f64).sin()
                }
            });
            integrator.set_input(torques).unwrap();
            integrator.step().unwrap();
            let after = integrator.state();
            for i in 3..D {
                let change = after.momentum[i] - before.momentum[i];
                assert!(
                    (change - torques[i] * 0.2).abs() < 1e-15 * 50.0,
                    "wheel {i} at step {k}"
                );
            }
        }
        let last = integrator.state();
        let drift = (spatial(last) - h0).norm() / h0.norm();
        // 500 steps of rounding on momenta of order one (measured 2e-15 and 3e-15).
        assert!(
            drift < 1e-13,
            "K = {K}: total momentum drifted by {drift:e}"
        );
        let balance = (last.energy(&craft) - e0 - integrator.work_done()).abs() / e0;
        // Measured 5e-15 and 8e-16: the method at h = 0.2, n = 8 is at rounding here.
        assert!(balance < 1e-12, "K = {K}: energy balance {balance:e}");
    }
    check::<3, 6>(craft3());
    let j = Matrix3::new(10.0, 0.3, -0.2, 0.3, 12.0, 0.4, -0.2, 0.4, 8.0);
    let s = 1.0 / 3f64.sqrt();
    let pyramid = [
        Vector3::new(s, s, s),
        Vector3::new(-s, s, s),
        Vector3::new(-s, -s, s),
        Vector3::new(s, -s, s),
    ];
    check::<4, 7>(Gyrostat::new(j, pyramid, [0.05; 4]).unwrap());
}

/// The step's linearisation (attitude, wheel angles, body and wheel rates; inputs body
/// torque and motor torques) against central differences through `reset` and `step`.
#[test]
fn the_gyrostat_linearisation_matches_differences() {
    const EPS: f64 = 1e-5;
    let craft = craft3();
    let start = BodyWheels {
        attitude: SO3::exp(&Vector3::new(0.3, -0.2, 1.0)),
        wheels: Vector3::new(0.1, 0.2, -0.3),
    };
    let velocity = SVector::<f64, 6>::new(0.3, -0.2, 0.5, 2.0, -1.0, 0.5);
    let input = SVector::<f64, 6>::new(0.01, 0.0, -0.02, 0.03, 0.01, -0.02);
    for chart in [ChartKind::Exp, ChartKind::Cayley] {
        for n in [4, 8, 12] {
            let settings = StepSettings::new(0.25, n).unwrap().with_chart(chart);
            let mut integrator = Integrator::new(craft, settings, start, velocity).unwrap();
            integrator.set_input(input).unwrap();
            let step = integrator.linearize().unwrap();
            let reference = step.end;
            let mut a = DMatrix::<f64>::zeros(12, 12);
            let mut b = DMatrix::<f64>::zeros(12, 6);
            for col in 0..18 {
                let mut sides = Vec::new();
                for sign in [1.0, -1.0] {
                    let mut e = [SVector::<f64, 6>::zeros(); 3];
                    e[col / 6][col % 6] = sign * EPS;
                    let perturbed = BodyWheels {
                        attitude: start
                            .attitude
                            .compose(&SO3::exp(&e[0].fixed_rows::<3>(0).into_owned())),
                        wheels: start.wheels + e[0].fixed_rows::<3>(3),
                    };
                    integrator.reset(0.0, perturbed, velocity + e[1]).unwrap();
                    integrator.set_input(input + e[2]).unwrap();
                    integrator.step().unwrap();
                    let s = integrator.state();
                    let mut out = SVector::<f64, 12>::zeros();
                    out.fixed_rows_mut::<3>(0).copy_from(
                        &reference
                            .configuration
                            .attitude
                            .inverse()
                            .compose(&s.configuration.attitude)
                            .log(),
                    );
                    out.fixed_rows_mut::<3>(3)
                        .copy_from(&(s.configuration.wheels - reference.configuration.wheels));
                    out.fixed_rows_mut::<6>(6)
                        .copy_from(&(s.velocity - reference.velocity));
                    sides.push(out);
                }
                let column = (sides[0] - sides[1]) / (2.0 * EPS);
                for r in 0..12 {
                    if col < 12 {
                        a[(r, col)] = column[r];
                    } else {
                        b[(r, col - 12)] = column[r];
                    }
                }
            }
            let da = (step.a(Coordinates::Velocity) - &a).amax() / a.amax().max(1.0);
            let db = (step.b(Coordinates::Velocity) - &b).amax() / b.amax().max(1.0);
            // Central differences at ε = 1e-5 are good to ~1e-10 here; the goal is 1e-7.
            assert!(
                da < 1e-7 && db < 1e-7,
                "{chart:?} n = {n}: A {da:e}, B {db:e}"
            );
            // A conservative, volume-preserving step (constant mass matrix).
            let det = step.a(Coordinates::Velocity).determinant();
            assert!(
                (det - 1.0).abs() < 1e-12,
                "{chart:?} n = {n}: det A = {det}"
            );
        }
    }
}

#[test]
fn a_gyrostat_that_cannot_exist_is_refused() {
    let j = Matrix3::from_diagonal(&Vector3::new(10.0, 12.0, 8.0));
    let axes = [Vector3::x(), Vector3::y(), Vector3::z()];
    assert!(matches!(
        Gyrostat::new(j, [Vector3::x(), Vector3::zeros(), Vector3::z()], [0.05; 3]),
        Err(MechanicsError::InvalidSetting {
            name: "wheel axis",
            ..
        })
    ));
    assert!(matches!(
        Gyrostat::new(j, axes, [0.05, -0.01, 0.05]),
        Err(MechanicsError::InvalidSetting {
            name: "wheel inertia",
            ..
        })
    ));
    // The wheel's axial inertia exceeds the whole spacecraft's about that axis.
    assert!(matches!(
        Gyrostat::new(j, axes, [0.05, 0.05, 9.0]),
        Err(MechanicsError::InvalidSetting {
            name: "gyrostat inertia",
            ..
        })
    ));
    let mut skew = j;
    skew[(0, 1)] = 1.0;
    assert!(matches!(
        Gyrostat::new(skew, axes, [0.05; 3]),
        Err(MechanicsError::InvalidSetting {
            name: "gyrostat inertia",
            ..
        })
    ));
    assert!(matches!(
        Gyrostat::new(j, axes, [f64::NAN, 0.05, 0.05]),
        Err(MechanicsError::NonFinite { .. })
    ));
}

/// The gyrostat's group SO(3) × ℝᴷ passes the law suite every group runs
/// (`lgsvi_lie::laws`), for each wheel count: 64ε of the examples' scale for the exact laws.
#[test]
fn the_product_group_passes_the_law_suite() {
    use lgsvi_lie::laws::group_laws;
    use lgsvi_lie::ExponentialMap;
    use lgsvi_mechanics::gyrostat::BodyWheels;
    fn check<const K: usize, const D: usize>()
    where
        BodyWheels<f64, K>: ExponentialMap<
            Scalar = f64,
            Tangent = nalgebra::SVector<f64, D>,
            Jacobian = nalgebra::SMatrix<f64, D, D>,
        >,
    {
        let tangents: Vec<nalgebra::SVector<f64, D>> = (0..4)
            .map(|k| nalgebra::SVector::from_fn(|i, _| ((i + 3 * k) as f64 * 0.77).sin()))
            .collect();
        let elements: Vec<BodyWheels<f64, K>> = tangents
            .iter()
            .map(|xi| BodyWheels::exp(&(xi * 0.9)))
            .collect();
        group_laws(&elements, &tangents, 64.0 * f64::EPSILON).unwrap();
    }
    check::<1, 4>();
    check::<2, 5>();
    check::<3, 6>();
    check::<4, 7>();
}
