//! Property tests over random rotations, motions and chart vectors (proptest; failures
//! are kept in `tests/properties.proptest-regressions`).

mod common;

use common::EPS;
use lgsvi_lie::{
    CayleyChart, Chart, ChartKind, ExpChart, LieGroup, So3Chart, UnscaledCayleyChart, SE3, SO3,
};
use nalgebra::{Vector3, Vector6};
use proptest::prelude::*;

fn vec3(limit: f64) -> impl Strategy<Value = Vector3<f64>> {
    prop::array::uniform3(-limit..limit).prop_map(Vector3::from)
}

proptest! {
    /// exp stays on the group to rounding at every angle, and log inverts it below π.
    #[test]
    fn exp_is_orthogonal_and_log_inverts_it(w in vec3(10.0)) {
        let r = SO3::exp(&w);
        // Rodrigues: each entry sums three terms of size ≤ 1 (|sinc|, 2|b| ≤ 1): 16ε.
        prop_assert!(r.orthogonality_error() <= 16.0 * EPS);
        prop_assert!((r.matrix().determinant() - 1.0).abs() <= 16.0 * EPS);
        if w.norm() < 3.0 {
            // log's derivative is ≤ θ/(2 sin(θ/2)) ≤ 3/(2 sin 1.5) ≈ 1.5 here.
            prop_assert!((r.log() - w).amax() <= 32.0 * EPS * (1.0 + w.norm()));
        }
        // The axis is fixed.
        prop_assert!((r.act(&w) - w).amax() <= 16.0 * EPS * w.norm());
    }

    /// Every chart maps into SO(3) and its inverse recovers the vector (for exp, only
    /// below π: beyond it log returns the other representative, 2π − |ω| the other way).
    #[test]
    fn charts_round_trip(w in vec3(2.5)) {
        let exp_round_trip = if w.norm() < 3.0 {
            let r: SO3 = ExpChart.to_group(&w);
            Some((r, ExpChart.to_algebra(&r)))
        } else {
            None
        };
        for (r, back) in exp_round_trip.into_iter().chain([
            { let r: SO3 = CayleyChart.to_group(&w); (r, CayleyChart.to_algebra(&r)) },
            { let r: SO3 = UnscaledCayleyChart.to_group(&w); (r, UnscaledCayleyChart.to_algebra(&r)) },
        ]) {
            prop_assert!(r.orthogonality_error() <= 16.0 * EPS);
            // Cayley inverses have derivative ≤ 1 + |ξ|²/4 ≤ 3 here.
            prop_assert!((back.unwrap() - w).amax() <= 64.0 * EPS * (1.0 + w.norm_squared()));
        }
    }

    /// Beyond a half turn the exp chart's inverse on the branch near a guess recovers the
    /// vector: for `|ω|` in (0.1, 6), `rotation_vector_near(exp ω, ω + δ)` with a guess
    /// off by `|δ| < 0.05` returns `ω`, where the principal logarithm returns
    /// `(|ω| − 2π) ω/|ω|` past `π`. The other branch is `2π − 2|ω|`-far at worst (≥ 0.57
    /// here), so a 0.05 guess cannot pick it. Tolerance: past `π` the result is the
    /// principal logarithm (angle `2π − |ω|` ≥ 0.28) stretched to length `|ω|`, which
    /// scales the rounding of its axis (≲ 2ε/angle) by ≤ 6: ≤ 45ε, inside 64ε(1 + |ω|).
    #[test]
    fn exp_inverse_follows_the_branch_of_a_guess(w in vec3(3.5), d in vec3(0.028)) {
        prop_assume!(w.norm() > 0.1 && w.norm() < 6.0);
        let r = ExpChart.rotation_matrix(&w);
        let back = ExpChart.rotation_vector_near(&r, &(w + d)).unwrap();
        prop_assert!((back - w).amax() <= 64.0 * EPS * (1.0 + w.norm()), "{back} vs {w}");
        // The default (any other chart) is the plain inverse.
        let c = CayleyChart.rotation_matrix(&w);
        prop_assert_eq!(
            CayleyChart.rotation_vector_near(&c, &(w + d)).unwrap(),
            CayleyChart.rotation_vector(&c).unwrap()
        );
    }

    /// The Rodrigues coefficients rebuild `Φ` and `A` of every chart. Both sides evaluate
    /// the same coefficient functions, so they agree to a few ulps of the entries (each a
    /// sum of three terms of size ≤ |e| + |a||ω| + |b||ω|², at most ~4 for `|ω| < 6`).
    /// The coefficients' independent check is the mechanics layer's test of the Newton
    /// matrix built from them against dual numbers.
    #[test]
    fn rodrigues_coefficients_rebuild_the_chart_maps(w in vec3(3.5)) {
        for chart in ChartKind::ALL {
            let s = w.norm_squared();
            let phi = chart.rotation_matrix_coefficients(s).unwrap().matrix(&w);
            let a = chart.rotation_left_differential_coefficients(s).unwrap().matrix(&w);
            prop_assert!((phi - chart.rotation_matrix(&w)).amax() <= 16.0 * EPS * (1.0 + s));
            prop_assert!(
                (a - chart.rotation_left_differential(&w)).amax() <= 16.0 * EPS * (1.0 + s)
            );
        }
    }

    /// SE(3): exp/log round trip and the group's action agrees with the matrix.
    #[test]
    fn se3_exp_log_and_action(w in vec3(2.5), v in vec3(5.0), p in vec3(5.0)) {
        prop_assume!(w.norm() < 3.0, "log inverts exp below π only");
        let xi = Vector6::new(w.x, w.y, w.z, v.x, v.y, v.z);
        let g = SE3::exp(&xi);
        // J_l⁻¹ has norm ≤ ~5 for |ω| ≤ 4.4; translations up to ~10.
        prop_assert!((g.log() - xi).amax() <= 256.0 * EPS * (1.0 + xi.norm()));
        let m = g.to_matrix();
        let hom = m * nalgebra::Vector4::new(p.x, p.y, p.z, 1.0);
        prop_assert!((g.act(&p) - hom.xyz()).amax() <= 16.0 * EPS * (1.0 + p.norm() + v.norm()));
    }
}
