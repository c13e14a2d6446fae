//! Every baseline is verified for its order on the shared 40-digit references (the
//! paper's free rigid body, case A, and its stable 3D pendulum, case B) before it is used
//! as a yardstick.

use lgsvi_baselines::{dop853, Dop853State, Lgvi2, Model, OneStep, Splitting, State, Yoshida4};
use nalgebra::Matrix3;

struct Case {
    model: Model,
    start: State,
    r10: Matrix3<f64>,
}

fn case(name: &str) -> Case {
    let c = lgsvi_cases::case(name).unwrap();
    let (model, start) = lgsvi_baselines::so3_problem(c).unwrap();
    Case {
        model,
        start,
        r10: c.attitude_at(10.0).unwrap(),
    }
}

fn error_at_10(method: &dyn OneStep, c: &Case, steps: usize) -> f64 {
    let mut s = c.start;
    method
        .run(&c.model, &mut s, 10.0 / steps as f64, steps)
        .unwrap();
    (s.attitude - c.r10).norm()
}

/// Richardson-style observed orders from steps N, 2N, 4N, 8N.
fn orders(method: &dyn OneStep, c: &Case, first: usize) -> Vec<f64> {
    let errors: Vec<f64> = (0..4).map(|k| error_at_10(method, c, first << k)).collect();
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

#[test]
fn structure_preserving_baselines_have_their_orders() {
    for name in ["A", "B"] {
        let c = case(name);
        let lgvi4 = Yoshida4(Lgvi2);
        let split4 = Yoshida4(Splitting);
        let methods: [(&str, &dyn OneStep, usize); 4] = [
            ("LGVI2", &Lgvi2, 200),
            ("splitting", &Splitting, 200),
            ("LGVI2-Yoshida4", &lgvi4, 100),
            ("splitting-Yoshida4", &split4, 100),
        ];
        for (label, method, first) in methods {
            let p = orders(method, &c, first);
            println!("{name} {label}: observed orders {p:.3?}");
            // The last observed order is within 0.1 of the nominal one (the errors are far
            // above rounding: ≥ 1e-9 at these steps).
            let last = *p.last().unwrap();
            assert!(
                (last - method.order() as f64).abs() < 0.1,
                "{name} {label}: {p:?}"
            );
        }
    }
}

#[test]
fn lgvi_and_splitting_conserve_what_they_should() {
    let c = case("A");
    for (label, method) in [("LGVI2", &Lgvi2 as &dyn OneStep), ("splitting", &Splitting)] {
        let mut s = c.start;
        let pi0 = s.attitude * s.momentum;
        method.run(&c.model, &mut s, 0.1, 1000).unwrap();
        // Both are Lie–Poisson maps of the free body: spatial momentum exactly, |Π| exactly.
        let drift = (s.attitude * s.momentum - pi0).norm() / pi0.norm();
        let casimir = (s.momentum.norm() - c.start.momentum.norm()).abs() / pi0.norm();
        let orth = (s.attitude.transpose() * s.attitude - Matrix3::identity()).norm();
        println!("{label}: Rπ drift {drift:.1e}, |Π| drift {casimir:.1e}, ‖RᵀR − I‖ {orth:.1e}");
        assert!(drift < 1e-13 && casimir < 1e-13 && orth < 1e-13, "{label}");
    }
}

#[test]
fn dop853_converges_with_the_tolerance() {
    for name in ["A", "B"] {
        let c = case(name);
        for kind in [Dop853State::Quaternion, Dop853State::Matrix] {
            let mut last = f64::INFINITY;
            for tol in [1e-6, 1e-9, 1e-12] {
                let (s, evals) = dop853(&c.model, &c.start, 10.0, tol, kind).unwrap();
                let err = (s.attitude - c.r10).norm();
                println!("{name} {kind:?} tol {tol:e}: error {err:.2e}, {evals} evaluations");
                assert!(err < last, "{name} {kind:?}: no gain at tol {tol}");
                last = err;
            }
            // At tol 1e-12 DOP853 is within ~1e-10 of the reference at t = 10.
            assert!(last < 1e-9, "{name} {kind:?}: {last:e}");
        }
    }
}

/// The baselines' failures say what failed and what to change: the LGVI's Newton at a step
/// far too long for the motion, DOP853 asked for a tolerance below double precision.
#[test]
fn baseline_failures_name_the_method_and_the_remedy() {
    let c = case("A");
    let mut s = c.start;
    let error = Lgvi2.run(&c.model, &mut s, 40.0, 1).unwrap_err();
    let text = error.to_string();
    assert!(
        text.contains("LGVI") && text.contains("take a smaller step"),
        "{text}"
    );
    let error = dop853(&c.model, &c.start, 10.0, 1e-300, Dop853State::Quaternion).unwrap_err();
    assert!(error.to_string().starts_with("DOP853:"), "{error}");
}
