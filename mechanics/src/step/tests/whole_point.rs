//! The whole Gauss point against dual numbers: the generic chain rule, the force terms,
//! SE(3)'s rotation–translation chart, the matching map's Jacobian and the mixed
//! derivatives the linearisation reads.

use super::*;

/// A Lagrangian on SE(3) that couples attitude, position and both velocities and depends
/// on time (exercises every block of the generic chain rule).
pub(super) struct CoupledSe3;
impl crate::System<6> for CoupledSe3 {
    type Group = crate::group::RigidMotions;
    fn lagrangian<T: RealField + Copy>(
        &self,
        t: f64,
        g: &lgsvi_lie::SE3<T>,
        xi: &SVector<T, 6>,
    ) -> T {
        let c = |x: f64| -> T { nalgebra::convert(x) };
        let r = g.rotation().matrix();
        let x = g.translation();
        let w = Vector3::new(xi[0], xi[1], xi[2]);
        let v = Vector3::new(xi[3], xi[4], xi[5]);
        c(0.5) * (w.x * w.x * c(1.2) + w.y * w.y * c(2.1) + w.z * w.z * c(2.7))
            + c(0.5) * c(1.7) * v.dot(&v)
            + (r.transpose() * Vector3::new(c(0.2), c(-0.1), c(1.0))).dot(&w) * c(0.3)
            + x.dot(&v) * c(0.2 + 0.1 * t)
            - r[(0, 1)] * x.z * c(1.3)
            - c(1.0) / (x.dot(x) + c(1.0)).sqrt()
    }
}

/// A body whose centre of mass sits at `c`, off the body frame's origin: its kinetic energy
/// `½ΩᵀJΩ + ½m|v + Ω × c|²` couples turning and moving (`X_ωu = m ĉ`, `X_uω = −m ĉ`),
/// the two blocks of the rotation–translation chart's closed form
/// (`super::rotation_translation`) that the built-in bodies (centre of mass at the
/// origin) leave at zero. Its `local_derivatives`: `μ = (JΩ + m c × v_c, m v_c)` with
/// `v_c = v + Ω × c`, the velocity of the centre of mass, and
/// `X = [[J − m ĉ², m ĉ], [−m ĉ, m I]]`.
struct OffsetBody;
const OFFSET_MASS: f64 = 1.7;
const OFFSET: [f64; 3] = [0.2, -0.1, 0.3];
const OFFSET_INERTIA: [f64; 3] = [1.2, 2.1, 2.7];
impl crate::System<6> for OffsetBody {
    type Group = crate::group::RigidMotions;
    fn lagrangian<T: RealField + Copy>(
        &self,
        _t: f64,
        _g: &lgsvi_lie::SE3<T>,
        xi: &SVector<T, 6>,
    ) -> T {
        let c = |x: f64| -> T { nalgebra::convert(x) };
        let w = Vector3::new(xi[0], xi[1], xi[2]);
        let v = Vector3::new(xi[3], xi[4], xi[5]);
        let v_c = v + w.cross(&Vector3::new(c(OFFSET[0]), c(OFFSET[1]), c(OFFSET[2])));
        let [a, b, d] = OFFSET_INERTIA;
        c(0.5) * (w.x * w.x * c(a) + w.y * w.y * c(b) + w.z * w.z * c(d))
            + c(0.5 * OFFSET_MASS) * v_c.dot(&v_c)
    }
    fn is_left_invariant(&self) -> bool {
        true
    }
    fn local_derivatives(
        &self,
        _time: f64,
        _g: &lgsvi_lie::SE3,
        xi: &SVector<f64, 6>,
        with_hessian: bool,
    ) -> Option<crate::system::LocalDerivatives<6>> {
        let m = OFFSET_MASS;
        let j = Matrix3::from_diagonal(&Vector3::from(OFFSET_INERTIA));
        let c = Vector3::from(OFFSET);
        let c_hat = lgsvi_lie::so3::hat(&c);
        let (w, v) = (
            xi.fixed_rows::<3>(0).into_owned(),
            xi.fixed_rows::<3>(3).into_owned(),
        );
        let v_c = v + w.cross(&c);
        let mut velocity_hessian = nalgebra::SMatrix::<f64, 6, 6>::zeros();
        if with_hessian {
            let blocks = [
                (0, 0, j - c_hat * c_hat * m),
                (0, 3, c_hat * m),
                (3, 0, -c_hat * m),
                (3, 3, Matrix3::identity() * m),
            ];
            for (r, k, block) in blocks {
                velocity_hessian
                    .fixed_view_mut::<3, 3>(r, k)
                    .copy_from(&block);
            }
        }
        Some(crate::system::LocalDerivatives {
            configuration_gradient: SVector::zeros(),
            momentum: lgsvi_lie::se3::join(&(j * w + c.cross(&v_c) * m), &(v_c * m)),
            configuration_hessian: nalgebra::SMatrix::zeros(),
            velocity_hessian,
        })
    }
    fn point_derivatives<C: crate::group::GroupChart<crate::group::RigidMotions, 6>>(
        &self,
        chart: &C,
        point: &crate::point::GaussPoint<'_, crate::group::RigidMotions, 6>,
        out: &mut Stacked<18>,
    ) -> bool {
        super::rotation_translation::point_derivatives(self, chart, point, out)
    }
}

/// The generic chain rule against a second-order dual number through the whole of `ℓ̃`
/// (18 variables), on SE(3) for both charts and both variable sets, and on SO(3) (a
/// system without the closed-form path), at points from `x = 0` to large rotations. Both
/// are exact up to rounding: 1e-12 relative to the largest entry.
#[test]
fn generic_chain_rule_matches_dual_numbers_through_the_whole_point() {
    use crate::group::{RigidMotions, Rotations};
    use crate::system::ElementOf;
    use lgsvi_lie::{CayleyChart, ExpChart, SE3};
    fn compare<S, C, const D: usize>(
        system: &S,
        chart: C,
        base: &ElementOf<S, D>,
        x: &SVector<f64, D>,
        v: &SVector<f64, D>,
        name: &str,
    ) where
        S: crate::System<D>,
        C: crate::group::GroupChart<S::Group, D>,
    {
        for with_configuration in [false, true] {
            let ell = EllTilde {
                system,
                chart: &chart,
                base,
                time: 0.7,
            };
            let mut fast = <S::Group as crate::group::StepGroup<D>>::Jet::zeros();
            let point = gauss_point(base, x, v, with_configuration, true, None);
            super::points::chain_rule(&ell, &point, &mut fast);
            let mut gradient_only = fast.clone();
            let point = gauss_point(base, x, v, with_configuration, false, None);
            super::points::chain_rule(&ell, &point, &mut gradient_only);
            // The system's own path where it has one (the built-in SE(3) systems: by
            // blocks on the rotation–translation chart), else the generic chain rule again;
            // started from NaN, so that a block it does not write shows.
            let mut own = <S::Group as crate::group::StepGroup<D>>::Jet::zeros();
            own.gradient_mut().fill(f64::NAN);
            for r in 0..own.size() {
                for c in 0..own.size() {
                    own.set_hessian(r, c, f64::NAN);
                }
            }
            super::points::point_derivatives(
                &ell,
                x,
                v,
                with_configuration,
                true,
                None,
                &mut own,
                &mut None,
            );
            let mut own_gradient = own.clone();
            super::points::point_derivatives(
                &ell,
                x,
                v,
                with_configuration,
                false,
                None,
                &mut own_gradient,
                &mut None,
            );
            let mut slow = <S::Group as crate::group::StepGroup<D>>::Jet::zeros();
            slow.set_by_dual_numbers(&ell, x.as_slice(), v.as_slice(), with_configuration);
            let n = fast.size();
            let mut scale = 1.0f64;
            for r in 0..n {
                scale = scale.max(slow.gradient()[r].abs());
                for c in 0..n {
                    scale = scale.max(slow.hessian(r, c).abs());
                }
            }
            // The ζζ block is not read by the solver (and differs: the chain rule's
            // exponential is second order only where that block is concerned).
            let mut worst = 0.0f64;
            for r in 0..n {
                worst = worst.max((fast.gradient()[r] - slow.gradient()[r]).abs());
                worst = worst.max((gradient_only.gradient()[r] - slow.gradient()[r]).abs());
                for g in [own.gradient()[r], own_gradient.gradient()[r]] {
                    let d = (g - slow.gradient()[r]).abs();
                    worst = worst.max(if d.is_nan() { f64::INFINITY } else { d });
                }
                for c in 0..n {
                    if r >= 2 * D && c >= 2 * D {
                        continue;
                    }
                    if !with_configuration && (r >= 2 * D || c >= 2 * D) {
                        continue;
                    }
                    worst = worst.max((fast.hessian(r, c) - slow.hessian(r, c)).abs());
                    worst = worst.max((own.hessian(r, c) - slow.hessian(r, c)).abs());
                }
            }
            assert!(
                worst <= 1e-12 * scale,
                "{name} ζ = {with_configuration}: {worst:e} of {scale:e}"
            );
            // The system's own path against the generic rule over the whole Hessian, the ζζ
            // block (which the linearisation reads) and the zeros without ζ included.
            let mut apart = 0.0f64;
            for r in 0..n {
                for c in 0..n {
                    // A NaN left in place counts as infinitely far (f64::max would skip it).
                    let d = (own.hessian(r, c) - fast.hessian(r, c)).abs();
                    apart = apart.max(if d.is_nan() { f64::INFINITY } else { d });
                }
            }
            assert!(
                apart <= 1e-12 * scale,
                "{name} ζ = {with_configuration}: own path {apart:e} from the generic one"
            );
        }
    }
    let b6 = SE3::new(
        SO3::exp(&Vector3::new(0.4, -0.7, 0.2)),
        Vector3::new(1.0, -2.0, 0.5),
    );
    let orbit = crate::OrbitingBody::new(
        Inertia::from_principal_moments([0.3, 0.2, 0.4]).unwrap(),
        1.3,
        2.0,
    )
    .unwrap();
    let points = [
        (
            SVector::<f64, 6>::zeros(),
            SVector::<f64, 6>::new(1.1, 0.4, -0.6, 0.3, 0.2, -0.1),
        ),
        (
            SVector::<f64, 6>::new(0.3, -0.1, 0.25, 0.2, 0.1, -0.3),
            SVector::<f64, 6>::new(1.1, 0.4, -0.6, -0.5, 0.8, 0.1),
        ),
        (
            SVector::<f64, 6>::new(1.5, -2.2, 1.1, -0.4, 0.9, 0.3),
            SVector::<f64, 6>::new(2.0, 0.7, -1.0, 0.2, 0.0, 0.6),
        ),
    ];
    /// A potential that couples attitude, position and time: a dipole along body x in a
    /// field that varies in space, plus a spring on the centre of mass.
    struct Field;
    impl crate::FieldPotential for Field {
        fn potential<T: RealField + Copy>(&self, t: f64, r: &Matrix3<T>, x: &Vector3<T>) -> T {
            let c = |v: f64| nalgebra::convert::<f64, T>(v);
            let field = Vector3::new(x.y * c(0.3), c(1.0 + 0.1 * t) + x.x * x.z, x.z.sin());
            let dipole = Vector3::new(r[(0, 0)], r[(1, 0)], r[(2, 0)]);
            -dipole.dot(&field) + x.norm_squared() * c(0.4)
        }
    }
    let field = crate::BodyInField::new(
        Inertia::from_principal_moments([0.3, 0.2, 0.4]).unwrap(),
        1.3,
        Field,
    )
    .unwrap();
    let free = crate::FreeBody::new(
        Inertia::from_principal_moments([0.3, 0.2, 0.4]).unwrap(),
        1.3,
    )
    .unwrap();
    use crate::group::Screw;
    for (x, v) in &points {
        compare::<_, _, 6>(&CoupledSe3, ExpChart, &b6, x, v, "coupled exp");
        compare::<_, _, 6>(&CoupledSe3, CayleyChart, &b6, x, v, "coupled cayley");
        compare::<_, _, 6>(&orbit, ExpChart, &b6, x, v, "orbit exp");
        compare::<_, _, 6>(&orbit, CayleyChart, &b6, x, v, "orbit cayley");
        compare::<_, _, 6>(&field, ExpChart, &b6, x, v, "field exp");
        compare::<_, _, 6>(
            &field,
            ChartKind::CayleyUnscaled,
            &b6,
            x,
            v,
            "field paper cayley",
        );
        compare::<_, _, 6>(&free, ChartKind::Cayley, &b6, x, v, "free cayley");
        compare::<_, _, 6>(&OffsetBody, ExpChart, &b6, x, v, "offset body exp");
        compare::<_, _, 6>(&OffsetBody, CayleyChart, &b6, x, v, "offset body cayley");
        compare::<_, _, 6>(&orbit, Screw(ExpChart), &b6, x, v, "orbit screw exp");
        compare::<_, _, 6>(&field, Screw(CayleyChart), &b6, x, v, "field screw cayley");
        compare::<_, _, 6>(&CoupledSe3, Screw(ExpChart), &b6, x, v, "coupled screw exp");
    }
    // The points of the step's parameter columns (`ParameterDerivative`, ℓ replaced by
    // ∂ℓ/∂p): the SE(3) bodies' closed-form local derivatives through the chart's blocks
    // (and the generic rule in the screw chart), against dual numbers through ∂ℓ/∂p.
    use crate::step::linearize::ParameterDerivative;
    for (x, v) in &points {
        for index in 0..7 {
            let name = format!("parameter {index}");
            let orbit_p = ParameterDerivative {
                system: &orbit,
                index,
            };
            compare::<_, _, 6>(&orbit_p, ExpChart, &b6, x, v, &format!("orbit {name}"));
            compare::<_, _, 6>(&orbit_p, CayleyChart, &b6, x, v, &format!("orbit {name}"));
            let free_p = ParameterDerivative {
                system: &free,
                index,
            };
            compare::<_, _, 6>(&free_p, ExpChart, &b6, x, v, &format!("free {name}"));
            let field_p = ParameterDerivative {
                system: &field,
                index,
            };
            compare::<_, _, 6>(
                &field_p,
                Screw(ExpChart),
                &b6,
                x,
                v,
                &format!("field {name}"),
            );
            compare::<_, _, 6>(&field_p, CayleyChart, &b6, x, v, &format!("field {name}"));
        }
    }
    // SO(3) through the generic path: a wrapper that hides the closed form.
    struct Generic<L>(L);
    impl<L: Lagrangian> crate::System<3> for Generic<L> {
        type Group = Rotations;
        fn lagrangian<T: RealField + Copy>(&self, _t: f64, g: &SO3<T>, w: &Vector3<T>) -> T {
            Lagrangian::lagrangian(&self.0, g.matrix(), w)
        }
    }
    let b = SO3::from_matrix_unchecked(base());
    for chart in ChartKind::ALL {
        for (x, v) in [
            (Vector3::zeros(), Vector3::new(1.1, 0.4, -0.6)),
            (Vector3::new(0.3, -0.1, 0.25), Vector3::new(1.1, 0.4, -0.6)),
            (Vector3::new(1.5, -2.2, 1.1), Vector3::new(2.0, 0.7, -1.0)),
        ] {
            compare::<_, _, 3>(&Generic(top()), chart, &b, &x, &v, "heavy top");
            compare::<_, _, 3>(&Generic(Coupled), chart, &b, &x, &v, "coupled SO(3)");
            // The parameter columns' points of an SO(3) body (the heavy top's six inertia
            // entries and its mass: the generic chain rule through ∂ℓ/∂p).
            let top = top();
            for index in 0..7 {
                let derivative = ParameterDerivative {
                    system: &top,
                    index,
                };
                compare::<_, _, 3>(
                    &derivative,
                    chart,
                    &b,
                    &x,
                    &v,
                    &format!("top parameter {index}"),
                );
            }
        }
    }
    let _ = RigidMotions;
}

/// Every closed-form force path (the built-in forces' jets through the SO(3) Rodrigues
/// path and through the generic chain rule, the control input, a user force whose jet
/// comes by dual numbers on the force alone) against dual numbers through the whole
/// point: `ℓ̃` by a second-order dual number and the force terms `(A(x)ᵀF, F)` by
/// first-order dual numbers through chart and force together
/// ([`crate::group::PointJet::add_force`]). Every chart, points from `x = 0` to large
/// rotations. Both are exact up to rounding: 1e-12 relative to the largest entry. The
/// `ζζ` block and the `ζ` columns are not read by the solver and are skipped.
#[test]
fn force_terms_match_dual_numbers_through_the_whole_point() {
    use super::points::{point_derivatives, ForceTerms};
    use crate::forces::AngularDamping;
    use crate::forces::BodyTorque;
    use crate::forces::ForceOfTime;
    use crate::forces::Forcing;
    use crate::forces::SpaceForce;
    use crate::group::{RigidMotions, Rotations};
    use crate::system::{ElementOf, Forced};
    use crate::RigidBody;
    use lgsvi_lie::{CayleyChart, ExpChart, SE3};

    fn compare<S, C, const D: usize>(
        system: &S,
        chart: C,
        base: &ElementOf<S, D>,
        x: &SVector<f64, D>,
        v: &SVector<f64, D>,
        input: &SVector<f64, D>,
        name: &str,
    ) where
        S: crate::System<D>,
        C: crate::group::GroupChart<S::Group, D>,
    {
        let ell = EllTilde {
            system,
            chart: &chart,
            base,
            time: 0.7,
        };
        let mut fast = <S::Group as crate::group::StepGroup<D>>::Jet::zeros();
        point_derivatives(&ell, x, v, true, true, Some(input), &mut fast, &mut None);
        let mut gradient_only = fast.clone();
        point_derivatives(
            &ell,
            x,
            v,
            true,
            false,
            Some(input),
            &mut gradient_only,
            &mut None,
        );
        let mut slow = <S::Group as crate::group::StepGroup<D>>::Jet::zeros();
        slow.set_by_dual_numbers(&ell, x.as_slice(), v.as_slice(), true);
        slow.add_force(&ForceTerms { ell: &ell, input }, x.as_slice(), v.as_slice());
        let n = fast.size();
        let mut scale = 1.0f64;
        for r in 0..n {
            scale = scale.max(slow.gradient()[r].abs());
            for c in 0..2 * D {
                scale = scale.max(slow.hessian(r, c).abs());
            }
        }
        let mut worst = 0.0f64;
        for r in 0..n {
            worst = worst.max((fast.gradient()[r] - slow.gradient()[r]).abs());
            worst = worst.max((gradient_only.gradient()[r] - slow.gradient()[r]).abs());
            for c in 0..2 * D {
                worst = worst.max((fast.hessian(r, c) - slow.hessian(r, c)).abs());
            }
        }
        assert!(worst <= 1e-12 * scale, "{name}: {worst:e} of {scale:e}");
        // A gradient-only assembly reads the force's value alone: the jet's, bit for bit
        // (the predictor's and the points' results must not depend on which was asked).
        use crate::point::PointForce;
        use lgsvi_lie::LieGroup;
        let at = base.compose(&chart.to_group(x));
        let xi = chart.left_differential(x) * v;
        let force = super::points::StepForce::new(system, 0.7, input);
        assert_eq!(force.value(&at, &xi), force.jet(&at, &xi).value, "{name}");
    }

    /// A force of the attitude and velocity with no closed form: its jet comes from
    /// first-order dual numbers on the force alone (the default [`Forcing::jet`]).
    #[derive(Clone, Copy)]
    struct Magnetic;
    impl Forcing<Rotations, 3> for Magnetic {
        fn force<T: RealField + Copy>(&self, t: f64, g: &SO3<T>, w: &Vector3<T>) -> Vector3<T> {
            // A body dipole m = e₁ in a field b = (0.2, −0.1, 1 + sin t)ᵀ, plus drag ∝ |Ω|Ω.
            let field = Vector3::new(
                nalgebra::convert(0.2),
                nalgebra::convert(-0.1),
                nalgebra::convert(1.0 + t.sin()),
            );
            let body_field = g.matrix().transpose() * field;
            Vector3::x()
                .map(nalgebra::convert::<f64, T>)
                .cross(&body_field)
                - w * (w.norm() * nalgebra::convert::<f64, T>(0.05))
        }
    }
    impl Forcing<RigidMotions, 6> for Magnetic {
        fn force<T: RealField + Copy>(
            &self,
            t: f64,
            g: &SE3<T>,
            xi: &SVector<T, 6>,
        ) -> SVector<T, 6> {
            let w = Vector3::new(xi[0], xi[1], xi[2]);
            let torque = Forcing::<Rotations, 3>::force(self, t, g.rotation(), &w);
            // A spring to the origin in the world frame, as a body force Rᵀ(−k x).
            let pull = g.rotation().matrix().transpose()
                * g.translation()
                * nalgebra::convert::<f64, T>(-0.3);
            SVector::<T, 6>::new(torque.x, torque.y, torque.z, pull.x, pull.y, pull.z)
        }
    }

    let body = RigidBody::new(Inertia::from_paper_jd([1.3, 2.1, 1.2]).unwrap());
    let torque = BodyTorque(Vector3::new(0.1, -0.2, 0.05));
    let profile = ForceOfTime(|t: f64| Vector3::new(0.3 * t.sin(), -0.1, 0.2 * t.cos()));
    let input3 = Vector3::new(0.02, 0.5, -0.3);
    let b = SO3::from_matrix_unchecked(base());
    // SO(3) through the generic path: a wrapper that hides the closed form.
    struct Generic<L>(L);
    impl<L: Lagrangian> crate::System<3> for Generic<L> {
        type Group = Rotations;
        fn lagrangian<T: RealField + Copy>(&self, _t: f64, g: &SO3<T>, w: &Vector3<T>) -> T {
            Lagrangian::lagrangian(&self.0, g.matrix(), w)
        }
    }
    for chart in ChartKind::ALL {
        for (x, v) in [
            (Vector3::zeros(), Vector3::new(1.1, 0.4, -0.6)),
            (Vector3::new(0.3, -0.1, 0.25), Vector3::new(1.1, 0.4, -0.6)),
            (Vector3::new(1.5, -2.2, 1.1), Vector3::new(2.0, 0.7, -1.0)),
        ] {
            let zero = Vector3::zeros();
            compare(
                &Forced::new(body, torque),
                chart,
                &b,
                &x,
                &v,
                &zero,
                "torque",
            );
            compare(
                &Forced::new(body, AngularDamping(0.7)),
                chart,
                &b,
                &x,
                &v,
                &zero,
                "damping",
            );
            compare(
                &Forced::new(body, profile),
                chart,
                &b,
                &x,
                &v,
                &zero,
                "profile",
            );
            compare(
                &Forced::new(body, Magnetic),
                chart,
                &b,
                &x,
                &v,
                &zero,
                "user force",
            );
            compare(
                &Forced::new(top(), (torque, AngularDamping(0.2))),
                chart,
                &b,
                &x,
                &v,
                &zero,
                "top",
            );
            compare(
                &Forced::new(top(), Magnetic),
                chart,
                &b,
                &x,
                &v,
                &input3,
                "top, user force, input",
            );
            compare(&body, chart, &b, &x, &v, &input3, "input alone");
            compare(
                &Forced::new(Generic(top()), (Magnetic, torque)),
                chart,
                &b,
                &x,
                &v,
                &input3,
                "generic",
            );
        }
    }
    let b6 = SE3::new(
        SO3::exp(&Vector3::new(0.4, -0.7, 0.2)),
        Vector3::new(1.0, -2.0, 0.5),
    );
    let orbit = crate::OrbitingBody::new(
        Inertia::from_principal_moments([0.3, 0.2, 0.4]).unwrap(),
        1.3,
        2.0,
    )
    .unwrap();
    let free = crate::FreeBody::new(
        Inertia::from_principal_moments([0.3, 0.2, 0.4]).unwrap(),
        1.7,
    )
    .unwrap();
    let input6 = SVector::<f64, 6>::new(0.02, 0.5, -0.3, 0.1, 0.0, -0.2);
    let space = SpaceForce(Vector3::new(0.3, -1.0, 0.4));
    for (x, v) in [
        (
            SVector::<f64, 6>::zeros(),
            SVector::<f64, 6>::new(1.1, 0.4, -0.6, 0.3, 0.2, -0.1),
        ),
        (
            SVector::<f64, 6>::new(1.5, -2.2, 1.1, -0.4, 0.9, 0.3),
            SVector::<f64, 6>::new(2.0, 0.7, -1.0, 0.2, 0.0, 0.6),
        ),
    ] {
        for (chart, name) in [(ChartKind::Exp, "exp"), (ChartKind::Cayley, "cayley")] {
            let zero = SVector::<f64, 6>::zeros();
            compare(&Forced::new(free, space), chart, &b6, &x, &v, &zero, name);
            compare(
                &Forced::new(free, (torque, AngularDamping(0.4))),
                chart,
                &b6,
                &x,
                &v,
                &input6,
                name,
            );
            compare(
                &Forced::new(orbit, Magnetic),
                chart,
                &b6,
                &x,
                &v,
                &input6,
                name,
            );
            compare(
                &Forced::new(orbit, (space, torque)),
                chart,
                &b6,
                &x,
                &v,
                &zero,
                name,
            );
        }
        compare(
            &Forced::new(orbit, space),
            ExpChart,
            &b6,
            &x,
            &v,
            &input6,
            "exp type",
        );
        compare(
            &Forced::new(orbit, space),
            CayleyChart,
            &b6,
            &x,
            &v,
            &input6,
            "cayley type",
        );
    }
}

/// The matching map's Jacobian `∂/∂y [A(y)ᵀ Ad_{Φ(y)}ᵀ w]` (chart derivatives and the
/// coadjoint generator) against dual numbers through the chart and the adjoint, on SO(3)
/// for every chart and on SE(3) for the rotation–translation and the screw charts, from
/// `y = 0` to rotations past 2 rad. Both exact to rounding: 1e-13 of the largest entry.
#[test]
fn matching_map_jacobian_matches_dual_numbers() {
    use crate::group::{GroupChart, Screw};
    use crate::system::System;
    fn compare<S: System<D>, C: GroupChart<S::Group, D>, const D: usize>(
        system: &S,
        chart: C,
        name: &str,
    ) {
        let settings = StepSettings::new(0.4, 5).unwrap();
        let d = Discretisation::new(&settings).unwrap();
        let stepper = StepSolver {
            system,
            chart: &chart,
            settings: &settings,
            d: &d,
            time: 0.0,
            forcing: None,
            point_inputs: None,
        };
        let w = SVector::<f64, D>::from_fn(|i, _| 0.7 - 0.45 * i as f64);
        for scale in [0.0, 1e-9, 0.3, 1.0, 2.1] {
            let y = SVector::<f64, D>::from_fn(|i, _| scale * (0.9 * i as f64 + 0.4).sin());
            let fast = stepper.matching_map_jacobian(&y, &w);
            let slow = stepper.matching_map_jacobian_by_dual_numbers(&y, &w);
            let size = slow.amax().max(1.0);
            assert!(
                (fast - slow).amax() <= 1e-13 * size,
                "{name} at {y:?}: {:e} of {size:e}",
                (fast - slow).amax()
            );
        }
    }
    let body = crate::RigidBody::new(Inertia::from_principal_moments([0.5, 0.9, 0.7]).unwrap());
    let free = crate::FreeBody::new(
        Inertia::from_principal_moments([0.5, 0.9, 0.7]).unwrap(),
        1.3,
    )
    .unwrap();
    for chart in ChartKind::ALL {
        compare::<_, _, 3>(&body, chart, &format!("SO(3) {chart}"));
        compare::<_, _, 6>(&free, chart, &format!("SE(3) rotation–translation {chart}"));
        compare::<_, _, 6>(&free, Screw(chart), &format!("SE(3) screw {chart}"));
    }
}

/// The closed-form mixed derivatives of a Gauss point in the start's perturbation `θ`
/// (what the linearisation of a step reads) against three hyper-dual numbers through the
/// whole point, for attitude-dependent, coupled and forced systems on both groups, every
/// chart, at points from `x = 0` to large rotations. Both exact to rounding: 1e-12
/// relative to the largest entry (sums of tens of products of order-one terms).
#[test]
fn point_mixed_derivatives_match_hyper_dual_numbers() {
    use crate::group::{GroupChart, Screw};
    use crate::system::System;
    use lgsvi_lie::SE3;
    fn compare<S: System<D>, C: GroupChart<S::Group, D>, const D: usize>(
        system: &S,
        chart: C,
        base: &crate::system::ElementOf<S, D>,
        name: &str,
    ) {
        let settings = StepSettings::new(0.4, 5).unwrap();
        let d = Discretisation::new(&settings).unwrap();
        let input = SVector::<f64, D>::from_fn(|i, _| 0.2 - 0.1 * i as f64);
        // Unforced, and with a control input: the assembly's ζ gradient then carries the
        // force, which the mixed derivatives must take off again.
        for (forcing, scale) in [None, Some(input)]
            .into_iter()
            .flat_map(|f| [0.0, 0.3, 1.0, 2.1].map(|s| (f, s)))
        {
            let stepper = StepSolver {
                system,
                chart: &chart,
                settings: &settings,
                d: &d,
                time: 0.3,
                forcing,
                point_inputs: None,
            };
            let mut jet = <<S::Group as crate::group::StepGroup<D>>::Jet as PointJet>::zeros();
            {
                let x = SVector::<f64, D>::from_fn(|i, _| scale * (0.9 * i as f64 + 0.4).sin());
                let v = SVector::<f64, D>::from_fn(|i, _| 0.8 - 0.3 * i as f64);
                // The point's derivatives as an exact-matching assembly leaves them: with the
                // ζ rows and the Hessian.
                let ell = EllTilde {
                    system,
                    chart: &chart,
                    base,
                    time: stepper.time + d.times[2],
                };
                super::points::point_derivatives(
                    &ell,
                    &x,
                    &v,
                    true,
                    true,
                    forcing.as_ref(),
                    &mut jet,
                    &mut None,
                );
                let point = super::linearize::PointChart::at(&chart, &x);
                let fast = stepper.point_mixed(base, 2, &point, &v, &jet);
                let slow = stepper.point_mixed_by_dual_numbers(base, 2, &x, &v);
                for (what, f, s) in [
                    ("x", fast.x, slow.x),
                    ("v", fast.v, slow.v),
                    ("ζ", fast.zeta, slow.zeta),
                ] {
                    let size = s.amax().max(1.0);
                    assert!(
                        (f - s).amax() <= 1e-12 * size,
                        "{name}, input {forcing:?}, {what} rows at scale {scale}: {:e} of {size:e}",
                        (f - s).amax()
                    );
                }
            }
        }
    }
    let inertia = Inertia::from_principal_moments([0.5, 0.9, 0.7]).unwrap();
    let attitude = SO3::exp(&Vector3::new(0.3, -0.7, 0.2));
    let top = top();
    let potential = crate::RigidBodyInPotential::new(inertia, Quadratic);
    let free = crate::FreeBody::new(inertia, 1.3).unwrap();
    let orbit = crate::OrbitingBody::new(inertia, 1.0, 2.0).unwrap();
    let pushed = crate::Forced::new(
        free,
        crate::forces::SpaceForce(Vector3::new(0.1, -0.3, 0.2)),
    );
    let place = SE3::new(attitude, Vector3::new(2.0, -1.0, 0.5));
    for chart in ChartKind::ALL {
        compare::<_, _, 3>(&top, chart, &attitude, &format!("heavy top, {chart}"));
        compare::<_, _, 3>(&Coupled, chart, &attitude, &format!("coupled, {chart}"));
        compare::<_, _, 3>(&potential, chart, &attitude, &format!("potential, {chart}"));
        compare::<_, _, 6>(&orbit, chart, &place, &format!("orbit, {chart}"));
        compare::<_, _, 6>(
            &CoupledSe3,
            chart,
            &place,
            &format!("coupled SE(3), {chart}"),
        );
        compare::<_, _, 6>(&pushed, chart, &place, &format!("space force, {chart}"));
        compare::<_, _, 6>(
            &orbit,
            Screw(chart),
            &place,
            &format!("orbit, screw {chart}"),
        );
    }
}

/// The chart's terms a point hands back to the exact matching ([`crate::system::PointTransport`])
/// are the chart's own [`crate::GroupChart::transport_and_differential`] at the point: the
/// same Rodrigues coefficients put together in another order, so equal to a few roundings
/// of their largest entry (1e-14 relative). They are handed back exactly where the matching
/// reads them and the point formed `Φ(x)`: with the configuration rows, for the heavy top
/// (its attitude term) and a potential of `R`, in every chart, with and without Hessians;
/// never without the configuration rows, nor by the free SO(3) body, which forms no
/// `Φ(x)`, nor by the SE(3) systems, whose points do not hand them back (forming the 6 × 6
/// pair costs about what it saves).
#[test]
fn points_hand_back_the_charts_transport() {
    use crate::system::ElementOf;
    use lgsvi_lie::SE3;
    fn check<S, C, const D: usize>(
        system: &S,
        chart: C,
        base: &ElementOf<S, D>,
        x: &SVector<f64, D>,
        v: &SVector<f64, D>,
        hands_back: bool,
        name: &str,
    ) where
        S: crate::System<D>,
        C: crate::group::GroupChart<S::Group, D>,
    {
        for with_configuration in [false, true] {
            for with_hessian in [false, true] {
                let ell = EllTilde {
                    system,
                    chart: &chart,
                    base,
                    time: 0.7,
                };
                let mut jet = <S::Group as crate::group::StepGroup<D>>::Jet::zeros();
                let mut transport = None;
                super::points::point_derivatives(
                    &ell,
                    x,
                    v,
                    with_configuration,
                    with_hessian,
                    None,
                    &mut jet,
                    &mut transport,
                );
                let case = format!("{name}, ζ = {with_configuration}, H = {with_hessian}");
                assert_eq!(
                    transport.is_some(),
                    hands_back && with_configuration,
                    "{case}"
                );
                if let Some(t) = transport {
                    let (to_start, differential) = chart.transport_and_differential(x);
                    let apart = (t.to_start - to_start)
                        .amax()
                        .max((t.differential - differential).amax());
                    let scale = to_start.amax().max(differential.amax());
                    assert!(apart <= 1e-14 * scale, "{case}: {apart:e} of {scale:e}");
                }
            }
        }
    }
    let b3 = SO3::exp(&Vector3::new(0.4, -0.7, 0.2));
    let b6 = SE3::new(b3, Vector3::new(3.0, -2.0, 0.5));
    let inertia = Inertia::from_principal_moments([0.3, 0.2, 0.4]).unwrap();
    let potential = crate::RigidBodyInPotential::new(inertia, super::Quadratic);
    let free = crate::RigidBody::new(inertia);
    let orbit = crate::OrbitingBody::new(inertia, 1.3, 2.0).unwrap();
    let field = crate::BodyInField::new(inertia, 1.3, Spring).unwrap();
    /// A spring on the centre of mass and a dipole along body x in a uniform field.
    struct Spring;
    impl crate::FieldPotential for Spring {
        fn potential<T: RealField + Copy>(&self, _t: f64, r: &Matrix3<T>, x: &Vector3<T>) -> T {
            x.norm_squared() * nalgebra::convert::<f64, T>(0.4) - r[(2, 0)]
        }
    }
    let rotations = [
        Vector3::zeros(),
        Vector3::new(0.3, -0.1, 0.25),
        Vector3::new(1.5, -2.2, 1.1),
    ];
    let w = Vector3::new(1.1, 0.4, -0.6);
    for chart in ChartKind::ALL {
        for x in &rotations {
            let name = format!("{chart} at {x:?}");
            check::<_, _, 3>(&super::top(), chart, &b3, x, &w, true, &name);
            check::<_, _, 3>(&potential, chart, &b3, x, &w, true, &name);
            check::<_, _, 3>(&free, chart, &b3, x, &w, false, &name);
            let x6 = SVector::<f64, 6>::new(x.x, x.y, x.z, 0.2, 0.1, -0.3);
            let v6 = SVector::<f64, 6>::new(w.x, w.y, w.z, -0.5, 0.8, 0.1);
            check::<_, _, 6>(&orbit, chart, &b6, &x6, &v6, false, &name);
            check::<_, _, 6>(&field, chart, &b6, &x6, &v6, false, &name);
        }
    }
}
