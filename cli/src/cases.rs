//! The paper's named test cases and their high-precision references: one source of truth
//! for `simulate`'s defaults, `reproduce`, `converge` and `bench`.
//!
//! Everything comes from `tests/data/rigid_body_refs.json` (40-digit trajectories, two
//! independent routes; its README gives the conventions), compiled into the binary:
//! the inputs (`J_d`, `J`, `Ω(0)`, `R(0)`, `m g`) and the reference states.

use nalgebra::Matrix3;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::sync::OnceLock;

/// The reference file, as compiled in.
const REFERENCES: &str = include_str!("../../tests/data/rigid_body_refs.json");

#[derive(Debug, Deserialize)]
struct File {
    cases: BTreeMap<String, RawCase>,
}

#[derive(Debug, Deserialize)]
struct RawCase {
    #[serde(rename = "J_d")]
    inertia_d: [String; 3],
    #[serde(rename = "J")]
    inertia: [String; 3],
    omega0: [String; 3],
    #[serde(rename = "R0")]
    attitude0: [String; 9],
    #[serde(default)]
    m: Option<String>,
    #[serde(default)]
    g: Option<String>,
    states: Vec<RawState>,
}

#[derive(Debug, Deserialize)]
struct RawState {
    t: String,
    #[serde(rename = "R")]
    attitude: [String; 9],
}

/// A named case: its inputs, rounded to doubles, and its reference attitudes.
#[derive(Debug, Clone)]
pub struct Case {
    /// The paper's `J_d` (`J = tr(J_d) I − J_d`).
    pub inertia_d: [f64; 3],
    /// The standard principal moments `J`.
    pub inertia: [f64; 3],
    /// `Ω(0)`.
    pub omega0: [f64; 3],
    /// `R(0)`, row-major.
    pub attitude0: [f64; 9],
    /// Mass and gravitational acceleration of the heavy top (zero for the free body).
    pub mass: Option<f64>,
    pub gravity: Option<f64>,
    /// `(t, R(t))` at the stored times (`0, 0.5, …, 10` and `100`).
    pub references: Vec<(f64, Matrix3<f64>)>,
}

fn number(text: &str) -> f64 {
    // The file is compiled in and checked by the test below: a malformed number is a
    // build defect, not user input.
    text.parse()
        .expect("a decimal number in rigid_body_refs.json")
}

fn numbers<const N: usize>(texts: &[String; N]) -> [f64; N] {
    std::array::from_fn(|i| number(&texts[i]))
}

fn all() -> &'static BTreeMap<String, Case> {
    static CASES: OnceLock<BTreeMap<String, Case>> = OnceLock::new();
    CASES.get_or_init(|| {
        let file: File = serde_json::from_str(REFERENCES).expect("rigid_body_refs.json parses");
        file.cases
            .into_iter()
            .map(|(name, c)| {
                let case = Case {
                    inertia_d: numbers(&c.inertia_d),
                    inertia: numbers(&c.inertia),
                    omega0: numbers(&c.omega0),
                    attitude0: numbers(&c.attitude0),
                    mass: c.m.as_deref().map(number),
                    gravity: c.g.as_deref().map(number),
                    references: c
                        .states
                        .iter()
                        .map(|s| (number(&s.t), Matrix3::from_row_slice(&numbers(&s.attitude))))
                        .collect(),
                };
                (name, case)
            })
            .collect()
    })
}

/// Case `name` (`"A"`: the paper's rigid body; `"B"`, `"C"`: its 3D pendulum near the
/// stable and the unstable equilibrium; `"B_mg1"`, `"C_mg1"`: the same with `m g = 1`).
pub fn case(name: &str) -> &'static Case {
    all()
        .get(name)
        .unwrap_or_else(|| panic!("no case {name} in rigid_body_refs.json"))
}

impl Case {
    /// `m g` of the heavy top.
    pub fn weight(&self) -> Option<f64> {
        Some(self.mass? * self.gravity?)
    }

    /// The reference attitude at a stored time `t`.
    pub fn reference(&self, t: f64) -> Option<Matrix3<f64>> {
        self.references
            .iter()
            .find(|(time, _)| *time == t)
            .map(|(_, r)| *r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_cases_are_as_its_errata_state() {
        let a = case("A");
        assert_eq!(a.inertia_d, [1.3, 2.1, 1.2]);
        assert_eq!(a.inertia, [3.3, 2.5, 3.4]);
        assert_eq!(a.omega0, [-2.0, 1.9, -1.0]);
        assert_eq!(a.weight(), Some(0.0));
        let (b, c) = (case("B"), case("C"));
        assert_eq!(b.inertia_d, [1.0, 2.8, 2.0]);
        assert_eq!(b.omega0, [0.5, -0.5, 0.4]);
        assert_eq!((b.mass, b.gravity), (Some(1.0), Some(9.81)));
        assert_eq!(c.attitude0, [-1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -1.0]);
        for name in ["A", "B", "C"] {
            let case = case(name);
            assert_eq!(case.references.len(), 22);
            let r = case.reference(100.0).unwrap();
            assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-15);
        }
    }
}
