//! Named test cases for rigid-body integrators and their high-precision references, parsed
//! once from the committed files into typed values — the one parser the tests, the
//! baselines, the examples and the `lgsvi` binary share.
//!
//! Two files, compiled in (each with a README beside it in `data/` giving how the numbers
//! were made, their accuracy and the conventions):
//!
//! - `rigid_body_refs.json`: the paper's cases — `A` (the free rigid body), `B` and `C`
//!   (the 3D pendulum near its stable and its unstable equilibrium) and `B_mg1`, `C_mg1`
//!   (the same with `m g = 1`); 40 significant digits, stored values accurate to 1e-38.
//! - `se3_forced_refs.json`: `FJ1` (a free body with a full inertia tensor), `F1` (a
//!   constant body torque), `O1` (a body orbiting a point mass, MacCullagh's gravity); at
//!   least 25 digits.
//!
//! Every case states its inputs (rounded to doubles from exact decimals: `g = 9.81` is
//! 981/100) and the reference states at `t = 0, 0.5, …, 10` and `100`. Conventions: `R`
//! body-to-space (`Ṙ = R Ω̂`), `Ω` in the body frame, position and velocity of the centre
//! of mass in the world frame, `J` the standard inertia tensor (the paper's `J_d` is
//! `½ tr(J) I − J`, stored for its cases).
//!
//! ```
//! let a = lgsvi_cases::case("A")?;
//! assert_eq!(a.kind, lgsvi_cases::Kind::FreeBody);
//! assert_eq!(a.principal_moments(), Some([3.3, 2.5, 3.4]));
//! let end = a.state_at(100.0).expect("every case holds t = 100");
//! assert!((end.attitude.transpose() * end.attitude).is_identity(1e-15));
//! assert!(lgsvi_cases::case("Z").is_err());
//! # Ok::<(), lgsvi_cases::CaseError>(())
//! ```

#![deny(missing_docs)]

use nalgebra::{Matrix3, Vector3};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::sync::OnceLock;

/// The paper's cases, as committed.
const RIGID_BODY: &str = include_str!("../data/rigid_body_refs.json");
/// The full-tensor, forced and orbiting cases, as committed.
const SPACE: &str = include_str!("../data/se3_forced_refs.json");

/// A case name that is not among the committed cases.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("no case named {name:?}; the cases are {known}")]
pub struct CaseError {
    /// The name asked for.
    pub name: String,
    /// The names there are, comma-separated.
    pub known: String,
}

/// What system a case is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A free rigid body, `ℓ = ½ΩᵀJΩ` (`A`, `FJ1`).
    FreeBody,
    /// The heavy top / 3D pendulum, `ℓ = ½ΩᵀJΩ + m g e₃ᵀRρ` (`B`, `C`, …).
    HeavyTop,
    /// A rigid body under a constant body torque (`F1`).
    Torqued,
    /// A rigid body orbiting a point mass `μ` (MacCullagh's gravity to quadrupole order,
    /// `O1`).
    Orbit,
}

/// One reference state.
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// The time.
    pub t: f64,
    /// `R(t)`, body to space.
    pub attitude: Matrix3<f64>,
    /// `Ω(t)`, body frame.
    pub omega: Vector3<f64>,
    /// The centre of mass (world frame), for an orbiting body.
    pub position: Option<Vector3<f64>>,
    /// Its velocity (world frame), for an orbiting body.
    pub velocity: Option<Vector3<f64>>,
    /// The energy (the Lagrangian's), where stored.
    pub energy: Option<f64>,
    /// The spatial angular momentum `π = R J Ω` (about the body's centre of mass or
    /// pivot), where stored (not for `O1`, whose total angular momentum includes the
    /// orbit's).
    pub spatial_momentum: Option<Vector3<f64>>,
    /// The work the torque has done since `t = 0` (`F1`).
    pub work: Option<f64>,
    /// How much an initial error is amplified by this time (the files' `agreement`):
    /// an integrator whose local errors are at rounding cannot beat about
    /// `ε · sensitivity` here.
    pub sensitivity: Option<f64>,
    /// A bound on the stored values' absolute error.
    pub error_bound: f64,
}

/// A named case: its inputs, rounded to doubles, and its reference states.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    /// Its name (`"A"`, `"O1"`, …).
    pub name: String,
    /// The system.
    pub kind: Kind,
    /// One line on what it is.
    pub description: String,
    /// The standard inertia tensor `J` (body frame; diagonal except for `FJ1`).
    pub inertia: Matrix3<f64>,
    /// The paper's `J_d` (its cases only).
    pub inertia_d: Option<[f64; 3]>,
    /// `R(0)`.
    pub attitude0: Matrix3<f64>,
    /// `Ω(0)`.
    pub omega0: Vector3<f64>,
    /// The heavy top's mass (or the orbiting body's).
    pub mass: Option<f64>,
    /// The heavy top's gravitational acceleration.
    pub gravity: Option<f64>,
    /// The heavy top's centre of mass `ρ` (body frame, from the pivot).
    pub center_of_mass: Option<Vector3<f64>>,
    /// The constant body torque (`F1`).
    pub torque: Option<Vector3<f64>>,
    /// The point mass's gravitational parameter `μ` (`O1`).
    pub mu: Option<f64>,
    /// The centre of mass at `t = 0` (`O1`).
    pub position0: Option<Vector3<f64>>,
    /// Its velocity at `t = 0` (`O1`).
    pub velocity0: Option<Vector3<f64>>,
    /// The energy at `t = 0`.
    pub energy0: f64,
    /// The reference states, by time.
    pub states: Vec<State>,
}

impl Case {
    /// The principal moments if `J` is diagonal.
    pub fn principal_moments(&self) -> Option<[f64; 3]> {
        let j = &self.inertia;
        let diagonal = (0..3).all(|a| (0..3).all(|b| a == b || j[(a, b)] == 0.0));
        diagonal.then(|| [j[(0, 0)], j[(1, 1)], j[(2, 2)]])
    }

    /// `m g` of a heavy top.
    pub fn weight(&self) -> Option<f64> {
        Some(self.mass? * self.gravity?)
    }

    /// The reference state at a stored time `t` (`0, 0.5, …, 10, 100`).
    pub fn state_at(&self, t: f64) -> Option<&State> {
        self.states.iter().find(|s| s.t == t)
    }

    /// The reference attitude at a stored time `t`.
    pub fn attitude_at(&self, t: f64) -> Option<Matrix3<f64>> {
        self.state_at(t).map(|s| s.attitude)
    }
}

/// A decimal string, as both files store every number.
#[derive(Debug, Deserialize)]
#[serde(transparent)]
struct Number(String);

impl Number {
    fn value(&self) -> f64 {
        // The files are compiled in and every number is checked by this crate's tests: a
        // malformed one is a defect of the build, not an input.
        self.0
            .parse()
            .unwrap_or_else(|_| panic!("{:?} in a committed reference file", self.0))
    }
}

fn vector(n: &[Number; 3]) -> Vector3<f64> {
    Vector3::new(n[0].value(), n[1].value(), n[2].value())
}

fn matrix(n: &[Number; 9]) -> Matrix3<f64> {
    Matrix3::from_fn(|a, b| n[3 * a + b].value())
}

#[derive(Debug, Deserialize)]
struct File {
    cases: BTreeMap<String, RawCase>,
}

#[derive(Debug, Deserialize)]
struct RawCase {
    kind: String,
    description: String,
    #[serde(rename = "J_d")]
    inertia_d: Option<[Number; 3]>,
    #[serde(rename = "J")]
    inertia: Option<[Number; 3]>,
    #[serde(rename = "J_full")]
    inertia_full: Option<[[Number; 3]; 3]>,
    #[serde(rename = "R0")]
    attitude0: [Number; 9],
    omega0: [Number; 3],
    m: Option<Number>,
    g: Option<Number>,
    rho: Option<[Number; 3]>,
    tau_const: Option<[Number; 3]>,
    mu: Option<Number>,
    x0: Option<[Number; 3]>,
    v0: Option<[Number; 3]>,
    #[serde(rename = "E0")]
    energy0: Number,
    states: Vec<RawState>,
    #[serde(default)]
    agreement: Vec<RawAgreement>,
}

#[derive(Debug, Deserialize)]
struct RawAgreement {
    t: Number,
    sensitivity: Option<f64>,
}

#[derive(Debug, Deserialize)]
struct RawState {
    t: Number,
    #[serde(rename = "R")]
    attitude: [Number; 9],
    omega: [Number; 3],
    position: Option<[Number; 3]>,
    velocity: Option<[Number; 3]>,
    energy: Option<Number>,
    pi: Option<[Number; 3]>,
    work: Option<Number>,
    abs_err_bound: Number,
}

fn parse(name: String, c: RawCase) -> Case {
    let kind = match c.kind.as_str() {
        "free" | "free_full_J" => Kind::FreeBody,
        "heavy_top" => Kind::HeavyTop,
        "forced" => Kind::Torqued,
        "orbit" => Kind::Orbit,
        other => panic!("case {name}: unknown kind {other:?} in a committed reference file"),
    };
    let inertia = match (&c.inertia_full, &c.inertia) {
        (Some(full), _) => Matrix3::from_fn(|a, b| full[a][b].value()),
        (None, Some(j)) => Matrix3::from_diagonal(&vector(j)),
        (None, None) => panic!("case {name}: no inertia in a committed reference file"),
    };
    let heavy = kind == Kind::HeavyTop;
    Case {
        kind,
        description: c.description,
        inertia,
        inertia_d: c
            .inertia_d
            .as_ref()
            .map(|d| [d[0].value(), d[1].value(), d[2].value()]),
        attitude0: matrix(&c.attitude0),
        omega0: vector(&c.omega0),
        mass: c
            .m
            .as_ref()
            .filter(|_| heavy || kind == Kind::Orbit)
            .map(Number::value),
        gravity: c.g.as_ref().filter(|_| heavy).map(Number::value),
        center_of_mass: c.rho.as_ref().filter(|_| heavy).map(vector),
        torque: c.tau_const.as_ref().map(vector),
        mu: c.mu.as_ref().map(Number::value),
        position0: c.x0.as_ref().map(vector),
        velocity0: c.v0.as_ref().map(vector),
        energy0: c.energy0.value(),
        states: c
            .states
            .iter()
            .map(|s| State {
                t: s.t.value(),
                attitude: matrix(&s.attitude),
                omega: vector(&s.omega),
                position: s.position.as_ref().map(vector),
                velocity: s.velocity.as_ref().map(vector),
                energy: s.energy.as_ref().map(Number::value),
                spatial_momentum: s.pi.as_ref().map(vector),
                work: s.work.as_ref().map(Number::value),
                sensitivity: c
                    .agreement
                    .iter()
                    .find(|a| a.t.0 == s.t.0)
                    .and_then(|a| a.sensitivity),
                error_bound: s.abs_err_bound.value(),
            })
            .collect(),
        name,
    }
}

/// Every case, by name.
pub fn all() -> &'static BTreeMap<String, Case> {
    static CASES: OnceLock<BTreeMap<String, Case>> = OnceLock::new();
    CASES.get_or_init(|| {
        [RIGID_BODY, SPACE]
            .into_iter()
            .flat_map(|text| {
                let file: File = serde_json::from_str(text)
                    .unwrap_or_else(|e| panic!("a committed reference file does not parse: {e}"));
                file.cases
            })
            .map(|(name, raw)| (name.clone(), parse(name, raw)))
            .collect()
    })
}

/// The case named `name`.
///
/// # Errors
/// [`CaseError`] (naming the cases there are) if there is none.
pub fn case(name: &str) -> Result<&'static Case, CaseError> {
    all().get(name).ok_or_else(|| CaseError {
        name: name.into(),
        known: all().keys().cloned().collect::<Vec<_>>().join(", "),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The inputs as the files' READMEs and the paper's errata state them.
    #[test]
    fn the_cases_are_as_their_readmes_state() {
        let a = case("A").unwrap();
        assert_eq!(a.inertia_d, Some([1.3, 2.1, 1.2]));
        assert_eq!(a.principal_moments(), Some([3.3, 2.5, 3.4]));
        assert_eq!(a.omega0, Vector3::new(-2.0, 1.9, -1.0));
        assert_eq!((a.kind, a.weight()), (Kind::FreeBody, None));
        let (b, c) = (case("B").unwrap(), case("C").unwrap());
        assert_eq!(b.inertia_d, Some([1.0, 2.8, 2.0]));
        assert_eq!(b.omega0, Vector3::new(0.5, -0.5, 0.4));
        assert_eq!((b.mass, b.gravity), (Some(1.0), Some(9.81)));
        assert_eq!(b.center_of_mass, Some(Vector3::z()));
        assert_eq!(
            c.attitude0,
            Matrix3::from_diagonal(&Vector3::new(-1.0, 1.0, -1.0))
        );
        assert_eq!(case("C_mg1").unwrap().weight(), Some(1.0));
        let fj1 = case("FJ1").unwrap();
        assert_eq!(fj1.principal_moments(), None);
        assert_eq!(fj1.inertia[(0, 1)], 0.4);
        assert_eq!(fj1.inertia, fj1.inertia.transpose());
        let f1 = case("F1").unwrap();
        assert_eq!(f1.torque, Some(Vector3::new(0.1, -0.2, 0.05)));
        let o1 = case("O1").unwrap();
        assert_eq!((o1.mu, o1.mass), (Some(1.0), Some(1.0)));
        assert_eq!(o1.position0, Some(Vector3::new(3.0, 0.0, 0.0)));
        assert_eq!(o1.velocity0, Some(Vector3::new(0.0, 0.55, 0.05)));
        assert!(o1.state_at(10.0).unwrap().position.is_some());
    }

    /// Every case holds the 22 stored times, its attitudes are rotations to the files'
    /// accuracy (rounded to doubles: a few ulps), its first state is its start, and its
    /// error bounds are far below double precision.
    #[test]
    fn every_state_is_a_rotation_at_the_stored_times() {
        assert_eq!(all().len(), 8);
        for c in all().values() {
            assert_eq!(c.states.len(), 22, "{}", c.name);
            assert_eq!(c.states[0].t, 0.0);
            assert_eq!(c.states[21].t, 100.0);
            // The stored first state is the integrators' output at t = 0 (FJ1's carries
            // 1e-64 where R(0) has zeros): equal to the start far below double precision.
            assert!(
                (c.states[0].attitude - c.attitude0).amax() < 1e-30,
                "{}",
                c.name
            );
            assert!((c.states[0].omega - c.omega0).amax() < 1e-30, "{}", c.name);
            for s in &c.states {
                let r = s.attitude;
                assert!(
                    (r.transpose() * r - Matrix3::identity()).amax() < 1e-15,
                    "{}",
                    c.name
                );
                assert!(s.error_bound < 1e-20, "{} at {}", c.name, s.t);
            }
        }
    }

    #[test]
    fn an_unknown_name_lists_the_cases() {
        let e = case("a").unwrap_err();
        assert_eq!(e.name, "a");
        assert!(
            e.to_string().contains("A, B, B_mg1, C, C_mg1, F1, FJ1, O1"),
            "{e}"
        );
    }
}

/// This crate's `README.md`, whose Rust example is compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
