//! DOP853 on bodies in space against the 40-digit references of
//! `cases/data/se3_forced_refs.json` (O1: the orbiting body; F1: the torqued body): at a
//! tolerance of 1e-13 DOP853 must land within 1e-9 of the reference at t = 10 (its error
//! per unit time at that tolerance is ~1e-12 relative on these bodies, times a
//! sensitivity ≤ 30 by t = 10), and its error must fall with the tolerance.
use lgsvi_baselines::{dop853_in_space, SpaceModel, SpaceState};

fn case(name: &str) -> (SpaceModel, SpaceState, &'static lgsvi_cases::State) {
    let c = lgsvi_cases::case(name).unwrap();
    let (model, start) = lgsvi_baselines::space_problem(c).unwrap();
    (model, start, c.state_at(10.0).unwrap())
}

fn error(end: &SpaceState, reference: &lgsvi_cases::State, orbit: bool) -> f64 {
    let mut e = (end.attitude - reference.attitude).amax();
    e = e.max((end.omega - reference.omega).amax());
    if orbit {
        e = e.max((end.position - reference.position.unwrap()).amax());
        e = e.max((end.velocity - reference.velocity.unwrap()).amax());
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
            reference,
            orbit,
        );
        let tight = error(
            &dop853_in_space(&model, &start, 10.0, 1e-13).unwrap().0,
            reference,
            orbit,
        );
        assert!(tight < 1e-9, "{name}: error {tight:e} at tol 1e-13");
        assert!(
            tight < 1e-3 * loose,
            "{name}: {tight:e} (1e-13) against {loose:e} (1e-6)"
        );
    }
}
