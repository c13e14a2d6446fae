//! Errors of this crate.

use lgsvi_lie::LieError;
use lgsvi_quadrature::QuadratureError;
use lgsvi_spectral::SpectralError;

/// The condition number of `∂²ℓ/∂ξ²` from which a failed step is put down to it
/// ([`MechanicsError::IllConditioned`]): the velocity is then recovered from the momentum
/// to no better than `ε · 10⁶ ≈ 2e-10` of its size. On thin rods `J = (δ, 1, 1)`,
/// `δ = 1e-6` steps as any body, `δ ≤ 1e-7` fails Newton at `h = 0.5` and, at shorter
/// steps, differs between step sizes by about `ε/δ`.
pub(crate) const ILL_CONDITIONED: f64 = 1e6;

/// Why a system, a setting or a step was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MechanicsError {
    /// An inertia that no rigid body has.
    #[error("non-physical inertia {moments:?}: {reason}")]
    InvalidInertia {
        /// The principal moments (or diagonal) given.
        moments: [f64; 3],
        /// What is wrong and what to change.
        reason: String,
    },
    /// NaN or infinity in an input.
    #[error("{what} is not finite: {value}")]
    NonFinite {
        /// Which input.
        what: &'static str,
        /// Its value, as written.
        value: String,
    },
    /// A start the system cannot take: an orbiting body at (or next to) its attracting
    /// centre, inside its own far field, or too far out for double precision
    /// ([`crate::OrbitingBody::check_position`]).
    #[error("invalid start {value}: {reason}")]
    InvalidStart {
        /// The start, as written.
        value: String,
        /// Why the system cannot take it, and what to change.
        reason: String,
    },
    /// A setting out of range.
    #[error("invalid setting {name} = {value}: {reason}")]
    InvalidSetting {
        /// The setting's name.
        name: &'static str,
        /// Its value, as written.
        value: String,
        /// The allowed range.
        reason: &'static str,
    },
    /// Newton's iteration did not converge.
    #[error(
        "step {step} (t = {time}): Newton did not converge in {iterations} iterations \
         (residual {residual:e}); take a smaller step h or more nodes{advice}"
    )]
    NewtonDiverged {
        /// The step that failed (0-based).
        step: usize,
        /// Its start time.
        time: f64,
        /// Iterations spent.
        iterations: usize,
        /// The last residual norm.
        residual: f64,
        /// The chart's own advice ([`crate::group::GroupChart::advice`]): another chart that
        /// follows longer steps, where there is one; empty for the exp chart, which
        /// already does.
        advice: &'static str,
    },
    /// `Ω` could not be recovered from `μ` (the Lagrangian is not convex in `Ω` there).
    #[error(
        "cannot recover the velocity from the momentum (residual {residual:e}): the \
         Lagrangian must be strictly convex in the velocity; check the system's kinetic \
         energy (its inertia and mass, or your Lagrangian's velocity terms) at this state"
    )]
    InverseLegendre {
        /// The last residual `|∂ℓ/∂Ω − μ|`.
        residual: f64,
    },
    /// A step failed because the Lagrangian is not strictly convex in the velocity at the
    /// state: `∂²ℓ/∂ξ²` is singular or indefinite (a zero or negative inertia or mass).
    #[error(
        "step {step} (t = {time}): the Lagrangian is not strictly convex in the velocity here \
         (∂²ℓ/∂ξ² has eigenvalues from {least:e} to {most:e}): a zero or negative inertia or \
         mass, or velocity terms of your own Lagrangian that are not strictly convex at this \
         state; check the system's parameters (e.g. what system_mut changed) — no step h or \
         node count can mend it"
    )]
    DegenerateLagrangian {
        /// The step that failed (0-based).
        step: usize,
        /// Its start time.
        time: f64,
        /// The least eigenvalue of `∂²ℓ/∂ξ²`.
        least: f64,
        /// The largest in magnitude.
        most: f64,
    },
    /// A step failed where `∂²ℓ/∂ξ²` (the inertia, with the mass in space) is
    /// ill-conditioned: the velocity follows from the momentum only to about `ε` times its
    /// condition number, which Newton's tolerance cannot see below. A principal moment (or
    /// the mass, in these units) far below the others; a shorter step may converge, but no
    /// run is more accurate than that. The step's own failure is the source.
    #[error(
        "step {step} (t = {time}): the step failed where the Lagrangian's Hessian ∂²ℓ/∂ξ² is \
         ill-conditioned (eigenvalues from {least:.3e} to {most:.3e}, condition {:.1e}): {}; give the \
         smallest principal moment (or the mass, in units that make it comparable) a size \
         within {:.0e} of the largest: a shorter step h may converge, but no run is more \
         accurate than that",
        most / least,
        recovered_to(f64::EPSILON * most / least),
        ILL_CONDITIONED
    )]
    IllConditioned {
        /// The step that failed (0-based).
        step: usize,
        /// Its start time.
        time: f64,
        /// The least eigenvalue of `∂²ℓ/∂ξ²`.
        least: f64,
        /// The largest.
        most: f64,
        /// How the step failed.
        #[source]
        failure: Box<MechanicsError>,
    },
    /// A step ended where the state lies outside what the system models
    /// ([`crate::System::model_breakdown`]): an orbiting body falling within twice its
    /// radius of gyration of the attracting point, for instance. The step is not taken
    /// (the state stays the last one the model holds at); the run's physics, not its
    /// step, must change.
    #[error("step {step} (t = {time}) ends outside what the system models: {reason}")]
    LeftModel {
        /// The step (0-based).
        step: usize,
        /// Its start time.
        time: f64,
        /// What lies outside the model at the step's end, and what to change.
        reason: String,
    },
    /// A step failed where the state lies outside what the system models
    /// ([`crate::System::model_breakdown`]): an orbiting body whose mass surrounds
    /// the attracting point, for instance. A shorter step or more nodes do not make the
    /// model hold there; the step's own failure is the source.
    #[error("step {step} (t = {time}): the step failed outside what the system models: {reason}")]
    OutsideModel {
        /// The step that failed (0-based).
        step: usize,
        /// Its start time.
        time: f64,
        /// What lies outside the model, and what to change.
        reason: String,
        /// How the step failed.
        #[source]
        failure: Box<MechanicsError>,
    },
    /// The Newton matrix is singular (or the iteration produced non-finite numbers).
    #[error("step {step} (t = {time}): singular Newton system; take a smaller step h{advice}")]
    SingularJacobian {
        /// The step that failed.
        step: usize,
        /// Its start time.
        time: f64,
        /// The chart's own advice, as for [`MechanicsError::NewtonDiverged`].
        advice: &'static str,
    },
    /// The motion turns the body further within one step than the chart can follow: a
    /// root Newton found would be an aliased one (energy and momenta conserved, the
    /// attitude wrong by a turn the chart cannot see).
    #[error(
        "step {step} (t = {time}): the body turns by at least {rotation:.3} rad within the step, \
         beyond the {chart} chart's reach of {limit:.3} rad; take a smaller step h (below {}){advice}",
        readable(*suggested)
    )]
    StepTooLong {
        /// The step that failed (0-based).
        step: usize,
        /// Its start time.
        time: f64,
        /// The chart's name.
        chart: &'static str,
        /// The rotation angle the motion reaches (an estimate).
        rotation: f64,
        /// The chart's [`lgsvi_lie::So3Chart::max_rotation_angle`].
        limit: f64,
        /// A step that stays within reach at the present speed.
        suggested: f64,
        /// What else to change, if anything.
        advice: &'static str,
    },
    /// Newton converged, but to an attitude that is not the continuation of the motion
    /// (checked against the system's own flow over the step): an aliased root.
    #[error(
        "step {step} (t = {time}): Newton converged to an attitude {} (an aliased root of the \
         {chart} chart); take a smaller step h{advice}",
        away_from_flow(*distance)
    )]
    AliasedRoot {
        /// The step that failed (0-based).
        step: usize,
        /// Its start time.
        time: f64,
        /// The chart's name.
        chart: &'static str,
        /// The rotation angle between the converged attitude and the flow's.
        distance: f64,
        /// What else to change, if anything.
        advice: &'static str,
    },
    /// The step's curve left the domain of the chart.
    #[error("step {step} (t = {time}): {source}")]
    OutsideChart {
        /// The step that failed.
        step: usize,
        /// Its start time.
        time: f64,
        /// What the chart said.
        source: LieError,
    },
    /// A tolerance-driven step whose error estimate stays above its share of the
    /// tolerance with every remedy the settings allow spent (the most nodes, and the
    /// most halvings of the step where the step may change): accepting it would end the
    /// run further from the truth than the tolerance asked.
    #[error(
        "step {step} (t = {time}): the error estimate {estimate:e} stays above the step's share \
         {budget:e} of the tolerance at {nodes} nodes{halved}; {advice}"
    )]
    ToleranceNotMet {
        /// The step that failed (0-based).
        step: usize,
        /// Its start time.
        time: f64,
        /// The step's error estimate.
        estimate: f64,
        /// Its share of the tolerance (`rate · h`).
        budget: f64,
        /// The nodes it was solved with (the most allowed).
        nodes: usize,
        /// ", after halving the step to …" where the step was halved.
        halved: String,
        /// What to change.
        advice: &'static str,
    },
    /// A checked tolerance run ([`crate::tolerance::ToleranceCheck`]) whose difference from its
    /// companion stayed above `CHECK_ACCEPTS · tolerance` on every run allowed, or at the
    /// rounding of a step.
    #[error(
        "tolerance {tolerance:e} not met: after {attempts} run(s), the last with a share per \
         step {tightened:.0e}× below the first's, the run differs by {measured:.1e} from its \
         check at t = {time} (step {step}); {}",
        if *at_floor {
            format!("at the rounding of every step, the motion amplifies rounding errors to \
                     about {best:.1e}: ask for at least that")
        } else {
            "the motion amplifies each step's error: raise the tolerance or shorten the step"
                .to_string()
        }
    )]
    ToleranceNotChecked {
        /// The tolerance asked for.
        tolerance: f64,
        /// Runs taken.
        attempts: usize,
        /// The last run's share per step against the first's.
        tightened: f64,
        /// The last run's largest difference.
        measured: f64,
        /// Where it was measured: the time and the step (1-based).
        time: f64,
        /// The step after which it was measured.
        step: usize,
        /// Whether the share per step had reached the rounding of a step.
        at_floor: bool,
        /// The least largest difference of the runs: what the motion allows.
        best: f64,
    },
    /// The companion of a checked run ([`crate::tolerance::CheckedIntegrator`]) failed on a step the run itself
    /// took: the run cannot be checked from there.
    #[error(
        "step {step} (t = {time}): the check of the run (the same step with more nodes) \
         failed: {source}; shorten the step h so that both solve it"
    )]
    CheckFailed {
        /// The step that failed (0-based).
        step: usize,
        /// The time the step reached.
        time: f64,
        /// The companion's error.
        source: Box<MechanicsError>,
    },
    /// A step whose result is not finite (a user's force or Lagrangian returning NaN or
    /// infinity there, or an overflow).
    #[error("step {step} (t = {time}): {what} is not finite; {hint}")]
    NonFiniteStep {
        /// The step that failed (0-based).
        step: usize,
        /// Its start time.
        time: f64,
        /// The quantity.
        what: &'static str,
        /// Where to look.
        hint: &'static str,
    },
    /// A starting configuration that is not on the group (an attitude that is not a
    /// rotation).
    #[error("{what}: {source}")]
    NotOnGroup {
        /// Which configuration ("initial configuration", "reset configuration").
        what: &'static str,
        /// Why it is not on the group.
        source: LieError,
    },
    /// An invalid attitude or other geometric input.
    #[error(transparent)]
    Lie(#[from] LieError),
    /// From the quadrature layer.
    #[error(transparent)]
    Quadrature(#[from] QuadratureError),
    /// From the spectral layer.
    #[error(transparent)]
    Spectral(#[from] SpectralError),
}

/// A non-finite check with a helpful error.
pub(crate) fn check_finite(what: &'static str, values: &[f64]) -> Result<(), MechanicsError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(MechanicsError::NonFinite {
            what,
            value: format!("{values:?}"),
        })
    }
}

/// How well the velocity follows from the momentum at a relative rounding of `relative`,
/// for [`MechanicsError::IllConditioned`]'s message.
fn recovered_to(relative: f64) -> String {
    if relative < 0.1 {
        format!("the velocity follows from the momentum only to about {relative:.0e} of its size")
    } else {
        "the velocity is not determined by the momentum in double precision".to_string()
    }
}

/// Where an aliased root lies from the flow's end, for [`MechanicsError::AliasedRoot`]'s
/// message (a distance that is not finite is said so, not printed as "NaN rad").
fn away_from_flow(distance: f64) -> String {
    if distance.is_finite() {
        format!("{distance:.3} rad away from the motion's continuation")
    } else {
        "whose distance from the motion's continuation is not finite".into()
    }
}

/// A positive number for a message: three decimals where that shows four significant
/// digits or fewer zeros, scientific notation below 1e-3 (a step "below 0.000" says
/// nothing).
fn readable(x: f64) -> String {
    if x.abs() >= 1e-3 || x == 0.0 {
        format!("{x:.3}")
    } else {
        format!("{x:.3e}")
    }
}
