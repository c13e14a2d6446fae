//! The paper's whole job (`lgsvi reproduce`, the command line's main job) as one call: the
//! measurements behind the nine figures of Hall and Leok's paper
//! ([`lgsvi_experiments::paper`]), each figure and its CSV handed to the caller as soon as
//! it is drawn, and `REPORT.md`'s text (the claims table with a verdict per claim, then a
//! section per figure). The caller decides where the files go.
//!
//! The subjects are the free rigid body of case A, the 3D pendulum near its stable
//! equilibrium (case B) and near its unstable one (case C) of `lgsvi-cases`, in the paper's
//! chart (its unscaled Cayley map): [`PaperSubjects`]. A library user regenerates the
//! paper without the binary:
//!
//! ```no_run
//! use lgsvi_reports::reproduce::{report_text, Artifact, PaperSubjects};
//! # fn main() -> Result<(), lgsvi_experiments::ExperimentError> {
//! let mut emit = |artifact: Artifact<'_>| -> Result<(), lgsvi_experiments::ExperimentError> {
//!     if let Artifact::Figure { name, csv, .. } = artifact {
//!         println!("{name}: {} rows", csv.lines().count() - 1);
//!     }
//!     Ok(())
//! };
//! let job = PaperSubjects::new()?.job(&mut emit, &mut ())?;
//! println!("{}", report_text(&job, "0.1.0", 0.0));
//! # Ok(())
//! # }
//! ```

use crate::paper::{self as report, EnergySummary, Findings};
use crate::paper_figures as figures;
use lgsvi_experiments::convergence::{REFERENCE_NODES, REFERENCE_STEP};
use lgsvi_experiments::paper::{self, NodeFit, Progress};
use lgsvi_experiments::scenario::{Model, Scenario, Top};
use lgsvi_experiments::{ExperimentError, Subject};
use lgsvi_mechanics::lie::{ChartKind, SO3};
use lgsvi_mechanics::settings::NewtonJacobian;
use lgsvi_mechanics::{Inertia, Matching, MechanicsError, StepSettings};
use lgsvi_plot::{Figure, SphereFigure};
use nalgebra::{Matrix3, Vector3};
use std::fmt::Write;

/// A figure of the job, with its data as CSV text, under its file name (no extension).
#[derive(Debug, Clone, Copy)]
pub enum Artifact<'a> {
    /// A 2D figure.
    Figure {
        /// The file name without extension (`fig1_rigid_body_n_refinement`, …).
        name: &'a str,
        /// The figure.
        figure: &'a Figure,
        /// Its data.
        csv: &'a str,
    },
    /// The momenta on the sphere (figure 4).
    Sphere {
        /// The file name without extension.
        name: &'a str,
        /// The figure.
        figure: &'a SphereFigure,
        /// Its data.
        csv: &'a str,
    },
}

/// The paper's three subjects as [`Scenario`]s, with its parameters (`lgsvi-cases`' cases
/// A, B, C: `J = tr(J_d) I − J_d`, the pendulum's centre of mass on `e₃` and gravity along
/// it) and settings (`h = 0.5`, 8 nodes, the unscaled Cayley chart, exact matching).
#[derive(Debug, Clone)]
pub struct PaperSubjects {
    /// The free rigid body (case A).
    pub rigid: Scenario,
    /// The pendulum near its stable equilibrium (case B).
    pub stable: Scenario,
    /// The pendulum near its unstable equilibrium (case C: case B from case C's attitude).
    pub unstable: Scenario,
}

impl PaperSubjects {
    /// The paper's subjects.
    ///
    /// # Errors
    /// None for the compiled-in cases (their test checks them); an [`ExperimentError`]
    /// were they invalid.
    pub fn new() -> Result<Self, ExperimentError> {
        let settings = StepSettings::new(0.5, 8)?
            .with_chart(ChartKind::CayleyUnscaled)
            .with_matching(Matching::Exact)
            .with_jacobian(NewtonJacobian::default());
        let case = |name: &str| {
            lgsvi_cases::case(name).map_err(|e| MechanicsError::InvalidSetting {
                name: "case",
                value: e.to_string(),
                reason: "not among the compiled-in cases",
            })
        };
        let missing = |what: &str| MechanicsError::InvalidSetting {
            name: "case",
            value: what.into(),
            reason: "missing from the compiled-in cases",
        };
        let scenario = |name: &str, model: Model, attitude: &Matrix3<f64>| {
            let case = case(name)?;
            let jd = case.inertia_d.ok_or_else(|| missing("J_d"))?;
            let attitude =
                SO3::try_from_row_major(std::array::from_fn(|i| attitude[(i / 3, i % 3)]))
                    .map_err(MechanicsError::from)?;
            let inertia = Inertia::from_paper_jd(jd)?;
            let scenario = Scenario::new(model, inertia, attitude, case.omega0)?;
            Ok::<_, ExperimentError>(scenario.with_settings(settings))
        };
        let b = case("B")?;
        let top = Model::HeavyTop(Top {
            mass: b.mass.ok_or_else(|| missing("case B's mass"))?,
            gravity: b.gravity.ok_or_else(|| missing("case B's g"))?,
            com: Vector3::z(),
            direction: Vector3::z(),
        });
        let c = case("C")?.attitude0;
        Ok(Self {
            rigid: scenario("A", Model::RigidBody, &Matrix3::identity())?,
            stable: scenario("B", top.clone(), &Matrix3::identity())?,
            unstable: scenario("B", top, &c)?,
        })
    }

    /// The paper's job on these subjects ([`paper_job`]).
    ///
    /// # Errors
    /// [`paper_job`]'s.
    pub fn job<E: From<ExperimentError>>(
        &self,
        emit: &mut dyn FnMut(Artifact<'_>) -> Result<(), E>,
        progress: &mut dyn Progress,
    ) -> Result<PaperJob, E> {
        let j = self.rigid.inertia.principal_moments();
        let from_momentum = |mu: Vector3<f64>| {
            let mut p = self.rigid.clone();
            p.omega0 = Vector3::new(mu.x / j[0], mu.y / j[1], mu.z / j[2]);
            p
        };
        let subjects = Subjects {
            rigid: &self.rigid,
            rigid_from_momentum: &from_momentum,
            stable: &self.stable,
            unstable: &self.unstable,
        };
        paper_job(&subjects, emit, progress)
    }
}

/// The subjects of the paper's job.
pub struct Subjects<'a, P> {
    /// The free rigid body (case A).
    pub rigid: &'a P,
    /// The free rigid body started from a body momentum `μ` (figure 4's polhodes).
    pub rigid_from_momentum: &'a dyn Fn(Vector3<f64>) -> P,
    /// The 3D pendulum near its stable equilibrium (case B).
    pub stable: &'a P,
    /// The 3D pendulum near its unstable equilibrium (case C).
    pub unstable: &'a P,
}

/// What the job measured: the findings behind the claims table, and the report's sections
/// (a heading, the figure and its tables per figure), in the paper's order.
#[derive(Default)]
pub struct PaperJob {
    /// The measurements the claims are judged on.
    pub findings: Findings,
    /// `REPORT.md`'s sections.
    pub sections: String,
}

/// A figure's report heading, file name and title.
struct Section {
    heading: &'static str,
    name: &'static str,
    title: &'static str,
}

impl Section {
    /// The report's heading and image link.
    fn open(&self, text: &mut String) {
        let _ = writeln!(text, "## {}\n\n![]({}.png)\n", self.heading, self.name);
    }
}

/// Runs the paper's nine figures on `subjects`: each figure goes to `emit` when drawn (a
/// failing `emit` stops the job with its error), progress to `progress`.
///
/// # Errors
/// A measurement's ([`ExperimentError`], through `E`) or `emit`'s.
pub fn paper_job<P: Subject, E: From<ExperimentError>>(
    subjects: &Subjects<'_, P>,
    emit: &mut dyn FnMut(Artifact<'_>) -> Result<(), E>,
    progress: &mut dyn Progress,
) -> Result<PaperJob, E> {
    let mut job = PaperJob::default();
    let (text, f) = (&mut job.sections, &mut job.findings);
    let rigid = subjects.rigid;
    let stable = subjects.stable;

    f.rb_factors = n_refinement(
        emit,
        text,
        Section {
            heading: "Figure 1 — rigid body, n-refinement at h = 0.5",
            name: "fig1_rigid_body_n_refinement",
            title: "Rigid body: n-refinement at h = 0.5 (T = 10)",
        },
        rigid,
        progress,
    )?;
    f.rb_orders = h_refinement(
        emit,
        text,
        Section {
            heading: "Figure 2 — rigid body, h-refinement",
            name: "fig2_rigid_body_h_refinement",
            title: "Rigid body: h-refinement (unscaled Cayley)",
        },
        rigid,
        progress,
    )?;
    f.rb_energy = energy(
        emit,
        text,
        Section {
            heading: "Figure 3 — rigid body, energy error over a long run (n = 12, h = 0.5)",
            name: "fig3_rigid_body_energy",
            title: "Rigid body: relative energy error, n = 12, h = 0.5",
        },
        rigid,
        (0.5, 12, 10_000),
        progress,
    )?;

    let name = "fig4_rigid_body_momentum_sphere";
    let data = paper::sphere_runs(subjects.rigid_from_momentum, progress)?;
    emit(Artifact::Sphere {
        name,
        figure: &figures::sphere(&data),
        csv: &figures::sphere_csv(&data),
    })?;
    let _ = writeln!(text, "## Figure 4 — rigid body, body momentum on the sphere |y| = 1 (n = 8, h = 0.5)\n\n![]({name}.png)\n");
    text.push_str(&report::sphere(&data));
    f.sphere = data.summary();

    f.pend_factors = n_refinement(
        emit,
        text,
        Section {
            heading: "Figure 5 — 3D pendulum near the stable equilibrium, n-refinement at h = 0.5",
            name: "fig5_pendulum_n_refinement",
            title: "3D pendulum (stable): n-refinement at h = 0.5 (T = 10)",
        },
        stable,
        progress,
    )?;
    f.pend_orders = h_refinement(
        emit,
        text,
        Section {
            heading: "Figure 6 — 3D pendulum near the stable equilibrium, h-refinement",
            name: "fig6_pendulum_h_refinement",
            title: "3D pendulum (stable): h-refinement (unscaled Cayley)",
        },
        stable,
        progress,
    )?;
    f.pend_energy = energy(
        emit,
        text,
        Section {
            heading: "Figure 7 — 3D pendulum, stable case, energy error (n = 8, h = 1.5)",
            name: "fig7_pendulum_energy",
            title: "3D pendulum (stable): relative energy error, n = 8, h = 1.5",
        },
        stable,
        (1.5, 8, 1000),
        progress,
    )?;

    let data = paper::unstable_runs(subjects.unstable, progress)?;
    emit(Artifact::Figure {
        name: "fig8_unstable_pendulum_dynamics",
        figure: &figures::unstable_dynamics(&data),
        csv: &figures::unstable_dynamics_csv(&data),
    })?;
    emit(Artifact::Figure {
        name: "fig9_unstable_pendulum_energy",
        figure: &figures::unstable_energy(&data),
        csv: &figures::unstable_energy_csv(&data),
    })?;
    let _ = writeln!(text, "## Figures 8 and 9 — 3D pendulum near the unstable equilibrium (n = 20, h = 0.6)\n\n![](fig8_unstable_pendulum_dynamics.png)\n\n![](fig9_unstable_pendulum_energy.png)\n");
    text.push_str(&report::unstable(&data));
    f.unstable = report::unstable_findings(&data);
    f.unstable_jumps = data.jumps;
    Ok(job)
}

/// `REPORT.md` of a finished job that took `seconds`, by lgsvi `version`: a header with the
/// parameters, the claims table, the sections.
pub fn report_text(job: &PaperJob, version: &str, seconds: f64) -> String {
    let mut full = String::new();
    let _ = writeln!(
        full,
        "# lgsvi reproduce — Hall & Leok, *Lie group spectral variational integrators*\n"
    );
    let _ = writeln!(full, "Generated by `lgsvi reproduce` (lgsvi {version}) in {seconds:.1} s. Parameters: `docs/paper-notes.md` in the lgsvi repository (rigid body J = diag(3.3, 2.5, 3.4) from J_d = diag(1.3, 2.1, 1.2), Ω(0) = (−2, 1.9, −1), R(0) = I; 3D pendulum J = diag(4.8, 3.0, 3.8) from J_d = diag(1, 2.8, 2), m = 1, g = 9.81, ρ = e₃, Ω(0) = (0.5, −0.5, 0.4), R(0) = I (stable) or diag(−1, 1, −1) (unstable)). The paper's chart is its unscaled Cayley map; every figure is run with the paper's momentum matching and with the exact one. Errors are Frobenius norms against the exact free-body solution or a high-accuracy run (exp chart, h = {REFERENCE_STEP}, n = {REFERENCE_NODES}), never against the method itself. Each figure has its data in a CSV of the same name.\n");
    full.push_str(&report::claims(&job.findings));
    full.push_str(&job.sections);
    full
}

/// Figures 1 and 5: measure, draw, report; returns the fits for the claims.
fn n_refinement<P: Subject, E: From<ExperimentError>>(
    emit: &mut dyn FnMut(Artifact<'_>) -> Result<(), E>,
    text: &mut String,
    section: Section,
    subject: &P,
    progress: &mut dyn Progress,
) -> Result<Vec<NodeFit>, E> {
    let data = paper::n_refinement(subject, section.name, progress)?;
    emit(Artifact::Figure {
        name: section.name,
        figure: &figures::n_refinement(&data, section.title),
        csv: &figures::n_refinement_csv(&data),
    })?;
    section.open(text);
    text.push_str(&report::n_refinement(&data));
    Ok(data.fits)
}

/// Figures 2 and 6; returns the fitted orders.
fn h_refinement<P: Subject, E: From<ExperimentError>>(
    emit: &mut dyn FnMut(Artifact<'_>) -> Result<(), E>,
    text: &mut String,
    section: Section,
    subject: &P,
    progress: &mut dyn Progress,
) -> Result<Vec<(usize, Matching, Option<f64>)>, E> {
    let data = paper::h_refinement(subject, section.name, progress)?;
    emit(Artifact::Figure {
        name: section.name,
        figure: &figures::h_refinement(&data, section.title),
        csv: &figures::h_refinement_csv(&data),
    })?;
    section.open(text);
    text.push_str(&report::h_refinement(&data));
    Ok(data.orders)
}

/// Figures 3 and 7 at `(h, n, steps)`; returns the summary for the claims.
fn energy<P: Subject, E: From<ExperimentError>>(
    emit: &mut dyn FnMut(Artifact<'_>) -> Result<(), E>,
    text: &mut String,
    section: Section,
    subject: &P,
    settings: (f64, usize, usize),
    progress: &mut dyn Progress,
) -> Result<Vec<EnergySummary>, E> {
    let data = paper::energy_runs(subject, section.name, settings, progress)?;
    emit(Artifact::Figure {
        name: section.name,
        figure: &figures::energy(&data, section.title),
        csv: &figures::energy_csv(&data),
    })?;
    section.open(text);
    text.push_str(&report::energy(&data));
    Ok(report::energy_summary(&data))
}
