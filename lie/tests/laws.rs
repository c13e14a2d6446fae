//! The law suite, written once and run for every group (SO(3), SE(3)), every chart (exp,
//! Cayley, the paper's unscaled Cayley, and the run-time `ChartKind`), and both scalar
//! types (`f64`, and `Dual64` for the group laws). Run with `--nocapture` for the coverage
//! table.

mod common;

use common::{dual_vector, max_abs, Components, Rng, EPS};
use lgsvi_lie::{
    CayleyChart, Chart, ChartKind, ExpChart, LieGroup, NaturalChart, UnscaledCayleyChart, SE3, SO3,
};
use nalgebra::{SMatrix, SVector, Vector3};
use num_dual::Dual64;
use std::sync::Mutex;

static COVERAGE: Mutex<Vec<String>> = Mutex::new(Vec::new());

fn record(line: String) {
    COVERAGE.lock().unwrap().push(line);
}

/// Group axioms and the structure maps. Elements are O(1) (rotations, translations ≤ 2),
/// so every identity below holds to a small multiple of ε: 64ε covers the few products
/// of 3×3/4×4/6×6 matrices each side involves.
fn group_laws<G, T, const N: usize, const M: usize>(elements: &[G], tangents: &[SVector<T, N>])
where
    T: Components,
    G: LieGroup<
        Scalar = T,
        Tangent = SVector<T, N>,
        Jacobian = SMatrix<T, N, N>,
        Matrix = SMatrix<T, M, M>,
        Point = Vector3<T>,
    >,
{
    let tol = 64.0 * EPS;
    let e = G::identity();
    for a in elements {
        assert!(max_abs(&(a.compose(&e).to_matrix() - a.to_matrix())) <= tol);
        assert!(max_abs(&(e.compose(a).to_matrix() - a.to_matrix())) <= tol);
        assert!(max_abs(&(a.compose(&a.inverse()).to_matrix() - e.to_matrix())) <= tol);
        for b in elements {
            // Homomorphism into matrices.
            let ab = a.compose(b);
            assert!(max_abs(&(ab.to_matrix() - a.to_matrix() * b.to_matrix())) <= tol);
            for c in elements.iter().take(3) {
                let left = ab.compose(c).to_matrix();
                let right = a.compose(&b.compose(c)).to_matrix();
                assert!(max_abs(&(left - right)) <= tol, "associativity");
            }
            let p = Vector3::new(T::lift(0.3), T::lift(-1.1), T::lift(2.0));
            assert!(max_abs(&(ab.act(&p) - a.act(&b.act(&p)))) <= tol * 4.0);
        }
        let a_mat = a.to_matrix();
        let a_inv_mat = a.inverse().to_matrix();
        for xi in tangents {
            assert!(max_abs(&(G::vee(&G::hat(xi)) - xi)) == 0.0, "vee ∘ hat");
            // Ad rebuilt from hat/vee: (Ad_g ξ)^ = g ξ^ g⁻¹.
            let conj = G::vee(&(a_mat * G::hat(xi) * a_inv_mat));
            assert!(max_abs(&(a.adjoint() * xi - conj)) <= tol * 4.0, "adjoint");
            // The coadjoint action preserves the pairing: ⟨Ad*_{g⁻¹}μ, Ad_g ξ⟩ = ⟨μ, ξ⟩.
            for mu in tangents.iter().take(3) {
                let lhs = a.coadjoint_action(mu).dot(&(a.adjoint() * xi));
                assert!(
                    (lhs - mu.dot(xi))
                        .components()
                        .iter()
                        .all(|d| d.abs() <= tol * 16.0),
                    "coadjoint"
                );
            }
        }
        for xi in tangents {
            for eta in tangents {
                let bracket = G::hat(xi) * G::hat(eta) - G::hat(eta) * G::hat(xi);
                let ad = G::small_adjoint(xi) * eta;
                assert!(
                    max_abs(&(ad - G::vee(&bracket))) <= tol * 4.0,
                    "small adjoint"
                );
            }
        }
    }
    record(format!(
        "{:<6} {:<16} {:<7} group laws",
        G::NAME,
        "-",
        T::NAME
    ));
}

/// Chart laws on f64, with the differentials checked against automatic differentiation
/// (the same chart code run on `Dual64`) and against central differences.
fn chart_laws<G, GD, C, const N: usize, const M: usize>(
    chart: C,
    xis: &[SVector<f64, N>],
    bases: &[G],
) where
    G: LieGroup<
        Scalar = f64,
        Tangent = SVector<f64, N>,
        Jacobian = SMatrix<f64, N, N>,
        Matrix = SMatrix<f64, M, M>,
    >,
    GD: LieGroup<Scalar = Dual64, Tangent = SVector<Dual64, N>, Matrix = SMatrix<Dual64, M, M>>,
    C: Chart<G> + Chart<GD> + Copy,
{
    let name = Chart::<G>::name(&chart);
    let identity = G::identity().to_matrix();
    let zero = SVector::<f64, N>::zeros();
    let at_zero: G = chart.to_group(&zero);
    assert!(
        max_abs(&(at_zero.to_matrix() - identity)) == 0.0,
        "Φ(0) = e"
    );
    let mut rng = Rng::new(7);
    let mut worst_ad = 0.0f64;
    let mut worst_fd = 0.0f64;
    for xi in xis {
        let g: G = chart.to_group(xi);
        let g_inv = g.inverse().to_matrix();
        // Φ⁻¹(Φ(ξ)) = ξ. Conditioning: the chart vectors here have |ξ| ≤ 3, where Φ⁻¹ has
        // derivative ≤ ~4; 256ε|ξ| covers it.
        let back = chart.to_algebra(&g).expect("inside the chart");
        assert!(
            (back - xi).amax() <= 256.0 * EPS * (1.0 + xi.norm()),
            "{name}: Φ⁻¹Φ(ξ) = {back:?}, ξ = {xi:?}"
        );
        let a = Chart::<G>::left_differential(&chart, xi);
        let b = Chart::<G>::right_differential(&chart, xi);
        let a_inv = Chart::<G>::left_differential_inverse(&chart, xi).unwrap();
        let b_inv = Chart::<G>::right_differential_inverse(&chart, xi).unwrap();
        let id = SMatrix::<f64, N, N>::identity();
        // A A⁻¹ = I to κ(A)·ε; κ ≤ ~50 for these ξ.
        assert!((a * a_inv - id).amax() <= 1024.0 * EPS, "{name}: A A⁻¹");
        assert!((b * b_inv - id).amax() <= 1024.0 * EPS, "{name}: B B⁻¹");
        for _ in 0..3 {
            let v = rng.vector::<N>(1.0);
            // Automatic differentiation: the ε-part of Φ(ξ + εv) is DΦ(ξ)[v].
            let gd: GD = chart.to_group(&dual_vector(xi, &v));
            let d_phi = gd.to_matrix().map(|x| x.eps);
            let left_ad = G::vee(&(g_inv * d_phi));
            let right_ad = G::vee(&(d_phi * g_inv));
            let scale = 1.0 + a.amax().max(b.amax());
            let err_ad = (left_ad - a * v).amax().max((right_ad - b * v).amax()) / scale;
            // Both sides are exact up to rounding in O(1)-sized products: 256ε.
            assert!(
                err_ad <= 256.0 * EPS,
                "{name}: A, B vs AD at {xi:?}: {err_ad:e}"
            );
            worst_ad = worst_ad.max(err_ad);
            // Central differences, h = 1e-5: truncation h²|Φ'''|/6 ≲ 1e-9, rounding ε/h ≈
            // 2e-11.
            let h = 1e-5;
            let plus: G = chart.to_group(&(xi + v * h));
            let minus: G = chart.to_group(&(xi - v * h));
            let fd = (plus.to_matrix() - minus.to_matrix()) / (2.0 * h);
            let err_fd = (G::vee(&(g_inv * fd)) - a * v)
                .amax()
                .max((G::vee(&(fd * g_inv)) - b * v).amax())
                / scale;
            assert!(
                err_fd <= 1e-8,
                "{name}: A, B vs central differences: {err_fd:e}"
            );
            worst_fd = worst_fd.max(err_fd);
        }
        // Natural-chart equivariance: φ_{hg}(h g') = φ_g(g').
        for base in bases {
            for k in bases.iter().take(2) {
                let g_prime = base.compose(&g);
                let here = NaturalChart::new(base.clone(), chart)
                    .to_algebra(&g_prime)
                    .unwrap();
                let moved = NaturalChart::new(k.compose(base), chart)
                    .to_algebra(&k.compose(&g_prime))
                    .unwrap();
                assert!(
                    (here - moved).amax() <= 1024.0 * EPS * (1.0 + xi.norm()),
                    "{name}: equivariance"
                );
            }
        }
    }
    record(format!(
        "{:<6} {:<16} {:<7} chart laws; A, B vs AD (Dual64) worst {:.1e}, vs central differences worst {:.1e}",
        G::NAME, name, "f64", worst_ad, worst_fd
    ));
}

fn so3_samples(rng: &mut Rng) -> Vec<Vector3<f64>> {
    let mut xs: Vec<Vector3<f64>> = (0..8).map(|_| rng.vector::<3>(1.5)).collect();
    xs.push(Vector3::zeros());
    xs.push(Vector3::new(1e-9, -2e-9, 0.5e-9));
    xs.push(Vector3::new(0.0, 0.0, 1.9)); // just below the series threshold θ = 2
    xs.push(Vector3::new(0.0, 2.1, 0.0)); // just above it
    xs.push(Vector3::new(1.0, 1.0, 1.0) * (2.9 / 3f64.sqrt())); // near π for exp
    xs
}

#[test]
fn so3_group_laws_f64_and_dual() {
    let mut rng = Rng::new(1);
    let elements: Vec<SO3> = so3_samples(&mut rng).iter().map(SO3::exp).collect();
    let tangents = so3_samples(&mut rng);
    group_laws(&elements, &tangents);
    // The same laws with dual numbers: elements carrying derivatives.
    let dual_elements: Vec<SO3<Dual64>> = so3_samples(&mut rng)
        .iter()
        .map(|x| SO3::exp(&dual_vector(x, &rng.vector::<3>(1.0))))
        .collect();
    let dual_tangents: Vec<SVector<Dual64, 3>> = tangents
        .iter()
        .map(|x| dual_vector(x, &rng.vector::<3>(1.0)))
        .collect();
    group_laws(&dual_elements, &dual_tangents);
}

#[test]
fn se3_group_laws_f64_and_dual() {
    let mut rng = Rng::new(2);
    let xis: Vec<SVector<f64, 6>> = (0..8).map(|_| rng.vector::<6>(1.5)).collect();
    let elements: Vec<SE3> = xis.iter().map(SE3::exp).collect();
    group_laws(&elements, &xis);
    let dual_elements: Vec<SE3<Dual64>> = xis
        .iter()
        .map(|x| SE3::exp(&dual_vector(x, &rng.vector::<6>(1.0))))
        .collect();
    let dual_tangents: Vec<SVector<Dual64, 6>> = xis
        .iter()
        .map(|x| dual_vector(x, &rng.vector::<6>(1.0)))
        .collect();
    group_laws(&dual_elements, &dual_tangents);
}

fn chart_samples_so3(rng: &mut Rng) -> Vec<Vector3<f64>> {
    // |ξ| ≤ 3 < π keeps Φ⁻¹ defined for every chart (Cayley images are always below π).
    let mut xs = so3_samples(rng);
    xs.retain(|x| x.norm() < 3.0);
    xs
}

#[test]
fn so3_chart_laws() {
    let mut rng = Rng::new(3);
    let xis = chart_samples_so3(&mut rng);
    let bases: Vec<SO3> = (0..3).map(|_| SO3::exp(&rng.vector::<3>(2.0))).collect();
    chart_laws::<SO3, SO3<Dual64>, _, 3, 3>(ExpChart, &xis, &bases);
    chart_laws::<SO3, SO3<Dual64>, _, 3, 3>(CayleyChart, &xis, &bases);
    chart_laws::<SO3, SO3<Dual64>, _, 3, 3>(UnscaledCayleyChart, &xis, &bases);
    for kind in ChartKind::ALL {
        chart_laws::<SO3, SO3<Dual64>, _, 3, 3>(kind, &xis, &bases);
    }
}

#[test]
fn se3_chart_laws() {
    let mut rng = Rng::new(4);
    let mut xis: Vec<SVector<f64, 6>> = chart_samples_so3(&mut rng)
        .iter()
        .map(|w| {
            let v = rng.vector::<3>(2.0);
            SVector::<f64, 6>::new(w.x, w.y, w.z, v.x, v.y, v.z)
        })
        .collect();
    xis.push(SVector::<f64, 6>::new(0.0, 0.0, 0.0, 1.0, -2.0, 0.5)); // pure translation
    let bases: Vec<SE3> = (0..3).map(|_| SE3::exp(&rng.vector::<6>(2.0))).collect();
    chart_laws::<SE3, SE3<Dual64>, _, 6, 4>(ExpChart, &xis, &bases);
    chart_laws::<SE3, SE3<Dual64>, _, 6, 4>(CayleyChart, &xis, &bases);
    chart_laws::<SE3, SE3<Dual64>, _, 6, 4>(UnscaledCayleyChart, &xis, &bases);
    for kind in ChartKind::ALL {
        chart_laws::<SE3, SE3<Dual64>, _, 6, 4>(kind, &xis, &bases);
    }
}

#[test]
fn unscaled_cayley_is_the_standard_one_at_minus_twice_the_vector() {
    // The paper's Φ(q) = (I − q̂)(I + q̂)⁻¹ rotates by −2 atan|q| about q.
    let q = Vector3::new(0.2, -0.4, 0.1);
    let unscaled: SO3 = UnscaledCayleyChart.to_group(&q);
    let standard: SO3 = CayleyChart.to_group(&(-2.0 * q));
    assert!((unscaled.matrix() - standard.matrix()).amax() <= 4.0 * EPS);
    let angle = -2.0 * q.norm().atan();
    let by_exp = SO3::exp(&(q.normalize() * angle));
    assert!((unscaled.matrix() - by_exp.matrix()).amax() <= 8.0 * EPS);
    // The closed form of the left-trivialised differential.
    let a = lgsvi_lie::So3Chart::rotation_left_differential(&UnscaledCayleyChart, &q);
    let expected = (nalgebra::Matrix3::identity() + lgsvi_lie::so3::hat(&q))
        * (-2.0 / (1.0 + q.norm_squared()));
    assert!((a - expected).amax() <= 4.0 * EPS);
}

#[test]
fn zzz_print_coverage() {
    // Runs last in alphabetical order when tests run single-threaded; with threads the
    // table may be partial, which only affects the printout.
    std::thread::sleep(std::time::Duration::from_millis(200));
    for line in COVERAGE.lock().unwrap().iter() {
        println!("{line}");
    }
}

/// The exported law suite (`lgsvi_lie::laws`), the one a user's group runs, on the built-in
/// groups and every chart: the same laws as above on `f64`, from outside the crate. The
/// exact laws hold to a few ε of the examples' scale (64ε leaves the products' rounding
/// room); the differentiating ones to the central difference's ~1e-10 (held to 1e-6).
#[test]
fn the_exported_law_suite_passes_on_so3_and_se3() {
    use lgsvi_lie::laws::{chart_laws, group_laws};
    let mut rng = Rng::new(31);
    let so3: Vec<SO3> = (0..4).map(|_| SO3::exp(&rng.vector::<3>(1.2))).collect();
    let w: Vec<SVector<f64, 3>> = (0..4).map(|_| rng.vector::<3>(1.0)).collect();
    let report = group_laws(&so3, &w, 64.0 * EPS).unwrap();
    assert_eq!(report.len(), 12);
    let se3: Vec<SE3> = (0..4).map(|_| SE3::exp(&rng.vector::<6>(1.0))).collect();
    let xi: Vec<SVector<f64, 6>> = (0..4).map(|_| rng.vector::<6>(1.0)).collect();
    group_laws(&se3, &xi, 64.0 * EPS).unwrap();
    for kind in ChartKind::ALL {
        chart_laws::<SO3, _, 3>(&kind, &w, 64.0 * EPS).unwrap();
        chart_laws::<SE3, _, 6>(&kind, &xi, 64.0 * EPS).unwrap();
    }
    // A law that does not hold is reported with its size: a "chart" whose differential is
    // off by a factor.
    #[derive(Clone, Copy)]
    struct Wrong;
    impl Chart<SO3> for Wrong {
        fn name(&self) -> &'static str {
            "wrong"
        }
        fn to_group(&self, xi: &Vector3<f64>) -> SO3 {
            ExpChart.to_group(xi)
        }
        fn to_algebra(&self, g: &SO3) -> Result<Vector3<f64>, lgsvi_lie::LieError> {
            ExpChart.to_algebra(g)
        }
        fn check_domain(&self, xi: &Vector3<f64>) -> Result<(), lgsvi_lie::LieError> {
            Chart::<SO3>::check_domain(&ExpChart, xi)
        }
        fn left_differential(&self, xi: &Vector3<f64>) -> SMatrix<f64, 3, 3> {
            Chart::<SO3>::left_differential(&ExpChart, xi) * 1.001
        }
        fn left_differential_inverse(
            &self,
            xi: &Vector3<f64>,
        ) -> Result<SMatrix<f64, 3, 3>, lgsvi_lie::LieError> {
            Chart::<SO3>::left_differential_inverse(&ExpChart, xi)
        }
        fn right_differential(&self, xi: &Vector3<f64>) -> SMatrix<f64, 3, 3> {
            Chart::<SO3>::right_differential(&ExpChart, xi)
        }
        fn right_differential_inverse(
            &self,
            xi: &Vector3<f64>,
        ) -> Result<SMatrix<f64, 3, 3>, lgsvi_lie::LieError> {
            Chart::<SO3>::right_differential_inverse(&ExpChart, xi)
        }
    }
    let violation = chart_laws::<SO3, _, 3>(&Wrong, &w, 64.0 * EPS).unwrap_err();
    assert_eq!(violation.law, "left differential");
    assert!(violation.error > 1e-4, "{violation}");
}
