//! `lgsvi.optimal`'s compiled core: the slew of a rigid body, a heavy top or a spacecraft
//! by its reaction wheels at the least energy or in the least time
//! ([`lgsvi_optimal::Slew`]), and a body in space's manoeuvre at the least energy or in
//! the least time ([`lgsvi_optimal::Manoeuvre`]), solved with the GIL released.

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
#[pyo3(signature = (inertia, t_end, attitude_final, attitude0=None, omega0=None, omega_final=None, steps=40, nodes=10, torque_max=None, tolerance=1e-10, max_iterations=100, warm_start=None, cost="energy", inputs="constant", track=None, terminal_cost=None, gravity=None, mass=1.0, com=None, gravity_direction=None, wheels=None, wheel_inertia=None, wheel_speeds0=None, disturbance=None))]
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
    disturbance: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let shape = input_shape(inputs)?;
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
    let bound = torque_max.map(|b| bound3(b, "torque_max")).transpose()?;
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
    if let Some(torque) = disturbance {
        let d = vector3(torque, "disturbance")?;
        slew = slew.disturbance([d.x, d.y, d.z]);
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
    Common {
        cost: solution.cost,
        t_end: solution.t_end,
        h: solution.h,
        converged: solution.converged,
        statistics: &solution.statistics,
        multipliers: &solution.multipliers,
        times: solution.states.iter().map(|s| s.time).collect(),
        inputs: &solution.inputs,
        inputs_at_points: &solution.inputs_at_points,
        quadrature_nodes: &solution.quadrature_nodes,
    }
    .set(&d)?;
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

/// Solves a manoeuvre of a body in space; the Python layer's `lgsvi.optimal.manoeuvre`
/// wraps it (its documentation).
#[pyfunction]
#[pyo3(signature = (inertia, mass, t_end, attitude_final=None, position_final=None, attitude0=None, position0=None, omega0=None, velocity0=None, omega_final=None, velocity_final=None, mu=None, steps=40, nodes=10, torque_max=None, force_max=None, tolerance=1e-10, max_iterations=500, warm_start=None, inputs="constant", track=None, terminal_cost=None, cost="energy", disturbance=None, disturbance_force=None))]
#[allow(clippy::too_many_arguments)]
#[allow(clippy::type_complexity)] // the tracking tuple mirrors the Python argument
fn _manoeuvre<'py>(
    py: Python<'py>,
    inertia: &Bound<'py, PyAny>,
    mass: f64,
    t_end: Option<f64>,
    attitude_final: Option<&Bound<'py, PyAny>>,
    position_final: Option<&Bound<'py, PyAny>>,
    attitude0: Option<&Bound<'py, PyAny>>,
    position0: Option<&Bound<'py, PyAny>>,
    omega0: Option<&Bound<'py, PyAny>>,
    velocity0: Option<&Bound<'py, PyAny>>,
    omega_final: Option<&Bound<'py, PyAny>>,
    velocity_final: Option<&Bound<'py, PyAny>>,
    mu: Option<f64>,
    steps: usize,
    nodes: usize,
    torque_max: Option<&Bound<'py, PyAny>>,
    force_max: Option<&Bound<'py, PyAny>>,
    tolerance: f64,
    max_iterations: usize,
    warm_start: Option<&Bound<'py, PyAny>>,
    inputs: &str,
    track: Option<(
        Bound<'py, PyAny>,
        Bound<'py, PyAny>,
        Bound<'py, PyAny>,
        Bound<'py, PyAny>,
        [f64; 4],
    )>,
    terminal_cost: Option<[f64; 4]>,
    cost: &str,
    disturbance: Option<&Bound<'py, PyAny>>,
    disturbance_force: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    use lgsvi_mechanics::built_in::BuiltInSe3;
    use lgsvi_mechanics::lie::{SE3, SO3};
    use nalgebra::Vector6;
    let shape = input_shape(inputs)?;
    let cost = match cost {
        "energy" => Cost::Energy,
        "time" => Cost::Time,
        other => {
            return Err(invalid(format!(
                "cost = {other:?}: \"energy\" (the integral of |tau|^2 + |f|^2 in the time \
                 t_end) or \"time\" (the least final time, torque_max and force_max needed)"
            )))
        }
    };
    let moments = vector3(inertia, "inertia")?;
    let inertia = Inertia::from_principal_moments([moments.x, moments.y, moments.z])
        .map_err(|e| invalid(format!("inertia: {e}")))?;
    let vector_or =
        |v: Option<&Bound<'py, PyAny>>, name, default| v.map_or(Ok(default), |v| vector3(v, name));
    let attitude0 = attitude0.map_or(Ok(SO3::identity()), |r| rotation(r, "attitude0"))?;
    let attitude_final = attitude_final.map_or(Ok(attitude0), |r| rotation(r, "attitude_final"))?;
    let position0 = vector_or(position0, "position0", Vector3::zeros())?;
    let position_final = vector_or(position_final, "position_final", position0)?;
    let body: BuiltInSe3 = match mu {
        None => lgsvi_mechanics::FreeBody::new(inertia, mass)
            .map_err(mechanics)?
            .into(),
        Some(mu) => {
            let body = lgsvi_mechanics::OrbitingBody::new(inertia, mass, mu).map_err(mechanics)?;
            for (name, position) in [("position0", position0), ("position_final", position_final)] {
                body.check_position(&position)
                    .map_err(|e| invalid(format!("{name}: {e}")))?;
            }
            body.into()
        }
    };
    // The body velocity (Ω, v), v = Rᵀ ẋ, from the world-frame ẋ given.
    let body_velocity = |attitude: &SO3, omega: Vector3<f64>, velocity: Vector3<f64>| {
        let v = attitude.matrix().transpose() * velocity;
        Vector6::new(omega.x, omega.y, omega.z, v.x, v.y, v.z)
    };
    let start = body_velocity(
        &attitude0,
        vector_or(omega0, "omega0", Vector3::zeros())?,
        vector_or(velocity0, "velocity0", Vector3::zeros())?,
    );
    let target = body_velocity(
        &attitude_final,
        vector_or(omega_final, "omega_final", Vector3::zeros())?,
        vector_or(velocity_final, "velocity_final", Vector3::zeros())?,
    );
    let (start, target) = (
        (SE3::new(attitude0, position0), start),
        (SE3::new(attitude_final, position_final), target),
    );
    let torque_max = torque_max.map(|b| bound3(b, "torque_max")).transpose()?;
    let force_max = force_max.map(|b| bound3(b, "force_max")).transpose()?;
    let t_end = match (t_end, cost) {
        (Some(t), _) => t,
        // The least time's first guess; where it has none (a bound missing or refused, the
        // target being the start) the solver's check names the setting.
        (None, Cost::Time) => lgsvi_optimal::separate_bang_bang_time(
            &inertia,
            mass,
            &start,
            &target,
            torque_max.map_or([0.0; 3], Into::into),
            force_max.map_or([0.0; 3], Into::into),
        )
        .unwrap_or(1.0),
        (None, _) => {
            return Err(invalid(
                "t_end: a minimum-energy manoeuvre takes a fixed duration in seconds".to_string(),
            ))
        }
    };
    let mut manoeuvre = lgsvi_optimal::Manoeuvre::new(body, t_end)
        .from(start.0, start.1)
        .to(target.0, target.1)
        .steps(steps)
        .nodes(nodes)
        .tolerance(tolerance)
        .max_iterations(max_iterations)
        .cost(cost)
        .inputs(shape);
    if let Some(bound) = torque_max {
        manoeuvre = manoeuvre.torque_max(bound.into());
    }
    if let Some(bound) = force_max {
        manoeuvre = manoeuvre.force_max(bound.into());
    }
    if disturbance.is_some() || disturbance_force.is_some() {
        let part = |v: Option<&Bound<'py, PyAny>>, name| {
            v.map_or(Ok(Vector3::zeros()), |v| vector3(v, name))
        };
        let torque = part(disturbance, "disturbance")?;
        let force = part(disturbance_force, "disturbance_force")?;
        manoeuvre = manoeuvre.disturbance(torque.into(), force.into());
    }
    if let Some(initial) = warm_start {
        let rows = crate::convert::matrix(initial, "warm_start")?;
        if rows.ncols() != 6 {
            return Err(invalid(format!(
                "warm_start must have shape (M, 6), got ({}, {})",
                rows.nrows(),
                rows.ncols()
            )));
        }
        manoeuvre = manoeuvre.warm_start(
            rows.row_iter()
                .map(|r| Vector6::from_iterator(r.iter().copied()))
                .collect(),
        );
    }
    if let Some((attitudes, positions, omegas, velocities, weights)) = track {
        let attitudes = crate::convert::rotations(&attitudes, "track attitudes")?;
        let positions = vectors3(&positions, "track positions")?;
        let omegas = vectors3(&omegas, "track omegas")?;
        let velocities = vectors3(&velocities, "track velocities")?;
        let counts = [positions.len(), omegas.len(), velocities.len()];
        if counts.iter().any(|n| *n != attitudes.len()) {
            return Err(invalid(format!(
                "track: {} attitudes, {} positions, {} rates and {} velocities; one of each per \
                 step boundary after the start",
                attitudes.len(),
                counts[0],
                counts[1],
                counts[2]
            )));
        }
        let reference = attitudes
            .iter()
            .zip(&positions)
            .zip(omegas.iter().zip(&velocities))
            .map(|((r, x), (w, v))| (SE3::new(*r, *x), body_velocity(r, *w, *v)))
            .collect();
        manoeuvre = manoeuvre.track(reference, weights);
    }
    if let Some(weights) = terminal_cost {
        manoeuvre = manoeuvre.terminal_cost(weights);
    }
    let solution = py.detach(|| guarded(|| manoeuvre.solve().map_err(optimal_error)))?;
    let k = solution.inputs.len();
    let d = PyDict::new(py);
    Common {
        cost: solution.cost,
        t_end: solution.t_end,
        h: solution.h,
        converged: solution.converged,
        statistics: &solution.statistics,
        multipliers: &solution.multipliers,
        times: solution.states.iter().map(|s| s.time).collect(),
        inputs: &solution.inputs,
        inputs_at_points: &solution.inputs_at_points,
        quadrature_nodes: &solution.quadrature_nodes,
    }
    .set(&d)?;
    let states = &solution.states;
    d.set_item(
        "attitude",
        array3(
            py,
            (k + 1, 3, 3),
            states
                .iter()
                .flat_map(|s| rows3(s.attitude().matrix()))
                .collect(),
        ),
    )?;
    let triples = |f: &dyn Fn(&lgsvi_mechanics::State<SE3, 6>) -> Vector3<f64>| {
        array2(
            py,
            k + 1,
            3,
            states
                .iter()
                .flat_map(|s| f(s).iter().copied().collect::<Vec<_>>())
                .collect(),
        )
    };
    d.set_item("position", triples(&|s| s.position()))?;
    d.set_item("omega", triples(&|s| s.angular_velocity()))?;
    d.set_item("velocity", triples(&|s| s.linear_velocity()))?;
    Ok(d)
}

/// What a slew's and a manoeuvre's results share, inputs of `M` entries.
struct Common<'a, const M: usize> {
    cost: f64,
    t_end: f64,
    h: f64,
    converged: bool,
    statistics: &'a lgsvi_optimal::Statistics,
    multipliers: &'a [f64],
    times: Vec<f64>,
    inputs: &'a [nalgebra::SVector<f64, M>],
    inputs_at_points: &'a [Vec<nalgebra::SVector<f64, M>>],
    quadrature_nodes: &'a [f64],
}

impl<const M: usize> Common<'_, M> {
    /// Puts the fields into the result's dictionary.
    fn set(self, d: &Bound<'_, PyDict>) -> PyResult<()> {
        let py = d.py();
        d.set_item("cost", self.cost)?;
        d.set_item("t_end", self.t_end)?;
        d.set_item("h", self.h)?;
        d.set_item("converged", self.converged)?;
        d.set_item("iterations", self.statistics.iterations)?;
        d.set_item(
            "kkt_residuals",
            array1(py, self.statistics.kkt_residuals.clone()),
        )?;
        d.set_item("time_s", self.statistics.time_s)?;
        d.set_item("multipliers", array1(py, self.multipliers.to_vec()))?;
        d.set_item("t", array1(py, self.times))?;
        let flat = |u: &nalgebra::SVector<f64, M>| u.iter().copied().collect::<Vec<_>>();
        d.set_item(
            "inputs",
            array2(
                py,
                self.inputs.len(),
                M,
                self.inputs.iter().flat_map(flat).collect(),
            ),
        )?;
        d.set_item(
            "quadrature_nodes",
            array1(py, self.quadrature_nodes.to_vec()),
        )?;
        let points = if self.inputs_at_points.is_empty() {
            0
        } else {
            self.quadrature_nodes.len()
        };
        d.set_item(
            "inputs_at_points",
            array3(
                py,
                (self.inputs_at_points.len(), points, M),
                self.inputs_at_points
                    .iter()
                    .flatten()
                    .flat_map(flat)
                    .collect(),
            ),
        )?;
        Ok(())
    }
}

/// `"constant"` or `"polynomial"`.
fn input_shape(inputs: &str) -> PyResult<Inputs> {
    match inputs {
        "constant" => Ok(Inputs::Constant),
        "polynomial" => Ok(Inputs::Polynomial),
        other => Err(invalid(format!(
            "inputs = {other:?}: \"constant\" (held over each step) or \"polynomial\" \
             (given at each step's Gauss points)"
        ))),
    }
}

/// A bound for every axis (a number) or one per axis (three).
fn bound3(bound: &Bound<'_, PyAny>, name: &str) -> PyResult<Vector3<f64>> {
    match crate::convert::shape_of(bound, name)?.as_slice() {
        [] => {
            let u: f64 = bound.extract()?;
            Ok(Vector3::new(u, u, u))
        }
        _ => vector3(bound, name),
    }
}

/// Registers the slew and manoeuvre solvers and their exception.
pub fn register(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("InfeasibleError", module.py().get_type::<InfeasibleError>())?;
    module.add_function(wrap_pyfunction!(_slew, module)?)?;
    module.add_function(wrap_pyfunction!(_manoeuvre, module)?)?;
    Ok(())
}
