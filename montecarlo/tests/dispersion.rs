//! The draws against their laws: reproducible from `(seed, member)` alone, the sample
//! moments of each distribution within the central limit theorem's bounds, bounded draws
//! within their bounds, a misaligned tensor with the drawn moments as its eigenvalues, and
//! every spec that could give a non-physical member refused up front naming its key.

use lgsvi_mechanics::lie::{LieGroup, SO3};
use lgsvi_mechanics::Inertia;
use lgsvi_montecarlo::{Body, Dispersion, DispersionError, Dispersions, Member, Plan};
use nalgebra::Vector3;
use rayon::prelude::*;

fn nominal() -> Body {
    let inertia = Inertia::from_principal_moments([3.3, 2.5, 3.4]).unwrap();
    let attitude = SO3::exp(&Vector3::new(0.3, -0.2, 0.1));
    let mut n = Body::new(inertia, attitude, Vector3::new(0.1, -0.05, 0.2));
    n.mass = Some(100.0);
    n.wheel_inertias = vec![0.1, 0.1, 0.1];
    n.wheel_axes = vec![Vector3::x(), Vector3::y(), Vector3::z()];
    n
}

fn everything() -> Dispersions {
    Dispersions {
        attitude: Some(Dispersion::Uniform { half_width: 0.05 }),
        omega: Some(Dispersion::Normal { sigma: 0.01 }),
        inertia: Some(Dispersion::TruncatedNormal {
            sigma: 0.02,
            bound: 0.05,
        }),
        inertia_misalignment: Some(Dispersion::Normal { sigma: 0.01 }),
        mass: Some(Dispersion::Uniform { half_width: 0.1 }),
        torque: Some(Dispersion::Normal { sigma: 1e-3 }),
        wheel_inertia: Some(Dispersion::TruncatedNormal {
            sigma: 0.05,
            bound: 0.2,
        }),
        wheel_axis: Some(Dispersion::Normal { sigma: 0.005 }),
    }
}

fn members(plan: &Plan, indices: impl Iterator<Item = u64>) -> Vec<Member> {
    indices.map(|i| plan.member(i).unwrap()).collect()
}

/// Member `i` is the same drawn in order, in reverse, on one thread or two, and whichever
/// other quantities are dispersed; another seed gives other members.
#[test]
fn a_member_depends_on_seed_and_index_alone() {
    let plan = Plan::new(nominal(), everything(), 2026).unwrap();
    let forward = members(&plan, 0..500);
    let mut backward = members(&plan, (0..500).rev());
    backward.reverse();
    assert_eq!(forward, backward);
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let parallel: Vec<Member> = pool.install(|| {
            (0..500u64)
                .into_par_iter()
                .map(|i| plan.member(i).unwrap())
                .collect()
        });
        assert_eq!(forward, parallel, "{threads} threads");
    }
    // The rates alone dispersed: the same rates as with everything dispersed.
    let rates_only = Dispersions {
        omega: everything().omega,
        ..Dispersions::default()
    };
    let plan_rates = Plan::new(nominal(), rates_only, 2026).unwrap();
    for member in &forward[..50] {
        let alone = plan_rates.member(member.index).unwrap();
        assert_eq!(alone.body.omega, member.body.omega);
        assert_eq!(alone.body.attitude, nominal().attitude);
    }
    let other = Plan::new(nominal(), everything(), 2027).unwrap();
    assert_ne!(other.member(0).unwrap().body.omega, forward[0].body.omega);
}

/// Sample mean and standard deviation over 30 000 members (90 000 draws a quantity):
/// within 5 standard errors of the distribution's (the mean's error σ/√N, the standard
/// deviation's σ/√(2N)); bounded draws within their bounds.
#[test]
fn the_draws_follow_their_distributions() {
    let plan = Plan::new(nominal(), everything(), 7).unwrap();
    let all = members(&plan, 0..30_000);
    let n = nominal();
    let stats = |values: &[f64]| {
        let count = values.len() as f64;
        let mean = values.iter().sum::<f64>() / count;
        let var = values.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (count - 1.0);
        (mean, var.sqrt(), count)
    };
    let check = |name: &str, values: Vec<f64>, sigma: f64| {
        let (mean, std, count) = stats(&values);
        assert!(
            mean.abs() < 5.0 * sigma / count.sqrt(),
            "{name}: mean {mean:e}"
        );
        assert!(
            (std - sigma).abs() < 5.0 * sigma / (2.0 * count).sqrt(),
            "{name}: σ {std:e} against {sigma:e}"
        );
    };
    // Normal: the rates.
    let omega: Vec<f64> = all
        .iter()
        .flat_map(|m| (m.body.omega - n.omega).data.0[0])
        .collect();
    check("omega", omega, 0.01);
    // Uniform on [−w, w]: σ = w/√3, every draw within w.
    let attitude: Vec<f64> = all
        .iter()
        .flat_map(|m| n.attitude.inverse().compose(&m.body.attitude).log().data.0[0])
        .collect();
    assert!(attitude.iter().all(|x| x.abs() <= 0.05 + 1e-15));
    check("attitude", attitude, 0.05 / 3f64.sqrt());
    // Truncated normal, σ = 0.02 cut at k = 2.5σ: σ_t² = σ²(1 − 2kφ(k)/(2Φ(k) − 1)).
    // (Without the misalignment, so that the moments stay in body-axis order: 3.3 and
    // 3.4 are closer than the perturbations.)
    let aligned = Plan::new(
        nominal(),
        Dispersions {
            inertia_misalignment: None,
            ..everything()
        },
        7,
    )
    .unwrap();
    let moments = n.inertia.principal_moments();
    let relative: Vec<f64> = members(&aligned, 0..30_000)
        .iter()
        .flat_map(|m| {
            let drawn = m.body.inertia.principal_moments();
            (0..3).map(move |k| drawn[k] / moments[k] - 1.0)
        })
        .collect();
    assert!(relative.iter().all(|x| x.abs() <= 0.05 + 1e-14));
    let k: f64 = 2.5;
    let phi = (-0.5 * k * k).exp() / (2.0 * std::f64::consts::PI).sqrt();
    let big_phi_2m1 = 0.987_580_669_348_447_7; // erf(2.5/√2) = 2Φ(2.5) − 1 (Python's math.erf)
    let sigma_t = 0.02 * (1.0 - 2.0 * k * phi / big_phi_2m1).sqrt();
    check("inertia", relative, sigma_t);
}

/// A misaligned tensor keeps the drawn moments as its eigenvalues: the same member drawn
/// without the misalignment has the same moments (the streams are separate) and a
/// diagonal tensor.
#[test]
fn misalignment_rotates_the_principal_axes_only() {
    let with = Plan::new(nominal(), everything(), 11).unwrap();
    let without = Plan::new(
        nominal(),
        Dispersions {
            inertia_misalignment: None,
            ..everything()
        },
        11,
    )
    .unwrap();
    for i in 0..200 {
        let (a, b) = (with.member(i).unwrap(), without.member(i).unwrap());
        assert!(!a.body.inertia.is_diagonal() && b.body.inertia.is_diagonal());
        let mut ea = a.body.inertia.matrix().symmetric_eigenvalues().data.0[0];
        let mut eb = b.body.inertia.principal_moments();
        ea.sort_by(f64::total_cmp);
        eb.sort_by(f64::total_cmp);
        for k in 0..3 {
            // The tensor's rounding: a few ε of its largest moment.
            assert!(
                (ea[k] - eb[k]).abs() < 8.0 * f64::EPSILON * 3.6,
                "{ea:?} {eb:?}"
            );
        }
        // The wheels' axes stay unit vectors near the nominal.
        for (axis, nominal) in a.body.wheel_axes.iter().zip(&nominal().wheel_axes) {
            assert!((axis.norm() - 1.0).abs() < 4.0 * f64::EPSILON);
            assert!((axis - nominal).norm() < 0.1);
        }
    }
}

/// Every spec that could make a member non-physical, or that is malformed, is refused
/// before any member is drawn, naming its key and what to give.
#[test]
fn specs_that_could_break_a_member_are_refused_naming_the_key() {
    let refused = |d: Dispersions, nominal: Body, needles: &[&str]| {
        let error = Plan::new(nominal, d, 1).unwrap_err();
        let text = error.to_string();
        for needle in needles {
            assert!(text.contains(needle), "{text:?} does not say {needle:?}");
        }
        error
    };
    // A normal relative perturbation of the inertia or the mass: unbounded.
    let error = refused(
        Dispersions {
            inertia: Some(Dispersion::Normal { sigma: 0.01 }),
            ..Dispersions::default()
        },
        nominal(),
        &[
            "dispersion inertia",
            "truncated_normal",
            "triangle inequality",
        ],
    );
    assert!(matches!(
        error,
        DispersionError::NotPhysical { key: "inertia", .. }
    ));
    refused(
        Dispersions {
            mass: Some(Dispersion::Normal { sigma: 0.01 }),
            ..Dispersions::default()
        },
        nominal(),
        &["dispersion mass", "below 1.000000", "its positivity"],
    );
    // A bound past the triangle inequality's room: (3.3, 2.5, 3.4) has room
    // (2.5 + 3.3 − 3.4)/9.2 ≈ 0.26; a flat body (1, 2, 3 − 1e-3) has almost none.
    refused(
        Dispersions {
            inertia: Some(Dispersion::Uniform { half_width: 0.3 }),
            ..Dispersions::default()
        },
        nominal(),
        &["up to 0.300000", "below 0.260870"],
    );
    let mut flat = nominal();
    flat.inertia = Inertia::from_principal_moments([1.0, 2.0, 2.999]).unwrap();
    refused(
        Dispersions {
            inertia: Some(Dispersion::TruncatedNormal {
                sigma: 0.01,
                bound: 0.02,
            }),
            ..Dispersions::default()
        },
        flat,
        &["below 0.000167"],
    );
    // Parameters out of range.
    for (dispersion, needle) in [
        (Dispersion::Normal { sigma: -0.1 }, "sigma = -0.1"),
        (Dispersion::Normal { sigma: f64::NAN }, "sigma = NaN"),
        (
            Dispersion::Uniform {
                half_width: f64::INFINITY,
            },
            "half_width = inf",
        ),
        (
            Dispersion::TruncatedNormal {
                sigma: 1.0,
                bound: 0.01,
            },
            "at least sigma/10",
        ),
        (
            Dispersion::TruncatedNormal {
                sigma: 0.0,
                bound: 0.01,
            },
            "> 0",
        ),
    ] {
        refused(
            Dispersions {
                omega: Some(dispersion),
                ..Dispersions::default()
            },
            nominal(),
            &["dispersion omega", needle],
        );
    }
    // A quantity the nominal body does not have.
    let body = Body::new(nominal().inertia, SO3::identity(), Vector3::zeros());
    refused(
        Dispersions {
            mass: Some(Dispersion::Uniform { half_width: 0.1 }),
            ..Dispersions::default()
        },
        body.clone(),
        &["dispersion mass", "no mass"],
    );
    refused(
        Dispersions {
            wheel_axis: Some(Dispersion::Uniform { half_width: 0.1 }),
            ..Dispersions::default()
        },
        body,
        &["no wheels"],
    );
}

/// A spec reads from TOML, and an unknown key or distribution is refused naming it.
#[test]
fn a_spec_reads_from_toml() {
    let text = r#"
        omega = { distribution = "normal", sigma = 0.01 }
        inertia = { distribution = "truncated_normal", sigma = 0.02, bound = 0.05 }
        attitude = { distribution = "uniform", half_width = 0.05 }
    "#;
    let spec: Dispersions = toml::from_str(text).unwrap();
    assert_eq!(spec.omega, Some(Dispersion::Normal { sigma: 0.01 }));
    assert_eq!(
        spec.inertia,
        Some(Dispersion::TruncatedNormal {
            sigma: 0.02,
            bound: 0.05
        })
    );
    assert_eq!(spec.mass, None);
    let unknown =
        toml::from_str::<Dispersions>("omegas = { distribution = \"normal\", sigma = 1.0 }")
            .unwrap_err()
            .to_string();
    assert!(unknown.contains("omegas"), "{unknown}");
    let family =
        toml::from_str::<Dispersions>("omega = { distribution = \"cauchy\", sigma = 1.0 }")
            .unwrap_err()
            .to_string();
    assert!(family.contains("cauchy"), "{family}");
}

/// A nominal body built field by field that is inconsistent (two wheel axes for one wheel
/// inertia, a mass that is not positive) is refused naming what to fix.
#[test]
fn an_inconsistent_nominal_body_is_refused() {
    let mut body = nominal();
    body.wheel_inertias = vec![0.1];
    body.wheel_axes = vec![Vector3::x(), Vector3::y()];
    let error = Plan::new(body, Dispersions::default(), 1).unwrap_err();
    assert!(matches!(error, DispersionError::Nominal(_)), "{error:?}");
    assert!(error.to_string().contains("one axis per wheel"), "{error}");
    let mut body = nominal();
    body.mass = Some(-2.0);
    let error = Plan::new(body, Dispersions::default(), 1).unwrap_err();
    assert!(
        error.to_string().contains("mass -2") && error.to_string().contains("positive"),
        "{error}"
    );
}
