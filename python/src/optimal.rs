//! `lgsvi.optimal`'s compiled core: the slew of a rigid body, a heavy top or a spacecraft
//! by its reaction wheels at the least energy or in the least time
//! ([`lgsvi_optimal::Slew`]), solved with the GIL released.

use crate::convert::{array1, array2, array3, rotation, rows3, vector3, vectors3};
use crate::errors::{guarded, invalid, mechanics, ConvergenceError, LgsviError};
use lgsvi_mechanics::lie::LieGroup;
use lgsvi_mechanics::Inertia;
use lgsvi_optimal::{Cost, Inputs, OptimalError, Slew};
use nalgebra::Vector3;
use pyo3::prelude::*;
use pyo3::types::PyDict;

pyo3::create_exception!(
    lgsvi._lgsvi,
    InfeasibleError,
    LgsviError,
    "No inputs within the bounds reach the target in the time: raise the bound or the time."
);

/// The exception for a solver's error.
fn optimal_error(error: OptimalError) -> PyErr {
    match error {
        // The solver's names of the wheels' settings, as this function's arguments.
        OptimalError::InvalidSetting { name, .. } => match name {
            "wheel axes" => invalid(format!("wheels: {error}")),
            "wheel inertia" => invalid(format!("wheel_inertia: {error}")),
            "inertia and wheel inertia" => invalid(format!("inertia and wheel_inertia: {error}")),
            "wheel speeds" => invalid(format!("wheel_speeds0: {error}")),
            _ => invalid(error.to_string()),
        },
        OptimalError::Infeasible { .. } => InfeasibleError::new_err(error.to_string()),
        OptimalError::NotConverged { .. } => ConvergenceError::new_err(error.to_string()),
        OptimalError::Mechanics(inner) => mechanics(inner),
        other => LgsviError::new_err(other.to_string()),
    }
}

/// Solves a slew; the Python layer's `lgsvi.optimal.slew` wraps it (its documentation).
#[pyfunction]
#[pyo3(signature = (inertia, t_end, attitude_final, attitude0=None, omega0=None, omega_final=None, steps=40, nodes=10, torque_max=None, tolerance=1e-10, max_iterations=100, warm_start=None, cost="energy", inputs="constant", track=None, terminal_cost=None, gravity=None, mass=1.0, com=None, gravity_direction=None, wheels=None, wheel_inertia=None, wheel_speeds0=None))]
#[allow(clippy::too_many_arguments)]
fn _slew<'py>(
    py: Python<'py>,
    inertia: &Bound<'py, PyAny>,
    t_end: Option<f64>,
    attitude_final: &Bound<'py, PyAny>,
    attitude0: Option<&Bound<'py, PyAny>>,
    omega0: Option<&Bound<'py, PyAny>>,
    omega_final: Option<&Bound<'py, PyAny>>,
    steps: usize,
    nodes: usize,
    torque_max: Option<&Bound<'py, PyAny>>,
    tolerance: f64,
    max_iterations: usize,
    warm_start: Option<&Bound<'py, PyAny>>,
    cost: &str,
    inputs: &str,
    track: Option<(Bound<'py, PyAny>, Bound<'py, PyAny>, [f64; 2])>,
    terminal_cost: Option<[f64; 2]>,
    gravity: Option<f64>,
    mass: f64,
    com: Option<&Bound<'py, PyAny>>,
    gravity_direction: Option<&Bound<'py, PyAny>>,
    wheels: Option<&Bound<'py, PyAny>>,
    wheel_inertia: Option<&Bound<'py, PyAny>>,
    wheel_speeds0: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let shape = match inputs {
        "constant" => Inputs::Constant,
        "polynomial" => Inputs::Polynomial,
        other => {
            return Err(invalid(format!(
                "inputs = {other:?}: \"constant\" (held over each step) or \"polynomial\" \
                 (given at each step's Gauss points)"
            )))
        }
    };
    let cost = match cost {
        "energy" => Cost::Energy,
        "time" => Cost::Time,
        other => {
            return Err(invalid(format!(
                "cost = {other:?}: \"energy\" (the integral of |u|^2 in the time t_end) or \
                 \"time\" (the least final time, torque_max needed)"
            )))
        }
    };
    let moments = vector3(inertia, "inertia")?;
    let inertia = Inertia::from_principal_moments([moments.x, moments.y, moments.z])
        .map_err(|e| invalid(format!("inertia: {e}")))?;
    let vector_or_zero =
        |v: Option<&Bound<'py, PyAny>>, name| v.map_or(Ok(Vector3::zeros()), |v| vector3(v, name));
    let start = match attitude0 {
        Some(r) => rotation(r, "attitude0")?,
        None => lgsvi_mechanics::lie::SO3::identity(),
    };
    let target = rotation(attitude_final, "attitude_final")?;
    let bound = match torque_max {
        Some(bound) => Some(
            match crate::convert::shape_of(bound, "torque_max")?.as_slice() {
                [] => {
                    let u: f64 = bound.extract()?;
                    Vector3::new(u, u, u)
                }
                _ => vector3(bound, "torque_max")?,
            },
        ),
        None => None,
    };
    let t_end = match (t_end, cost, bound) {
        (Some(t), _, _) => t,
        (None, Cost::Time, Some(b)) => {
            lgsvi_optimal::eigen_axis_time(&inertia, &start.inverse().compose(&target), b.into())
                .ok_or_else(|| {
                    invalid(
                        "attitude_final: the target attitude is the start's; give another \
                         target, or t_end as the first guess of the time"
                            .to_string(),
                    )
                })?
        }
        (None, Cost::Time, None) => {
            return Err(invalid(
                "torque_max: a minimum-time slew needs a torque bound".to_string(),
            ))
        }
        (None, _, _) => {
            return Err(invalid(
                "t_end: a minimum-energy slew takes a fixed duration in seconds".to_string(),
            ))
        }
    };
    let mut slew = Slew::new(inertia, t_end)
        .from(start, vector_or_zero(omega0, "omega0")?)
        .to(target, vector_or_zero(omega_final, "omega_final")?)
        .steps(steps)
        .nodes(nodes)
        .tolerance(tolerance)
        .max_iterations(max_iterations)
        .cost(cost)
        .inputs(shape);
    if let Some(bound) = bound {
        slew = slew.torque_max([bound.x, bound.y, bound.z]);
    }
    match gravity {
        Some(g) => {
            slew = slew.gravity(lgsvi_optimal::Gravity {
                mass,
                gravity: g,
                center_of_mass: com.map_or(Ok(Vector3::z()), |c| vector3(c, "com"))?,
                direction: gravity_direction
                    .map_or(Ok(Vector3::z()), |d| vector3(d, "gravity_direction"))?,
            })
        }
        None if com.is_some() || gravity_direction.is_some() || mass != 1.0 => {
            return Err(invalid(
                "mass, com and gravity_direction describe a heavy top: give gravity as well \
                 (or drop them for a free body)"
                    .to_string(),
            ))
        }
        None => {}
    }
    match wheels {
        Some(axes) => {
            let axes = vectors3(axes, "wheels")?;
            let [a, b, c] = axes.as_slice() else {
                return Err(invalid(format!(
                    "wheels: {} axes; give three wheel axes (body frame), one per row",
                    axes.len()
                )));
            };
            let inertia = match wheel_inertia {
                None => Vector3::repeat(0.05),
                Some(i) => match crate::convert::shape_of(i, "wheel_inertia")?.as_slice() {
                    [] => Vector3::repeat(i.extract::<f64>()?),
                    _ => vector3(i, "wheel_inertia")?,
                },
            };
            let wheels = lgsvi_optimal::Wheels {
                axes: [*a, *b, *c],
                inertia: [inertia.x, inertia.y, inertia.z],
                speeds: vector_or_zero(wheel_speeds0, "wheel_speeds0")?,
            };
            slew = slew.wheels(wheels);
        }
        None if wheel_inertia.is_some() || wheel_speeds0.is_some() => {
            return Err(invalid(
                "wheel_inertia and wheel_speeds0 describe reaction wheels: give wheels (their \
                 three axes) as well"
                    .to_string(),
            ))
        }
        None => {}
    }
    if let Some((attitudes, omegas, weights)) = track {
        let attitudes = crate::convert::rotations(&attitudes, "track attitudes")?;
        let omegas = vectors3(&omegas, "track omegas")?;
        if attitudes.len() != omegas.len() {
            return Err(invalid(format!(
                "track: {} attitudes and {} rates; one of each per step boundary after the start",
                attitudes.len(),
                omegas.len()
            )));
        }
        slew = slew.track(attitudes.into_iter().zip(omegas).collect(), weights);
    }
    if let Some(weights) = terminal_cost {
        slew = slew.terminal_cost(weights);
    }
    if let Some(inputs) = warm_start {
        slew = slew.warm_start(vectors3(inputs, "warm_start")?);
    }
    let solution = py.detach(|| guarded(|| slew.solve().map_err(optimal_error)))?;
    let k = solution.inputs.len();
    let d = PyDict::new(py);
    d.set_item("cost", solution.cost)?;
    d.set_item("t_end", solution.t_end)?;
    d.set_item("h", solution.h)?;
    d.set_item("converged", solution.converged)?;
    d.set_item("iterations", solution.statistics.iterations)?;
    d.set_item(
        "kkt_residuals",
        array1(py, solution.statistics.kkt_residuals.clone()),
    )?;
    d.set_item("time_s", solution.statistics.time_s)?;
    d.set_item("multipliers", array1(py, solution.multipliers.to_vec()))?;
    d.set_item(
        "t",
        array1(py, solution.states.iter().map(|s| s.time).collect()),
    )?;
    d.set_item(
        "inputs",
        array2(
            py,
            k,
            3,
            solution
                .inputs
                .iter()
                .flat_map(|u| [u.x, u.y, u.z])
                .collect(),
        ),
    )?;
    let points = solution.quadrature_nodes.len();
    d.set_item(
        "quadrature_nodes",
        array1(py, solution.quadrature_nodes.clone()),
    )?;
    d.set_item(
        "inputs_at_points",
        array3(
            py,
            (
                solution.inputs_at_points.len(),
                if solution.inputs_at_points.is_empty() {
                    0
                } else {
                    points
                },
                3,
            ),
            solution
                .inputs_at_points
                .iter()
                .flatten()
                .flat_map(|u| [u.x, u.y, u.z])
                .collect(),
        ),
    )?;
    d.set_item(
        "wheel_speeds",
        array2(
            py,
            solution.wheel_speeds.len(),
            3,
            solution
                .wheel_speeds
                .iter()
                .flat_map(|w| [w.x, w.y, w.z])
                .collect(),
        ),
    )?;
    d.set_item(
        "attitude",
        array3(
            py,
            (k + 1, 3, 3),
            solution
                .states
                .iter()
                .flat_map(|s| rows3(s.configuration.matrix()))
                .collect(),
        ),
    )?;
    d.set_item(
        "omega",
        array2(
            py,
            k + 1,
            3,
            solution
                .states
                .iter()
                .flat_map(|s| [s.velocity.x, s.velocity.y, s.velocity.z])
                .collect(),
        ),
    )?;
    Ok(d)
}

/// Registers the slew solver and its exception.
pub fn register(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("InfeasibleError", module.py().get_type::<InfeasibleError>())?;
    module.add_function(wrap_pyfunction!(_slew, module)?)?;
    Ok(())
}
