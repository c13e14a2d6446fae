//! The front door for runs: [`IntegratorBuilder`] takes a system, its start, and either a
//! fixed step and node count or a tolerance, and gives a stepper ([`crate::Stepper`]).

use crate::control::GroupLog;
use crate::error::MechanicsError;
use crate::group::GroupChart;
use crate::integrator::Integrator;
use crate::settings::{Matching, StepSettings, DEFAULT_ADAPTIVE_NODES, DEFAULT_NODES};
use crate::system::{ElementOf, System};
use crate::tolerance::{first_nodes, tolerance_step, CheckedIntegrator};
use lgsvi_lie::ChartKind;
use nalgebra::SVector;

/// Builds a run of a system from its start: with a fixed step `h` and `n` nodes, or to a
/// tolerance over a horizon, where the step, the first step's nodes and the nodes per step
/// are chosen for you ([`crate::tolerance`]).
///
/// - [`IntegratorBuilder::build`] gives an [`Integrator`]: the step you drive from a
///   control loop (its tolerance-driven runs are not checked).
/// - [`IntegratorBuilder::build_checked`] gives a [`CheckedIntegrator`]: every step taken
///   again beside a companion with two more nodes, the difference measured; with a
///   tolerance, a run that misses it is taken again with a tightened share per step, and
///   one that cannot meet it is an error. This is what `lgsvi simulate --tol` runs.
///
/// Both are [`crate::Stepper`]s (`step`, `run`, `run_until`, `drive`).
///
/// ```
/// use lgsvi_mechanics::prelude::*;
///
/// // The paper's rigid body to 1e-10 over T = 100, checked.
/// let body = RigidBody::new(Inertia::from_paper_jd([1.3, 2.1, 1.2])?);
/// let mut run = Integrator::builder(body)
///     .start(SO3::identity(), Vector3::new(-2.0, 1.9, -1.0))
///     .tolerance(1e-10)
///     .horizon(100.0)
///     .build_checked()?;
/// let trajectory = run.run_until(100.0, 10)?;
/// assert_eq!(trajectory.states.last().unwrap().time, 100.0);
/// // The companion's measured difference, within the tolerance's acceptance.
/// assert!(run.estimated_error() <= 3e-10);
///
/// // A fixed step and node count, for a control loop.
/// let mut integrator = Integrator::builder(body)
///     .start(SO3::identity(), Vector3::new(-2.0, 1.9, -1.0))
///     .step(0.5)
///     .nodes(8)
///     .build()?;
/// integrator.set_input(Vector3::new(0.0, 0.0, 0.1))?;
/// integrator.step()?;
/// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
/// ```
#[derive(Debug, Clone)]
pub struct IntegratorBuilder<S: System<D>, const D: usize> {
    system: S,
    start: Option<(f64, ElementOf<S, D>, SVector<f64, D>)>,
    h: Option<f64>,
    nodes: Option<usize>,
    tolerance: Option<f64>,
    horizon: Option<f64>,
    chart: Option<ChartKind>,
    matching: Option<Matching>,
    quadrature_points: Option<usize>,
    settings: Option<StepSettings>,
    input: Option<SVector<f64, D>>,
}

impl<S: System<D>, const D: usize> Integrator<S, ChartKind, D>
where
    ChartKind: GroupChart<S::Group, D>,
{
    /// A builder for a run of `system` ([`IntegratorBuilder`]).
    pub fn builder(system: S) -> IntegratorBuilder<S, D> {
        IntegratorBuilder {
            system,
            start: None,
            h: None,
            nodes: None,
            tolerance: None,
            horizon: None,
            chart: None,
            matching: None,
            quadrature_points: None,
            settings: None,
            input: None,
        }
    }
}

impl<S: System<D>, const D: usize> IntegratorBuilder<S, D>
where
    ChartKind: GroupChart<S::Group, D>,
{
    /// Starts at configuration `g₀` (on SO(3) the attitude `R₀ = world_from_body`) with
    /// body velocity `ξ₀` (on SO(3) `Ω₀`), at `t = 0`. Required.
    pub fn start(mut self, configuration: ElementOf<S, D>, velocity: SVector<f64, D>) -> Self {
        self.start = Some((0.0, configuration, velocity));
        self
    }

    /// Starts at time `t₀` from `(g₀, ξ₀)` ([`IntegratorBuilder::start`]).
    pub fn start_at(
        mut self,
        time: f64,
        configuration: ElementOf<S, D>,
        velocity: SVector<f64, D>,
    ) -> Self {
        self.start = Some((time, configuration, velocity));
        self
    }

    /// The step `h`. Without a tolerance it is required; with one it overrides the step
    /// chosen from the motion.
    pub fn step(mut self, h: f64) -> Self {
        self.h = Some(h);
        self
    }

    /// The number of Chebyshev–Lobatto nodes `n` (degree `n − 1`): a fixed run's
    /// ([`crate::settings::DEFAULT_NODES`] unless given), or a tolerance-driven run's first step (within
    /// [`crate::settings::DEFAULT_ADAPTIVE_NODES`]; [`first_nodes`] of the tolerance unless
    /// given).
    pub fn nodes(mut self, n: usize) -> Self {
        self.nodes = Some(n);
        self
    }

    /// Runs to a tolerance: the largest error of the attitude (radians), the velocity
    /// and, on SE(3), the position at the horizon ([`IntegratorBuilder::horizon`],
    /// required with it). The nodes adapt per step to a share of `tolerance / horizon` per
    /// unit time; unless given, the step divides the horizon into steps of about 3 rad at
    /// the initial motion's rate ([`crate::tolerance::step_count`]) and the first step
    /// takes [`first_nodes`]`(tolerance)` nodes.
    pub fn tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = Some(tolerance);
        self
    }

    /// The horizon `T` of a tolerance-driven run (the run goes from `t₀` to `t₀ + T`).
    pub fn horizon(mut self, t_end: f64) -> Self {
        self.horizon = Some(t_end);
        self
    }

    /// The chart (default: exp, which reaches a full turn per step; the paper's unscaled
    /// Cayley map reproduces its figures).
    pub fn chart(mut self, chart: ChartKind) -> Self {
        self.chart = Some(chart);
        self
    }

    /// The momentum matching (default: exact, which makes the map exactly variational).
    pub fn matching(mut self, matching: Matching) -> Self {
        self.matching = Some(matching);
        self
    }

    /// The number of Gauss points `m` of a fixed run (default `m = n`).
    pub fn quadrature_points(mut self, m: usize) -> Self {
        self.quadrature_points = Some(m);
        self
    }

    /// The control input held from the start ([`Integrator::set_input`]): a checked run
    /// that is taken again starts again with it.
    pub fn input(mut self, input: SVector<f64, D>) -> Self {
        self.input = Some(input);
        self
    }

    /// Every setting at once, for what the other methods do not reach (the Newton
    /// Jacobian, the iteration cap, factor reuse): the step, nodes, chart, matching and
    /// Gauss points given to this builder replace the settings' own; a tolerance makes the
    /// settings tolerance-driven.
    pub fn settings(mut self, settings: StepSettings) -> Self {
        self.settings = Some(settings);
        self
    }

    /// The integrator ([`Integrator`]): a fixed run, or a tolerance-driven run that is not
    /// checked (its [`Integrator::estimated_global_error`] is the sum of the steps' local
    /// estimates, a model; [`IntegratorBuilder::build_checked`] measures instead).
    ///
    /// # Errors
    /// [`MechanicsError::InvalidSetting`] naming what is missing or out of range: no start,
    /// neither a step nor a tolerance, a tolerance without a horizon, a horizon that is not
    /// positive and finite, nodes outside `2…100` (with a tolerance, outside
    /// [`crate::settings::DEFAULT_ADAPTIVE_NODES`]), a tolerance below the rounding of the
    /// run's steps;
    /// [`Integrator::new`]'s errors for the start (not finite, off the group).
    pub fn build(self) -> Result<Integrator<S, ChartKind, D>, MechanicsError> {
        let Some((time, configuration, velocity)) = self.start else {
            return Err(MechanicsError::InvalidSetting {
                name: "start",
                value: "none".into(),
                reason: "a run needs its start: call .start(configuration, velocity)",
            });
        };
        let settings = self.resolve(&configuration, &velocity)?;
        let input = self.input;
        let mut integrator = Integrator::new(self.system, settings, configuration, velocity)?;
        if time != 0.0 {
            integrator.reset(time, configuration, velocity)?;
        }
        if let Some(input) = input {
            integrator.set_input(input)?;
        }
        Ok(integrator)
    }

    /// The checked run ([`CheckedIntegrator`]): beside a companion with two more nodes per
    /// step; with a tolerance, held to it (taken again with a tightened share per step
    /// where it misses, an error where it cannot meet it).
    ///
    /// # Errors
    /// As [`IntegratorBuilder::build`]; [`CheckedIntegrator::with_extra_nodes`]'s.
    pub fn build_checked(self) -> Result<CheckedIntegrator<S, ChartKind, D>, MechanicsError>
    where
        S: Clone,
        ElementOf<S, D>: GroupLog<D>,
    {
        let tolerance = self.tolerance;
        let checked = CheckedIntegrator::new(self.build()?)?;
        match tolerance {
            Some(tolerance) => checked.with_tolerance(tolerance),
            None => Ok(checked),
        }
    }

    /// The step settings this builder describes, for a run from `(g₀, ξ₀)`.
    fn resolve(
        &self,
        configuration: &ElementOf<S, D>,
        velocity: &SVector<f64, D>,
    ) -> Result<StepSettings, MechanicsError> {
        let horizon = match (self.tolerance, self.horizon) {
            (Some(_), None) => {
                return Err(MechanicsError::InvalidSetting {
                    name: "horizon",
                    value: "none".into(),
                    reason: "a tolerance-driven run needs its horizon (.horizon(t_end)): each \
                             step's share of the error is tolerance / horizon",
                })
            }
            (_, Some(t)) if !(t.is_finite() && t > 0.0) => {
                return Err(MechanicsError::InvalidSetting {
                    name: "horizon",
                    value: format!("{t:?}"),
                    reason: "must be positive and finite",
                })
            }
            (_, horizon) => horizon,
        };
        if let Some(tol) = self.tolerance {
            if !(tol.is_finite() && tol > 0.0) {
                return Err(MechanicsError::InvalidSetting {
                    name: "tolerance",
                    value: format!("{tol:?}"),
                    reason: "must be positive and finite",
                });
            }
        }
        let base = self.settings;
        let chart = self.chart.or(base.map(|s| s.chart())).unwrap_or_default();
        let matching = self
            .matching
            .or(base.map(|s| s.matching()))
            .unwrap_or_default();
        let h = match (self.h, self.tolerance, horizon) {
            (Some(h), _, _) => h,
            (None, Some(_), Some(t_end)) => {
                tolerance_step(&self.system, &chart, t_end, configuration, velocity)
                    .unwrap_or(t_end)
            }
            _ => match base {
                Some(settings) => settings.h(),
                None => {
                    return Err(MechanicsError::InvalidSetting {
                        name: "step",
                        value: "none".into(),
                        reason: "give a step (.step(h)) and nodes, or a tolerance and horizon \
                                 (.tolerance(tol).horizon(t_end))",
                    })
                }
            },
        };
        let nodes = match (self.nodes, self.tolerance) {
            (Some(n), Some(_)) => {
                let (least, most) = DEFAULT_ADAPTIVE_NODES;
                if !(least..=most).contains(&n) {
                    return Err(MechanicsError::InvalidSetting {
                        name: "nodes",
                        value: n.to_string(),
                        reason: "with a tolerance, the nodes are the first step's, within the \
                                 adaptive range 5 to 30",
                    });
                }
                n
            }
            (Some(n), None) => n,
            (None, Some(tol)) => first_nodes(tol),
            (None, None) => base.map_or(DEFAULT_NODES, |s| s.nodes()),
        };
        let mut settings = StepSettings::new(h, nodes)?;
        if let Some(base) = base {
            settings = settings
                .with_jacobian(base.jacobian())
                .with_max_newton_iterations(base.max_newton_iterations())
                .with_factor_reuse(base.reuses_factors());
        }
        if let Some(m) = self
            .quadrature_points
            .or(base.and_then(|s| s.explicit_quadrature_points()))
        {
            settings = settings.with_quadrature_points(m)?;
        }
        if let (Some(tol), Some(t_end)) = (self.tolerance, horizon) {
            settings = settings.with_tolerance(tol / t_end.max(h))?;
        }
        Ok(settings.with_chart(chart).with_matching(matching))
    }
}
