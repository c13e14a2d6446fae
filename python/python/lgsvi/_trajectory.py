"""Results as ndarrays: :class:`Trajectory` (one run) and :class:`EnsembleResult` (many)."""

from __future__ import annotations

from typing import Any, Dict, List

import numpy as np

_ARRAYS = (
    "t",
    "attitude",
    "quaternion",
    "omega",
    "momentum",
    "energy",
    "spatial_momentum",
    "position",
    "velocity",
    "linear_momentum",
    "wheel_angles",
    "wheel_speeds",
    "newton_iterations",
)


class Trajectory:
    """A recorded run: one row per recorded state, every field an ndarray.

    Attributes
    ----------
    t : ndarray (N,)
        Times.
    attitude : ndarray (N, 3, 3)
        ``R = world_from_body``.
    quaternion : ndarray (N, 4)
        The attitude as ``(w, x, y, z)``, ``w >= 0``.
    omega : ndarray (N, 3)
        Body angular velocity.
    momentum : ndarray (N, D)
        Body momentum ``mu = dl/dxi``.
    energy : ndarray (N,)
        ``<mu, xi> - l``.
    spatial_momentum : ndarray (N, 3)
        Angular momentum in the world frame (about the origin for a body in space).
    position, velocity, linear_momentum : ndarray (N, 3) or None
        Bodies in space: centre of mass, its velocity and ``m xdot``, world frame.
    wheel_angles, wheel_speeds : ndarray (N, K) or None
        A gyrostat's wheels, relative to the body.
    newton_iterations : ndarray (N,)
        Newton iterations of the step that reached each state (0 for the start).
    events : list of EventHit
        The crossings of ``run_until(events=...)``, in time order (``stats
        ["stopped_by_event"]`` says whether a terminal one ended the run).
    stats : dict
        The run's ``steps``, ``newton_iterations``, ``max_newton_iterations``,
        ``factorizations``, ``rejected_steps``, ``wall_time_s`` (the integration alone),
        ``nodes_histogram`` ({n: steps}), ``work`` (the forces' work since the start),
        ``estimated_error`` (a tolerance run's measured difference from its companion, else
        the sum of the steps' local estimates since the start: a model, not a bound) and,
        for a tolerance run, ``check`` (what the companion measured).
    """

    __slots__ = _ARRAYS + ("stats", "events")

    def __init__(self, **fields: Any) -> None:
        from ._events import EventHit

        for name in _ARRAYS:
            setattr(self, name, fields.get(name))
        self.stats: Dict[str, Any] = dict(fields.get("stats", {}))
        self.events: List[EventHit] = [
            hit if isinstance(hit, EventHit) else EventHit(*hit) for hit in fields.get("events", [])
        ]

    def __len__(self) -> int:
        return len(self.t)

    def __getitem__(self, index: Any) -> "Trajectory":
        """The rows ``index`` (an int, a slice or a mask) as a trajectory."""
        if isinstance(index, (int, np.integer)):
            index = slice(index, index + 1 if index != -1 else None)
        fields = {
            name: (None if getattr(self, name) is None else getattr(self, name)[index])
            for name in _ARRAYS
        }
        return Trajectory(stats=self.stats, events=self.events, **fields)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Trajectory):
            return NotImplemented
        for name in _ARRAYS:
            a, b = getattr(self, name), getattr(other, name)
            if (a is None) != (b is None):
                return False
            if a is not None and not np.array_equal(a, b):
                return False
        return True

    def __getstate__(self) -> Dict[str, Any]:
        state = {name: getattr(self, name) for name in _ARRAYS}
        state["stats"] = self.stats
        state["events"] = [tuple(hit) for hit in self.events]
        return state

    def __setstate__(self, state: Dict[str, Any]) -> None:
        for name in _ARRAYS:
            setattr(self, name, state.get(name))
        self.stats = state.get("stats", {})
        from ._events import EventHit

        self.events = [EventHit(*hit) for hit in state.get("events", [])]

    def __repr__(self) -> str:
        span = f"t = {self.t[0]:g} ... {self.t[-1]:g}" if len(self.t) else "empty"
        return f"Trajectory({len(self.t)} states, {span})"


class EnsembleResult:
    """The final states of :func:`lgsvi.run_ensemble`'s members, one row each.

    Attributes
    ----------
    t, attitude, omega, momentum, spatial_momentum, energy : ndarray
        As :class:`Trajectory`'s, one row per member (NaN for a failed member).
    position, velocity : ndarray (M, 3) or None
        Bodies in space.
    wheel_speeds, wheel_angles : ndarray (M, K) or None
        Gyrostats.
    ok : ndarray (M,) of bool
        Which members reached the end.
    errors : dict
        Each failed member's index and its exception (an :class:`lgsvi.LgsviError`, not
        raised: the other members' results stand).
    """

    __slots__ = (
        "t",
        "attitude",
        "omega",
        "momentum",
        "spatial_momentum",
        "energy",
        "position",
        "velocity",
        "wheel_speeds",
        "wheel_angles",
        "ok",
        "errors",
    )

    def __init__(self, **fields: Any) -> None:
        for name in self.__slots__:
            setattr(self, name, fields.get(name))
        if self.errors is None:
            self.errors = {}

    def __len__(self) -> int:
        return len(self.ok)

    def __getstate__(self) -> Dict[str, Any]:
        return {name: getattr(self, name) for name in self.__slots__}

    def __setstate__(self, state: Dict[str, Any]) -> None:
        for name in self.__slots__:
            setattr(self, name, state.get(name))

    def __repr__(self) -> str:
        failed = len(self.errors)
        return f"EnsembleResult({len(self.ok)} members, {failed} failed)"
