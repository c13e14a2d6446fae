//! Gauss–Hermite, –Laguerre, –Jacobi and –Chebyshev rules against the 60-digit mpmath
//! reference `tests/data/gauss_classical.txt`, printed by the committed script
//! `tests/data/generate_classical.py` (Newton at 60 digits from scipy's nodes, weights from
//! the families' closed forms: independent of this crate). Run with `--nocapture` to see
//! the measured errors per family and m.

use lgsvi_quadrature::{
    gauss_chebyshev_first, gauss_chebyshev_second, gauss_hermite, gauss_jacobi, gauss_laguerre,
    Rule,
};
use std::collections::BTreeMap;

const EPS: f64 = f64::EPSILON;

/// `(family, params, m)` → `[(i, node, weight)]`.
type Table = BTreeMap<(String, String, usize), Vec<(usize, f64, f64)>>;

fn table() -> Table {
    parse(include_str!("data/gauss_classical.txt"))
}

/// Lines `family params m i node weight`, `#` for comments.
fn parse(text: &str) -> Table {
    let mut out = Table::new();
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let f: Vec<&str> = line.split_whitespace().collect();
        let key = (f[0].to_string(), f[1].to_string(), f[2].parse().unwrap());
        out.entry(key).or_default().push((
            f[3].parse().unwrap(),
            f[4].parse().unwrap(),
            f[5].parse().unwrap(),
        ));
    }
    out
}

fn build(family: &str, params: &str, m: usize) -> Rule {
    let p: Vec<f64> = params
        .split(',')
        .filter(|s| *s != "-")
        .map(|s| s.parse().unwrap())
        .collect();
    match family {
        "hermite" => gauss_hermite(m),
        "laguerre" => gauss_laguerre(m, p[0]),
        "jacobi" => gauss_jacobi(m, p[0], p[1]),
        "chebyshev1" => gauss_chebyshev_first(m),
        "chebyshev2" => gauss_chebyshev_second(m),
        other => panic!("unknown family {other}"),
    }
    .unwrap()
}

/// Node errors in ε relative to `max(|x|, 1)`, weight errors in ε relative (weights at or
/// above 1e-300 only), the largest over the tabulated indices.
fn errors(rule: &Rule, rows: &[(usize, f64, f64)]) -> (f64, f64) {
    let (mut node, mut weight) = (0.0f64, 0.0f64);
    for &(i, x, w) in rows {
        node = node.max((rule.nodes()[i] - x).abs() / x.abs().max(1.0) / EPS);
        if w >= 1e-300 {
            weight = weight.max(((rule.weights()[i] - w) / w).abs() / EPS);
        }
    }
    (node, weight)
}

/// Every family and size of the reference: the measured errors, printed, and the bounds
/// they are held to.
#[test]
fn classical_rules_match_the_reference() {
    let table = table();
    assert!(table.len() > 100, "{} rules", table.len());
    let mut worst: BTreeMap<(String, String), (f64, f64, usize, usize)> = BTreeMap::new();
    println!("family params m: node error [ε·max(|x|,1)], weight error [ε, relative]");
    for ((family, params, m), rows) in &table {
        let rule = build(family, params, *m);
        assert_eq!(rule.num_points(), *m);
        let (node, weight) = errors(&rule, rows);
        println!("{family} {params} {m}: {node:.1} {weight:.1}");
        let entry = worst.entry((family.clone(), params.clone())).or_default();
        if node > entry.0 {
            (entry.0, entry.2) = (node, *m);
        }
        if weight > entry.1 {
            (entry.1, entry.3) = (weight, *m);
        }
    }
    for ((family, params), (node, weight, at_node, at_weight)) in &worst {
        // m = 0 marks a family whose every value matched exactly.
        let at = |m: &usize| {
            if *m == 0 {
                "all exact".to_string()
            } else {
                format!("m = {m}")
            }
        };
        println!(
            "worst {family} {params}: nodes {node:.1}ε ({}), weights {weight:.1}ε ({})",
            at(at_node),
            at(at_weight)
        );
        // Nodes: the double nearest the root found from the double-double residual, so
        // within an ulp or two; the bound is 4.
        assert!(
            *node <= 4.0,
            "{family} {params}: nodes off by {node:.1}ε at m = {at_node}"
        );
        // Weights: the Christoffel sum in double-double, μ₀ from the Gamma function
        // (a few ulps) and the first-order move to the true root: a few ε; 16ε leaves room
        // for the Gamma function's rounding, far inside the 1e-14 (45ε).
        assert!(
            *weight <= 16.0,
            "{family} {params}: weights off by {weight:.1}ε at m = {at_weight}"
        );
    }
    // Every family and size the script writes is here.
    for family in ["hermite", "laguerre", "jacobi", "chebyshev1", "chebyshev2"] {
        let sizes: Vec<usize> = table
            .keys()
            .filter(|k| k.0 == family)
            .map(|k| k.2)
            .collect();
        assert!(
            sizes.contains(&1) && sizes.contains(&1000),
            "{family}: {sizes:?}"
        );
    }
}

/// Laws that need no reference: each rule integrates its weight's moments exactly up to
/// degree `2m − 1` (the moments in closed form), and symmetric weights give mirrored nodes.
#[test]
fn classical_rules_integrate_their_moments() {
    use std::f64::consts::PI;
    let gamma = lanczos_gamma;
    for m in [1usize, 2, 5, 12, 30] {
        let hermite = gauss_hermite(m).unwrap();
        let laguerre = gauss_laguerre(m, 0.7).unwrap();
        let jacobi = gauss_jacobi(m, 1.5, -0.25).unwrap();
        // Each sum's rounding: x^k to about k ulps, m terms; so the tolerance is
        // (k + m)·4ε times the sum of the terms' magnitudes (odd Hermite moments cancel
        // to 0 from terms of size Γ(k/2)).
        let bound = |rule: &Rule, k: usize| {
            4.0 * EPS * (k + m) as f64 * rule.integrate(|x| x.powi(k as i32).abs())
        };
        for k in 0..2 * m {
            let h = hermite.integrate(|x| x.powi(k as i32));
            let exact_h = if k % 2 == 1 {
                0.0
            } else {
                gamma((k as f64 + 1.0) / 2.0)
            };
            // The Lanczos Γ of the test itself is good to about 1e-15 relative.
            let tol_h = bound(&hermite, k) + 1e-15 * exact_h;
            assert!((h - exact_h).abs() <= tol_h, "H m {m} k {k}: {h} {exact_h}");
            let l = laguerre.integrate(|x| x.powi(k as i32));
            let exact_l = gamma(k as f64 + 1.7);
            let tol_l = bound(&laguerre, k) + 1e-15 * exact_l;
            assert!((l - exact_l).abs() <= tol_l, "L m {m} k {k}: {l} {exact_l}");
        }
        // Jacobi (1 − x)^a (1 + x)^b: x-moments by a rule of higher order as the check
        // (exact for degree 2·40 − 1), the mass in closed form.
        let fine = gauss_jacobi(40, 1.5, -0.25).unwrap();
        for k in 0..2 * m {
            let j = jacobi.integrate(|x| x.powi(k as i32));
            let f = fine.integrate(|x| x.powi(k as i32));
            assert!(
                (j - f).abs() <= bound(&fine, k) + bound(&jacobi, k),
                "J m {m} k {k}: {j} {f}"
            );
        }
        let mass = 2f64.powf(2.25) * gamma(2.5) * gamma(0.75) / gamma(3.25);
        assert!((jacobi.integrate(|_| 1.0) - mass).abs() <= 1e-14 * mass);
        for rule in [
            gauss_chebyshev_first(m).unwrap(),
            gauss_chebyshev_second(m).unwrap(),
        ] {
            let first = rule.weight_exponents() == Some((-0.5, -0.5));
            // ∫ x^{2j} w = π (2j−1)!!/(2j)!!, times 1/(2j+2) more for the second kind.
            let mut ratio = 1.0;
            for j in 0..m {
                if j > 0 {
                    ratio *= (2 * j - 1) as f64 / (2 * j) as f64;
                }
                let exact = if first {
                    PI * ratio
                } else {
                    PI * ratio / (2 * j + 2) as f64
                };
                let value = rule.integrate(|x| x.powi(2 * j as i32));
                assert!(
                    (value - exact).abs() <= 1e-14,
                    "Chebyshev m {m} j {j}: {value} {exact}"
                );
            }
        }
        for rule in [&hermite, &gauss_jacobi(m, 0.3, 0.3).unwrap()] {
            let n = rule.nodes();
            assert!((0..m).all(|i| n[i] == -n[m - 1 - i]));
        }
    }
}

/// Γ by the reflection-free Lanczos approximation (g = 7, n = 9), accurate to ~1e-15 for
/// the arguments above (0.5 … 60): the test's own, not the crate's.
fn lanczos_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + G + 0.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    (2.0 * std::f64::consts::PI).sqrt() * t.powf(x + 0.5) * (-t).exp() * a
}

/// Refusals: no points, exponents at or below −1 or not finite, a Hermite or Laguerre rule
/// mapped to a finite interval, a weighted rule on a reversed one. A Jacobi rule maps with
/// its weight: on [a, b] it integrates (b − x)^α (x − a)^β.
#[test]
fn classical_rules_refuse_what_they_cannot_do() {
    use lgsvi_quadrature::QuadratureError;
    assert!(matches!(
        gauss_hermite(0),
        Err(QuadratureError::TooFewPoints { .. })
    ));
    for bad in [-1.0, -2.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            gauss_laguerre(3, bad),
            Err(QuadratureError::InvalidExponent { name: "alpha", .. })
        ));
        assert!(matches!(
            gauss_jacobi(3, 0.0, bad),
            Err(QuadratureError::InvalidExponent { name: "beta", .. })
        ));
    }
    assert!(matches!(
        gauss_hermite(4).unwrap().on(0.0, 1.0),
        Err(QuadratureError::UnboundedRule { .. })
    ));
    assert!(matches!(
        gauss_laguerre(4, 0.0).unwrap().on(0.0, 1.0),
        Err(QuadratureError::UnboundedRule { .. })
    ));
    assert!(matches!(
        gauss_jacobi(4, 0.5, 0.5).unwrap().on(1.0, 0.0),
        Err(QuadratureError::ReversedWeight { .. })
    ));
    // ∫_0^2 (2 − x)^1 x^2 dx = 4/3: a = 0, b = 2, α = 1, β = 2.
    let rule = gauss_jacobi(3, 1.0, 2.0).unwrap().on(0.0, 2.0).unwrap();
    assert!((rule.integrate(|_| 1.0) - 4.0 / 3.0).abs() < 1e-15);
    assert_eq!(rule.interval(), (0.0, 2.0));
    assert_eq!(
        gauss_hermite(2).unwrap().interval(),
        (f64::NEG_INFINITY, f64::INFINITY)
    );
}

/// Rules of 10⁴ and 10⁵ points (the `O(m)` march) against the 40-digit mpmath reference
/// `tests/data/gauss_classical_large.txt` (`tests/data/generate_classical_large.py`: each
/// sampled root bracketed by bisection on the Sturm count of the three-term recurrence,
/// refined by Newton at 40 digits, its weight from the family's closed form): both ends
/// and five indices between, for Hermite, Laguerre (α = 0, 2) and Jacobi ((½, −½),
/// (−0.7, 0.3), (1.5, 1.5)).
#[test]
fn large_rules_match_the_reference() {
    let table = parse(include_str!("data/gauss_classical_large.txt"));
    assert_eq!(table.len(), 12, "six weights at two sizes");
    for ((family, params, m), rows) in &table {
        let rule = build(family, params, *m);
        assert_eq!(rule.num_points(), *m);
        let (node, weight) = errors(&rule, rows);
        println!("{family} {params} {m}: nodes {node:.1}ε, weights {weight:.1}ε");
        // The same bounds as the rules up to 1000 points: the march carries y and y' in
        // double-double, so nothing accumulates over the 10⁵ roots.
        assert!(
            node <= 4.0,
            "{family} {params} {m}: nodes off by {node:.1}ε"
        );
        assert!(
            weight <= 16.0,
            "{family} {params} {m}: weights off by {weight:.1}ε"
        );
        // Ascending, inside the interval, positive (or underflowed) weights.
        let (a, b) = rule.interval();
        assert!(rule.nodes().windows(2).all(|w| w[0] < w[1]));
        assert!(rule.nodes().iter().all(|&x| x > a && x < b));
        assert!(rule.weights().iter().all(|&w| w >= 0.0));
    }
}
