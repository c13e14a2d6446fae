//! Gauss–Legendre rules of any size in `O(m)`: the asymptotic expansions of the nodes and
//! weights in the angle `θ = arccos x` (Tricomi's and Olver's expansions as arranged by
//! Hale and Townsend, 2013, in the form of FastGaussQuadrature.jl's `asy`), no iteration.
//!
//! With `ν = m + ½` and `j_k` the `k`-th zero of `J₀`, `a_k = j_k/ν` and `u = cot a_k`:
//!
//! - `θ_k = a_k + (u − 1/a)/8 · ν⁻² + v₁ ν⁻⁴ + v₄ ν⁻⁶` (`v₁`, `v₄` below), `x_k = cos θ_k`;
//! - `w_k = 2 / (J₁(j_k)² · (a/sin a) · (ν² + W₁ + W₂ ν⁻² + W₃ ν⁻⁴))`.
//!
//! Every term is kept at every `m` (FastGaussQuadrature.jl drops them as `m` grows, which
//! leaves the weights about `1e-13` off beyond `m = 850 000`). The zeros `j_k` and
//! `J₁(j_k)²` come from 20-digit tables for the first 20 and 10 (printed by
//! `tests/data/generate_bessel_tables.py` from mpmath), McMahon's expansions beyond.
//! Accuracy is pinned by the crate's tests against the 60-digit reference at `m = 100`
//! and `500` and against the Golub–Welsch-and-Newton rules up to `m = 4000`.

use crate::symmetric::{symmetric, Polished};
use std::f64::consts::PI;

/// `j_{0,k}`, `k = 1…20` (the digits as printed, rounded to doubles by the compiler).
#[allow(clippy::excessive_precision)]
const BESSEL_J0_ZEROS: [f64; 20] = [
    2.404_825_557_695_772_8,
    5.520_078_110_286_310_6,
    8.653_727_912_911_012,
    11.791_534_439_014_282,
    14.930_917_708_487_786,
    18.071_063_967_910_923,
    21.211_636_629_879_26,
    24.352_471_530_749_303,
    27.493_479_132_040_255,
    30.634_606_468_431_975,
    33.775_820_213_573_57,
    36.917_098_353_664_04,
    40.058_425_764_628_24,
    43.199_791_713_176_73,
    46.341_188_371_661_814,
    49.482_609_897_397_82,
    52.624_051_841_114_996,
    55.765_510_755_019_98,
    58.906_983_926_080_94,
    62.048_469_190_227_17,
];

/// `J₁(j_{0,k})²`, `k = 1…10`.
#[allow(clippy::excessive_precision)]
const BESSEL_J1_SQUARED: [f64; 10] = [
    0.269_514_123_941_916_93,
    0.115_780_138_582_203_7,
    0.073_686_351_136_408_22,
    0.054_037_573_198_116_28,
    0.042_661_429_017_243_09,
    0.035_242_103_490_996_1,
    0.030_021_070_103_054_673,
    0.026_147_391_495_308_09,
    0.023_159_121_824_691_392,
    0.020_783_829_122_267_858,
];

/// `Σ c_i x^i` by Horner's rule.
fn poly(x: f64, c: &[f64]) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ci| acc * x + ci)
}

/// `j_{0,k}` (`k ≥ 1`): the table, then McMahon's expansion (NIST DLMF 10.21.19) with
/// `β = (k − ¼)π`, whose first omitted term is below `1e-15` absolute from `k = 21` on.
fn bessel_j0_zero(k: usize) -> f64 {
    if k <= BESSEL_J0_ZEROS.len() {
        return BESSEL_J0_ZEROS[k - 1];
    }
    let beta = PI * (k as f64 - 0.25);
    let t = 0.125 / beta;
    let t2 = t * t;
    beta + t * poly(
        t2,
        &[
            1.0,
            -124.0 / 3.0,
            120_928.0 / 15.0,
            -401_743_168.0 / 105.0,
            1_071_187_749_376.0 / 315.0,
        ],
    )
}

/// `J₁(j_{0,k})²` (`k ≥ 1`): the table, then the expansion of FastGaussQuadrature.jl
/// (the Taylor series of DLMF 10.17.3 at McMahon's zeros) with every term.
fn bessel_j1_squared(k: usize) -> f64 {
    if k <= BESSEL_J1_SQUARED.len() {
        return BESSEL_J1_SQUARED[k - 1];
    }
    let beta = PI * (k as f64 - 0.25);
    let b2 = 1.0 / (beta * beta);
    let tail = poly(
        b2,
        &[
            -7.0 / 24.0,
            151.0 / 80.0,
            -172_913.0 / 8064.0,
            461_797.0 / 1152.0,
            -171_497_088_497.0 / 15_206_400.0,
        ],
    );
    (2.0 + b2 * b2 * tail) / (PI * beta)
}

/// `(x_k, w_k)` for `k = 1…⌈m/2⌉`, `x_k = cos θ_k` descending from near 1 (module
/// documentation).
fn upper_half(m: usize, k: usize) -> (f64, f64) {
    let nu_inv = 1.0 / (m as f64 + 0.5);
    let (v2, v4) = (nu_inv * nu_inv, nu_inv.powi(4));
    let v6 = v4 * v2;
    let a = bessel_j0_zero(k) * nu_inv;
    let (sin_a, cos_a) = a.sin_cos();
    let u = cos_a / sin_a;
    let u2 = u * u;
    let (a2, a3) = (a * a, a * a * a);
    let a5 = a3 * a2;

    let theta1 = (u - 1.0 / a) / 8.0;
    let theta2 = (6.0 * (1.0 + u2) / a + 25.0 / a3 - u * (31.0 * u2 + 33.0)) / 384.0;
    let theta3 = u * poly(u2, &[2595.0 / 15360.0, 6350.0 / 15360.0, 3779.0 / 15360.0])
        - 1073.0 / 5120.0 / a5
        + (1.0 + u2)
            * (-(31.0 / 1024.0 * u2 + 11.0 / 1024.0) / a + u / 512.0 / a2 - 25.0 / 3072.0 / a3);
    let theta = a + theta1 * v2 + theta2 * v4 + theta3 * v6;

    let ua = u * a;
    let inv_a = 1.0 / a;
    let inv_a2 = inv_a * inv_a;
    let w1 = ((ua - 1.0) * inv_a2 + 1.0) / 8.0;
    let w2 = poly(
        inv_a2,
        &[
            poly(u2, &[-27.0, -84.0, -56.0]),
            -3.0 * (1.0 - 2.0 * u2) + 6.0 * ua,
            81.0 - 31.0 * ua,
        ],
    ) / 384.0;
    let w3 = poly(
        inv_a,
        &[
            poly(
                u2,
                &[153.0 / 1024.0, 295.0 / 256.0, 187.0 / 96.0, 151.0 / 160.0],
            ),
            poly(u2, &[-65.0 / 1024.0, -119.0 / 768.0, -35.0 / 384.0]) * u,
            poly(u2, &[5.0 / 512.0, 15.0 / 512.0, 7.0 / 384.0]),
            (u2 / 512.0 - 13.0 / 1536.0) * u,
            53.0 / 3072.0 - 7.0 / 384.0 * u2,
            3749.0 / 15360.0 * u,
            -1125.0 / 1024.0,
        ],
    );
    let big = 1.0 / v2 + w1 + w2 * v2 + w3 * v4;
    let weight = 2.0 / (bessel_j1_squared(k) * (a / sin_a) * big);
    (theta.cos(), weight)
}

/// From this many points on, [`crate::gauss_legendre`] uses the expansions (below it
/// they lose accuracy: 47ε in the nodes at `m = 40`).
pub(crate) const ASYMPTOTIC_FROM: usize = 100;

/// The `m`-point Gauss–Legendre nodes (ascending, exactly symmetric, `0` exactly for odd
/// `m`) and weights by the asymptotic expansions, in `O(m)`.
pub(crate) fn gauss_legendre_asymptotic(m: usize) -> (Vec<f64>, Vec<f64>) {
    symmetric(m, |i| {
        // `i` counts from the largest node: the `(i + 1)`-th zero of `J₀`.
        let (node, weight) = upper_half(m, i + 1);
        Polished {
            // The middle node of an odd rule is 0 exactly (P_m is odd).
            node: if 2 * i + 1 == m { 0.0 } else { node },
            weight,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::double_double::DoubleDouble;
    use crate::rules::{gauss_legendre_golub_welsch, gauss_legendre_node};

    const EPS: f64 = f64::EPSILON;

    /// Max absolute node difference and max relative weight difference, in ε.
    fn differences(x: &[f64], w: &[f64], y: &[f64], v: &[f64]) -> (f64, f64) {
        let node = x
            .iter()
            .zip(y)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let weight = w
            .iter()
            .zip(v)
            .map(|(a, b)| ((a - b) / b).abs())
            .fold(0.0, f64::max);
        (node / EPS, weight / EPS)
    }

    /// Against the Golub–Welsch rules polished by Newton in double-double (within 4ε and
    /// 8ε of the 60-digit reference, `tests/reference.rs`) from the switch on: within
    /// 2.6ε in the nodes and 4.9ε in the weights up to m = 4000, so the asymptotic
    /// rules keep the crate's contract (4ε, 8ε) with the polished rules' own error added.
    /// Below the switch the expansions lose accuracy (m = 40: 47ε, 185ε), which is why
    /// the rules there stay Golub–Welsch.
    #[test]
    fn asymptotic_rules_agree_with_the_polished_ones() {
        for m in [ASYMPTOTIC_FROM, 150, 300, 1000, 4000] {
            let (x, w) = gauss_legendre_asymptotic(m);
            let r = gauss_legendre_golub_welsch(m).unwrap();
            let (node, weight) = differences(&x, &w, r.nodes(), r.weights());
            println!("m = {m}: nodes {node:.2} ε, weights {weight:.2} ε");
            assert!(
                node <= 3.0 && weight <= 6.0,
                "m = {m}: {node} ε, {weight} ε"
            );
        }
    }

    /// At sizes Golub–Welsch cannot reach, sampled nodes (both ends, the middle, a spread)
    /// polished from the asymptotic values by Newton on `P_m` with the double-double
    /// evaluation of the Golub–Welsch path (`O(m)` per node): the asymptotic nodes and
    /// weights keep the contract, 4ε and 8ε.
    #[test]
    fn asymptotic_rules_keep_the_contract_at_a_million_points() {
        for m in [10_000, 100_000, 1_000_000] {
            let (x, w) = gauss_legendre_asymptotic(m);
            let half = m.div_ceil(2);
            let mut sample: Vec<usize> = (0..8).chain(half - 4..half).collect();
            sample.extend((1..12).map(|j| j * half / 12));
            let (mut node, mut weight) = (0.0f64, 0.0f64);
            for i in sample {
                // Index from the right end: the largest nodes first.
                let index = m - 1 - i;
                if 1.0 - x[index] < 1e-6 {
                    // Where 1 − x is tiny, the polished weight (at the node rounded to a
                    // double, corrected to first order) is itself off: 176ε at m = 1e5,
                    // i = 0, where the expansions agree with 40-digit mpmath to 1 ulp.
                    // Those nodes are checked against mpmath below.
                    continue;
                }
                let polished = gauss_legendre_node(m, x[index]);
                node = node.max((x[index] - polished.node).abs() / EPS);
                weight = weight.max(((w[index] - polished.weight) / polished.weight).abs() / EPS);
            }
            println!("m = {m}: sampled nodes {node:.2} ε, weights {weight:.2} ε");
            assert!(
                node <= 4.0 && weight <= 8.0,
                "m = {m}: {node} ε, {weight} ε"
            );
        }
    }

    /// The three largest nodes at m = 1e5 and 1e6 (`1 − x` down to 5e-12), where a
    /// double-precision weight formula at the rounded node loses digits, against 40-digit
    /// mpmath (`tests/data/generate_legendre_extremes.py`).
    #[test]
    fn the_extreme_nodes_match_mpmath() {
        let text = include_str!("../tests/data/gauss_legendre_extremes.txt");
        let mut rules = std::collections::BTreeMap::new();
        let mut checked = 0;
        for line in text.lines().filter(|l| !l.starts_with('#')) {
            let v: Vec<&str> = line.split_whitespace().collect();
            let (m, i): (usize, usize) = (v[0].parse().unwrap(), v[1].parse().unwrap());
            let (x, w): (f64, f64) = (v[2].parse().unwrap(), v[3].parse().unwrap());
            let (nodes, weights) = rules
                .entry(m)
                .or_insert_with(|| gauss_legendre_asymptotic(m));
            let index = m - 1 - i;
            let node = (nodes[index] - x).abs() / EPS;
            let weight = ((weights[index] - w) / w).abs() / EPS;
            println!("m = {m}, i = {i}: node {node:.2} ε, weight {weight:.2} ε");
            assert!(
                node <= 4.0 && weight <= 8.0,
                "m = {m}, i = {i}: {node} ε, {weight} ε"
            );
            checked += 1;
        }
        assert_eq!(checked, 6);
    }

    /// Laws at a million points: symmetric, ascending inside (−1, 1), weights positive and
    /// summing to 2, and `∫x² = 2/3`, `∫x⁴ = 2/5` to the rounding of a million-term sum.
    #[test]
    fn a_million_point_rule_integrates_polynomials() {
        let m = 1_000_001;
        let (x, w) = gauss_legendre_asymptotic(m);
        assert_eq!(x[m / 2], 0.0);
        assert!(x.windows(2).all(|p| p[0] < p[1]) && x[0] > -1.0 && x[m - 1] < 1.0);
        assert!((0..m).all(|i| x[i] == -x[m - 1 - i] && w[i] == w[m - 1 - i] && w[i] > 0.0));
        let sum = |f: &dyn Fn(f64) -> f64| -> f64 {
            let mut s = DoubleDouble::from_f64(0.0);
            for (xi, wi) in x.iter().zip(&w) {
                s = s.add(DoubleDouble::from_f64(wi * f(*xi)));
            }
            s.to_f64()
        };
        // Each weight within 8ε, so each sum within 8ε of its value; 1e-14 is 45ε.
        assert!((sum(&|_| 1.0) - 2.0).abs() <= 1e-14);
        assert!((sum(&|x| x * x) - 2.0 / 3.0).abs() <= 1e-14);
        assert!((sum(&|x| x.powi(4)) - 0.4).abs() <= 1e-14);
    }
}
