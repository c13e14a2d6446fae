//! `lgsvi.montecarlo`'s compiled core: one chunk of a Monte Carlo run (members
//! `first..last` of a plan drawn by [`lgsvi_montecarlo::Plan`], run in parallel with the
//! GIL released) and the percentile envelope they add to ([`MonteCarloEnvelope`]), which
//! pickles and merges exactly, so that chunks run on a cluster's workers combine into the
//! run a single machine gives.

use crate::control::PdLaw;
use crate::convert::{array1, array2, array3, rotation, rows3, vector, vector3};
use crate::errors::{guarded, invalid, mechanics, ConvergenceError};
use crate::run::{chart_named, each_run, in_pool, matching_named, Options, Run};
use crate::state::Start;
use crate::systems::{system_of, Drive, InertiaInput, Spec};
use lgsvi_experiments::control::SampledLaw;
use lgsvi_experiments::record::{record_until, Columns};
use lgsvi_experiments::stop::{StopWhen, Watch};
use lgsvi_experiments::ExperimentError;
use lgsvi_mechanics::Inertia;
use lgsvi_montecarlo::statistics::{Envelope, RunEnd, Samples};
use lgsvi_montecarlo::{Body, Dispersions, Member, Plan};
use nalgebra::Vector3;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyTuple};
use rayon::prelude::*;

/// Members run between two additions to the envelope: their sampled states are held only
/// that long, so a chunk's memory does not grow with its members.
const BATCH: u64 = 256;

/// The nominal body of `spec` from `start`: the inertia, the body torque, the mass (of a
/// body in space, or of a heavy top that has one) and the wheels, which a plan disperses.
fn nominal_of(spec: &Spec, start: &Start) -> PyResult<Body> {
    let inertia = |input: &InertiaInput| input.inertia();
    let (inertia, torque, mass) = match spec {
        Spec::RigidBody { inertia: i, drive } => (inertia(i)?, drive.torque, None),
        Spec::HeavyTop {
            inertia: i,
            mass,
            drive,
            ..
        } => (inertia(i)?, drive.torque, Some(*mass).filter(|&m| m > 0.0)),
        Spec::FreeBody {
            inertia: i,
            mass,
            drive,
        }
        | Spec::OrbitingBody {
            inertia: i,
            mass,
            drive,
            ..
        } => (inertia(i)?, drive.torque, Some(*mass)),
        Spec::Gyrostat { inertia: j, .. } => (
            Inertia::from_tensor(*j).map_err(mechanics)?,
            Vector3::zeros(),
            None,
        ),
    };
    let mut body = Body::new(inertia, start.attitude, start.omega);
    body.torque = torque;
    body.mass = mass;
    if let Spec::Gyrostat {
        axes,
        wheel_inertias,
        ..
    } = spec
    {
        body.wheel_inertias = wheel_inertias.clone();
        body.wheel_axes = axes.clone();
    }
    Ok(body)
}

/// `spec` with a member's draws in place of the nominal's parameters: its inertia (as the
/// tensor `lgsvi montecarlo` hands simulate), torque, mass and wheels.
fn member_spec(spec: &Spec, body: &Body) -> Spec {
    let mut member = spec.clone();
    let tensor = body.inertia.matrix();
    match &mut member {
        Spec::RigidBody { inertia, drive } => {
            *inertia = InertiaInput::Tensor(tensor);
            drive.torque = body.torque;
        }
        Spec::HeavyTop {
            inertia,
            mass,
            drive,
            ..
        }
        | Spec::FreeBody {
            inertia,
            mass,
            drive,
        }
        | Spec::OrbitingBody {
            inertia,
            mass,
            drive,
            ..
        } => {
            *inertia = InertiaInput::Tensor(tensor);
            *mass = body.mass.unwrap_or(*mass);
            drive.torque = body.torque;
        }
        Spec::Gyrostat {
            inertia,
            axes,
            wheel_inertias,
        } => {
            *inertia = tensor;
            axes.clone_from(&body.wheel_axes);
            wheel_inertias.clone_from(&body.wheel_inertias);
        }
    }
    member
}

/// What a run needs beside the system: its start, settings, end, sampling, watched
/// conditions and constant input.
struct Setup {
    options: Options,
    t_end: f64,
    every: usize,
    watch: Watch,
    input: Option<Vec<f64>>,
    control: Option<SampledLaw>,
}

/// `spec`'s run from `start`, sampled every `every` steps and at its end, as `lgsvi
/// montecarlo` runs a member ([`record_until`]: the same steps, the same events).
fn run_sampled(
    spec: &Spec,
    start: &Start,
    setup: &Setup,
    watch: &Watch,
) -> Result<(Samples, RunEnd), PyErr> {
    let built = spec.build()?;
    let mut run = Run::new(built, &setup.options, start)?;
    if let Some(u) = &setup.input {
        run.set_input(u)?;
    }
    let recording = each_run!(&mut run, it => {
        record_until(it, setup.t_end, setup.every, watch, setup.control.as_ref(), &mut |_| {})
    })
    .map_err(experiment)?;
    Ok(Samples::of_recording(recording))
}

/// A run's error as the Python exception of its kind: the library's own, a state that
/// overflowed as a [`ConvergenceError`], the rest as invalid input.
fn experiment(error: ExperimentError) -> PyErr {
    match error {
        ExperimentError::Mechanics(e) => mechanics(e),
        e @ ExperimentError::Overflow { .. } => ConvergenceError::new_err(e.to_string()),
        other => invalid(other.to_string()),
    }
}

/// One member's draws and final state (or why it failed).
struct Outcome {
    member: Member,
    result: Result<(Samples, RunEnd), PyErr>,
}

/// Percentile envelopes over a Monte Carlo run's members: per channel (attitude departure
/// from the nominal run in degrees, the three body rates, the energy's relative change)
/// and sample time, a sketch whose quantiles are within 0.55% of the exact sample
/// percentiles. Envelopes of disjoint sets of members merge exactly (`merge`), in any
/// order; an envelope pickles.
#[pyclass(module = "lgsvi._lgsvi")]
#[derive(Debug, Clone)]
pub struct MonteCarloEnvelope {
    envelope: Envelope,
}

#[pymethods]
impl MonteCarloEnvelope {
    /// The channels' names.
    #[getter]
    fn channels(&self) -> Vec<String> {
        self.envelope.channels().to_vec()
    }

    /// The number of sample times.
    #[getter]
    fn samples(&self) -> usize {
        self.envelope.samples()
    }

    /// The members counted at the first sample time (those that finished).
    #[getter]
    fn members(&self) -> u64 {
        if self.envelope.samples() == 0 || self.envelope.channels().is_empty() {
            0
        } else {
            self.envelope.at(0, 0).count()
        }
    }

    /// Adds every count of `other`, an envelope of the same run's other members.
    fn merge(&mut self, other: &MonteCarloEnvelope) -> PyResult<()> {
        if !self.envelope.same_shape(&other.envelope) {
            return Err(invalid(format!(
                "envelopes of different runs: channels {:?} at {} samples against {:?} at {}",
                self.envelope.channels(),
                self.envelope.samples(),
                other.envelope.channels(),
                other.envelope.samples()
            )));
        }
        self.envelope.merge(&other.envelope);
        Ok(())
    }

    /// The `q`-th percentile (0 to 100) of every channel at every sample time, an array
    /// of shape `(channels, samples)`; NaN where no member finished.
    fn percentile<'py>(&self, py: Python<'py>, q: f64) -> PyResult<Bound<'py, PyAny>> {
        if !(0.0..=100.0).contains(&q) {
            return Err(invalid(format!("q must lie in [0, 100], got {q}")));
        }
        let (c, n) = (self.envelope.channels().len(), self.envelope.samples());
        let values = (0..c)
            .flat_map(|ch| (0..n).map(move |k| (ch, k)))
            .map(|(ch, k)| {
                self.envelope
                    .at(ch, k)
                    .quantile(q / 100.0)
                    .unwrap_or(f64::NAN)
            })
            .collect();
        Ok(array2(py, c, n, values).into_any())
    }

    /// Pickling: the sketches' counts as JSON.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let text =
            serde_json::to_vec(&self.envelope).map_err(|e| invalid(format!("envelope: {e}")))?;
        let from = py
            .import("lgsvi._lgsvi")?
            .getattr("_montecarlo_envelope_from_bytes")?;
        PyTuple::new(
            py,
            [
                from,
                PyTuple::new(py, [PyBytes::new(py, &text)])?.into_any(),
            ],
        )
    }

    fn __repr__(&self) -> String {
        format!(
            "MonteCarloEnvelope(channels={:?}, samples={}, members={})",
            self.envelope.channels(),
            self.envelope.samples(),
            self.members()
        )
    }
}

/// An envelope from its pickled bytes.
#[pyfunction]
fn _montecarlo_envelope_from_bytes(data: &[u8]) -> PyResult<MonteCarloEnvelope> {
    let envelope: Envelope =
        serde_json::from_slice(data).map_err(|e| invalid(format!("envelope: {e}")))?;
    Ok(MonteCarloEnvelope { envelope })
}

/// A condition given as `name=` (`stop_when`, `settle_when`), parsed (the system's check
/// of its quantity comes with the nominal integrator, [`Watch::check`]).
fn condition(text: Option<&str>, name: &str) -> PyResult<Option<StopWhen>> {
    text.map(|text| {
        text.parse()
            .map_err(|reason| invalid(format!("{name} {text:?}: {reason}")))
    })
    .transpose()
}

/// Runs members `first..last` of the plan of `system` from `(attitude, omega)` (and
/// `position`, `velocity` in space, `wheel_speeds` of a gyrostat), the dispersions
/// `dispersions` (JSON, the keys of `lgsvi_montecarlo::Dispersions`) and `seed`, each to
/// `t_end` with steps `h` of `nodes` nodes under the constant `input`; returns their
/// draws, final states, stop and settling times, failures and envelope (the Python
/// layer's `lgsvi.montecarlo.run` wraps it).
#[pyfunction]
#[pyo3(signature = (system, attitude, omega, dispersions, seed, first, last, t_end, h, nodes, samples, chart="exp", matching="exact", threads=None, stop_when=None, settle_when=None, position=None, velocity=None, wheel_speeds=None, input=None, controller=None, sample_period=None))]
#[allow(clippy::too_many_arguments)]
fn _montecarlo_chunk<'py>(
    py: Python<'py>,
    system: &Bound<'py, PyAny>,
    attitude: &Bound<'py, PyAny>,
    omega: &Bound<'py, PyAny>,
    dispersions: &str,
    seed: u64,
    first: u64,
    last: u64,
    t_end: f64,
    h: f64,
    nodes: usize,
    samples: usize,
    chart: &str,
    matching: &str,
    threads: Option<usize>,
    stop_when: Option<&str>,
    settle_when: Option<&str>,
    position: Option<&Bound<'py, PyAny>>,
    velocity: Option<&Bound<'py, PyAny>>,
    wheel_speeds: Option<&Bound<'py, PyAny>>,
    input: Option<&Bound<'py, PyAny>>,
    controller: Option<PyRef<'py, PdLaw>>,
    sample_period: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let (spec, _) = system_of(system)?;
    let k = spec.wheels();
    let space = spec.in_space();
    let in_space = "a body in space (FreeBody, OrbitingBody)";
    for (given, name, applies, of) in [
        (position.is_some(), "position", space, in_space),
        (velocity.is_some(), "velocity", space, in_space),
        (wheel_speeds.is_some(), "wheel_speeds", k > 0, "a gyrostat"),
    ] {
        if given && !applies {
            return Err(invalid(format!(
                "{name} is a start of {of}, not of a {}",
                spec.name()
            )));
        }
    }
    let start = Start {
        t: 0.0,
        attitude: rotation(attitude, "attitude")?,
        omega: vector3(omega, "omega")?,
        position: position.map_or(Ok(Vector3::zeros()), |p| vector3(p, "position"))?,
        velocity: velocity.map_or(Ok(Vector3::zeros()), |v| vector3(v, "velocity"))?,
        wheel_speeds: wheel_speeds.map_or(Ok(vec![0.0; k]), |w| vector(w, "wheel_speeds"))?,
        wheel_angles: vec![0.0; k],
    };
    if start.wheel_speeds.len() != k {
        return Err(invalid(format!(
            "wheel_speeds has {} entries for the gyrostat's {k} wheels",
            start.wheel_speeds.len()
        )));
    }
    let input = input.map(|u| vector(u, "input")).transpose()?;
    let dispersions: Dispersions =
        serde_json::from_str(dispersions).map_err(|e| invalid(format!("dispersions: {e}")))?;
    if dispersions.torque.is_some() && k > 0 {
        return Err(invalid(
            "dispersion torque: a gyrostat takes no body torque (its wheels' motor torques \
             are the input)",
        ));
    }
    let nominal = nominal_of(&spec, &start)?;
    let plan = Plan::new(nominal, dispersions, seed).map_err(|e| invalid(e.to_string()))?;
    if first > last {
        return Err(invalid(format!(
            "members {first}..{last}: the first member comes before the last"
        )));
    }
    if !(t_end.is_finite() && t_end > 0.0) {
        return Err(invalid(format!(
            "t_end must be finite and positive, got {t_end}"
        )));
    }
    if !(2..=10_000).contains(&samples) {
        return Err(invalid(format!(
            "samples must be from 2 to 10000, got {samples}"
        )));
    }
    if threads == Some(0) {
        return Err(invalid("threads must be at least 1"));
    }
    let options = Options {
        h,
        nodes,
        chart: chart_named(chart)?,
        matching: matching_named(matching)?,
        quadrature_points: None,
        max_newton_iterations: None,
    };
    let settings = options.settings()?;
    let control = match (controller, sample_period) {
        (None, None) => None,
        (Some(_), None) => {
            return Err(invalid(
                "controller needs sample_period: the law is sampled every sample_period \
                 (a whole number of steps h) and held",
            ))
        }
        (None, Some(_)) => {
            return Err(invalid(
                "sample_period is the controller's: give controller=lgsvi.control.PdLaw(...)",
            ))
        }
        (Some(law), Some(period)) => {
            if spec.wheels() > 0 {
                return Err(invalid(
                    "controller: a gyrostat turns by its wheels' motor torques (input), not \
                     by a body torque",
                ));
            }
            if spec.drive().and_then(Drive::target).is_some() {
                return Err(invalid(
                    "controller: the system has an attitude law of its own (attitude_gain, \
                     target); give the law to one of them",
                ));
            }
            if input.is_some() {
                return Err(invalid(
                    "input and controller: the controller sets the input at each sample; give \
                     one of them",
                ));
            }
            let sampled = SampledLaw::new(law.law, period).map_err(|_| {
                invalid(format!(
                    "sample_period must be positive and finite, got {period}"
                ))
            })?;
            sampled.check_step(settings.h()).map_err(|_| {
                invalid(format!(
                    "sample_period {period} is not a whole number of steps h = {h}: take h as \
                     the period divided by a whole number"
                ))
            })?;
            Some(sampled)
        }
    };
    let watch = Watch {
        stop: condition(stop_when, "stop_when")?,
        settle: condition(settle_when, "settle_when")?,
        // `error` is measured from the attitude law's target (the sampled controller's,
        // the identity without either).
        target: spec
            .drive()
            .and_then(Drive::target)
            .or(control.map(|c| *c.law().target())),
    };
    // A condition on a quantity the system lacks is refused here, once, as the command
    // line refuses it, rather than failing every member.
    let probe = Run::new(spec.build()?, &options, &start)?;
    each_run!(&probe, it => {
        let (state, motion, wheels) = Columns::columns(it.state());
        watch.check(&state, motion.as_ref(), wheels.as_ref())
    })
    .map_err(|error| match error {
        ExperimentError::Stop { condition, reason } => {
            let name = if watch.names_settle(&condition) {
                "settle_when"
            } else {
                "stop_when"
            };
            invalid(format!(
                "{name} {condition:?}: {reason}, not to a {}",
                spec.name()
            ))
        }
        other => experiment(other),
    })?;
    let whole = (t_end / settings.h() + 1e-9).floor();
    if whole > 1e9 {
        return Err(invalid(format!(
            "t_end / h = {whole:e} steps: take a longer step or a shorter run"
        )));
    }
    let setup = Setup {
        options,
        t_end,
        every: ((whole as usize) / (samples - 1)).max(1),
        watch,
        input,
        control,
    };
    // The nominal runs to the end (the envelopes' times), whatever stop_when says.
    let nominal_run = py
        .detach(|| run_sampled(&spec, &start, &setup, &Watch::NOTHING))
        .map_err(|e| invalid(format!("the nominal run failed: {e}")))?
        .0;
    // A system with an attitude law or a target adds the pointing error's channel.
    let target = setup.watch.target;
    let mut envelope = Envelope::of_run(nominal_run.times.len(), k, target.is_some());
    let mut outcomes: Vec<Outcome> = Vec::with_capacity((last - first) as usize);
    py.detach(|| {
        guarded(|| {
            let work = || -> PyResult<()> {
                let mut begin = first;
                while begin < last {
                    let end = (begin + BATCH).min(last);
                    let batch: Vec<PyResult<Outcome>> = (begin..end)
                        .into_par_iter()
                        .map(|index| {
                            let member = plan.member(index).map_err(|e| invalid(e.to_string()))?;
                            let mut from = start.clone();
                            from.attitude = member.body.attitude;
                            from.omega = member.body.omega;
                            let spec = member_spec(&spec, &member.body);
                            let result = run_sampled(&spec, &from, &setup, &setup.watch);
                            Ok(Outcome { member, result })
                        })
                        .collect();
                    for outcome in batch {
                        let mut outcome = outcome?;
                        if let Ok((sampled, _)) = &mut outcome.result {
                            envelope.add_member(&nominal_run, sampled, target.as_ref());
                            // Only the final state is kept past the batch.
                            sampled.keep_last();
                        }
                        outcomes.push(outcome);
                    }
                    begin = end;
                }
                Ok(())
            };
            in_pool(threads, work)
        })
    })?;
    chunk_dict(py, outcomes, envelope, &nominal_run, space, k)
}

/// The chunk's arrays, failures and envelope as a dict.
fn chunk_dict<'py>(
    py: Python<'py>,
    outcomes: Vec<Outcome>,
    envelope: Envelope,
    nominal: &Samples,
    space: bool,
    wheels: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let m = outcomes.len();
    let errors = PyDict::new(py);
    let (mut index, mut ok) = (Vec::with_capacity(m), Vec::with_capacity(m));
    let (mut j, mut r0, mut w0, mut tau) = (vec![], vec![], vec![], vec![]);
    let (mut mass, mut wheel_inertia, mut wheel_axes) = (vec![], vec![], vec![]);
    let (mut t, mut r, mut w, mut e) = (vec![], vec![], vec![], vec![]);
    let (mut x, mut v, mut speeds) = (vec![], vec![], vec![]);
    let (mut t_stop, mut t_settle) = (Vec::with_capacity(m), Vec::with_capacity(m));
    for outcome in outcomes {
        let body = &outcome.member.body;
        index.push(outcome.member.index);
        j.extend(rows3(&body.inertia.matrix()));
        r0.extend(rows3(body.attitude.matrix()));
        w0.extend_from_slice(body.omega.as_slice());
        tau.extend_from_slice(body.torque.as_slice());
        mass.push(body.mass.unwrap_or(f64::NAN));
        wheel_inertia.extend_from_slice(&body.wheel_inertias);
        wheel_axes.extend(body.wheel_axes.iter().flat_map(|a| [a.x, a.y, a.z]));
        match outcome.result {
            Ok((s, ended)) => {
                ok.push(true);
                t_stop.push(ended.stop.unwrap_or(f64::NAN));
                t_settle.push(ended.settle.unwrap_or(f64::NAN));
                t.push(s.times[0]);
                r.extend(rows3(&s.attitudes[0]));
                w.extend_from_slice(s.omegas[0].as_slice());
                e.push(s.energies[0]);
                let (xs, vs) = ended.motion.unwrap_or_default();
                x.extend_from_slice(xs.as_slice());
                v.extend_from_slice(vs.as_slice());
                match s.wheel_speeds.first() {
                    Some(last) => speeds.extend_from_slice(last),
                    None => speeds.extend(std::iter::repeat_n(f64::NAN, wheels)),
                }
            }
            Err(error) => {
                ok.push(false);
                t_stop.push(f64::NAN);
                t_settle.push(f64::NAN);
                t.push(f64::NAN);
                r.extend([f64::NAN; 9]);
                w.extend([f64::NAN; 3]);
                e.push(f64::NAN);
                x.extend([f64::NAN; 3]);
                v.extend([f64::NAN; 3]);
                speeds.extend(std::iter::repeat_n(f64::NAN, wheels));
                errors.set_item(outcome.member.index, error.value(py))?;
            }
        }
    }
    let d = PyDict::new(py);
    d.set_item("member", PyArray1::from_vec(py, index))?;
    d.set_item("ok", PyArray1::from_vec(py, ok))?;
    d.set_item("inertia", array3(py, (m, 3, 3), j))?;
    d.set_item("attitude0", array3(py, (m, 3, 3), r0))?;
    d.set_item("omega0", array2(py, m, 3, w0))?;
    d.set_item("torque", array2(py, m, 3, tau))?;
    d.set_item("mass", array1(py, mass))?;
    d.set_item("wheel_inertia", array2(py, m, wheels, wheel_inertia))?;
    d.set_item("wheel_axes", array3(py, (m, wheels, 3), wheel_axes))?;
    d.set_item("t", array1(py, t))?;
    d.set_item("attitude", array3(py, (m, 3, 3), r))?;
    d.set_item("omega", array2(py, m, 3, w))?;
    d.set_item("energy", array1(py, e))?;
    if space {
        d.set_item("position", array2(py, m, 3, x))?;
        d.set_item("velocity", array2(py, m, 3, v))?;
    }
    d.set_item("wheel_speeds", array2(py, m, wheels, speeds))?;
    d.set_item("t_stop", array1(py, t_stop))?;
    d.set_item("t_settle", array1(py, t_settle))?;
    d.set_item("errors", errors)?;
    d.set_item("envelope", MonteCarloEnvelope { envelope })?;
    d.set_item("times", array1(py, nominal.times.clone()))?;
    let k = nominal.times.len() - 1;
    d.set_item(
        "nominal_attitude",
        array2(py, 3, 3, rows3(&nominal.attitudes[k]).to_vec()),
    )?;
    d.set_item(
        "nominal_omega",
        array1(py, nominal.omegas[k].as_slice().to_vec()),
    )?;
    Ok(d)
}

/// Registers the chunk runner and the envelope class.
pub fn register(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add_class::<MonteCarloEnvelope>()?;
    module.add_function(wrap_pyfunction!(_montecarlo_chunk, module)?)?;
    module.add_function(wrap_pyfunction!(_montecarlo_envelope_from_bytes, module)?)?;
    Ok(())
}
