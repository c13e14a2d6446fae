use super::assembly::Workspace;
use super::newton::substitute;
use super::points::EllTilde;
use super::tables::Discretisation;
use super::*;
use crate::group::{PointJet, Stacked};
use crate::inertia::Inertia;
use crate::jet;
use crate::lagrangian::{HeavyTop, Lagrangian};
use crate::settings::{Matching, StepSettings};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor;
use faer::{Mat, Par};
use lgsvi_lie::{ChartKind, SO3};
use nalgebra::{Matrix3, RealField, SVector, Vector3};

type PointDerivatives = Stacked<9>;

/// `ℓ(g Φ(x) exp(ζ), A(x) v)` in f64, through the generic point function.
fn ell_tilde<L: Lagrangian>(
    system: &L,
    chart: ChartKind,
    base: &Matrix3<f64>,
    x: &Vector3<f64>,
    v: &Vector3<f64>,
    zeta: Option<&Vector3<f64>>,
) -> f64 {
    use crate::group::StackedFunction;
    let base = SO3::from_matrix_unchecked(*base);
    let ell = EllTilde {
        system,
        chart: &chart,
        base: &base,
        time: 0.0,
    };
    let mut y = vec![x.x, x.y, x.z, v.x, v.y, v.z];
    if let Some(z) = zeta {
        y.extend_from_slice(z.as_slice());
    }
    ell.eval(&y)
}

/// The dual-number path alone.
fn point_derivatives_by_dual_numbers<L: Lagrangian>(
    system: &L,
    chart: ChartKind,
    base: &Matrix3<f64>,
    x: &Vector3<f64>,
    v: &Vector3<f64>,
    with_configuration: bool,
) -> PointDerivatives {
    let base = SO3::from_matrix_unchecked(*base);
    let ell = EllTilde {
        system,
        chart: &chart,
        base: &base,
        time: 0.0,
    };
    let mut out = PointDerivatives::zeros();
    out.set_by_dual_numbers(&ell, x.as_slice(), v.as_slice(), with_configuration);
    out
}

fn top() -> HeavyTop {
    HeavyTop::new(
        Inertia::from_paper_jd([1.0, 2.8, 2.0]).unwrap(),
        1.3,
        9.81,
        Vector3::new(0.1, -0.2, 1.0),
        Vector3::new(0.3, 0.1, 1.0),
    )
    .unwrap()
}

fn base() -> Matrix3<f64> {
    *SO3::exp(&Vector3::new(0.4, -0.7, 0.2)).matrix()
}

/// A Gauss point at time 0.7 from `base`.
fn gauss_point<'a, G: crate::ConfigurationGroup<D>, const D: usize>(
    base: &'a G::Element<f64>,
    x: &'a SVector<f64, D>,
    v: &'a SVector<f64, D>,
    with_configuration: bool,
    with_hessian: bool,
    force: Option<&'a dyn crate::PointForce<G, D>>,
) -> crate::GaussPoint<'a, G, D> {
    crate::GaussPoint {
        time: 0.7,
        base,
        x,
        v,
        with_configuration,
        with_hessian,
        force,
    }
}

/// The chain-rule path alone ([`jet::point_derivatives`]), as a value.
fn chain_rule_at<L: Lagrangian>(
    system: &L,
    chart: ChartKind,
    x: &Vector3<f64>,
    v: &Vector3<f64>,
    with_configuration: bool,
    with_hessian: bool,
) -> PointDerivatives {
    let mut out = PointDerivatives::zeros();
    let b = SO3::from_matrix_unchecked(base());
    let point = gauss_point(&b, x, v, with_configuration, with_hessian, None);
    let done = jet::point_derivatives(system, &chart, &point, &mut out);
    assert!(done, "{chart} has a Rodrigues form");
    out
}

/// The per-point gradient and Hessian from dual numbers against central differences of
/// the same function in f64. Step 1e-4 for the gradient (truncation ~h²·|f'''| ≈ 1e-8·10,
/// rounding ε|f|/h ≈ 1e-11) and 1e-4 on the gradient for the Hessian: bound 1e-6
/// relative to the largest entry.
#[test]
fn point_derivatives_match_central_differences() {
    let system = top();
    for chart in ChartKind::ALL {
        let (x, v) = (Vector3::new(0.3, -0.1, 0.25), Vector3::new(1.1, 0.4, -0.6));
        let p = chain_rule_at(&system, chart, &x, &v, true, true);
        let f = |y: &SVector<f64, 9>| {
            let x = y.fixed_rows::<3>(0).into_owned();
            let v = y.fixed_rows::<3>(3).into_owned();
            let z = y.fixed_rows::<3>(6).into_owned();
            ell_tilde(&system, chart, &base(), &x, &v, Some(&z))
        };
        let y0 =
            SVector::<f64, 9>::from_column_slice(&[x.x, x.y, x.z, v.x, v.y, v.z, 0.0, 0.0, 0.0]);
        let h = 1e-4;
        let scale = p.hessian.amax().max(p.gradient.amax());
        for a in 0..9 {
            let e = SVector::<f64, 9>::from_fn(|i, _| if i == a { h } else { 0.0 });
            let fd = (f(&(y0 + e)) - f(&(y0 - e))) / (2.0 * h);
            assert!(
                (fd - p.gradient[a]).abs() <= 1e-6 * scale,
                "{chart} gradient {a}"
            );
            let gp = chain_rule_at(
                &system,
                chart,
                &(x + e.fixed_rows::<3>(0)),
                &(v + e.fixed_rows::<3>(3)),
                true,
                true,
            );
            // The ζ-columns need the function itself (the point is always at ζ = 0).
            for b in 0..6 {
                if a < 6 {
                    let gm = chain_rule_at(
                        &system,
                        chart,
                        &(x - e.fixed_rows::<3>(0)),
                        &(v - e.fixed_rows::<3>(3)),
                        true,
                        true,
                    );
                    let fd2 = (gp.gradient[b] - gm.gradient[b]) / (2.0 * h);
                    assert!(
                        (fd2 - p.hessian[(a, b)]).abs() <= 1e-6 * scale,
                        "{chart} hessian ({a},{b})"
                    );
                }
            }
        }
    }
}

/// A Lagrangian that couples `R` and `Ω` and is not linear in `R` (exercises every block
/// of the chain rule through the default, dual-number [`Lagrangian::derivatives`]).
struct Coupled;
impl Lagrangian for Coupled {
    fn lagrangian<T: RealField + Copy>(&self, r: &Matrix3<T>, w: &Vector3<T>) -> T {
        let c = |x: f64| -> T { nalgebra::convert(x) };
        let up = r.transpose() * Vector3::new(c(0.2), c(-0.1), c(1.0));
        c(0.5) * (w.x * w.x * c(1.2) + w.y * w.y * c(2.1) + w.z * w.z * c(2.7))
            + up.dot(w) * c(0.3)
            + r[(0, 1)] * r[(2, 2)] * c(1.7)
            - r[(1, 0)] * c(0.4)
    }
}

/// A potential quadratic in `R` (through [`RigidBodyInPotential`]'s closed-form kinetic
/// part and dual-number potential).
struct Quadratic;
impl crate::Potential for Quadratic {
    fn potential<T: RealField + Copy>(&self, r: &Matrix3<T>) -> T {
        let c = |x: f64| -> T { nalgebra::convert(x) };
        r[(2, 0)] * r[(2, 0)] * c(3.0) - r[(1, 2)] * c(0.5)
    }
}

/// The chain rule (chart Rodrigues jets and [`Lagrangian::derivatives`]) against a
/// second-order dual number through the whole of `ℓ̃`, for every chart, system and
/// variable set, at points from `x = 0` to rotations past 3 rad. Both are exact up to
/// rounding, which here is a few hundred ulps of the largest entry at most (sums of
/// tens of terms of size ~ the scale): 1e-13 relative.
#[test]
fn chain_rule_derivatives_match_dual_numbers() {
    let inertia = Inertia::from_paper_jd([1.0, 2.8, 2.0]).unwrap();
    let points = [
        (Vector3::zeros(), Vector3::new(1.1, 0.4, -0.6)),
        (
            Vector3::new(1e-9, -2e-9, 5e-10),
            Vector3::new(-0.3, 0.9, 0.2),
        ),
        (Vector3::new(0.3, -0.1, 0.25), Vector3::new(1.1, 0.4, -0.6)),
        (Vector3::new(-0.4, 0.2, 0.1), Vector3::new(0.5, -1.5, 2.0)),
        (Vector3::new(1.5, -2.2, 1.1), Vector3::new(2.0, 0.7, -1.0)),
    ];
    fn compare<L: Lagrangian>(system: &L, name: &str, x: &Vector3<f64>, v: &Vector3<f64>) {
        for chart in ChartKind::ALL {
            for with_configuration in [false, true] {
                let fast = chain_rule_at(system, chart, x, v, with_configuration, true);
                let gradient_only = chain_rule_at(system, chart, x, v, with_configuration, false);
                // The gradient-only path takes the coefficients' first derivatives
                // from a first-order dual number instead of a second-order one: the
                // same formulas, evaluated in another order, so a few ulps apart.
                let size = fast.gradient.amax().max(1.0);
                assert!(
                    (gradient_only.gradient - fast.gradient).amax() <= 8.0 * f64::EPSILON * size,
                    "{chart}: {} vs {}",
                    gradient_only.gradient,
                    fast.gradient
                );
                let slow = point_derivatives_by_dual_numbers(
                    system,
                    chart,
                    &base(),
                    x,
                    v,
                    with_configuration,
                );
                let scale = slow.gradient.amax().max(slow.hessian.amax()).max(1.0);
                let gradient = (fast.gradient - slow.gradient).amax();
                let hessian = (fast.hessian - slow.hessian).amax();
                assert!(
                    gradient <= 1e-13 * scale && hessian <= 1e-13 * scale,
                    "{name} {chart} x = {x:?} ζ = {with_configuration}: \
                         gradient {gradient:e}, Hessian {hessian:e} of {scale:e}"
                );
            }
        }
    }
    for (x, v) in &points {
        compare(&crate::RigidBody::new(inertia), "rigid body", x, v);
        compare(&top(), "heavy top", x, v);
        compare(
            &crate::RigidBodyInPotential::new(inertia, Quadratic),
            "quadratic potential",
            x,
            v,
        );
        compare(&Coupled, "coupled", x, v);
    }
}

/// [`substitute`] on faer's LU solves the system: the residual `‖A x − b‖∞` of the
/// computed solution is at most a small multiple of `ε ‖A‖∞ ‖x‖∞` (partial pivoting is
/// backward stable; for these sizes the growth factor stays small), on a nonsymmetric
/// matrix that needs row exchanges (its diagonal is small).
#[test]
fn substitution_on_faer_factors_solves_the_system() {
    for size in [1usize, 3, 27, 45] {
        let entry = |i: usize, j: usize| {
            let (x, y) = (i as f64, j as f64);
            (1.3 * x + 0.7 * y).sin() + if i == j { 1e-3 } else { 0.0 }
        };
        let a = Mat::from_fn(size, size, entry);
        let b: Vec<f64> = (0..size).map(|i| (0.4 * i as f64).cos() + 0.5).collect();
        let mut lu = a.clone();
        let (mut perm, mut perm_inv) = (vec![0; size], vec![0; size]);
        let mut stack = MemBuffer::new(factor::lu_in_place_scratch::<usize, f64>(
            size,
            size,
            Par::Seq,
            Default::default(),
        ));
        factor::lu_in_place(
            lu.as_mut(),
            &mut perm,
            &mut perm_inv,
            Par::Seq,
            MemStack::new(&mut stack),
            Default::default(),
        );
        let mut x: Vec<f64> = perm.iter().map(|&p| b[p]).collect();
        substitute(&lu, &mut x);
        let norm_a = (0..size)
            .map(|i| (0..size).map(|j| a[(i, j)].abs()).sum::<f64>())
            .fold(0.0, f64::max);
        let norm_x = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let residual = (0..size)
            .map(|i| ((0..size).map(|j| a[(i, j)] * x[j]).sum::<f64>() - b[i]).abs())
            .fold(0.0, f64::max);
        assert!(
            residual <= 64.0 * size as f64 * f64::EPSILON * norm_a * norm_x,
            "size {size}: residual {residual:e}, ‖A‖ {norm_a:e}, ‖x‖ {norm_x:e}"
        );
    }
}

/// A workspace holding a curve that is not a solution (constant velocity plus a wobble),
/// assembled with its Newton matrix at the step's start `b` with momentum `μ`.
fn assembled_off_the_solution<S: crate::GroupLagrangian<3, Group = crate::group::Rotations>>(
    stepper: &Stepper<'_, S, ChartKind, 3>,
    d: &Discretisation,
) -> (Workspace<Stacked<9>, 3>, SO3, Vector3<f64>) {
    let mut work = Workspace::<Stacked<9>, 3>::new(d);
    let omega = Vector3::new(0.5, -0.8, 0.3);
    for (i, t) in d.node_times().iter().enumerate() {
        work.xi[i] = omega * *t + Vector3::new(0.02, -0.01, 0.03) * (t * t);
    }
    work.xi[0] = Vector3::zeros();
    let mu = Vector3::new(2.4, -1.5, 1.52);
    let b = SO3::from_matrix_unchecked(base());
    stepper.assemble(&b, &mu, &mut work, true);
    stepper.fill_jacobian(&mut work);
    (work, b, mu)
}

/// The exact Newton matrix (both matchings, a configuration-dependent system, every
/// chart) against forward differences of the residual away from the solution. Forward
/// differences with step √ε·max(1, |z|) are accurate to ~√ε·|F''| ≈ 1e-7 relative.
#[test]
fn exact_newton_matrix_matches_differences_of_the_residual() {
    let system = top();
    for chart in ChartKind::ALL {
        for matching in [Matching::Exact, Matching::Paper] {
            let settings = StepSettings::new(0.4, 5)
                .unwrap()
                .with_chart(chart)
                .with_matching(matching);
            let d = Discretisation::new(&settings).unwrap();
            let stepper = Stepper {
                system: &system,
                chart: &chart,
                settings: &settings,
                d: &d,
                time: 0.0,
                forcing: None,
            };
            let (mut work, b, mu) = assembled_off_the_solution(&stepper, &d);
            let exact = work.jacobian.clone();
            stepper.fill_jacobian_by_differences(&b, &mu, &mut work);
            let mut worst = 0.0f64;
            let mut scale = 0.0f64;
            for r in 0..exact.nrows() {
                for c in 0..exact.ncols() {
                    worst = worst.max((exact[(r, c)] - work.jacobian[(r, c)]).abs());
                    scale = scale.max(exact[(r, c)].abs());
                }
            }
            assert!(
                worst <= 1e-6 * scale,
                "{chart} {matching:?}: {worst:e} of {scale:e}"
            );
        }
    }
}

/// The exact matching's `w` carried through a move `δ` of the unknowns with the last
/// Newton matrix's `∂w/∂ξ` ([`Stepper::carry_matching`], which the Newton loop applies
/// to its last chord step instead of assembling again) agrees with `w` assembled at the
/// moved unknowns up to the second-order remainder: for `|δ| = 1e-5` that is ~1e-10 of
/// `|w|` (curvature of order one), where leaving `w` where it was is off by ~1e-5. The
/// heavy top under a torque: configuration terms from both ℓ and the force.
#[test]
fn carried_matching_momentum_agrees_with_a_new_assembly() {
    let system = top();
    let input = Vector3::new(0.3, -0.2, 0.1);
    for chart in ChartKind::ALL {
        let settings = StepSettings::new(0.4, 6).unwrap().with_chart(chart);
        let d = Discretisation::new(&settings).unwrap();
        let stepper = Stepper {
            system: &system,
            chart: &chart,
            settings: &settings,
            d: &d,
            time: 0.0,
            forcing: Some(input),
        };
        let (mut work, b, mu) = assembled_off_the_solution(&stepper, &d);
        let before = work.matching.w;
        for (k, delta) in work.delta.iter_mut().enumerate() {
            *delta = 1e-5 * ((k as f64 * 0.7).sin() + 0.3);
        }
        for (i, xi) in work.xi.iter_mut().enumerate().skip(1) {
            for c in 0..3 {
                xi[c] += work.delta[3 * (i - 1) + c];
            }
        }
        stepper.carry_matching(&mut work);
        let carried = work.matching.w;
        stepper.assemble(&b, &mu, &mut work, false);
        let assembled = work.matching.w;
        let scale = assembled.amax();
        assert!(
            (carried - assembled).amax() <= 1e-9 * scale,
            "{chart}: carried {carried:?}, assembled {assembled:?}"
        );
        // The move matters at first order: the test would notice a carry that did nothing.
        assert!((before - assembled).amax() >= 1e-7 * scale, "{chart}");
    }
}

/// A Lagrangian on SE(3) that couples attitude, position and both velocities and depends
/// on time (exercises every block of the generic chain rule).
struct CoupledSe3;
impl crate::GroupLagrangian<6> for CoupledSe3 {
    type Group = crate::RigidMotions;
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
        S: crate::GroupLagrangian<D>,
        C: crate::GroupChart<S::Group, D>,
    {
        for with_configuration in [false, true] {
            let ell = EllTilde {
                system,
                chart: &chart,
                base,
                time: 0.7,
            };
            let mut fast = <S::Group as crate::ConfigurationGroup<D>>::Jet::zeros();
            let point = gauss_point(base, x, v, with_configuration, true, None);
            super::points::chain_rule(&ell, &point, &mut fast);
            let mut gradient_only = fast.clone();
            let point = gauss_point(base, x, v, with_configuration, false, None);
            super::points::chain_rule(&ell, &point, &mut gradient_only);
            let mut slow = <S::Group as crate::ConfigurationGroup<D>>::Jet::zeros();
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
                for c in 0..n {
                    if r >= 2 * D && c >= 2 * D {
                        continue;
                    }
                    if !with_configuration && (r >= 2 * D || c >= 2 * D) {
                        continue;
                    }
                    worst = worst.max((fast.hessian(r, c) - slow.hessian(r, c)).abs());
                }
            }
            assert!(
                worst <= 1e-12 * scale,
                "{name} ζ = {with_configuration}: {worst:e} of {scale:e}"
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
        compare::<_, _, 6>(&orbit, Screw(ExpChart), &b6, x, v, "orbit screw exp");
        compare::<_, _, 6>(&field, Screw(CayleyChart), &b6, x, v, "field screw cayley");
        compare::<_, _, 6>(&CoupledSe3, Screw(ExpChart), &b6, x, v, "coupled screw exp");
    }
    // SO(3) through the generic path: a wrapper that hides the closed form.
    struct Generic<L>(L);
    impl<L: Lagrangian> crate::GroupLagrangian<3> for Generic<L> {
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
    use crate::group::{RigidMotions, Rotations};
    use crate::system::{ElementOf, Forced, Forcing};
    use crate::{AngularDamping, BodyTorque, ForceOfTime, RigidBody, SpaceForce};
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
        S: crate::GroupLagrangian<D>,
        C: crate::GroupChart<S::Group, D>,
    {
        let ell = EllTilde {
            system,
            chart: &chart,
            base,
            time: 0.7,
        };
        let mut fast = <S::Group as crate::ConfigurationGroup<D>>::Jet::zeros();
        point_derivatives(&ell, x, v, true, true, Some(input), &mut fast);
        let mut gradient_only = fast.clone();
        point_derivatives(&ell, x, v, true, false, Some(input), &mut gradient_only);
        let mut slow = <S::Group as crate::ConfigurationGroup<D>>::Jet::zeros();
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
    impl<L: Lagrangian> crate::GroupLagrangian<3> for Generic<L> {
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

/// The rotation–translation chart's closed-form derivatives on SE(3) against the
/// dual-number ones of the same chart (`dual_number_derivatives`), every chart, points from
/// `x = 0` to large rotations, each contraction with arbitrary vectors. Exact up to
/// rounding: 1e-13 relative to the largest entry.
#[test]
fn rotation_translation_chart_derivatives_match_dual_numbers() {
    use crate::group::{dual_number_derivatives, ChartDerivatives, GroupChart, RigidMotions};
    let g = SVector::<f64, 6>::new(0.7, -1.2, 0.4, 2.0, -0.3, 0.9);
    let mu = SVector::<f64, 6>::new(-0.5, 0.8, 1.3, 0.2, -1.1, 0.6);
    let v = SVector::<f64, 6>::new(1.1, 0.4, -0.6, -0.5, 0.8, 0.1);
    for chart in ChartKind::ALL {
        for x in [
            SVector::<f64, 6>::zeros(),
            SVector::<f64, 6>::new(0.3, -0.1, 0.25, 0.2, 0.1, -0.3),
            SVector::<f64, 6>::new(1.5, -2.2, 1.1, -0.4, 0.9, 0.3),
        ] {
            let read = |d: &dyn ChartDerivatives<6>| {
                [
                    d.differential(),
                    d.differential_times(&v),
                    d.transpose_times(&g),
                    d.second(&mu, &v),
                ]
            };
            let fast = GroupChart::<RigidMotions, 6>::with_derivatives(&chart, &x, true, read);
            let slow = dual_number_derivatives::<RigidMotions, _, _, 6>(&chart, &x, read);
            for (k, (f, s)) in fast.iter().zip(&slow).enumerate() {
                let scale = s.amax().max(1.0);
                assert!(
                    (f - s).amax() <= 1e-13 * scale,
                    "{chart} at {x:?}, contraction {k}: {:e}",
                    (f - s).amax()
                );
            }
        }
    }
}

/// The matching map's Jacobian `∂/∂y [A(y)ᵀ Ad_{Φ(y)}ᵀ w]` (chart derivatives and the
/// coadjoint generator) against dual numbers through the chart and the adjoint, on SO(3)
/// for every chart and on SE(3) for the rotation–translation and the screw charts, from
/// `y = 0` to rotations past 2 rad. Both exact to rounding: 1e-13 of the largest entry.
#[test]
fn matching_map_jacobian_matches_dual_numbers() {
    use crate::group::{GroupChart, Screw};
    use crate::system::GroupLagrangian;
    fn compare<S: GroupLagrangian<D>, C: GroupChart<S::Group, D>, const D: usize>(
        system: &S,
        chart: C,
        name: &str,
    ) {
        let settings = StepSettings::new(0.4, 5).unwrap();
        let d = Discretisation::new(&settings).unwrap();
        let stepper = Stepper {
            system,
            chart: &chart,
            settings: &settings,
            d: &d,
            time: 0.0,
            forcing: None,
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
    use crate::system::GroupLagrangian;
    use lgsvi_lie::SE3;
    fn compare<S: GroupLagrangian<D>, C: GroupChart<S::Group, D>, const D: usize>(
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
            let stepper = Stepper {
                system,
                chart: &chart,
                settings: &settings,
                d: &d,
                time: 0.3,
                forcing,
            };
            let mut jet = <<S::Group as crate::ConfigurationGroup<D>>::Jet as PointJet>::zeros();
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
    let pushed = crate::Forced::new(free, crate::SpaceForce(Vector3::new(0.1, -0.3, 0.2)));
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
