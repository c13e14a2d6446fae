//! Shared helpers of the `lie` tests: scalars whose parts can be inspected, sample data.
#![allow(dead_code)]

use nalgebra::{RealField, SMatrix, SVector};
use num_dual::Dual64;

pub const EPS: f64 = f64::EPSILON;

/// A scalar whose components (real part, derivative parts) the tests can inspect.
pub trait Components: RealField + Copy {
    fn components(self) -> Vec<f64>;
    fn lift(x: f64) -> Self;
    const NAME: &'static str;
}

impl Components for f64 {
    fn components(self) -> Vec<f64> {
        vec![self]
    }
    fn lift(x: f64) -> Self {
        x
    }
    const NAME: &'static str = "f64";
}

impl Components for Dual64 {
    fn components(self) -> Vec<f64> {
        vec![self.re, self.eps]
    }
    fn lift(x: f64) -> Self {
        Dual64::new(x, 0.0)
    }
    const NAME: &'static str = "Dual64";
}

/// Largest absolute component of any entry.
pub fn max_abs<T: Components, const R: usize, const C: usize>(m: &SMatrix<T, R, C>) -> f64 {
    m.iter()
        .flat_map(|x| x.components())
        .fold(0.0, |a, b| a.max(b.abs()))
}

/// Deterministic pseudo-random numbers in [−1, 1] (xorshift64).
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
    pub fn vector<const N: usize>(&mut self, scale: f64) -> SVector<f64, N> {
        SVector::from_fn(|_, _| self.next() * scale)
    }
}

/// A vector of f64 as a vector of duals with derivative parts `direction`.
pub fn dual_vector<const N: usize>(
    x: &SVector<f64, N>,
    direction: &SVector<f64, N>,
) -> SVector<Dual64, N> {
    SVector::from_fn(|i, _| Dual64::new(x[i], direction[i]))
}
