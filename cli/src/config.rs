//! The `simulate` configuration: TOML file, then command-line flags over it, then the
//! embedded defaults (the paper's parameters for each system).

use crate::error::CliError;
use clap::{Args, ValueEnum};
use lgsvi_mechanics::lie::{ChartKind, LieError, SO3};
use lgsvi_mechanics::settings::{NewtonJacobian, MAX_NODES};
use lgsvi_mechanics::Matching;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A built-in system.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SystemKind {
    /// The free rigid body, `ℓ = ½ΩᵀJΩ`.
    RigidBody,
    /// The heavy top / 3D pendulum, `ℓ = ½ΩᵀJΩ + m g e₃ᵀRρ`.
    HeavyTop,
    /// A free rigid body on SE(3): rotation and translation, `ℓ = ½ΩᵀJΩ + ½m|ẋ|²`.
    Se3Body,
    /// A rigid body orbiting a point mass on SE(3) (MacCullagh's potential: the
    /// gravity-gradient torque couples attitude and orbit).
    OrbitingBody,
    /// A spacecraft with 1 to 4 reaction wheels on SO(3) × ℝᴷ (`--wheel-axes`,
    /// `--wheel-inertia`): `ℓ = ½ΩᵀJΩ + Σ I_i (a_iᵀΩ) φ̇_i + ½ Σ I_i φ̇_i²`, J with the
    /// wheels locked; motor torques `--wheel-torque`.
    Gyrostat,
}

impl SystemKind {
    /// The name `--system` takes.
    pub fn name(self) -> &'static str {
        match self {
            SystemKind::RigidBody => "rigid-body",
            SystemKind::HeavyTop => "heavy-top",
            SystemKind::Se3Body => "se3-body",
            SystemKind::OrbitingBody => "orbiting-body",
            SystemKind::Gyrostat => "gyrostat",
        }
    }
}

/// The chart, for the command line and config files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ChartArg {
    /// The exponential map (default).
    Exp,
    /// The standard Cayley transform.
    Cayley,
    /// The paper's unscaled Cayley transform.
    CayleyUnscaled,
}

impl From<ChartArg> for ChartKind {
    fn from(c: ChartArg) -> Self {
        match c {
            ChartArg::Exp => ChartKind::Exp,
            ChartArg::Cayley => ChartKind::Cayley,
            ChartArg::CayleyUnscaled => ChartKind::CayleyUnscaled,
        }
    }
}

/// The momentum matching.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MatchingArg {
    /// The exact derivative of the discrete Lagrangian (default; conserves momenta).
    Exact,
    /// The paper's recipe (drifts; for reproducing the paper).
    Paper,
}

impl From<MatchingArg> for Matching {
    fn from(m: MatchingArg) -> Self {
        match m {
            MatchingArg::Exact => Matching::Exact,
            MatchingArg::Paper => Matching::Paper,
        }
    }
}

/// The Newton matrix.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum JacobianArg {
    /// Exact, by automatic differentiation (default).
    Exact,
    /// Forward differences (the paper's solver).
    FiniteDifference,
}

impl From<JacobianArg> for NewtonJacobian {
    fn from(j: JacobianArg) -> Self {
        match j {
            JacobianArg::Exact => NewtonJacobian::Exact,
            JacobianArg::FiniteDifference => NewtonJacobian::FiniteDifference,
        }
    }
}

/// Output format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Format {
    /// One JSON document (default).
    Json,
    /// One row per recorded state, with a header.
    Csv,
}

/// Parses `a,b,c` into `N` finite numbers.
pub(crate) fn numbers<const N: usize>(text: &str) -> Result<[f64; N], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(format!(
            "expected {N} comma-separated numbers, got {} in {text:?}",
            parts.len()
        ));
    }
    let mut out = [0.0; N];
    for (slot, part) in out.iter_mut().zip(&parts) {
        let value: f64 = part
            .parse()
            .map_err(|_| format!("{part:?} is not a number"))?;
        if !value.is_finite() {
            return Err(format!("{part:?} is not finite"));
        }
        *slot = value;
    }
    Ok(out)
}

/// A comma-separated list of numbers of any length (one flag value, or a TOML array).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(transparent)]
pub struct Numbers(pub Vec<f64>);

/// Parses `a,b,…` into finite numbers (at least one).
fn list(text: &str) -> Result<Numbers, String> {
    text.split(',')
        .map(str::trim)
        .map(|part| match part.parse::<f64>() {
            Ok(value) if value.is_finite() => Ok(value),
            Ok(_) => Err(format!("{part:?} is not finite")),
            Err(_) => Err(format!("{part:?} is not a number")),
        })
        .collect::<Result<Vec<f64>, String>>()
        .map(Numbers)
}

/// The options of `lgsvi simulate`: every one may also come from `--config FILE`
/// (same names, kebab-case keys, numbers and arrays as TOML values); flags win.
#[derive(Debug, Clone, Default, Args, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct SimulateOptions {
    /// Built-in system [default: rigid-body].
    #[arg(long, value_enum)]
    pub system: Option<SystemKind>,
    /// Standard principal moments of inertia J = diag(a, b, c) [default: the paper's, per system].
    #[arg(long, value_parser = numbers::<3>, allow_hyphen_values = true, conflicts_with = "inertia_d", value_name = "A,B,C")]
    pub inertia: Option<[f64; 3]>,
    /// The paper's nonstandard inertia J_d = diag(a, b, c), J = tr(J_d) I − J_d.
    #[arg(long, value_parser = numbers::<3>, allow_hyphen_values = true, value_name = "A,B,C")]
    pub inertia_d: Option<[f64; 3]>,
    /// Full body-frame inertia tensor J, 9 numbers row-major (symmetric, positive
    /// definite, principal moments obeying the triangle inequality); instead of --inertia.
    #[arg(long, value_parser = numbers::<9>, allow_hyphen_values = true, conflicts_with_all = ["inertia", "inertia_d"], value_name = "J11,...,J33")]
    pub inertia_tensor: Option<[f64; 9]>,
    /// Initial body angular velocity Ω(0) [default: the paper's, per system].
    #[arg(long, value_parser = numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub omega0: Option<[f64; 3]>,
    /// Initial attitude R(0) = world_from_body, 9 numbers row-major [default: identity].
    #[arg(long, value_parser = numbers::<9>, allow_hyphen_values = true, conflicts_with = "quaternion0", value_name = "R11,...,R33")]
    pub attitude0: Option<[f64; 9]>,
    /// Initial attitude as a unit quaternion (w, x, y, z), Hamilton convention.
    #[arg(long, value_parser = numbers::<4>, allow_hyphen_values = true, value_name = "W,X,Y,Z")]
    pub quaternion0: Option<[f64; 4]>,
    /// Heavy top, se3-body, orbiting-body: mass m [default: 1].
    #[arg(long, allow_hyphen_values = true)]
    pub mass: Option<f64>,
    /// Orbiting body: gravitational parameter μ = GM of the point mass at the origin [default: 1].
    #[arg(long, allow_hyphen_values = true)]
    pub mu: Option<f64>,
    /// SE(3) systems: initial centre of mass x(0), world frame [default: 3,0,0 for
    /// orbiting-body, 0,0,0 for se3-body].
    #[arg(long, value_parser = numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub position0: Option<[f64; 3]>,
    /// SE(3) systems: initial centre-of-mass velocity ẋ(0), world frame [default:
    /// 0,0.55,0.05 for orbiting-body, 0,0,0 for se3-body].
    #[arg(long, value_parser = numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub velocity0: Option<[f64; 3]>,
    /// A constant body-frame torque τ on the body (every system) [default: none].
    #[arg(long, value_parser = numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub torque: Option<[f64; 3]>,
    /// Angular damping: a torque −cΩ with c ≥ 0 (every system) [default: 0].
    #[arg(long, allow_hyphen_values = true, value_name = "C")]
    pub damping: Option<f64>,
    /// PD attitude control: a torque −K·θ toward the target attitude (--target-quaternion),
    /// θ = log(R_targetᵀR) the body's rotation vector from the target (body frame, rad), K ≥
    /// 0 in N·m/rad; with --damping C as the derivative gain the law is −Kθ − CΩ, a
    /// continuous law integrated to the method's order (every system but the gyrostat)
    /// [default: 0].
    #[arg(long, allow_hyphen_values = true, value_name = "K")]
    pub attitude_gain: Option<f64>,
    /// A sampled PD law: --attitude-gain K and --damping C are a controller's gains, its
    /// torque −Kθ − CΩ evaluated from the state every T from the start and held until the
    /// next sample (zero-order hold), as a flight computer runs it, instead of a continuous
    /// law; T is a whole number of steps (--h; by default the longest step up to 0.5 that
    /// divides T, and --t-end too where one at least an eighth as long does, else the run's
    /// end is refused, naming the ends that fit) (every system but the gyrostat) [default:
    /// continuous].
    #[arg(long, allow_hyphen_values = true, value_name = "T")]
    pub sample_period: Option<f64>,
    /// The actuator's largest torque L, N·m: a sampled law's torque longer than L is scaled
    /// back to length L along its own direction (needs --sample-period) [default: no limit].
    #[arg(long, allow_hyphen_values = true, value_name = "L")]
    pub torque_limit: Option<f64>,
    /// The target attitude as a unit quaternion (w, x, y, z), Hamilton convention: what
    /// --attitude-gain turns the body to and what the `error` quantity of --stop-when and
    /// --settle-when is measured from [default: identity].
    #[arg(long, value_parser = numbers::<4>, allow_hyphen_values = true, value_name = "W,X,Y,Z")]
    pub target_quaternion: Option<[f64; 4]>,
    /// Gyrostat: the wheel axes in the body frame, three numbers per wheel, 1 to 4 wheels
    /// [default: the body axes x, y, z].
    #[arg(long, value_parser = list, allow_hyphen_values = true, value_name = "X1,Y1,Z1,...")]
    pub wheel_axes: Option<Numbers>,
    /// Gyrostat: each wheel's axial inertia I_i > 0 [default: 0.05 each].
    #[arg(long, value_parser = list, allow_hyphen_values = true, value_name = "I1,...")]
    pub wheel_inertia: Option<Numbers>,
    /// Gyrostat: each wheel's initial spin rate relative to the body, rad per unit time
    /// [default: 0].
    #[arg(long, value_parser = list, allow_hyphen_values = true, value_name = "W1,...")]
    pub wheel_speeds0: Option<Numbers>,
    /// Gyrostat: a constant motor torque on each wheel (the body takes the reaction)
    /// [default: 0].
    #[arg(long, value_parser = list, allow_hyphen_values = true, value_name = "T1,...")]
    pub wheel_torque: Option<Numbers>,
    /// Heavy top: gravitational acceleration g [default: 9.81].
    #[arg(long, allow_hyphen_values = true)]
    pub gravity: Option<f64>,
    /// Heavy top: centre of mass ρ in the body frame [default: 0,0,1].
    #[arg(long, value_parser = numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub com: Option<[f64; 3]>,
    /// Heavy top: the direction gravity pulls in, world frame [default: 0,0,1, the paper's e₃].
    #[arg(long, value_parser = numbers::<3>, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub gravity_direction: Option<[f64; 3]>,
    /// Step h, between 1e-280 and 1e280 [default: 0.5].
    #[arg(long, allow_hyphen_values = true)]
    pub h: Option<f64>,
    /// Chebyshev–Lobatto nodes, 2 ≤ n ≤ 100 (polynomial degree n − 1) [default: 10].
    #[arg(long)]
    pub nodes: Option<usize>,
    /// Gauss points, 1 ≤ m ≤ 1000 [default: n].
    #[arg(long)]
    pub quad: Option<usize>,
    /// Accuracy wanted along the run, e.g. 1e-10: the nodes are chosen per step (5 to 30,
    /// rising only) from each step's own error estimate so that the local errors add up to
    /// at most TOL over --t-end, and, unless --h is given, the step from the initial motion (3 rad of
    /// rotation per step with exp, π/2 with a Cayley chart); --nodes is then the first
    /// step's count [default: 3 + ⌈−log₁₀(TOL)/2⌉]. The run is checked by a companion
    /// taking every step with 2 more nodes: where the two differ by more than 3·TOL the run
    /// is taken again with a tighter share per step (three runs at most), then refused.
    /// Not with --quad (the Gauss points follow the nodes).
    #[arg(long, allow_hyphen_values = true, value_name = "TOL")]
    pub tol: Option<f64>,
    /// A fixed-(h, n) run: run the companion check too (the same steps with 2 more nodes,
    /// about twice the time), so that `estimated_error` is the measured difference at the
    /// end instead of the sum of the steps' local estimates. --tol runs are checked anyway,
    /// and so are fixed runs on SE(3) and of an inertia whose principal moments span 100 or
    /// more, where the steps' own estimates miss rounding the motion amplifies.
    #[arg(long)]
    #[serde(default)]
    pub check: bool,
    /// With --tol: skip the companion check (about half the time); the reported estimate is
    /// then the sum of the steps' local estimates, which does not see errors that grow
    /// along the motion (fast spins, unstable or orbital motion).
    #[arg(long)]
    #[serde(default)]
    pub no_check: bool,
    /// Natural chart [default: exp].
    #[arg(long, value_enum)]
    pub chart: Option<ChartArg>,
    /// Momentum matching [default: exact].
    #[arg(long, value_enum)]
    pub matching: Option<MatchingArg>,
    /// Newton matrix [default: exact].
    #[arg(long, value_enum)]
    pub jacobian: Option<JacobianArg>,
    /// Final time T, a whole number of steps h (the method takes fixed steps; other values
    /// are refused with the nearest that work), at most 10⁹ steps [default: 10].
    #[arg(long, allow_hyphen_values = true)]
    pub t_end: Option<f64>,
    /// Keep every K-th step (and always the first and last) [default: 1].
    #[arg(long)]
    pub every: Option<usize>,
    /// Stop after the step in which a quantity falls below (`<`) or rises above (`>`) a
    /// value, e.g. `omega_3<0.1` or `angle>90` (degrees turned from the start); the
    /// crossing's time and state are reported (`stopped` in the JSON). Quantities:
    /// omega_1..3, omega, angle, error (degrees from the target attitude,
    /// --target-quaternion), x_1..3, r, speed (bodies in space), wheel_1..4 (gyrostats).
    #[arg(long, value_name = "CONDITION")]
    pub stop_when: Option<String>,
    /// Report the settling time of a condition (the quantities of --stop-when): the time
    /// from which it holds to the run's end, e.g. `omega<0.001` (the rates stay below
    /// 1e-3 rad/s) or `error<0.1` (the pointing error stays below 0.1°) — the last crossing
    /// into it, located on the step's curve (`settled` in the JSON; null where it does not
    /// hold at the end).
    #[arg(long, value_name = "CONDITION")]
    pub settle_when: Option<String>,
    /// Output format [default: json].
    #[arg(long, value_enum)]
    pub format: Option<Format>,
    /// Output file [default: standard output].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also draw the run's conservation figure to PLOT.svg and PLOT.png: the energy
    /// balance |E − E₀ − W| and the drift of the conserved momenta over time.
    #[arg(long, value_name = "PLOT")]
    pub plot: Option<PathBuf>,
    /// No progress bar (one is shown on a terminal for runs of 1000 steps or more).
    #[arg(long)]
    #[serde(default)]
    pub quiet: bool,
    /// Print the exact solution (free rigid body only: Jacobi elliptic functions) at the
    /// times the integrator would record, in the same format, instead of integrating.
    #[arg(long)]
    #[serde(default)]
    pub exact: bool,
    /// A TOML file with any of these options (flags given on the command line win).
    #[arg(long)]
    #[serde(skip)]
    pub config: Option<PathBuf>,
}

impl SimulateOptions {
    /// The file's options with these flags laid over them.
    pub fn merged_with_config(self) -> Result<Self, CliError> {
        let Some(path) = self.config.clone() else {
            return Ok(self);
        };
        let (mut table, _) = read_config_table(&path, "converge")?;
        table.remove("converge");
        table.remove("montecarlo");
        let mut merged: Self = overlaid(table, &self, &path, "")?;
        merged.config = Some(path);
        Ok(merged)
    }

    /// The system, defaulting to the rigid body.
    pub fn system(&self) -> SystemKind {
        self.system.unwrap_or(SystemKind::RigidBody)
    }

    /// The target attitude (`--target-quaternion`), the identity where none is given.
    pub fn target(&self) -> Result<SO3, CliError> {
        self.target_quaternion.map_or(Ok(SO3::identity()), |q| {
            SO3::try_from_quaternion_wxyz(q).map_err(|source| CliError::Geometry {
                flag: "--target-quaternion",
                source,
            })
        })
    }

    /// The initial attitude.
    pub fn attitude(&self) -> Result<SO3, CliError> {
        match (self.attitude0, self.quaternion0) {
            (Some(_), Some(_)) => Err(CliError::Conflict("--attitude0", "--quaternion0")),
            (Some(r), None) => SO3::try_from_row_major(r).map_err(|e| match e {
                LieError::NotOrthogonal { deviation, .. } => CliError::NotARotation { deviation },
                source => CliError::Geometry {
                    flag: "--attitude0",
                    source,
                },
            }),
            (None, Some(q)) => {
                SO3::try_from_quaternion_wxyz(q).map_err(|source| CliError::Geometry {
                    flag: "--quaternion0",
                    source,
                })
            }
            (None, None) => Ok(SO3::identity()),
        }
    }
}

/// `table` (from a config file) with the options given as flags (`flags`) laid over it,
/// deserialized: a flag replaces its key; one inertia and one attitude, the command
/// line's if it gives one.
pub fn overlaid<T: Serialize + serde::de::DeserializeOwned>(
    mut table: toml::Table,
    flags: &T,
    path: &Path,
    prefix: &str,
) -> Result<T, CliError> {
    let given = toml::Table::try_from(flags).map_err(|e| config_error(path, &e.to_string()))?;
    let groups = [
        &["inertia", "inertia-d", "inertia-tensor"][..],
        &["attitude0", "quaternion0"],
    ];
    for group in groups
        .into_iter()
        .filter(|g| g.iter().any(|k| given.contains_key(*k)))
    {
        group.iter().for_each(|key| drop(table.remove(*key)));
    }
    // Options not given are `None` (left out of `given`) or `false`.
    table.extend(
        given
            .into_iter()
            .filter(|(_, value)| value != &toml::Value::Boolean(false)),
    );
    deserialize_naming_the_key(table, path, prefix)
}

/// Deserializes a config table; a refused value's message names its key (`prefix` before
/// it, e.g. `[converge] `): the first entry that fails on its own. A table read into a
/// value carries no positions, and "invalid type: floating point `8.0`, expected usize"
/// alone does not say which of twenty keys holds it.
fn deserialize_naming_the_key<T: serde::de::DeserializeOwned>(
    table: toml::Table,
    path: &Path,
    prefix: &str,
) -> Result<T, CliError> {
    T::deserialize(table.clone()).map_err(|e| {
        let key = table.iter().find_map(|(key, value)| {
            let mut alone = toml::Table::new();
            alone.insert(key.clone(), value.clone());
            T::deserialize(alone).is_err().then_some(key)
        });
        match key {
            Some(key) => config_error(path, &format!("{prefix}{key}: {}", e.message())),
            None => config_error(path, &format!("{prefix}{}", e.message())),
        }
    })
}

/// A parser's message about a config file, on one line.
pub fn config_error(path: &Path, message: &str) -> CliError {
    CliError::Config {
        path: path.to_path_buf(),
        message: message.replace('\n', " "),
    }
}

/// The config file as a table, and its table `[section]` (a command's own keys:
/// `converge`, `montecarlo`).
pub fn read_config_table(
    path: &Path,
    section: &str,
) -> Result<(toml::Table, Option<toml::Table>), CliError> {
    let text = std::fs::read_to_string(path).map_err(|source| CliError::ReadConfig {
        path: path.to_path_buf(),
        source,
    })?;
    let table: toml::Table = toml::from_str(&text).map_err(|e| config_error(path, e.message()))?;
    let own = match table.get(section) {
        None => None,
        Some(toml::Value::Table(t)) => Some(t.clone()),
        Some(_) => return Err(config_error(path, &format!("`{section}` must be a table"))),
    };
    Ok((table, own))
}

/// Which refinements `lgsvi converge` runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StudyKind {
    /// n-refinement at fixed h.
    Nodes,
    /// h-refinement at fixed n.
    Step,
    /// Both.
    Both,
    /// The per-step error estimate against the true local error, over a grid of `(h, n)`
    /// (any system: SO(3), SE(3), the gyrostat).
    Estimate,
    /// `--tol` runs over a list of tolerances against a reference and the fastest fixed
    /// `(h, n)` as accurate (any system).
    Tolerance,
}

pub(crate) fn node_range(text: &str) -> Result<[usize; 2], String> {
    let (a, b) = text
        .split_once("..")
        .ok_or_else(|| format!("expected a range like 2..16, got {text:?}"))?;
    let parse = |s: &str| {
        s.trim()
            .parse::<usize>()
            .map_err(|_| format!("{s:?} is not a node count"))
    };
    let (a, b) = (parse(a)?, parse(b)?);
    if a < 2 || b < a || b > MAX_NODES {
        return Err(format!(
            "invalid range {text}: need 2 ≤ first ≤ last ≤ {MAX_NODES}"
        ));
    }
    Ok([a, b])
}

pub(crate) fn positive_step(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(h) if h.is_finite() && h > 0.0 => Ok(h),
        _ => Err(format!("{text:?} is not a positive step")),
    }
}

pub(crate) fn node_count(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if (2..=MAX_NODES).contains(&n) => Ok(n),
        _ => Err(format!(
            "{text:?} is not a node count from 2 to {MAX_NODES}"
        )),
    }
}

/// `lgsvi converge`: the system and integrator flags of `simulate`, plus the study's.
#[derive(Debug, Clone, Default, Args, Deserialize, Serialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
// simulate's `--exact`, `--every`, `--check`, `--no-check`, `--stop-when` and
// `--settle-when` do not apply to a study: not listed in its help, and refused if given.
#[command(
    mut_arg("exact", |a| a.hide(true)),
    mut_arg("every", |a| a.hide(true)),
    mut_arg("check", |a| a.hide(true)),
    mut_arg("no_check", |a| a.hide(true)),
    mut_arg("stop_when", |a| a.hide(true)),
    mut_arg("settle_when", |a| a.hide(true))
)]
pub struct ConvergeOptions {
    /// System, initial state, chart, matching, `--h` (the step of the n-refinement),
    /// `--t-end` (default 10), `--format`, `--out` (the data), `--config`. A config file may
    /// hold the study's keys in a `[converge]` table (kebab-case, as the flags).
    #[command(flatten)]
    #[serde(skip)]
    pub base: SimulateOptions,
    /// Which refinement: nodes, step or both [default: both].
    #[arg(long, value_enum)]
    pub study: Option<StudyKind>,
    /// n-refinement: node counts, as FIRST..LAST [default: 2..16].
    #[arg(long, value_parser = node_range, value_name = "FIRST..LAST")]
    pub nodes_range: Option<[usize; 2]>,
    /// h-refinement: the steps [default: 1,0.5,0.25,0.125,0.0625].
    #[arg(long, value_parser = positive_step, value_delimiter = ',', value_name = "H1,H2,...")]
    pub steps: Option<Vec<f64>>,
    /// h-refinement: one series per node count [default: 2,3,4,5].
    #[arg(long, value_parser = node_count, value_delimiter = ',', value_name = "N1,N2,...")]
    pub step_nodes: Option<Vec<usize>>,
    /// Points per step at which the Galerkin curve is compared, 1 (none) to 1000 [default: 8].
    #[arg(long)]
    pub curve_samples: Option<usize>,
    /// Tolerance study: the tolerances [default: 1e-6,1e-7,…,1e-13].
    #[arg(long, value_parser = positive_tolerance, value_delimiter = ',', value_name = "T1,T2,...")]
    pub tols: Option<Vec<f64>>,
}

fn positive_tolerance(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(t) if t.is_finite() && t > 0.0 => Ok(t),
        _ => Err(format!("{text:?} is not a positive tolerance like 1e-10")),
    }
}
