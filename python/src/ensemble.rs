//! `lgsvi.run_ensemble`: many initial conditions of one system run in parallel (rayon,
//! the GIL released), each member's failure reported beside the others' results.

use crate::convert::{array1, array2, array3, rotations, rows3, vectors3};
use crate::errors::{guarded, invalid, mechanics};
use crate::run::{chart_named, each_run, in_pool, matching_named, start_refusal, Options, Run};
use crate::state::{Element, Sample, Start};
use crate::systems::system_of;
use lgsvi_lie::ChartKind;
use lgsvi_mechanics::ensemble::{run_ensemble_until, InitialCondition};
use lgsvi_mechanics::group::GroupChart;
use lgsvi_mechanics::system::ElementOf;
use lgsvi_mechanics::{Integrator, MechanicsError, System};
use nalgebra::Vector3;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The members' final states (or errors) of one system from `starts`.
fn members<S, const D: usize>(
    it: &Integrator<S, ChartKind, D>,
    starts: &[Start],
    t_end: f64,
) -> PyResult<Vec<Result<Sample, MechanicsError>>>
where
    S: System<D> + Clone + Send + Sync,
    ElementOf<S, D>: Element<D> + Send + Sync,
    ChartKind: GroupChart<S::Group, D>,
{
    let initial = starts
        .iter()
        .map(|s| {
            let (configuration, velocity) = Element::from_start(s)?;
            Ok(InitialCondition {
                configuration,
                velocity,
            })
        })
        .collect::<PyResult<Vec<_>>>()?;
    let system = it.system().clone();
    let results = run_ensemble_until(&system, it.settings(), &initial, t_end);
    Ok(results
        .into_iter()
        .map(|r| {
            r.map(|member| {
                let s = member.state;
                let energy = s.momentum.dot(&s.velocity)
                    - system.lagrangian(s.time, &s.configuration, &s.velocity);
                Element::sample(&s, energy)
            })
        })
        .collect())
}

/// Runs many initial conditions of one system to `t_end` in parallel and returns their
/// final states as arrays.
///
/// Parameters
/// ----------
/// system : a system
/// h, nodes : float, int
///     The step and the nodes per step (as `Integrator`).
/// attitudes : array_like (M, 3, 3)
///     The members' initial attitudes.
/// omegas : array_like (M, 3)
///     Their initial body angular velocities.
/// t_end : float
///     The end time (each member from t = 0; steps of `h`, the last shortened).
/// positions, velocities : array_like (M, 3), optional
///     Bodies in space: their centres of mass and velocities, world frame.
/// wheel_speeds : array_like (M, K), optional
///     A gyrostat's wheel rates.
/// chart, matching : str
///     As `Integrator`.
/// threads : int, optional
///     The number of threads (default: rayon's, one per core).
///
/// Returns a dict: `t` (M,), `attitude` (M, 3, 3), `omega` (M, 3), `momentum`,
/// `spatial_momentum`, `energy`, `position`/`velocity` (M, 3) for bodies in space,
/// `wheel_speeds`/`wheel_angles` for a gyrostat, `ok` (M,) bool, and `errors`: a dict from
/// each failed member's index to its exception (not raised: the other members' results
/// stand; a failed member's entries are NaN). The Python layer wraps it in an
/// `EnsembleResult`.
#[pyfunction]
#[pyo3(signature = (system, h, nodes, attitudes, omegas, t_end, positions=None, velocities=None, wheel_speeds=None, chart="exp", matching="exact", threads=None))]
#[allow(clippy::too_many_arguments)]
fn _run_ensemble<'py>(
    py: Python<'py>,
    system: &Bound<'py, PyAny>,
    h: f64,
    nodes: usize,
    attitudes: &Bound<'py, PyAny>,
    omegas: &Bound<'py, PyAny>,
    t_end: f64,
    positions: Option<&Bound<'py, PyAny>>,
    velocities: Option<&Bound<'py, PyAny>>,
    wheel_speeds: Option<&Bound<'py, PyAny>>,
    chart: &str,
    matching: &str,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (spec, built) = system_of(system)?;
    let attitudes = rotations(attitudes, "attitudes")?;
    let omegas = vectors3(omegas, "omegas")?;
    let m = attitudes.len();
    let same = |len: usize, name: &str| {
        if len == m {
            Ok(())
        } else {
            Err(invalid(format!(
                "{name} has {len} members and attitudes {m}: one entry per member"
            )))
        }
    };
    same(omegas.len(), "omegas")?;
    let space = spec.in_space();
    for (given, name) in [(positions, "positions"), (velocities, "velocities")] {
        if given.is_some() && !space {
            return Err(invalid(format!(
                "{name} applies to a body in space (FreeBody, OrbitingBody), not to a {}",
                spec.name()
            )));
        }
    }
    let positions = positions.map(|p| vectors3(p, "positions")).transpose()?;
    let velocities = velocities.map(|v| vectors3(v, "velocities")).transpose()?;
    if let Some(p) = &positions {
        same(p.len(), "positions")?;
    }
    if let Some(v) = &velocities {
        same(v.len(), "velocities")?;
    }
    let k = spec.wheels();
    let speeds: Option<Vec<Vec<f64>>> = match wheel_speeds {
        None => None,
        Some(_) if k == 0 => {
            return Err(invalid(format!(
                "wheel_speeds applies to a Gyrostat, not to a {}",
                spec.name()
            )))
        }
        Some(s) => {
            let flat = crate::convert::values(s, "wheel_speeds", &[m, k])?;
            Some(flat.chunks(k).map(<[f64]>::to_vec).collect())
        }
    };
    if !(t_end.is_finite() && t_end >= 0.0) {
        return Err(invalid(format!(
            "t_end must be finite and non-negative, got {t_end}"
        )));
    }
    if threads == Some(0) {
        return Err(invalid("threads must be at least 1"));
    }
    let starts: Vec<Start> = (0..m)
        .map(|i| Start {
            t: 0.0,
            attitude: attitudes[i],
            omega: omegas[i],
            position: positions.as_ref().map_or(Vector3::zeros(), |p| p[i]),
            velocity: velocities.as_ref().map_or(Vector3::zeros(), |v| v[i]),
            wheel_speeds: speeds.as_ref().map_or(vec![0.0; k], |s| s[i].clone()),
            wheel_angles: vec![0.0; k],
        })
        .collect();
    let options = Options {
        h,
        nodes,
        chart: chart_named(chart)?,
        matching: matching_named(matching)?,
        quadrature_points: None,
        max_newton_iterations: None,
    };
    // An integrator of the system from the first member (or at rest): the settings and the
    // system checked once, up front.
    let first = starts.first().cloned().unwrap_or_else(|| Start {
        t: 0.0,
        attitude: lgsvi_lie::SO3::identity(),
        omega: Vector3::zeros(),
        position: Vector3::zeros(),
        velocity: Vector3::zeros(),
        wheel_speeds: vec![0.0; k],
        wheel_angles: vec![0.0; k],
    });
    for (i, start) in starts.iter().enumerate() {
        if let Some(error) = start_refusal(&built, start) {
            return Err(invalid(format!("member {i}: {error}")));
        }
    }
    let probe = Run::new(built, &options, &first)?;
    let results = py.detach(|| {
        guarded(|| {
            let work = || each_run!(&probe, it => members(it, &starts, t_end));
            in_pool(threads, work)
        })
    })?;
    result_dict(py, results, space, k)
}

fn result_dict<'py>(
    py: Python<'py>,
    results: Vec<Result<Sample, MechanicsError>>,
    space: bool,
    k: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let m = results.len();
    let nan3 = [f64::NAN; 3];
    let errors = PyDict::new(py);
    let mut ok = Vec::with_capacity(m);
    let (mut t, mut r, mut w, mut mu, mut pi, mut e) =
        (vec![], vec![], vec![], vec![], vec![], vec![]);
    let (mut x, mut v, mut speeds, mut angles) = (vec![], vec![], vec![], vec![]);
    let width = match (space, k) {
        (true, _) => 6,
        (false, 0) => 3,
        (false, k) => 3 + k,
    };
    for (i, result) in results.into_iter().enumerate() {
        match result {
            Ok(s) => {
                ok.push(true);
                t.push(s.t);
                r.extend(rows3(&s.attitude));
                w.extend_from_slice(s.omega.as_slice());
                mu.extend_from_slice(&s.momentum);
                pi.extend_from_slice(s.spatial_momentum.as_slice());
                e.push(s.energy);
                x.extend_from_slice(s.position.unwrap_or_default().as_slice());
                v.extend_from_slice(s.velocity.unwrap_or_default().as_slice());
                speeds.extend_from_slice(&s.wheel_speeds.map_or_else(Vec::new, |w| w.to_vec()));
                angles.extend_from_slice(&s.wheel_angles.map_or_else(Vec::new, |w| w.to_vec()));
            }
            Err(error) => {
                ok.push(false);
                t.push(f64::NAN);
                r.extend([f64::NAN; 9]);
                w.extend(nan3);
                mu.extend(vec![f64::NAN; width]);
                pi.extend(nan3);
                e.push(f64::NAN);
                x.extend(nan3);
                v.extend(nan3);
                speeds.extend(vec![f64::NAN; k]);
                angles.extend(vec![f64::NAN; k]);
                errors.set_item(i, mechanics(error).value(py))?;
            }
        }
    }
    let d = PyDict::new(py);
    d.set_item("t", array1(py, t))?;
    d.set_item("attitude", array3(py, (m, 3, 3), r))?;
    d.set_item("omega", array2(py, m, 3, w))?;
    d.set_item("momentum", array2(py, m, width, mu))?;
    d.set_item("spatial_momentum", array2(py, m, 3, pi))?;
    d.set_item("energy", array1(py, e))?;
    if space {
        d.set_item("position", array2(py, m, 3, x))?;
        d.set_item("velocity", array2(py, m, 3, v))?;
    }
    if k > 0 {
        d.set_item("wheel_speeds", array2(py, m, k, speeds))?;
        d.set_item("wheel_angles", array2(py, m, k, angles))?;
    }
    d.set_item("ok", numpy::PyArray1::from_vec(py, ok))?;
    d.set_item("errors", errors)?;
    Ok(d)
}

/// Registers the ensemble function (the Python layer's `lgsvi.run_ensemble` wraps it).
pub fn register(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add_function(wrap_pyfunction!(_run_ensemble, module)?)?;
    Ok(())
}
