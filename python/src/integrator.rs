//! `lgsvi.Integrator`: the integrator of a built-in system, stepped from Python (a control
//! loop) or run to a horizon (a trajectory of ndarrays), to a tolerance or with fixed
//! `(h, n)`, with its exact linearisation and dense output.

use crate::convert::{
    array1, array2, array3, from_matrix, rotation, rows3, stacked, vector, vector3,
};
use crate::errors::{guarded, invalid, mechanics, InternalError};
use crate::run::{
    chart_name, chart_named, coordinates_named, each_run, events_of, matching_name, matching_named,
    on_curve, run_to_tolerance, run_until, Linear, Options, Record, Recording, Run,
};
use crate::state::{quaternion, Sample, Small, Start, State};
use crate::systems::{system_of, Spec};
use lgsvi_lie::SO3;
use lgsvi_mechanics::events::Direction;
use lgsvi_mechanics::integrator::GalerkinCurve;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use std::sync::{Mutex, MutexGuard};

/// What an integrator holds behind its lock.
struct Inner {
    spec: Spec,
    options: Options,
    run: Run,
}

/// The Lie group spectral variational integrator of a system.
///
/// Parameters
/// ----------
/// system : RigidBody, HeavyTop, FreeBody, OrbitingBody or Gyrostat
/// h : float
///     The step (s).
/// nodes : int, optional
///     Chebyshev–Lobatto nodes per step `n` (degree `n − 1`; default 10).
/// attitude : array_like (3, 3), optional
///     `R₀ = world_from_body` (default the identity).
/// omega : array_like (3,), optional
///     Body angular velocity `Ω₀` (rad/s, default zero).
/// position, velocity : array_like (3,), optional
///     A body in space's centre of mass and its velocity, world frame.
/// wheel_speeds, wheel_angles : array_like (K,), optional
///     A gyrostat's wheel rates and angles relative to the body.
/// t0 : float, optional
///     The start time (default 0).
/// chart : {"exp", "cayley", "cayley-unscaled"}
///     The natural chart (exp reaches a full turn per step; the paper's unscaled Cayley map
///     reproduces its figures).
/// matching : {"exact", "paper"}
///     The momentum matching (exact: the map is exactly variational and conserves momenta).
/// quadrature_points : int, optional
///     Gauss points per step `m` (default `n`).
/// max_newton_iterations : int, optional
///     The cap on Newton iterations per step (default 40; a step that needs more raises
///     ConvergenceError).
///
/// The integrator is safe to use from several threads (a lock guards it; long calls
/// release the GIL) and pickles: an unpickled integrator continues from the same state,
/// its steps equal the original's bit for bit when pickled before its first step or
/// right after `reset`, and to rounding otherwise (the predictor and a reused Newton matrix
/// start afresh).
#[pyclass(module = "lgsvi._lgsvi", frozen)]
pub struct Integrator {
    system: Py<PyAny>,
    inner: Mutex<Inner>,
}

impl Integrator {
    fn lock(&self) -> PyResult<MutexGuard<'_, Inner>> {
        self.inner.lock().map_err(|_| {
            InternalError::new_err(
                "the integrator's lock was poisoned by an earlier internal error; build a new \
                 integrator",
            )
        })
    }
}

/// A start from the constructor's or `reset`'s arguments, defaults from `base`.
#[allow(clippy::too_many_arguments)]
fn start_from(
    spec: &Spec,
    base: &Start,
    t0: Option<f64>,
    attitude: Option<&Bound<'_, PyAny>>,
    omega: Option<&Bound<'_, PyAny>>,
    position: Option<&Bound<'_, PyAny>>,
    velocity: Option<&Bound<'_, PyAny>>,
    wheel_speeds: Option<&Bound<'_, PyAny>>,
    wheel_angles: Option<&Bound<'_, PyAny>>,
) -> PyResult<Start> {
    let mut start = base.clone();
    if let Some(t) = t0 {
        if !t.is_finite() {
            return Err(invalid(format!("t0 must be finite, got {t}")));
        }
        start.t = t;
    }
    if let Some(r) = attitude {
        start.attitude = rotation(r, "attitude")?;
    }
    if let Some(w) = omega {
        start.omega = vector3(w, "omega")?;
    }
    let space = spec.in_space();
    for (given, name) in [(position, "position"), (velocity, "velocity")] {
        if given.is_some() && !space {
            return Err(invalid(format!(
                "{name} applies to a body in space (FreeBody, OrbitingBody), not to a {}",
                spec.name()
            )));
        }
    }
    if let Some(x) = position {
        start.position = vector3(x, "position")?;
    }
    if let Some(v) = velocity {
        start.velocity = vector3(v, "velocity")?;
    }
    for (given, name) in [
        (wheel_speeds, "wheel_speeds"),
        (wheel_angles, "wheel_angles"),
    ] {
        if given.is_some() && spec.wheels() == 0 {
            return Err(invalid(format!(
                "{name} applies to a Gyrostat, not to a {}",
                spec.name()
            )));
        }
    }
    if let Some(s) = wheel_speeds {
        start.wheel_speeds = vector(s, "wheel_speeds")?;
    }
    if let Some(a) = wheel_angles {
        start.wheel_angles = vector(a, "wheel_angles")?;
    }
    Ok(start)
}

/// The start at rest at the identity.
fn rest(spec: &Spec) -> Start {
    Start {
        t: 0.0,
        attitude: SO3::identity(),
        omega: nalgebra::Vector3::zeros(),
        position: nalgebra::Vector3::zeros(),
        velocity: nalgebra::Vector3::zeros(),
        wheel_speeds: vec![0.0; spec.wheels()],
        wheel_angles: vec![0.0; spec.wheels()],
    }
}

/// The trajectory's arrays as a dict (the Python layer makes it a `Trajectory`): each
/// column filled in one pass over the states.
pub fn trajectory_dict<'py>(py: Python<'py>, recording: Recording) -> PyResult<Bound<'py, PyDict>> {
    let samples = &recording.samples;
    let n = samples.len();
    let first = samples.first();
    let width = first.map_or(3, |s| s.momentum.len());
    let space = first.is_some_and(|s| s.position.is_some());
    let k = first.and_then(|s| s.wheel_speeds.map(|w| w.len()));
    let mut t = Vec::with_capacity(n);
    let mut attitude = Vec::with_capacity(9 * n);
    let mut quaternions = Vec::with_capacity(4 * n);
    let mut omega = Vec::with_capacity(3 * n);
    let mut momentum = Vec::with_capacity(width * n);
    let mut energy = Vec::with_capacity(n);
    let mut spatial = Vec::with_capacity(3 * n);
    let columns = if space { 3 * n } else { 0 };
    let (mut position, mut velocity, mut linear) = (
        Vec::with_capacity(columns),
        Vec::with_capacity(columns),
        Vec::with_capacity(columns),
    );
    let wheel_columns = k.unwrap_or(0) * n;
    let (mut angles, mut speeds) = (
        Vec::with_capacity(wheel_columns),
        Vec::with_capacity(wheel_columns),
    );
    for s in samples {
        t.push(s.t);
        attitude.extend_from_slice(&rows3(&s.attitude));
        quaternions.extend_from_slice(&quaternion(&s.attitude));
        omega.extend_from_slice(s.omega.as_slice());
        momentum.extend_from_slice(&s.momentum);
        energy.push(s.energy);
        spatial.extend_from_slice(s.spatial_momentum.as_slice());
        if space {
            position.extend_from_slice(s.position.unwrap_or_default().as_slice());
            velocity.extend_from_slice(s.velocity.unwrap_or_default().as_slice());
            linear.extend_from_slice(s.linear_momentum.unwrap_or_default().as_slice());
        }
        if k.is_some() {
            angles.extend_from_slice(&s.wheel_angles.unwrap_or(Small::new([])));
            speeds.extend_from_slice(&s.wheel_speeds.unwrap_or(Small::new([])));
        }
    }
    let d = PyDict::new(py);
    d.set_item("t", array1(py, t))?;
    d.set_item("attitude", array3(py, (n, 3, 3), attitude))?;
    d.set_item("quaternion", array2(py, n, 4, quaternions))?;
    d.set_item("omega", array2(py, n, 3, omega))?;
    d.set_item("momentum", array2(py, n, width, momentum))?;
    d.set_item("energy", array1(py, energy))?;
    d.set_item("spatial_momentum", array2(py, n, 3, spatial))?;
    if space {
        d.set_item("position", array2(py, n, 3, position))?;
        d.set_item("velocity", array2(py, n, 3, velocity))?;
        d.set_item("linear_momentum", array2(py, n, 3, linear))?;
    }
    if let Some(k) = k {
        d.set_item("wheel_angles", array2(py, n, k, angles))?;
        d.set_item("wheel_speeds", array2(py, n, k, speeds))?;
    }
    d.set_item(
        "newton_iterations",
        numpy::PyArray1::from_vec(py, recording.iterations.iter().map(|&i| i as i64).collect()),
    )?;
    d.set_item("stats", stats_dict(py, &recording)?)?;
    let hits = PyList::empty(py);
    for hit in &recording.hits {
        let direction = match hit.direction {
            Direction::Rising => "rising",
            Direction::Falling => "falling",
            Direction::Either => "either",
        };
        hits.append((
            hit.event,
            hit.name.clone(),
            hit.sample.t,
            direction,
            State { sample: hit.sample },
        ))?;
    }
    d.set_item("events", hits)?;
    Ok(d)
}

fn stats_dict<'py>(py: Python<'py>, recording: &Recording) -> PyResult<Bound<'py, PyDict>> {
    let s = &recording.stats;
    let d = PyDict::new(py);
    d.set_item("steps", s.totals.steps)?;
    d.set_item("newton_iterations", s.totals.newton_iterations)?;
    d.set_item("max_newton_iterations", s.totals.max_newton_iterations)?;
    d.set_item("factorizations", s.totals.factorizations)?;
    d.set_item("rejected_steps", s.totals.rejected_steps)?;
    d.set_item("estimated_error", s.totals.estimated_error)?;
    d.set_item("work", s.totals.work)?;
    d.set_item("wall_time_s", s.wall_time_s)?;
    d.set_item("stopped_by_event", recording.stopped)?;
    let nodes = PyDict::new(py);
    for (n, steps) in &s.nodes {
        nodes.set_item(n, steps)?;
    }
    d.set_item("nodes_histogram", nodes)?;
    if let Some((report, tolerance)) = &s.check {
        let c = PyDict::new(py);
        c.set_item("tolerance", tolerance)?;
        c.set_item("difference", report.difference)?;
        c.set_item("largest_difference", report.largest.value)?;
        c.set_item("largest_at_time", report.largest.time)?;
        c.set_item("local_estimates_sum", report.local_sum)?;
        c.set_item("runs", report.attempts)?;
        c.set_item("share_tightened", report.tightened)?;
        d.set_item("check", c)?;
    }
    Ok(d)
}

/// Wraps a dict of arrays into the Python layer's `Trajectory`.
pub fn trajectory<'py>(py: Python<'py>, recording: Recording) -> PyResult<Bound<'py, PyAny>> {
    let d = trajectory_dict(py, recording)?;
    py.import("lgsvi._trajectory")?
        .getattr("Trajectory")?
        .call((), Some(&d))
}

#[pymethods]
impl Integrator {
    #[new]
    #[pyo3(signature = (system, h, nodes=10, attitude=None, omega=None, position=None, velocity=None, wheel_speeds=None, wheel_angles=None, t0=0.0, chart="exp", matching="exact", quadrature_points=None, max_newton_iterations=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        system: &Bound<'_, PyAny>,
        h: f64,
        nodes: usize,
        attitude: Option<&Bound<'_, PyAny>>,
        omega: Option<&Bound<'_, PyAny>>,
        position: Option<&Bound<'_, PyAny>>,
        velocity: Option<&Bound<'_, PyAny>>,
        wheel_speeds: Option<&Bound<'_, PyAny>>,
        wheel_angles: Option<&Bound<'_, PyAny>>,
        t0: f64,
        chart: &str,
        matching: &str,
        quadrature_points: Option<usize>,
        max_newton_iterations: Option<usize>,
    ) -> PyResult<Self> {
        guarded(|| {
            let (spec, built) = system_of(system)?;
            let options = Options {
                h,
                nodes,
                chart: chart_named(chart)?,
                matching: matching_named(matching)?,
                quadrature_points,
                max_newton_iterations,
            };
            let start = start_from(
                &spec,
                &rest(&spec),
                Some(t0),
                attitude,
                omega,
                position,
                velocity,
                wheel_speeds,
                wheel_angles,
            )?;
            let run = Run::new(built, &options, &start)?;
            Ok(Self {
                system: system.clone().unbind(),
                inner: Mutex::new(Inner { spec, options, run }),
            })
        })
    }

    /// The system.
    #[getter]
    fn system(&self, py: Python<'_>) -> Py<PyAny> {
        self.system.clone_ref(py)
    }

    /// The present state (a `State`).
    #[getter]
    fn state(&self) -> PyResult<State> {
        guarded(|| {
            Ok(State {
                sample: self.lock()?.run.sample(),
            })
        })
    }

    /// The present time.
    #[getter]
    fn t(&self) -> PyResult<f64> {
        guarded(|| Ok(self.lock()?.run.sample().t))
    }

    /// The settings: `h`, `nodes`, `quadrature_points`, `chart`, `matching`,
    /// `max_newton_iterations`.
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let o = self.lock()?.options;
        let d = PyDict::new(py);
        d.set_item("h", o.h)?;
        d.set_item("nodes", o.nodes)?;
        d.set_item("quadrature_points", o.quadrature_points.unwrap_or(o.nodes))?;
        d.set_item("chart", chart_name(o.chart))?;
        d.set_item("matching", matching_name(o.matching))?;
        d.set_item(
            "max_newton_iterations",
            o.settings()?.max_newton_iterations(),
        )?;
        Ok(d)
    }

    /// The integrator's statistics since it was built: `steps`, `newton_iterations`,
    /// `max_newton_iterations`, `factorizations`, `rejected_steps`; and since the start or
    /// the last `reset`: `estimated_error` (the sum of the steps' local error estimates, a
    /// model of the global error, not a bound) and `work` (the work of the forces and
    /// inputs, `E(t) − E(0)` to the method's accuracy).
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let t = self.lock()?.run.totals();
        let d = PyDict::new(py);
        d.set_item("steps", t.steps)?;
        d.set_item("newton_iterations", t.newton_iterations)?;
        d.set_item("max_newton_iterations", t.max_newton_iterations)?;
        d.set_item("factorizations", t.factorizations)?;
        d.set_item("rejected_steps", t.rejected_steps)?;
        d.set_item("estimated_error", t.estimated_error)?;
        d.set_item("work", t.work)?;
        Ok(d)
    }

    /// The control input in force (held over the following steps).
    #[getter]
    fn input<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
        Ok(array1(py, self.lock()?.run.input()))
    }

    /// Sets the control input, held constant over the following steps until set again: a
    /// body torque (3) on SO(3), a body wrench `(τ, f)` (6) on SE(3), the motor torques
    /// (K) or a body torque and them (3 + K) for a gyrostat.
    fn set_input(&self, u: &Bound<'_, PyAny>) -> PyResult<()> {
        guarded(|| {
            let u = vector(u, "u")?;
            self.lock()?.run.set_input(&u)
        })
    }

    /// The Gauss points of a step as fractions of its length, ``c_j`` in (0, 1): where
    /// :meth:`set_input_at_points` acts.
    #[getter]
    fn quadrature_nodes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
        Ok(array1(py, self.lock()?.run.quadrature().0))
    }

    /// The weights ``b_j`` of a step's quadrature (summing to 1):
    /// ``∫ f dt ≈ h Σ_j b_j f(c_j h)``.
    #[getter]
    fn quadrature_weights<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
        Ok(array1(py, self.lock()?.run.quadrature().1))
    }

    /// Sets the control input at each Gauss point of the following steps (``u`` of shape
    /// ``(m, d)``, ``m = len(quadrature_nodes)``): an input varying within a step, such as
    /// a polynomial given by its values at the points; :meth:`set_input` holds a constant
    /// again. Raises InvalidInputError for the wrong number of points or a non-finite
    /// entry.
    fn set_input_at_points(&self, u: &Bound<'_, PyAny>) -> PyResult<()> {
        guarded(|| {
            let shape = crate::convert::shape_of(u, "u")?;
            let [m, d] = shape.as_slice() else {
                return Err(crate::errors::invalid(format!(
                    "u: an (m, d) array, one input a Gauss point; got shape {shape:?}"
                )));
            };
            let values = crate::convert::values(u, "u", &[*m, *d])?;
            let rows: Vec<Vec<f64>> = values.chunks(*d).map(|r| r.to_vec()).collect();
            self.lock()?.run.set_input_at_points(&rows)
        })
    }

    /// Advances one step; returns its Newton iterations. Releases the GIL.
    ///
    /// Raises ConvergenceError, ChartError or ModelError, naming the step, when it fails
    /// (the state is then unchanged).
    fn step(&self, py: Python<'_>) -> PyResult<usize> {
        py.detach(|| guarded(|| self.lock()?.run.step().map_err(mechanics)))
    }

    /// Takes `steps` steps without recording them (the loop stays in Rust; the GIL is
    /// released).
    fn advance(&self, py: Python<'_>, steps: usize) -> PyResult<()> {
        py.detach(|| {
            guarded(|| {
                let mut inner = self.lock()?;
                for _ in 0..steps {
                    inner.run.step().map_err(mechanics)?;
                }
                Ok(())
            })
        })
    }

    /// Takes `steps` steps and returns the `Trajectory` of the start, every `every`-th
    /// state and the last.
    #[pyo3(signature = (steps, every=1))]
    fn run<'py>(&self, py: Python<'py>, steps: usize, every: usize) -> PyResult<Bound<'py, PyAny>> {
        let end = {
            let inner = self.lock()?;
            let (t, h) = (inner.run.sample().t, inner.options.h);
            t + steps as f64 * h
        };
        self.run_until(py, end, every, None, None, None, None)
    }

    /// Runs to exactly `t_end` and returns the `Trajectory`.
    ///
    /// Parameters
    /// ----------
    /// t_end : float
    ///     The end time (steps of `h`, the last shortened to land on it).
    /// every : int
    ///     Record the start, every `every`-th state and the last.
    /// tol : float, optional
    ///     Run to this tolerance instead, as `lgsvi simulate --tol` does: the step from the
    ///     initial motion (about 3 rad a step), the nodes per step from each step's own
    ///     error estimate, every step taken again beside a companion with two more nodes
    ///     whose difference is the run's measured error (`stats["estimated_error"]`,
    ///     `stats["check"]`); a run that misses is taken again with a tighter share per
    ///     step, and one that cannot meet the tolerance raises ToleranceError. The
    ///     integrator's own `h` and `nodes` are for fixed steps and are not used (`step`
    ///     imposes a step); afterwards the integrator continues from the run's end.
    /// step : float, optional
    ///     With `tol`, the step to take instead of the policy's.
    /// dense : array_like, optional
    ///     Record the states at these times instead (ascending, within the run), each on
    ///     its step's Galerkin curve (the polynomial dense output, of the method's
    ///     accuracy between the nodes).
    /// events : list of Event, optional
    ///     Zero crossings of functions of the state to locate on each step's curve (to a
    ///     few ulps of the curve's own crossing): the trajectory's `events` lists them, and
    ///     a terminal event stops the run after the step holding it (its last recorded
    ///     state is that step's end).
    ///
    /// Releases the GIL while it runs (an event's function takes it back for each call).
    #[pyo3(signature = (t_end, every=1, tol=None, step=None, dense=None, events=None))]
    #[allow(clippy::too_many_arguments)]
    fn run_until<'py>(
        &self,
        py: Python<'py>,
        t_end: f64,
        every: usize,
        tol: Option<f64>,
        step: Option<f64>,
        dense: Option<&Bound<'py, PyAny>>,
        events: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let events = events_of(events)?;
        let record = match dense {
            Some(times) => {
                let times = vector(times, "dense")?;
                if times.windows(2).any(|w| w[1] < w[0]) {
                    return Err(invalid("dense times must be in ascending order"));
                }
                Record::Dense(times)
            }
            None => {
                if every == 0 {
                    return Err(invalid("every must be at least 1"));
                }
                Record::Every(every)
            }
        };
        if let Some(tol) = tol {
            if !(tol.is_finite() && tol > 0.0) {
                return Err(invalid(format!(
                    "tol must be positive and finite, got {tol}"
                )));
            }
        } else if step.is_some() {
            return Err(invalid("step applies to a tolerance-driven run (tol=...)"));
        }
        let recording = py.detach(|| {
            guarded(|| {
                let mut inner = self.lock()?;
                let now = inner.run.sample().t;
                if !(t_end.is_finite() && t_end >= now) {
                    return Err(invalid(format!(
                        "t_end must be finite and not before the present time {now}, got {t_end}"
                    )));
                }
                if let Record::Dense(times) = &record {
                    if times.first().is_some_and(|&t| t < now)
                        || times.last().is_some_and(|&t| t > t_end)
                    {
                        return Err(invalid(format!(
                            "dense times must lie within the run [{now}, {t_end}]"
                        )));
                    }
                }
                let recording = match tol {
                    Some(tol) if t_end > now => each_run!(&mut inner.run, it => {
                        run_to_tolerance(it, t_end, tol, step, &record, &events)
                    }),
                    _ => each_run!(&mut inner.run, it => run_until(it, t_end, &record, &events)),
                };
                recording.map_err(PyErr::from)
            })
        })?;
        trajectory(py, recording)
    }

    /// The Rust library's own `run_until` on this integrator, its trajectory of states kept
    /// in Rust and dropped (returns the number of states): the benchmark's reference for
    /// what `run_until` adds (python/benches/bench.py).
    #[pyo3(signature = (t_end, every=1))]
    fn _library_run_until(&self, py: Python<'_>, t_end: f64, every: usize) -> PyResult<usize> {
        py.detach(|| {
            guarded(|| {
                let mut inner = self.lock()?;
                each_run!(&mut inner.run, it => {
                    lgsvi_mechanics::Stepper::run_until(it, t_end, every)
                        .map(|trajectory| trajectory.states.len())
                        .map_err(mechanics)
                })
            })
        })
    }

    /// Restarts from the given state (arguments as the constructor's; those not given keep
    /// their present values, `t0` the present time). The input and the statistics are
    /// kept; the predictor forgets the last step.
    #[pyo3(signature = (t0=None, attitude=None, omega=None, position=None, velocity=None, wheel_speeds=None, wheel_angles=None))]
    #[allow(clippy::too_many_arguments)]
    fn reset(
        &self,
        t0: Option<f64>,
        attitude: Option<&Bound<'_, PyAny>>,
        omega: Option<&Bound<'_, PyAny>>,
        position: Option<&Bound<'_, PyAny>>,
        velocity: Option<&Bound<'_, PyAny>>,
        wheel_speeds: Option<&Bound<'_, PyAny>>,
        wheel_angles: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        guarded(|| {
            let mut inner = self.lock()?;
            let base = Start::of(&inner.run.sample());
            let start = start_from(
                &inner.spec,
                &base,
                t0,
                attitude,
                omega,
                position,
                velocity,
                wheel_speeds,
                wheel_angles,
            )?;
            inner.run.reset(&start)
        })
    }

    /// The exact linearisation of the next step from the present state with the present
    /// input, without taking it: `(A, B)` with `x₊ ≈ A x + B u`.
    ///
    /// Coordinates (`coordinates="velocity"`): the state perturbation is `x = (θ, ω)`, with
    /// the attitude (and, on SE(3), the position) perturbed in the body frame,
    /// `g = ḡ exp(θ)` (on SO(3) `R = R̄ exp(θ̂)`), and the body velocity by `ξ = ξ̄ + ω`;
    /// `coordinates="momentum"` takes the body momentum `μ = μ̄ + δμ` instead. The input
    /// is the control input of `set_input` (or of `set_input_at_points`). With
    /// `parameters=True` it returns `(A, B, P, names)` with `P = ∂x₊/∂p` in the system's
    /// physical parameters `names` (the inertia tensor's entries, the mass, the wheels'
    /// inertias).
    ///
    /// With `points=True` two entries follow, about the step's Gauss points
    /// (`quadrature_nodes`, `m` of them): `B_points`, of shape `(m, 2d, d)`, the derivative
    /// `∂x₊/∂u_j` in the input at each point when the inputs were given per point
    /// (`set_input_at_points`; they sum to `B`), else None; and `configurations`, of shape
    /// `(m, d, 2d + k)`, `∂θ_j/∂(x, u)`: the configuration at point `j`, perturbed as
    /// `g_j exp(θ_j)` (body frame, as `θ₊`), against the start state and then the inputs
    /// (`k = d` for a held input, `k = m·d` for inputs at the points, point by point). What
    /// a cost or constraint on the motion within a step differentiates by.
    #[pyo3(signature = (coordinates="velocity", parameters=false, points=false))]
    fn linearize<'py>(
        &self,
        py: Python<'py>,
        coordinates: &str,
        parameters: bool,
        points: bool,
    ) -> PyResult<Bound<'py, PyTuple>> {
        self.linearised(py, coordinates, parameters, points, false)
    }

    /// Takes the next step and returns its exact linearisation, as `linearize`.
    #[pyo3(signature = (coordinates="velocity", parameters=false, points=false))]
    fn step_linearized<'py>(
        &self,
        py: Python<'py>,
        coordinates: &str,
        parameters: bool,
        points: bool,
    ) -> PyResult<Bound<'py, PyTuple>> {
        self.linearised(py, coordinates, parameters, points, true)
    }

    /// The last step's Galerkin curve (dense output), or None before the first step.
    fn curve(&self) -> PyResult<Option<Curve>> {
        guarded(|| {
            let inner = self.lock()?;
            Ok(match &inner.run {
                Run::So3(it) => it.last_curve().map(|c| AnyCurve::So3(c, *it.system())),
                Run::Se3(it) => it.last_curve().map(|c| AnyCurve::Se3(c, *it.system())),
                Run::W1(it) => it.last_curve().map(|c| AnyCurve::W1(c, *it.system())),
                Run::W2(it) => it.last_curve().map(|c| AnyCurve::W2(c, *it.system())),
                Run::W3(it) => it.last_curve().map(|c| AnyCurve::W3(c, *it.system())),
                Run::W4(it) => it.last_curve().map(|c| AnyCurve::W4(c, *it.system())),
            }
            .map(|curve| Curve { curve }))
        })
    }

    fn __repr__(&self) -> PyResult<String> {
        let inner = self.lock()?;
        let o = inner.options;
        Ok(format!(
            "Integrator({}, h={}, nodes={}, chart={:?}, matching={:?}, t={})",
            inner.spec.name(),
            o.h,
            o.nodes,
            chart_name(o.chart),
            matching_name(o.matching),
            inner.run.sample().t
        ))
    }

    /// Equal when the systems, settings, states and inputs are.
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> PyResult<bool> {
        let Ok(other) = other.cast::<Integrator>() else {
            return Ok(false);
        };
        let other = other.get();
        if std::ptr::eq(self, other) {
            return Ok(true);
        }
        let (a, b) = (self.lock()?, other.lock()?);
        Ok(a.spec == b.spec
            && a.options == b.options
            && a.run.sample() == b.run.sample()
            && a.run.input() == b.run.input())
    }

    /// Pickling: the system, the settings, the present state and input.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let py = slf.py();
        let this = slf.get();
        let inner = this.lock()?;
        let o = inner.options;
        let sample = inner.run.sample();
        let start = Start::of(&sample);
        let kwargs = PyDict::new(py);
        kwargs.set_item("h", o.h)?;
        kwargs.set_item("nodes", o.nodes)?;
        kwargs.set_item("t0", start.t)?;
        kwargs.set_item(
            "attitude",
            array2(py, 3, 3, rows3(start.attitude.matrix()).to_vec()),
        )?;
        kwargs.set_item("omega", array1(py, start.omega.as_slice().to_vec()))?;
        if inner.spec.in_space() {
            kwargs.set_item("position", array1(py, start.position.as_slice().to_vec()))?;
            kwargs.set_item("velocity", array1(py, start.velocity.as_slice().to_vec()))?;
        }
        if inner.spec.wheels() > 0 {
            kwargs.set_item("wheel_speeds", array1(py, start.wheel_speeds.clone()))?;
            kwargs.set_item("wheel_angles", array1(py, start.wheel_angles.clone()))?;
        }
        kwargs.set_item("chart", chart_name(o.chart))?;
        kwargs.set_item("matching", matching_name(o.matching))?;
        kwargs.set_item("quadrature_points", o.quadrature_points)?;
        kwargs.set_item("max_newton_iterations", o.max_newton_iterations)?;
        let input = array1(py, inner.run.input());
        let restore = py
            .import("lgsvi._lgsvi")?
            .getattr("_integrator_from_parts")?;
        let args = PyTuple::new(
            py,
            [
                this.system.bind(py).clone(),
                kwargs.into_any(),
                input.into_any(),
            ],
        )?;
        Ok((restore, args))
    }
}

impl Integrator {
    fn linearised<'py>(
        &self,
        py: Python<'py>,
        coordinates: &str,
        parameters: bool,
        points: bool,
        take_step: bool,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let coordinates = coordinates_named(coordinates)?;
        let linear = py.detach(|| {
            guarded(|| {
                let mut inner = self.lock()?;
                each_run!(&mut inner.run, it => {
                    let l = match (take_step, parameters) {
                        (false, false) => it.linearize(),
                        (false, true) => it.linearize_with_parameters(),
                        (true, false) => it.step_linearized(),
                        (true, true) => it.step_linearized_with_parameters(),
                    }
                    .map_err(mechanics)?;
                    Ok(Linear::of(&l, coordinates, points))
                })
            })
        })?;
        let mut items = vec![
            from_matrix(py, &linear.a).into_any(),
            from_matrix(py, &linear.b).into_any(),
        ];
        if let Some((p, names)) = linear.p {
            items.push(from_matrix(py, &p).into_any());
            items.push(names.into_pyobject(py)?.into_any());
        }
        if let Some(points) = linear.points {
            items.push(match points.b {
                Some(b) => stacked(py, &b).into_any(),
                None => py.None().into_bound(py),
            });
            items.push(stacked(py, &points.configurations).into_any());
        }
        PyTuple::new(py, items)
    }
}

/// Unpickles an [`Integrator`]: built from the system and settings at the pickled state,
/// with the pickled input.
#[pyfunction]
pub fn _integrator_from_parts<'py>(
    py: Python<'py>,
    system: &Bound<'py, PyAny>,
    kwargs: &Bound<'py, PyDict>,
    input: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let class = py.import("lgsvi._lgsvi")?.getattr("Integrator")?;
    let made = class.call((system,), Some(kwargs))?;
    made.cast::<Integrator>()?.get().set_input(input)?;
    Ok(made)
}

/// A step's Galerkin curve, with its system.
enum AnyCurve {
    So3(GalerkinCurve, crate::systems::So3System),
    Se3(
        GalerkinCurve<lgsvi_mechanics::group::RigidMotions, lgsvi_lie::ChartKind, 6>,
        crate::systems::Se3System,
    ),
    W1(
        GalerkinCurve<lgsvi_mechanics::gyrostat::BodyAndWheels<1>, lgsvi_lie::ChartKind, 4>,
        lgsvi_mechanics::gyrostat::Gyrostat<1>,
    ),
    W2(
        GalerkinCurve<lgsvi_mechanics::gyrostat::BodyAndWheels<2>, lgsvi_lie::ChartKind, 5>,
        lgsvi_mechanics::gyrostat::Gyrostat<2>,
    ),
    W3(
        GalerkinCurve<lgsvi_mechanics::gyrostat::BodyAndWheels<3>, lgsvi_lie::ChartKind, 6>,
        lgsvi_mechanics::gyrostat::Gyrostat<3>,
    ),
    W4(
        GalerkinCurve<lgsvi_mechanics::gyrostat::BodyAndWheels<4>, lgsvi_lie::ChartKind, 7>,
        lgsvi_mechanics::gyrostat::Gyrostat<4>,
    ),
}

/// A step's Galerkin curve `g(t) = g_k Φ(ξ(t))` (the dense output between its ends), from
/// `Integrator.curve()`. Call it at a time within the step for the `State` there.
///
/// Attributes
/// ----------
/// start : float
///     The step's start time.
/// h : float
///     Its length.
#[pyclass(module = "lgsvi._lgsvi", frozen)]
pub struct Curve {
    curve: AnyCurve,
}

macro_rules! each_curve {
    ($curve:expr, ($c:ident, $s:ident) => $body:expr) => {
        match $curve {
            AnyCurve::So3($c, $s) => $body,
            AnyCurve::Se3($c, $s) => $body,
            AnyCurve::W1($c, $s) => $body,
            AnyCurve::W2($c, $s) => $body,
            AnyCurve::W3($c, $s) => $body,
            AnyCurve::W4($c, $s) => $body,
        }
    };
}

#[pymethods]
impl Curve {
    /// The step's start time.
    #[getter]
    fn start(&self) -> f64 {
        each_curve!(&self.curve, (c, _s) => c.start())
    }

    /// The step's length.
    #[getter]
    fn h(&self) -> f64 {
        each_curve!(&self.curve, (c, _s) => c.step())
    }

    /// The state at time `t` (absolute, within the step).
    fn __call__(&self, t: f64) -> PyResult<State> {
        guarded(|| {
            let sample =
                each_curve!(&self.curve, (c, s) => on_curve(s, c, t)).map_err(mechanics)?;
            Ok(State { sample })
        })
    }

    /// The `Trajectory` at the times `t` (absolute, within the step).
    fn sample<'py>(&self, py: Python<'py>, t: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let times = vector(t, "t")?;
        let samples = guarded(|| {
            times
                .iter()
                .map(|&t| each_curve!(&self.curve, (c, s) => on_curve(s, c, t)).map_err(mechanics))
                .collect::<PyResult<Vec<Sample>>>()
        })?;
        let n = samples.len();
        trajectory(
            py,
            Recording {
                samples,
                iterations: vec![0; n],
                stats: Default::default(),
                hits: Vec::new(),
                stopped: false,
            },
        )
    }

    fn __repr__(&self) -> String {
        format!("Curve(start={}, h={})", self.start(), self.h())
    }
}
