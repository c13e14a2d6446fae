//! Cross-crate tests of lgsvi. The README below is compiled and its Rust examples run as
//! doctests, so the README cannot drift from the code.
#![doc = include_str!("../../README.md")]
