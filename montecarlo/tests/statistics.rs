//! The quantile sketch against exact sample quantiles (sorted samples): within its stated
//! relative error for every percentile, over normal, log-normal (values over twelve
//! decades), signed data with zeros and NaNs; the same counts however the values are split
//! and merged; and its size over 10⁵ values.

use lgsvi_montecarlo::statistics::{Envelope, Quantiles, RELATIVE_ERROR};
use rand::SeedableRng;
use rand_distr::{Distribution, LogNormal, Normal};

fn sample(kind: &str, n: usize, seed: u64) -> Vec<f64> {
    let mut rng = rand_chacha::ChaCha12Rng::seed_from_u64(seed);
    match kind {
        "normal" => {
            let d = Normal::new(0.3, 2.0).unwrap();
            (0..n).map(|_| d.sample(&mut rng)).collect()
        }
        // exp(N(0, 6²)): values from about 1e-12 to 1e12 at 10⁵ draws.
        "lognormal" => {
            let d = LogNormal::new(0.0, 6.0).unwrap();
            (0..n).map(|_| d.sample(&mut rng)).collect()
        }
        // A third exact zeros, the rest of both signs and many sizes.
        _ => {
            let d = LogNormal::new(0.0, 3.0).unwrap();
            (0..n)
                .map(|i| match i % 3 {
                    0 => 0.0,
                    1 => d.sample(&mut rng),
                    _ => -d.sample(&mut rng),
                })
                .collect()
        }
    }
}

/// The `⌈qN⌉`-th smallest (the smallest for `q = 0`).
fn exact(sorted: &[f64], q: f64) -> f64 {
    let n = sorted.len();
    let rank = ((q * n as f64).ceil() as usize).clamp(1, n);
    sorted[rank - 1]
}

#[test]
fn every_percentile_is_within_the_stated_relative_error() {
    assert!((RELATIVE_ERROR - (2f64.powf(1.0 / 128.0) - 1.0)).abs() < 1e-17);
    for kind in ["normal", "lognormal", "signed"] {
        for n in [1, 2, 7, 1000, 100_000] {
            let values = sample(kind, n, n as u64);
            let mut sketch = Quantiles::new();
            values.iter().for_each(|&x| sketch.add(x));
            let mut sorted = values.clone();
            sorted.sort_by(f64::total_cmp);
            assert_eq!(sketch.count(), n as u64);
            for k in 0..=1000 {
                let q = k as f64 / 1000.0;
                let (got, want) = (sketch.quantile(q).unwrap(), exact(&sorted, q));
                let bound = RELATIVE_ERROR * want.abs() * (1.0 + 1e-12);
                assert!(
                    (got - want).abs() <= bound,
                    "{kind}, N = {n}, q = {q}: {got:e} against {want:e}"
                );
                if want == 0.0 {
                    assert_eq!(got, 0.0);
                }
            }
        }
    }
}

#[test]
fn merging_gives_the_same_counts_in_any_order_and_size_stays_bounded() {
    let values = sample("signed", 100_000, 5);
    let mut whole = Quantiles::new();
    values.iter().for_each(|&x| whole.add(x));
    // Split in chunks of different sizes, merged forwards and backwards.
    for chunk in [1, 7, 1000, 33_333] {
        let parts: Vec<Quantiles> = values
            .chunks(chunk)
            .map(|c| {
                let mut q = Quantiles::new();
                c.iter().for_each(|&x| q.add(x));
                q
            })
            .collect();
        let mut forward = Quantiles::new();
        parts.iter().for_each(|p| forward.merge(p));
        let mut backward = Quantiles::new();
        parts.iter().rev().for_each(|p| backward.merge(p));
        assert_eq!(forward, whole);
        assert_eq!(backward, whole);
    }
    // 10⁵ values over about 10 decades of both signs: a few thousand bins at most
    // (64 a factor of two), not one per value.
    assert!(whole.bins() < 4000, "{}", whole.bins());
    // NaN and infinities are counted apart and take no rank.
    let mut q = Quantiles::new();
    for x in [f64::NAN, 1.0, f64::INFINITY, 2.0, f64::NEG_INFINITY] {
        q.add(x);
    }
    assert_eq!((q.count(), q.non_finite()), (2, 3));
    assert!((q.quantile(1.0).unwrap() - 2.0).abs() <= RELATIVE_ERROR * 2.0);
    assert_eq!(Quantiles::new().quantile(0.5), None);
    assert_eq!(q.quantile(1.5), None);
}

#[test]
fn an_envelope_merges_channel_by_channel() {
    let mut a = Envelope::new(&["x", "y"], 3);
    let mut b = Envelope::new(&["x", "y"], 3);
    for k in 0..3 {
        a.add(0, k, 1.0 + k as f64);
        b.add(0, k, 10.0 + k as f64);
        b.add(1, k, -5.0);
    }
    a.merge(&b);
    assert_eq!(a.at(0, 2).count(), 2);
    assert_eq!(a.at(1, 0).count(), 1);
    assert!((a.at(0, 1).quantile(1.0).unwrap() - 11.0).abs() <= 11.0 * RELATIVE_ERROR);
    assert_eq!(a.channels(), ["x", "y"]);
}

#[test]
fn an_envelope_serializes_to_the_same_counts_and_refuses_a_broken_shape() {
    let mut envelope = Envelope::new(&["a", "b"], 3);
    for (i, x) in sample("normal", 500, 9).into_iter().enumerate() {
        envelope.add(i % 2, i % 3, x);
    }
    let text = serde_json::to_string(&envelope).unwrap();
    let back: Envelope = serde_json::from_str(&text).unwrap();
    assert_eq!(back, envelope);
    let mut other = Envelope::new(&["a", "b"], 2);
    assert!(!envelope.same_shape(&other));
    other = Envelope::new(&["a", "b"], 3);
    assert!(envelope.same_shape(&other));
    let broken = r#"{"channels": ["a", "b"], "samples": 3, "sketches": []}"#;
    let error = serde_json::from_str::<Envelope>(broken).unwrap_err();
    assert!(error.to_string().contains("not their product"), "{error}");
}

/// A gyrostat's envelope: the attitude channels and one per wheel, each wheel's rate
/// counted at every sample; a member's samples cut to the last.
#[test]
fn a_gyrostat_envelope_counts_each_wheel_and_samples_keep_their_last() {
    use lgsvi_montecarlo::statistics::{Samples, ATTITUDE_CHANNELS};
    use nalgebra::{Matrix3, Vector3};
    let envelope = Envelope::of_attitude_and_wheels(3, 2);
    assert_eq!(envelope.channels().len(), ATTITUDE_CHANNELS.len() + 2);
    assert_eq!(envelope.channels()[6], "wheel_2");
    let run = |speed: f64| Samples {
        times: vec![0.0, 1.0, 2.0],
        attitudes: vec![Matrix3::identity(); 3],
        omegas: vec![Vector3::zeros(); 3],
        energies: vec![1.0; 3],
        wheel_speeds: (0..3).map(|k| vec![speed * k as f64, -speed]).collect(),
    };
    let mut envelope = envelope;
    let nominal = run(0.0);
    for speed in [1.0, 2.0, 3.0, 4.0, 5.0] {
        envelope.add_attitude_samples(&nominal, &run(speed));
    }
    // At the last sample wheel 1 spins at 2 × speed: the median of 2, 4, … 10 is 6 (the
    // sketch's relative error aside); wheel 2's at −3.
    let median = |channel: usize| envelope.at(channel, 2).quantile(0.5).unwrap();
    assert!(
        (median(5) - 6.0).abs() <= 6.0 * RELATIVE_ERROR,
        "{}",
        median(5)
    );
    assert!(
        (median(6) + 3.0).abs() <= 3.0 * RELATIVE_ERROR,
        "{}",
        median(6)
    );
    assert_eq!(envelope.at(5, 0).count(), 5);
    let mut kept = run(1.0);
    kept.keep_last();
    assert_eq!(kept.times, vec![2.0]);
    assert_eq!(kept.wheel_speeds, vec![vec![2.0, -1.0]]);
    assert_eq!(kept.energies.len(), 1);
}
