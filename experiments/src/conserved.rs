//! How far a state's energy, Casimir `|μ|²` and spatial momentum `Rμ` have moved from the
//! initial state's: every study, figure and benchmark measures conservation through
//! [`Tracker`].

use lgsvi_mechanics::System;
use nalgebra::{Matrix3, Vector3};

/// The initial values, and which invariants the system has.
#[derive(Debug, Clone, Copy)]
pub struct Tracker {
    energy: f64,
    casimir: f64,
    spatial_momentum: Vector3<f64>,
    symmetry: Symmetry,
}

/// Which part of the spatial angular momentum `Rμ` a system conserves (Noether's theorem
/// for its symmetry group).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Symmetry {
    /// All of `Rμ`: a free, left-invariant body.
    Full,
    /// Its component `d·Rμ` along a spatial direction `d` (a heavy top's gravity
    /// direction; normalised by [`Tracker::with_symmetry`]).
    Axis(Vector3<f64>),
    /// None of it (a potential without symmetry, a torque): the drift is not measured.
    None,
}

/// Relative drifts from the initial state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drift {
    /// `|E − E₀|/|E₀|`.
    pub energy: f64,
    /// `||μ|² − |μ₀|²|/|μ₀|²`.
    pub casimir: f64,
    /// `|Rμ − R₀μ₀|/|R₀μ₀|` for a free body, `|d·(Rμ − R₀μ₀)|/|R₀μ₀|` along the
    /// conserved axis `d`, NaN for a system without this symmetry ([`Symmetry::None`]).
    pub spatial_momentum: f64,
}

/// The larger of two drifts, NaN if either is: a drift that is not measured (no symmetry)
/// must not read as the 0 of a quantity conserved exactly, which `f64::max` would make it.
pub(crate) fn largest(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// A denominator that is never zero (a body at rest has `E₀ = 0`, `μ₀ = 0`).
fn nonzero(x: f64) -> f64 {
    x.max(1e-300)
}

impl Symmetry {
    /// What an SO(3) system conserves, as it says itself: all of `Rμ` when it is left
    /// invariant and unforced, `d·Rμ` for its [`System::symmetry_generator`] `d`
    /// when unforced, nothing under a force.
    pub fn of<S: System<3>>(system: &S) -> Self {
        if system.is_forced() {
            Symmetry::None
        } else if system.is_left_invariant() {
            Symmetry::Full
        } else {
            system
                .symmetry_generator()
                .map_or(Symmetry::None, Symmetry::Axis)
        }
    }
}

impl Tracker {
    /// From the initial energy, attitude and body momentum, and the conserved axis of the
    /// spatial momentum (`None`: all of it is conserved; the axis is normalised here).
    pub fn new(
        energy: f64,
        attitude: &Matrix3<f64>,
        momentum: &Vector3<f64>,
        axis: Option<Vector3<f64>>,
    ) -> Self {
        let symmetry = match axis {
            None => Symmetry::Full,
            Some(d) => Symmetry::Axis(d),
        };
        Self::with_symmetry(energy, attitude, momentum, symmetry)
    }

    /// From the initial energy, attitude and body momentum, and the system's symmetry.
    pub fn with_symmetry(
        energy: f64,
        attitude: &Matrix3<f64>,
        momentum: &Vector3<f64>,
        symmetry: Symmetry,
    ) -> Self {
        Self {
            energy,
            casimir: momentum.norm_squared(),
            spatial_momentum: attitude * momentum,
            symmetry: match symmetry {
                Symmetry::Axis(d) => Symmetry::Axis(d.normalize()),
                other => other,
            },
        }
    }

    /// The drifts of a later state.
    pub fn drift(&self, energy: f64, attitude: &Matrix3<f64>, momentum: &Vector3<f64>) -> Drift {
        let d = attitude * momentum - self.spatial_momentum;
        Drift {
            energy: (energy - self.energy).abs() / nonzero(self.energy.abs()),
            casimir: (momentum.norm_squared() - self.casimir).abs() / nonzero(self.casimir),
            spatial_momentum: match self.symmetry {
                Symmetry::Full => d.norm(),
                Symmetry::Axis(axis) => axis.dot(&d).abs(),
                Symmetry::None => f64::NAN,
            } / nonzero(self.spatial_momentum.norm()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drifts_are_relative_and_respect_the_symmetry() {
        let (r, mu) = (Matrix3::identity(), Vector3::new(3.0, 0.0, 4.0));
        let free = Tracker::new(2.0, &r, &mu, None);
        assert_eq!(
            free.drift(2.0, &r, &mu),
            Drift {
                energy: 0.0,
                casimir: 0.0,
                spatial_momentum: 0.0
            }
        );
        // Energy up by 1 of 2; |μ|² from 25 to 26; Rμ moved by 1 in x (|π₀| = 5).
        let d = free.drift(3.0, &r, &Vector3::new(4.0, 0.0, 3.0f64.hypot(1.0)));
        assert_eq!(d.energy, 0.5);
        assert!((d.casimir - 1.0 / 25.0).abs() < 1e-15);
        // Only e₃·Rμ counts for the top: a change in x is no drift.
        let top = Tracker::new(2.0, &r, &mu, Some(Vector3::z()));
        assert_eq!(
            top.drift(2.0, &r, &Vector3::new(5.0, 0.0, 4.0))
                .spatial_momentum,
            0.0
        );
        assert_eq!(
            free.drift(2.0, &r, &Vector3::new(5.0, 0.0, 4.0))
                .spatial_momentum,
            0.4
        );
        // Gravity along x: only x·Rμ counts, whatever its length was given as.
        let sideways = Tracker::new(2.0, &r, &mu, Some(Vector3::new(2.0, 0.0, 0.0)));
        assert_eq!(
            sideways
                .drift(2.0, &r, &Vector3::new(3.0, 1.0, 0.0))
                .spatial_momentum,
            0.0
        );
        assert_eq!(
            sideways
                .drift(2.0, &r, &Vector3::new(4.0, 0.0, 4.0))
                .spatial_momentum,
            0.2
        );
        // A body at rest: no division by zero.
        let rest = Tracker::new(0.0, &r, &Vector3::zeros(), None);
        assert!(rest.drift(0.0, &r, &Vector3::zeros()).energy == 0.0);
        // What a system says it conserves.
        use lgsvi_mechanics::forces::BodyTorque;
        use lgsvi_mechanics::{Forced, HeavyTop, Inertia, RigidBody};
        let inertia = Inertia::from_principal_moments([1.0, 2.0, 2.5]).unwrap();
        let top = HeavyTop::new(
            inertia,
            1.0,
            9.81,
            Vector3::z(),
            Vector3::new(0.0, 3.0, 4.0),
        )
        .unwrap();
        assert_eq!(Symmetry::of(&RigidBody::new(inertia)), Symmetry::Full);
        assert_eq!(
            Symmetry::of(&top),
            Symmetry::Axis(Vector3::new(0.0, 0.6, 0.8))
        );
        let torqued = Forced::new(RigidBody::new(inertia), BodyTorque(Vector3::x()));
        assert_eq!(Symmetry::of(&torqued), Symmetry::None);
        let untorqued = Forced::new(top, BodyTorque(Vector3::zeros()));
        assert_eq!(
            Symmetry::of(&untorqued),
            Symmetry::Axis(Vector3::new(0.0, 0.6, 0.8))
        );
        // No symmetry: the momentum drift is not a number, energy and Casimir still are.
        let none = Tracker::with_symmetry(2.0, &r, &mu, Symmetry::None);
        let d = none.drift(3.0, &r, &mu);
        assert!(d.spatial_momentum.is_nan());
        // Its largest over a run stays NaN, whichever comes first.
        assert!(largest(0.0, d.spatial_momentum).is_nan());
        assert!(largest(d.spatial_momentum, 1e-16).is_nan());
        assert_eq!(largest(1e-16, 3e-16), 3e-16);
        assert_eq!((d.energy, d.casimir), (0.5, 0.0));
    }
}
