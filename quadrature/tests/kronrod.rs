//! Gauss–Kronrod pairs against the 150-digit mpmath reference `tests/data/gauss_kronrod.txt`
//! (`generate_kronrod.py`: the Stieltjes polynomial from its definition, weights from the
//! exactness conditions — not Laurie's algorithm, which the crate uses).

use lgsvi_quadrature::{gauss_kronrod, QuadratureError};

const EPS: f64 = f64::EPSILON;

#[test]
fn kronrod_rules_match_the_reference() {
    let text = include_str!("data/gauss_kronrod.txt");
    let mut table: std::collections::BTreeMap<usize, Vec<(f64, f64, f64)>> = Default::default();
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let f: Vec<&str> = line.split_whitespace().collect();
        table.entry(f[0].parse().unwrap()).or_default().push((
            f[2].parse().unwrap(),
            f[3].parse().unwrap(),
            f[4].parse().unwrap(),
        ));
    }
    assert!(table.contains_key(&7) && table.contains_key(&30));
    println!(
        "n: node error [ε], Kronrod weight error [ε relative], Gauss weight error [ε relative]"
    );
    for (n, rows) in &table {
        let pair = gauss_kronrod(*n).unwrap();
        let rule = pair.kronrod();
        assert_eq!(rule.num_points(), 2 * n + 1);
        let (mut node, mut kw, mut gw) = (0.0f64, 0.0f64, 0.0f64);
        for (i, &(x, wk, wg)) in rows.iter().enumerate() {
            node = node.max((rule.nodes()[i] - x).abs() / EPS);
            kw = kw.max(((rule.weights()[i] - wk) / wk).abs() / EPS);
            if wg == 0.0 {
                assert_eq!(pair.gauss_weights()[i], 0.0);
            } else {
                gw = gw.max(((pair.gauss_weights()[i] - wg) / wg).abs() / EPS);
            }
        }
        println!("{n}: {node:.1} {kw:.1} {gw:.1}");
        // Nodes: Golub–Welsch eigenvalues of a matrix of norm ≤ 1 (the added nodes) and the
        // polished Gauss nodes: a few ulps.
        assert!(node <= 4.0, "n = {n}: nodes off by {node:.1}ε");
        // Weights: Christoffel numbers in double-double of Laurie's recurrence, itself in
        // double-double: a few ε.
        assert!(kw <= 4.0, "n = {n}: Kronrod weights off by {kw:.1}ε");
        assert!(gw <= 8.0, "n = {n}: Gauss weights off by {gw:.1}ε");
        assert_eq!(rule.degree_of_exactness(), 3 * n + 1 + n % 2);
    }
}

/// The pair's estimate: on a polynomial of degree 2n the Gauss rule errs and the Kronrod
/// rule does not; on [a, b] and backwards, as Rule::on.
#[test]
fn the_pair_estimates_the_gauss_error() {
    assert!(matches!(
        gauss_kronrod(0),
        Err(QuadratureError::TooFewPoints { .. })
    ));
    let pair = gauss_kronrod(5).unwrap().on(0.0, 2.0).unwrap();
    // ∫_0^2 x^10 dx = 2^11/11: degree 10 = 2n, beyond the 5-point Gauss rule.
    let exact = 2f64.powi(11) / 11.0;
    let (k, estimate) = pair.integrate(|x| x.powi(10));
    assert!((k - exact).abs() <= 8.0 * EPS * exact);
    let gauss: f64 = pair
        .kronrod()
        .nodes()
        .iter()
        .zip(pair.gauss_weights())
        .map(|(x, w)| w * x.powi(10))
        .sum();
    assert!(((gauss - exact).abs() - estimate).abs() <= 8.0 * EPS * exact);
    // The 5-point Gauss rule misses x^10 by 1.57e-5 of the value (numpy's leggauss): the
    // estimate is that miss.
    assert!((estimate / exact - 1.5747e-5).abs() < 1e-9);
    let back = gauss_kronrod(5).unwrap().on(2.0, 0.0).unwrap();
    let (kb, eb) = back.integrate(|x| x.powi(10));
    assert!((kb + exact).abs() <= 8.0 * EPS * exact && (eb - estimate).abs() <= 8.0 * EPS * exact);
}

/// Gauss–Kronrod–Jacobi pairs against the 150-digit mpmath reference
/// `tests/data/gauss_kronrod_jacobi.txt` (`generate_kronrod_jacobi.py`: the Stieltjes
/// polynomial from its definition against the weight `P_n (1 − x)^α (1 + x)^β`, weights from
/// the exactness conditions, not Laurie's algorithm): six weights, `n` from 1 to 20; where
/// the reference finds no extension with real nodes inside `(−1, 1)` and positive weights,
/// the crate refuses with `NoKronrodExtension`.
#[test]
fn kronrod_jacobi_rules_match_the_reference() {
    use lgsvi_quadrature::gauss_kronrod_jacobi;
    let text = include_str!("data/gauss_kronrod_jacobi.txt");
    type Key = (String, usize);
    let mut table: std::collections::BTreeMap<Key, Vec<(f64, f64, f64)>> = Default::default();
    let mut none = Vec::new();
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let f: Vec<&str> = line.split_whitespace().collect();
        let key = (f[0].to_string(), f[1].parse().unwrap());
        if f[2] == "none" {
            none.push(key);
            continue;
        }
        table.entry(key).or_default().push((
            f[3].parse().unwrap(),
            f[4].parse().unwrap(),
            f[5].parse().unwrap(),
        ));
    }
    assert!(
        table.len() > 30 && none.len() >= 10,
        "{} {}",
        table.len(),
        none.len()
    );
    let exponents = |name: &str| -> (f64, f64) {
        let (a, b) = name.split_once(',').unwrap();
        (a.parse().unwrap(), b.parse().unwrap())
    };
    for (name, n) in &none {
        let (a, b) = exponents(name);
        assert!(
            matches!(
                gauss_kronrod_jacobi(*n, a, b),
                Err(QuadratureError::NoKronrodExtension { .. })
            ),
            "({a}, {b}) n = {n}: the reference has no extension"
        );
    }
    for ((name, n), rows) in &table {
        let (a, b) = exponents(name);
        let pair = gauss_kronrod_jacobi(*n, a, b).unwrap();
        let rule = pair.kronrod();
        assert_eq!(rule.num_points(), 2 * n + 1);
        let (mut node, mut kw, mut gw) = (0.0f64, 0.0f64, 0.0f64);
        for (i, &(x, wk, wg)) in rows.iter().enumerate() {
            node = node.max((rule.nodes()[i] - x).abs() / EPS);
            kw = kw.max(((rule.weights()[i] - wk) / wk).abs() / EPS);
            if wg == 0.0 {
                assert_eq!(pair.gauss_weights()[i], 0.0);
            } else {
                gw = gw.max(((pair.gauss_weights()[i] - wg) / wg).abs() / EPS);
            }
        }
        println!("({a}, {b}) n = {n}: nodes {node:.1}ε, Kronrod weights {kw:.1}ε, Gauss weights {gw:.1}ε");
        // As the Legendre pairs, with the mass Γ-function's rounding (a few ε) in every
        // weight: nodes a few ulps, weights 16ε (the classical rules' bound).
        assert!(node <= 4.0, "({a}, {b}) n = {n}: nodes off by {node:.1}ε");
        assert!(
            kw <= 16.0,
            "({a}, {b}) n = {n}: Kronrod weights off by {kw:.1}ε"
        );
        assert!(
            gw <= 16.0,
            "({a}, {b}) n = {n}: Gauss weights off by {gw:.1}ε"
        );
    }
}
