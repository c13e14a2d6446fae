//! Cross-crate tests of lgsvi. The README below is compiled and its Rust examples run as
//! doctests, so the README cannot drift from the code.
#![doc = include_str!("../../README.md")]

/// The user guide's page on the quadrature and spectral crates on their own
/// (`docs/guide/standalone.md`), whose Rust examples are compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../../docs/guide/standalone.md")]
pub struct StandaloneGuide;

/// The user guide's pages whose Rust examples are compiled and run as doctests here (the
/// events, Monte Carlo and optimal-control pages are doctests of their own crates).
#[cfg(doctest)]
pub mod guide {
    /// `docs/guide/getting-started.md`.
    #[doc = include_str!("../../docs/guide/getting-started.md")]
    pub struct GettingStarted;
    /// `docs/guide/simulating.md`.
    #[doc = include_str!("../../docs/guide/simulating.md")]
    pub struct Simulating;
    /// `docs/guide/control.md`.
    #[doc = include_str!("../../docs/guide/control.md")]
    pub struct Control;
    /// `docs/guide/tolerance.md`.
    #[doc = include_str!("../../docs/guide/tolerance.md")]
    pub struct Tolerance;
    /// `docs/guide/own-group.md`.
    #[doc = include_str!("../../docs/guide/own-group.md")]
    pub struct OwnGroup;
    /// `docs/guide/studies.md`.
    #[doc = include_str!("../../docs/guide/studies.md")]
    pub struct Studies;
}
