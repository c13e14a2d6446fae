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

/// Every built-in group with every chart passes the chart law suite, at points from near
/// the origin to large rotations. The consistency laws compare two exact routes, each a
/// few products of Rodrigues coefficients: 1e-14 times the suite's allowance factor
/// (64 × scale², with scale ≤ 2.5 here) stays within 1e-11, above the few ulps that the
/// different summation orders leave; the differenced laws use the suite's own 1e-6.
#[test]
fn every_built_in_chart_passes_the_chart_laws() {
    fn points<const D: usize>() -> Vec<SVector<f64, D>> {
        [0.0, 0.3, 1.6, 2.4]
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
                    && x.fixed_rows::<3>(0).norm() < 0.9 * chart.max_rotation_angle().min(3.0)
            })
            .collect();
        assert!(
            inside.len() >= 3,
            "{}: {} examples",
            chart.name(),
            inside.len()
        );
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
