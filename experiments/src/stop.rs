//! A run's conditions, `QUANTITY<VALUE` or `QUANTITY>VALUE`, and what a run watches
//! ([`Watch`]):
//! - a **stop** condition (`lgsvi simulate --stop-when`): the run ends after the step in
//!   which the quantity falls below or rises above the value;
//! - a **settling** condition (`--settle-when`): the run goes on to its end, and its
//!   settling time is the time from which the condition holds to the end (a controller's
//!   "pointing error stays below 0.1°", a damped body's "rates stay below 1e-3 rad/s").
//!
//! Every crossing is located on the step's curve and refined by the method's own steps
//! ([`lgsvi_mechanics::events`]).
//!
//! | quantity | meaning | systems |
//! |---|---|---|
//! | `omega_1`, `omega_2`, `omega_3` | a body rate `Ω_i`, rad/s | all |
//! | `omega` | `|Ω|`, rad/s | all |
//! | `angle` | the rotation from the start attitude, `|log(R₀ᵀR)|`, degrees | all |
//! | `error` | the pointing error: the rotation from the target attitude, `|log(R_targetᵀR)|`, degrees (the identity where the run has no target, [`Watch::target`]) | all |
//! | `x_1`, `x_2`, `x_3` | a coordinate of the centre of mass, world frame | bodies in space |
//! | `r` | `|x|` | bodies in space |
//! | `speed` | `|ẋ|` | bodies in space |
//! | `wheel_1` … `wheel_4` | a wheel's rate relative to the body, rad/s | gyrostats |
//!
//! ```
//! use lgsvi_experiments::stop::StopWhen;
//! let stop: StopWhen = "angle>90".parse()?;
//! assert_eq!(stop.to_string(), "angle>90");
//! assert!("omega_4<1".parse::<StopWhen>().is_err());
//! # Ok::<(), String>(())
//! ```

use crate::record::{MotionRecord, WheelRecord};
use crate::ExperimentError;
use lgsvi_mechanics::events::{Direction, Event};
use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::State;
use nalgebra::SVector;
use std::fmt;
use std::str::FromStr;

/// A quantity a stop condition watches (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// `Ω_i`, `i` in 0..3.
    Omega(usize),
    /// `|Ω|`.
    OmegaNorm,
    /// The rotation angle from the start attitude, degrees.
    Angle,
    /// The rotation angle from the target attitude (the pointing error), degrees.
    Error,
    /// `x_i`, `i` in 0..3.
    Position(usize),
    /// `|x|`.
    Distance,
    /// `|ẋ|`.
    Speed,
    /// Wheel `k`'s rate, `k` in 0..4.
    Wheel(usize),
}

impl Quantity {
    /// The quantity's value at a state's SO(3) columns (and translation or wheels), the
    /// run's start attitude `r0` and target attitude given; `None` where the system has no
    /// such quantity.
    pub fn value(
        &self,
        rotation: &State,
        motion: Option<&MotionRecord>,
        wheels: Option<&WheelRecord>,
        r0: &SO3,
        target: &SO3,
    ) -> Option<f64> {
        let degrees_from = |reference: &SO3| {
            let relative = reference.matrix().transpose() * rotation.configuration.matrix();
            SO3::from_matrix_unchecked(relative)
                .log()
                .norm()
                .to_degrees()
        };
        Some(match *self {
            Quantity::Omega(i) => rotation.velocity[i],
            Quantity::OmegaNorm => rotation.velocity.norm(),
            Quantity::Angle => degrees_from(r0),
            Quantity::Error => degrees_from(target),
            Quantity::Position(i) => motion?.position[i],
            Quantity::Distance => motion?.position.norm(),
            Quantity::Speed => motion?.velocity.norm(),
            Quantity::Wheel(k) => *wheels?.speeds.get(k)?,
        })
    }

    /// What the quantity needs, for an error where the system lacks it.
    pub fn applies_to(&self) -> &'static str {
        match self {
            Quantity::Position(_) | Quantity::Distance | Quantity::Speed => {
                "a body in space (free-body, orbiting-body)"
            }
            Quantity::Wheel(_) => "a gyrostat with that many wheels",
            _ => "every system",
        }
    }
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Quantity::Omega(i) => write!(f, "omega_{}", i + 1),
            Quantity::OmegaNorm => write!(f, "omega"),
            Quantity::Angle => write!(f, "angle"),
            Quantity::Error => write!(f, "error"),
            Quantity::Position(i) => write!(f, "x_{}", i + 1),
            Quantity::Distance => write!(f, "r"),
            Quantity::Speed => write!(f, "speed"),
            Quantity::Wheel(k) => write!(f, "wheel_{}", k + 1),
        }
    }
}

impl FromStr for Quantity {
    type Err = String;

    fn from_str(name: &str) -> Result<Self, String> {
        let indexed = |prefix: &str, count: usize| {
            name.strip_prefix(prefix)
                .and_then(|i| i.parse::<usize>().ok())
                .filter(|i| (1..=count).contains(i))
                .map(|i| i - 1)
        };
        Ok(match name {
            "omega" => Quantity::OmegaNorm,
            "angle" => Quantity::Angle,
            "error" => Quantity::Error,
            "r" => Quantity::Distance,
            "speed" => Quantity::Speed,
            _ => {
                if let Some(i) = indexed("omega_", 3) {
                    Quantity::Omega(i)
                } else if let Some(i) = indexed("x_", 3) {
                    Quantity::Position(i)
                } else if let Some(k) = indexed("wheel_", 4) {
                    Quantity::Wheel(k)
                } else {
                    return Err(format!(
                        "unknown quantity {name:?}: one of omega_1, omega_2, omega_3, omega, \
                         angle (degrees from the start attitude), error (degrees from the \
                         target attitude), x_1, x_2, x_3, r, speed, wheel_1 … wheel_4"
                    ));
                }
            }
        })
    }
}

/// A stop condition: the run ends when `quantity` falls below (`<`) or rises above (`>`)
/// `threshold` (module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StopWhen {
    /// What is watched.
    pub quantity: Quantity,
    /// `true` for `<` (a falling crossing), `false` for `>` (a rising one).
    pub below: bool,
    /// The value.
    pub threshold: f64,
}

impl StopWhen {
    /// Whether `value` of the quantity meets the condition (strictly below or above the
    /// threshold).
    pub fn holds(&self, value: f64) -> bool {
        if self.below {
            value < self.threshold
        } else {
            value > self.threshold
        }
    }

    /// The recorded (not terminal) event of every crossing of the threshold, either way,
    /// on a run from the attitude `r0` toward `target` (a settling condition's,
    /// [`Watch::settle`]); as [`StopWhen::event`] otherwise.
    pub fn crossings<'a, E: Copy + 'a, const D: usize>(
        self,
        r0: SO3,
        target: SO3,
        columns: impl Fn(&State<E, D>) -> (State, Option<MotionRecord>, Option<WheelRecord>) + 'a,
    ) -> Event<'a, E, D> {
        self.watched(r0, target, columns)
            .direction(Direction::Either)
    }

    /// The terminal event that watches this condition on a run from the attitude `r0`
    /// (toward `target`, which `error` is measured from):
    /// `quantity − threshold` of the state on the step's curve, its SO(3) columns and the
    /// translation or wheels beside them given by `columns` (the quantities read the
    /// configuration and the velocity only, so the state handed to `columns` carries a
    /// zero momentum rather than one computed at every evaluation).
    pub fn event<'a, E: Copy + 'a, const D: usize>(
        self,
        r0: SO3,
        target: SO3,
        columns: impl Fn(&State<E, D>) -> (State, Option<MotionRecord>, Option<WheelRecord>) + 'a,
    ) -> Event<'a, E, D> {
        self.watched(r0, target, columns).terminal()
    }

    /// `quantity − threshold` as an event in the condition's direction, recorded.
    fn watched<'a, E: Copy + 'a, const D: usize>(
        self,
        r0: SO3,
        target: SO3,
        columns: impl Fn(&State<E, D>) -> (State, Option<MotionRecord>, Option<WheelRecord>) + 'a,
    ) -> Event<'a, E, D> {
        Event::new(self.to_string(), move |t, g: &E, xi: &SVector<f64, D>| {
            let (rotation, motion, wheels) = columns(&State {
                time: t,
                configuration: *g,
                momentum: SVector::zeros(),
                velocity: *xi,
            });
            self.quantity
                .value(&rotation, motion.as_ref(), wheels.as_ref(), &r0, &target)
                .map_or(f64::NAN, |v| v - self.threshold)
        })
        .direction(self.direction())
    }

    /// The crossing's direction of `quantity − threshold`.
    pub fn direction(&self) -> Direction {
        if self.below {
            Direction::Falling
        } else {
            Direction::Rising
        }
    }
}

impl fmt::Display for StopWhen {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let sign = if self.below { '<' } else { '>' };
        // Integers as typed (`angle>90`), others in their shortest exact form (`1e300`).
        let t = self.threshold;
        if t.fract() == 0.0 && t.abs() < 1e15 {
            write!(f, "{}{sign}{t:.0}", self.quantity)
        } else {
            write!(f, "{}{sign}{t:?}", self.quantity)
        }
    }
}

impl FromStr for StopWhen {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        let text = text.trim();
        let (at, below) = match (text.find('<'), text.find('>')) {
            (Some(i), None) => (i, true),
            (None, Some(i)) => (i, false),
            _ => {
                return Err(format!(
                    "{text:?} is not QUANTITY<VALUE or QUANTITY>VALUE (e.g. omega_3<0.1: stop \
                     when Ω₃ falls below 0.1 rad/s; angle>90: when the body has turned 90°)"
                ))
            }
        };
        let quantity: Quantity = text[..at].trim().parse()?;
        let value = text[at + 1..].trim();
        let threshold: f64 = value
            .parse()
            .map_err(|_| format!("{value:?} is not a number (in {text:?})"))?;
        if !threshold.is_finite() {
            return Err(format!("the value {threshold} is not finite (in {text:?})"));
        }
        Ok(Self {
            quantity,
            below,
            threshold,
        })
    }
}

/// What a run watches beside its integration: where it stops and where it settles.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Watch {
    /// The run ends after the step in which this is met (`--stop-when`).
    pub stop: Option<StopWhen>,
    /// The run's settling time is the time from which this holds to the run's end
    /// (`--settle-when`): the last crossing into it, or the start where it holds
    /// throughout; none where it does not hold at the end.
    pub settle: Option<StopWhen>,
    /// The target attitude `error` is measured from (a controller's,
    /// [`lgsvi_mechanics::forces::AttitudeSpring`]); `None` for the identity.
    pub target: Option<SO3>,
}

impl Watch {
    /// Nothing watched: the run goes to its end.
    pub const NOTHING: Watch = Watch {
        stop: None,
        settle: None,
        target: None,
    };

    /// A watch of the stop condition `stop` alone.
    pub fn stop(stop: Option<StopWhen>) -> Self {
        Self {
            stop,
            settle: None,
            target: None,
        }
    }

    /// Refuses a condition on a quantity the system lacks (a position for a body on
    /// SO(3), a wheel beyond the gyrostat's count), judged at the start's SO(3) columns and
    /// the translation or wheels beside them: what [`crate::record::record_until`] checks
    /// before it runs, for a caller to check once before many runs.
    ///
    /// # Errors
    /// [`ExperimentError::Stop`] naming the condition and the systems it applies to.
    pub fn check(
        &self,
        start: &State,
        motion: Option<&MotionRecord>,
        wheels: Option<&WheelRecord>,
    ) -> Result<(), ExperimentError> {
        for (condition, _) in self.conditions() {
            if condition
                .quantity
                .value(start, motion, wheels, &start.configuration, &self.target())
                .is_none()
            {
                return Err(ExperimentError::Stop {
                    condition: condition.to_string(),
                    reason: format!(
                        "{} applies to {}",
                        condition.quantity,
                        condition.quantity.applies_to()
                    ),
                });
            }
        }
        Ok(())
    }

    /// Whether `condition` (as a refusal names it) is the settling condition and not the
    /// stop one: which of the two a caller's error should name.
    pub fn names_settle(&self, condition: &str) -> bool {
        let given = |c: Option<StopWhen>| c.is_some_and(|c| c.to_string() == condition);
        given(self.settle) && !given(self.stop)
    }

    /// The attitude `error` is measured from: the target, or the identity.
    pub fn target(&self) -> SO3 {
        self.target.unwrap_or_else(SO3::identity)
    }

    /// The conditions watched, each with whether it is the settling one.
    pub fn conditions(&self) -> impl Iterator<Item = (StopWhen, bool)> {
        self.stop
            .map(|c| (c, false))
            .into_iter()
            .chain(self.settle.map(|c| (c, true)))
    }
}
