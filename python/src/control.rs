//! Control design on a step's exact linearisation: discrete LQR (Drake's
//! `DiscreteTimeLinearQuadraticRegulator` order and sign: `u = −K x`), the finite-horizon
//! recursion along a trajectory, the error state on the group, and the regulator.

use crate::convert::{from_matrix, matrix, vector};
use crate::errors::{guarded, invalid, mechanics};
use crate::state::{Sample, State};
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
    Ok(())
}
