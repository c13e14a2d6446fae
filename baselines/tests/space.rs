//! DOP853 on bodies in space against the 40-digit references of
//! `tests/data/se3_forced_refs.json` (O1: the orbiting body; F1: the torqued body): at a
//! tolerance of 1e-13 DOP853 must land within 1e-9 of the reference at t = 10 (its error
//! per unit time at that tolerance is ~1e-12 relative on these bodies, times a
//! sensitivity ≤ 30 by t = 10), and its error must fall with the tolerance.
use lgsvi_baselines::{dop853_in_space, SpaceModel, SpaceState};
use nalgebra::{Matrix3, Vector3};

fn num(v: &serde_json::Value) -> f64 {
    v.as_str().unwrap().parse().unwrap()
}

fn vec3(v: &serde_json::Value) -> Vector3<f64> {
    let a: Vec<f64> = v.as_array().unwrap().iter().map(num).collect();
    Vector3::from_row_slice(&a)
}

fn case(name: &str) -> (SpaceModel, SpaceState, serde_json::Value) {
    let data: serde_json::Value =
        serde_json::from_str(include_str!("../../tests/data/se3_forced_refs.json")).unwrap();
    let c = data["cases"][name].clone();
    let j = vec3(&c["J"]);
    let orbit = name == "O1";
    let model = SpaceModel {
        inertia: [j.x, j.y, j.z],
        mass: if orbit { num(&c["m"]) } else { 1.0 },
        mu: if orbit { num(&c["mu"]) } else { 0.0 },
        torque: if orbit {
            Vector3::zeros()
        } else {
            vec3(&c["tau_const"])
        },
    };
    let start = SpaceState {
        attitude: Matrix3::identity(),
        omega: vec3(&c["omega0"]),
        position: if orbit {
            vec3(&c["x0"])
        } else {
            Vector3::zeros()
        },
        velocity: if orbit {
            vec3(&c["v0"])
        } else {
            Vector3::zeros()
        },
    };
    let at10 = c["states"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| num(&s["t"]) == 10.0)
        .unwrap()
        .clone();
    (model, start, at10)
}

fn error(end: &SpaceState, reference: &serde_json::Value, orbit: bool) -> f64 {
    let r: Vec<f64> = reference["R"].as_array().unwrap().iter().map(num).collect();
    let mut e = (end.attitude - Matrix3::from_row_slice(&r)).amax();
    e = e.max((end.omega - vec3(&reference["omega"])).amax());
    if orbit {
        e = e.max((end.position - vec3(&reference["position"])).amax());
        e = e.max((end.velocity - vec3(&reference["velocity"])).amax());
    }
    e
}

#[test]
fn dop853_in_space_matches_the_references() {
    for name in ["O1", "F1"] {
        let (model, start, reference) = case(name);
        let orbit = name == "O1";
        let loose = error(
            &dop853_in_space(&model, &start, 10.0, 1e-6).unwrap().0,
            &reference,
            orbit,
        );
        let tight = error(
            &dop853_in_space(&model, &start, 10.0, 1e-13).unwrap().0,
            &reference,
            orbit,
        );
        assert!(tight < 1e-9, "{name}: error {tight:e} at tol 1e-13");
        assert!(
            tight < 1e-3 * loose,
            "{name}: {tight:e} (1e-13) against {loose:e} (1e-6)"
        );
    }
}
