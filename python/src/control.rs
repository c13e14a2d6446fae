//! Control design on a step's exact linearisation: discrete LQR (Drake's
//! `DiscreteTimeLinearQuadraticRegulator` order and sign: `u = −K x`), the finite-horizon
//! recursion along a trajectory, the error state on the group, and the regulator.

use crate::convert::{from_matrix, matrix, rotation, vector};
use crate::errors::{guarded, invalid, mechanics};
use crate::state::{Sample, State};
use crate::systems::matrix_array;
use lgsvi_lie::{SE3, SO3};
use lgsvi_mechanics::control::{self, Regulator as RustRegulator};
use lgsvi_mechanics::State as RustState;
use nalgebra::{DMatrix, SVector};
use numpy::{PyArray1, PyArray3};
use pyo3::prelude::*;

/// A matrix handed to Python.
type Matrix<'py> = Bound<'py, numpy::PyArray2<f64>>;

/// The infinite-horizon discrete LQR for `x₊ = A x + B u` with stage cost `xᵀQx + uᵀRu`.
///
/// Returns `(K, S)`: the gain of `u = −K x` and the cost-to-go `S` (`xᵀSx`), the
/// stabilising solution of the discrete algebraic Riccati equation (structured doubling).
/// Raises InvalidInputError for shapes that do not fit, `R` not positive definite, or a
/// pair that no gain stabilises.
#[pyfunction]
#[pyo3(signature = (A, B, Q, R))]
#[allow(non_snake_case)]
fn dlqr<'py>(
    py: Python<'py>,
    A: &Bound<'py, PyAny>,
    B: &Bound<'py, PyAny>,
    Q: &Bound<'py, PyAny>,
    R: &Bound<'py, PyAny>,
) -> PyResult<(Matrix<'py>, Matrix<'py>)> {
    let (a, b, q, r) = (
        matrix(A, "A")?,
        matrix(B, "B")?,
        matrix(Q, "Q")?,
        matrix(R, "R")?,
    );
    let design = py.detach(|| guarded(|| control::lqr(&a, &b, &q, &r).map_err(mechanics)))?;
    Ok((from_matrix(py, &design.gain), from_matrix(py, &design.cost)))
}

/// The stabilising solution `S` of the discrete algebraic Riccati equation
/// `S = AᵀSA − AᵀSB (R + BᵀSB)⁻¹ BᵀSA + Q`.
#[pyfunction]
#[pyo3(signature = (A, B, Q, R))]
#[allow(non_snake_case)]
fn dare<'py>(
    py: Python<'py>,
    A: &Bound<'py, PyAny>,
    B: &Bound<'py, PyAny>,
    Q: &Bound<'py, PyAny>,
    R: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
    let (a, b, q, r) = (
        matrix(A, "A")?,
        matrix(B, "B")?,
        matrix(Q, "Q")?,
        matrix(R, "R")?,
    );
    let s = py.detach(|| guarded(|| control::dare(&a, &b, &q, &r).map_err(mechanics)))?;
    Ok(from_matrix(py, &s))
}

/// The time-varying LQR along a trajectory: the gains `K_k` (`u_k = −K_k x_k`) of the
/// finite-horizon problem with linearisations `(A_k, B_k)`, stage cost `xᵀQx + uᵀRu` and
/// final cost `xᵀQf x` (the backward Riccati recursion).
///
/// Parameters
/// ----------
/// As, Bs : sequences of arrays (N of each), or arrays (N, n, n) and (N, n, m)
/// Q, R, Qf : arrays
///
/// Returns an array (N, m, n) of gains.
#[pyfunction]
#[pyo3(signature = (As, Bs, Q, R, Qf))]
#[allow(non_snake_case)]
fn tvlqr<'py>(
    py: Python<'py>,
    As: &Bound<'py, PyAny>,
    Bs: &Bound<'py, PyAny>,
    Q: &Bound<'py, PyAny>,
    R: &Bound<'py, PyAny>,
    Qf: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray3<f64>>> {
    let list = |v: &Bound<'py, PyAny>, name: &str| -> PyResult<Vec<DMatrix<f64>>> {
        let items: Vec<Bound<'py, PyAny>> = v
            .try_iter()
            .map_err(|_| invalid(format!("{name} must be a sequence of matrices")))?
            .collect::<PyResult<_>>()?;
        items
            .iter()
            .enumerate()
            .map(|(k, m)| matrix(m, &format!("{name}[{k}]")))
            .collect()
    };
    let (a, b) = (list(As, "As")?, list(Bs, "Bs")?);
    if a.len() != b.len() {
        return Err(invalid(format!(
            "As has {} matrices and Bs {}: one pair per step",
            a.len(),
            b.len()
        )));
    }
    let (q, r, qf) = (matrix(Q, "Q")?, matrix(R, "R")?, matrix(Qf, "Qf")?);
    let steps: Vec<(DMatrix<f64>, DMatrix<f64>)> = a.into_iter().zip(b).collect();
    let gains = py.detach(|| {
        guarded(|| control::finite_horizon_gains(&steps, &q, &r, &qf).map_err(mechanics))
    })?;
    let (m, n) = gains.first().map_or((0, 0), |k| k.shape());
    let flat: Vec<f64> = gains
        .iter()
        .flat_map(|k| k.transpose().iter().copied().collect::<Vec<_>>())
        .collect();
    Ok(crate::convert::array3(py, (gains.len(), m, n), flat))
}

/// A state of SO(3) or SE(3) as the library's, from its numbers.
enum GroupState {
    So3(RustState<SO3, 3>),
    Se3(RustState<SE3, 6>),
}

impl GroupState {
    fn of(sample: &Sample, name: &str) -> PyResult<Self> {
        if sample.wheel_speeds.is_some() {
            return Err(invalid(format!(
                "{name}: the error state and the regulator take states of SO(3) and SE(3) \
                 bodies, not of a gyrostat"
            )));
        }
        let attitude = SO3::from_matrix_unchecked(sample.attitude);
        Ok(match (sample.position, sample.velocity) {
            (Some(x), Some(v)) => {
                let body = sample.attitude.transpose() * v;
                let w = sample.omega;
                GroupState::Se3(RustState {
                    time: sample.t,
                    configuration: SE3::new(attitude, x),
                    momentum: SVector::<f64, 6>::from_column_slice(&sample.momentum),
                    velocity: SVector::<f64, 6>::new(w.x, w.y, w.z, body.x, body.y, body.z),
                })
            }
            _ => GroupState::So3(RustState {
                time: sample.t,
                configuration: attitude,
                momentum: SVector::<f64, 3>::from_column_slice(&sample.momentum),
                velocity: sample.omega,
            }),
        })
    }
}

/// The error state `x = (θ, ξ − ξ̄)` of `state` against `reference` (`2D` entries): `θ` the
/// group's logarithm of `reference⁻¹ state` (body frame), then the body velocities'
/// difference: the coordinates of `Integrator.linearize(coordinates="velocity")`.
#[pyfunction]
fn error_state<'py>(
    py: Python<'py>,
    state: PyRef<'py, State>,
    reference: PyRef<'py, State>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let x = match (
        GroupState::of(&state.sample, "state")?,
        GroupState::of(&reference.sample, "reference")?,
    ) {
        (GroupState::So3(s), GroupState::So3(r)) => control::error_state(&s, &r),
        (GroupState::Se3(s), GroupState::Se3(r)) => control::error_state(&s, &r),
        _ => {
            return Err(invalid(
                "state and reference must be of the same group (both SO(3) or both SE(3))",
            ))
        }
    };
    Ok(PyArray1::from_vec(py, x.iter().copied().collect()))
}

enum AnyRegulator {
    So3(RustRegulator<SO3, 3>),
    Se3(RustRegulator<SE3, 6>),
}

/// A regulator about a reference state: `u = ū − K (θ, ξ − ξ̄)`, the error taken by the
/// group's logarithm (`error_state`), `K` from `dlqr` on the reference's linearisation.
/// Call `input(state)` each step and hand the result to `Integrator.set_input`.
///
/// Parameters
/// ----------
/// reference : State
///     The state to hold (an equilibrium of SO(3) or SE(3)).
/// K : array_like (D, 2D)
///     The gain, in the coordinates of `linearize(coordinates="velocity")`.
/// feedforward : array_like (D,), optional
///     The input `ū` that holds the reference (default zero).
#[pyclass(module = "lgsvi._lgsvi", frozen)]
pub struct Regulator {
    regulator: AnyRegulator,
}

#[pymethods]
impl Regulator {
    #[new]
    #[pyo3(signature = (reference, K, feedforward=None))]
    #[allow(non_snake_case)]
    fn new(
        reference: PyRef<'_, State>,
        K: &Bound<'_, PyAny>,
        feedforward: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let gain = matrix(K, "K")?;
        let u = feedforward.map(|f| vector(f, "feedforward")).transpose()?;
        let regulator = match GroupState::of(&reference.sample, "reference")? {
            GroupState::So3(r) => {
                let u = fixed::<3>(u)?;
                AnyRegulator::So3(RustRegulator::new(r, u, gain).map_err(mechanics)?)
            }
            GroupState::Se3(r) => {
                let u = fixed::<6>(u)?;
                AnyRegulator::Se3(RustRegulator::new(r, u, gain).map_err(mechanics)?)
            }
        };
        Ok(Self { regulator })
    }

    /// The input for `state`.
    fn input<'py>(
        &self,
        py: Python<'py>,
        state: PyRef<'py, State>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let u: Vec<f64> = match (&self.regulator, GroupState::of(&state.sample, "state")?) {
            (AnyRegulator::So3(r), GroupState::So3(s)) => r.input(&s).iter().copied().collect(),
            (AnyRegulator::Se3(r), GroupState::Se3(s)) => r.input(&s).iter().copied().collect(),
            _ => return Err(invalid("state must be of the regulator's group")),
        };
        Ok(PyArray1::from_vec(py, u))
    }
}

/// A PD attitude law with a torque limit, for a controller that samples the state and
/// holds its torque: `u = sat_L(−K θ − C Ω)`, `θ = log(R_targetᵀ R)` the rotation vector
/// from the target to the attitude (body frame), `sat_L` scaling a torque longer than `L`
/// back to length `L` along its own direction (an actuator's limit that keeps the law's
/// axis). Call `input(state)` at each sampling instant and hand the result to
/// `Integrator.set_input`, or give the law to `lgsvi.montecarlo.run(controller=...,
/// sample_period=...)`. (The continuous, unlimited law is a system's `attitude_gain` with
/// its `damping`.)
///
/// Parameters
/// ----------
/// gain : float
///     `K ≥ 0`, N·m per radian.
/// rate_gain : float
///     `C ≥ 0`, N·m·s per radian (default 0).
/// target : array_like (3, 3), optional
///     The target attitude `R_target` (world from body; default the identity).
/// torque_limit : float, optional
///     The actuator's largest torque `L > 0`, N·m (default: no limit).
#[pyclass(module = "lgsvi._lgsvi", frozen)]
pub struct PdLaw {
    pub law: control::PdLaw,
}

#[pymethods]
impl PdLaw {
    #[new]
    #[pyo3(signature = (gain, rate_gain=0.0, target=None, torque_limit=None))]
    fn new(
        gain: f64,
        rate_gain: f64,
        target: Option<&Bound<'_, PyAny>>,
        torque_limit: Option<f64>,
    ) -> PyResult<Self> {
        let target = target.map_or(Ok(SO3::identity()), |t| rotation(t, "target"))?;
        if !(gain.is_finite() && gain >= 0.0) {
            return Err(invalid(format!(
                "gain must be finite and non-negative (K of −Kθ, N·m per radian), got {gain}"
            )));
        }
        if !(rate_gain.is_finite() && rate_gain >= 0.0) {
            return Err(invalid(format!(
                "rate_gain must be finite and non-negative (C of −CΩ, N·m·s per radian), got \
                 {rate_gain}"
            )));
        }
        let law = control::PdLaw::new(target, gain, rate_gain).map_err(mechanics)?;
        let law = match torque_limit {
            Some(limit) => law.with_limit(limit).map_err(|_| {
                invalid(format!(
                    "torque_limit must be positive (the actuator's largest torque, N·m), got \
                     {limit}"
                ))
            })?,
            None => law,
        };
        Ok(Self { law })
    }

    /// `K`.
    #[getter]
    fn gain(&self) -> f64 {
        self.law.gain()
    }

    /// `C`.
    #[getter]
    fn rate_gain(&self) -> f64 {
        self.law.rate_gain()
    }

    /// The target attitude, `(3, 3)`.
    #[getter]
    fn target<'py>(&self, py: Python<'py>) -> Matrix<'py> {
        matrix_array(py, self.law.target().matrix())
    }

    /// `L`, `None` without a limit.
    #[getter]
    fn torque_limit(&self) -> Option<f64> {
        Some(self.law.limit()).filter(|l| l.is_finite())
    }

    /// The pointing error `|θ|` of `state` from the target, radians.
    fn error(&self, state: PyRef<'_, State>) -> f64 {
        self.law
            .error_angle(&SO3::from_matrix_unchecked(state.sample.attitude))
    }

    /// The input for `state`, as `Integrator.set_input` takes it: the torque (3 entries)
    /// for a body on SO(3), the torque and a zero force (6) for a body in space.
    fn input<'py>(
        &self,
        py: Python<'py>,
        state: PyRef<'py, State>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let sample = &state.sample;
        if sample.wheel_speeds.is_some() {
            return Err(invalid(
                "state: a gyrostat turns by its wheels' motor torques, not by a body torque",
            ));
        }
        let attitude = SO3::from_matrix_unchecked(sample.attitude);
        let torque = self.law.torque(&attitude, &sample.omega);
        let mut u: Vec<f64> = torque.iter().copied().collect();
        if sample.position.is_some() {
            u.extend([0.0; 3]);
        }
        Ok(PyArray1::from_vec(py, u))
    }

    fn __repr__(&self) -> String {
        let mut s = format!(
            "PdLaw(gain={:?}, rate_gain={:?}",
            self.law.gain(),
            self.law.rate_gain()
        );
        if *self.law.target() != SO3::identity() {
            s += &format!(", target={:?}", rows(self.law.target().matrix()));
        }
        if self.law.limit().is_finite() {
            s += &format!(", torque_limit={:?}", self.law.limit());
        }
        s + ")"
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PdLaw>()
            .is_ok_and(|other| other.get().law == self.law)
    }

    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, pyo3::types::PyTuple>)> {
        let py = slf.py();
        let law = &slf.get().law;
        let limit = Some(law.limit()).filter(|l| l.is_finite());
        let args = (
            law.gain(),
            law.rate_gain(),
            matrix_array(py, law.target().matrix()),
            limit,
        )
            .into_pyobject(py)?;
        Ok((slf.get_type().into_any(), args))
    }
}

/// A matrix's rows, for a repr.
fn rows(m: &nalgebra::Matrix3<f64>) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}

/// A feedforward of `D` entries (zero when not given).
fn fixed<const D: usize>(u: Option<Vec<f64>>) -> PyResult<SVector<f64, D>> {
    match u {
        None => Ok(SVector::zeros()),
        Some(v) if v.len() == D => Ok(SVector::<f64, D>::from_column_slice(&v)),
        Some(v) => Err(invalid(format!(
            "feedforward must have {D} entries (the input's), got {}",
            v.len()
        ))),
    }
}

/// Registers the control functions (the Python layer's `lgsvi.control` re-exports them).
pub fn register(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add_function(wrap_pyfunction!(dlqr, module)?)?;
    module.add_function(wrap_pyfunction!(dare, module)?)?;
    module.add_function(wrap_pyfunction!(tvlqr, module)?)?;
    module.add_function(wrap_pyfunction!(error_state, module)?)?;
    module.add_class::<Regulator>()?;
    module.add_class::<PdLaw>()?;
    Ok(())
}
