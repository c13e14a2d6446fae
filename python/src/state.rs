//! A state as Python sees it (`lgsvi.State`), and the conversions between the library's
//! states on each group and plain numbers: attitude, rates, position and velocity in the
//! world frame, wheels.

use crate::convert::{array1, array2, rows3};
use crate::errors::invalid;
use lgsvi_lie::{SE3, SO3};
use lgsvi_mechanics::gyrostat::BodyWheels;
use lgsvi_mechanics::State as RustState;
use nalgebra::{Matrix3, SVector, Vector3};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

/// At most seven numbers, kept inline (a state's momentum has `D ≤ 7` entries, a
/// gyrostat at most four wheels): a state's numbers are copied without allocating.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Small {
    values: [f64; 7],
    len: usize,
}

impl Small {
    /// The first `values.len() ≤ 7` entries.
    pub fn new(values: impl IntoIterator<Item = f64>) -> Self {
        let mut small = Self {
            values: [0.0; 7],
            len: 0,
        };
        for v in values {
            small.values[small.len] = v;
            small.len += 1;
        }
        small
    }
}

impl std::ops::Deref for Small {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.values[..self.len]
    }
}

/// One state's numbers, on any group.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Time.
    pub t: f64,
    /// `R = world_from_body`.
    pub attitude: Matrix3<f64>,
    /// Body angular velocity `Ω`.
    pub omega: Vector3<f64>,
    /// Centre of mass `x`, world frame (SE(3)).
    pub position: Option<Vector3<f64>>,
    /// Its velocity `ẋ`, world frame (SE(3)).
    pub velocity: Option<Vector3<f64>>,
    /// Body momentum `μ = ∂ℓ/∂ξ` (`D` entries).
    pub momentum: Small,
    /// Spatial angular momentum: `Rμ` on SO(3), `RJΩ + x × mẋ` about the origin on SE(3),
    /// `R h` (the total, wheels included) for a gyrostat.
    pub spatial_momentum: Vector3<f64>,
    /// Linear momentum `mẋ`, world frame (SE(3)).
    pub linear_momentum: Option<Vector3<f64>>,
    /// Wheel angles relative to the body (gyrostat).
    pub wheel_angles: Option<Small>,
    /// Wheel rates relative to the body (gyrostat).
    pub wheel_speeds: Option<Small>,
    /// Energy `⟨μ, ξ⟩ − ℓ`.
    pub energy: f64,
}

/// How to read and make states of one group (`D` its algebra's dimension).
pub trait Element<const D: usize>: Copy + Send + Sync + 'static {
    /// The configuration and body velocity of a start given in plain numbers.
    ///
    /// # Errors
    /// A start the group does not take (wheel counts that do not match).
    fn from_start(start: &Start) -> PyResult<(Self, SVector<f64, D>)>;
    /// The state's numbers, its energy given.
    fn sample(state: &RustState<Self, D>, energy: f64) -> Sample;
    /// The control input from the entries given.
    ///
    /// # Errors
    /// A length the group's input does not have.
    fn input(u: &[f64]) -> PyResult<SVector<f64, D>>;
}

/// A start in plain numbers (world-frame position and velocity on SE(3)).
#[derive(Debug, Clone, PartialEq)]
pub struct Start {
    /// The start time.
    pub t: f64,
    /// `R₀`.
    pub attitude: SO3,
    /// `Ω₀`.
    pub omega: Vector3<f64>,
    /// `x₀` (SE(3)).
    pub position: Vector3<f64>,
    /// `ẋ₀`, world frame (SE(3)).
    pub velocity: Vector3<f64>,
    /// The wheels' rates (gyrostat).
    pub wheel_speeds: Vec<f64>,
    /// The wheels' angles (gyrostat).
    pub wheel_angles: Vec<f64>,
}

impl Start {
    /// A start from a sample of the same group.
    pub fn of(sample: &Sample) -> Self {
        Self {
            t: sample.t,
            attitude: SO3::from_matrix_unchecked(sample.attitude),
            omega: sample.omega,
            position: sample.position.unwrap_or_default(),
            velocity: sample.velocity.unwrap_or_default(),
            wheel_speeds: sample.wheel_speeds.map_or_else(Vec::new, |v| v.to_vec()),
            wheel_angles: sample.wheel_angles.map_or_else(Vec::new, |v| v.to_vec()),
        }
    }
}

impl Element<3> for SO3 {
    fn from_start(start: &Start) -> PyResult<(Self, Vector3<f64>)> {
        Ok((start.attitude, start.omega))
    }
    fn sample(state: &RustState<SO3, 3>, energy: f64) -> Sample {
        Sample {
            t: state.time,
            attitude: *state.configuration.matrix(),
            omega: state.velocity,
            position: None,
            velocity: None,
            momentum: Small::new(state.momentum.iter().copied()),
            spatial_momentum: state.spatial_momentum(),
            linear_momentum: None,
            wheel_angles: None,
            wheel_speeds: None,
            energy,
        }
    }
    fn input(u: &[f64]) -> PyResult<Vector3<f64>> {
        match u {
            [x, y, z] => Ok(Vector3::new(*x, *y, *z)),
            _ => Err(invalid(format!(
                "u must be a body torque of 3 entries on SO(3), got {}",
                u.len()
            ))),
        }
    }
}

impl Element<6> for SE3 {
    fn from_start(start: &Start) -> PyResult<(Self, SVector<f64, 6>)> {
        let g = SE3::new(start.attitude, start.position);
        let v = start.attitude.matrix().transpose() * start.velocity;
        let w = start.omega;
        Ok((g, SVector::<f64, 6>::new(w.x, w.y, w.z, v.x, v.y, v.z)))
    }
    fn sample(state: &RustState<SE3, 6>, energy: f64) -> Sample {
        let spatial = state.spatial_momentum();
        Sample {
            t: state.time,
            attitude: *state.attitude().matrix(),
            omega: state.angular_velocity(),
            position: Some(state.position()),
            velocity: Some(state.linear_velocity()),
            momentum: Small::new(state.momentum.iter().copied()),
            spatial_momentum: spatial.fixed_rows::<3>(0).into_owned(),
            linear_momentum: Some(spatial.fixed_rows::<3>(3).into_owned()),
            wheel_angles: None,
            wheel_speeds: None,
            energy,
        }
    }
    fn input(u: &[f64]) -> PyResult<SVector<f64, 6>> {
        if u.len() != 6 {
            return Err(invalid(format!(
                "u must be a body wrench (torque, force) of 6 entries on SE(3), got {}",
                u.len()
            )));
        }
        Ok(SVector::<f64, 6>::from_column_slice(u))
    }
}

macro_rules! wheels_element {
    ($($k:literal => $d:literal),*) => {$(
        impl Element<$d> for BodyWheels<f64, $k> {
            fn from_start(start: &Start) -> PyResult<(Self, SVector<f64, $d>)> {
                let speeds = wheel_values(&start.wheel_speeds, $k, "wheel_speeds")?;
                let angles = wheel_values(&start.wheel_angles, $k, "wheel_angles")?;
                let mut xi = SVector::<f64, $d>::zeros();
                xi.fixed_rows_mut::<3>(0).copy_from(&start.omega);
                for i in 0..$k {
                    xi[3 + i] = speeds[i];
                }
                let g = BodyWheels {
                    attitude: start.attitude,
                    wheels: SVector::<f64, $k>::from_column_slice(&angles),
                };
                Ok((g, xi))
            }
            fn sample(state: &RustState<Self, $d>, energy: f64) -> Sample {
                let r = *state.configuration.attitude.matrix();
                let h = state.momentum.fixed_rows::<3>(0).into_owned();
                Sample {
                    t: state.time,
                    attitude: r,
                    omega: state.velocity.fixed_rows::<3>(0).into_owned(),
                    position: None,
                    velocity: None,
                    momentum: Small::new(state.momentum.iter().copied()),
                    spatial_momentum: r * h,
                    linear_momentum: None,
                    wheel_angles: Some(Small::new(state.configuration.wheels.iter().copied())),
                    wheel_speeds: Some(Small::new(state.velocity.iter().skip(3).copied())),
                    energy,
                }
            }
            fn input(u: &[f64]) -> PyResult<SVector<f64, $d>> {
                let mut full = SVector::<f64, $d>::zeros();
                match u.len() {
                    $k => full.rows_mut(3, $k).copy_from_slice(u),
                    $d => full.copy_from_slice(u),
                    n => {
                        return Err(invalid(format!(
                            "u must be the {} motor torques, or a body torque and them ({} \
                             entries), got {n}",
                            $k, $d
                        )))
                    }
                }
                Ok(full)
            }
        }
    )*};
}
wheels_element!(1 => 4, 2 => 5, 3 => 6, 4 => 7);

/// `values` as `k` wheel entries (none given: zeros).
fn wheel_values(values: &[f64], k: usize, name: &str) -> PyResult<Vec<f64>> {
    match values.len() {
        0 => Ok(vec![0.0; k]),
        n if n == k => Ok(values.to_vec()),
        n => Err(invalid(format!(
            "{name} has {n} entries for a gyrostat with {k} wheels: one per wheel"
        ))),
    }
}

/// The state of a system at one time: attitude, rates and, where the system has them,
/// position and velocity (world frame) or wheels. Immutable; compares equal entry by entry;
/// pickles.
///
/// Attributes
/// ----------
/// t : float
/// attitude : ndarray (3, 3)
///     `R = world_from_body` (a vector `v_body` is `R @ v_body` in the world frame).
/// quaternion : ndarray (4,)
///     The attitude as a unit quaternion `(w, x, y, z)`, `w ≥ 0`.
/// omega : ndarray (3,)
///     Body angular velocity `Ω` (rad/s).
/// position, velocity : ndarray (3,) or None
///     Centre of mass and its velocity, world frame (bodies in space).
/// momentum : ndarray (D,)
///     Body momentum `μ = ∂ℓ/∂ξ` (`JΩ` on SO(3); `(JΩ, m v)` on SE(3); `(h, p)` for a
///     gyrostat: total body angular momentum and the wheels' axial momenta).
/// spatial_momentum : ndarray (3,)
///     Angular momentum in the world frame (about the origin for a body in space).
/// linear_momentum : ndarray (3,) or None
///     `m ẋ` (bodies in space).
/// energy : float
/// wheel_angles, wheel_speeds : ndarray (K,) or None
///     A gyrostat's wheels, relative to the body.
#[pyclass(module = "lgsvi._lgsvi", frozen)]
#[derive(Debug, Clone)]
pub struct State {
    pub(crate) sample: Sample,
}

fn opt3<'py>(py: Python<'py>, v: &Option<Vector3<f64>>) -> Option<Bound<'py, PyArray1<f64>>> {
    v.map(|v| array1(py, v.as_slice().to_vec()))
}

#[pymethods]
impl State {
    /// Time.
    #[getter]
    fn t(&self) -> f64 {
        self.sample.t
    }
    /// `R = world_from_body` (3×3).
    #[getter]
    fn attitude<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        array2(py, 3, 3, rows3(&self.sample.attitude).to_vec())
    }
    /// The attitude as a unit quaternion `(w, x, y, z)`, `w ≥ 0`.
    #[getter]
    fn quaternion<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, quaternion(&self.sample.attitude).to_vec())
    }
    /// Body angular velocity `Ω`.
    #[getter]
    fn omega<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.sample.omega.as_slice().to_vec())
    }
    /// Centre of mass, world frame (bodies in space; else None).
    #[getter]
    fn position<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        opt3(py, &self.sample.position)
    }
    /// Centre of mass velocity, world frame (bodies in space; else None).
    #[getter]
    fn velocity<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        opt3(py, &self.sample.velocity)
    }
    /// Body momentum `μ = ∂ℓ/∂ξ`.
    #[getter]
    fn momentum<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.sample.momentum.to_vec())
    }
    /// Angular momentum in the world frame.
    #[getter]
    fn spatial_momentum<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.sample.spatial_momentum.as_slice().to_vec())
    }
    /// Linear momentum `m ẋ` (bodies in space; else None).
    #[getter]
    fn linear_momentum<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        opt3(py, &self.sample.linear_momentum)
    }
    /// Energy `⟨μ, ξ⟩ − ℓ`.
    #[getter]
    fn energy(&self) -> f64 {
        self.sample.energy
    }
    /// Wheel angles relative to the body (a gyrostat; else None).
    #[getter]
    fn wheel_angles<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.sample.wheel_angles.map(|v| array1(py, v.to_vec()))
    }
    /// Wheel rates relative to the body (a gyrostat; else None).
    #[getter]
    fn wheel_speeds<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.sample.wheel_speeds.map(|v| array1(py, v.to_vec()))
    }
    /// The state's fields as a dict of floats and ndarrays.
    fn to_dict<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        let py = slf.py();
        let d = PyDict::new(py);
        for name in FIELDS {
            d.set_item(name, slf.getattr(name)?)?;
        }
        Ok(d)
    }
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<State>()
            .is_ok_and(|o| o.get().sample == self.sample)
    }
    fn __repr__(&self) -> String {
        let s = &self.sample;
        let mut text = format!(
            "State(t={}, omega={:?}, energy={}",
            s.t,
            s.omega.as_slice(),
            s.energy
        );
        if let Some(x) = s.position {
            text += &format!(", position={:?}", x.as_slice());
        }
        if let Some(w) = &s.wheel_speeds {
            text += &format!(", wheel_speeds={:?}", &w[..]);
        }
        text + ")"
    }
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let py = slf.py();
        let restore = py.import("lgsvi._lgsvi")?.getattr("_state_from_fields")?;
        let s = &slf.get().sample;
        let fields = (
            s.t,
            rows3(&s.attitude).to_vec(),
            s.omega.as_slice().to_vec(),
            s.position.map(|v| v.as_slice().to_vec()),
            s.velocity.map(|v| v.as_slice().to_vec()),
            s.momentum.to_vec(),
            s.spatial_momentum.as_slice().to_vec(),
            s.linear_momentum.map(|v| v.as_slice().to_vec()),
            s.wheel_angles.map(|v| v.to_vec()),
            s.wheel_speeds.map(|v| v.to_vec()),
            s.energy,
        );
        Ok((restore, PyTuple::new(py, [fields.into_pyobject(py)?])?))
    }
}

/// The attributes `State.to_dict` holds.
const FIELDS: [&str; 12] = [
    "t",
    "attitude",
    "quaternion",
    "omega",
    "position",
    "velocity",
    "momentum",
    "spatial_momentum",
    "linear_momentum",
    "energy",
    "wheel_angles",
    "wheel_speeds",
];

type Fields = (
    f64,
    Vec<f64>,
    Vec<f64>,
    Option<Vec<f64>>,
    Option<Vec<f64>>,
    Vec<f64>,
    Vec<f64>,
    Option<Vec<f64>>,
    Option<Vec<f64>>,
    Option<Vec<f64>>,
    f64,
);

/// Unpickles a [`State`].
#[pyfunction]
pub fn _state_from_fields(fields: Fields) -> State {
    let v3 = |v: &Vec<f64>| Vector3::from_column_slice(v);
    let (t, r, w, x, v, mu, pi, p, angles, speeds, energy) = fields;
    State {
        sample: Sample {
            t,
            attitude: Matrix3::from_row_slice(&r),
            omega: v3(&w),
            position: x.as_ref().map(v3),
            velocity: v.as_ref().map(v3),
            momentum: Small::new(mu),
            spatial_momentum: v3(&pi),
            linear_momentum: p.as_ref().map(v3),
            wheel_angles: angles.map(Small::new),
            wheel_speeds: speeds.map(Small::new),
            energy,
        },
    }
}

/// `R` as a unit quaternion `(w, x, y, z)` with `w ≥ 0`.
pub fn quaternion(r: &Matrix3<f64>) -> [f64; 4] {
    let q = SO3::from_matrix_unchecked(*r).quaternion_wxyz();
    if q[0] < 0.0 {
        q.map(|x| -x)
    } else {
        q
    }
}
