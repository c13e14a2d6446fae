"""Events: zero crossings of a function of the state, located on each step's curve."""

from __future__ import annotations

from typing import Any, Callable, NamedTuple, Optional

from . import _lgsvi

_DIRECTIONS = ("rising", "falling", "either")


class Event:
    """A zero crossing to locate during :meth:`Integrator.run_until` (``events=[...]``).

    Parameters
    ----------
    function : callable
        ``function(state) -> float`` of a :class:`State` (its ``t``, ``attitude``,
        ``omega``, ``position``, ``wheel_speeds``...). Called at ``n + 1`` points of every
        step's curve, and more where it changes sign.
    direction : str
        ``"rising"`` (from negative to zero or positive), ``"falling"`` or ``"either"``.
    terminal : bool
        The first crossing stops the run, after the step that holds it.
    name : str, optional
        For the hits (default: the function's name).

    Each step's crossings are located on its Galerkin curve (the dense output): the
    function is sampled along the step, and where it changes sign in the event's direction
    it is fitted by a Chebyshev series to machine precision and its root taken, so the time
    is the curve's own crossing to a few ulps. Two crossings closer than ``h / n`` may be
    missed. An exception raised by ``function`` ends the run and is raised as it is.

    Example::

        import numpy as np
        import lgsvi

        body = lgsvi.RigidBody([1.0, 1.0, 2.0])
        it = lgsvi.Integrator(body, 0.25, 12, omega=[0.3, 0.0, 1.5])
        stop = lgsvi.Event(lambda s: s.omega[0], direction="falling", terminal=True)
        trajectory = it.run_until(10.0, events=[stop])
        trajectory.events[0].t        # pi / 3: omega_1 = 0.3 cos(1.5 t)
    """

    __slots__ = ("function", "direction", "terminal", "name")

    def __init__(
        self,
        function: Callable[[Any], float],
        direction: str = "either",
        terminal: bool = False,
        name: Optional[str] = None,
    ) -> None:
        if not callable(function):
            raise _lgsvi.InvalidInputError("function must be callable: a function of a State")
        if direction not in _DIRECTIONS:
            raise _lgsvi.InvalidInputError(
                f'direction must be "rising", "falling" or "either", got {direction!r}'
            )
        self.function = function
        self.direction = direction
        self.terminal = bool(terminal)
        self.name = name if name is not None else getattr(function, "__name__", "event")

    def __repr__(self) -> str:
        return (
            f"Event({self.name!r}, direction={self.direction!r}, terminal={self.terminal})"
        )


class EventHit(NamedTuple):
    """A located crossing: which event (its index in the list and its name), the time,
    whether the function rose or fell through zero, and the state on the curve there."""

    event: int
    name: str
    t: float
    direction: str
    state: Any
