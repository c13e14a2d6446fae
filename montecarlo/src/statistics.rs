//! Statistics over members with bounded memory, the same whatever order the members come
//! in.
//!
//! [`Quantiles`] is a log-binned histogram: a value `x ≠ 0` falls in the bin of
//! `⌊BINS_PER_OCTAVE · log₂|x|⌋` of its sign, so every bin spans a factor
//! `2^(1/64) ≈ 1 + 1.09%`; zeros (and values below `f64::MIN_POSITIVE` in size) are
//! counted apart, exactly. A quantile is the geometric middle of the bin that holds the
//! exact order statistic, so it is within **0.55% relative** of the exact sample quantile
//! (the `⌈qN⌉`-th smallest of the `N` values, `q` in `[0, 1]`), whatever `N` and however the
//! values are spread; exact where the order statistic is zero. Bins are kept only where
//! values fell (a sorted map), so a sketch holds a few hundred counts where the values span
//! a few decades, and two sketches merge by adding counts: exactly, in any order, so a run
//! on any number of threads gives the same quantiles.
//!
//! [`Envelope`] holds one [`Quantiles`] per output channel and sample time: the percentile
//! envelopes of a Monte Carlo run without holding its members.

use std::collections::BTreeMap;

/// Bins per factor of two in [`Quantiles`]: each spans `2^(1/64)`, a relative width of
/// 1.09%, so a bin's geometric middle is within 0.55% of any value in it.
pub const BINS_PER_OCTAVE: f64 = 64.0;

/// The largest relative error of a quantile of [`Quantiles`] against the exact sample
/// quantile: half a bin, `2^(1/128) − 1`.
pub const RELATIVE_ERROR: f64 = 0.005_429_901_112_802_726;

/// A streaming quantile sketch of `f64` values (module documentation): counts per log bin,
/// merged exactly.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Quantiles {
    /// Counts of the positive values per bin index.
    positive: BTreeMap<i32, u64>,
    /// Counts of the negative values per bin index of `|x|`.
    negative: BTreeMap<i32, u64>,
    /// Zeros and values below `f64::MIN_POSITIVE` in size.
    zeros: u64,
    /// Values that were not finite (counted, never placed).
    non_finite: u64,
}

impl Quantiles {
    /// An empty sketch.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one value (a NaN or an infinity is counted in [`Quantiles::non_finite`] and
    /// takes no rank).
    pub fn add(&mut self, x: f64) {
        if !x.is_finite() {
            self.non_finite += 1;
        } else if x.abs() < f64::MIN_POSITIVE {
            self.zeros += 1;
        } else {
            let bin = (x.abs().log2() * BINS_PER_OCTAVE).floor() as i32;
            let side = if x > 0.0 {
                &mut self.positive
            } else {
                &mut self.negative
            };
            *side.entry(bin).or_insert(0) += 1;
        }
    }

    /// Adds every count of `other` (exact: the result does not depend on the order of
    /// merges).
    pub fn merge(&mut self, other: &Quantiles) {
        for (side, theirs) in [
            (&mut self.positive, &other.positive),
            (&mut self.negative, &other.negative),
        ] {
            for (bin, count) in theirs {
                *side.entry(*bin).or_insert(0) += count;
            }
        }
        self.zeros += other.zeros;
        self.non_finite += other.non_finite;
    }

    /// The finite values added.
    pub fn count(&self) -> u64 {
        self.positive.values().sum::<u64>() + self.negative.values().sum::<u64>() + self.zeros
    }

    /// The values added that were not finite.
    pub fn non_finite(&self) -> u64 {
        self.non_finite
    }

    /// The bins held (the sketch's size).
    pub fn bins(&self) -> usize {
        self.positive.len() + self.negative.len() + usize::from(self.zeros > 0)
    }

    /// The `q`-quantile (`q` in `[0, 1]`): the `⌈qN⌉`-th smallest value (the smallest for
    /// `q = 0`) to within [`RELATIVE_ERROR`]; `None` for an empty sketch or a `q` outside
    /// `[0, 1]`.
    pub fn quantile(&self, q: f64) -> Option<f64> {
        let n = self.count();
        if n == 0 || !(0.0..=1.0).contains(&q) {
            return None;
        }
        let rank = ((q * n as f64).ceil() as u64).clamp(1, n);
        let middle = |bin: i32| ((f64::from(bin) + 0.5) / BINS_PER_OCTAVE).exp2();
        // Ascending: the negatives from the largest |x| down, the zeros, the positives.
        let mut seen = 0;
        for (bin, count) in self.negative.iter().rev() {
            seen += count;
            if seen >= rank {
                return Some(-middle(*bin));
            }
        }
        seen += self.zeros;
        if seen >= rank {
            return Some(0.0);
        }
        for (bin, count) in &self.positive {
            seen += count;
            if seen >= rank {
                return Some(middle(*bin));
            }
        }
        None
    }
}

/// Percentile envelopes: one [`Quantiles`] per channel and sample time.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Envelope {
    channels: Vec<String>,
    samples: usize,
    /// `sketches[channel * samples + k]`.
    sketches: Vec<Quantiles>,
}

impl Envelope {
    /// An empty envelope of `channels` at `samples` sample times.
    pub fn new(channels: &[&str], samples: usize) -> Self {
        Self {
            channels: channels.iter().map(|c| c.to_string()).collect(),
            samples,
            sketches: vec![Quantiles::new(); channels.len() * samples],
        }
    }

    /// The channels' names.
    pub fn channels(&self) -> &[String] {
        &self.channels
    }

    /// The sample times' count.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// Adds one member's value of `channel` at sample `k`.
    ///
    /// # Panics
    /// For a channel or sample out of range (a caller's bug: the envelope's shape is fixed
    /// when it is made).
    pub fn add(&mut self, channel: usize, k: usize, value: f64) {
        assert!(channel < self.channels.len() && k < self.samples);
        self.sketches[channel * self.samples + k].add(value);
    }

    /// Adds every count of `other`, which has the same channels and samples.
    ///
    /// # Panics
    /// For envelopes of different shapes.
    pub fn merge(&mut self, other: &Envelope) {
        assert_eq!(
            (&self.channels, self.samples),
            (&other.channels, other.samples)
        );
        for (mine, theirs) in self.sketches.iter_mut().zip(&other.sketches) {
            mine.merge(theirs);
        }
    }

    /// The sketch of `channel` at sample `k`.
    pub fn at(&self, channel: usize, k: usize) -> &Quantiles {
        &self.sketches[channel * self.samples + k]
    }

    /// Bins held over all sketches (the envelope's memory is about 40 bytes a bin).
    pub fn bins(&self) -> usize {
        self.sketches.iter().map(Quantiles::bins).sum()
    }
}
