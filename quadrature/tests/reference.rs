//! Nodes and weights against the 60-digit mpmath reference in `tests/data/`, printed by the
//! committed script `tests/data/generate_reference.py` (independent of this crate).
//!
//! Bounds are the contract: node error ≤ 4ε (absolute, on [−1, 1]) and relative
//! weight error ≤ 8ε, for every tabulated m. Run with `--nocapture` to see the measured
//! errors per m.

use lgsvi_quadrature::{gauss_legendre, gauss_lobatto, gauss_radau_left, gauss_radau_right, Rule};

const EPS: f64 = f64::EPSILON;
const NODE_BOUND: f64 = 4.0 * EPS;
const WEIGHT_BOUND: f64 = 8.0 * EPS;

/// Parses `m i node weight` lines into `(m, nodes, weights)` groups. Rust's `f64` parsing
/// rounds correctly, so each reference value is within half an ulp of the exact one.
fn reference(text: &str) -> Vec<(usize, Vec<f64>, Vec<f64>)> {
    let mut out: Vec<(usize, Vec<f64>, Vec<f64>)> = Vec::new();
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let mut it = line.split_whitespace();
        let m: usize = it.next().unwrap().parse().unwrap();
        let i: usize = it.next().unwrap().parse().unwrap();
        let x: f64 = it.next().unwrap().parse().unwrap();
        let w: f64 = it.next().unwrap().parse().unwrap();
        if i == 0 {
            out.push((m, Vec::new(), Vec::new()));
        }
        let last = out.last_mut().unwrap();
        assert_eq!((last.0, last.1.len()), (m, i), "malformed reference file");
        last.1.push(x);
        last.2.push(w);
    }
    out
}

/// Max absolute node error and max relative weight error, in units of ε.
fn errors(rule: &Rule, nodes: &[f64], weights: &[f64]) -> (f64, f64) {
    assert_eq!(rule.num_points(), nodes.len());
    let node = rule
        .nodes()
        .iter()
        .zip(nodes)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let weight = rule
        .weights()
        .iter()
        .zip(weights)
        .map(|(a, b)| ((a - b) / b).abs())
        .fold(0.0, f64::max);
    (node / EPS, weight / EPS)
}

fn check_family(name: &str, text: &str, build: impl Fn(usize) -> Rule) {
    let table = reference(text);
    assert!(!table.is_empty());
    println!("{name}: m, max node error [ε], max relative weight error [ε]");
    for (m, nodes, weights) in &table {
        let (node_err, weight_err) = errors(&build(*m), nodes, weights);
        println!("{name} {m:>4} {node_err:>6.2} {weight_err:>6.2}");
        assert!(
            node_err * EPS <= NODE_BOUND,
            "{name} m = {m}: node error {node_err} ε"
        );
        assert!(
            weight_err * EPS <= WEIGHT_BOUND,
            "{name} m = {m}: weight error {weight_err} ε"
        );
    }
}

#[test]
fn gauss_legendre_matches_mpmath() {
    check_family(
        "gauss-legendre",
        include_str!("data/gauss_legendre.txt"),
        |m| gauss_legendre(m).unwrap(),
    );
}

#[test]
fn gauss_lobatto_matches_mpmath() {
    check_family(
        "gauss-lobatto",
        include_str!("data/gauss_lobatto.txt"),
        |m| gauss_lobatto(m).unwrap(),
    );
}

#[test]
fn gauss_radau_matches_mpmath() {
    check_family(
        "gauss-radau-left",
        include_str!("data/gauss_radau.txt"),
        |m| gauss_radau_left(m).unwrap(),
    );
    // The right rule is the mirror image: nodes −x reversed, same weights reversed.
    let table = reference(include_str!("data/gauss_radau.txt"));
    for (m, nodes, weights) in table {
        let mirrored: Vec<f64> = nodes.iter().rev().map(|x| -x).collect();
        let w: Vec<f64> = weights.iter().rev().copied().collect();
        let (node_err, weight_err) = errors(&gauss_radau_right(m).unwrap(), &mirrored, &w);
        assert!(node_err * EPS <= NODE_BOUND && weight_err * EPS <= WEIGHT_BOUND);
    }
}
