"""Monte Carlo dispersion analysis: thousands of runs of a built-in system (rigid body,
heavy top, free or orbiting body in space, gyrostat) whose inertia, start, torque, mass and
wheels are dispersed about a nominal, on one machine or a Dask cluster.

Member ``i``'s draws depend on ``(seed, i)`` alone (a ChaCha stream per quantity), so a
member is the same whatever the thread count, the chunking, or the machine that runs it: a
run split over a Dask cluster (``client=``) gives, bit for bit, the arrays and percentiles a
local run gives.

A dispersion spec is a dict from a quantity's key to its distribution, the keys and
fields of ``lgsvi montecarlo``'s ``[montecarlo.dispersions]`` table:

======================== ============================================================
key                      perturbation ``d`` of each member
======================== ============================================================
``attitude``             each component of a body-frame rotation vector, rad:
                         ``R0 = R0_nominal exp(hat(d))``
``omega``                added to each start rate, rad/s
``inertia``              each principal moment, relative: ``J_i (1 + d_i)``
``inertia_misalignment`` each component of a rotation vector of the principal axes, rad
``torque``               added to each component of the constant body torque, N m
``mass``                 relative: ``m (1 + d)`` (a body in space, a heavy top)
``wheel_inertia``        each wheel's axial inertia, relative: ``I_k (1 + d_k)``
``wheel_axis``           each component of a rotation vector of each wheel's axis, rad
======================== ============================================================

Each value is :func:`normal`, :func:`truncated_normal` or :func:`uniform` (or the same
dict written out, e.g. ``{"distribution": "normal", "sigma": 0.01}``). A spec that could
make a member non-physical (a relative perturbation reaching -1, principal moments that
could break the triangle inequality) is refused up front: disperse the inertia by a
truncated normal or a uniform.

Example::

    import numpy as np
    import lgsvi
    from lgsvi import montecarlo

    body = lgsvi.RigidBody([3.3, 2.5, 3.4])
    result = montecarlo.run(
        body, np.eye(3), [0.1, 0.0, 0.2],
        {"omega": montecarlo.normal(0.01), "inertia": montecarlo.truncated_normal(0.02, 0.06)},
        members=1000, seed=42, t_end=20.0, h=0.5, nodes=10,
    )
    result.percentile("attitude_departure_deg", 99)   # (samples,) over result.times
"""

from __future__ import annotations

import json
from typing import Any, Dict, Iterable, List, Optional

import numpy as np

from . import _lgsvi

__all__ = [
    "MonteCarloEnvelope",
    "MonteCarloResult",
    "normal",
    "run",
    "truncated_normal",
    "uniform",
]

MonteCarloEnvelope = _lgsvi.MonteCarloEnvelope

#: The envelope's channels: the attitude's departure from the nominal run at the same
#: time (degrees), the body rates (rad/s) and the energy's relative change since the start;
#: a gyrostat's envelope adds ``wheel_1`` ... ``wheel_K``, each wheel's rate (rad/s).
CHANNELS = ("attitude_departure_deg", "omega_1", "omega_2", "omega_3", "energy_change")

#: Members one chunk of a Dask run holds without ``chunk_size``.
DEFAULT_CHUNK = 500


def normal(sigma: float) -> Dict[str, Any]:
    """A normal perturbation, mean 0, standard deviation ``sigma >= 0``."""
    return {"distribution": "normal", "sigma": float(sigma)}


def truncated_normal(sigma: float, bound: float) -> Dict[str, Any]:
    """A normal perturbation of standard deviation ``sigma > 0`` conditioned on
    ``|d| <= bound`` (``bound >= sigma / 10``)."""
    return {"distribution": "truncated_normal", "sigma": float(sigma), "bound": float(bound)}


def uniform(half_width: float) -> Dict[str, Any]:
    """A uniform perturbation on ``[-half_width, half_width]``."""
    return {"distribution": "uniform", "half_width": float(half_width)}


_FIELDS = (
    "member",
    "ok",
    "inertia",
    "attitude0",
    "omega0",
    "torque",
    "t",
    "attitude",
    "omega",
    "energy",
    "t_stop",
    "t_settle",
    "mass",
    "wheel_inertia",
    "wheel_axes",
    "wheel_speeds",
)

#: Fields only a body in space has.
_SPACE_FIELDS = ("position", "velocity")


class MonteCarloResult:
    """A Monte Carlo run: every member's draws and final state, the failures, and the
    percentile envelopes over the members at the sample times.

    Attributes
    ----------
    member : ndarray (M,) of uint64
        The members' indices.
    ok : ndarray (M,) of bool
        Which members reached ``t_end``.
    inertia, attitude0 : ndarray (M, 3, 3)
        Each member's drawn inertia tensor (body frame) and start attitude.
    omega0, torque : ndarray (M, 3)
        Its start rates and constant body torque.
    t, energy : ndarray (M,)
        Its final time and energy (NaN for a failed member).
    t_stop : ndarray (M,)
        Where ``stop_when`` stopped it (NaN where it never met the condition, or failed).
    t_settle : ndarray (M,)
        From when ``settle_when`` held to the end (NaN where it does not hold at the end,
        or failed).
    mass : ndarray (M,)
        The drawn mass (NaN for a system without one).
    wheel_inertia : ndarray (M, K); wheel_axes : ndarray (M, K, 3)
        A gyrostat's drawn wheel inertias and unit axes (K = 0 without wheels).
    wheel_speeds : ndarray (M, K)
        The wheels' final rates relative to the body.
    position, velocity : ndarray (M, 3)
        A body in space's final position and velocity (world frame); absent otherwise.
    attitude : ndarray (M, 3, 3)
        Its final attitude; ``omega`` (M, 3) its final rates (NaN for a failed member).
    errors : dict
        Each failed member's index and its exception (an :class:`lgsvi.LgsviError`).
    seed : int
        The run's seed: ``(seed, member)`` reproduces a member.
    times : ndarray (S,)
        The envelopes' sample times (every few steps, and ``t_end``).
    envelope : MonteCarloEnvelope
        The percentile sketches per channel and sample time.
    nominal_attitude, nominal_omega : ndarray
        The nominal run's final state.
    """

    def __init__(self, fields: Dict[str, Any], seed: int) -> None:
        for name in _FIELDS:
            setattr(self, name, fields[name])
        for name in _SPACE_FIELDS:
            if name in fields:
                setattr(self, name, fields[name])
        self.errors: Dict[int, Exception] = dict(fields["errors"])
        self.envelope: MonteCarloEnvelope = fields["envelope"]
        self.times: np.ndarray = fields["times"]
        self.nominal_attitude: np.ndarray = fields["nominal_attitude"]
        self.nominal_omega: np.ndarray = fields["nominal_omega"]
        self.seed = seed

    def __len__(self) -> int:
        return len(self.member)

    @property
    def channels(self) -> List[str]:
        """The envelope's channels: :data:`CHANNELS`, a gyrostat's ``wheel_K``, and
        ``error_deg`` (the pointing error, degrees from the target) for a system with an
        ``attitude_gain`` law or a ``target``."""
        return list(self.envelope.channels)

    def percentile(self, channel: str, q: float) -> np.ndarray:
        """The ``q``-th percentile (0 to 100) of ``channel`` (one of :attr:`channels`)
        over the members that finished, at each of :attr:`times`: within 0.55% of the
        exact sample percentile."""
        channels = self.channels
        if channel not in channels:
            raise _lgsvi.InvalidInputError(
                f"channel must be one of {', '.join(channels)}, got {channel!r}"
            )
        return self.envelope.percentile(q)[channels.index(channel)]

    def stop_statistics(self) -> Dict[str, Any]:
        """The stop times of the members ``stop_when`` stopped: ``stopped`` (how many),
        ``not_stopped`` (finished without meeting it), and the exact sample percentiles
        ``p1`` ... ``p99`` (the ``ceil(qN)``-th smallest) with ``min`` and ``max``."""
        return self._time_statistics(self.t_stop, "stopped")

    def settle_statistics(self) -> Dict[str, Any]:
        """The settling times of the members ``settle_when`` held for at the end:
        ``settled`` (how many), ``not_settled`` (finished without it holding), and the
        exact sample percentiles ``p1`` ... ``p99`` with ``min`` and ``max``."""
        return self._time_statistics(self.t_settle, "settled")

    def _time_statistics(self, times: np.ndarray, verb: str) -> Dict[str, Any]:
        times = np.sort(times[self.ok & np.isfinite(times)])
        n = len(times)
        out: Dict[str, Any] = {verb: n, f"not_{verb}": int(self.ok.sum()) - n}
        for p in (1, 5, 25, 50, 75, 95, 99):
            rank = min(max(int(np.ceil(p / 100 * n)), 1), n) if n else 0
            out[f"p{p}"] = float(times[rank - 1]) if n else float("nan")
        out["min"] = float(times[0]) if n else float("nan")
        out["max"] = float(times[-1]) if n else float("nan")
        return out

    def final_statistics(self) -> Dict[str, np.ndarray]:
        """The final rates' and attitude departures' mean and covariance over the members
        that finished: ``omega_mean`` (3,), ``omega_covariance`` (3, 3), and the same of
        the departure from the nominal's final attitude as a rotation vector
        (``departure_mean``, ``departure_covariance``, radians)."""
        from .lie import so3_log

        ok = self.ok
        rel = np.einsum("ji,mjk->mik", self.nominal_attitude, self.attitude[ok])
        departure = so3_log(rel).reshape(-1, 3) if len(rel) else np.zeros((0, 3))
        omega = self.omega[ok]

        def cov(x: np.ndarray) -> np.ndarray:
            return np.cov(x, rowvar=False).reshape(3, 3) if len(x) > 1 else np.zeros((3, 3))

        return {
            "omega_mean": omega.mean(axis=0) if len(omega) else np.full(3, np.nan),
            "omega_covariance": cov(omega),
            "departure_mean": departure.mean(axis=0) if len(omega) else np.full(3, np.nan),
            "departure_covariance": cov(departure),
        }

    def __repr__(self) -> str:
        return (
            f"MonteCarloResult(members={len(self)}, failed={len(self.errors)}, "
            f"seed={self.seed}, samples={len(self.times)})"
        )


def _spec_json(dispersions: Optional[Dict[str, Any]]) -> str:
    if dispersions is None:
        return "{}"
    if not isinstance(dispersions, dict):
        raise _lgsvi.InvalidInputError(
            "dispersions must be a dict from a quantity (attitude, omega, inertia, "
            "inertia_misalignment, torque, mass, wheel_inertia, wheel_axis) to its "
            f"distribution, got {type(dispersions).__name__}"
        )
    try:
        return json.dumps(dispersions, allow_nan=False)
    except (TypeError, ValueError) as error:
        raise _lgsvi.InvalidInputError(f"dispersions: {error}") from None


def _combine(chunks: List[Dict[str, Any]], seed: int) -> MonteCarloResult:
    names = _FIELDS + tuple(n for n in _SPACE_FIELDS if n in chunks[0])
    fields: Dict[str, Any] = {name: np.concatenate([c[name] for c in chunks]) for name in names}
    errors: Dict[int, Exception] = {}
    envelope = chunks[0]["envelope"]
    for k, chunk in enumerate(chunks):
        errors.update(chunk["errors"])
        if k > 0:
            envelope.merge(chunk["envelope"])
    fields.update(
        errors=errors,
        envelope=envelope,
        times=chunks[0]["times"],
        nominal_attitude=chunks[0]["nominal_attitude"],
        nominal_omega=chunks[0]["nominal_omega"],
    )
    return MonteCarloResult(fields, seed)


def _ranges(members: int, size: int) -> Iterable[tuple]:
    return ((a, min(a + size, members)) for a in range(0, members, size))


def run(
    system: Any,
    attitude: Any,
    omega: Any,
    dispersions: Optional[Dict[str, Any]] = None,
    *,
    members: int,
    seed: int = 0,
    t_end: float,
    h: float,
    nodes: int,
    samples: int = 100,
    chart: str = "exp",
    matching: str = "exact",
    threads: Optional[int] = None,
    client: Any = None,
    chunk_size: Optional[int] = None,
    stop_when: Optional[str] = None,
    settle_when: Optional[str] = None,
    position: Any = None,
    velocity: Any = None,
    wheel_speeds: Any = None,
    input: Any = None,
    controller: Any = None,
    sample_period: Optional[float] = None,
) -> MonteCarloResult:
    """Runs ``members`` members of ``system`` (any built-in system:
    :class:`lgsvi.RigidBody`, :class:`lgsvi.HeavyTop`, :class:`lgsvi.FreeBody`,
    :class:`lgsvi.OrbitingBody`, :class:`lgsvi.Gyrostat`) from the nominal start
    ``(attitude, omega)`` (and ``position``, ``velocity`` in space, ``wheel_speeds`` of a
    gyrostat), each with its own draws of ``dispersions`` (module documentation), to
    ``t_end`` with steps ``h`` of ``nodes`` nodes (every member the same steps, so that all
    share the sample times).

    Parameters
    ----------
    samples : int
        Sample times of the percentile envelopes, 2 to 10000, evenly spaced in steps.
    stop_when : str, optional
        Stop each member after the step in which a quantity falls below (``<``) or rises
        above (``>``) a value, as ``lgsvi simulate --stop-when``: ``"omega<0.01"``,
        ``"angle>90"`` (degrees turned from the start), ``"omega_3<0"``. The crossing's
        time (located on the step's curve and refined by the method's own steps) is in
        ``t_stop``; :meth:`MonteCarloResult.stop_statistics` summarises them.
        ``"wheel_1>300"`` is a wheel speed limit.
    settle_when : str, optional
        A settling condition, as ``lgsvi montecarlo --settle-when``: each member's
        ``t_settle`` is the time from which it holds to the member's end (the last crossing
        into it, or the start), NaN where it does not hold at the end; e.g.
        ``"omega<0.001"``, or ``"error<0.1"`` (the pointing error, degrees from the target
        of the system's ``attitude_gain`` law, stays below 0.1°).
        :meth:`MonteCarloResult.settle_statistics` summarises them.
    input : array_like, optional
        A constant control input for every member, as :meth:`lgsvi.Integrator.set_input`
        takes it (a gyrostat's ``(body torque, wheel motor torques)``).
    controller : lgsvi.control.PdLaw, optional
        A sampled controller in the loop of every member (the same gains for all): its
        torque, formed from the member's state every ``sample_period`` from the start, is
        held until the next sample (zero-order hold) and limited by its ``torque_limit``,
        as a flight computer runs it. ``"error"`` in the conditions and the ``error_deg``
        envelope are measured from its target. Not with ``input``, a gyrostat, or a
        system with an attitude law of its own (``attitude_gain``, ``target``); a
        system's ``damping`` acts beside it, as a physical damping.
    sample_period : float, optional
        The controller's period, a whole number of steps ``h``; needed with
        ``controller``.
    threads : int, optional
        Threads per process (default: one per core locally, one per task on a cluster,
        whose workers run tasks side by side).
    client : dask.distributed.Client, optional
        Runs the members in chunks of ``chunk_size`` (default 500) as tasks on the client's
        cluster; the result is the local run's, bit for bit. Each worker needs ``lgsvi``
        installed.

    A member that fails (Newton, a chart's reach) is listed in ``errors`` with its
    exception, never dropped; the others stand.

    Raises
    ------
    InvalidInputError
        For members < 1, a bad spec (its message names the key), a dispersion of a
        quantity the system lacks (a torque on a gyrostat, a mass on a free rigid body), a
        non-physical dispersion, a start or condition the system lacks, bad settings.
    """
    if isinstance(members, bool) or not isinstance(members, (int, np.integer)) or members < 1:
        raise _lgsvi.InvalidInputError(f"members must be an int >= 1, got {members!r}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 2**64:
        raise _lgsvi.InvalidInputError(f"seed must be an int in [0, 2**64), got {seed!r}")
    members, seed = int(members), int(seed)
    spec = _spec_json(dispersions)
    attitude = np.asarray(attitude, dtype=float)
    omega = np.asarray(omega, dtype=float)
    common = dict(
        chart=chart,
        matching=matching,
        stop_when=stop_when,
        settle_when=settle_when,
        position=position,
        velocity=velocity,
        wheel_speeds=wheel_speeds,
        input=input,
        controller=controller,
        sample_period=None if sample_period is None else float(sample_period),
    )
    args = (system, attitude, omega, spec, seed)
    settings = (float(t_end), float(h), int(nodes), int(samples))
    if client is None:
        fields = _lgsvi._montecarlo_chunk(
            *args, 0, members, *settings, threads=threads, **common
        )
        return _combine([fields], seed)
    size = DEFAULT_CHUNK if chunk_size is None else int(chunk_size)
    if size < 1:
        raise _lgsvi.InvalidInputError(f"chunk_size must be >= 1, got {chunk_size!r}")
    # One thread per task by default: a worker runs as many tasks at once as it has
    # threads, each releasing the GIL.
    per_task = 1 if threads is None else threads
    # Check the spec and settings here, on a single member, before a cluster runs them.
    _lgsvi._montecarlo_chunk(*args, 0, 0, *settings, threads=1, **common)
    futures = [
        client.submit(
            _lgsvi._montecarlo_chunk,
            *args,
            a,
            b,
            *settings,
            threads=per_task,
            pure=False,
            **common,
        )
        for a, b in _ranges(members, size)
    ]
    return _combine(client.gather(futures), seed)
