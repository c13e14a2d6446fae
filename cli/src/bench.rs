//! `lgsvi bench`: work-precision of lgsvi against what users would pick instead, measured
//! by `lgsvi-bench`; here, the options, the tables, the plots and the files.

use crate::error::{CliError, Result};
use crate::plot;
use clap::Args;
use lgsvi_bench::long_run::{energy_trend, long_run, long_run_settings, LongRun};
use lgsvi_bench::report;
use lgsvi_bench::so3::{ensemble, runs_per_case, sweep};
use lgsvi_mechanics::StepSettings;
use std::path::PathBuf;

/// The most timed repetitions of a bench run.
const MAX_REPEATS: usize = 1000;
/// The most steps of the long run (10⁹ steps of case A take about 2.5 hours).
const MAX_LONG_RUN_STEPS: usize = 1_000_000_000;
/// The most initial conditions of an ensemble.
const MAX_MEMBERS: usize = 100_000;

/// `lgsvi bench`.
#[derive(Debug, Clone, Default, Args)]
pub struct BenchOptions {
    /// Output folder for the table, JSON and plots [default: lgsvi-bench].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Timed repetitions of every run, 1 to 1000; the median is reported [default: 5].
    #[arg(long)]
    pub repeats: Option<usize>,
    /// Run only the long run instead of the sweep: lgsvi (case A, h = 0.5, n = 8) beside
    /// DOP853 over the same horizon, invariants over time.
    #[arg(long)]
    pub long_run: bool,
    /// Steps of the long run, 2 to 10⁹ [default: 1000000].
    #[arg(long, value_name = "N")]
    pub long_run_steps: Option<usize>,
    /// The long run's step h (and its ensemble's) [default: 0.5].
    #[arg(long, value_name = "H")]
    pub long_run_h: Option<f64>,
    /// The long run's nodes n (and its ensemble's) [default: 8]; with --long-run-tol, the
    /// first step's.
    #[arg(long, value_name = "N")]
    pub long_run_nodes: Option<usize>,
    /// The long run (and its ensemble) with nodes chosen per step for this error per unit
    /// time (`StepSettings::with_tolerance`), e.g. 1e-13.
    #[arg(long, value_name = "RATE")]
    pub long_run_tol: Option<f64>,
    /// Initial conditions of the long run's energy-trend ensemble, each run for the same
    /// steps in parallel; 0 skips it, at most 100000 [default: 12].
    #[arg(long, value_name = "N")]
    pub long_run_members: Option<usize>,
    /// Initial conditions per case in the parallel-ensemble measurement, 1 to 100000 [default: 64].
    #[arg(long, value_name = "N")]
    pub ensemble_members: Option<usize>,
    /// Run only the Monte Carlo throughput instead of the sweep: N dispersed members of
    /// case A (rates 0.02 rad/s, moments 1%), each to T = 100 at 1e-10 in attitude, by
    /// lgsvi (one thread and all, at its fastest step and nodes) and by DOP853 (all
    /// threads); 1 to 100000.
    #[arg(long, value_name = "N")]
    pub dispersion: Option<usize>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// `lgsvi bench`.
pub fn run(options: BenchOptions) -> Result<()> {
    let invalid = |flag: &'static str, value: usize, reason: String| CliError::Invalid {
        flag,
        value: value.to_string(),
        reason,
    };
    let repeats = options.repeats.unwrap_or(5);
    if !(1..=MAX_REPEATS).contains(&repeats) {
        return Err(invalid(
            "--repeats",
            repeats,
            format!("from 1 to {MAX_REPEATS} runs"),
        ));
    }
    let steps = options.long_run_steps.unwrap_or(1_000_000);
    if !(2..=MAX_LONG_RUN_STEPS).contains(&steps) {
        return Err(invalid(
            "--long-run-steps",
            steps,
            format!("from 2 to {MAX_LONG_RUN_STEPS}"),
        ));
    }
    let members = options.ensemble_members.unwrap_or(64);
    if !(1..=MAX_MEMBERS).contains(&members) {
        return Err(invalid(
            "--ensemble-members",
            members,
            format!("from 1 to {MAX_MEMBERS} initial conditions"),
        ));
    }
    if let Some(members) = options.long_run_members {
        if members > MAX_MEMBERS {
            return Err(invalid(
                "--long-run-members",
                members,
                format!("at most {MAX_MEMBERS} (0 skips the trend)"),
            ));
        }
    }
    let dir = options
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("lgsvi-bench"));
    std::fs::create_dir_all(&dir).map_err(|source| CliError::CreateDir {
        path: dir.clone(),
        source,
    })?;
    if options.long_run {
        let members = options.long_run_members.unwrap_or(12);
        if members == 1 {
            return Err(invalid(
                "--long-run-members",
                1,
                "a trend needs at least 2 (or 0 to skip it)".into(),
            ));
        }
        let (h, n) = (
            options.long_run_h.unwrap_or(0.5),
            options.long_run_nodes.unwrap_or(8),
        );
        let mut settings = long_run_settings(h, n).map_err(|e| {
            CliError::invalid(
                "--long-run-h/--long-run-nodes",
                format!("{h}, {n}"),
                e.to_string(),
            )
        })?;
        if let Some(rate) = options.long_run_tol {
            settings = settings
                .with_tolerance(rate)
                .map_err(|e| CliError::invalid("--long-run-tol", rate, e.to_string()))?;
        }
        return run_long(&dir, settings, steps, members, options.quiet);
    }
    if let Some(members) = options.dispersion {
        if !(1..=MAX_MEMBERS).contains(&members) {
            return Err(invalid(
                "--dispersion",
                members,
                format!("from 1 to {MAX_MEMBERS} members"),
            ));
        }
        return run_dispersion(&dir, members, repeats);
    }
    let total = (2 * 2 * runs_per_case() + lgsvi_bench::space::runs()) as u64;
    let progress = crate::progress::bar(total, "bench", "runs", options.quiet);
    let points = sweep(repeats, || progress.inc(1));
    let space_points = lgsvi_bench::space::sweep(repeats, || progress.inc(1));
    progress.finish_and_clear();
    let ensemble = ensemble(members, repeats)?;
    let (table, figures) = report::sweep_report(repeats, &points, &space_points, &ensemble);
    for (name, figure) in &figures {
        plot::save(figure, &dir.join(name))?;
    }
    let write = |name: &str, text: &str| {
        let path = dir.join(name);
        crate::files::write(&path, text.as_bytes())
    };
    write("BENCH.md", &table)?;
    let json = serde_json::to_string_pretty(&serde_json::json!({
        "points": points,
        "ensemble": ensemble,
    }))?;
    write("bench.json", &json)?;
    println!("{}", report::targets(&points));
    println!("{}", report::dop853_ratios(&points));
    println!("{}", report::tolerance_table(&points));
    println!("{}", report::ensemble_line(&ensemble));
    println!(
        "table: {}, data: {}, plots: {}/bench_*.svg|png",
        dir.join("BENCH.md").display(),
        dir.join("bench.json").display(),
        dir.display()
    );
    Ok(())
}

/// `lgsvi bench --long-run`: runs [`long_run`] and writes `LONG_RUN.md`, `long_run.json`
/// and the plots `long_run_{energy,casimir,spatial_momentum,orthogonality}.svg|png`.
fn run_long(
    dir: &std::path::Path,
    settings: StepSettings,
    steps: usize,
    members: usize,
    quiet: bool,
) -> Result<()> {
    let progress = crate::progress::bar(steps as u64, "long run (lgsvi)", "steps", quiet);
    // The long run's settings are the flags': a run that fails names them.
    let named = |error: lgsvi_bench::BenchError| {
        CliError::invalid(
            "--long-run-h/--long-run-nodes",
            format!("{}, {}", settings.h(), settings.nodes()),
            error.to_string(),
        )
    };
    let run = long_run(settings, steps, 500, |k| progress.inc(k)).map_err(named)?;
    progress.finish_and_clear();
    let trend = if members > 0 {
        let total = (members * steps) as u64;
        let progress = crate::progress::bar(total, "energy trend (ensemble)", "steps", quiet);
        let trend = energy_trend(settings, steps, members, |k| progress.inc(k)).map_err(named)?;
        progress.finish_and_clear();
        Some(trend)
    } else {
        None
    };
    let (md, figures) = report::long_run_report(settings, steps, &run, trend.as_ref());
    for (name, figure) in &figures {
        plot::save(figure, &dir.join(name))?;
    }
    let LongRun {
        lgsvi,
        dop,
        lgsvi_time,
        dop_time,
        ..
    } = run;
    let write = |name: &str, text: &str| {
        let path = dir.join(name);
        crate::files::write(&path, text.as_bytes())
    };
    write("LONG_RUN.md", &md)?;
    let json = serde_json::to_string_pretty(&serde_json::json!({
        "steps": steps, "lgsvi_time_s": lgsvi_time, "dop853_time_s": dop_time,
        "lgsvi": lgsvi, "dop853": dop, "trend": trend,
    }))?;
    write("long_run.json", &json)?;
    print!("{md}");
    println!(
        "report: {}, data: {}, plots: {}/long_run_*.svg|png",
        dir.join("LONG_RUN.md").display(),
        dir.join("long_run.json").display(),
        dir.display()
    );
    Ok(())
}

/// `lgsvi bench --dispersion N`: the Monte Carlo throughput, printed as a table and
/// written to `dispersion.json`.
fn run_dispersion(dir: &std::path::Path, members: usize, repeats: usize) -> Result<()> {
    let t = lgsvi_bench::dispersion::throughput(members, 2026, repeats)?;
    let per_s = |s: f64| t.members as f64 / s;
    println!(
        "lgsvi's settings within {:e} on the nominal, each timed on one thread over the \
         first {} members:",
        lgsvi_bench::dispersion::TARGET,
        t.members.min(lgsvi_bench::dispersion::SAMPLE)
    );
    println!("| h | n | nominal error | wall time (s) |");
    println!("|---|---|---|---|");
    for c in &t.candidates {
        println!(
            "| {} | {} | {:.1e} | {:.3} |",
            c.h, c.nodes, c.nominal_error, c.sample_s
        );
    }
    println!();
    println!(
        "{} dispersed members of case A, T = {}, attitude within {:e} on the nominal \
         ({} threads, median of {repeats})",
        t.members,
        lgsvi_bench::dispersion::T_END,
        lgsvi_bench::dispersion::TARGET,
        t.threads
    );
    println!("| method | settings | nominal error | wall time (s) | members/s |");
    println!("|---|---|---|---|---|");
    println!(
        "| lgsvi, 1 thread | h = {}, n = {} | {:.1e} | {:.2} | {:.0} |",
        t.lgsvi_step,
        t.lgsvi_nodes,
        t.lgsvi_nominal_error,
        t.lgsvi_one_thread_s,
        per_s(t.lgsvi_one_thread_s)
    );
    println!(
        "| lgsvi, {} threads | h = {}, n = {} | {:.1e} | {:.2} | {:.0} |",
        t.threads,
        t.lgsvi_step,
        t.lgsvi_nodes,
        t.lgsvi_nominal_error,
        t.lgsvi_parallel_s,
        per_s(t.lgsvi_parallel_s)
    );
    println!(
        "| DOP853, {} threads | tol = {:.1e} | {:.1e} | {:.2} | {:.0} |",
        t.threads,
        t.dop853_tolerance,
        t.dop853_nominal_error,
        t.dop853_parallel_s,
        per_s(t.dop853_parallel_s)
    );
    println!(
        "lgsvi's time / DOP853's: {:.2}; lgsvi's scaling 1 → {} threads: {:.2}×; the two \
         methods' final attitudes agree to {:.1e} over the members; failures: {}",
        t.time_ratio, t.threads, t.lgsvi_scaling, t.agreement, t.failures
    );
    let text = serde_json::to_string_pretty(&t)? + "\n";
    crate::files::write(&dir.join("dispersion.json"), text.as_bytes())?;
    Ok(())
}
