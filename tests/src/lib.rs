//! Cross-crate tests of lgsvi. The README below is compiled and its Rust examples run as
//! doctests, so the README cannot drift from the code.
#![doc = include_str!("../../README.md")]

/// The user guide's page on the quadrature and spectral crates on their own
/// (`docs/guide/standalone.md`), whose Rust examples are compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../docs/guide/standalone.md")]
pub struct StandaloneGuide;
