//! `lgsvi montecarlo`: many runs of simulate's system (any built-in one), each member's
//! inertia, start, torque, mass and wheels dispersed about the nominal
//! ([`lgsvi_montecarlo`]), in parallel; one CSV row per member and a JSON summary
//! (final-state statistics, stop and settling times, and every failure).
//!
//! Every member runs exactly as `lgsvi simulate` with its drawn parameters as flags
//! (`--inertia-tensor` its `J`, `--attitude0` its `R₀`, `--omega0` its `Ω₀`, `--torque`
//! its torque, `--mass` its mass, `--wheel-inertia` and `--wheel-axes` its wheels, the
//! nominal's other flags): `members.csv` prints those and the final state to round-trip,
//! so simulate given a row's parameters reproduces the row bit for bit, and `--replay K`
//! does so for member `K`, writing its whole trajectory.

use crate::config::{config_error, Numbers, SimulateOptions};
use crate::error::{CliError, Result};
use crate::problem::Problem;
use clap::Args;
use lgsvi_experiments::scenario::Model;
use lgsvi_experiments::stop::{StopWhen, Watch};
use lgsvi_mechanics::lie::SO3;
use lgsvi_montecarlo::statistics::{Envelope, RunEnd, Samples as Sampled};
use lgsvi_montecarlo::{Body, Dispersion, DispersionError, Dispersions, Member, Plan};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use serde_json::json;
use std::path::PathBuf;

/// The options of `lgsvi montecarlo`: simulate's system, start and integrator flags (the
/// nominal run), the members, the seed and the dispersions.
#[derive(Debug, Clone, Default, Args, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
// A member writes a row, not a trajectory (`--replay` writes one); --out is the folder.
#[command(
    mut_arg("every", |a| a.hide(true)),
    mut_arg("format", |a| a.hide(true)),
    mut_arg("plot", |a| a.hide(true)),
    mut_arg("exact", |a| a.hide(true)),
    mut_arg("out", |a| a.help("Output folder [default: ./lgsvi-montecarlo]; with --replay, the member's trajectory file (JSON) [default: standard output]"))
)]
pub struct MontecarloOptions {
    /// The nominal run: simulate's flags, every system. A config file (`--config`) may
    /// hold the Monte Carlo keys below in a `[montecarlo]` table, and the whole dispersion
    /// spec in `[montecarlo.dispersions]` (keys `attitude`, `omega`, `inertia`,
    /// `inertia_misalignment`, `torque`, `mass`, `wheel_inertia`, `wheel_axis`, each a
    /// table like `{ distribution = "truncated_normal", sigma = 0.02, bound = 0.06 }`).
    #[command(flatten)]
    #[serde(skip)]
    pub base: SimulateOptions,
    /// Members to run [default: 100].
    #[arg(long)]
    pub members: Option<u64>,
    /// The seed: member i's draws depend on (seed, i) alone [default: 0].
    #[arg(long)]
    pub seed: Option<u64>,
    /// Disperse each start rate: a normal perturbation of standard deviation SIGMA, rad/s.
    #[arg(long, value_name = "SIGMA", allow_hyphen_values = true)]
    pub disperse_omega: Option<f64>,
    /// Disperse each principal moment: a relative normal perturbation of standard
    /// deviation FRACTION, truncated at 3 FRACTION.
    #[arg(long, value_name = "FRACTION", allow_hyphen_values = true)]
    pub disperse_inertia: Option<f64>,
    /// Disperse the start attitude: a body-frame rotation vector, each component normal of
    /// standard deviation DEGREES.
    #[arg(long, value_name = "DEGREES", allow_hyphen_values = true)]
    pub disperse_attitude: Option<f64>,
    /// The dispersion spec of the config's `[montecarlo.dispersions]` table (no flag).
    #[arg(skip)]
    pub dispersions: Option<Dispersions>,
    /// Run member K alone and write its whole trajectory as simulate does (JSON).
    #[arg(long, value_name = "K")]
    pub replay: Option<u64>,
    /// Sample times of the percentile envelopes, evenly spaced in steps over the run,
    /// 2 to 10000 [default: 100].
    #[arg(long, value_name = "K")]
    pub samples: Option<usize>,
    /// Complete the interrupted run in --out (its options are the run's own, kept in
    /// checkpoint.json; give no others): every finished member is kept, the rest run.
    #[arg(long)]
    #[serde(skip)]
    pub resume: bool,
    /// Stop once this many members are written, as an interruption would (for testing
    /// --resume).
    #[arg(long, hide = true, value_name = "MEMBERS")]
    #[serde(skip)]
    pub interrupt_after: Option<u64>,
}

/// What a run keeps beside members.csv after every chunk, so that `--resume` completes an
/// interrupted run exactly as an uninterrupted one would have ended.
#[derive(Serialize, Deserialize)]
struct Checkpoint {
    /// The Monte Carlo options (the config's merged in).
    options: MontecarloOptions,
    /// The nominal's options, resolved.
    simulate: SimulateOptions,
    /// Members whose rows members.csv holds.
    members_done: u64,
    /// members.csv's length after them (a row half written past it is cut off).
    csv_bytes: u64,
    /// The statistics over them.
    statistics: Statistics,
    /// The integration's wall time so far.
    wall_time_s: f64,
}

/// The file of [`Checkpoint`] in a run's folder.
const CHECKPOINT: &str = "checkpoint.json";

/// One member's outcome: its draws, and its final state or why it failed.
struct Outcome {
    member: Member,
    result: std::result::Result<Final, String>,
}

/// A member's last recorded state (its translation or wheels beside the rotation),
/// where `--stop-when` stopped it and from when `--settle-when` held.
#[derive(Clone, Serialize, Deserialize)]
struct Final {
    time: f64,
    attitude: Matrix3<f64>,
    omega: Vector3<f64>,
    /// `(x, ẋ)`, world frame, for a body in space.
    motion: Option<(Vector3<f64>, Vector3<f64>)>,
    /// The wheels' rates relative to the body, for a gyrostat (else empty).
    wheel_speeds: Vec<f64>,
    stop: Option<f64>,
    settle: Option<f64>,
}

/// A run's last state and how it ended.
fn final_of(sampled: &Sampled, ended: &RunEnd) -> Option<Final> {
    sampled.last().map(|(time, attitude, omega)| Final {
        time,
        attitude,
        omega,
        motion: ended.motion,
        wheel_speeds: sampled.wheel_speeds.last().cloned().unwrap_or_default(),
        stop: ended.stop,
        settle: ended.settle,
    })
}

/// The optional columns of members.csv, from the nominal system and the options: the
/// drawn torque, mass and wheels, the final translation and wheel rates, the stop and
/// settling times.
#[derive(Clone, Copy)]
struct Layout {
    torque: bool,
    mass: bool,
    wheels: usize,
    motion: bool,
    stop: bool,
    settle: bool,
    /// The target attitude of a run with one (`--attitude-gain`, `--target-quaternion`):
    /// its envelopes add the pointing error.
    target: Option<SO3>,
}

/// Bins of the stop times' histogram, over their own range.
const STOP_BINS: usize = 40;

/// The percentiles of the envelopes.
const PERCENTILES: [f64; 7] = [1.0, 5.0, 25.0, 50.0, 75.0, 95.0, 99.0];

/// The memory a chunk of members' sampled states may take (14 numbers a sample): the
/// members run between two additions to the envelopes, whose sampled states are held only
/// that long, so a run's memory does not grow with its members' trajectories.
const CHUNK_BYTES: usize = 16 << 20;

/// Members a chunk holds at `samples` sample times: within [`CHUNK_BYTES`], at least 16
/// (a few per thread) and at most 1024.
fn chunk_members(samples: usize) -> u64 {
    (CHUNK_BYTES / (samples * 14 * 8)).clamp(16, 1024) as u64
}

/// Runs `lgsvi montecarlo`; `Ok(())` when every member finished, else
/// [`CliError::MembersFailed`] after writing everything.
pub fn run(options: MontecarloOptions) -> Result<()> {
    let (options, checkpoint) = if options.resume {
        let (options, checkpoint) = resumed(options)?;
        (options, Some(checkpoint))
    } else {
        (with_config(options)?, None)
    };
    let base = &options.base;
    let row = "montecarlo writes one row per member (see --replay)";
    crate::error::refuse_simulate_only(&[
        ("--every", base.every.is_some(), row),
        ("--format", base.format.is_some(), row),
        (
            "--plot",
            base.plot.is_some(),
            "montecarlo draws no figure yet",
        ),
        ("--exact", base.exact, "montecarlo integrates every member"),
    ])?;
    let members = options.members.unwrap_or(DEFAULT_MEMBERS);
    if members == 0 || members > MAX_MEMBERS {
        return Err(CliError::invalid(
            "--members",
            members,
            format!("from 1 to {MAX_MEMBERS}"),
        ));
    }
    let seed = options.seed.unwrap_or(0);
    let mut nominal_options = base.clone();
    nominal_options.out = None;
    nominal_options.quiet = true;
    let (nominal_problem, resolved) = Problem::resolve(nominal_options)?;
    nominal_problem.check_watch()?;
    let scenario = &nominal_problem.scenario;
    let mut nominal = Body::new(scenario.inertia, scenario.attitude0, scenario.omega0);
    nominal.torque = resolved.torque.map_or(Vector3::zeros(), Vector3::from);
    // The mass of a body in space, or of a heavy top that has one; a gyrostat's wheels.
    nominal.mass = match &nominal_problem.model {
        Model::HeavyTop(top) => Some(top.mass).filter(|&m| m > 0.0),
        Model::FreeInSpace(body) => Some(body.mass),
        Model::Orbiting(orbit) => Some(orbit.body.mass),
        Model::RigidBody | Model::Gyrostat(_) => None,
    };
    if let Model::Gyrostat(wheels) = &nominal_problem.model {
        nominal.wheel_inertias = wheels.inertia.clone();
        nominal.wheel_axes = wheels.axes.clone();
    }
    let dispersions = dispersions(&options);
    if dispersions.torque.is_some() && !nominal.wheel_inertias.is_empty() {
        return Err(named_by_flag(
            DispersionError::NotApplicable {
                key: "torque",
                what: "body torque (a gyrostat's wheels take --wheel-torque)",
            },
            &options,
        ));
    }
    let plan = Plan::new(nominal, dispersions, seed).map_err(|e| named_by_flag(e, &options))?;
    let layout = Layout {
        torque: plan.dispersions().torque.is_some() || resolved.torque.is_some(),
        mass: plan.nominal().mass.is_some() && plan.dispersions().mass.is_some(),
        wheels: plan.nominal().wheel_inertias.len(),
        motion: scenario.motion.is_some(),
        stop: nominal_problem.watch.stop.is_some(),
        settle: nominal_problem.watch.settle.is_some(),
        target: nominal_problem.watch.target,
    };
    // Every member takes the nominal's step, so that all share one time grid (a --tol
    // run's first step would otherwise follow each member's own rate).
    let h = nominal_problem.settings().h();
    let member_options = |member: &Member| {
        let mut o = resolved.clone();
        o.h = Some(h);
        o.config = None;
        o.quiet = true;
        o.out = None;
        o.inertia = None;
        o.inertia_d = None;
        o.inertia_tensor = Some(row_major(&member.body.inertia.matrix()));
        o.quaternion0 = None;
        o.attitude0 = Some(row_major(member.body.attitude.matrix()));
        o.omega0 = Some(member.body.omega.into());
        if member.body.torque != Vector3::zeros() || o.torque.is_some() {
            o.torque = Some(member.body.torque.into());
        }
        if layout.mass {
            o.mass = member.body.mass;
        }
        if layout.wheels > 0 {
            o.wheel_inertia = Some(Numbers(member.body.wheel_inertias.clone()));
            o.wheel_axes = Some(Numbers(
                member
                    .body
                    .wheel_axes
                    .iter()
                    .flat_map(|a| [a.x, a.y, a.z])
                    .collect(),
            ));
        }
        o
    };
    if let Some(k) = options.replay {
        let member = plan.member(k)?;
        let mut o = member_options(&member);
        o.out = base.out.clone();
        o.quiet = base.quiet;
        return crate::run_simulate(o);
    }
    let out = base
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_OUT));
    let table = out.join("members.csv");
    if table.exists() && checkpoint.is_none() {
        return Err(CliError::invalid(
            "--out",
            out.display(),
            "the folder holds another run (members.csv): give another folder, remove it, or \
             complete an interrupted one with --resume",
        ));
    }
    std::fs::create_dir_all(&out).map_err(|source| CliError::CreateDir {
        path: out.clone(),
        source,
    })?;
    let samples = options.samples.unwrap_or(DEFAULT_SAMPLES);
    if !(2..=MAX_SAMPLES).contains(&samples) {
        return Err(CliError::invalid(
            "--samples",
            samples,
            format!("from 2 to {MAX_SAMPLES}"),
        ));
    }
    let steps = crate::problem::whole_steps(nominal_problem.t_end, h)?;
    let every = (steps / (samples - 1)).max(1);
    // The nominal run fails as simulate's would, with its own error.
    // The nominal runs to the end (the envelopes' times), whatever --stop-when says.
    let (nominal_run, nominal_end) = run_sampled(&nominal_problem, every, &Watch::NOTHING)?;
    let nominal_final = final_of(&nominal_run, &nominal_end).ok_or(CliError::invalid(
        "--t-end",
        nominal_problem.t_end,
        "the nominal run recorded no state",
    ))?;
    let (mut stats, mut first, earlier_wall_time, resume_bytes) = match checkpoint {
        Some(c) => (
            c.statistics,
            c.members_done,
            c.wall_time_s,
            Some(c.csv_bytes),
        ),
        None => (
            Statistics::new(nominal_run.times.len(), nominal_final, layout),
            0,
            0.0,
            None,
        ),
    };
    let bar = crate::progress::bar(members, "members", "members", base.quiet);
    bar.set_position(first);
    let started = std::time::Instant::now();
    let chunk_size = chunk_members(nominal_run.times.len());
    // Rows are written as their chunk finishes, in member order, and the statistics
    // updated: nothing of a member is held past its chunk. After each chunk the rows are
    // flushed to disk and the checkpoint written, so an interruption loses one chunk.
    let (mut file, mut csv_bytes) = open_table(&table, resume_bytes, &layout)?;
    let checkpoint_path = out.join(CHECKPOINT);
    while first < members {
        let mut last = (first + chunk_size).min(members);
        if let Some(at) = options.interrupt_after.filter(|&at| at > first) {
            last = last.min(at);
        }
        let chunk: Vec<(Outcome, Option<Sampled>)> = (first..last)
            .into_par_iter()
            .map(|index| {
                let outcome = run_member(&plan, index, every, &member_options);
                bar.inc(1);
                outcome
            })
            .collect::<Result<_>>()?;
        let mut rows = String::new();
        for (outcome, sampled) in chunk {
            rows.push_str(&csv_row(&outcome, &layout));
            rows.push('\n');
            stats.add(
                &outcome,
                sampled.as_ref(),
                &nominal_run,
                layout.target.as_ref(),
            );
        }
        append(&mut file, &table, rows.as_bytes())?;
        csv_bytes += rows.len() as u64;
        first = last;
        let saved = Checkpoint {
            options: MontecarloOptions {
                base: SimulateOptions::default(),
                ..options.clone()
            },
            simulate: resolved.clone(),
            members_done: first,
            csv_bytes,
            statistics: stats,
            wall_time_s: earlier_wall_time + started.elapsed().as_secs_f64(),
        };
        crate::files::write(&checkpoint_path, &serde_json::to_vec(&saved)?)?;
        stats = saved.statistics;
        if options.interrupt_after == Some(first) && first < members {
            bar.finish_and_clear();
            return Err(CliError::invalid(
                "--interrupt-after",
                first,
                format!("interrupted after {first} of {members} members, as asked"),
            ));
        }
    }
    bar.finish_and_clear();
    let wall_time = earlier_wall_time + started.elapsed().as_secs_f64();
    let mut summary = summary(&options, &plan, &nominal_problem, &stats, wall_time);
    summary["envelopes"] = envelopes_json(&stats.envelope, &nominal_run.times);
    crate::plot::save(
        &envelope_figure(
            &stats.envelope,
            &nominal_run.times,
            0,
            "attitude departure (deg)",
        ),
        &out.join("envelope_attitude"),
    )?;
    crate::plot::save(
        &envelope_figure(
            &stats.envelope,
            &nominal_run.times,
            4,
            "relative energy change",
        ),
        &out.join("envelope_energy"),
    )?;
    if layout.target.is_some() {
        crate::plot::save(
            &envelope_figure(
                &stats.envelope,
                &nominal_run.times,
                stats.envelope.channels().len() - 1,
                "pointing error (deg)",
            ),
            &out.join("envelope_error"),
        )?;
    }
    for wheel in 0..layout.wheels {
        let channel = lgsvi_montecarlo::statistics::ATTITUDE_CHANNELS.len() + wheel;
        crate::plot::save(
            &envelope_figure(
                &stats.envelope,
                &nominal_run.times,
                channel,
                &format!("wheel {} rate (rad/s)", wheel + 1),
            ),
            &out.join(format!("envelope_wheel_{}", wheel + 1)),
        )?;
    }
    for (condition, timed, key, file) in [
        (
            nominal_problem.watch.stop,
            Timed::Stop,
            "stop",
            "stop_times",
        ),
        (
            nominal_problem.watch.settle,
            Timed::Settle,
            "settle",
            "settle_times",
        ),
    ] {
        if let Some(condition) = condition {
            summary[key] = times_json(&condition, timed, &stats);
            crate::plot::save(&times_figure(&condition, timed, &stats), &out.join(file))?;
        }
    }
    let text = serde_json::to_string_pretty(&summary)? + "\n";
    let summary_path = out.join("summary.json");
    crate::files::write(&summary_path, text.as_bytes())?;
    // Complete: nothing left to resume.
    let _ = std::fs::remove_file(&checkpoint_path);
    if !stats.failures.is_empty() {
        return Err(CliError::MembersFailed {
            failed: stats.failures.len(),
            members: members as usize,
            summary: summary_path,
        });
    }
    Ok(())
}

/// The members run without `--members` (a quick look; thousands for a sign-off).
const DEFAULT_MEMBERS: u64 = 100;
/// The envelopes' sample times without `--samples`.
const DEFAULT_SAMPLES: usize = 100;
/// The most sample times (the envelopes hold a sketch per channel and time).
const MAX_SAMPLES: usize = 10_000;
/// The most members one run takes (its table is held in memory).
const MAX_MEMBERS: u64 = 10_000_000;
/// The output folder without `--out`.
const DEFAULT_OUT: &str = "lgsvi-montecarlo";

/// The options and checkpoint of the interrupted run in `--out` that `--resume`
/// completes: the run's own options (only `--out` and `--quiet` may be given beside
/// `--resume`).
fn resumed(given: MontecarloOptions) -> Result<(MontecarloOptions, Checkpoint)> {
    let out = given
        .base
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_OUT));
    let quiet = given.base.quiet;
    let mut bare = given.clone();
    bare.resume = false;
    bare.interrupt_after = None;
    bare.base.out = None;
    bare.base.quiet = false;
    let nothing_else = serde_json::to_value(&bare)?
        == serde_json::to_value(MontecarloOptions::default())?
        && serde_json::to_value(&bare.base)? == serde_json::to_value(SimulateOptions::default())?
        && bare.base.config.is_none();
    if !nothing_else {
        return Err(CliError::invalid(
            "--resume",
            out.display(),
            "a resumed run takes its own options from the folder's checkpoint.json: give \
             only --out (and --quiet) with --resume",
        ));
    }
    let path = out.join(CHECKPOINT);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        CliError::invalid(
            "--resume",
            out.display(),
            format!(
                "the folder holds no interrupted run ({}: {e}); a complete run leaves none",
                path.display()
            ),
        )
    })?;
    let checkpoint: Checkpoint = serde_json::from_str(&text).map_err(|e| {
        CliError::invalid(
            "--resume",
            path.display(),
            format!("not a checkpoint of this version of lgsvi montecarlo: {e}"),
        )
    })?;
    let mut options = checkpoint.options.clone();
    options.base = checkpoint.simulate.clone();
    options.base.out = Some(out);
    options.base.quiet = quiet;
    options.interrupt_after = given.interrupt_after;
    Ok((options, checkpoint))
}

/// members.csv for writing: created with its header, or (resuming) cut back to the
/// `bytes` the checkpoint counted and opened at its end; its length.
fn open_table(
    table: &std::path::Path,
    resume_bytes: Option<u64>,
    layout: &Layout,
) -> Result<(std::fs::File, u64)> {
    let failed = |source: std::io::Error| {
        CliError::invalid(
            "--out",
            table.display(),
            format!("members.csv cannot be written: {source}"),
        )
    };
    match resume_bytes {
        Some(bytes) => {
            let mut file = std::fs::OpenOptions::new()
                .read(true)
                .write(true)
                .open(table)
                .map_err(failed)?;
            let length = file.metadata().map_err(failed)?.len();
            if length < bytes {
                return Err(CliError::invalid(
                    "--resume",
                    table.display(),
                    format!(
                        "members.csv holds {length} bytes, fewer than the {bytes} its checkpoint \
                         counted: it was changed since; start the run again in a new folder"
                    ),
                ));
            }
            file.set_len(bytes).map_err(failed)?;
            std::io::Seek::seek(&mut file, std::io::SeekFrom::End(0)).map_err(failed)?;
            Ok((file, bytes))
        }
        None => {
            let mut file = std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(table)
                .map_err(failed)?;
            let header = csv_header(layout) + "\n";
            append(&mut file, table, header.as_bytes())?;
            Ok((file, header.len() as u64))
        }
    }
}

/// Appends `bytes` to members.csv and waits until they are on disk.
fn append(file: &mut std::fs::File, table: &std::path::Path, bytes: &[u8]) -> Result<()> {
    use std::io::Write;
    file.write_all(bytes)
        .and_then(|()| file.sync_data())
        .map_err(|source| {
            CliError::invalid(
                "--out",
                table.display(),
                format!("members.csv cannot be written: {source}"),
            )
        })
}

/// The options with the config's `[montecarlo]` table under the flags.
fn with_config(options: MontecarloOptions) -> Result<MontecarloOptions> {
    let Some(path) = options.base.config.clone() else {
        return Ok(options);
    };
    let (_, Some(mut section)) = crate::config::read_config_table(&path, "montecarlo")? else {
        return Ok(options);
    };
    let spec = match section.remove("dispersions") {
        None => None,
        Some(value) => Some(Dispersions::deserialize(value).map_err(|e| {
            config_error(&path, &format!("[montecarlo.dispersions] {}", e.message()))
        })?),
    };
    let mut options = options;
    let base = std::mem::take(&mut options.base);
    let mut merged: MontecarloOptions =
        crate::config::overlaid(section, &options, &path, "[montecarlo] ")?;
    merged.base = base;
    merged.dispersions = spec;
    Ok(merged)
}

/// The config's spec with the flags' dispersions over it.
fn dispersions(options: &MontecarloOptions) -> Dispersions {
    let mut spec = options.dispersions.unwrap_or_default();
    if let Some(sigma) = options.disperse_omega {
        spec.omega = Some(Dispersion::Normal { sigma });
    }
    if let Some(sigma) = options.disperse_inertia {
        spec.inertia = Some(if sigma == 0.0 {
            Dispersion::Uniform { half_width: 0.0 }
        } else {
            Dispersion::TruncatedNormal {
                sigma,
                bound: 3.0 * sigma,
            }
        });
    }
    if let Some(degrees) = options.disperse_attitude {
        spec.attitude = Some(Dispersion::Normal {
            sigma: degrees.to_radians(),
        });
    }
    spec
}

/// A refused dispersion that a flag set, as an error naming the flag and its value as
/// given; one the config's `[montecarlo.dispersions]` set, naming the file and the key.
fn named_by_flag(error: DispersionError, options: &MontecarloOptions) -> CliError {
    // Not set by a flag: the config's table set it, and the error names the file.
    let from_config = |error: DispersionError| match &options.base.config {
        Some(path) => config_error(path, &format!("[montecarlo.dispersions] {error}")),
        None => error.into(),
    };
    let key = match &error {
        DispersionError::Invalid { key, .. }
        | DispersionError::NotPhysical { key, .. }
        | DispersionError::NotApplicable { key, .. } => *key,
        _ => return error.into(),
    };
    let given = match key {
        "omega" => options.disperse_omega.map(|v| ("--disperse-omega", v, "")),
        "inertia" => options
            .disperse_inertia
            .map(|v| ("--disperse-inertia", v, " (truncated at 3 FRACTION)")),
        "attitude" => options
            .disperse_attitude
            .map(|v| ("--disperse-attitude", v, " (the flag's degrees in radians)")),
        _ => None,
    };
    match given {
        Some((flag, value, how)) => CliError::invalid(flag, value, format!("{error}{how}")),
        None => from_config(error),
    }
}

/// Member `index` drawn and run as simulate runs it with its parameters as flags, its
/// states kept every `every` steps (for the envelopes) until they are added.
fn run_member(
    plan: &Plan,
    index: u64,
    every: usize,
    options: &dyn Fn(&Member) -> SimulateOptions,
) -> Result<(Outcome, Option<Sampled>)> {
    let member = plan.member(index)?;
    let run = Problem::resolve(options(&member))
        .and_then(|(problem, _)| run_sampled(&problem, every, &problem.watch))
        .map_err(|e| e.to_string().replace('\n', " "));
    let (result, sampled) = match run {
        Ok((sampled, ended)) => match final_of(&sampled, &ended) {
            Some(last) => (Ok(last), Some(sampled)),
            None => (Err("no state recorded".to_string()), None),
        },
        Err(error) => (Err(error), None),
    };
    Ok((Outcome { member, result }, sampled))
}

/// The problem's run, its states every `every` steps and the last, ended where `watch`'s
/// stop condition is met; the crossing's time, the settling time and the last
/// translation beside them.
fn run_sampled(problem: &Problem, every: usize, watch: &Watch) -> Result<(Sampled, RunEnd)> {
    let settings = problem.settings();
    let recording = problem.scenario.record(
        settings,
        problem.check,
        problem.t_end,
        every,
        watch,
        &mut |_| {},
    )?;
    Ok(Sampled::of_recording(recording))
}

/// The stop times' histogram: [`STOP_BINS`] bins from the least to the largest (one bin
/// of width zero where all are equal); its edges and counts.
fn stop_histogram(times: &[f64]) -> (Vec<f64>, Vec<u64>) {
    let Some((least, largest)) = times.iter().fold(None, |r: Option<(f64, f64)>, &t| {
        Some(r.map_or((t, t), |(a, b)| (a.min(t), b.max(t))))
    }) else {
        return (Vec::new(), Vec::new());
    };
    if largest == least {
        return (vec![least, largest], vec![times.len() as u64]);
    }
    let width = (largest - least) / STOP_BINS as f64;
    let edges = (0..=STOP_BINS).map(|i| least + width * i as f64).collect();
    let mut counts = vec![0u64; STOP_BINS];
    for &t in times {
        let bin = ((t - least) / width).floor() as usize;
        counts[bin.min(STOP_BINS - 1)] += 1;
    }
    (edges, counts)
}

/// What a run's event times are: the stop times (`--stop-when`) or the settling times
/// (`--settle-when`).
#[derive(Clone, Copy)]
enum Timed {
    Stop,
    Settle,
}

impl Timed {
    /// The verb of the members counted (`members_stopped`, `members_settled`).
    fn verb(self) -> &'static str {
        match self {
            Timed::Stop => "stopped",
            Timed::Settle => "settled",
        }
    }

    /// The times of the members that met the condition.
    fn times(self, stats: &Statistics) -> &[f64] {
        match self {
            Timed::Stop => &stats.stop_times,
            Timed::Settle => &stats.settle_times,
        }
    }
}

/// The times over the members that met `condition` (`members_stopped` or
/// `members_settled` of the finished ones): their exact sample percentiles (the
/// `⌈qN⌉`-th smallest), least and largest, and their histogram.
fn times_json(condition: &StopWhen, timed: Timed, stats: &Statistics) -> serde_json::Value {
    let mut sorted = timed.times(stats).to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    let mut percentiles = serde_json::Map::new();
    for p in PERCENTILES {
        let rank = ((p / 100.0 * n as f64).ceil() as usize).clamp(1, n.max(1));
        percentiles.insert(format!("p{p}"), json!(sorted.get(rank - 1)));
    }
    let (edges, counts) = stop_histogram(&sorted);
    let verb = timed.verb();
    json!({
        "condition": condition.to_string(),
        format!("members_{verb}"): n,
        format!("members_not_{verb}"): stats.finished() as usize - n,
        "time_percentiles": percentiles,
        "time_min": sorted.first(),
        "time_max": sorted.last(),
        "histogram": {"edges": edges, "counts": counts},
    })
}

/// The times' histogram as a staircase.
fn times_figure(condition: &StopWhen, timed: Timed, stats: &Statistics) -> lgsvi_plot::Figure {
    let times = timed.times(stats);
    let (edges, counts) = stop_histogram(times);
    let mut points = Vec::new();
    if let (Some(&first), Some(&last)) = (edges.first(), edges.last()) {
        points.push((first, 0.0));
        for (i, &count) in counts.iter().enumerate() {
            points.extend([(edges[i], count as f64), (edges[i + 1], count as f64)]);
        }
        points.push((last, 0.0));
    }
    let (title, label) = match timed {
        Timed::Stop => (format!("when {condition}"), "stop times"),
        Timed::Settle => (format!("{condition} from then on"), "settling times"),
    };
    lgsvi_plot::Figure {
        title: format!("{title}: {} of {} members", times.len(), stats.finished()),
        x_label: "t".into(),
        y_label: "members per bin".into(),
        x_log: false,
        y_log: false,
        series: vec![lgsvi_plot::Series {
            label: format!("{label} ({} bins)", counts.len()),
            points,
            style: lgsvi_plot::Style::Line,
            color: 0,
        }],
        hlines: vec![],
    }
}

/// The envelopes as JSON: the sample times, and per channel each percentile's series
/// (`p1` … `p99`), each value within 0.55% of the exact sample percentile.
fn envelopes_json(envelope: &Envelope, times: &[f64]) -> serde_json::Value {
    let mut channels = serde_json::Map::new();
    for (c, name) in envelope.channels().iter().enumerate() {
        let mut series = serde_json::Map::new();
        for p in PERCENTILES {
            let values: Vec<Option<f64>> = (0..envelope.samples())
                .map(|k| envelope.at(c, k).quantile(p / 100.0))
                .collect();
            series.insert(format!("p{p}"), json!(values));
        }
        channels.insert(name.clone(), serde_json::Value::Object(series));
    }
    json!({
        "t": times,
        "relative_accuracy": lgsvi_montecarlo::statistics::RELATIVE_ERROR,
        "percentile": "the ceil(q N)-th smallest of the N members that finished, to relative_accuracy",
        "channels": channels,
    })
}

/// A channel's median and its 1% and 99% percentiles over time.
fn envelope_figure(
    envelope: &Envelope,
    times: &[f64],
    channel: usize,
    label: &str,
) -> lgsvi_plot::Figure {
    let series = |p: f64, color: usize, name: &str| lgsvi_plot::Series {
        label: name.into(),
        points: (0..envelope.samples())
            .filter_map(|k| Some((times[k], envelope.at(channel, k).quantile(p / 100.0)?)))
            .collect(),
        style: lgsvi_plot::Style::Line,
        color,
    };
    lgsvi_plot::Figure {
        title: format!("{label}: median, 1% and 99% of the members"),
        x_label: "t".into(),
        y_label: label.into(),
        x_log: false,
        y_log: false,
        series: vec![
            series(99.0, 1, "99th percentile"),
            series(50.0, 0, "median"),
            series(1.0, 2, "1st percentile"),
        ],
        hlines: vec![],
    }
}

/// A 3×3 matrix's entries, row by row.
fn row_major(m: &Matrix3<f64>) -> [f64; 9] {
    [
        m.m11, m.m12, m.m13, m.m21, m.m22, m.m23, m.m31, m.m32, m.m33,
    ]
}

/// The header of `members.csv`: the draws (`J`, `R0`, `omega0`, and where the run has
/// them the torque `tau_1..3`, the mass `m`, each wheel's inertia `I_wK` and axis
/// `a_wK_1..3`), the final state (`t`, `R`, `omega`, and `x_1..3`, `v_1..3` for a body in
/// space, `wheel_K` for a gyrostat), then `t_stop` and `t_settle` where watched.
fn csv_header(layout: &Layout) -> String {
    let names = |prefix: &str| -> Vec<String> {
        (1..=3)
            .flat_map(|i| (1..=3).map(move |j| format!("{prefix}_{i}{j}")))
            .collect()
    };
    let three =
        |prefix: &str| -> Vec<String> { (1..=3).map(|i| format!("{prefix}_{i}")).collect() };
    let mut header = vec!["member".to_string(), "status".to_string()];
    header.extend(names("J"));
    header.extend(names("R0"));
    header.extend(three("omega0"));
    if layout.torque {
        header.extend(three("tau"));
    }
    if layout.mass {
        header.push("m".into());
    }
    for k in 1..=layout.wheels {
        header.push(format!("I_w{k}"));
        header.extend(three(&format!("a_w{k}")));
    }
    header.push("t".into());
    header.extend(names("R"));
    header.extend(three("omega"));
    if layout.motion {
        header.extend(three("x"));
        header.extend(three("v"));
    }
    header.extend((1..=layout.wheels).map(|k| format!("wheel_{k}")));
    if layout.stop {
        header.push("t_stop".into());
    }
    if layout.settle {
        header.push("t_settle".into());
    }
    header.join(",")
}

/// A member's row of `members.csv` ([`csv_header`]): every float in Rust's shortest form
/// that reads back to the same bits; a failed member's final state left empty, as are
/// the stop and settling times of a member that did not meet its condition.
fn csv_row(outcome: &Outcome, layout: &Layout) -> String {
    let m = &outcome.member;
    let mut cells = vec![
        m.index.to_string(),
        if outcome.result.is_ok() {
            "ok"
        } else {
            "failed"
        }
        .to_string(),
    ];
    let floats = |values: &[f64]| values.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>();
    cells.extend(floats(&row_major(&m.body.inertia.matrix())));
    cells.extend(floats(&row_major(m.body.attitude.matrix())));
    cells.extend(floats(m.body.omega.as_slice()));
    if layout.torque {
        cells.extend(floats(m.body.torque.as_slice()));
    }
    if layout.mass {
        cells.extend(floats(&[m.body.mass.unwrap_or(f64::NAN)]));
    }
    for (inertia, axis) in m.body.wheel_inertias.iter().zip(&m.body.wheel_axes) {
        cells.extend(floats(&[*inertia, axis.x, axis.y, axis.z]));
    }
    let finals = 13 + if layout.motion { 6 } else { 0 } + layout.wheels;
    match &outcome.result {
        Ok(f) => {
            cells.extend(floats(&[f.time]));
            cells.extend(floats(&row_major(&f.attitude)));
            cells.extend(floats(f.omega.as_slice()));
            if layout.motion {
                let (x, v) = f
                    .motion
                    .unwrap_or((Vector3::repeat(f64::NAN), Vector3::repeat(f64::NAN)));
                cells.extend(floats(x.as_slice()));
                cells.extend(floats(v.as_slice()));
            }
            cells.extend(floats(&f.wheel_speeds));
        }
        Err(_) => cells.extend(std::iter::repeat_n(String::new(), finals)),
    }
    let result = outcome.result.as_ref().ok();
    for (watched, time) in [
        (layout.stop, result.and_then(|f| f.stop)),
        (layout.settle, result.and_then(|f| f.settle)),
    ] {
        if watched {
            cells.push(time.map_or(String::new(), |t| format!("{t:?}")));
        }
    }
    cells.join(",")
}

/// What the summary reports, gathered member by member in member order: the envelopes,
/// the final rates' (and translation's, wheel rates') and attitude departures' running
/// mean and covariance (Welford), the largest departure angle, the stop and settling
/// times, and every failure.
#[derive(Serialize, Deserialize)]
struct Statistics {
    envelope: Envelope,
    /// The stop times of the members `--stop-when` stopped (8 bytes a member: held, so
    /// that their percentiles are exact and their histogram spans their own range).
    stop_times: Vec<f64>,
    /// The settling times of the members that settled under `--settle-when`, held as the
    /// stop times are.
    settle_times: Vec<f64>,
    nominal_final: Final,
    rates: Running,
    departures: Running,
    /// The final position and velocity of a body in space.
    positions: Option<Running>,
    velocities: Option<Running>,
    /// The final wheel rates of a gyrostat.
    wheel_speeds: Option<Running>,
    largest_angle: f64,
    failures: Vec<serde_json::Value>,
}

impl Statistics {
    fn new(samples: usize, nominal_final: Final, layout: Layout) -> Self {
        Self {
            envelope: Envelope::of_run(samples, layout.wheels, layout.target.is_some()),
            stop_times: Vec::new(),
            settle_times: Vec::new(),
            nominal_final,
            rates: Running::new(3),
            departures: Running::new(3),
            positions: layout.motion.then(|| Running::new(3)),
            velocities: layout.motion.then(|| Running::new(3)),
            wheel_speeds: (layout.wheels > 0).then(|| Running::new(layout.wheels)),
            largest_angle: 0.0,
            failures: Vec::new(),
        }
    }

    /// The members that finished.
    fn finished(&self) -> u64 {
        self.rates.count
    }

    /// Adds a member's outcome, its samples measured from the nominal run's (and its
    /// pointing error from `target`, for a run with one).
    fn add(
        &mut self,
        outcome: &Outcome,
        sampled: Option<&Sampled>,
        nominal: &Sampled,
        target: Option<&SO3>,
    ) {
        match &outcome.result {
            Ok(last) => {
                let relative = self.nominal_final.attitude.transpose() * last.attitude;
                let departure = SO3::from_matrix_unchecked(relative).log();
                self.largest_angle = self.largest_angle.max(departure.norm());
                self.departures.add(departure.as_slice());
                self.rates.add(last.omega.as_slice());
                if let (Some(p), Some(v), Some((x, xdot))) =
                    (&mut self.positions, &mut self.velocities, &last.motion)
                {
                    p.add(x.as_slice());
                    v.add(xdot.as_slice());
                }
                if let Some(w) = &mut self.wheel_speeds {
                    w.add(&last.wheel_speeds);
                }
                self.stop_times.extend(last.stop);
                self.settle_times.extend(last.settle);
            }
            Err(error) => self.failures.push(json!({
                "member": outcome.member.index,
                "seed": outcome.member.seed,
                "error": error,
            })),
        }
        if let Some(sampled) = sampled {
            self.envelope.add_member(nominal, sampled, target);
        }
    }
}

/// Running mean and covariance of vectors of one length (Welford's update, in the order
/// added).
#[derive(Serialize, Deserialize)]
struct Running {
    count: u64,
    mean: DVector<f64>,
    scatter: DMatrix<f64>,
}

impl Running {
    fn new(dimension: usize) -> Self {
        Self {
            count: 0,
            mean: DVector::zeros(dimension),
            scatter: DMatrix::zeros(dimension, dimension),
        }
    }

    fn add(&mut self, x: &[f64]) {
        let x = DVector::from_column_slice(x);
        self.count += 1;
        let before = &x - &self.mean;
        self.mean += &before / self.count as f64;
        self.scatter += &before * (&x - &self.mean).transpose();
    }

    /// Mean and covariance (unbiased; zero for one value; null for none), as JSON.
    fn json(&self) -> serde_json::Value {
        if self.count == 0 {
            return json!({"mean": null, "covariance": null});
        }
        // Welford's scatter is symmetric but for rounding: its symmetric part.
        let covariance = if self.count > 1 {
            (&self.scatter + self.scatter.transpose()) / (2.0 * (self.count - 1) as f64)
        } else {
            DMatrix::zeros(self.mean.len(), self.mean.len())
        };
        let rows: Vec<Vec<f64>> = covariance
            .row_iter()
            .map(|row| row.iter().copied().collect())
            .collect();
        json!({"mean": self.mean.as_slice(), "covariance": rows})
    }
}

/// `summary.json`: the run's description, the final state's statistics over the members
/// that finished (the rates' mean and covariance; the attitude's departure from the
/// nominal run's, as a rotation vector, its mean and covariance and the largest angle),
/// and every failure with its member, seed and cause.
fn summary(
    options: &MontecarloOptions,
    plan: &Plan,
    nominal: &Problem,
    stats: &Statistics,
    wall_time: f64,
) -> serde_json::Value {
    let mut settings =
        lgsvi_reports::trajectory::settings_json(&nominal.settings(), nominal.t_end, nominal.every);
    settings["check"] = format!("{:?}", nominal.check).into();
    let members = options.members.unwrap_or(DEFAULT_MEMBERS);
    let last = &stats.nominal_final;
    let mut summary = json!({
        "command": "montecarlo",
        "members": members,
        "finished": stats.finished(),
        "failed": stats.failures.len(),
        "seed": plan.seed(),
        "dispersions": plan.dispersions(),
        "nominal": nominal.description,
        "settings": settings,
        "nominal_final": {
            "t": last.time,
            "R": row_major(&last.attitude),
            "omega": last.omega.as_slice(),
        },
        "final_omega": stats.rates.json(),
        "final_attitude_departure": {
            "rotation_vector": stats.departures.json(),
            "largest_angle_rad": stats.largest_angle,
        },
        "failures": stats.failures,
        "wall_time_s": wall_time,
        "threads": rayon::current_num_threads(),
    });
    if let Some((x, v)) = last.motion {
        summary["nominal_final"]["x"] = x.as_slice().into();
        summary["nominal_final"]["v"] = v.as_slice().into();
    }
    if !last.wheel_speeds.is_empty() {
        summary["nominal_final"]["wheel_speeds"] = last.wheel_speeds.clone().into();
    }
    for (key, running) in [
        ("final_x", &stats.positions),
        ("final_v", &stats.velocities),
        ("final_wheel_speeds", &stats.wheel_speeds),
    ] {
        if let Some(running) = running {
            summary[key] = running.json();
        }
    }
    summary
}
