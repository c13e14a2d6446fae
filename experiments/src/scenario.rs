//! A built-in system and its start from plain parameters: the systems `lgsvi simulate`
//! names (the free rigid body, the heavy top, the free body in space, the body orbiting a
//! point mass, the gyrostat), built, checked and run as one type, whatever their group.
//!
//! ```
//! use lgsvi_experiments::record::Check;
//! use lgsvi_experiments::scenario::{Model, Orbit, Scenario};
//! use lgsvi_experiments::stop::Watch;
//! use lgsvi_mechanics::lie::SO3;
//! use lgsvi_mechanics::{Inertia, StepSettings};
//! use nalgebra::Vector3;
//!
//! # fn main() -> Result<(), lgsvi_experiments::ExperimentError> {
//! let inertia = Inertia::from_principal_moments([0.3, 0.2, 0.4])?;
//! let orbit = Model::Orbiting(Orbit::default()); // μ = m = 1 from (3, 0, 0)
//! let scenario = Scenario::new(orbit, inertia, SO3::identity(), Vector3::new(0.2, -0.3, 0.5))?;
//! let settings = StepSettings::new(1.0, 8)?;
//! let run = scenario.record(settings, Check::None, 10.0, 1, &Watch::NOTHING, &mut |_| {})?;
//! assert_eq!(run.steps, 10);
//! # Ok(())
//! # }
//! ```

use crate::control::SampledLaw;
use crate::record::{record_checked, record_exact, Check, Recording};
use crate::stop::Watch;
use crate::tolerance::{local_errors, tolerance_runs, LocalError, ToleranceStudy};
use crate::{ExperimentError, Subject};
use lgsvi_mechanics::built_in::{BuiltInSe3, BuiltInSo3};
use lgsvi_mechanics::exact::{FreeRigidBodyExact, Regime};
use lgsvi_mechanics::forces::{AngularDamping, AttitudeSpring, BodyTorque};
use lgsvi_mechanics::group::{GroupChart, StepGroup};
use lgsvi_mechanics::gyrostat::{AnyGyrostat, BodyAndWheels, BodyWheels, Gyrostat};
use lgsvi_mechanics::lie::{ChartKind, SE3, SO3};
use lgsvi_mechanics::{
    Forced, FreeBody, HeavyTop, Inertia, Integrator, MechanicsError, OrbitingBody, RigidBody,
    StepSettings, System,
};
use nalgebra::{SVector, Vector3};

/// The torque, damping and attitude spring every built-in system but the gyrostat takes:
/// zero for all three, and then the steps are the unforced system's, bit for bit. The
/// damping `−cΩ` and the spring `−kθ` toward a target together are the PD attitude law
/// ([`AttitudeSpring`]); [`drive`] builds one.
pub type Drive = (BodyTorque, (AngularDamping, AttitudeSpring));

/// The [`Drive`] of a constant body torque, an angular damping and an attitude spring.
pub fn drive(torque: Vector3<f64>, damping: f64, spring: AttitudeSpring) -> Drive {
    (BodyTorque(torque), (AngularDamping(damping), spring))
}

/// No drive: the unforced system.
pub fn no_drive() -> Drive {
    drive(Vector3::zeros(), 0.0, AttitudeSpring::none())
}

/// A built-in SO(3) system under a torque, damping and attitude spring.
pub type Driven = Forced<BuiltInSo3, Drive>;

/// A built-in SE(3) system under a torque, damping and attitude spring.
pub type DrivenMotion = Forced<BuiltInSe3, Drive>;

/// The heavy top's parameters: mass `m`, gravity `g`, centre of mass `ρ` in the body
/// frame and the world direction gravity pulls in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Top {
    /// Mass `m ≥ 0`.
    pub mass: f64,
    /// Gravitational acceleration `g`.
    pub gravity: f64,
    /// Centre of mass `ρ`, body frame.
    pub com: Vector3<f64>,
    /// The direction gravity pulls in, world frame (normalised by [`HeavyTop::new`]).
    pub direction: Vector3<f64>,
}

/// A body in space: its mass and its centre of mass's start, world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Space {
    /// Mass `m > 0`.
    pub mass: f64,
    /// The centre of mass `x(0)`.
    pub position: Vector3<f64>,
    /// Its velocity `ẋ(0)`.
    pub velocity: Vector3<f64>,
}

impl Default for Space {
    /// Unit mass at rest at the origin.
    fn default() -> Self {
        Self {
            mass: 1.0,
            position: Vector3::zeros(),
            velocity: Vector3::zeros(),
        }
    }
}

/// A body orbiting a point mass of gravitational parameter `μ = GM` at the origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    /// The body in space (mass, start).
    pub body: Space,
    /// `μ = GM ≥ 0`.
    pub mu: f64,
}

impl Default for Orbit {
    /// `μ = m = 1` from `x = (3, 0, 0)` at `ẋ = (0, 0.55, 0.05)`: a slightly inclined,
    /// eccentric orbit (the circular speed at r = 3 is 0.577).
    fn default() -> Self {
        Self {
            body: Space {
                mass: 1.0,
                position: Vector3::new(3.0, 0.0, 0.0),
                velocity: Vector3::new(0.0, 0.55, 0.05),
            },
            mu: 1.0,
        }
    }
}

/// A gyrostat's 1 to 4 wheels: axes (body frame), axial inertias, initial spin rates
/// relative to the body and constant motor torques, one entry per wheel.
#[derive(Debug, Clone, PartialEq)]
pub struct Wheels {
    /// The axes (normalised by [`Gyrostat::new`]).
    pub axes: Vec<Vector3<f64>>,
    /// Each wheel's axial inertia `I_i > 0`.
    pub inertia: Vec<f64>,
    /// Each wheel's initial spin rate.
    pub speeds0: Vec<f64>,
    /// Each wheel's motor torque (the body takes the reaction).
    pub torque: Vec<f64>,
}

impl Wheels {
    /// Wheels on `axes`, each of axial inertia 0.05, at rest, without torque.
    pub fn on(axes: Vec<Vector3<f64>>) -> Self {
        let k = axes.len();
        Self {
            axes,
            inertia: vec![0.05; k],
            speeds0: vec![0.0; k],
            torque: vec![0.0; k],
        }
    }
}

impl Default for Wheels {
    /// Three wheels on the body axes.
    fn default() -> Self {
        Self::on(vec![Vector3::x(), Vector3::y(), Vector3::z()])
    }
}

/// Which built-in system, with its own parameters (the inertia, attitude and angular
/// velocity are every system's: [`Scenario::new`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Model {
    /// The free rigid body on SO(3).
    RigidBody,
    /// The heavy top on SO(3).
    HeavyTop(Top),
    /// The free body in space on SE(3).
    FreeInSpace(Space),
    /// The body orbiting a point mass on SE(3) (MacCullagh's potential).
    Orbiting(Orbit),
    /// A spacecraft with reaction wheels on SO(3) × ℝᴷ (inertia with the wheels locked).
    Gyrostat(Wheels),
}

/// An SE(3) run: the system under its torque and damping, and its start (body
/// velocities `(Ω, v)` with `ẋ = R v`).
#[derive(Debug, Clone, Copy)]
pub struct Motion {
    /// The system.
    pub system: DrivenMotion,
    /// `(R₀, x₀)`.
    pub start: SE3,
    /// `(Ω₀, v₀)`.
    pub velocity0: SVector<f64, 6>,
}

impl Motion {
    /// An integrator from the start, in the settings' chart.
    ///
    /// # Errors
    /// [`Integrator::new`]'s.
    pub fn integrator(
        &self,
        settings: StepSettings,
    ) -> Result<Integrator<DrivenMotion, ChartKind, 6>, MechanicsError> {
        Integrator::new(self.system, settings, self.start, self.velocity0)
    }
}

/// A gyrostat run: the spacecraft, its wheels' start and their motor torques.
#[derive(Debug, Clone)]
pub struct WheelRun {
    /// The spacecraft, as many wheels as it has.
    pub system: AnyGyrostat,
    /// The wheels' initial spin rates.
    pub speeds0: Vec<f64>,
    /// Their motor torques.
    pub torque: Vec<f64>,
}

impl WheelRun {
    /// An integrator for `craft` (this run's gyrostat with `K` wheels, `D = 3 + K`) from
    /// `(R₀, φ = 0)` with velocity `(Ω₀, φ̇₀)`, the motor torques set as its input
    /// `(0, τ_m)`.
    ///
    /// # Errors
    /// [`Integrator::new`]'s and [`Integrator::set_input`]'s.
    pub fn integrator<const K: usize, const D: usize>(
        &self,
        craft: Gyrostat<K>,
        settings: StepSettings,
        attitude: SO3,
        omega: Vector3<f64>,
    ) -> Result<Integrator<Gyrostat<K>, ChartKind, D>, MechanicsError>
    where
        Gyrostat<K>: System<D, Group = BodyAndWheels<K>>,
        BodyAndWheels<K>: StepGroup<D, Element<f64> = BodyWheels<f64, K>>,
        ChartKind: GroupChart<BodyAndWheels<K>, D>,
    {
        let mut velocity = SVector::<f64, D>::zeros();
        let mut input = SVector::<f64, D>::zeros();
        velocity.fixed_rows_mut::<3>(0).copy_from(&omega);
        for i in 0..K {
            velocity[3 + i] = self.speeds0[i];
            input[3 + i] = self.torque[i];
        }
        let start = BodyWheels {
            attitude,
            wheels: SVector::<f64, K>::zeros(),
        };
        let mut integrator = Integrator::new(craft, settings, start, velocity)?;
        integrator.set_input(input)?;
        Ok(integrator)
    }
}

/// `$body` once per size of an [`AnyGyrostat`], with `$craft` the gyrostat and `$k`, `$d`
/// constants bound to its number of wheels and its dimension `3 + K`:
/// `each_gyrostat!(any, (craft, K, D) => run::<K, D>(craft))`.
#[macro_export]
macro_rules! each_gyrostat {
    ($any:expr, ($craft:ident, $k:tt, $d:tt) => $body:expr) => {{
        use $crate::__gyrostat::AnyGyrostat as __Any;
        match $any {
            __Any::One($craft) => $crate::__each_gyrostat_arm!(1, 4, $k, $d, $body),
            __Any::Two($craft) => $crate::__each_gyrostat_arm!(2, 5, $k, $d, $body),
            __Any::Three($craft) => $crate::__each_gyrostat_arm!(3, 6, $k, $d, $body),
            __Any::Four($craft) => $crate::__each_gyrostat_arm!(4, 7, $k, $d, $body),
        }
    }};
}

/// One arm of [`each_gyrostat`]: `$k`, `$d` bound as constants.
#[macro_export]
#[doc(hidden)]
macro_rules! __each_gyrostat_arm {
    ($kv:literal, $dv:literal, $k:ident, $d:ident, $body:expr) => {{
        #[allow(non_upper_case_globals)]
        const $k: usize = $kv;
        #[allow(non_upper_case_globals)]
        const $d: usize = $dv;
        $body
    }};
}

/// `$body` with `$make` the way to build the integrator of whichever system `$scenario`
/// (a `&Scenario`) holds, `StepSettings → Result<Integrator<…>, MechanicsError>`, and
/// `$d` a constant bound to its dimension: a gyrostat (through [`each_gyrostat`], `$k`
/// bound to its number of wheels), a body in space (6) or on SO(3) (3). The one dispatch
/// of [`Scenario`]'s studies.
macro_rules! with_system {
    ($scenario:expr, ($make:ident, $k:ident, $d:ident) => $body:expr) => {{
        let scenario: &Scenario = $scenario;
        if let Some(wheels) = &scenario.wheels {
            let (attitude, omega) = (scenario.attitude0, scenario.omega0);
            crate::each_gyrostat!(wheels.system, (craft, $k, $d) => {
                let $make =
                    |s: StepSettings| wheels.integrator::<$k, $d>(craft, s, attitude, omega);
                $body
            })
        } else if let Some(motion) = &scenario.motion {
            #[allow(non_upper_case_globals)]
            const $d: usize = 6;
            let $make = |s: StepSettings| motion.integrator(s);
            $body
        } else {
            #[allow(non_upper_case_globals)]
            const $d: usize = 3;
            let $make = |s: StepSettings| Subject::integrator(scenario, s);
            $body
        }
    }};
}

/// A built-in system from its start, ready to run: on SO(3) (`motion` and `wheels` both
/// `None`), on SE(3) (`motion`) or a gyrostat (`wheels`).
#[derive(Debug, Clone)]
pub struct Scenario {
    /// The SO(3) system (for an SE(3) or gyrostat run, its rotational part as a free body:
    /// unused).
    pub system: Driven,
    /// The SE(3) run.
    pub motion: Option<Motion>,
    /// The gyrostat run.
    pub wheels: Option<WheelRun>,
    /// The inertia (with the wheels locked, for a gyrostat).
    pub inertia: Inertia,
    /// `R(0)`.
    pub attitude0: SO3,
    /// `Ω(0)`.
    pub omega0: Vector3<f64>,
    /// The settings of [`Subject::settings`] (the studies' chart, matching and Newton
    /// Jacobian): ten nodes at `h = 0.5` unless [`Scenario::with_settings`] says otherwise.
    pub settings: StepSettings,
    /// A sampled controller in the loop ([`Scenario::with_control`]), beside the drive:
    /// [`Scenario::record`] runs it (and [`Subject::exact`] knows no closed form with it);
    /// the studies ([`Scenario::local_errors`], [`Scenario::tolerance_runs`], the
    /// [`Subject`] studies) run steps of many lengths and take the drive alone.
    pub control: Option<SampledLaw>,
}

impl Scenario {
    /// `model` of `inertia` from `(attitude0, omega0)`, without torque or damping.
    ///
    /// # Errors
    /// A system's constructor's refusal: [`ExperimentError::Parameter`] naming the
    /// parameters (the free body in space's and the orbiting body's mass and `μ`, the
    /// wheels' axes, inertias and their counts), the heavy top's as
    /// [`ExperimentError::Mechanics`] (its message names them); an orbiting body at (or next
    /// to) the attracting centre or too far out for double precision
    /// ([`ExperimentError::InvalidStart`]).
    pub fn new(
        model: Model,
        inertia: Inertia,
        attitude0: SO3,
        omega0: Vector3<f64>,
    ) -> Result<Self, ExperimentError> {
        Self::driven(model, inertia, attitude0, omega0, no_drive())
    }

    /// As [`Scenario::new`], under a constant body torque, an angular damping and an
    /// attitude spring (the gyrostat's wheels take their motor torques instead: a gyrostat
    /// under a non-zero drive is refused).
    ///
    /// # Errors
    /// As [`Scenario::new`].
    pub fn driven(
        model: Model,
        inertia: Inertia,
        attitude0: SO3,
        omega0: Vector3<f64>,
        drive: Drive,
    ) -> Result<Self, ExperimentError> {
        let parameter = |parameter| move |source| ExperimentError::Parameter { parameter, source };
        let mut scenario = Self {
            system: Forced::new(BuiltInSo3::Free(RigidBody::new(inertia)), drive),
            motion: None,
            wheels: None,
            inertia,
            attitude0,
            omega0,
            settings: StepSettings::new(0.5, 10)?,
            control: None,
        };
        let (inner, body) = match model {
            Model::RigidBody => return Ok(scenario),
            Model::HeavyTop(top) => {
                let Top {
                    mass,
                    gravity,
                    com,
                    direction,
                } = top;
                let top = HeavyTop::new(inertia, mass, gravity, com, direction)?;
                scenario.system = Forced::new(BuiltInSo3::Top(top), drive);
                return Ok(scenario);
            }
            Model::Gyrostat(wheels) => {
                let k = wheels.axes.len();
                let (speeds, torques) = (wheels.speeds0.len(), wheels.torque.len());
                if speeds != k || torques != k {
                    let source = MechanicsError::InvalidSetting {
                        name: "wheel speeds and torques",
                        value: format!("{speeds} and {torques} for {k} wheels"),
                        reason: "one start speed and one motor torque per wheel",
                    };
                    return Err(parameter("speeds0/torque")(source));
                }
                let (BodyTorque(torque), (AngularDamping(damping), spring)) = drive;
                if torque != Vector3::zeros() || damping != 0.0 || spring.stiffness() != 0.0 {
                    let source = MechanicsError::InvalidSetting {
                        name: "body torque, damping and attitude spring",
                        value: format!(
                            "{:?}, {damping}, {}",
                            torque.as_slice(),
                            spring.stiffness()
                        ),
                        reason: "a gyrostat takes its wheels' motor torques (Wheels::torque), \
                                 not a body torque, damping or attitude spring",
                    };
                    return Err(parameter("drive")(source));
                }
                let j = inertia.matrix();
                let system = AnyGyrostat::new(j, &wheels.axes, &wheels.inertia)
                    .map_err(parameter("axes/inertia"))?;
                scenario.wheels = Some(WheelRun {
                    system,
                    speeds0: wheels.speeds0,
                    torque: wheels.torque,
                });
                return Ok(scenario);
            }
            Model::FreeInSpace(body) => {
                let free = FreeBody::new(inertia, body.mass).map_err(parameter("mass"))?;
                (BuiltInSe3::Free(free), body)
            }
            Model::Orbiting(Orbit { body, mu }) => {
                // Each physical parameter on its own first, naming itself (an infinite μ
                // is a bad μ, not a start at the centre); then the start against them.
                let orbiting = OrbitingBody::new(inertia, body.mass, mu).map_err(|source| {
                    let named = match &source {
                        MechanicsError::NonFinite { what, .. } => *what,
                        MechanicsError::InvalidSetting { name, .. } => *name,
                        _ => "mass/mu",
                    };
                    parameter(if named == "mu" { "mu" } else { "mass" })(source)
                })?;
                checked_orbit_radius(&body, &orbiting)?;
                (BuiltInSe3::Orbit(orbiting), body)
            }
        };
        let v = attitude0.matrix().transpose() * body.velocity;
        let w = omega0;
        scenario.motion = Some(Motion {
            system: Forced::new(inner, drive),
            start: SE3::new(attitude0, body.position),
            velocity0: SVector::<f64, 6>::new(w.x, w.y, w.z, v.x, v.y, v.z),
        });
        Ok(scenario)
    }

    /// The scenario with other base settings ([`Subject::settings`]).
    pub fn with_settings(mut self, settings: StepSettings) -> Self {
        self.settings = settings;
        self
    }

    /// The scenario with a sampled attitude controller in the loop: its torque, set at
    /// each sampling instant, is the body's control input beside the drive
    /// ([`crate::control`]).
    ///
    /// # Errors
    /// [`ExperimentError::Parameter`] for a gyrostat (it turns by its wheels' motor
    /// torques).
    pub fn with_control(mut self, control: SampledLaw) -> Result<Self, ExperimentError> {
        if self.wheels.is_some() {
            return Err(crate::control::on_a_gyrostat());
        }
        self.control = Some(control);
        Ok(self)
    }

    /// The initial motion's fastest rate, rad per unit time: the system's own
    /// ([`System::motion_rate`]: the spin, and the heavy top's pendulum
    /// frequency, the orbiting body's gravity-gradient libration or the wheels' fastest
    /// spin). A tolerance-driven run's step turns a fixed angle at it.
    ///
    /// # Errors
    /// The start's refusal by [`Integrator::new`] (not finite, off the group).
    pub fn rate(&self) -> Result<f64, ExperimentError> {
        with_system!(self, (make, _K, _D) => {
            let it = make(self.settings)?;
            let s = it.state();
            Ok(it.system().motion_rate(s.time, &s.configuration, &s.velocity))
        })
    }

    /// Runs to `t_end` with `settings`, checked as `check` says, recording every
    /// `every`-th state ([`record_checked`]); ended early where `watch`'s stop condition
    /// is met, its settling time found ([`crate::record::record_until`]).
    ///
    /// # Errors
    /// [`record_checked`]'s.
    pub fn record(
        &self,
        settings: StepSettings,
        check: Check,
        t_end: f64,
        every: usize,
        watch: &Watch,
        progress: &mut dyn FnMut(usize),
    ) -> Result<Recording, ExperimentError> {
        with_system!(self, (make, K, D) => {
            let control = self.control.as_ref();
            record_checked::<_, ChartKind, D>(
                make, settings, check, t_end, every, watch, control, progress,
            )
        })
    }

    /// Refuses a condition of `watch` on a quantity this system lacks ([`Watch::check`] at
    /// the start), once, before many runs.
    ///
    /// # Errors
    /// [`ExperimentError::Stop`]; the integrator's refusal of the start.
    pub fn check_watch(&self, watch: &Watch) -> Result<(), ExperimentError> {
        with_system!(self, (make, _K, _D) => {
            let it = make(self.settings)?;
            let (start, motion, wheels) = crate::record::Columns::columns(it.state());
            watch.check(&start, motion.as_ref(), wheels.as_ref())
        })
    }

    /// The exact solution of a free rigid body (Jacobi elliptic functions) recorded as
    /// [`Scenario::record`] would record a run with `settings` to `t_end` ([`record_exact`]),
    /// and the motion's regime; `None` for a system without a closed form.
    ///
    /// # Errors
    /// [`FreeRigidBodyExact::new`]'s, [`Integrator::steps_until`]'s, [`record_exact`]'s.
    pub fn record_exact(
        &self,
        settings: StepSettings,
        t_end: f64,
        every: usize,
    ) -> Option<Result<(Recording, Regime), ExperimentError>> {
        let exact = Subject::exact(self)?;
        Some((|| {
            let body = exact?;
            let steps = Subject::integrator(self, settings)?.steps_until(t_end)?;
            let recording = record_exact(&body, &self.system, settings.h(), steps, every)?;
            Ok((recording, body.regime()))
        })())
    }

    /// The local errors of every step of runs with `steps × nodes` to `t_end`, in the
    /// chart of `chart` ([`local_errors`]); every system (SO(3), SE(3), a gyrostat).
    ///
    /// # Errors
    /// [`local_errors`]'s.
    pub fn local_errors(
        &self,
        chart: ChartKind,
        steps: &[f64],
        nodes: &[usize],
        t_end: f64,
        tick: &mut dyn FnMut(),
    ) -> Result<Vec<LocalError>, ExperimentError> {
        with_system!(self, (make, K, D) => {
            let make = |s: StepSettings| make(s.with_chart(chart));
            local_errors::<_, ChartKind, D>(&make, steps, nodes, t_end, tick)
        })
    }

    /// Tolerance-driven runs with `settings` (tolerance and settings) against a
    /// reference and the grid `steps × nodes` of fixed runs, in `chart`
    /// ([`tolerance_runs`]); every system (SO(3), SE(3), a gyrostat).
    ///
    /// # Errors
    /// [`tolerance_runs`]'s.
    pub fn tolerance_runs(
        &self,
        chart: ChartKind,
        settings: &[(f64, StepSettings)],
        steps: &[f64],
        nodes: &[usize],
        t_end: f64,
        tick: &mut dyn FnMut(),
    ) -> Result<ToleranceStudy, ExperimentError> {
        with_system!(self, (make, K, D) => {
            let make = |s: StepSettings| make(s.with_chart(chart));
            tolerance_runs::<_, ChartKind, D>(&make, chart, settings, steps, nodes, t_end, tick)
        })
    }
}

/// `|x|` of the orbiting body's start, refused where the potential `−μm/r` and its
/// gravity gradient are singular or overflow, or where the attracting point lies inside the
/// body's mass (within twice its radius of gyration).
fn checked_orbit_radius(body: &Space, orbiting: &OrbitingBody) -> Result<f64, ExperimentError> {
    orbiting
        .check_position(&body.position)
        .map_err(|error| match error {
            MechanicsError::InvalidStart { value, reason } => {
                ExperimentError::InvalidStart { value, reason }
            }
            other => ExperimentError::Mechanics(other),
        })
}

/// The SO(3) scenario as the studies of this crate run it (for an SE(3) or gyrostat
/// scenario, its rotational part as a free body: use [`Scenario::record`],
/// [`Scenario::local_errors`] and [`Scenario::tolerance_runs`] for those).
impl Subject for Scenario {
    type System = Driven;

    fn system(&self) -> &Driven {
        &self.system
    }

    fn settings(&self) -> StepSettings {
        self.settings
    }

    fn integrator(&self, settings: StepSettings) -> Result<Integrator<Driven>, MechanicsError> {
        Integrator::new(self.system, settings, self.attitude0, self.omega0)
    }

    /// The exact solution, for a free, unforced body on SO(3) (not for the rotational part
    /// of an SE(3) or gyrostat scenario: that is not their motion).
    fn exact(&self) -> Option<Result<FreeRigidBodyExact, MechanicsError>> {
        // A sampled controller's torques are not in the system: the body is not free.
        let rotation_only = self.motion.is_none() && self.wheels.is_none();
        (rotation_only && self.is_free() && self.control.is_none())
            .then(|| FreeRigidBodyExact::new(self.inertia, self.attitude0, self.omega0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inertia() -> Inertia {
        Inertia::from_principal_moments([0.3, 0.2, 0.4]).unwrap()
    }

    /// `model` of [`inertia`] from the identity, at rest.
    fn at_rest(model: Model) -> Result<Scenario, ExperimentError> {
        Scenario::new(model, inertia(), SO3::identity(), Vector3::zeros())
    }

    /// The scenario's orbiting body is the one built by hand: start `(R₀, x₀)`, body
    /// velocity `v = R₀ᵀẋ₀`, the same steps to the last bit.
    #[test]
    fn an_orbit_runs_as_the_integrator_built_by_hand() {
        let attitude = SO3::exp(&Vector3::new(0.3, -0.2, 0.5));
        let omega = Vector3::new(0.2, -0.3, 0.5);
        let orbit = Orbit::default();
        let scenario = Scenario::new(Model::Orbiting(orbit), inertia(), attitude, omega).unwrap();
        let settings = StepSettings::new(1.0, 8).unwrap();
        let run = scenario
            .record(settings, Check::None, 5.0, 1, &Watch::NOTHING, &mut |_| {})
            .unwrap();
        let body = OrbitingBody::new(inertia(), 1.0, 1.0).unwrap();
        let v = attitude.matrix().transpose() * orbit.body.velocity;
        let xi = SVector::<f64, 6>::new(omega.x, omega.y, omega.z, v.x, v.y, v.z);
        let start = SE3::new(attitude, orbit.body.position);
        let mut by_hand = Integrator::new(body, settings, start, xi).unwrap();
        for _ in 0..5 {
            by_hand.step().unwrap();
        }
        let last = run.motion.as_ref().unwrap().last().unwrap();
        assert_eq!(last.position, by_hand.state().position());
        // The libration joins the spin in the rate: √(3μ/r³) at r = 3.
        assert_eq!(
            scenario.rate().unwrap(),
            omega.norm() + (3.0f64 / 27.0).sqrt()
        );
    }

    /// An orbiting body at the attracting centre, next to it, or too far out for double
    /// precision is refused with the reason; μ = 0 (no attraction) is not.
    #[test]
    fn an_orbit_starting_where_gravity_is_singular_is_refused() {
        for (x, says) in [
            (0.0, "attracting centre"),
            (1e-120, "attracting centre"),
            (1e80, "overflow"),
        ] {
            let mut orbit = Orbit::default();
            orbit.body.position = Vector3::new(x, 0.0, 0.0);
            let error = at_rest(Model::Orbiting(orbit)).unwrap_err();
            assert!(
                matches!(error, ExperimentError::InvalidStart { .. }),
                "{error}"
            );
            assert!(error.to_string().contains(says), "{error}");
            orbit.mu = 0.0;
            let free = at_rest(Model::Orbiting(orbit)).unwrap();
            // No attraction, no libration to follow (not 0/0 at the origin).
            assert_eq!(free.rate().unwrap(), 0.0);
        }
    }

    /// The tolerance module's studies run a gyrostat (three wheels spinning under motor
    /// torques on a tumbling body): the true local error of a step falls geometrically with
    /// the nodes (the method's spectral convergence at a fixed step), every step has a
    /// finite positive estimate, and a tolerance-driven run is as accurate as asked against
    /// the study's reference run.
    #[test]
    fn the_tolerance_studies_run_a_gyrostat() {
        let wheels = Wheels {
            speeds0: vec![0.4, -0.3, 0.2],
            torque: vec![0.002, -0.001, 0.003],
            ..Wheels::default()
        };
        let omega0 = Vector3::new(0.3, -0.2, 0.4);
        let craft =
            Scenario::new(Model::Gyrostat(wheels), inertia(), SO3::identity(), omega0).unwrap();
        let nodes = [3, 4, 5];
        let rows = craft
            .local_errors(ChartKind::Exp, &[0.5], &nodes, 2.0, &mut || {})
            .unwrap();
        assert_eq!(rows.len(), nodes.len() * 4);
        let worst = |n: usize| {
            rows.iter()
                .filter(|r| r.nodes == n)
                .map(|r| r.truth)
                .fold(0.0, f64::max)
        };
        for pair in nodes.windows(2) {
            // h|Ω| ≈ 0.27: the largest local error of the four steps falls about three
            // orders of magnitude a node (measured 2.0e-6, 8.1e-10, 4.5e-13 at n = 3, 4,
            // 5); at least two asked, above the rounding floor of ~1e-15.
            let (coarse, fine) = (worst(pair[0]), worst(pair[1]));
            assert!(fine * 100.0 < coarse, "n = {pair:?}: {coarse:e} → {fine:e}");
        }
        assert!(rows
            .iter()
            .all(|r| r.estimate > 0.0 && r.estimate.is_finite()));
        // 7 = 3 + K: the gyrostat's D, through each_gyrostat!.
        // The command line's policy: a tolerance `tol` over `T` is the rate `tol / T`.
        let (tol, t_end) = (1e-9, 5.0);
        let settings = StepSettings::new(0.5, 6)
            .unwrap()
            .with_tolerance(tol / t_end)
            .unwrap();
        let study = craft
            .tolerance_runs(
                ChartKind::Exp,
                &[(tol, settings)],
                &[0.5],
                &[6, 8],
                t_end,
                &mut || {},
            )
            .unwrap();
        assert_eq!(study.fixed.len(), 2);
        let run = &study.runs[0];
        assert!(run.failure.is_none(), "{:?}", run.failure);
        // An honest run's error at the horizon is within its tolerance (the reference, 24
        // nodes against 28, is good to rounding here).
        assert!(run.error <= tol, "{:e}", run.error);
        assert!(run.estimated_error.is_finite() && run.estimated_error > 0.0);
    }

    /// A gyrostat's parameters' refusals name them.
    #[test]
    fn a_gyrostat_is_refused_where_it_does_not_fit() {
        let craft = at_rest(Model::Gyrostat(Wheels::default())).unwrap();
        let mut wheels = Wheels::default();
        wheels.inertia[1] = -1.0;
        let error = at_rest(Model::Gyrostat(wheels)).unwrap_err();
        assert!(
            matches!(
                error,
                ExperimentError::Parameter {
                    parameter: "axes/inertia",
                    ..
                }
            ),
            "{error}"
        );
        // The message names the parameters and the wheel's value.
        let text = error.to_string();
        assert!(
            text.starts_with("axes/inertia: ") && text.contains("wheel inertia"),
            "{text}"
        );
        // A start speed or a motor torque missing for a wheel, or a body torque the
        // wheels would not see: refused, never a panic or a silent drop.
        let mut wheels = Wheels::default();
        wheels.speeds0.pop();
        let short = at_rest(Model::Gyrostat(wheels));
        assert!(
            matches!(
                short,
                Err(ExperimentError::Parameter {
                    parameter: "speeds0/torque",
                    ..
                })
            ),
            "{short:?}"
        );
        let drive = drive(Vector3::x(), 0.0, AttitudeSpring::none());
        let model = Model::Gyrostat(Wheels::default());
        let driven = Scenario::driven(model, inertia(), SO3::identity(), Vector3::zeros(), drive);
        assert!(
            matches!(
                driven,
                Err(ExperimentError::Parameter {
                    parameter: "drive",
                    ..
                })
            ),
            "{driven:?}"
        );
        // The exact free-body solution is not a gyrostat's (nor an SE(3) body's) motion.
        assert!(craft
            .record_exact(StepSettings::new(0.5, 8).unwrap(), 1.0, 1)
            .is_none());
        let space = Model::FreeInSpace(Space::default());
        let body = Scenario::new(space, inertia(), SO3::identity(), Vector3::x()).unwrap();
        assert!(Subject::exact(&body).is_none());
        let free = Scenario::new(Model::RigidBody, inertia(), SO3::identity(), Vector3::x());
        assert!(Subject::exact(&free.unwrap()).is_some());
    }
}
