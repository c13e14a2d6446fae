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

use lgsvi_experiments::record::Recording;
use lgsvi_mechanics::lie::SO3;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Bins per factor of two in [`Quantiles`]: each spans `2^(1/64)`, a relative width of
/// 1.09%, so a bin's geometric middle is within 0.55% of any value in it.
pub const BINS_PER_OCTAVE: f64 = 64.0;

/// The largest relative error of a quantile of [`Quantiles`] against the exact sample
/// quantile: half a bin, `2^(1/128) − 1`.
pub const RELATIVE_ERROR: f64 = 0.005_429_901_112_802_726;

/// A streaming quantile sketch of `f64` values (module documentation): counts per log bin,
/// merged exactly. It serializes (serde) as its counts, so a sketch made on one machine
/// merges into one made on another.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
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

/// Percentile envelopes: one [`Quantiles`] per channel and sample time; serializable as
/// its sketches, for envelopes made apart (a cluster's workers) and merged.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "EnvelopeData")]
pub struct Envelope {
    channels: Vec<String>,
    samples: usize,
    /// `sketches[channel * samples + k]`.
    sketches: Vec<Quantiles>,
}

/// An envelope as read, before its shape is checked.
#[derive(Deserialize)]
struct EnvelopeData {
    channels: Vec<String>,
    samples: usize,
    sketches: Vec<Quantiles>,
}

impl TryFrom<EnvelopeData> for Envelope {
    type Error = String;

    fn try_from(data: EnvelopeData) -> Result<Self, String> {
        if data.channels.len().checked_mul(data.samples) != Some(data.sketches.len()) {
            return Err(format!(
                "an envelope of {} channels at {} samples holds {} sketches, not their product",
                data.channels.len(),
                data.samples,
                data.sketches.len()
            ));
        }
        Ok(Self {
            channels: data.channels,
            samples: data.samples,
            sketches: data.sketches,
        })
    }
}

impl Envelope {
    /// Whether `other` has the same channels and sample count ([`Envelope::merge`]'s
    /// condition).
    pub fn same_shape(&self, other: &Envelope) -> bool {
        self.channels == other.channels && self.samples == other.samples
    }

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

/// A run's states at its sample times: what a member adds to the attitude envelope.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Samples {
    /// The sample times.
    pub times: Vec<f64>,
    /// `R = world_from_body` at each.
    pub attitudes: Vec<Matrix3<f64>>,
    /// The body rates `Ω` at each.
    pub omegas: Vec<Vector3<f64>>,
    /// The energy at each.
    pub energies: Vec<f64>,
    /// The wheels' rates relative to the body at each, for a gyrostat (empty without
    /// wheels).
    pub wheel_speeds: Vec<Vec<f64>>,
}

/// How a member's run ended beside its samples ([`Samples::of_recording`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RunEnd {
    /// Where its stop condition was met.
    pub stop: Option<f64>,
    /// From when its settling condition held to its end.
    pub settle: Option<f64>,
    /// The last position and velocity (world frame) of a body in space.
    pub motion: Option<(Vector3<f64>, Vector3<f64>)>,
}

impl Samples {
    /// A recorded run's states as samples (`R`, `Ω`, the energy and a gyrostat's wheel
    /// rates at each recorded time), and how the run ended: the stop and settling times
    /// and a body in space's last translation.
    pub fn of_recording(recording: Recording) -> (Samples, RunEnd) {
        let end = RunEnd {
            stop: recording.stopped.as_ref().map(|s| s.time),
            settle: recording.settled.as_ref().and_then(|s| s.time),
            motion: recording
                .motion
                .as_ref()
                .and_then(|m| m.last())
                .map(|m| (m.position, m.velocity)),
        };
        let samples = Samples {
            times: recording.states.iter().map(|s| s.time).collect(),
            attitudes: recording
                .states
                .iter()
                .map(|s| *s.attitude().matrix())
                .collect(),
            omegas: recording.states.iter().map(|s| s.velocity).collect(),
            energies: recording.energies,
            wheel_speeds: recording
                .wheels
                .map(|w| w.into_iter().map(|w| w.speeds).collect())
                .unwrap_or_default(),
        };
        (samples, end)
    }

    /// Drops every sample but the last (what a run keeps of a member once its samples are
    /// in the envelope).
    pub fn keep_last(&mut self) {
        fn last<T>(values: &mut Vec<T>) {
            let before = values.len().saturating_sub(1);
            values.drain(..before);
        }
        last(&mut self.times);
        last(&mut self.attitudes);
        last(&mut self.omegas);
        last(&mut self.energies);
        last(&mut self.wheel_speeds);
    }

    /// The last sample's time, attitude and rates.
    pub fn last(&self) -> Option<(f64, Matrix3<f64>, Vector3<f64>)> {
        Some((
            *self.times.last()?,
            *self.attitudes.last()?,
            *self.omegas.last()?,
        ))
    }
}

/// The channels of a rigid body's envelope ([`Envelope::of_attitude`]): the attitude's
/// departure from the nominal run's at the same time (degrees, the angle of `R̄ᵀR`), the
/// body rates, and the energy's relative change since the start (the integrator's error,
/// for a body that conserves it).
pub const ATTITUDE_CHANNELS: [&str; 5] = [
    "attitude_departure_deg",
    "omega_1",
    "omega_2",
    "omega_3",
    "energy_change",
];

/// The names of a gyrostat's wheel channels after [`ATTITUDE_CHANNELS`]
/// ([`Envelope::of_attitude_and_wheels`]): `wheel_1` … `wheel_K`, each wheel's rate
/// relative to the body.
pub const WHEEL_CHANNELS: [&str; 4] = ["wheel_1", "wheel_2", "wheel_3", "wheel_4"];

/// The name of the pointing-error channel ([`Envelope::add_error_samples`]): the angle
/// from a target attitude, degrees.
pub const ERROR_CHANNEL: &str = "error_deg";

impl Envelope {
    /// An empty envelope of [`ATTITUDE_CHANNELS`] at `samples` sample times.
    pub fn of_attitude(samples: usize) -> Self {
        Self::new(&ATTITUDE_CHANNELS, samples)
    }

    /// An empty envelope of [`ATTITUDE_CHANNELS`] and the rates of `wheels` wheels
    /// ([`WHEEL_CHANNELS`], at most four) at `samples` sample times.
    ///
    /// # Panics
    /// If `wheels > 4` (a gyrostat has one to four wheels).
    pub fn of_attitude_and_wheels(samples: usize, wheels: usize) -> Self {
        Self::of_run(samples, wheels, false)
    }

    /// Adds a member's samples to an envelope of [`ATTITUDE_CHANNELS`] (and its wheels'
    /// channels, [`Envelope::of_attitude_and_wheels`]), its attitude measured from the
    /// nominal run's at the same sample; samples past the shorter run's or the envelope's
    /// are left out.
    pub fn add_attitude_samples(&mut self, nominal: &Samples, member: &Samples) {
        let e0 = member.energies.first().copied().unwrap_or(f64::NAN);
        let samples = self
            .samples
            .min(member.times.len())
            .min(nominal.times.len());
        let wheels = self.channels.len()
            - ATTITUDE_CHANNELS.len()
            - usize::from(self.channels.iter().any(|c| c == ERROR_CHANNEL));
        for k in 0..samples {
            let relative = nominal.attitudes[k].transpose() * member.attitudes[k];
            let departure = SO3::from_matrix_unchecked(relative)
                .log()
                .norm()
                .to_degrees();
            self.add(0, k, departure);
            for axis in 0..3 {
                self.add(1 + axis, k, member.omegas[k][axis]);
            }
            self.add(4, k, (member.energies[k] - e0) / e0.abs());
            if let Some(speeds) = member.wheel_speeds.get(k) {
                for (wheel, &speed) in speeds.iter().enumerate().take(wheels) {
                    self.add(ATTITUDE_CHANNELS.len() + wheel, k, speed);
                }
            }
        }
    }

    /// The envelope of a run's members at `samples` sample times: [`ATTITUDE_CHANNELS`],
    /// the rates of `wheels` wheels ([`WHEEL_CHANNELS`], at most four) and, for a run with
    /// a target attitude, [`ERROR_CHANNEL`] last; [`Envelope::add_member`] fills it.
    ///
    /// # Panics
    /// If `wheels > 4` (a gyrostat has one to four wheels).
    pub fn of_run(samples: usize, wheels: usize, with_target: bool) -> Self {
        let channels: Vec<&str> = ATTITUDE_CHANNELS
            .iter()
            .chain(&WHEEL_CHANNELS[..wheels])
            .chain(with_target.then_some(&ERROR_CHANNEL))
            .copied()
            .collect();
        Self::new(&channels, samples)
    }

    /// Adds a member's samples to an envelope of [`Envelope::of_run`]: its attitude, rates,
    /// energy and wheels ([`Envelope::add_attitude_samples`]) and, where the run has a
    /// `target`, its pointing error ([`Envelope::add_error_samples`]).
    pub fn add_member(&mut self, nominal: &Samples, member: &Samples, target: Option<&SO3>) {
        self.add_attitude_samples(nominal, member);
        if let Some(target) = target {
            self.add_error_samples(target, member);
        }
    }

    /// Adds a member's pointing error to [`ERROR_CHANNEL`] (an envelope of
    /// [`Envelope::of_run`] with a target): at each sample the angle of `R_targetᵀ R`,
    /// degrees. Does nothing on an envelope without the channel.
    pub fn add_error_samples(&mut self, target: &SO3, member: &Samples) {
        let Some(channel) = self.channels.iter().position(|c| c == ERROR_CHANNEL) else {
            return;
        };
        for (k, attitude) in member.attitudes.iter().enumerate().take(self.samples) {
            let relative = target.matrix().transpose() * attitude;
            let error = SO3::from_matrix_unchecked(relative)
                .log()
                .norm()
                .to_degrees();
            self.add(channel, k, error);
        }
    }
}
