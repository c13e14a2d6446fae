//! One exception hierarchy for the library's errors, and the guard that turns a Rust panic
//! into one of them instead of a crash.
//!
//! ```text
//! LgsviError (Exception)
//! ├── InvalidInputError (also a ValueError): a bad argument, named
//! ├── ConvergenceError: Newton did not converge, or converged to a root that is not the motion
//! ├── ChartError: a step leaves the chart's domain (the body turns too far in one step)
//! ├── ToleranceError: a tolerance the run cannot meet, or its check failed
//! ├── ModelError: a state outside what the system models (a degenerate Lagrangian)
//! └── InternalError: a defect of lgsvi (a Rust panic), reported rather than crashing
//! ```
//!
//! Each message is the library's one-line cause and advice, as the command line prints it.

use lgsvi_lie::LieError;
use lgsvi_mechanics::MechanicsError;
use lgsvi_quadrature::QuadratureError;
use lgsvi_spectral::SpectralError;
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};

pyo3::create_exception!(
    lgsvi._lgsvi,
    LgsviError,
    PyException,
    "The base of every error lgsvi raises."
);
pyo3::create_exception!(
    lgsvi._lgsvi,
    ConvergenceError,
    LgsviError,
    "Newton's iteration did not converge within a step, or converged to a root that is not \
     the continuation of the motion: take a smaller step h or more nodes."
);
pyo3::create_exception!(
    lgsvi._lgsvi,
    ChartError,
    LgsviError,
    "A step leaves the chart's domain (the body turns further within one step than the \
     chart reaches): take a smaller step h, or the exp chart."
);
pyo3::create_exception!(
    lgsvi._lgsvi,
    ToleranceError,
    LgsviError,
    "A tolerance-driven run cannot meet its tolerance, or its check failed."
);
pyo3::create_exception!(
    lgsvi._lgsvi,
    ModelError,
    LgsviError,
    "The state lies outside what the system models (a Lagrangian that is not convex in the \
     velocity there, an orbiting body inside its attracting mass)."
);
pyo3::create_exception!(
    lgsvi._lgsvi,
    InternalError,
    LgsviError,
    "A defect of lgsvi (a Rust panic), raised instead of crashing the interpreter; please \
     report it with the call that raised it."
);

static INVALID_INPUT: PyOnceLock<Py<PyType>> = PyOnceLock::new();

/// `InvalidInputError(LgsviError, ValueError)`: made with `type()`, as an exception
/// declared in Rust has one base only.
pub fn invalid_input_type(py: Python<'_>) -> PyResult<&Bound<'_, PyType>> {
    INVALID_INPUT
        .get_or_try_init(py, || -> PyResult<Py<PyType>> {
            let bases = PyTuple::new(
                py,
                [py.get_type::<LgsviError>(), py.get_type::<PyValueError>()],
            )?;
            let namespace = PyDict::new(py);
            namespace.set_item("__module__", "lgsvi._lgsvi")?;
            namespace.set_item(
                "__doc__",
                "An argument lgsvi cannot take (a wrong shape, a NaN, a non-physical \
                 inertia, a matrix that is not a rotation): the message names the argument. \
                 Also a ValueError.",
            )?;
            let made = py
                .get_type::<PyType>()
                .call1(("InvalidInputError", bases, namespace))?;
            Ok(made.cast_into::<PyType>()?.unbind())
        })
        .map(|t| t.bind(py))
}

/// An [`invalid_input_type`] error with `message`.
pub fn invalid(message: impl Into<String>) -> PyErr {
    let message = message.into();
    Python::attach(|py| match invalid_input_type(py) {
        Ok(kind) => PyErr::from_type(kind.clone(), message),
        Err(error) => error,
    })
}

/// The exception for a library error: its kind by what went wrong, its message the
/// library's own.
pub fn mechanics(error: MechanicsError) -> PyErr {
    use MechanicsError as E;
    // The library's advice names the exp chart where it is the way out; here with the
    // Integrator's argument that takes it.
    let message = error
        .to_string()
        .replace("the exp chart,", "the exp chart (chart=\"exp\"),");
    match error {
        E::InvalidInertia { .. }
        | E::NonFinite { .. }
        | E::InvalidSetting { .. }
        | E::InvalidStart { .. }
        | E::NotOnGroup { .. } => invalid(message),
        E::NewtonDiverged { .. }
        | E::SingularJacobian { .. }
        | E::InverseLegendre { .. }
        | E::AliasedRoot { .. }
        | E::NonFiniteStep { .. } => ConvergenceError::new_err(message),
        E::StepTooLong { .. } | E::OutsideChart { .. } => ChartError::new_err(message),
        E::ToleranceNotMet { .. } | E::ToleranceNotChecked { .. } | E::CheckFailed { .. } => {
            ToleranceError::new_err(message)
        }
        E::DegenerateLagrangian { .. }
        | E::OutsideModel { .. }
        | E::LeftModel { .. }
        | E::IllConditioned { .. } => ModelError::new_err(message),
        E::Lie(_) => invalid(message),
        E::Quadrature(inner) => quadrature(inner),
        E::Spectral(inner) => spectral(inner),
        _ => LgsviError::new_err(message),
    }
}

/// The exception for a geometry error: every one is an input's fault.
pub fn lie(error: LieError) -> PyErr {
    invalid(error.to_string())
}

/// The exception for a quadrature error: a rule's eigenvalue iteration that did not
/// converge is a [`ConvergenceError`], the rest are inputs.
pub fn quadrature(error: QuadratureError) -> PyErr {
    match error {
        QuadratureError::EigenNotConverged { .. } => ConvergenceError::new_err(error.to_string()),
        _ => invalid(error.to_string()),
    }
}

/// The exception for a spectral error: a function its series does not resolve is a
/// [`ConvergenceError`], the rest are inputs.
pub fn spectral(error: SpectralError) -> PyErr {
    match error {
        SpectralError::NotResolved { .. } => ConvergenceError::new_err(error.to_string()),
        _ => invalid(error.to_string()),
    }
}

/// Runs `f`, turning a panic into an [`InternalError`] (the interpreter keeps running).
pub fn guarded<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(result) => result,
        Err(payload) => {
            let message = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic without a message".into());
            Err(InternalError::new_err(format!(
                "internal error (a Rust panic): {message}"
            )))
        }
    }
}

/// Panics inside the guard: the test suite's way to check that a panic becomes an
/// `InternalError` and leaves the interpreter running.
#[pyfunction]
pub fn _panic_for_tests() -> PyResult<()> {
    guarded(|| -> PyResult<()> { panic!("a panic raised on purpose by the test suite") })
}

/// Registers the exceptions in the module.
pub fn register(module: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = module.py();
    module.add("LgsviError", py.get_type::<LgsviError>())?;
    module.add("InvalidInputError", invalid_input_type(py)?)?;
    module.add("ConvergenceError", py.get_type::<ConvergenceError>())?;
    module.add("ChartError", py.get_type::<ChartError>())?;
    module.add("ToleranceError", py.get_type::<ToleranceError>())?;
    module.add("ModelError", py.get_type::<ModelError>())?;
    module.add("InternalError", py.get_type::<InternalError>())?;
    module.add_function(wrap_pyfunction!(_panic_for_tests, module)?)?;
    Ok(())
}
