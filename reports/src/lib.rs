//! Tables, Markdown and figures from lgsvi's experiments (`lgsvi-experiments`): what the
//! `lgsvi` command line prints and writes, as functions from data to text or to a
//! [`lgsvi_plot::Figure`], so that a library user renders their own studies the same way.
//!
//! - [`convergence`]: a convergence study's console table and CSV;
//! - [`linearization`]: a step's linearisation as JSON, the coordinates in words;
//! - [`paper`]: the paper's report (`REPORT.md`): a section per figure and the table of
//!   the paper's claims, each with a verdict from the measurements;
//! - [`paper_figures`]: the paper's figures and their CSV data;
//! - [`reproduce`]: the paper's whole job (nine figures, their CSV, `REPORT.md`) as one call;
//! - [`trajectory`]: a recorded run as `lgsvi simulate` writes it (JSON through serde, CSV
//!   through the `csv` crate) and its conservation figure;
//! - [`tolerance`]: the error-estimate calibration and the tolerance study, as tables and
//!   figures.
//!
//! ```
//! use lgsvi_experiments::convergence::{study, Reference, Refinement};
//! use lgsvi_experiments::Body;
//! use lgsvi_mechanics::lie::SO3;
//! use lgsvi_mechanics::{Inertia, RigidBody, StepSettings};
//! use nalgebra::Vector3;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let inertia = Inertia::from_principal_moments([3.3, 2.5, 3.4])?;
//! let body = Body::new(
//!     RigidBody::new(inertia),
//!     SO3::identity(),
//!     Vector3::new(-2.0, 1.9, -1.0),
//!     StepSettings::new(0.5, 4)?,
//! )
//! .with_exact_solution(inertia);
//! let reference = Reference::for_subject(&body, 2.0)?;
//! let refinement = Refinement {
//!     h: 0.5,
//!     nodes: vec![3, 4, 5, 6],
//!     steps: vec![],
//!     step_nodes: vec![],
//!     t_end: 2.0,
//!     curve_samples: 4,
//! };
//! let result = study(&body, &reference, &refinement, || {})?;
//! let table = lgsvi_reports::convergence::table(&result);
//! assert!(table.contains("n-refinement: exp chart, exact matching, h = 0.5, T = 2"));
//! let csv = lgsvi_reports::convergence::csv(&result.nodes_refinement.iter().collect::<Vec<_>>(), "nodes");
//! assert_eq!(csv.lines().count(), 1 + 4);
//! # Ok(())
//! # }
//! ```

#![warn(missing_docs)]

pub mod convergence;
pub mod linearization;
pub mod paper;
pub mod paper_figures;
pub mod reproduce;
pub mod tolerance;
pub mod trajectory;

/// This crate's `README.md`, whose Rust example is compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
