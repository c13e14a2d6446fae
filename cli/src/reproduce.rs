//! `lgsvi reproduce`: the paper's nine figures (`docs/paper-notes.md` §4), each as SVG, PNG and CSV,
//! and `REPORT.md` with the tables, fitted rates and, for each claim of the paper, what
//! lgsvi measured. Errors are measured against the exact free-body solution or a
//! high-accuracy run, never against the method itself.

//!
//! The job itself is `lgsvi_reports::reproduce::PaperSubjects::job` (measure, draw, report,
//! figure by figure); here are its progress bars and the files it writes.

use crate::error::{CliError, Result};
use crate::plot::{self, Drawing};
use crate::progress::Bars;
use clap::Args;
use lgsvi_reports::reproduce::{report_text, Artifact, PaperSubjects};
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

/// The files written so far.
struct Output {
    dir: PathBuf,
    files: Vec<PathBuf>,
}

impl Output {
    fn write(&mut self, name: &str, text: &str) -> Result<()> {
        let path = self.dir.join(name);
        crate::files::write(&path, text.as_bytes())?;
        self.files.push(path);
        Ok(())
    }
    /// A figure as SVG and PNG.
    fn save(&mut self, name: &str, figure: &impl Drawing) -> Result<()> {
        let base = self.dir.join(name);
        plot::save(figure, &base)?;
        self.files.push(base.with_extension("svg"));
        self.files.push(base.with_extension("png"));
        Ok(())
    }
    /// A figure and its data as CSV.
    fn artifact(&mut self, artifact: Artifact<'_>) -> Result<()> {
        let (name, csv) = match artifact {
            Artifact::Figure { name, figure, csv } => {
                (name, self.save(name, figure).map(|()| csv)?)
            }
            Artifact::Sphere { name, figure, csv } => {
                (name, self.save(name, figure).map(|()| csv)?)
            }
        };
        self.write(&format!("{name}.csv"), csv)
    }
}

/// `lgsvi reproduce`: the files it wrote are listed on standard output.
pub fn run(options: ReproduceOptions) -> Result<()> {
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
    };
    let mut emit = |artifact: Artifact<'_>| out.artifact(artifact);
    let bars = &mut Bars {
        quiet: options.quiet,
        bar: None,
    };
    let job = PaperSubjects::new()?.job(&mut emit, bars)?;
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
    Ok(())
}
