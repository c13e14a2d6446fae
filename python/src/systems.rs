//! The built-in systems as Python classes: `System` and its subclasses `RigidBody`,
//! `HeavyTop`, `FreeBody`, `OrbitingBody`, `Gyrostat`. Each holds the parameters as given
//! (so that it pickles back to the same object) and the Rust system they make.

use crate::convert::{matrix3, rotation, rows3, vector, vector3, vectors3};
use crate::errors::{guarded, invalid, mechanics};
use lgsvi_experiments::scenario;
use lgsvi_mechanics as library;
use lgsvi_mechanics::built_in::{BuiltInSe3, BuiltInSo3};
use lgsvi_mechanics::forces::{AttitudeSpring, SpaceForce};
use lgsvi_mechanics::gyrostat::AnyGyrostat;
use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::{Forced, Inertia};
use nalgebra::{Matrix3, Vector3};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

/// The SO(3) systems as the integrator steps them: a built-in body under a constant body
/// torque, an angular damping and an attitude spring (the command line's, `scenario::Drive`).
pub type So3System = scenario::Driven;
/// The SE(3) systems as the integrator steps them: a built-in body under the same drive
/// and a constant space-frame force on its centre of mass.
pub type Se3System = Forced<BuiltInSe3, (scenario::Drive, SpaceForce)>;

/// An inertia as it was given: principal moments, a tensor, or the paper's `J_d`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InertiaInput {
    /// `J = diag(a, b, c)`.
    Moments([f64; 3]),
    /// A full tensor `J` (body frame).
    Tensor(Matrix3<f64>),
    /// The paper's `J_d`, `J = tr(J_d) I − J_d`.
    PaperJd([f64; 3]),
}

impl InertiaInput {
    /// From the `inertia` and `inertia_d` arguments (exactly one of them).
    pub fn from_arguments(
        inertia: Option<&Bound<'_, PyAny>>,
        inertia_d: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        match (inertia, inertia_d) {
            (Some(_), Some(_)) => Err(invalid(
                "give the inertia as inertia= (J) or inertia_d= (the paper's J_d), not both",
            )),
            (None, None) => Err(invalid(
                "the inertia is required: inertia= (three principal moments or a 3×3 tensor) \
                 or inertia_d= (the paper's J_d)",
            )),
            (None, Some(jd)) => {
                let v = vector3(jd, "inertia_d")?;
                Ok(Self::PaperJd([v.x, v.y, v.z]))
            }
            (Some(j), None) => {
                let shape = crate::convert::shape_of(j, "inertia")?;
                match shape.as_slice() {
                    [3] => {
                        let v = vector3(j, "inertia")?;
                        Ok(Self::Moments([v.x, v.y, v.z]))
                    }
                    [3, 3] => Ok(Self::Tensor(matrix3(j, "inertia")?)),
                    other => Err(invalid(format!(
                        "inertia must be three principal moments (shape (3,)) or a tensor \
                         (shape (3, 3)), got shape {other:?}"
                    ))),
                }
            }
        }
    }

    /// The inertia, checked for physics.
    pub fn inertia(&self) -> PyResult<Inertia> {
        match *self {
            Self::Moments(m) => Inertia::from_principal_moments(m),
            Self::Tensor(t) => Inertia::from_tensor(t),
            Self::PaperJd(jd) => Inertia::from_paper_jd(jd),
        }
        .map_err(|e| invalid(format!("inertia: {e}")))
    }

    /// `(inertia, inertia_d)` as constructor arguments.
    fn arguments<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let none = py.None().into_bound(py);
        Ok(match *self {
            Self::Moments(m) => (PyArray1::from_slice(py, &m).into_any(), none),
            Self::Tensor(t) => (matrix_array(py, &t).into_any(), none),
            Self::PaperJd(jd) => (none, PyArray1::from_slice(py, &jd).into_any()),
        })
    }
}

pub fn matrix_array<'py>(py: Python<'py>, m: &Matrix3<f64>) -> Bound<'py, PyArray2<f64>> {
    crate::convert::array2(py, 3, 3, rows3(m).to_vec())
}

/// Forcing as given: a body torque, an angular damping, an attitude spring toward a
/// target (with the damping, the PD attitude law) and (on SE(3)) a space-frame force.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    /// The constant body torque `τ` (N·m).
    pub torque: Vector3<f64>,
    /// The damping `c ≥ 0` of `τ = −c Ω` (N·m·s).
    pub damping: f64,
    /// The torque `−K θ` toward a target attitude.
    pub spring: AttitudeSpring,
    /// The constant space-frame force `f` on the centre of mass (N), SE(3) only.
    pub force: Vector3<f64>,
}

impl Default for Drive {
    fn default() -> Self {
        Self {
            torque: Vector3::zeros(),
            damping: 0.0,
            spring: AttitudeSpring::none(),
            force: Vector3::zeros(),
        }
    }
}

impl Drive {
    fn from_arguments(
        torque: Option<&Bound<'_, PyAny>>,
        damping: f64,
        force: Option<&Bound<'_, PyAny>>,
        attitude_gain: f64,
        target: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let torque = torque.map_or(Ok(Vector3::zeros()), |t| vector3(t, "torque"))?;
        let force = force.map_or(Ok(Vector3::zeros()), |f| vector3(f, "force"))?;
        if !(damping.is_finite() && damping >= 0.0) {
            return Err(invalid(format!(
                "damping must be finite and non-negative (τ = −c Ω), got {damping}"
            )));
        }
        let target = target.map_or(Ok(SO3::identity()), |t| rotation(t, "target"))?;
        let spring = AttitudeSpring::new(target, attitude_gain).map_err(|_| {
            invalid(format!(
                "attitude_gain must be finite and non-negative (τ = −K θ toward the target, \
                 N·m per radian), got {attitude_gain}"
            ))
        })?;
        Ok(Self {
            torque,
            damping,
            spring,
            force,
        })
    }

    /// The target a run's `error` is measured from: the attitude law's, where the system
    /// has a law or a target (`None` otherwise: the identity, and no pointing-error channel
    /// in a Monte Carlo envelope).
    pub fn target(&self) -> Option<SO3> {
        let target = *self.spring.target();
        (self.spring.stiffness() != 0.0 || target != SO3::identity()).then_some(target)
    }
}

impl Spec {
    /// The drive of a system that takes one (all but the gyrostat).
    pub fn drive(&self) -> Option<&Drive> {
        match self {
            Spec::RigidBody { drive, .. }
            | Spec::HeavyTop { drive, .. }
            | Spec::FreeBody { drive, .. }
            | Spec::OrbitingBody { drive, .. } => Some(drive),
            Spec::Gyrostat { .. } => None,
        }
    }
}

/// Which system, with its parameters as given.
#[derive(Debug, Clone, PartialEq)]
pub enum Spec {
    /// The free rigid body on SO(3).
    RigidBody { inertia: InertiaInput, drive: Drive },
    /// The heavy top on SO(3).
    HeavyTop {
        inertia: InertiaInput,
        mass: f64,
        gravity: f64,
        com: Vector3<f64>,
        gravity_direction: Vector3<f64>,
        drive: Drive,
    },
    /// The free body in space on SE(3).
    FreeBody {
        inertia: InertiaInput,
        mass: f64,
        drive: Drive,
    },
    /// The body orbiting a point mass on SE(3).
    OrbitingBody {
        inertia: InertiaInput,
        mass: f64,
        mu: f64,
        drive: Drive,
    },
    /// A gyrostat with 1 to 4 wheels on SO(3) × ℝᴷ.
    Gyrostat {
        inertia: Matrix3<f64>,
        axes: Vec<Vector3<f64>>,
        wheel_inertias: Vec<f64>,
    },
}

/// What a spec builds.
#[derive(Debug, Clone, Copy)]
pub enum Built {
    /// An SO(3) system.
    So3(So3System),
    /// An SE(3) system.
    Se3(Se3System),
    /// A gyrostat.
    Wheels(AnyGyrostat),
}

impl Spec {
    /// The Rust system.
    pub fn build(&self) -> PyResult<Built> {
        let drive = |d: &Drive| scenario::drive(d.torque, d.damping, d.spring);
        let so3 = |body, d: &Drive| -> So3System { Forced::new(body, drive(d)) };
        let se3 =
            |body, d: &Drive| -> Se3System { Forced::new(body, (drive(d), SpaceForce(d.force))) };
        Ok(match self {
            Spec::RigidBody { inertia, drive } => Built::So3(so3(
                BuiltInSo3::Free(library::RigidBody::new(inertia.inertia()?)),
                drive,
            )),
            Spec::HeavyTop {
                inertia,
                mass,
                gravity,
                com,
                gravity_direction,
                drive,
            } => {
                let top = library::HeavyTop::new(
                    inertia.inertia()?,
                    *mass,
                    *gravity,
                    *com,
                    *gravity_direction,
                )
                .map_err(mechanics)?;
                Built::So3(so3(BuiltInSo3::Top(top), drive))
            }
            Spec::FreeBody {
                inertia,
                mass,
                drive,
            } => {
                let body = library::FreeBody::new(inertia.inertia()?, *mass).map_err(mechanics)?;
                Built::Se3(se3(BuiltInSe3::Free(body), drive))
            }
            Spec::OrbitingBody {
                inertia,
                mass,
                mu,
                drive,
            } => {
                let body = library::OrbitingBody::new(inertia.inertia()?, *mass, *mu)
                    .map_err(mechanics)?;
                Built::Se3(se3(BuiltInSe3::Orbit(body), drive))
            }
            Spec::Gyrostat {
                inertia,
                axes,
                wheel_inertias,
            } => {
                Built::Wheels(AnyGyrostat::new(*inertia, axes, wheel_inertias).map_err(mechanics)?)
            }
        })
    }

    /// The class name.
    pub fn name(&self) -> &'static str {
        match self {
            Spec::RigidBody { .. } => "RigidBody",
            Spec::HeavyTop { .. } => "HeavyTop",
            Spec::FreeBody { .. } => "FreeBody",
            Spec::OrbitingBody { .. } => "OrbitingBody",
            Spec::Gyrostat { .. } => "Gyrostat",
        }
    }

    /// The number of wheels (0 but for a gyrostat).
    pub fn wheels(&self) -> usize {
        match self {
            Spec::Gyrostat { axes, .. } => axes.len(),
            _ => 0,
        }
    }

    /// Whether the system moves in space (SE(3)).
    pub fn in_space(&self) -> bool {
        matches!(self, Spec::FreeBody { .. } | Spec::OrbitingBody { .. })
    }
}

/// A mechanical system lgsvi integrates: the base class of `RigidBody`, `HeavyTop`,
/// `FreeBody`, `OrbitingBody` and `Gyrostat`. Systems are immutable, compare equal when
/// their parameters are, and pickle.
#[pyclass(module = "lgsvi._lgsvi", subclass, frozen)]
pub struct System {
    pub(crate) spec: Spec,
    pub(crate) built: Built,
}

impl System {
    fn new(spec: Spec) -> PyResult<Self> {
        let built = spec.build()?;
        Ok(Self { spec, built })
    }
}

#[pymethods]
impl System {
    /// The inertia tensor `J` (3×3, body frame; for a gyrostat with its wheels locked).
    #[getter]
    fn inertia<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let j = match &self.spec {
            Spec::Gyrostat { inertia, .. } => *inertia,
            Spec::RigidBody { inertia, .. }
            | Spec::HeavyTop { inertia, .. }
            | Spec::FreeBody { inertia, .. }
            | Spec::OrbitingBody { inertia, .. } => inertia.inertia()?.matrix(),
        };
        Ok(matrix_array(py, &j))
    }

    /// The group the system moves on: `"SO3"`, `"SE3"` or `"SO3xR^K"` (a gyrostat).
    #[getter]
    fn group(&self) -> String {
        match &self.spec {
            Spec::RigidBody { .. } | Spec::HeavyTop { .. } => "SO3".into(),
            Spec::FreeBody { .. } | Spec::OrbitingBody { .. } => "SE3".into(),
            Spec::Gyrostat { axes, .. } => format!("SO3xR^{}", axes.len()),
        }
    }

    /// The dimension of the control input `set_input` takes: 3 (a body torque) on SO(3),
    /// 6 (a body torque and a body force) on SE(3), `3 + K` for a gyrostat (a body torque
    /// and the K motor torques; `K` alone is accepted too).
    #[getter]
    fn input_dimension(&self) -> usize {
        match &self.spec {
            Spec::FreeBody { .. } | Spec::OrbitingBody { .. } => 6,
            other => 3 + other.wheels(),
        }
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<System>()
            .is_ok_and(|o| o.get().spec == self.spec)
    }

    fn __repr__(&self) -> String {
        let inertia = |i: &InertiaInput| match i {
            InertiaInput::Moments(m) => format!("inertia={m:?}"),
            InertiaInput::Tensor(t) => format!("inertia={:?}", rows3(t)),
            InertiaInput::PaperJd(jd) => format!("inertia_d={jd:?}"),
        };
        let drive = |d: &Drive, space: bool| {
            let mut s = String::new();
            if d.torque != Vector3::zeros() {
                s += &format!(", torque={:?}", d.torque.as_slice());
            }
            if d.damping != 0.0 {
                s += &format!(", damping={}", d.damping);
            }
            if d.spring.stiffness() != 0.0 {
                s += &format!(", attitude_gain={}", d.spring.stiffness());
            }
            if *d.spring.target() != SO3::identity() {
                s += &format!(", target={:?}", rows3(d.spring.target().matrix()));
            }
            if space && d.force != Vector3::zeros() {
                s += &format!(", force={:?}", d.force.as_slice());
            }
            s
        };
        match &self.spec {
            Spec::RigidBody {
                inertia: i,
                drive: d,
            } => {
                format!("RigidBody({}{})", inertia(i), drive(d, false))
            }
            Spec::HeavyTop {
                inertia: i,
                mass,
                gravity,
                com,
                gravity_direction,
                drive: d,
            } => format!(
                "HeavyTop({}, mass={mass}, gravity={gravity}, com={:?}, gravity_direction={:?}{})",
                inertia(i),
                com.as_slice(),
                gravity_direction.as_slice(),
                drive(d, false)
            ),
            Spec::FreeBody {
                inertia: i,
                mass,
                drive: d,
            } => format!("FreeBody({}, mass={mass}{})", inertia(i), drive(d, true)),
            Spec::OrbitingBody {
                inertia: i,
                mass,
                mu,
                drive: d,
            } => format!(
                "OrbitingBody({}, mass={mass}, mu={mu}{})",
                inertia(i),
                drive(d, true)
            ),
            Spec::Gyrostat {
                inertia,
                axes,
                wheel_inertias,
            } => format!(
                "Gyrostat(inertia={:?}, wheel_axes={:?}, wheel_inertias={wheel_inertias:?})",
                rows3(inertia),
                axes.iter().map(|a| [a.x, a.y, a.z]).collect::<Vec<_>>()
            ),
        }
    }

    /// Pickling: the class and its constructor's arguments.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let py = slf.py();
        let spec = &slf.get().spec;
        let v3 = |v: &Vector3<f64>| PyArray1::from_slice(py, v.as_slice()).into_any();
        let drive_args = |d: &Drive, space: bool| -> Vec<Bound<'py, PyAny>> {
            let mut args = vec![
                v3(&d.torque),
                d.damping
                    .into_pyobject(py)
                    .expect("a float converts")
                    .into_any(),
            ];
            if space {
                args.push(v3(&d.force));
            }
            args.push(
                d.spring
                    .stiffness()
                    .into_pyobject(py)
                    .expect("a float converts")
                    .into_any(),
            );
            args.push(matrix_array(py, d.spring.target().matrix()).into_any());
            args
        };
        let mut args: Vec<Bound<'py, PyAny>> = Vec::new();
        match spec {
            Spec::RigidBody { inertia, drive } => {
                let (j, jd) = inertia.arguments(py)?;
                args.extend([j, jd]);
                args.extend(drive_args(drive, false));
            }
            Spec::HeavyTop {
                inertia,
                mass,
                gravity,
                com,
                gravity_direction,
                drive,
            } => {
                let (j, jd) = inertia.arguments(py)?;
                args.push(j);
                args.push(mass.into_pyobject(py)?.into_any());
                args.push(gravity.into_pyobject(py)?.into_any());
                args.push(v3(com));
                args.push(v3(gravity_direction));
                args.push(jd);
                args.extend(drive_args(drive, false));
            }
            Spec::FreeBody {
                inertia,
                mass,
                drive,
            } => {
                let (j, jd) = inertia.arguments(py)?;
                args.push(j);
                args.push(mass.into_pyobject(py)?.into_any());
                args.push(jd);
                args.extend(drive_args(drive, true));
            }
            Spec::OrbitingBody {
                inertia,
                mass,
                mu,
                drive,
            } => {
                let (j, jd) = inertia.arguments(py)?;
                args.push(j);
                args.push(mass.into_pyobject(py)?.into_any());
                args.push(mu.into_pyobject(py)?.into_any());
                args.push(jd);
                args.extend(drive_args(drive, true));
            }
            Spec::Gyrostat {
                inertia,
                axes,
                wheel_inertias,
            } => {
                args.push(matrix_array(py, inertia).into_any());
                let flat: Vec<f64> = axes.iter().flat_map(|a| [a.x, a.y, a.z]).collect();
                args.push(crate::convert::array2(py, axes.len(), 3, flat).into_any());
                args.push(PyArray1::from_slice(py, wheel_inertias).into_any());
            }
        }
        Ok((slf.get_type().into_any(), PyTuple::new(py, args)?))
    }
}

/// A free rigid body on SO(3): `ℓ = ½ ΩᵀJΩ`, optionally under a constant body torque and
/// an angular damping.
///
/// Parameters
/// ----------
/// inertia : array_like, shape (3,) or (3, 3)
///     The principal moments `J = diag(a, b, c)` or the full inertia tensor (body frame,
///     kg·m²). Physical: positive, symmetric, each moment at most the sum of the others.
/// inertia_d : array_like, shape (3,), optional
///     The paper's `J_d` instead (`J = tr(J_d) I − J_d`).
/// torque : array_like, shape (3,), optional
///     A constant body-frame torque (N·m).
/// damping : float, optional
///     Damping `c ≥ 0` of the torque `τ = −c Ω` (N·m·s).
/// attitude_gain : float, optional
///     `K ≥ 0` of the torque `τ = −K θ` toward `target`, `θ = log(R_targetᵀ R)` (N·m per
///     radian): with `damping` the PD attitude law `−K θ − c Ω`, a continuous law
///     integrated to the method's order.
/// target : array_like, shape (3, 3), optional
///     The target attitude (world from body; the identity by default); also what a Monte
///     Carlo run's `error` condition is measured from.
#[pyclass(module = "lgsvi._lgsvi", extends = System, frozen)]
pub struct RigidBody;

#[pymethods]
impl RigidBody {
    #[new]
    #[pyo3(signature = (inertia=None, inertia_d=None, torque=None, damping=0.0, attitude_gain=0.0, target=None))]
    fn new(
        inertia: Option<&Bound<'_, PyAny>>,
        inertia_d: Option<&Bound<'_, PyAny>>,
        torque: Option<&Bound<'_, PyAny>>,
        damping: f64,
        attitude_gain: f64,
        target: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyClassInitializer<Self>> {
        guarded(|| {
            let spec = Spec::RigidBody {
                inertia: InertiaInput::from_arguments(inertia, inertia_d)?,
                drive: Drive::from_arguments(torque, damping, None, attitude_gain, target)?,
            };
            Ok(PyClassInitializer::from(System::new(spec)?).add_subclass(RigidBody))
        })
    }
}

/// A heavy top (3D pendulum) on SO(3): `ℓ = ½ ΩᵀJΩ + m g dᵀRρ` with gravity pulling along
/// `d` (world frame) on the centre of mass `ρ` (body frame). `R = I` hangs at rest when
/// `ρ` and `d` agree (the paper's defaults: `m = 1`, `g = 9.81`, `ρ = d = e₃`).
///
/// Parameters
/// ----------
/// inertia : array_like, shape (3,) or (3, 3)
///     `J` about the pivot (principal moments or a tensor), or give `inertia_d`.
/// mass, gravity : float
///     `m ≥ 0` (kg), `g ≥ 0` (m/s²).
/// com : array_like, shape (3,)
///     The centre of mass `ρ` from the pivot, body frame (m).
/// gravity_direction : array_like, shape (3,)
///     The direction gravity pulls, world frame (normalised here).
/// inertia_d, torque, damping, attitude_gain, target
///     As for `RigidBody`.
#[pyclass(module = "lgsvi._lgsvi", extends = System, frozen)]
pub struct HeavyTop;

#[pymethods]
impl HeavyTop {
    #[new]
    #[pyo3(signature = (inertia=None, mass=1.0, gravity=9.81, com=None, gravity_direction=None, inertia_d=None, torque=None, damping=0.0, attitude_gain=0.0, target=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        inertia: Option<&Bound<'_, PyAny>>,
        mass: f64,
        gravity: f64,
        com: Option<&Bound<'_, PyAny>>,
        gravity_direction: Option<&Bound<'_, PyAny>>,
        inertia_d: Option<&Bound<'_, PyAny>>,
        torque: Option<&Bound<'_, PyAny>>,
        damping: f64,
        attitude_gain: f64,
        target: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyClassInitializer<Self>> {
        guarded(|| {
            let spec = Spec::HeavyTop {
                inertia: InertiaInput::from_arguments(inertia, inertia_d)?,
                mass: finite_scalar(mass, "mass")?,
                gravity: finite_scalar(gravity, "gravity")?,
                com: com.map_or(Ok(Vector3::z()), |c| vector3(c, "com"))?,
                gravity_direction: gravity_direction
                    .map_or(Ok(Vector3::z()), |d| vector3(d, "gravity_direction"))?,
                drive: Drive::from_arguments(torque, damping, None, attitude_gain, target)?,
            };
            Ok(PyClassInitializer::from(System::new(spec)?).add_subclass(HeavyTop))
        })
    }
}

/// A rigid body moving freely in space, on SE(3): `ℓ = ½ ΩᵀJΩ + ½ m |ẋ|²`, optionally
/// under a body torque, an angular damping and a constant space-frame force on its centre
/// of mass.
///
/// Parameters
/// ----------
/// inertia : array_like, shape (3,) or (3, 3)
///     `J` about the centre of mass, or give `inertia_d`.
/// mass : float
///     `m > 0` (kg).
/// inertia_d, torque, damping, attitude_gain, target
///     As for `RigidBody`.
/// force : array_like, shape (3,), optional
///     A constant space-frame force on the centre of mass (N).
#[pyclass(module = "lgsvi._lgsvi", extends = System, frozen)]
pub struct FreeBody;

#[pymethods]
impl FreeBody {
    #[new]
    #[pyo3(signature = (inertia=None, mass=1.0, inertia_d=None, torque=None, damping=0.0, force=None, attitude_gain=0.0, target=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        inertia: Option<&Bound<'_, PyAny>>,
        mass: f64,
        inertia_d: Option<&Bound<'_, PyAny>>,
        torque: Option<&Bound<'_, PyAny>>,
        damping: f64,
        force: Option<&Bound<'_, PyAny>>,
        attitude_gain: f64,
        target: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyClassInitializer<Self>> {
        guarded(|| {
            let spec = Spec::FreeBody {
                inertia: InertiaInput::from_arguments(inertia, inertia_d)?,
                mass: finite_scalar(mass, "mass")?,
                drive: Drive::from_arguments(torque, damping, force, attitude_gain, target)?,
            };
            Ok(PyClassInitializer::from(System::new(spec)?).add_subclass(FreeBody))
        })
    }
}

/// A rigid body orbiting a point mass of gravitational parameter `μ = GM` at the origin, on
/// SE(3): the potential to second order in the body's size (MacCullagh's), so the gravity
/// gradient's torque couples attitude and orbit.
///
/// Parameters
/// ----------
/// inertia : array_like, shape (3,) or (3, 3)
///     `J` about the centre of mass, or give `inertia_d`.
/// mass : float
///     `m > 0`.
/// mu : float
///     `μ = GM ≥ 0`.
/// inertia_d, torque, damping, force, attitude_gain, target
///     As for `FreeBody`.
#[pyclass(module = "lgsvi._lgsvi", extends = System, frozen)]
pub struct OrbitingBody;

#[pymethods]
impl OrbitingBody {
    #[new]
    #[pyo3(signature = (inertia=None, mass=1.0, mu=1.0, inertia_d=None, torque=None, damping=0.0, force=None, attitude_gain=0.0, target=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        inertia: Option<&Bound<'_, PyAny>>,
        mass: f64,
        mu: f64,
        inertia_d: Option<&Bound<'_, PyAny>>,
        torque: Option<&Bound<'_, PyAny>>,
        damping: f64,
        force: Option<&Bound<'_, PyAny>>,
        attitude_gain: f64,
        target: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyClassInitializer<Self>> {
        guarded(|| {
            let spec = Spec::OrbitingBody {
                inertia: InertiaInput::from_arguments(inertia, inertia_d)?,
                mass: finite_scalar(mass, "mass")?,
                mu: finite_scalar(mu, "mu")?,
                drive: Drive::from_arguments(torque, damping, force, attitude_gain, target)?,
            };
            Ok(PyClassInitializer::from(System::new(spec)?).add_subclass(OrbitingBody))
        })
    }
}

/// A spacecraft with 1 to 4 reaction wheels on fixed body axes, on SO(3) × ℝᴷ: the wheels'
/// motor torques are its control input (`Integrator.set_input`).
///
/// Parameters
/// ----------
/// inertia : array_like, shape (3, 3) or (3,)
///     The whole spacecraft's inertia with the wheels locked (their axial inertia
///     included).
/// wheel_axes : array_like, shape (K, 3)
///     The wheel axes, body frame (normalised here).
/// wheel_inertias : array_like, shape (K,)
///     The wheels' axial inertias (positive).
#[pyclass(module = "lgsvi._lgsvi", extends = System, frozen)]
pub struct Gyrostat;

#[pymethods]
impl Gyrostat {
    #[new]
    #[pyo3(signature = (inertia, wheel_axes, wheel_inertias))]
    fn new(
        inertia: &Bound<'_, PyAny>,
        wheel_axes: &Bound<'_, PyAny>,
        wheel_inertias: &Bound<'_, PyAny>,
    ) -> PyResult<PyClassInitializer<Self>> {
        guarded(|| {
            let j = match InertiaInput::from_arguments(Some(inertia), None)? {
                InertiaInput::Moments(m) => Matrix3::from_diagonal(&Vector3::from(m)),
                InertiaInput::Tensor(t) => t,
                InertiaInput::PaperJd(_) => unreachable!("inertia_d was not given"),
            };
            let axes = vectors3(wheel_axes, "wheel_axes")?;
            let wheel_inertias = vector(wheel_inertias, "wheel_inertias")?;
            if axes.len() != wheel_inertias.len() {
                return Err(invalid(format!(
                    "wheel_axes has {} axes and wheel_inertias {} inertias: one per wheel",
                    axes.len(),
                    wheel_inertias.len()
                )));
            }
            let spec = Spec::Gyrostat {
                inertia: j,
                axes,
                wheel_inertias,
            };
            Ok(PyClassInitializer::from(System::new(spec)?).add_subclass(Gyrostat))
        })
    }
}

/// A scalar parameter that must be finite.
fn finite_scalar(value: f64, name: &str) -> PyResult<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(invalid(format!("{name} must be finite, got {value}")))
    }
}

/// The system a Python argument holds.
pub fn system_of(value: &Bound<'_, PyAny>) -> PyResult<(Spec, Built)> {
    let system = value.cast::<System>().map_err(|_| {
        invalid(format!(
            "system must be an lgsvi system (RigidBody, HeavyTop, FreeBody, OrbitingBody, \
             Gyrostat), got {}",
            value
                .get_type()
                .name()
                .map_or_else(|_| "an object".into(), |n| n.to_string())
        ))
    })?;
    let s = system.get();
    Ok((s.spec.clone(), s.built))
}

/// Registers the classes.
pub fn register(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add_class::<System>()?;
    module.add_class::<RigidBody>()?;
    module.add_class::<HeavyTop>()?;
    module.add_class::<FreeBody>()?;
    module.add_class::<OrbitingBody>()?;
    module.add_class::<Gyrostat>()?;
    Ok(())
}
