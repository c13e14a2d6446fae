//! The exact free rigid body and the Jacobi elliptic functions against 40-digit mpmath
//! values (`tests/data/generate_exact_reference.py`, inputs identical to the doubles used
//! here), and laws: conservation of energy, `|μ|²` and `Rμ`, orthogonality, Euler's
//! equations and `Ṙ = RΩ̂` by finite differences, in every regime.

use lgsvi_mechanics::exact::{jacobi_elliptic, FreeRigidBodyExact, Regime};
use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::{Inertia, MechanicsError};
use nalgebra::{Matrix3, Vector3};

const EPS: f64 = f64::EPSILON;

fn data() -> serde_json::Value {
    serde_json::from_str(include_str!("data/exact_reference.json")).unwrap()
}

fn num(v: &serde_json::Value) -> f64 {
    v.as_str().unwrap().parse().unwrap()
}

fn nums(v: &serde_json::Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(num).collect()
}

/// The reference bodies, built from the same doubles the generator used.
fn bodies() -> Vec<(String, FreeRigidBodyExact, serde_json::Value)> {
    data()["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| {
            let j = nums(&b["J"]);
            let inertia = Inertia::from_principal_moments([j[0], j[1], j[2]]).unwrap();
            let r0 = SO3::from_matrix_unchecked(Matrix3::from_row_slice(&nums(&b["R0"])));
            let omega0 = Vector3::from_row_slice(&nums(&b["omega0"]));
            let body = FreeRigidBodyExact::new(inertia, r0, omega0).unwrap();
            (b["name"].as_str().unwrap().to_string(), body, b.clone())
        })
        .collect()
}

/// `M`, the separatrix conditioning `M²/|M² − 2E J_mid|`, and the largest phase rate.
fn conditioning(body: &FreeRigidBodyExact) -> (f64, f64, f64) {
    let s = body.state(0.0).unwrap();
    let j = body.inertia().principal_moments();
    let mut sorted = j;
    sorted.sort_by(f64::total_cmp);
    let m2 = s.casimir();
    let n_mid = m2 - 2.0 * body.energy() * sorted[1];
    // ψ̇ is a weighted mean of M/J_x and M/J_y; u̇ = λ ≤ M/J_min as well.
    (
        m2.sqrt(),
        m2 / n_mid.abs().max(f64::MIN_POSITIVE),
        m2.sqrt() / sorted[0],
    )
}

#[test]
fn jacobi_elliptic_functions_match_mpmath() {
    let d = data();
    let mut worst = 0.0f64;
    for row in d["jacobi"].as_array().unwrap() {
        let (u, m) = (num(&row["u"]), num(&row["m"]));
        let f = jacobi_elliptic(u, m).unwrap();
        // Argument reduction and the AGM phase are backward stable: an error of a few ulps
        // of |u| in the phase (the functions have slope ≤ 1). Near m = 1 the first Landen
        // step's asin is ill-conditioned (ratio c/a → 1); measured up to ~6× more there.
        let bound = 8.0 * EPS * (4.0 + u.abs());
        for (name, got, want) in [
            ("sn", f.sn, &row["sn"]),
            ("cn", f.cn, &row["cn"]),
            ("dn", f.dn, &row["dn"]),
        ] {
            let err = (got - num(want)).abs();
            worst = worst.max(err / (EPS * (4.0 + u.abs())));
            assert!(err <= bound, "{name}({u} | {m}): error {err:e} > {bound:e}");
        }
        // The identities hold to rounding whatever the phase error.
        assert!((f.sn * f.sn + f.cn * f.cn - 1.0).abs() <= 4.0 * EPS);
        assert!((f.dn * f.dn + m * f.sn * f.sn - 1.0).abs() <= 4.0 * EPS);
    }
    println!("jacobi: worst error / (ε (4 + |u|)) = {worst:.2}");
}

#[test]
fn jacobi_elliptic_refuses_bad_input() {
    assert!(matches!(
        jacobi_elliptic(f64::NAN, 0.5),
        Err(MechanicsError::NonFinite { .. })
    ));
    assert!(matches!(
        jacobi_elliptic(1.0, 1.5),
        Err(MechanicsError::InvalidSetting { .. })
    ));
    assert!(matches!(
        jacobi_elliptic(1.0, -0.1),
        Err(MechanicsError::InvalidSetting { .. })
    ));
    // The limits are exact.
    let f = jacobi_elliptic(0.8, 0.0).unwrap();
    assert_eq!((f.sn, f.cn, f.dn), (0.8f64.sin(), 0.8f64.cos(), 1.0));
    let f = jacobi_elliptic(0.8, 1.0).unwrap();
    assert_eq!(f.sn, 0.8f64.tanh());
}

#[test]
fn every_regime_matches_the_mpmath_trajectories() {
    let mut regimes = Vec::new();
    for (name, body, reference) in bodies() {
        regimes.push(body.regime());
        let (_, kappa, rate) = conditioning(&body);
        let mut worst = 0.0f64;
        for s in reference["states"].as_array().unwrap() {
            let t = num(&s["t"]);
            let state = body.state(t).unwrap();
            let err_r = (state.attitude().matrix() - Matrix3::from_row_slice(&nums(&s["R"])))
                .abs()
                .max();
            let err_w = (state.velocity - Vector3::from_row_slice(&nums(&s["omega"])))
                .abs()
                .max();
            // Backward stability: the phases ψ(t) and u(t) (each at most rate·|t|) carry a
            // relative error of a few ε, and each phase enters with slope ≤ 1, so the error
            // is about ε (8 + 2 rate |t|). Near the separatrix the modulus k' is computed from
            // M² − 2E J_mid, whose relative rounding is ε κ, κ = M²/|M² − 2E J_mid|; the
            // period, and with it the phase, inherits that once the motion has left the
            // neighbourhood of t = 0: a factor κ (κ ≈ 10 for ordinary bodies).
            let phase = 8.0 + 2.0 * rate * t.abs();
            let bound = EPS * phase * if kappa > 1e3 { kappa } else { 1.0 };
            assert!(
                err_r <= bound && err_w <= bound,
                "{name} t = {t}: R {err_r:e}, Ω {err_w:e} > {bound:e}"
            );
            worst = worst.max(err_r.max(err_w) / (EPS * phase));
        }
        println!(
            "{name:24} {:?}: worst error / (ε (8 + 2 rate t)) = {worst:.3}",
            body.regime()
        );
    }
    // The suite covers every non-degenerate regime.
    assert!(regimes.contains(&Regime::Separatrix));
    assert!(regimes.contains(&Regime::Polhode {
        axis: 2,
        symmetric: false
    }));
    assert!(regimes.contains(&Regime::Polhode {
        axis: 1,
        symmetric: false
    }));
    assert!(regimes.contains(&Regime::Polhode {
        axis: 0,
        symmetric: false
    }));
    assert!(
        regimes
            .iter()
            .filter(|r| matches!(
                r,
                Regime::Polhode {
                    symmetric: true,
                    ..
                }
            ))
            .count()
            == 2
    );
}

#[test]
fn invariants_are_conserved_to_rounding() {
    for (name, body, _) in bodies() {
        let s0 = body.state(0.0).unwrap();
        let (m, _, rate) = conditioning(&body);
        for t in [0.1, 1.7, 6.0, 25.0, -3.0] {
            let s = body.state(t).unwrap();
            let r = s.attitude().matrix();
            // |μ|, energy: each component is amp·(sn|cn|dn), accurate to a few ulps;
            // Rμ = S R_z(ψ) P(μ) μ with P(μ) μ = M e_z to rounding: ~10 ε M.
            assert!(
                (s.casimir() - s0.casimir()).abs() <= 16.0 * EPS * m * m,
                "{name} |μ|² at {t}"
            );
            let e = 0.5 * s.momentum.dot(&s.velocity);
            assert!(
                (e - body.energy()).abs() <= 16.0 * EPS * body.energy(),
                "{name} E at {t}"
            );
            let drift = (s.spatial_momentum() - body.spatial_momentum()).norm();
            assert!(drift <= 16.0 * EPS * m, "{name} Rμ at {t}: {drift:e}");
            assert!(
                (r.transpose() * r - Matrix3::identity()).norm() <= 8.0 * EPS,
                "{name} RᵀR at {t}"
            );
            assert!((r.determinant() - 1.0).abs() <= 8.0 * EPS);
            let _ = rate;
        }
    }
}

#[test]
fn eulers_equations_and_kinematics_hold_by_finite_differences() {
    // Fourth-order central differences with step d: truncation ~ d⁴ |f⁽⁵⁾|/30 and rounding
    // ~ ε |f| / d. With rates up to ~6 (|f⁽⁵⁾| ≲ 6⁵ |f|) and d = 2e-3 both are ≲ 1e-10 |f|.
    let d = 2e-3;
    for (name, body, _) in bodies() {
        let (m, _, _) = conditioning(&body);
        for t in [0.4, 3.3, 11.0] {
            let at = |dt: f64| body.state(t + dt).unwrap();
            let diff = |f: &dyn Fn(f64) -> Matrix3<f64>| {
                (f(-2.0 * d) - 8.0 * f(-d) + 8.0 * f(d) - f(2.0 * d)) / (12.0 * d)
            };
            let s = at(0.0);
            let mu_dot = diff(&|dt| Matrix3::from_diagonal(&at(dt).momentum));
            let euler = Matrix3::from_diagonal(&s.momentum.cross(&s.velocity));
            assert!(
                (mu_dot - euler).norm() <= 1e-9 * m.max(1.0) * m.max(1.0),
                "{name}: Euler at t = {t}"
            );
            let r_dot = diff(&|dt| *at(dt).attitude().matrix());
            let kinematics = s.attitude().matrix() * lgsvi_mechanics::lie::so3::hat(&s.velocity);
            assert!(
                (r_dot - kinematics).norm() <= 1e-9 * m.max(1.0),
                "{name}: Ṙ = RΩ̂ at t = {t}"
            );
        }
    }
}

#[test]
fn degenerate_motions() {
    let inertia = Inertia::from_principal_moments([1.0, 2.0, 2.5]).unwrap();
    let rest = FreeRigidBodyExact::new(inertia, SO3::identity(), Vector3::zeros()).unwrap();
    assert_eq!(rest.regime(), Regime::Rest);
    assert_eq!(
        *rest.state(7.0).unwrap().attitude().matrix(),
        Matrix3::identity()
    );
    // Steady rotation about the (unstable) middle axis stays steady.
    let steady =
        FreeRigidBodyExact::new(inertia, SO3::identity(), Vector3::new(0.0, 1.5, 0.0)).unwrap();
    assert_eq!(steady.regime(), Regime::SteadyRotation);
    let r = *steady.state(2.0).unwrap().attitude().matrix();
    let expected = SO3::exp(&Vector3::new(0.0, 3.0, 0.0));
    assert!((r - expected.matrix()).norm() <= 4.0 * EPS);
    assert_eq!(steady.period(), None);
    // A sphere rotates steadily about any axis.
    let sphere = Inertia::from_principal_moments([2.0, 2.0, 2.0]).unwrap();
    let spin =
        FreeRigidBodyExact::new(sphere, SO3::identity(), Vector3::new(0.3, -0.2, 0.9)).unwrap();
    assert_eq!(spin.regime(), Regime::SteadyRotation);
    // Bad input is a typed error, and so is a bad time.
    let nan = FreeRigidBodyExact::new(inertia, SO3::identity(), Vector3::new(f64::NAN, 0.0, 0.0));
    assert!(matches!(nan, Err(MechanicsError::NonFinite { .. })));
    assert!(matches!(
        spin.state(f64::INFINITY),
        Err(MechanicsError::NonFinite { .. })
    ));
}

#[test]
fn the_period_is_that_of_the_angular_velocity() {
    for (name, body, _) in bodies() {
        if let Some(period) = body.period() {
            let (w0, w1) = (
                body.state(0.3).unwrap().velocity,
                body.state(0.3 + period).unwrap().velocity,
            );
            assert!(
                (w0 - w1).norm() <= 64.0 * EPS * w0.norm().max(1.0) * (1.0 + period),
                "{name}"
            );
            // ... and not of anything shorter: half a period flips two components.
            let half = body.state(0.3 + 0.5 * period).unwrap().velocity;
            assert!((w0 - half).norm() > 1e-3 * w0.norm(), "{name}");
        }
    }
}

/// Regression: `--omega0 1,1e-10,1e-10` (a spin about the paper's middle axis) gave an
/// `R(0)` rotated by 2.2 rad and the wrong sign of `Ω_z`: near the separatrix, sn u₀ → 1
/// and the small components cn u₀, dn u₀ = O(k') lost their relative accuracy. Now a
/// dense sweep around the separatrix (both sides, and on it; spins about the middle axis
/// perturbed by 1e-3 … 1e-15, energies within 1e-6 … 1e-14 of it) matches mpmath at
/// 60 digits (`data/generate_separatrix_sweep.py`).
#[test]
fn the_separatrix_neighbourhood_matches_mpmath() {
    let sweep: serde_json::Value =
        serde_json::from_str(include_str!("data/separatrix_sweep.json")).unwrap();
    let bodies = sweep["bodies"].as_array().unwrap();
    assert!(bodies.len() >= 20);
    let mut worst = (0.0f64, String::new());
    for b in bodies {
        let name = b["name"].as_str().unwrap();
        let j = nums(&b["J"]);
        let inertia = Inertia::from_principal_moments([j[0], j[1], j[2]]).unwrap();
        let omega0 = Vector3::from_row_slice(&nums(&b["omega0"]));
        let body = FreeRigidBodyExact::new(inertia, SO3::identity(), omega0).unwrap();
        let (_, _, rate) = conditioning(&body);
        for s in b["states"].as_array().unwrap() {
            let t = num(&s["t"]);
            let state = body.state(t).unwrap();
            let err_r = (state.attitude().matrix() - Matrix3::from_row_slice(&nums(&s["R"])))
                .abs()
                .max();
            let err_w = (state.velocity - Vector3::from_row_slice(&nums(&s["omega"])))
                .abs()
                .max();
            // Backward stability: the state is that of inputs perturbed by a few ulps
            // (forming μ, the N's, the amplitudes), amplified by the sensitivity S(t) the
            // generator measured (|ω₀| times the largest ∂state/∂ω₀; it is ≥ 1), plus the
            // phases' rounding as in `every_regime_matches_the_mpmath_trajectories`
            // (the reduction by K ≈ ln(4/k') ≤ 40 adds a few ulps of K: 2·40 ε).
            let sensitivity = num(&s["sensitivity"]);
            let phase = 8.0 + 2.0 * rate * t.abs() + 80.0;
            let bound = EPS * (phase + 8.0 * sensitivity);
            let err = err_r.max(err_w / omega0.norm());
            assert!(
                err <= bound,
                "{name} t = {t}: R {err_r:e}, Ω {err_w:e} > {bound:e}"
            );
            if t == 0.0 {
                // The initial state is reproduced to rounding.
                assert!(err <= 8.0 * EPS, "{name}: R(0) {err_r:e}, Ω(0) {err_w:e}");
            }
            if err / bound > worst.0 {
                worst = (err / bound, format!("{name} t = {t}: {err:.2e}"));
            }
        }
    }
    println!(
        "separatrix sweep: worst error / bound = {:.3} ({})",
        worst.0, worst.1
    );
}
