//! Python bindings of lgsvi: the compiled module `lgsvi._lgsvi` behind the `lgsvi` package
//! (`python/python/lgsvi`). numpy arrays in and out; long calls release the GIL; every
//! error is an exception of one hierarchy (`errors`), a Rust panic included.
//!
//! | module | what it binds |
//! |---|---|
//! | `systems` | the built-in systems (`RigidBody`, `HeavyTop`, `FreeBody`, `OrbitingBody`, `Gyrostat`) |
//! | `integrator` | `Integrator` (stepping, runs to a horizon or a tolerance, linearisation, dense output) |
//! | `state`, `run` | states as plain numbers on every group; the runs and what they record |
//! | `control` | discrete LQR, finite-horizon LQR, the regulator |
//! | `ensemble` | many initial conditions in parallel |
//! | `montecarlo` | a chunk of a Monte Carlo dispersion run and its percentile envelope |
//! | `optimal` | a rigid body's minimum-energy slew |
//! | `foundations` | the quadrature rules, Chebyshev series, SO(3)/SE(3) and the charts on arrays |

use pyo3::prelude::*;

mod control;
mod convert;
mod ensemble;
mod errors;
mod foundations;
mod integrator;
mod montecarlo;
mod optimal;
mod run;
mod state;
mod systems;

/// lgsvi's compiled core: Lie group spectral variational integrators for rotating and
/// moving bodies. Import `lgsvi`, not this module.
#[pymodule]
#[pyo3(name = "_lgsvi")]
fn lgsvi_module(module: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(module)?;
    systems::register(module)?;
    module.add_class::<state::State>()?;
    module.add_class::<integrator::Integrator>()?;
    module.add_class::<integrator::Curve>()?;
    module.add_function(wrap_pyfunction!(state::_state_from_fields, module)?)?;
    module.add_function(wrap_pyfunction!(
        integrator::_integrator_from_parts,
        module
    )?)?;
    control::register(module)?;
    ensemble::register(module)?;
    montecarlo::register(module)?;
    optimal::register(module)?;
    foundations::register(module)?;
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
