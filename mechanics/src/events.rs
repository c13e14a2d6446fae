//! Events: the times where a scalar function of the state crosses zero, located on each
//! step's Galerkin curve (the dense output), recorded or ending the run.
//!
//! An [`Event`] is a function `g(t, g, ξ)` of the time, configuration and body velocity,
//! a [`Direction`] (rising: `g` goes from negative to zero or positive; falling: the
//! reverse; either), and whether it stops the run. [`Events`] is an
//! [`Observer`]: give it to any driven run
//! ([`Stepper::drive`](crate::Stepper::drive), [`Stepper::drive_until`](crate::Stepper::drive_until),
//! alone or paired with a recorder) and after every step it
//!
//! 1. samples `g` along the step's curve at `n + 1` evenly spaced times (`n` the step's
//!    nodes), so a crossing is seen unless two fall within one sample spacing `h/n`;
//! 2. in each sample interval where `g` changes sign in the event's direction, fits `g`
//!    along the curve by a Chebyshev series to machine precision
//!    ([`lgsvi_spectral::Chebyshev::fit`]) and takes its root (colleague matrix, polished
//!    by Newton on the series): the curve's own crossing;
//! 3. refines it by the method's own steps: a variational step of length `τ` from the
//!    step's start lands on the motion to the accuracy of a step's end, which the curve
//!    between its nodes does not reach (there it is a lower-order approximation: at a
//!    tolerance run's long steps, 1e-7 inside against 1e-13 at the ends on an
//!    axisymmetric body); Newton on `τ`, each iterate one such step, until `τ` moves by a
//!    few ulps (two or three steps);
//! 4. records an [`EventHit`] (which event, time, configuration and velocity there) and,
//!    for a terminal event, stops the run after that step; later hits in the same step
//!    are dropped.
//!
//! The refinement needs the step's start, which the driving loops give every observer
//! ([`Observer::before_step`]), and a clone of the
//! system (`S: Clone`); where a refining step fails, the curve's crossing stands.
//!
//! A crossing at a step's end is reported once: a rising event counts `g` going from below
//! zero to zero or above, so the next step, starting at zero, does not count it again.
//! Where the curves of two steps disagree in sign at their common time (a velocity's
//! value jumps by the steps' error there), the crossing is reported at that time.
//!
//! ```
//! use lgsvi_mechanics::events::{Event, Events};
//! use lgsvi_mechanics::prelude::*;
//!
//! // An axisymmetric body (J₁ = J₂): Ω₁(t) = a cos(λt) with λ = (J₃ − J₁) Ω₃ / J₁.
//! let body = RigidBody::new(Inertia::from_principal_moments([1.0, 1.0, 2.0])?);
//! let omega0 = Vector3::new(0.3, 0.0, 1.5);
//! let lambda = (2.0 - 1.0) * 1.5 / 1.0;
//! let mut integrator = Integrator::new(body, StepSettings::new(0.25, 12)?, SO3::identity(), omega0)?;
//! let mut events = Events::new(vec![
//!     Event::new("omega_1 falls through 0", |_t, _r: &SO3, w: &Vector3<f64>| w.x).falling().terminal(),
//! ]);
//! integrator.drive_until(10.0, &mut events)?;
//! let hit = &events.hits()[0];
//! let exact = std::f64::consts::FRAC_PI_2 / lambda;
//! assert!((hit.time - exact).abs() <= 1e-12 * exact);
//! assert!(integrator.state().time < exact + 0.25); // stopped after that step
//! # Ok::<(), lgsvi_mechanics::MechanicsError>(())
//! ```

use crate::error::MechanicsError;
use crate::group::{GroupChart, StepGroup};
use crate::integrator::{GalerkinCurve, Integrator};
use crate::state::State;
use crate::stepper::{Observer, StepInfo};
use crate::system::{ElementOf, System};
use lgsvi_spectral::Chebyshev;
use nalgebra::SVector;
use std::ops::ControlFlow;

/// Which zero crossings of an event's function count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Direction {
    /// From negative to zero or positive.
    Rising,
    /// From positive to zero or negative.
    Falling,
    /// Both.
    Either,
}

impl Direction {
    /// Whether going from `a` to `b` is a crossing of this direction; the crossing's own
    /// direction.
    fn crossing(self, a: f64, b: f64) -> Option<Direction> {
        let rising = a < 0.0 && b >= 0.0;
        let falling = a > 0.0 && b <= 0.0;
        match self {
            Direction::Rising if rising => Some(Direction::Rising),
            Direction::Falling if falling => Some(Direction::Falling),
            Direction::Either if rising => Some(Direction::Rising),
            Direction::Either if falling => Some(Direction::Falling),
            _ => None,
        }
    }
}

/// The function of an event: `g(t, configuration, body velocity)`.
pub type EventFunction<'a, E, const D: usize> =
    Box<dyn FnMut(f64, &E, &SVector<f64, D>) -> f64 + 'a>;

/// A scalar function of the state whose zero crossings are located ([module
/// documentation](self)): either direction and recorded unless told otherwise.
pub struct Event<'a, E, const D: usize> {
    name: String,
    function: EventFunction<'a, E, D>,
    direction: Direction,
    terminal: bool,
}

impl<'a, E, const D: usize> Event<'a, E, D> {
    /// An event named `name` (for reports) of `g(t, configuration, body velocity)`:
    /// crossings in either direction, recorded.
    pub fn new(
        name: impl Into<String>,
        function: impl FnMut(f64, &E, &SVector<f64, D>) -> f64 + 'a,
    ) -> Self {
        Self {
            name: name.into(),
            function: Box::new(function),
            direction: Direction::Either,
            terminal: false,
        }
    }

    /// Only crossings from negative to zero or positive.
    pub fn rising(self) -> Self {
        self.direction(Direction::Rising)
    }

    /// Only crossings from positive to zero or negative.
    pub fn falling(self) -> Self {
        self.direction(Direction::Falling)
    }

    /// Crossings of `direction`.
    pub fn direction(mut self, direction: Direction) -> Self {
        self.direction = direction;
        self
    }

    /// The first crossing stops the run (after the step in which it falls).
    pub fn terminal(mut self) -> Self {
        self.terminal = true;
        self
    }

    /// The event's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Which crossings count.
    pub fn crossings(&self) -> Direction {
        self.direction
    }

    /// Whether its first crossing stops the run.
    pub fn is_terminal(&self) -> bool {
        self.terminal
    }
}

impl<E, const D: usize> std::fmt::Debug for Event<'_, E, D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Event")
            .field("name", &self.name)
            .field("direction", &self.direction)
            .field("terminal", &self.terminal)
            .finish_non_exhaustive()
    }
}

/// A located crossing.
#[derive(Debug, Clone, PartialEq)]
pub struct EventHit<E, const D: usize> {
    /// The event's index in [`Events::new`]'s list.
    pub event: usize,
    /// Its time.
    pub time: f64,
    /// Whether the function rose or fell through zero there.
    pub direction: Direction,
    /// The configuration on the step's curve at that time.
    pub configuration: E,
    /// The body velocity on the curve at that time.
    pub velocity: SVector<f64, D>,
}

/// The observer that locates events along a run ([module documentation](self)).
#[derive(Debug)]
pub struct Events<'a, E, const D: usize> {
    events: Vec<Event<'a, E, D>>,
    hits: Vec<EventHit<E, D>>,
    /// Each event's value at the end of the last step, on that step's curve.
    previous: Vec<Option<f64>>,
    /// The state at the start of the step being taken.
    start: Option<State<E, D>>,
    stopped: bool,
}

impl<'a, E: Copy, const D: usize> Events<'a, E, D> {
    /// An observer of `events`.
    pub fn new(events: Vec<Event<'a, E, D>>) -> Self {
        let previous = vec![None; events.len()];
        Self {
            events,
            hits: Vec::new(),
            previous,
            start: None,
            stopped: false,
        }
    }

    /// The events.
    pub fn events(&self) -> &[Event<'a, E, D>] {
        &self.events
    }

    /// The crossings located so far, in time order.
    pub fn hits(&self) -> &[EventHit<E, D>] {
        &self.hits
    }

    /// The crossings, taken.
    pub fn into_hits(self) -> Vec<EventHit<E, D>> {
        self.hits
    }

    /// Whether a terminal event stopped the run.
    pub fn stopped(&self) -> bool {
        self.stopped
    }
}

impl<S, C, const D: usize> Observer<S, C, D> for Events<'_, ElementOf<S, D>, D>
where
    S: System<D> + Clone,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: Copy,
{
    type Error = MechanicsError;

    fn before_step(&mut self, integrator: &Integrator<S, C, D>) {
        if !self.events.is_empty() {
            self.start = Some(*integrator.state());
        }
    }

    fn after_step(
        &mut self,
        integrator: &Integrator<S, C, D>,
        _step: StepInfo,
    ) -> Result<ControlFlow<()>, MechanicsError> {
        // No events, no work (a run without a stop condition pays nothing per step).
        if self.events.is_empty() {
            return Ok(ControlFlow::Continue(()));
        }
        let Some(curve) = integrator.last_curve() else {
            return Ok(ControlFlow::Continue(()));
        };
        let (t0, h) = (curve.start(), curve.step());
        let start = self
            .start
            .take()
            .filter(|s| (s.time - t0).abs() <= 1e-9 * h);
        let pieces = curve.nodes().len().max(2);
        let taus: Vec<f64> = (0..=pieces).map(|i| h * i as f64 / pieces as f64).collect();
        let states = taus
            .iter()
            .map(|&tau| curve.at(tau))
            .collect::<Result<Vec<_>, _>>()?;
        let end = integrator.state();
        let mut found: Vec<(EventHit<ElementOf<S, D>, D>, bool)> = Vec::new();
        for (k, event) in self.events.iter_mut().enumerate() {
            let (terminal, wanted) = (event.terminal, event.direction);
            let event_name = &event.name;
            let function = &mut event.function;
            let values: Vec<f64> = taus
                .iter()
                .zip(&states)
                .map(|(&tau, (g, xi))| function(t0 + tau, g, xi))
                .collect();
            if let Some(bad) = values.iter().find(|v| !v.is_finite()) {
                return Err(MechanicsError::NonFinite {
                    what: "an event's function along the step",
                    value: format!("{bad} (event \"{}\", step from t = {t0})", event.name),
                });
            }
            let mut crossings: Vec<(f64, Direction)> = Vec::new();
            // A sign change between the last step's end and this step's start (the two
            // curves' values at their common time) is a crossing at that time.
            if let Some(direction) = self.previous[k]
                .and_then(|before| wanted.crossing(before, values[0]))
                .filter(|_| values[0] != 0.0)
            {
                crossings.push((0.0, direction));
            }
            for i in 0..pieces {
                let (a, b) = (values[i], values[i + 1]);
                if let Some(direction) = wanted.crossing(a, b) {
                    crossings.push((
                        if b == 0.0 {
                            taus[i + 1]
                        } else {
                            located(&mut *function, &curve, (taus[i], a), (taus[i + 1], b))
                                .map_err(|error| MechanicsError::NonFinite {
                                    what: "an event's function along the step",
                                    value: format!(
                                        "(event \"{}\", between t = {} and {}: {error})",
                                        event_name,
                                        t0 + taus[i],
                                        t0 + taus[i + 1]
                                    ),
                                })?
                        },
                        direction,
                    ));
                }
            }
            self.previous[k] = values.last().copied();
            for (tau, direction) in crossings {
                let (time, configuration, velocity) = if tau >= h {
                    // The step's end: the integrator's own state.
                    (end.time, end.configuration, end.velocity)
                } else {
                    let (g, xi) = curve.at(tau)?;
                    let on_curve = (t0 + tau, g, xi);
                    match &start {
                        Some(start) if tau > 0.0 => {
                            refined(integrator, start, &mut *function, &curve, tau)
                                .unwrap_or(on_curve)
                        }
                        _ => on_curve,
                    }
                };
                found.push((
                    EventHit {
                        event: k,
                        time,
                        direction,
                        configuration,
                        velocity,
                    },
                    terminal,
                ));
            }
        }
        found.sort_by(|x, y| x.0.time.total_cmp(&y.0.time));
        let mut stop = false;
        for (hit, terminal) in found {
            self.hits.push(hit);
            if terminal {
                stop = true;
                break;
            }
        }
        self.stopped |= stop;
        Ok(if stop {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        })
    }
}

/// The root of the event's function along `curve` between two samples of opposite sign.
fn located<G, C, const D: usize>(
    function: &mut EventFunction<'_, G::Element<f64>, D>,
    curve: &GalerkinCurve<G, C, D>,
    a: (f64, f64),
    b: (f64, f64),
) -> Result<f64, MechanicsError>
where
    G: StepGroup<D>,
    C: GroupChart<G, D>,
{
    let t0 = curve.start();
    locate(
        |tau| match curve.at(tau) {
            Ok((g, xi)) => function(t0 + tau, &g, &xi),
            Err(_) => f64::NAN,
        },
        a,
        b,
    )
}

/// The crossing near `tau` (seconds into the step) of the function along the method's own
/// steps: a step of length `tau` from the step's `start` ends on the motion to the method's
/// accuracy at a step's end, which the curve between its nodes does not reach (its
/// interior is a lower-order approximation). Newton on the step's length, its slope the
/// curve's: `None` where a step fails or does not settle, the curve's crossing then
/// standing. Returns the time, configuration and velocity there.
#[allow(clippy::type_complexity)]
fn refined<S, C, const D: usize>(
    integrator: &Integrator<S, C, D>,
    start: &State<ElementOf<S, D>, D>,
    function: &mut EventFunction<'_, ElementOf<S, D>, D>,
    curve: &GalerkinCurve<S::Group, C, D>,
    tau: f64,
) -> Option<(f64, ElementOf<S, D>, SVector<f64, D>)>
where
    S: System<D> + Clone,
    C: GroupChart<S::Group, D>,
    ElementOf<S, D>: Copy,
{
    let h = curve.step();
    let t0 = curve.start();
    // The slope along the curve at the crossing, by a centred difference (the curve is a
    // polynomial in the chart; a relative error of the slope only slows Newton a little).
    let delta = 1e-6 * h;
    let along = |f: &mut EventFunction<'_, ElementOf<S, D>, D>, t: f64| {
        curve
            .at(t.clamp(0.0, h))
            .ok()
            .map(|(g, xi)| f(t0 + t.clamp(0.0, h), &g, &xi))
    };
    let up = along(function, tau + delta)?;
    let down = along(function, tau - delta)?;
    let width = (tau + delta).min(h) - (tau - delta).max(0.0);
    let slope = (up - down) / width;
    if !(slope.is_finite() && slope != 0.0) {
        return None;
    }
    let mut tau = tau;
    for _ in 0..4 {
        if !(tau > 0.0 && tau < h) {
            return None;
        }
        let settings = integrator.settings().with_step_unchecked(tau);
        let mut probe = Integrator::with_chart(
            integrator.system().clone(),
            *integrator.chart(),
            settings,
            start.configuration,
            start.velocity,
        )
        .ok()?;
        if start.time != 0.0 {
            probe
                .reset(start.time, start.configuration, start.velocity)
                .ok()?;
        }
        probe.set_input(*integrator.input()).ok()?;
        probe.step().ok()?;
        let s = probe.state();
        let value = function(s.time, &s.configuration, &s.velocity);
        if !value.is_finite() {
            return None;
        }
        let next = tau - value / slope;
        if (next - tau).abs() <= 4.0 * f64::EPSILON * (t0 + tau).abs().max(h) {
            return Some((t0 + next, s.configuration, s.velocity));
        }
        tau = next;
    }
    None
}

/// The root of `f` in `[a, b]` where `f(a)` and `f(b)` differ in sign (`f(b) ≠ 0`): the
/// root of its Chebyshev series nearest the sign change (an odd number of roots lies
/// between; the series resolves `f` to machine precision), or by bisection where `f` is
/// not smooth enough for a series.
fn locate(
    mut f: impl FnMut(f64) -> f64,
    (a, fa): (f64, f64),
    (b, fb): (f64, f64),
) -> Result<f64, MechanicsError> {
    let series = match Chebyshev::fit(&mut f, a, b) {
        Ok(series) => series,
        // A function the series cannot resolve (not smooth where it changes sign: a
        // switch, a jump) still changes sign: bisection finds where, to the last bit.
        Err(lgsvi_spectral::SpectralError::NotResolved { .. }) => {
            return bisect(&mut f, (a, fa), (b, fb));
        }
        Err(error) => return Err(error.into()),
    };
    let roots = series.roots();
    // The first root where the series changes sign the way the samples do; a sign change
    // the series sees at no root (a root at rounding distance of an end) is at that end.
    let rising = fb > fa;
    let width = b - a;
    let crosses = |x: f64| {
        let step = 1e-9 * width;
        let before = series.evaluate((x - step).max(a)).unwrap_or(fa);
        let after = series.evaluate((x + step).min(b)).unwrap_or(fb);
        if rising {
            before <= 0.0 && after >= 0.0
        } else {
            before >= 0.0 && after <= 0.0
        }
    };
    Ok(roots
        .iter()
        .copied()
        .find(|&x| crosses(x))
        .or_else(|| roots.first().copied())
        .unwrap_or(if fa.abs() < fb.abs() { a } else { b }))
}

/// The sign change of `f` between `a` and `b` by bisection, to adjacent doubles.
///
/// # Errors
/// [`MechanicsError::NonFinite`] where `f` is not finite at a midpoint.
fn bisect(
    f: &mut impl FnMut(f64) -> f64,
    (mut a, fa): (f64, f64),
    (mut b, _): (f64, f64),
) -> Result<f64, MechanicsError> {
    let below = fa < 0.0;
    for _ in 0..200 {
        let mid = 0.5 * (a + b);
        if mid <= a || mid >= b {
            break;
        }
        let value = f(mid);
        if !value.is_finite() {
            return Err(MechanicsError::NonFinite {
                what: "an event's function along the step",
                value: format!("{value} at τ = {mid}"),
            });
        }
        if (value < 0.0) == below && value != 0.0 {
            a = mid;
        } else {
            b = mid;
        }
    }
    Ok(b)
}

/// The user guide's page on events (`docs/guide/events.md`), whose Rust example is
/// compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../../docs/guide/events.md")]
pub struct GuidePage;
