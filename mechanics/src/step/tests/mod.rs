use super::assembly::{Workspace, WorkspaceOf};
use super::newton::substitute;
use super::points::EllTilde;
use super::tables::Discretisation;
use super::*;
use crate::group::{PointJet, Stacked};
use crate::inertia::Inertia;
use crate::jet;
use crate::lagrangian::{HeavyTop, Lagrangian};
use crate::settings::{Matching, StepSettings};
use lgsvi_lie::{ChartKind, SO3};
use nalgebra::{DMatrix, Matrix3, RealField, SVector, Vector3};

mod whole_point;

type PointDerivatives = Stacked<9>;

/// `ℓ(g Φ(x) exp(ζ), A(x) v)` in f64, through the generic point function.
fn ell_tilde<L: Lagrangian + crate::System<3, Group = crate::group::Rotations>>(
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
fn point_derivatives_by_dual_numbers<
    L: Lagrangian + crate::System<3, Group = crate::group::Rotations>,
>(
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
fn gauss_point<'a, G: crate::group::StepGroup<D>, const D: usize>(
    base: &'a G::Element<f64>,
    x: &'a SVector<f64, D>,
    v: &'a SVector<f64, D>,
    with_configuration: bool,
    with_hessian: bool,
    force: Option<&'a dyn crate::system::PointForce<G, D>>,
) -> crate::system::GaussPoint<'a, G, D> {
    crate::system::GaussPoint {
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
fn chain_rule_at<L: Lagrangian + crate::System<3, Group = crate::group::Rotations>>(
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
    let done = jet::point_derivatives(system, &chart, &point, &mut out, &mut None);
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
crate::system::so3_system! {
    impl[] for Coupled;
}

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

/// `got` against a second-order dual number through the whole of `ℓ̃` at the point: both
/// exact up to rounding, a few hundred ulps of the largest entry at most (sums of tens of
/// terms of size ~ the scale), so within 1e-13 of it.
fn assert_near_dual_numbers<L: Lagrangian + crate::System<3, Group = crate::group::Rotations>>(
    system: &L,
    chart: ChartKind,
    x: &Vector3<f64>,
    v: &Vector3<f64>,
    with_configuration: bool,
    got: &PointDerivatives,
    at: &str,
) {
    let slow = point_derivatives_by_dual_numbers(system, chart, &base(), x, v, with_configuration);
    let scale = slow.gradient.amax().max(slow.hessian.amax()).max(1.0);
    let gradient = (got.gradient - slow.gradient).amax();
    let hessian = (got.hessian - slow.hessian).amax();
    assert!(
        gradient <= 1e-13 * scale && hessian <= 1e-13 * scale,
        "{at}: gradient {gradient:e}, Hessian {hessian:e} of {scale:e}"
    );
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
    fn compare<L: Lagrangian + crate::System<3, Group = crate::group::Rotations>>(
        system: &L,
        name: &str,
        x: &Vector3<f64>,
        v: &Vector3<f64>,
    ) {
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
                let at = format!("{name} {chart} x = {x:?} ζ = {with_configuration}");
                assert_near_dual_numbers(system, chart, x, v, with_configuration, &fast, &at);
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

/// The points of an unforced step four at a time ([`crate::jet_lanes::points_in_lanes`])
/// against a second-order dual number through the whole of `ℓ̃`, for every chart, with
/// and without the `ζ` rows, at seven points (a full chunk of four and a short one of
/// three) from `x = 0` to rotations past 3 rad: the free body (ℓ's derivatives in closed
/// form), a kinetic energy of the user's own (by dual numbers) and the heavy top (an
/// attitude term linear in `R`). Both are exact up to rounding, a few hundred ulps of the
/// largest entry at most, as in [`chain_rule_derivatives_match_dual_numbers`]: 1e-13
/// relative. Against the point-by-point chain rule ([`jet::point_derivatives`]), bit for
/// bit, the chart's transports included. A gradient-only evaluation leaves the Hessians
/// as they were; a system whose attitude term is not linear is refused with nothing
/// written.
#[test]
fn points_in_lanes_match_dual_numbers() {
    /// `½ΩᵀJΩ + ¼ c |Ω|⁴`: left-invariant, not quadratic, derivatives by dual numbers.
    struct Quartic;
    crate::system::so3_system! {
        impl[] for Quartic;
    }

    impl Lagrangian for Quartic {
        fn lagrangian<T: RealField + Copy>(&self, _r: &Matrix3<T>, w: &Vector3<T>) -> T {
            let c = |x: f64| -> T { nalgebra::convert(x) };
            let q = w.x * w.x * c(1.2) + w.y * w.y * c(2.1) + w.z * w.z * c(2.7);
            let n2 = w.norm_squared();
            c(0.5) * q + c(0.05) * n2 * n2
        }
        fn is_left_invariant(&self) -> bool {
            true
        }
    }
    let inertia = Inertia::from_paper_jd([1.0, 2.8, 2.0]).unwrap();
    let xs = [
        Vector3::zeros(),
        Vector3::new(1e-9, -2e-9, 5e-10),
        Vector3::new(0.3, -0.1, 0.25),
        Vector3::new(-0.4, 0.2, 0.1),
        Vector3::new(1.5, -2.2, 1.1),
        Vector3::new(0.9, 0.6, -1.2),
        Vector3::new(-1.3, 0.2, 0.4),
    ];
    let vs = [
        Vector3::new(1.1, 0.4, -0.6),
        Vector3::new(-0.3, 0.9, 0.2),
        Vector3::new(1.1, 0.4, -0.6),
        Vector3::new(0.5, -1.5, 2.0),
        Vector3::new(2.0, 0.7, -1.0),
        Vector3::new(-0.8, 1.3, 0.3),
        Vector3::new(0.2, -0.4, 1.6),
    ];
    fn bits(p: &PointDerivatives) -> Vec<u64> {
        let h = p.hessian.iter().map(|e| e.to_bits());
        p.gradient.iter().map(|e| e.to_bits()).chain(h).collect()
    }
    fn check<L: Lagrangian + crate::System<3, Group = crate::group::Rotations>>(
        system: &L,
        name: &str,
        xs: &[Vector3<f64>],
        vs: &[Vector3<f64>],
    ) {
        let b = SO3::from_matrix_unchecked(base());
        let sentinel = PointDerivatives {
            gradient: SVector::repeat(f64::NAN),
            hessian: nalgebra::SMatrix::repeat(7.0),
        };
        let one_by_one = |chart: ChartKind, x, v, with_configuration, with_hessian| {
            let mut out = PointDerivatives::zeros();
            let mut transport = None;
            let point = gauss_point(&b, x, v, with_configuration, with_hessian, None);
            assert!(jet::point_derivatives(
                system,
                &chart,
                &point,
                &mut out,
                &mut transport
            ));
            (out, transport)
        };
        for chart in ChartKind::ALL {
            for with_configuration in [false, true] {
                let lanes = |with_hessian, out: &mut [PointDerivatives], transports: &mut [_]| {
                    let points = crate::system::GaussPoints {
                        base: &b,
                        x: xs,
                        v: vs,
                        with_configuration,
                        with_hessian,
                        force: None,
                    };
                    let mut power = vec![0.0; xs.len()];
                    let done = crate::jet_lanes::points_in_lanes(
                        system, &chart, &points, out, transports, &mut power,
                    );
                    assert!(power.iter().all(|p| p.is_nan()), "unforced: no power");
                    done
                };
                let mut out = vec![sentinel; xs.len()];
                let mut transports = vec![None; xs.len()];
                assert!(lanes(true, &mut out, &mut transports));
                let mut gradient_only = vec![sentinel; xs.len()];
                let mut unused = vec![None; xs.len()];
                assert!(lanes(false, &mut gradient_only, &mut unused));
                for (j, (x, v)) in xs.iter().zip(vs).enumerate() {
                    let at = format!("{name} {chart} ζ = {with_configuration} point {j}");
                    assert_near_dual_numbers(system, chart, x, v, with_configuration, &out[j], &at);
                    // The lanes do the scalar chain rule's operations in its order: the
                    // same bits, with and without Hessians (the docs' measurements rely
                    // on it), and the same transports.
                    let (scalar, transport) = one_by_one(chart, x, v, with_configuration, true);
                    assert_eq!(bits(&out[j]), bits(&scalar), "{at}");
                    assert_eq!(transports[j], transport, "{at}");
                    let (scalar, _) = one_by_one(chart, x, v, with_configuration, false);
                    assert_eq!(
                        gradient_only[j].gradient.map(f64::to_bits),
                        scalar.gradient.map(f64::to_bits),
                        "{at}, gradient only"
                    );
                    assert_eq!(gradient_only[j].hessian, sentinel.hessian, "{at}");
                }
            }
        }
    }
    /// A forced step's points (the system's force and a control input) four at a time
    /// against the point-by-point path, bit for bit, the powers `F·ξ` included (that path
    /// is checked against dual numbers in `force_terms_match_dual_numbers_through_the_whole_point`).
    fn check_forced<S: crate::System<3, Group = crate::group::Rotations>>(
        system: &S,
        name: &str,
        xs: &[Vector3<f64>],
        vs: &[Vector3<f64>],
    ) {
        use super::points::{point_derivatives, StepForce};
        use crate::system::PointForce;
        let b = SO3::from_matrix_unchecked(base());
        let input = Vector3::new(0.05, 0.0, -0.03);
        for chart in ChartKind::ALL {
            for with_hessian in [true, false] {
                let force_at = |_: usize, g: &SO3, xi: &Vector3<f64>| {
                    StepForce::new(system, 0.7, &input).jet_and_power(g, xi, with_hessian)
                };
                let reads = StepForce::new(system, 0.7, &input).depends_on_configuration();
                let points = crate::system::GaussPoints {
                    base: &b,
                    x: xs,
                    v: vs,
                    with_configuration: true,
                    with_hessian,
                    force: Some((&force_at, reads)),
                };
                let mut out = vec![PointDerivatives::zeros(); xs.len()];
                let (mut transports, mut power) = (vec![None; xs.len()], vec![0.0; xs.len()]);
                assert!(system.points_in_lanes(
                    &chart,
                    &points,
                    &mut out,
                    &mut transports,
                    &mut power
                ));
                for (j, (x, v)) in xs.iter().zip(vs).enumerate() {
                    let ell = EllTilde {
                        system,
                        chart: &chart,
                        base: &b,
                        time: 0.7,
                    };
                    let mut scalar = PointDerivatives::zeros();
                    let mut transport = None;
                    let scalar_power = point_derivatives(
                        &ell,
                        x,
                        v,
                        true,
                        with_hessian,
                        Some(&input),
                        &mut scalar,
                        &mut transport,
                    );
                    let at = format!("{name} {chart} Hessian {with_hessian} point {j}");
                    assert_eq!(bits(&out[j]), bits(&scalar), "{at}");
                    assert_eq!(transports[j], transport, "{at}");
                    assert_eq!(power[j].to_bits(), scalar_power.to_bits(), "{at}");
                    assert!(power[j].is_finite(), "{at}");
                }
            }
        }
    }
    let torque = crate::forces::BodyTorque(Vector3::new(0.1, -0.2, 0.05));
    let damping = crate::forces::AngularDamping(0.3);
    let free = crate::RigidBody::new(inertia);
    check_forced(
        &crate::Forced::new(free, torque),
        "free body, torque",
        &xs,
        &vs,
    );
    check_forced(
        &crate::Forced::new(free, (torque, damping)),
        "free body, damping",
        &xs,
        &vs,
    );
    check_forced(
        &crate::Forced::new(top(), (torque, damping)),
        "heavy top, damping",
        &xs,
        &vs,
    );
    check(&crate::RigidBody::new(inertia), "free body", &xs, &vs);
    check(&Quartic, "quartic kinetic energy", &xs, &vs);
    check(&top(), "heavy top", &xs, &vs);
    let b = SO3::from_matrix_unchecked(base());
    let mut out = vec![PointDerivatives::zeros(); xs.len()];
    let mut transports = vec![None; xs.len()];
    let points = crate::system::GaussPoints {
        base: &b,
        x: &xs,
        v: &vs,
        with_configuration: true,
        with_hessian: true,
        force: None,
    };
    let refused = !crate::jet_lanes::points_in_lanes(
        &Coupled,
        &ChartKind::Exp,
        &points,
        &mut out,
        &mut transports,
        &mut [0.0; 7],
    );
    assert!(refused && out.iter().all(|p| *p == PointDerivatives::zeros()));
}

/// [`substitute`] on the factors of [`super::lu::lu_in_place`] solves the system: the residual `‖A x − b‖∞` of the
/// computed solution is at most a small multiple of `ε ‖A‖∞ ‖x‖∞` (partial pivoting is
/// backward stable; for these sizes the growth factor stays small), on a nonsymmetric
/// matrix that needs row exchanges (its diagonal is small).
#[test]
fn substitution_on_the_lu_factors_solves_the_system() {
    for size in [1usize, 3, 27, 45] {
        let entry = |i: usize, j: usize| {
            let (x, y) = (i as f64, j as f64);
            (1.3 * x + 0.7 * y).sin() + if i == j { 1e-3 } else { 0.0 }
        };
        let a = DMatrix::from_fn(size, size, entry);
        let b: Vec<f64> = (0..size).map(|i| (0.4 * i as f64).cos() + 0.5).collect();
        let mut lu = a.clone();
        let mut perm = vec![0; size];
        super::lu::lu_in_place(&mut lu, &mut perm);
        // The pivots exchanged rows (the small diagonal makes them), so the test also
        // covers the permutation's layout.
        assert!(size < 3 || perm.iter().enumerate().any(|(i, &p)| i != p));
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

/// The AVX kernel does the baseline's products, sum and difference in the baseline's
/// order: bit for bit the same on every length (vector part, tail, both, neither), so a
/// step's result does not depend on the processor. Skipped where AVX is absent.
#[test]
#[cfg(target_arch = "x86_64")]
fn the_avx_update_is_the_baseline_bit_for_bit() {
    if !std::arch::is_x86_feature_detected!("avx") {
        return;
    }
    // Entries of mixed signs and magnitudes, so that the rounding of each operation
    // shows (a fused multiply-add, or another order, would change low bits).
    let entry = |i: usize, s: f64| (1.7 * i as f64 + s).sin() * 10f64.powi((i % 7) as i32 - 3);
    for len in 0..=45 {
        let l1: Vec<f64> = (0..len).map(|i| entry(i, 0.3)).collect();
        let l2: Vec<f64> = (0..len).map(|i| entry(i, 1.1)).collect();
        let x: Vec<f64> = (0..len).map(|i| entry(i, 2.9)).collect();
        let (u1, u2) = (0.7316, -1.0 / 3.0);
        let mut baseline = x.clone();
        super::lu::rank_two_update(&mut baseline, &l1, &l2, u1, u2);
        let mut vector = x.clone();
        // SAFETY: AVX was detected above.
        unsafe { super::lu::rank_two_update_avx(&mut vector, &l1, &l2, u1, u2) };
        let bits = |v: &[f64]| v.iter().map(|e| e.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&vector), bits(&baseline), "length {len}");
        // The update did something: the test would catch a kernel that returns early.
        assert!(len == 0 || baseline != x);
    }
}

/// [`super::lu::lu_in_place`] (column-major slices, AVX kernels) against a plain
/// elimination written here on nalgebra's indexing, one pair of pivots at a time with each
/// trailing entry updated as `x − (l₁u₁ + l₂u₂)`: the same factors and permutation bit for
/// bit, for every size from 1 to 50 (odd and even) on matrices whose small diagonal forces
/// row exchanges.
#[test]
fn the_lu_is_the_pairwise_elimination_bit_for_bit() {
    fn pivot(a: &mut DMatrix<f64>, perm: &mut [usize], k: usize) {
        let size = a.nrows();
        let mut p = k;
        for i in k + 1..size {
            if a[(i, k)].abs() > a[(p, k)].abs() {
                p = i;
            }
        }
        if p != k {
            perm.swap(k, p);
            a.swap_rows(k, p);
        }
        let inverse = 1.0 / a[(k, k)];
        for i in k + 1..size {
            a[(i, k)] *= inverse;
        }
    }
    for size in 1..=50 {
        let entry = |i: usize, j: usize| {
            let (x, y) = (i as f64, j as f64);
            (1.3 * x + 0.7 * y).sin() * (1.0 + 0.1 * (x * y).cos())
                + if i == j { 1e-3 } else { 0.0 }
        };
        let a = DMatrix::from_fn(size, size, entry);
        let mut reference = a.clone();
        let mut reference_perm: Vec<usize> = (0..size).collect();
        let mut k = 0;
        while k < size {
            pivot(&mut reference, &mut reference_perm, k);
            if k + 1 == size {
                break;
            }
            let u = reference[(k, k + 1)];
            for i in k + 1..size {
                reference[(i, k + 1)] -= reference[(i, k)] * u;
            }
            pivot(&mut reference, &mut reference_perm, k + 1);
            for c in k + 2..size {
                let u1 = reference[(k, c)];
                let u2 = reference[(k + 1, c)] - reference[(k + 1, k)] * u1;
                reference[(k + 1, c)] = u2;
                for i in k + 2..size {
                    reference[(i, c)] -= reference[(i, k)] * u1 + reference[(i, k + 1)] * u2;
                }
            }
            k += 2;
        }
        let mut lu = a.clone();
        let mut perm = vec![0; size];
        super::lu::lu_in_place(&mut lu, &mut perm);
        assert_eq!(perm, reference_perm, "size {size}");
        assert!(size < 3 || perm.iter().enumerate().any(|(i, &p)| i != p));
        let bits = |m: &DMatrix<f64>| m.iter().map(|e| e.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&lu), bits(&reference), "size {size}");
    }
}

/// The assembly's gradient kernel (`accumulate_gradient`: one component along all nodes
/// at a time, AVX2 where present) is the point-by-point, node-by-node sum it replaced, bit
/// for bit: `(g_x[c] φ_i + g_v[c] φ_i') w_j` summed over the points in order, and the
/// scale `max_j w_j (|g_x|∞ |φ_i| + |g_v|∞ |φ_i'|)`, for D = 3 and 6 and n from 2 to 24
/// (a fused multiply-add or another order would change low bits of these mixed entries).
#[test]
fn the_gradient_kernel_is_the_point_by_point_sum_bit_for_bit() {
    fn check<const D: usize>(n: usize, m: usize) {
        let entry = |i: usize, s: f64| (1.7 * i as f64 + s).sin() * 10f64.powi((i % 7) as i32 - 3);
        let values: Vec<f64> = (0..m * n).map(|i| entry(i, 0.3)).collect();
        let slopes: Vec<f64> = (0..m * n).map(|i| entry(i, 1.1)).collect();
        let weights: Vec<f64> = (0..m).map(|j| 0.1 + entry(j, 2.0).abs()).collect();
        let points: Vec<f64> = (0..m * 2 * D).map(|i| entry(i, 2.9)).collect();
        // The loop the kernel replaced.
        let mut gradient = vec![[0.0f64; D]; n];
        let mut scale = vec![0.0f64; n];
        for j in 0..m {
            let g = &points[2 * D * j..2 * D * (j + 1)];
            let size_x = g[..D].iter().fold(0.0f64, |a, b| a.max(b.abs()));
            let size_v = g[D..].iter().fold(0.0f64, |a, b| a.max(b.abs()));
            let w = weights[j];
            for i in 0..n {
                let (b, s) = (values[j * n + i], slopes[j * n + i]);
                for c in 0..D {
                    gradient[i][c] += (g[c] * b + g[D + c] * s) * w;
                }
                scale[i] = scale[i].max(w * (size_x * b.abs() + size_v * s.abs()));
            }
        }
        let mut by_component = vec![f64::NAN; D * n];
        let mut kernel_scale = vec![f64::NAN; n];
        super::assembly::accumulate_gradient::<D>(
            &mut by_component,
            &mut kernel_scale,
            &points,
            &weights,
            (&values, &slopes),
        );
        for i in 0..n {
            for c in 0..D {
                assert_eq!(
                    by_component[c * n + i].to_bits(),
                    gradient[i][c].to_bits(),
                    "D = {D}, n = {n}, node {i}, component {c}"
                );
            }
            assert_eq!(
                kernel_scale[i].to_bits(),
                scale[i].to_bits(),
                "scale, n = {n}"
            );
        }
    }
    for n in 2..=24 {
        check::<3>(n, n);
        check::<6>(n, n - 1);
    }
}

/// A workspace holding a curve that is not a solution (constant velocity plus a wobble),
/// assembled with its Newton matrix at the step's start `b` with momentum `μ`.
fn assembled_off_the_solution<S: crate::System<3, Group = crate::group::Rotations>>(
    stepper: &StepSolver<'_, S, ChartKind, 3>,
    d: &Discretisation,
) -> (Workspace<Stacked<9>, 3>, SO3, Vector3<f64>) {
    let mu = Vector3::new(2.4, -1.5, 1.52);
    let b = SO3::from_matrix_unchecked(base());
    let work = assembled_along(
        stepper,
        d,
        (&b, &mu),
        Vector3::new(0.5, -0.8, 0.3),
        Vector3::new(0.02, -0.01, 0.03),
    );
    (work, b, mu)
}

/// A workspace holding the curve `ξ(t) = rate t + wobble t²` at the nodes, assembled with
/// its Newton matrix at the step's start `base` with momentum `μ`.
fn assembled_along<S, C, const D: usize>(
    stepper: &StepSolver<'_, S, C, D>,
    d: &Discretisation,
    (base, mu): (&crate::system::ElementOf<S, D>, &SVector<f64, D>),
    rate: SVector<f64, D>,
    wobble: SVector<f64, D>,
) -> WorkspaceOf<S, D>
where
    S: crate::System<D>,
    C: crate::group::GroupChart<S::Group, D>,
{
    let mut work = WorkspaceOf::<S, D>::new(d);
    for (i, t) in d.node_times().iter().enumerate() {
        work.xi[i] = rate * *t + wobble * (t * t);
    }
    work.xi[0] = SVector::zeros();
    stepper.assemble(base, mu, &mut work, true);
    stepper.fill_jacobian(&mut work);
    work
}

/// The exact Newton matrix (both matchings, a configuration-dependent system, every
/// chart) against forward differences of the residual away from the solution; also
/// under a torque, damping and a control input, whose point Jacobians are not symmetric
/// (so that a matrix laid out by the wrong index, its transpose, shows). Forward
/// differences with step √ε·max(1, |z|) are accurate to ~√ε·|F''| ≈ 1e-7 relative.
#[test]
fn exact_newton_matrix_matches_differences_of_the_residual() {
    let forced = crate::Forced::new(
        top(),
        (
            crate::forces::BodyTorque(Vector3::new(0.1, -0.2, 0.05)),
            crate::forces::AngularDamping(0.3),
        ),
    );
    check_newton_matrix(&top(), None, "heavy top");
    // Its points four at a time (crate::jet_lanes).
    check_newton_matrix(
        &crate::RigidBody::new(Inertia::from_paper_jd([1.0, 2.8, 2.0]).unwrap()),
        None,
        "free body",
    );
    check_newton_matrix(
        &forced,
        Some(Vector3::new(0.05, 0.0, -0.03)),
        "heavy top, torque, damping and input",
    );
}

/// [`exact_newton_matrix_matches_differences_of_the_residual`] for one system.
fn check_newton_matrix<S: crate::System<3, Group = crate::group::Rotations>>(
    system: &S,
    forcing: Option<Vector3<f64>>,
    name: &str,
) {
    for chart in ChartKind::ALL {
        for matching in [Matching::Exact, Matching::Paper] {
            let settings = StepSettings::new(0.4, 5)
                .unwrap()
                .with_chart(chart)
                .with_matching(matching);
            let d = Discretisation::new(&settings).unwrap();
            let stepper = StepSolver {
                system,
                chart: &chart,
                settings: &settings,
                d: &d,
                time: 0.0,
                forcing,
                point_inputs: None,
            };
            let (mut work, b, mu) = assembled_off_the_solution(&stepper, &d);
            assert_newton_matrix_near_differences(
                &stepper,
                &b,
                &mu,
                &mut work,
                &format!("{name}, {chart} {matching:?}"),
            );
        }
    }
}

/// The exact Newton matrix in `work` (from [`StepSolver::fill_jacobian`]) within 1e-6 of its
/// largest entry of forward differences of the residual (accurate to ~√ε·|F''| ≈ 1e-7
/// relative).
fn assert_newton_matrix_near_differences<S, C, const D: usize>(
    stepper: &StepSolver<'_, S, C, D>,
    base: &crate::system::ElementOf<S, D>,
    mu: &SVector<f64, D>,
    work: &mut WorkspaceOf<S, D>,
    what: &str,
) where
    S: crate::System<D>,
    C: crate::group::GroupChart<S::Group, D>,
{
    let exact = work.jacobian.clone();
    stepper.fill_jacobian_by_differences(base, mu, work);
    let mut worst = 0.0f64;
    let mut scale = 0.0f64;
    for r in 0..exact.nrows() {
        for c in 0..exact.ncols() {
            worst = worst.max((exact[(r, c)] - work.jacobian[(r, c)]).abs());
            scale = scale.max(exact[(r, c)].abs());
        }
    }
    assert!(worst <= 1e-6 * scale, "{what}: {worst:e} of {scale:e}");
}

/// The exact matching's `w` carried through a move `δ` of the unknowns with the last
/// Newton matrix's `∂w/∂ξ` ([`StepSolver::carry_matching`], which the Newton loop applies
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
        let stepper = StepSolver {
            system: &system,
            chart: &chart,
            settings: &settings,
            d: &d,
            time: 0.0,
            forcing: Some(input),
            point_inputs: None,
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

/// A step solved to be linearised keeps the Hessians of its last assembly (for each system
/// in at least three steps of four: a loop that expected a chord step, or whose last chord
/// step moved more than 64 ulps, leaves the linearisation to assemble them, and it still
/// linearises), and the linearisation formed
/// from them is the one formed from a fresh assembly at the converged unknowns, to
/// rounding: that assembly was at the accepted unknowns or one
/// chord step of at most 64 ulps before them, so the two Newton matrices differ by
/// ~1e-14 relative at most and their solutions by that times the matrix's condition
/// (~1e2 here): 1e-11 allowed (measured: at most 7.3e-15, the orbiting body). Two steps each, the second from the
/// first's end with its curve as the guess. The heavy top under a torque input
/// (configuration terms from ℓ and the force), the free body, and the orbiting body on
/// SE(3) under a wrench (`D` = 6); every chart, two node counts.
#[test]
fn a_linearisation_from_the_kept_hessians_is_the_fresh_one() {
    use crate::group::GroupChart;
    use crate::system::ElementOf;
    fn check<S: crate::System<D>, const D: usize>(
        system: &S,
        forcing: Option<SVector<f64, D>>,
        start: (ElementOf<S, D>, SVector<f64, D>),
        name: &str,
    ) where
        ChartKind: GroupChart<S::Group, D>,
    {
        let (mut kept_steps, mut total) = (0, 0);
        for chart in ChartKind::ALL {
            for n in [5, 8] {
                let settings = StepSettings::new(0.5, n).unwrap().with_chart(chart);
                let d = Discretisation::new(&settings).unwrap();
                let stepper = StepSolver {
                    system,
                    chart: &chart,
                    settings: &settings,
                    d: &d,
                    time: 0.0,
                    forcing,
                    point_inputs: None,
                };
                let mut work: WorkspaceOf<S, D> = Workspace::new(&d);
                work.keep_converged_hessians = true;
                let (mut base, mut mu) = start;
                for step in 0..2 {
                    let outcome = stepper.solve(&base, &mu, &mut work, step, 0.0).unwrap();
                    total += 1;
                    if work.converged_hessians {
                        kept_steps += 1;
                        let kept = stepper.linearize(&base, &mu, &mut work, step).unwrap();
                        // The same linearisation with the points assembled again at the
                        // converged unknowns.
                        work.converged_hessians = false;
                        let fresh = stepper.linearize(&base, &mu, &mut work, step).unwrap();
                        let pairs = [
                            (kept.theta_theta, fresh.theta_theta),
                            (kept.theta_mu, fresh.theta_mu),
                            (kept.mu_theta, fresh.mu_theta),
                            (kept.mu_mu, fresh.mu_mu),
                            (kept.theta_u, fresh.theta_u),
                            (kept.mu_u, fresh.mu_u),
                        ];
                        for (k, f) in pairs {
                            let scale = f.amax().max(1.0);
                            assert!(
                                (k - f).amax() <= 1e-11 * scale,
                                "{name} {chart} n = {n}, step {step}: {:e} of {scale:e}",
                                (k - f).amax()
                            );
                        }
                    } else {
                        // The loop's last assembly was gradient-only (it expected a chord
                        // step) or a last chord step moved more than KEPT_STEP: the
                        // linearisation assembles the converged unknowns itself.
                        assert!(stepper.linearize(&base, &mu, &mut work, step).is_ok());
                    }
                    (base, mu) = (outcome.configuration, outcome.momentum);
                    work.guess_changed();
                }
            }
        }
        // Keeping them is the rule (a step to be linearised asks its last assembly for
        // Hessians), not an accident of the path: at least three steps in four.
        assert!(
            4 * kept_steps >= 3 * total,
            "{name}: Hessians kept in {kept_steps} of {total} steps"
        );
    }
    let free = crate::RigidBody::new(Inertia::from_principal_moments([0.5, 0.9, 0.7]).unwrap());
    let b = SO3::from_matrix_unchecked(base());
    let mu = Vector3::new(0.3, 0.09, -0.28);
    check(
        &top(),
        Some(Vector3::new(0.3, -0.2, 0.1)),
        (b, mu),
        "heavy top, torqued",
    );
    check(&free, None, (b, mu), "free body");
    let orbit = crate::OrbitingBody::new(
        Inertia::from_principal_moments([0.5, 0.9, 0.7]).unwrap(),
        1.0,
        1.0,
    )
    .unwrap();
    let g = lgsvi_lie::SE3::new(
        SO3::exp(&Vector3::new(0.1, 0.2, 0.0)),
        Vector3::new(3.0, 0.0, 0.5),
    );
    let xi = SVector::<f64, 6>::new(0.6, 0.1, -0.4, 0.0, 0.55, 0.05);
    let wrench = SVector::<f64, 6>::new(0.02, 0.0, -0.01, 0.1, 0.05, 0.0);
    check(
        &orbit,
        Some(wrench),
        (g, crate::state::body_momentum(&orbit, 0.0, &g, &xi)),
        "orbiting body, wrench",
    );
}

/// [`exact_newton_matrix_matches_differences_of_the_residual`] on the six-dimensional
/// groups, both matchings, every chart: SE(3)'s points by 3 × 3 blocks
/// (`rotation_translation`) for the free body in space (alone and under an input wrench),
/// the orbiting body (its gravity gradient couples rotation and translation), a force on
/// the centre of mass, and a body whose kinetic energy couples turning and moving; a
/// potential of the user's own (dual numbers); and a three-wheel gyrostat on SO(3) × ℝ³.
/// Forward differences with step √ε·max(1, |z|) are accurate to ~1e-7 relative; an entry
/// put in the wrong place or a term left out is off by the size of the entries.
#[test]
fn exact_newton_matrix_on_six_dimensional_groups_matches_differences() {
    use crate::system::ElementOf;
    use lgsvi_lie::SE3;
    fn check<S, C>(
        system: &S,
        chart: C,
        base: &ElementOf<S, 6>,
        forcing: Option<SVector<f64, 6>>,
        name: &str,
    ) where
        S: crate::System<6>,
        C: crate::group::GroupChart<S::Group, 6> + std::fmt::Debug,
    {
        for matching in [Matching::Exact, Matching::Paper] {
            let settings = StepSettings::new(0.4, 5).unwrap().with_matching(matching);
            let d = Discretisation::new(&settings).unwrap();
            let stepper = StepSolver {
                system,
                chart: &chart,
                settings: &settings,
                d: &d,
                time: 0.3,
                forcing,
                point_inputs: None,
            };
            let mu = SVector::<f64, 6>::new(0.4, -0.5, 0.52, 0.3, 1.1, -0.2);
            let mut work = assembled_along(
                &stepper,
                &d,
                (base, &mu),
                SVector::<f64, 6>::new(0.5, -0.8, 0.3, 0.2, 0.55, -0.1),
                SVector::<f64, 6>::new(0.02, -0.01, 0.03, -0.02, 0.01, 0.04),
            );
            assert_newton_matrix_near_differences(
                &stepper,
                base,
                &mu,
                &mut work,
                &format!("{name}, {chart:?} {matching:?}"),
            );
        }
    }
    /// A spring on the centre of mass and a dipole along body x in a uniform field.
    struct Spring;
    impl crate::FieldPotential for Spring {
        fn potential<T: RealField + Copy>(&self, _t: f64, r: &Matrix3<T>, x: &Vector3<T>) -> T {
            x.norm_squared() * nalgebra::convert::<f64, T>(0.4) - r[(2, 0)]
        }
    }
    let inertia = Inertia::from_principal_moments([0.5, 0.9, 0.7]).unwrap();
    let place = SE3::new(
        SO3::exp(&Vector3::new(0.3, -0.7, 0.2)),
        Vector3::new(2.0, -1.0, 0.5),
    );
    let free = crate::FreeBody::new(inertia, 1.3).unwrap();
    let orbit = crate::OrbitingBody::new(inertia, 1.0, 2.0).unwrap();
    let pushed = crate::Forced::new(
        free,
        crate::forces::SpaceForce(Vector3::new(0.1, -0.3, 0.2)),
    );
    let field = crate::BodyInField::new(inertia, 1.3, Spring).unwrap();
    let craft = crate::gyrostat::Gyrostat::new(
        Matrix3::from_diagonal(&Vector3::new(1.0, 1.2, 0.8)),
        [Vector3::x(), Vector3::y(), Vector3::z()],
        [0.05, 0.04, 0.06],
    )
    .unwrap();
    let craft_at = crate::gyrostat::BodyWheels {
        attitude: SO3::exp(&Vector3::new(0.3, -0.7, 0.2)),
        wheels: Vector3::new(0.1, -0.4, 2.0),
    };
    let wrench = SVector::<f64, 6>::new(0.02, 0.0, -0.01, 0.1, 0.05, 0.0);
    for chart in ChartKind::ALL {
        check(&free, chart, &place, None, "free body in space");
        check(
            &free,
            chart,
            &place,
            Some(wrench),
            "free body in space, input",
        );
        check(&orbit, chart, &place, None, "orbiting body");
        check(&pushed, chart, &place, None, "space force");
        check(&field, chart, &place, None, "potential of the user's own");
        check(
            &whole_point::CoupledSe3,
            chart,
            &place,
            None,
            "coupled SE(3)",
        );
        check(&craft, chart, &craft_at, None, "gyrostat");
    }
}

/// A system may hand the chart's terms back from some assemblies and not others (the
/// trait reads `transport` only as a point hands it back): here only from those with
/// Hessians. A gradient-only assembly at other unknowns must then read the chart at its
/// own points, not the terms an earlier assembly left at another curve: its matching `w`
/// is a fresh workspace's bit for bit (the same chart calls on the same points). Reading
/// the earlier curve's `Φ(x_j)` instead moves `w` by about the curves' distance, 0.1.
#[test]
fn a_point_that_hands_nothing_back_leaves_no_stale_transport() {
    use crate::group::Rotations;
    use crate::point::{GaussPoint, PointTransport};
    struct FromHessiansOnly(HeavyTop);
    impl crate::System<3> for FromHessiansOnly {
        type Group = Rotations;
        fn lagrangian<T: RealField + Copy>(&self, _t: f64, g: &SO3<T>, w: &Vector3<T>) -> T {
            Lagrangian::lagrangian(&self.0, g.matrix(), w)
        }
        fn point_derivatives<C: crate::group::GroupChart<Rotations, 3>>(
            &self,
            chart: &C,
            point: &GaussPoint<'_, Rotations, 3>,
            out: &mut Stacked<9>,
        ) -> bool {
            crate::System::<3>::point_derivatives(&self.0, chart, point, out)
        }
        fn point_derivatives_and_transport<C: crate::group::GroupChart<Rotations, 3>>(
            &self,
            chart: &C,
            point: &GaussPoint<'_, Rotations, 3>,
            out: &mut Stacked<9>,
            transport: &mut Option<PointTransport<3>>,
        ) -> bool {
            if point.with_hessian {
                crate::System::<3>::point_derivatives_and_transport(
                    &self.0, chart, point, out, transport,
                )
            } else {
                crate::System::<3>::point_derivatives(&self.0, chart, point, out)
            }
        }
    }
    let system = FromHessiansOnly(top());
    let settings = StepSettings::new(0.4, 5).unwrap();
    let d = Discretisation::new(&settings).unwrap();
    let chart = ChartKind::Exp;
    let stepper = StepSolver {
        system: &system,
        chart: &chart,
        settings: &settings,
        d: &d,
        time: 0.0,
        forcing: None,
        point_inputs: None,
    };
    let b = SO3::from_matrix_unchecked(base());
    let mu = Vector3::new(2.4, -1.5, 1.52);
    // An assembly with Hessians along one curve: the points hand their terms back.
    let mut work = assembled_along(
        &stepper,
        &d,
        (&b, &mu),
        Vector3::new(0.5, -0.8, 0.3),
        Vector3::new(0.02, -0.01, 0.03),
    );
    assert!(work.transports.iter().all(Option::is_some));
    // Then a gradient-only one along another, in that workspace and in a fresh one.
    let other = |xi: &mut Vec<Vector3<f64>>| {
        for (i, t) in d.node_times().iter().enumerate() {
            xi[i] = Vector3::new(0.7, -0.6, 0.45) * *t;
        }
        xi[0] = Vector3::zeros();
    };
    other(&mut work.xi);
    stepper.assemble(&b, &mu, &mut work, false);
    let mut fresh = Workspace::<Stacked<9>, 3>::new(&d);
    other(&mut fresh.xi);
    stepper.assemble(&b, &mu, &mut fresh, false);
    for c in 0..3 {
        assert_eq!(
            work.matching.w[c].to_bits(),
            fresh.matching.w[c].to_bits(),
            "w[{c}]: {} against {}",
            work.matching.w[c],
            fresh.matching.w[c]
        );
    }
}
