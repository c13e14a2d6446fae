//! `lgsvi reproduce`: the paper's nine figures (`docs/paper-notes.md` §4), each as SVG, PNG and CSV,
//! and `REPORT.md` with the tables, fitted rates and, for each claim of the paper, what
//! lgsvi measured. Errors are measured against the exact free-body solution or a
//! high-accuracy run, never against the method itself.

//!
//! The job itself is `lgsvi_reports::reproduce::paper_job` (measure, draw, report, figure
//! by figure); here are its subjects, resolved as `simulate` resolves its flags
//! ([`measure::problem`]), its progress bars and the files it writes.

mod measure;

use crate::config::{ChartArg, MatchingArg, SystemKind};
use crate::error::{CliError, Result};
use crate::plot::{self, Figure, SphereFigure};
use clap::Args;
use lgsvi_reports::reproduce::{paper_job, report_text, Artifact, Subjects};
use measure::Bars;
use nalgebra::Vector3;
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
    fn artifact(&mut self, artifact: Artifact<'_>) -> Result<()> {
        match artifact {
            Artifact::Figure { name, figure, csv } => self.figure(name, figure.clone(), csv),
            Artifact::Sphere { name, figure, csv } => self.sphere(name, figure, csv),
        }
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
    let j = rigid.inertia.principal_moments();
    let from_momentum = |mu: Vector3<f64>| {
        let mut p = rigid.clone();
        p.omega0 = Vector3::new(mu.x / j[0], mu.y / j[1], mu.z / j[2]);
        p
    };
    let (stable, unstable) = (pendulum(false)?, pendulum(true)?);
    let subjects = Subjects {
        rigid: &rigid,
        rigid_from_momentum: &from_momentum,
        stable: &stable,
        unstable: &unstable,
    };
    let mut emit = |artifact: Artifact<'_>| out.artifact(artifact);
    let job = paper_job(&subjects, &mut emit, &mut Bars::new(options.quiet))?;
    let seconds = started.elapsed().as_secs_f64();
    let text = report_text(&job, env!("CARGO_PKG_VERSION"), seconds);
    out.write("REPORT.md", &text)?;
    println!(
        "lgsvi reproduce: the paper's nine figures in {}/ ({:.1} s)",
        dir.display(),
        started.elapsed().as_secs_f64()
    );
    for file in &out.files {
        println!("  {}", file.display());
    }
    println!("\n{}", lgsvi_reports::paper::claims(&job.findings));
    Ok(out)
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
