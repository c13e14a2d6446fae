"""Many initial conditions of one system, in parallel."""

from __future__ import annotations

from typing import Any, Optional

from . import _lgsvi
from ._trajectory import EnsembleResult


def run_ensemble(
    system: Any,
    h: float,
    nodes: int,
    attitudes: Any,
    omegas: Any,
    t_end: float,
    *,
    positions: Optional[Any] = None,
    velocities: Optional[Any] = None,
    wheel_speeds: Optional[Any] = None,
    chart: str = "exp",
    matching: str = "exact",
    threads: Optional[int] = None,
) -> EnsembleResult:
    """Runs every member ``i`` from ``(attitudes[i], omegas[i])`` (and, for bodies in
    space, ``positions[i]``, ``velocities[i]``; for a gyrostat ``wheel_speeds[i]``) to
    ``t_end`` with steps ``h`` of ``nodes`` nodes, in parallel with the GIL released, and
    returns their final states (:class:`EnsembleResult`). A member that fails is reported
    in ``errors`` with its exception; the others' results stand. Each member's result is
    bit for bit what an :class:`Integrator` of the same settings gives, whatever the
    number of threads.
    """
    fields = _lgsvi._run_ensemble(
        system,
        h,
        nodes,
        attitudes,
        omegas,
        t_end,
        positions=positions,
        velocities=velocities,
        wheel_speeds=wheel_speeds,
        chart=chart,
        matching=matching,
        threads=threads,
    )
    return EnsembleResult(**fields)
