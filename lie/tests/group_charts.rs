//! The closed-form chart derivatives and transports of the built-in charts (SO(3); SE(3)'s
//! rotation–translation chart; SO(3) × ℝᴷ) against the dual-number derivatives and the
//! formed group elements of the same charts, and the chart law suite on every built-in
//! group and chart.

use lgsvi_lie::laws::group_chart_laws;
use lgsvi_lie::product::BodyAndWheels;
use lgsvi_lie::{
    dual_number_derivatives, ChartDerivatives, ChartKind, ConfigurationGroup, GroupChart, LieGroup,
    RigidMotions, Rotations, Screw,
};
use nalgebra::{SMatrix, SVector};

/// `Ad_{Φ(x)⁻¹}ᵀ`, formed from the group element.
fn formed_transport<G: ConfigurationGroup<D>, const D: usize>(
    chart: &impl GroupChart<G, D>,
    x: &SVector<f64, D>,
) -> SMatrix<f64, D, D> {
    chart.to_group(x).inverse().adjoint().transpose()
}

/// The rotation–translation chart's closed-form derivatives on SE(3) against the
/// dual-number ones of the same chart (`dual_number_derivatives`), every chart, points from
/// `x = 0` to large rotations, each contraction with arbitrary vectors. Exact up to
/// rounding: 1e-13 relative to the largest entry.
#[test]
fn rotation_translation_chart_derivatives_match_dual_numbers() {
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

/// The SO(3) charts' closed-form derivatives, the SO(3) × ℝᴷ charts' (the gyrostat's
/// group, `K = 1…4`) and SE(3)'s rotation–translation chart's, and their transport
/// `Ad_{Φ(x)⁻¹}ᵀ p`, against the dual-number derivatives and the formed `Φ(x)` of the
/// same chart, every chart, points from `x = 0` to large rotations; the transport's
/// matrix with `A(x)` ([`GroupChart::transport_and_differential`]) against both
/// formed apart. Exact up to rounding: 1e-13 relative to the largest entry (1e-14 for the
/// transport and `A`, single products of the Rodrigues coefficients).
#[test]
fn attitude_times_vector_chart_derivatives_match_dual_numbers() {
    fn check<G: ConfigurationGroup<D>, const D: usize>()
    where
        ChartKind: GroupChart<G, D>,
    {
        let at = |scale: f64, shift: f64| {
            SVector::<f64, D>::from_fn(|i, _| scale * (1.3 * i as f64 + shift).sin())
        };
        let (g, mu, v) = (at(1.0, 0.2), at(1.2, 1.1), at(0.9, 2.3));
        for chart in ChartKind::ALL {
            for x in [at(0.0, 0.0), at(0.3, 0.5), at(1.6, 0.9)] {
                let read = |d: &dyn ChartDerivatives<D>| {
                    [
                        d.differential(),
                        d.differential_times(&v),
                        d.transpose_times(&g),
                        d.second(&mu, &v),
                    ]
                };
                let fast = GroupChart::<G, D>::with_derivatives(&chart, &x, true, read);
                let slow = dual_number_derivatives::<G, _, _, D>(&chart, &x, read);
                for (k, (f, s)) in fast.iter().zip(&slow).enumerate() {
                    let scale = s.amax().max(1.0);
                    assert!(
                        (f - s).amax() <= 1e-13 * scale,
                        "{} {chart} at {x:?}, contraction {k}: {:e}",
                        G::NAME,
                        (f - s).amax()
                    );
                }
                let first = GroupChart::<G, D>::with_derivatives(&chart, &x, false, read);
                for k in 0..3 {
                    assert!((first[k] - slow[k]).amax() <= 1e-13 * slow[k].amax().max(1.0));
                }
                let moved = GroupChart::<G, D>::coadjoint_to_start(&chart, &x, &g);
                let formed = formed_transport::<G, D>(&chart, &x) * g;
                assert!((moved - formed).amax() <= 1e-14 * formed.amax().max(1.0));
                // The transport's matrix and A together, against both formed apart.
                let (transport, a) = GroupChart::<G, D>::transport_and_differential(&chart, &x);
                let apart = formed_transport::<G, D>(&chart, &x);
                let a_apart = GroupChart::<G, D>::left_differential(&chart, &x);
                assert!(
                    (transport - apart).amax() <= 1e-14 * apart.amax().max(1.0)
                        && (a - a_apart).amax() <= 1e-14 * a_apart.amax().max(1.0),
                    "{} {chart} at {x:?}: transport and A together",
                    G::NAME
                );
            }
        }
    }
    check::<Rotations, 3>();
    // SE(3)'s rotation–translation chart through the same checks.
    check::<RigidMotions, 6>();
    check::<BodyAndWheels<1>, 4>();
    check::<BodyAndWheels<2>, 5>();
    check::<BodyAndWheels<3>, 6>();
    check::<BodyAndWheels<4>, 7>();
}

/// Every built-in group with every chart passes the chart law suite, at points from the
/// origin to rotations of 2.5 rad (inside every chart's domain and below the half turn
/// where `Φ⁻¹` changes branch). The consistency laws compare two exact routes, each a few
/// products of Rodrigues coefficients, relative to the reference: the suite's `64 ×
/// tolerance` at 1e-14 is 6.4e-13, above the few ulps that the summation orders leave; the
/// differenced laws use the suite's own 1e-6.
#[test]
fn every_built_in_chart_passes_the_chart_laws() {
    fn points<const D: usize>() -> Vec<SVector<f64, D>> {
        [0.0, 0.3, 1.6, 2.2]
            .iter()
            .map(|&scale| SVector::<f64, D>::from_fn(|i, _| scale * (1.3 * i as f64 + 0.7).sin()))
            .collect()
    }
    fn check<G: ConfigurationGroup<D>, const D: usize>(chart: impl GroupChart<G, D>)
    where
        G::Element<f64>: lgsvi_lie::ExponentialMap,
    {
        // Cayley charts reach a half turn: keep the examples inside each chart's domain.
        let inside: Vec<_> = points::<D>()
            .into_iter()
            .filter(|x| {
                chart.check_domain(x).is_ok()
                    && x.fixed_rows::<3>(0).norm()
                        < 0.9 * chart.max_rotation_angle().min(std::f64::consts::PI)
            })
            .collect();
        // Every chart keeps every point: the largest turns by 2.48 rad.
        assert_eq!(inside.len(), 4, "{}", chart.name());
        let report = group_chart_laws::<G, _, D>(&chart, &inside, 1e-14)
            .unwrap_or_else(|e| panic!("{} {}: {e}", G::NAME, chart.name()));
        assert!(report.iter().any(|(law, _)| *law == "chart derivatives"));
    }
    for chart in ChartKind::ALL {
        check::<Rotations, 3>(chart);
        check::<RigidMotions, 6>(chart);
        check::<RigidMotions, 6>(Screw(chart));
        check::<BodyAndWheels<1>, 4>(chart);
        check::<BodyAndWheels<2>, 5>(chart);
        check::<BodyAndWheels<3>, 6>(chart);
        check::<BodyAndWheels<4>, 7>(chart);
    }
}

/// Every built-in group passes the marker's laws (lift, `exp` to second order, the
/// coadjoint generator's closed form, elements on the group) on elements from the identity
/// to a turn of 2.5 rad, at the exact allowance 1e-14 × scale (the closed forms are a few
/// products each); "exp to second order" holds their true exponentials to rounding and
/// their second-order `exp` to its third order (the suite's 1e-9 at `|ζ| = 1e-3`).
#[test]
fn every_built_in_group_passes_the_marker_laws() {
    use lgsvi_lie::laws::configuration_group_laws;
    use lgsvi_lie::product::BodyWheels;
    use lgsvi_lie::{ExponentialMap, SE3, SO3};
    use nalgebra::Vector3;
    fn tangents<const D: usize>() -> Vec<SVector<f64, D>> {
        (0..3)
            .map(|k| SVector::from_fn(|i, _| (1.3 * i as f64 + 0.7 * k as f64).sin()))
            .collect()
    }
    let rotations: Vec<SO3> = [0.0, 0.4, 2.5]
        .iter()
        .map(|&a| SO3::exp(&(Vector3::new(0.48, -0.6, 0.64) * a)))
        .collect();
    let report = configuration_group_laws::<Rotations, 3>(&rotations, &tangents(), 1e-14).unwrap();
    assert_eq!(report.len(), 5);
    let motions: Vec<SE3> = rotations
        .iter()
        .map(|r| SE3::new(*r, Vector3::new(1.0, -2.0, 0.5)))
        .collect();
    configuration_group_laws::<RigidMotions, 6>(&motions, &tangents(), 1e-14).unwrap();
    fn product<const K: usize, const D: usize>(rotations: &[SO3])
    where
        BodyAndWheels<K>: ConfigurationGroup<D, Element<f64> = BodyWheels<f64, K>>,
        BodyWheels<f64, K>: ExponentialMap,
    {
        let elements: Vec<BodyWheels<f64, K>> = rotations
            .iter()
            .map(|r| BodyWheels {
                attitude: *r,
                wheels: SVector::from_fn(|i, _| 0.5 - i as f64),
            })
            .collect();
        configuration_group_laws::<BodyAndWheels<K>, D>(&elements, &tangents::<D>(), 1e-14)
            .unwrap();
    }
    product::<1, 4>(&rotations);
    product::<2, 5>(&rotations);
    product::<3, 6>(&rotations);
    product::<4, 7>(&rotations);
}

/// The laws fail where they should: a chart whose closed-form derivatives of `A` are off by
/// a relative 1e-9 (the exp chart with its Rodrigues coefficients of `A` scaled, so that
/// `A` itself and the dual-number reference stay exp's), one whose closed form is NaN, and
/// a marker whose `exp` is wrong at second order.
#[test]
fn the_laws_catch_wrong_closed_forms() {
    use lgsvi_lie::laws::configuration_group_laws;
    use lgsvi_lie::{ExpChart, LieError, RodriguesCoefficients, So3Chart, SO3};
    use nalgebra::{Matrix3, RealField, Vector3};

    #[derive(Debug, Clone, Copy)]
    struct Skewed(f64);
    impl So3Chart for Skewed {
        fn chart_name(&self) -> &'static str {
            "skewed"
        }
        fn rotation_matrix<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
            ExpChart.rotation_matrix(w)
        }
        fn rotation_vector<T: RealField + Copy>(
            &self,
            r: &Matrix3<T>,
        ) -> Result<Vector3<T>, LieError> {
            ExpChart.rotation_vector(r)
        }
        fn check_rotation_domain<T: RealField + Copy>(
            &self,
            w: &Vector3<T>,
        ) -> Result<(), LieError> {
            ExpChart.check_rotation_domain(w)
        }
        fn rotation_left_differential<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
            ExpChart.rotation_left_differential(w)
        }
        fn rotation_left_differential_inverse<T: RealField + Copy>(
            &self,
            w: &Vector3<T>,
        ) -> Matrix3<T> {
            ExpChart.rotation_left_differential_inverse(w)
        }
        fn rotation_right_differential<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
            ExpChart.rotation_right_differential(w)
        }
        fn rotation_right_differential_inverse<T: RealField + Copy>(
            &self,
            w: &Vector3<T>,
        ) -> Matrix3<T> {
            ExpChart.rotation_right_differential_inverse(w)
        }
        fn translation_map<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
            ExpChart.translation_map(w)
        }
        fn translation_map_inverse<T: RealField + Copy>(&self, w: &Vector3<T>) -> Matrix3<T> {
            ExpChart.translation_map_inverse(w)
        }
        fn translation_map_derivative<T: RealField + Copy>(
            &self,
            w: &Vector3<T>,
            v: &Vector3<T>,
        ) -> Matrix3<T> {
            ExpChart.translation_map_derivative(w, v)
        }
        fn rotation_left_differential_coefficients<T: RealField + Copy>(
            &self,
            s: T,
        ) -> Option<RodriguesCoefficients<T>> {
            let f: T = nalgebra::convert(self.0);
            ExpChart
                .rotation_left_differential_coefficients(s)
                .map(|c| RodriguesCoefficients {
                    identity: c.identity * f,
                    hat: c.hat * f,
                    hat_squared: c.hat_squared * f,
                })
        }
    }
    let w: Vec<SVector<f64, 3>> = (0..3)
        .map(|k| SVector::from_fn(|i, _| (1.3 * i as f64 + 0.7 * k as f64).sin()))
        .collect();
    group_chart_laws::<Rotations, _, 3>(&Skewed(1.0), &w, 1e-14).unwrap();
    let wrong = group_chart_laws::<Rotations, _, 3>(&Skewed(1.0 + 1e-9), &w, 1e-14).unwrap_err();
    assert_eq!(wrong.law, "chart derivatives", "{wrong}");
    let nan = group_chart_laws::<Rotations, _, 3>(&Skewed(f64::NAN), &w, 1e-14).unwrap_err();
    assert!(nan.error.is_nan(), "{nan}");

    /// SO(3) whose `exp` keeps only the first order, `I + ζ̂` (not on the group).
    #[derive(Debug, Clone, Copy, Default)]
    struct FirstOrder;
    impl ConfigurationGroup<3> for FirstOrder {
        type Element<T: RealField + Copy> = SO3<T>;
        const NAME: &'static str = "SO(3), first-order exp";
        fn lift<T: RealField + Copy>(g: &SO3) -> SO3<T> {
            <Rotations as ConfigurationGroup<3>>::lift(g)
        }
        fn exp<T: RealField + Copy>(zeta: &Vector3<T>) -> SO3<T> {
            SO3::from_matrix_unchecked(Matrix3::identity() + lgsvi_lie::so3::hat(zeta))
        }
        fn is_finite(g: &SO3) -> bool {
            <Rotations as ConfigurationGroup<3>>::is_finite(g)
        }
    }
    let good = configuration_group_laws::<Rotations, 3>(&[SO3::identity()], &w, 1e-14);
    assert!(good.is_ok());
    let wrong =
        configuration_group_laws::<FirstOrder, 3>(&[SO3::identity()], &w, 1e-14).unwrap_err();
    assert_eq!(wrong.law, "exp to second order", "{wrong}");
}
