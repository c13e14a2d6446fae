//! `lgsvi.montecarlo`'s compiled core: one chunk of a Monte Carlo run (members
//! `first..last` of a plan drawn by [`lgsvi_montecarlo::Plan`], run in parallel with the
//! GIL released) and the percentile envelope they add to ([`MonteCarloEnvelope`]), which
//! pickles and merges exactly, so that chunks run on a cluster's workers combine into the
//! run a single machine gives.

use crate::convert::{array1, array2, array3, rotation, rows3, vector3};
use crate::errors::{guarded, invalid, mechanics};
use crate::run::{chart_named, in_pool, matching_named, Options};
use crate::systems::{system_of, So3System, Spec};
use lgsvi_experiments::stop::StopWhen;
use lgsvi_mechanics::built_in::BuiltInSo3;
use lgsvi_mechanics::events::Events;
use lgsvi_mechanics::forces::{AngularDamping, BodyTorque};
use lgsvi_mechanics::lie::SO3;
use lgsvi_mechanics::stepper::each;
use lgsvi_mechanics::State;
use lgsvi_mechanics::{
    Forced, HeavyTop, Integrator, MechanicsError, RigidBody, StepSettings, Stepper, System,
};
use lgsvi_montecarlo::statistics::{Envelope, Samples};
use lgsvi_montecarlo::{Body, Dispersions, Member, Plan};
use nalgebra::Vector3;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyTuple};
use rayon::prelude::*;
use std::ops::ControlFlow;

/// Members run between two additions to the envelope: their sampled states are held only
/// that long, so a chunk's memory does not grow with its members.
const BATCH: u64 = 256;

/// The nominal system of a run: which SO(3) body, and its parameters other than the
/// dispersed ones (inertia, torque).
#[derive(Debug, Clone, Copy)]
enum Kind {
    Free,
    Top {
        mass: f64,
        gravity: f64,
        com: Vector3<f64>,
        direction: Vector3<f64>,
    },
}

/// The system a member's body makes: the nominal's kind and damping, the body's inertia
/// and torque.
fn member_system(kind: Kind, damping: f64, body: &Body) -> Result<So3System, MechanicsError> {
    let built = match kind {
        Kind::Free => BuiltInSo3::Free(RigidBody::new(body.inertia)),
        Kind::Top {
            mass,
            gravity,
            com,
            direction,
        } => BuiltInSo3::Top(HeavyTop::new(body.inertia, mass, gravity, com, direction)?),
    };
    Ok(Forced::new(
        built,
        (BodyTorque(body.torque), AngularDamping(damping)),
    ))
}

/// Adds the integrator's present state to the samples.
fn push(sampled: &mut Samples, it: &Integrator<So3System>) {
    let s = it.state();
    let energy = s.momentum.dot(&s.velocity)
        - it.system()
            .lagrangian(s.time, &s.configuration, &s.velocity);
    sampled.times.push(s.time);
    sampled.attitudes.push(*s.configuration.matrix());
    sampled.omegas.push(s.velocity);
    sampled.energies.push(energy);
}

/// The body's run to `t_end`, sampled every `every` steps.
fn run_sampled(
    system: So3System,
    settings: StepSettings,
    body: &Body,
    t_end: f64,
    every: usize,
    stop: Option<&StopWhen>,
) -> Result<(Samples, Option<f64>), MechanicsError> {
    let mut it = Integrator::new(system, settings, body.attitude, body.omega)?;
    let mut sampled = Samples::default();
    push(&mut sampled, &it);
    // The condition as `lgsvi simulate --stop-when` watches it: the quantity of the state
    // on the curve, less the value.
    // The condition as `lgsvi simulate --stop-when` watches it.
    let mut events = Events::new(
        stop.map(|stop| stop.event(body.attitude, |s: &State| (*s, None, None)))
            .into_iter()
            .collect(),
    );
    let mut recorded = true;
    let mut observer = each(
        |it: &Integrator<So3System>, info: lgsvi_mechanics::stepper::StepInfo| {
            recorded = info.index.is_multiple_of(every) || info.last;
            if recorded {
                push(&mut sampled, it);
            }
            Ok::<_, MechanicsError>(ControlFlow::Continue(()))
        },
    );
    it.drive_until(t_end, &mut (&mut observer, &mut events))?;
    if events.stopped() && !recorded {
        // The step that holds the crossing ends the samples.
        push(&mut sampled, &it);
    }
    let stopped = events.hits().first().map(|hit| hit.time);
    Ok((sampled, stopped))
}

/// One member's draws and final state (or why it failed).
struct Outcome {
    member: Member,
    result: Result<(Samples, Option<f64>), MechanicsError>,
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

/// The nominal body and kind of `spec` (rigid body or heavy top), from `(attitude,
/// omega)`.
fn nominal_of(spec: &Spec, attitude: SO3, omega: Vector3<f64>) -> PyResult<(Kind, f64, Body)> {
    let (kind, inertia, drive) = match spec {
        Spec::RigidBody { inertia, drive } => (Kind::Free, inertia, drive),
        Spec::HeavyTop {
            inertia,
            mass,
            gravity,
            com,
            gravity_direction,
            drive,
        } => (
            Kind::Top {
                mass: *mass,
                gravity: *gravity,
                com: *com,
                direction: *gravity_direction,
            },
            inertia,
            drive,
        ),
        other => {
            return Err(invalid(format!(
                "montecarlo runs RigidBody and HeavyTop so far, not a {}",
                other.name()
            )))
        }
    };
    let mut body = Body::new(inertia.inertia()?, attitude, omega);
    body.torque = drive.torque;
    Ok((kind, drive.damping, body))
}

/// Runs members `first..last` of the plan of `system` from `(attitude, omega)`, the
/// dispersions `dispersions` (JSON, the keys of `lgsvi_montecarlo::Dispersions`) and
/// `seed`, each to `t_end` with steps `h` of `nodes` nodes; returns their draws, final
/// states, failures and envelope (the Python layer's `lgsvi.montecarlo.run` wraps it).
#[pyfunction]
#[pyo3(signature = (system, attitude, omega, dispersions, seed, first, last, t_end, h, nodes, samples, chart="exp", matching="exact", threads=None, stop_when=None))]
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
) -> PyResult<Bound<'py, PyDict>> {
    let (spec, _) = system_of(system)?;
    let stop = stop_when
        .map(|text| {
            let stop: StopWhen = text
                .parse()
                .map_err(|reason| invalid(format!("stop_when {text:?}: {reason}")))?;
            let probe = State {
                time: 0.0,
                configuration: SO3::identity(),
                momentum: Vector3::zeros(),
                velocity: Vector3::zeros(),
            };
            if stop
                .quantity
                .value(&probe, None, None, &SO3::identity())
                .is_none()
            {
                return Err(invalid(format!(
                    "stop_when {text:?}: {} applies to {}, not to a body on SO(3)",
                    stop.quantity,
                    stop.quantity.applies_to()
                )));
            }
            Ok(stop)
        })
        .transpose()?;
    let attitude = rotation(attitude, "attitude")?;
    let omega = vector3(omega, "omega")?;
    let dispersions: Dispersions =
        serde_json::from_str(dispersions).map_err(|e| invalid(format!("dispersions: {e}")))?;
    let (kind, damping, nominal) = nominal_of(&spec, attitude, omega)?;
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
    let settings = Options {
        h,
        nodes,
        chart: chart_named(chart)?,
        matching: matching_named(matching)?,
        quadrature_points: None,
        max_newton_iterations: None,
    }
    .settings()?;
    let whole = (t_end / settings.h() + 1e-9).floor();
    if whole > 1e9 {
        return Err(invalid(format!(
            "t_end / h = {whole:e} steps: take a longer step or a shorter run"
        )));
    }
    let every = ((whole as usize) / (samples - 1)).max(1);
    let nominal_system = member_system(kind, damping, plan.nominal()).map_err(mechanics)?;
    let nominal_run = py
        .detach(|| run_sampled(nominal_system, settings, plan.nominal(), t_end, every, None))
        .map_err(|e| invalid(format!("the nominal run failed: {e}")))?
        .0;
    let mut envelope = Envelope::of_attitude(nominal_run.times.len());
    let mut outcomes: Vec<Outcome> = Vec::with_capacity((last - first) as usize);
    py.detach(|| {
        guarded(|| {
            let work = || -> PyResult<()> {
                let mut start = first;
                while start < last {
                    let end = (start + BATCH).min(last);
                    let batch: Vec<PyResult<Outcome>> = (start..end)
                        .into_par_iter()
                        .map(|index| {
                            let member = plan.member(index).map_err(|e| invalid(e.to_string()))?;
                            let result =
                                member_system(kind, damping, &member.body).and_then(|system| {
                                    run_sampled(
                                        system,
                                        settings,
                                        &member.body,
                                        t_end,
                                        every,
                                        stop.as_ref(),
                                    )
                                });
                            Ok(Outcome { member, result })
                        })
                        .collect();
                    for outcome in batch {
                        let mut outcome = outcome?;
                        if let Ok((sampled, _)) = &mut outcome.result {
                            envelope.add_attitude_samples(&nominal_run, sampled);
                            // Only the final state is kept past the batch.
                            let k = sampled.times.len() - 1;
                            *sampled = Samples {
                                times: vec![sampled.times[k]],
                                attitudes: vec![sampled.attitudes[k]],
                                omegas: vec![sampled.omegas[k]],
                                energies: vec![sampled.energies[k]],
                            };
                        }
                        outcomes.push(outcome);
                    }
                    start = end;
                }
                Ok(())
            };
            in_pool(threads, work)
        })
    })?;
    chunk_dict(py, outcomes, envelope, &nominal_run)
}

/// The chunk's arrays, failures and envelope as a dict.
fn chunk_dict<'py>(
    py: Python<'py>,
    outcomes: Vec<Outcome>,
    envelope: Envelope,
    nominal: &Samples,
) -> PyResult<Bound<'py, PyDict>> {
    let m = outcomes.len();
    let errors = PyDict::new(py);
    let (mut index, mut ok) = (Vec::with_capacity(m), Vec::with_capacity(m));
    let (mut j, mut r0, mut w0, mut tau) = (vec![], vec![], vec![], vec![]);
    let (mut t, mut r, mut w, mut e) = (vec![], vec![], vec![], vec![]);
    let mut t_stop = Vec::with_capacity(m);
    for outcome in outcomes {
        let body = &outcome.member.body;
        index.push(outcome.member.index);
        j.extend(rows3(&body.inertia.matrix()));
        r0.extend(rows3(body.attitude.matrix()));
        w0.extend_from_slice(body.omega.as_slice());
        tau.extend_from_slice(body.torque.as_slice());
        match outcome.result {
            Ok((s, stopped)) => {
                ok.push(true);
                t_stop.push(stopped.unwrap_or(f64::NAN));
                t.push(s.times[0]);
                r.extend(rows3(&s.attitudes[0]));
                w.extend_from_slice(s.omegas[0].as_slice());
                e.push(s.energies[0]);
            }
            Err(error) => {
                ok.push(false);
                t_stop.push(f64::NAN);
                t.push(f64::NAN);
                r.extend([f64::NAN; 9]);
                w.extend([f64::NAN; 3]);
                e.push(f64::NAN);
                errors.set_item(outcome.member.index, mechanics(error).value(py))?;
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
    d.set_item("t", array1(py, t))?;
    d.set_item("attitude", array3(py, (m, 3, 3), r))?;
    d.set_item("omega", array2(py, m, 3, w))?;
    d.set_item("energy", array1(py, e))?;
    d.set_item("t_stop", array1(py, t_stop))?;
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
