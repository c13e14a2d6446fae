//! Gauss–Legendre rules from this crate beside the `gauss-quad` crate's (Bogaert's O(m)
//! algorithm), on the same machine in the same process: the error of every node and weight
//! against the committed 34-digit mpmath references (`tests/data/gauss_legendre.txt`, and the
//! three largest nodes of the rules of 10⁵ and 10⁶ points in
//! `tests/data/gauss_legendre_extremes.txt`), and the time to build a rule of m = 10² … 10⁶
//! points (best of 5). Then the Hermite, Laguerre and Jacobi rules (this crate's `O(m)` march
//! from 100 points on; gauss-quad's dense Golub–Welsch, `O(m³)`, timed up to 10³ points):
//! errors against `tests/data/gauss_classical.txt` and `gauss_classical_large.txt`, and
//! build times.
//!
//! Errors as the crate's reference tests measure them: the largest absolute node error and
//! the largest relative weight error, both in units of ε (every node is in [−1, 1]).
//!
//! Asserts that every error of this crate's rules is at most [`WITHIN`] ε (the bound the
//! crate's reference tests hold); the times are a measurement and are only printed.
//!
//! Run: `cargo run --release -p lgsvi-quadrature --example versus_gauss_quad [MAX_M]`: the
//! rules are timed up to `MAX_M` points (default 10⁶, about a minute; CI passes 1000).

use gauss_quad::legendre::GaussLegendre;
use lgsvi_quadrature::{gauss_hermite, gauss_jacobi, gauss_laguerre, gauss_legendre};
use std::collections::BTreeMap;
use std::num::NonZeroUsize;
use std::time::Instant;

type Rule = Vec<(f64, f64)>;

/// The largest node or relative weight error of this crate's rules, in ε, that the example
/// accepts: the crate's reference tests hold every rule to this bound (a few roundings of
/// the recurrences and the Newton polish, whatever m).
const WITHIN: f64 = 4.0;

/// Panics when one of this crate's errors (in ε) exceeds [`WITHIN`].
fn check(what: &str, m: usize, (node, weight): (f64, f64)) {
    assert!(
        node <= WITHIN && weight <= WITHIN,
        "{what}, m = {m}: node error {node} ε, weight error {weight} ε (more than {WITHIN} ε)"
    );
}

/// `(node, weight)` pairs, ascending nodes.
fn ours(m: usize) -> Rule {
    let rule = gauss_legendre(m).expect("m ≥ 1");
    rule.iter().collect()
}

fn theirs(m: usize) -> Rule {
    let rule = GaussLegendre::new(NonZeroUsize::new(m).expect("m ≥ 1"));
    let mut pairs: Rule = rule.iter().map(|(x, w)| (*x, *w)).collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    pairs
}

fn read(path: &str) -> BTreeMap<usize, Vec<(usize, f64, f64)>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut table: BTreeMap<usize, Vec<(usize, f64, f64)>> = BTreeMap::new();
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let f: Vec<&str> = line.split_whitespace().collect();
        let (m, i) = (f[0].parse().unwrap(), f[1].parse().unwrap());
        table
            .entry(m)
            .or_default()
            .push((i, f[2].parse().unwrap(), f[3].parse().unwrap()));
    }
    table
}

fn errors(rule: &Rule, reference: &[(usize, f64, f64)], from_the_top: bool) -> (f64, f64) {
    let m = rule.len();
    let (mut node, mut weight) = (0.0f64, 0.0f64);
    for &(i, x, w) in reference {
        let (xi, wi) = if from_the_top {
            rule[m - 1 - i]
        } else {
            rule[i]
        };
        node = node.max((xi - x).abs());
        weight = weight.max((wi - w).abs() / w.abs());
    }
    (node / f64::EPSILON, weight / f64::EPSILON)
}

fn best_of_5(build: impl Fn() -> Rule) -> f64 {
    (0..5)
        .map(|_| {
            let start = Instant::now();
            std::hint::black_box(build());
            start.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    let max_m: usize = match std::env::args().nth(1) {
        Some(text) => text.parse().unwrap_or_else(|_| {
            eprintln!("usage: versus_gauss_quad [MAX_M] (the largest rule timed; got {text:?})");
            std::process::exit(2)
        }),
        None => 1_000_000,
    };
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/");
    println!("errors against 34-digit references [ε]: largest absolute node error, largest relative weight error");
    println!(
        "{:>8}  {:>22}  {:>22}",
        "m", "lgsvi-quadrature", "gauss-quad"
    );
    let small = read(&format!("{dir}gauss_legendre.txt"));
    for (&m, reference) in small.iter().filter(|(&m, _)| m >= 5) {
        let (a, b) = (
            errors(&ours(m), reference, false),
            errors(&theirs(m), reference, false),
        );
        check("Gauss–Legendre", m, a);
        println!(
            "{m:>8}  {:>9.2} {:>12.2}  {:>9.2} {:>12.2}",
            a.0, a.1, b.0, b.1
        );
    }
    let large = read(&format!("{dir}gauss_legendre_extremes.txt"));
    for (&m, reference) in &large {
        let (a, b) = (
            errors(&ours(m), reference, true),
            errors(&theirs(m), reference, true),
        );
        check("Gauss–Legendre, the largest nodes", m, a);
        println!(
            "{m:>8}  {:>9.2} {:>12.2}  {:>9.2} {:>12.2}   (the {} largest nodes)",
            a.0,
            a.1,
            b.0,
            b.1,
            reference.len()
        );
    }
    println!("\ntime to build the rule (best of 5)");
    println!(
        "{:>8}  {:>16}  {:>16}  {:>8}",
        "m", "lgsvi-quadrature", "gauss-quad", "ratio"
    );
    for m in [100usize, 1_000, 10_000, 100_000, 1_000_000]
        .into_iter()
        .filter(|&m| m <= max_m)
    {
        let (a, b) = (best_of_5(|| ours(m)), best_of_5(|| theirs(m)));
        println!(
            "{m:>8}  {:>13.3} ms  {:>13.3} ms  {:>8.2}",
            1e3 * a,
            1e3 * b,
            a / b
        );
    }
    classical(dir, max_m);
}

/// A classical family by name, ours and gauss-quad's, as ascending `(node, weight)` pairs.
fn classical_rule(family: &str, m: usize, ours_or_theirs: bool) -> Rule {
    use gauss_quad::{FiniteAboveNegOneF64 as Exponent, GaussHermite, GaussJacobi, GaussLaguerre};
    let n = NonZeroUsize::new(m).expect("m ≥ 1");
    let e = |x: f64| Exponent::new(x).expect("above −1");
    let mut pairs: Rule = match (family, ours_or_theirs) {
        ("hermite", true) => gauss_hermite(m).unwrap().iter().collect(),
        ("laguerre", true) => gauss_laguerre(m, 0.0).unwrap().iter().collect(),
        ("jacobi", true) => gauss_jacobi(m, 0.5, -0.5).unwrap().iter().collect(),
        ("hermite", false) => GaussHermite::new(n).iter().map(|(x, w)| (*x, *w)).collect(),
        ("laguerre", false) => GaussLaguerre::new(n, e(0.0))
            .iter()
            .map(|(x, w)| (*x, *w))
            .collect(),
        ("jacobi", false) => GaussJacobi::new(n, e(0.5), e(-0.5))
            .iter()
            .map(|(x, w)| (*x, *w))
            .collect(),
        _ => unreachable!(),
    };
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    pairs
}

/// `(family, m) → [(i, node, weight)]`.
type Classical = BTreeMap<(String, usize), Vec<(usize, f64, f64)>>;

/// The reference rows of Hermite, Laguerre α = 0 and Jacobi (½, −½).
fn read_classical(path: &str) -> Classical {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut table = Classical::new();
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let f: Vec<&str> = line.split_whitespace().collect();
        let wanted = matches!(
            (f[0], f[1]),
            ("hermite", "-") | ("laguerre", "0.0") | ("jacobi", "0.5,-0.5")
        );
        if wanted {
            table
                .entry((f[0].to_string(), f[2].parse().unwrap()))
                .or_default()
                .push((
                    f[3].parse().unwrap(),
                    f[4].parse().unwrap(),
                    f[5].parse().unwrap(),
                ));
        }
    }
    table
}

/// Node errors in ε of `max(|x|, 1)`, relative weight errors in ε (weights ≥ 1e-300).
fn classical_errors(rule: &Rule, reference: &[(usize, f64, f64)]) -> (f64, f64) {
    let (mut node, mut weight) = (0.0f64, 0.0f64);
    for &(i, x, w) in reference {
        node = node.max((rule[i].0 - x).abs() / x.abs().max(1.0));
        if w >= 1e-300 {
            weight = weight.max((rule[i].1 - w).abs() / w);
        }
    }
    (node / f64::EPSILON, weight / f64::EPSILON)
}

fn classical(dir: &str, max_m: usize) {
    println!(
        "\nHermite, Laguerre (α = 0), Jacobi (½, −½): errors against 34/30-digit references [ε]"
    );
    println!(
        "{:>10} {:>8}  {:>22}  {:>22}",
        "family", "m", "lgsvi-quadrature", "gauss-quad"
    );
    let mut table = read_classical(&format!("{dir}gauss_classical.txt"));
    table.extend(read_classical(&format!("{dir}gauss_classical_large.txt")));
    for ((family, m), reference) in &table {
        if ![100usize, 500, 1000, 10_000, 100_000].contains(m) {
            continue;
        }
        let a = classical_errors(&classical_rule(family, *m, true), reference);
        check(family, *m, a);
        let theirs = if *m <= 1000 {
            let b = classical_errors(&classical_rule(family, *m, false), reference);
            format!("{:>9.2} {:>12.2e}", b.0, b.1)
        } else {
            format!("{:>22}", "–")
        };
        println!("{family:>10} {m:>8}  {:>9.2} {:>12.2e}  {theirs}", a.0, a.1);
    }
    println!("\ntime to build the rule (best of 3)");
    println!(
        "{:>10} {:>8}  {:>16}  {:>16}",
        "family", "m", "lgsvi-quadrature", "gauss-quad"
    );
    for family in ["hermite", "laguerre", "jacobi"] {
        for m in [100usize, 1_000, 10_000, 100_000, 1_000_000]
            .into_iter()
            .filter(|&m| m <= max_m)
        {
            let best = |ours: bool| {
                (0..3)
                    .map(|_| {
                        let start = Instant::now();
                        std::hint::black_box(classical_rule(family, m, ours));
                        start.elapsed().as_secs_f64()
                    })
                    .fold(f64::INFINITY, f64::min)
            };
            let a = best(true);
            let theirs = if m <= 1000 {
                format!("{:>13.3} ms", 1e3 * best(false))
            } else {
                format!("{:>16}", "–")
            };
            println!("{family:>10} {m:>8}  {:>13.3} ms  {theirs}", 1e3 * a);
        }
    }
}
