//! The command line's one error type. Each variant is one line that says what was wrong
//! and what to change; `main` prints it after `error: ` and exits with a failure code.

use lgsvi_mechanics::lie::LieError;
use lgsvi_mechanics::MechanicsError;
use std::path::PathBuf;

/// Why a command failed.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// From the integrator, a system or a setting (a setting the command line has a flag
    /// for arrives as [`CliError::Input`], naming the flag: see the `From` impl).
    #[error("{}", command_line_words(.0))]
    Mechanics(#[source] MechanicsError),
    /// From a study of `lgsvi-experiments`.
    #[error(transparent)]
    Experiment(#[from] lgsvi_experiments::ExperimentError),
    /// From a measurement of `lgsvi-bench`.
    #[error(transparent)]
    Bench(#[from] lgsvi_bench::BenchError),
    /// A flag's value that the mechanics layer refused.
    #[error("{flag}: {source}")]
    Input {
        /// The flag.
        flag: &'static str,
        /// Why.
        source: MechanicsError,
    },
    /// A flag's value that the geometry layer refused.
    #[error("{flag}: {source}")]
    Geometry {
        /// The flag.
        flag: &'static str,
        /// Why.
        source: LieError,
    },
    /// `--attitude0` is not orthogonal.
    #[error(
        "--attitude0: not a rotation matrix (‖RᵀR − I‖ = {deviation:.1e}); give its nine entries \
         row-major to full precision, or the attitude as --quaternion0 w,x,y,z"
    )]
    NotARotation {
        /// `‖RᵀR − I‖_F`.
        deviation: f64,
    },
    /// Two flags that exclude each other.
    #[error("give {0} or {1}, not both")]
    Conflict(&'static str, &'static str),
    /// A heavy-top parameter given for the free body.
    #[error("{flag} applies to the heavy top only (--system heavy-top); the rigid body is free")]
    HeavyTopOnly {
        /// The flag.
        flag: &'static str,
    },
    /// A flag that does not apply to the chosen system.
    #[error("{flag} does not apply to --system {system}: it applies to {applies}")]
    NotForSystem {
        /// The flag.
        flag: &'static str,
        /// The system chosen.
        system: &'static str,
        /// The systems it applies to.
        applies: String,
    },
    /// A `simulate` flag given to `converge`.
    #[error("{flag} is a simulate option; {why}")]
    SimulateOnly {
        /// The flag.
        flag: &'static str,
        /// What `converge` does instead.
        why: &'static str,
    },
    /// A value out of its range.
    #[error("invalid {flag} {value}: {reason}")]
    Invalid {
        /// The flag.
        flag: &'static str,
        /// The value, as given.
        value: String,
        /// The allowed range.
        reason: String,
    },
    /// A value from a config file that the flag's parser refuses.
    #[error("{key}: {reason}")]
    ConfigValue {
        /// The config key.
        key: &'static str,
        /// The parser's message.
        reason: String,
    },
    /// More steps than a run may take.
    #[error(
        "--t-end {t_end:?} with --h {h:?} asks for {steps:.3e} steps, more than the \
         {most:.0e} a run may take: take a shorter horizon or a longer step"
    )]
    TooManySteps {
        /// The horizon.
        t_end: f64,
        /// The step.
        h: f64,
        /// `t_end / h`.
        steps: f64,
        /// The most a run may take (`problem::MAX_RUN_STEPS`).
        most: f64,
    },
    /// A horizon that is not a whole number of steps.
    #[error(
        "--t-end {t_end:?} is not a whole number of steps h = {h:?}: the method takes fixed \
         steps, so end at {below:?} or {above:?}, or take h = {fitted:?} ({steps} step{})",
        if *steps == 1.0 { "" } else { "s" }
    )]
    NotWholeSteps {
        /// The horizon.
        t_end: f64,
        /// The step.
        h: f64,
        /// The whole-step horizons on either side.
        below: f64,
        /// See `below`.
        above: f64,
        /// A step that divides `t_end`.
        fitted: f64,
        /// The number of steps of `fitted`.
        steps: f64,
    },
    /// `--exact` for a system without a closed-form solution.
    #[error(
        "the exact solution is known for the free rigid body only (system rigid-body, \
         or a heavy top with m g = 0)"
    )]
    NoExactSolution,
    /// A config file that cannot be read.
    #[error("cannot read config {}: {source}", path.display())]
    ReadConfig {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A config file that does not parse or holds an unknown key.
    #[error("config {}: {message}", path.display())]
    Config {
        /// The file.
        path: PathBuf,
        /// The parser's message, on one line.
        message: String,
    },
    /// An output folder that cannot be created.
    #[error("cannot create {}: {source}", path.display())]
    CreateDir {
        /// The folder.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A `--tol` run that failed: the library's `ToleranceNotMet` (a step cannot meet its
    /// share of the tolerance) or `ToleranceNotChecked` (the companion check measured more
    /// than the tolerance on every attempt), with the command line's remedies for a run of
    /// step `h`.
    #[error("{}", tolerance_message(source, *h))]
    Tolerance {
        /// The library's error.
        source: MechanicsError,
        /// The run's step.
        h: f64,
    },
    /// Two outputs of one run on the same file.
    #[error(
        "{first} and {second} would both write {}: the later would replace the earlier; give \
         them different paths",
        path.display()
    )]
    Collision {
        /// The first flag.
        first: &'static str,
        /// The second flag.
        second: &'static str,
        /// The file.
        path: PathBuf,
    },
    /// An output file that cannot be written.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Standard output closed or full.
    #[error("cannot write to standard output: {0}")]
    Stdout(std::io::Error),
    /// A figure that could not be drawn.
    #[error("{}: {message}", path.display())]
    Plot {
        /// The figure's file.
        path: PathBuf,
        /// The renderer's message.
        message: String,
    },
    /// A Monte Carlo dispersion spec refused (its message names the dispersion's key).
    #[error(transparent)]
    Dispersion(#[from] lgsvi_montecarlo::DispersionError),
    /// Members of a Monte Carlo run that failed (each listed with its seed and cause in
    /// the summary); everything else was written.
    #[error(
        "{failed} of {members} members failed; each is listed with its seed and cause in {}",
        summary.display()
    )]
    MembersFailed {
        /// How many failed.
        failed: usize,
        /// How many ran.
        members: usize,
        /// The summary that lists them.
        summary: PathBuf,
    },
    /// JSON that could not be produced.
    #[error("JSON: {0}")]
    Json(#[from] serde_json::Error),
}

/// A `--tol` run's failure in the command line's terms: what happened, and which flag to
/// change.
fn tolerance_message(error: &MechanicsError, h: f64) -> String {
    match *error {
        MechanicsError::ToleranceNotMet {
            step,
            time,
            estimate,
            budget,
            nodes,
            ..
        } => format!(
            "step {step} (t = {time}): the error estimate {estimate:.1e} stays above the step's \
             share {budget:.1e} of --tol at {nodes} nodes, the most a --tol run takes: raise \
             --tol, or shorten the step (--h {:?} or less)",
            h / 10.0
        ),
        MechanicsError::ToleranceNotChecked {
            tolerance,
            attempts,
            tightened,
            measured,
            time,
            step,
            at_floor,
            best,
        } => {
            let advice = if at_floor {
                format!(
                    "at the rounding of every step (4ε), this motion amplifies rounding errors \
                     to about that (the closest of the runs: {best:.1e}): ask for --tol \
                     {best:.0e} or more"
                )
            } else {
                format!(
                    "the motion amplifies each step's error: raise --tol, or shorten the step \
                     (--h {:?} or less)",
                    h / 3.0
                )
            };
            format!(
                "--tol {tolerance:e} not met: after {attempts} run(s), the last with a share per \
                 step {tightened:.0e}× below the first's, the run still differs by \
                 {measured:.1e} from its check (the same steps with 2 more nodes) at t = {time} \
                 (step {step}); {advice}"
            )
        }
        ref other => other.to_string(),
    }
}

/// The command line's result.
pub type Result<T, E = CliError> = std::result::Result<T, E>;

/// Refuses the first of `flags` that was given: `(flag, given, why)`, `why` what the command
/// does instead ([`CliError::SimulateOnly`]). The commands that share simulate's flags
/// (`converge`, `linearize`, `montecarlo`) list the ones that do not apply to them.
pub fn refuse_simulate_only(flags: &[(&'static str, bool, &'static str)]) -> Result<()> {
    match flags.iter().find(|(_, given, _)| *given) {
        Some(&(flag, _, why)) => Err(CliError::SimulateOnly { flag, why }),
        None => Ok(()),
    }
}

impl CliError {
    /// [`CliError::Invalid`]: `flag`'s `value` refused, and why.
    pub fn invalid(flag: &'static str, value: impl ToString, reason: impl Into<String>) -> Self {
        CliError::Invalid {
            flag,
            value: value.to_string(),
            reason: reason.into(),
        }
    }

    /// A mechanics error that came through a recording or a study as
    /// [`CliError::Mechanics`], so that one match sees it wherever it arose.
    pub fn into_mechanics(self) -> Self {
        match self {
            CliError::Experiment(lgsvi_experiments::ExperimentError::Mechanics(error)) => {
                CliError::Mechanics(error)
            }
            other => other,
        }
    }
}

/// The command-line flag of a mechanics setting or input, by the name the library's
/// [`MechanicsError::InvalidSetting`] and [`MechanicsError::NonFinite`] give it.
fn flag_of(name: &str) -> Option<&'static str> {
    Some(match name {
        "h" => "--h",
        "nodes" => "--nodes",
        "quad" => "--quad",
        "tol" | "tolerance" => "--tol",
        "t-end" | "horizon" => "--t-end",
        "mass" => "--mass",
        "mu" => "--mu",
        "gravity" => "--gravity",
        "gravity direction" => "--gravity-direction",
        "centre of mass" => "--com",
        "initial angular velocity" => "--omega0",
        "inertia J_d" => "--inertia-d",
        "wheel inertia" => "--wheel-inertia",
        "wheel axis" => "--wheel-axes",
        _ => return None,
    })
}

/// A library error's message in the command line's words: its advice to take the exp chart
/// names the flag that takes it.
fn command_line_words(error: &MechanicsError) -> String {
    error
        .to_string()
        .replace("the exp chart,", "the exp chart (--chart exp),")
}

impl From<MechanicsError> for CliError {
    /// A refused setting or input that has a flag names it ([`CliError::Input`]); any other
    /// mechanics error passes through as it is.
    fn from(source: MechanicsError) -> Self {
        let name = match &source {
            MechanicsError::InvalidSetting { name, .. } => Some(*name),
            MechanicsError::NonFinite { what, .. } => Some(*what),
            _ => None,
        };
        match name.and_then(flag_of) {
            Some(flag) => CliError::Input { flag, source },
            None => CliError::Mechanics(source),
        }
    }
}
