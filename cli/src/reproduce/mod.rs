//! `lgsvi reproduce`: the paper's nine figures (`docs/paper-notes.md` §4), each as SVG, PNG and CSV,
//! and `REPORT.md` with the tables, fitted rates and, for each claim of the paper, what
//! lgsvi measured. Errors are measured against the exact free-body solution or a
//! high-accuracy run, never against the method itself.

//!
//! Three concerns, one module each: [`measure`] runs the integrator and returns the data
//! behind each figure, [`figures`] turns data into figures and CSV text, [`report`] into
//! the Markdown of `REPORT.md`; this module runs them in order and writes the files.

mod measure;

use crate::config::{ChartArg, MatchingArg, SystemKind};
use crate::error::{CliError, Result};
use crate::plot::{self, Figure, SphereFigure};
use crate::problem::Problem;
use clap::Args;
use lgsvi_experiments::paper;
use lgsvi_reports::{paper as report, paper_figures as figures};
use measure::Bars;
use nalgebra::Vector3;
use std::fmt::Write;
use std::path::PathBuf;
use std::time::Instant;

/// What `REPORT.md` says while `lgsvi reproduce` runs (and after, if it did not finish).
pub const INCOMPLETE_REPORT: &str = "# INCOMPLETE: lgsvi reproduce did not finish\n\n\
This folder holds the output of an `lgsvi reproduce` run that is still going, was \
interrupted, or failed (its error was printed on standard error). Figures and data here may \
be missing or from an earlier run. Run `lgsvi reproduce` again; when it finishes, this \
file is replaced by the report.\n";

/// `lgsvi reproduce`.
#[derive(Debug, Clone, Default, Args)]
pub struct ReproduceOptions {
    /// Output folder (created if missing; files in it are overwritten).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// No progress bars.
    #[arg(long)]
    pub quiet: bool,
}

/// The default output folder.
pub const DEFAULT_OUT: &str = "lgsvi-reproduce";

/// The paper's chart (its Cayley map without the factor ½; `docs/paper-notes.md` §2 item 7).
const PAPER_CHART: ChartArg = ChartArg::CayleyUnscaled;

/// The files written so far.
struct Output {
    dir: PathBuf,
    files: Vec<PathBuf>,
    /// The 2D figures written, by file name (without extension), for the checks.
    figures: Vec<(String, Figure)>,
}

impl Output {
    fn write(&mut self, name: &str, text: &str) -> Result<()> {
        let path = self.dir.join(name);
        crate::files::write(&path, text.as_bytes())?;
        self.files.push(path);
        Ok(())
    }
    /// A 2D figure as SVG and PNG, and its data as CSV.
    fn figure(&mut self, name: &str, fig: Figure, csv: &str) -> Result<()> {
        let base = self.dir.join(name);
        plot::save(&fig, &base)?;
        self.files.push(base.with_extension("svg"));
        self.files.push(base.with_extension("png"));
        self.figures.push((name.to_string(), fig));
        self.write(&format!("{name}.csv"), csv)
    }
    fn sphere(&mut self, name: &str, fig: &SphereFigure, csv: &str) -> Result<()> {
        let base = self.dir.join(name);
        plot::save(fig, &base)?;
        self.files.push(base.with_extension("svg"));
        self.files.push(base.with_extension("png"));
        self.write(&format!("{name}.csv"), csv)
    }
}

/// `lgsvi reproduce`.
pub fn run(options: ReproduceOptions) -> Result<()> {
    run_into(options).map(|_| ())
}

/// `lgsvi reproduce`, returning what it wrote.
fn run_into(options: ReproduceOptions) -> Result<Output> {
    let started = Instant::now();
    let dir = options
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_OUT));
    std::fs::create_dir_all(&dir).map_err(|source| CliError::CreateDir {
        path: dir.clone(),
        source,
    })?;
    // REPORT.md first says the run has not finished; the finished report replaces it
    // (atomically) at the end, so an interrupted or failed run leaves a visible mark.
    crate::files::write(&dir.join("REPORT.md"), INCOMPLETE_REPORT.as_bytes())?;
    let mut out = Output {
        dir: dir.clone(),
        files: Vec::new(),
        figures: Vec::new(),
    };
    let quiet = options.quiet;
    let mut text = String::new();
    let mut f = report::Findings::default();
    let rigid = measure::problem(
        SystemKind::RigidBody,
        PAPER_CHART,
        MatchingArg::Exact,
        0.5,
        8,
        10.0,
        false,
    )?;
    let pendulum = |unstable: bool| {
        measure::problem(
            SystemKind::HeavyTop,
            PAPER_CHART,
            MatchingArg::Exact,
            0.5,
            8,
            10.0,
            unstable,
        )
    };
    let stable = pendulum(false)?;

    f.rb_factors = n_refinement(
        &mut out,
        &mut text,
        Section {
            heading: "Figure 1 — rigid body, n-refinement at h = 0.5",
            name: "fig1_rigid_body_n_refinement",
            title: "Rigid body: n-refinement at h = 0.5 (T = 10)",
        },
        &rigid,
        quiet,
    )?;
    f.rb_orders = h_refinement(
        &mut out,
        &mut text,
        Section {
            heading: "Figure 2 — rigid body, h-refinement",
            name: "fig2_rigid_body_h_refinement",
            title: "Rigid body: h-refinement (unscaled Cayley)",
        },
        &rigid,
        quiet,
    )?;
    f.rb_energy = energy(
        &mut out,
        &mut text,
        Section {
            heading: "Figure 3 — rigid body, energy error over a long run (n = 12, h = 0.5)",
            name: "fig3_rigid_body_energy",
            title: "Rigid body: relative energy error, n = 12, h = 0.5",
        },
        &rigid,
        (0.5, 12, 10_000),
        quiet,
    )?;

    let name = "fig4_rigid_body_momentum_sphere";
    let j = rigid.inertia.principal_moments();
    let data = paper::sphere_runs(
        |mu| {
            let mut p = rigid.clone();
            p.omega0 = Vector3::new(mu.x / j[0], mu.y / j[1], mu.z / j[2]);
            p
        },
        &mut Bars::new(quiet),
    )?;
    out.sphere(name, &figures::sphere(&data), &figures::sphere_csv(&data))?;
    let _ = writeln!(text, "## Figure 4 — rigid body, body momentum on the sphere |y| = 1 (n = 8, h = 0.5)\n\n![]({name}.png)\n");
    text.push_str(&report::sphere(&data));
    f.sphere = data.summary();

    f.pend_factors = n_refinement(
        &mut out,
        &mut text,
        Section {
            heading: "Figure 5 — 3D pendulum near the stable equilibrium, n-refinement at h = 0.5",
            name: "fig5_pendulum_n_refinement",
            title: "3D pendulum (stable): n-refinement at h = 0.5 (T = 10)",
        },
        &stable,
        quiet,
    )?;
    f.pend_orders = h_refinement(
        &mut out,
        &mut text,
        Section {
            heading: "Figure 6 — 3D pendulum near the stable equilibrium, h-refinement",
            name: "fig6_pendulum_h_refinement",
            title: "3D pendulum (stable): h-refinement (unscaled Cayley)",
        },
        &stable,
        quiet,
    )?;
    f.pend_energy = energy(
        &mut out,
        &mut text,
        Section {
            heading: "Figure 7 — 3D pendulum, stable case, energy error (n = 8, h = 1.5)",
            name: "fig7_pendulum_energy",
            title: "3D pendulum (stable): relative energy error, n = 8, h = 1.5",
        },
        &stable,
        (1.5, 8, 1000),
        quiet,
    )?;

    let data = paper::unstable_runs(&pendulum(true)?, &mut Bars::new(quiet))?;
    out.figure(
        "fig8_unstable_pendulum_dynamics",
        figures::unstable_dynamics(&data),
        &figures::unstable_dynamics_csv(&data),
    )?;
    out.figure(
        "fig9_unstable_pendulum_energy",
        figures::unstable_energy(&data),
        &figures::unstable_energy_csv(&data),
    )?;
    let _ = writeln!(text, "## Figures 8 and 9 — 3D pendulum near the unstable equilibrium (n = 20, h = 0.6)\n\n![](fig8_unstable_pendulum_dynamics.png)\n\n![](fig9_unstable_pendulum_energy.png)\n");
    text.push_str(&report::unstable(&data));
    f.unstable = report::unstable_findings(&data);
    f.unstable_jumps = data.jumps;

    let mut full = String::new();
    let _ = writeln!(
        full,
        "# lgsvi reproduce — Hall & Leok, *Lie group spectral variational integrators*\n"
    );
    let _ = writeln!(full, "Generated by `lgsvi reproduce` (lgsvi {}) in {:.1} s. Parameters: `docs/paper-notes.md` in the lgsvi repository (rigid body J = diag(3.3, 2.5, 3.4) from J_d = diag(1.3, 2.1, 1.2), Ω(0) = (−2, 1.9, −1), R(0) = I; 3D pendulum J = diag(4.8, 3.0, 3.8) from J_d = diag(1, 2.8, 2), m = 1, g = 9.81, ρ = e₃, Ω(0) = (0.5, −0.5, 0.4), R(0) = I (stable) or diag(−1, 1, −1) (unstable)). The paper's chart is its unscaled Cayley map; every figure is run with the paper's momentum matching and with the exact one. Errors are Frobenius norms against the exact free-body solution or a high-accuracy run (exp chart, h = {}, n = {}), never against the method itself. Each figure has its data in a CSV of the same name.\n",
        env!("CARGO_PKG_VERSION"), started.elapsed().as_secs_f64(), lgsvi_experiments::convergence::REFERENCE_STEP, lgsvi_experiments::convergence::REFERENCE_NODES);
    full.push_str(&report::claims(&f));
    full.push_str(&text);
    out.write("REPORT.md", &full)?;
    println!(
        "lgsvi reproduce: the paper's nine figures in {}/ ({:.1} s)",
        dir.display(),
        started.elapsed().as_secs_f64()
    );
    for file in &out.files {
        println!("  {}", file.display());
    }
    println!("\n{}", report::claims(&f));
    Ok(out)
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

/// Figures 1 and 5: measure, draw, report; returns the fits for the claims.
fn n_refinement(
    out: &mut Output,
    text: &mut String,
    section: Section,
    system: &Problem,
    quiet: bool,
) -> Result<Vec<paper::NodeFit>> {
    let data = paper::n_refinement(system, section.name, &mut Bars::new(quiet))?;
    out.figure(
        section.name,
        figures::n_refinement(&data, section.title),
        &figures::n_refinement_csv(&data),
    )?;
    section.open(text);
    text.push_str(&report::n_refinement(&data));
    Ok(data.fits)
}

/// Figures 2 and 6; returns the fitted orders.
fn h_refinement(
    out: &mut Output,
    text: &mut String,
    section: Section,
    system: &Problem,
    quiet: bool,
) -> Result<Vec<(usize, lgsvi_mechanics::Matching, Option<f64>)>> {
    let data = paper::h_refinement(system, section.name, &mut Bars::new(quiet))?;
    out.figure(
        section.name,
        figures::h_refinement(&data, section.title),
        &figures::h_refinement_csv(&data),
    )?;
    section.open(text);
    text.push_str(&report::h_refinement(&data));
    Ok(data.orders)
}

/// Figures 3 and 7 at `(h, n, steps)`; returns the summary for the claims.
fn energy(
    out: &mut Output,
    text: &mut String,
    section: Section,
    system: &Problem,
    settings: (f64, usize, usize),
    quiet: bool,
) -> Result<Vec<report::EnergySummary>> {
    let data = paper::energy_runs(system, section.name, settings, &mut Bars::new(quiet))?;
    out.figure(
        section.name,
        figures::energy(&data, section.title),
        &figures::energy_csv(&data),
    )?;
    section.open(text);
    text.push_str(&report::energy(&data));
    Ok(report::energy_summary(&data))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every figure of the main job, checked as a referee would look at it: what is drawn
    /// for each series spans exactly its data (no renderer-made spikes, nothing cut), the
    /// data's extremes are numbers of the figure's CSV, the legend and the title fit in
    /// their own areas (the legend beside the plot, never over the data), and failed
    /// runs are marked rather than dropped.
    #[test]
    fn every_figure_draws_its_data_and_nothing_else() {
        let dir = std::env::temp_dir().join(format!("lgsvi-figures-{}", std::process::id()));
        let out = run_into(ReproduceOptions {
            out: Some(dir.clone()),
            quiet: true,
        })
        .unwrap();
        assert_eq!(out.figures.len(), 8, "the nine figures less the 3D sphere");
        for (name, fig) in &out.figures {
            let csv = std::fs::read_to_string(dir.join(format!("{name}.csv"))).unwrap();
            let cells: Vec<f64> = csv
                .lines()
                .skip(1)
                .flat_map(|l| l.split(',').filter_map(|c| c.parse::<f64>().ok()))
                .collect();
            for drawn in plot::inspect(fig) {
                assert_eq!(drawn.drawn, drawn.data, "{name} / {}", drawn.label);
                let series = fig.series.iter().find(|s| s.label == drawn.label).unwrap();
                // The data's own extremes (before zeros go to a log axis's bottom edge).
                let finite = || series.points.iter().map(|p| p.1).filter(|y| y.is_finite());
                let lo = finite().fold(f64::INFINITY, f64::min);
                let hi = finite().fold(f64::NEG_INFINITY, f64::max);
                for v in [lo, hi].into_iter().filter(|v| v.is_finite() && *v != 0.0) {
                    assert!(
                        cells.contains(&v),
                        "{name} / {}: plotted extreme {v:e} is not in the CSV",
                        drawn.label
                    );
                }
                let failed = series.points.iter().filter(|p| !p.1.is_finite()).count();
                assert_eq!(drawn.failures, failed, "{name}: every failure is marked");
            }
            let layout = plot::layout(fig, plot::SIZE);
            let (p, l) = (layout.plot, layout.legend);
            assert!(
                p.2 <= l.0,
                "{name}: the legend is beside the plot, not over it"
            );
            // Text widths are the font's metrics; renderers differ by a few pixels, so a
            // label must leave 12 px before the edge.
            for label in plot::legend_labels(fig) {
                let width = plot::legend_text_width(&label);
                assert!(
                    l.0 + plot::LEGEND_TEXT_X + width as i32 + 12 <= l.2,
                    "{name}: legend label {label:?} is cut"
                );
            }
            assert!(layout.title_fits, "{name}: title cut");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
