//! `lgsvi montecarlo`: many runs of simulate's system, each member's inertia, start and
//! torque dispersed about the nominal ([`lgsvi_montecarlo`]), in parallel; one CSV row per
//! member and a JSON summary (final-state statistics and every failure).
//!
//! Every member runs exactly as `lgsvi simulate` with its drawn parameters as flags
//! (`--inertia-tensor` its `J`, `--attitude0` its `R₀`, `--omega0` its `Ω₀`, `--torque`
//! its torque, the nominal's other flags): `members.csv` prints those and the final state
//! to round-trip, so simulate given a row's parameters reproduces the row bit for bit, and
//! `--replay K` does so for member `K`, writing its whole trajectory.

use crate::config::{config_error, SimulateOptions};
use crate::error::{CliError, Result};
use crate::problem::Problem;
use clap::Args;
use lgsvi_mechanics::lie::{LieGroup, SO3};
use lgsvi_montecarlo::{Dispersion, DispersionError, Dispersions, Member, Nominal, Plan};
use nalgebra::{Matrix3, Vector3};
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
    /// The nominal run: simulate's flags (rigid-body and heavy-top so far). A config file
    /// (`--config`) may hold the Monte Carlo keys below in a `[montecarlo]` table, and the
    /// whole dispersion spec in `[montecarlo.dispersions]` (keys `attitude`, `omega`,
    /// `inertia`, `inertia_misalignment`, `torque`, each a table like
    /// `{ distribution = "truncated_normal", sigma = 0.02, bound = 0.06 }`).
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
}

/// One member's outcome: its draws, and its final state or why it failed.
struct Outcome {
    member: Member,
    result: std::result::Result<Final, String>,
}

/// A member's last recorded state.
#[derive(Clone, Copy)]
struct Final {
    time: f64,
    attitude: Matrix3<f64>,
    omega: Vector3<f64>,
}

/// Runs `lgsvi montecarlo`; `Ok(())` when every member finished, else
/// [`CliError::MembersFailed`] after writing everything.
pub fn run(options: MontecarloOptions) -> Result<()> {
    let options = with_config(options)?;
    let base = &options.base;
    let row = "montecarlo writes one row per member (see --replay)";
    for (flag, given, why) in [
        ("--every", base.every.is_some(), row),
        ("--format", base.format.is_some(), row),
        (
            "--plot",
            base.plot.is_some(),
            "montecarlo draws no figure yet",
        ),
        ("--exact", base.exact, "montecarlo integrates every member"),
    ] {
        if given {
            return Err(CliError::SimulateOnly { flag, why });
        }
    }
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
    let scenario = &nominal_problem.scenario;
    if scenario.motion.is_some() || scenario.wheels.is_some() {
        return Err(CliError::invalid(
            "--system",
            resolved.system().name(),
            "montecarlo runs bodies on SO(3) (rigid-body, heavy-top) so far",
        ));
    }
    let mut nominal = Nominal::body(scenario.inertia, scenario.attitude0, scenario.omega0);
    nominal.torque = resolved.torque.map_or(Vector3::zeros(), Vector3::from);
    let dispersions = dispersions(&options)?;
    let plan = Plan::new(nominal, dispersions, seed).map_err(|error| {
        // A dispersion set by a flag is refused naming the flag.
        let flag = match &error {
            DispersionError::NotPhysical { key: "inertia", .. } => options
                .disperse_inertia
                .map(|f| ("--disperse-inertia", f, " (truncated at 3 FRACTION)")),
            _ => None,
        };
        match flag {
            Some((flag, value, how)) => CliError::invalid(flag, value, format!("{error}{how}")),
            None => error.into(),
        }
    })?;
    let member_options = |member: &Member| {
        let mut o = resolved.clone();
        o.config = None;
        o.quiet = true;
        o.out = None;
        o.inertia = None;
        o.inertia_d = None;
        o.inertia_tensor = Some(row_major(&member.inertia.matrix()));
        o.quaternion0 = None;
        o.attitude0 = Some(row_major(member.attitude.matrix()));
        o.omega0 = Some(member.omega.into());
        if member.torque != Vector3::zeros() || o.torque.is_some() {
            o.torque = Some(member.torque.into());
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
    if table.exists() {
        return Err(CliError::invalid(
            "--out",
            out.display(),
            "the folder holds another run (members.csv): give another folder, or remove it",
        ));
    }
    std::fs::create_dir_all(&out).map_err(|source| CliError::CreateDir {
        path: out.clone(),
        source,
    })?;
    let bar = crate::progress::bar(members, "members", "members", base.quiet);
    let started = std::time::Instant::now();
    let outcomes: Vec<Outcome> = (0..members)
        .into_par_iter()
        .map(|index| {
            let outcome = run_member(&plan, index, &member_options);
            bar.inc(1);
            outcome
        })
        .collect::<Result<_>>()?;
    bar.finish_and_clear();
    let wall_time = started.elapsed().as_secs_f64();
    let nominal_final =
        run_to_end(&nominal_problem).map_err(|e| CliError::invalid("the nominal run", "", e))?;
    crate::files::write(&table, members_csv(&outcomes).as_bytes())?;
    let summary = summary(
        &options,
        &plan,
        &nominal_problem,
        &outcomes,
        nominal_final,
        wall_time,
    );
    let text = serde_json::to_string_pretty(&summary)? + "\n";
    let summary_path = out.join("summary.json");
    crate::files::write(&summary_path, text.as_bytes())?;
    let failed = outcomes.iter().filter(|o| o.result.is_err()).count();
    if failed > 0 {
        return Err(CliError::MembersFailed {
            failed,
            members: outcomes.len(),
            summary: summary_path,
        });
    }
    Ok(())
}

/// The members run without `--members` (a quick look; thousands for a sign-off).
const DEFAULT_MEMBERS: u64 = 100;
/// The most members one run takes (its table is held in memory).
const MAX_MEMBERS: u64 = 10_000_000;
/// The output folder without `--out`.
const DEFAULT_OUT: &str = "lgsvi-montecarlo";

/// The options with the config's `[montecarlo]` table under the flags.
fn with_config(options: MontecarloOptions) -> Result<MontecarloOptions> {
    let Some(path) = options.base.config.clone() else {
        return Ok(options);
    };
    let text = std::fs::read_to_string(&path).map_err(|source| CliError::ReadConfig {
        path: path.clone(),
        source,
    })?;
    let table: toml::Table = toml::from_str(&text).map_err(|e| config_error(&path, e.message()))?;
    let Some(section) = table.get("montecarlo") else {
        return Ok(options);
    };
    let toml::Value::Table(section) = section else {
        return Err(config_error(&path, "`montecarlo` must be a table"));
    };
    let mut section = section.clone();
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
fn dispersions(options: &MontecarloOptions) -> Result<Dispersions> {
    let mut spec = options.dispersions.unwrap_or_default();
    let checked = |flag: &'static str, value: f64| -> Result<f64> {
        if value >= 0.0 && value.is_finite() {
            Ok(value)
        } else {
            Err(CliError::invalid(
                flag,
                value,
                "a standard deviation is finite and ≥ 0",
            ))
        }
    };
    if let Some(sigma) = options.disperse_omega {
        spec.omega = Some(Dispersion::Normal {
            sigma: checked("--disperse-omega", sigma)?,
        });
    }
    if let Some(sigma) = options.disperse_inertia {
        let sigma = checked("--disperse-inertia", sigma)?;
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
            sigma: checked("--disperse-attitude", degrees)?.to_radians(),
        });
    }
    Ok(spec)
}

/// Member `index` drawn and run as simulate runs it with its parameters as flags.
fn run_member(
    plan: &Plan,
    index: u64,
    options: &dyn Fn(&Member) -> SimulateOptions,
) -> Result<Outcome> {
    let member = plan.member(index)?;
    let result = Problem::resolve(options(&member))
        .map_err(|e| e.to_string())
        .and_then(|(problem, _)| run_to_end(&problem));
    Ok(Outcome { member, result })
}

/// The problem's run to its end (its last state), or why it failed, on one line.
fn run_to_end(problem: &Problem) -> std::result::Result<Final, String> {
    let settings = problem.settings();
    let steps =
        crate::problem::whole_steps(problem.t_end, settings.h()).map_err(|e| e.to_string())?;
    let recording = problem
        .scenario
        .record(
            settings,
            problem.check,
            problem.t_end,
            steps.max(1),
            &mut |_| {},
        )
        .map_err(|e| e.to_string().replace('\n', " "))?;
    let last = recording.states.last().ok_or("no state recorded")?;
    Ok(Final {
        time: last.time,
        attitude: *last.attitude().matrix(),
        omega: last.velocity,
    })
}

/// A 3×3 matrix's entries, row by row.
fn row_major(m: &Matrix3<f64>) -> [f64; 9] {
    [
        m.m11, m.m12, m.m13, m.m21, m.m22, m.m23, m.m31, m.m32, m.m33,
    ]
}

/// `members.csv`: one row per member in member order; every float in Rust's shortest form
/// that reads back to the same bits.
fn members_csv(outcomes: &[Outcome]) -> String {
    let names = |prefix: &str| -> Vec<String> {
        (1..=3)
            .flat_map(|i| (1..=3).map(move |j| format!("{prefix}_{i}{j}")))
            .collect()
    };
    let mut header = vec!["member".to_string(), "status".to_string()];
    header.extend(names("J"));
    header.extend(names("R0"));
    header.extend((1..=3).map(|i| format!("omega0_{i}")));
    header.push("t".into());
    header.extend(names("R"));
    header.extend((1..=3).map(|i| format!("omega_{i}")));
    let mut text = header.join(",") + "\n";
    for outcome in outcomes {
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
        cells.extend(floats(&row_major(&m.inertia.matrix())));
        cells.extend(floats(&row_major(m.attitude.matrix())));
        cells.extend(floats(m.omega.as_slice()));
        match &outcome.result {
            Ok(f) => {
                cells.extend(floats(&[f.time]));
                cells.extend(floats(&row_major(&f.attitude)));
                cells.extend(floats(f.omega.as_slice()));
            }
            Err(_) => cells.extend(std::iter::repeat_n(String::new(), 13)),
        }
        text += &(cells.join(",") + "\n");
    }
    text
}

/// `summary.json`: the run's description, the final state's statistics over the members
/// that finished (the rates' mean and covariance; the attitude's departure from the
/// nominal run's, as a rotation vector, its mean and covariance and the largest angle),
/// and every failure with its member, seed and cause.
fn summary(
    options: &MontecarloOptions,
    plan: &Plan,
    nominal: &Problem,
    outcomes: &[Outcome],
    nominal_final: Final,
    wall_time: f64,
) -> serde_json::Value {
    let finished: Vec<&Final> = outcomes
        .iter()
        .filter_map(|o| o.result.as_ref().ok())
        .collect();
    let reference = SO3::from_matrix_unchecked(nominal_final.attitude);
    let departures: Vec<Vector3<f64>> = finished
        .iter()
        .map(|f| {
            reference
                .inverse()
                .compose(&SO3::from_matrix_unchecked(f.attitude))
                .log()
        })
        .collect();
    let rates: Vec<Vector3<f64>> = finished.iter().map(|f| f.omega).collect();
    let failures: Vec<serde_json::Value> = outcomes
        .iter()
        .filter_map(|o| {
            o.result.as_ref().err().map(
                |error| json!({"member": o.member.index, "seed": o.member.seed, "error": error}),
            )
        })
        .collect();
    let largest_angle = departures.iter().map(|d| d.norm()).fold(0.0, f64::max);
    let mut settings =
        lgsvi_reports::trajectory::settings_json(&nominal.settings(), nominal.t_end, nominal.every);
    settings["check"] = format!("{:?}", nominal.check).into();
    json!({
        "command": "montecarlo",
        "members": outcomes.len(),
        "finished": finished.len(),
        "failed": failures.len(),
        "seed": plan.seed(),
        "dispersions": plan.dispersions(),
        "nominal": nominal.description,
        "settings": settings,
        "nominal_final": {
            "t": nominal_final.time,
            "R": row_major(&nominal_final.attitude),
            "omega": nominal_final.omega.as_slice(),
        },
        "final_omega": moments(&rates),
        "final_attitude_departure": {
            "rotation_vector": moments(&departures),
            "largest_angle_rad": largest_angle,
        },
        "failures": failures,
        "wall_time_s": wall_time,
        "threads": rayon::current_num_threads(),
        "members_requested": options.members.unwrap_or(DEFAULT_MEMBERS),
    })
}

/// Mean and covariance (unbiased; zero for fewer than two) of 3-vectors, as JSON.
fn moments(values: &[Vector3<f64>]) -> serde_json::Value {
    let n = values.len() as f64;
    if values.is_empty() {
        return json!({"mean": null, "covariance": null});
    }
    let mean = values.iter().sum::<Vector3<f64>>() / n;
    let covariance = if values.len() > 1 {
        values
            .iter()
            .map(|v| (v - mean) * (v - mean).transpose())
            .sum::<Matrix3<f64>>()
            / (n - 1.0)
    } else {
        Matrix3::zeros()
    };
    let rows: Vec<[f64; 3]> = (0..3)
        .map(|i| [covariance[(i, 0)], covariance[(i, 1)], covariance[(i, 2)]])
        .collect();
    json!({"mean": mean.as_slice(), "covariance": rows})
}
