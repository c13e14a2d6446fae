"""Lie group spectral variational integrators for rotating and moving bodies.

A variational integrator keeps what the physics keeps: momenta (exactly, by discrete
Noether), the symplectic form, a bounded energy error over millions of steps; on SO(3) and
SE(3) it stays exactly on the group. lgsvi's steps are spectral: each step's curve is a
Chebyshev polynomial in a natural chart, so adding nodes makes the error fall geometrically
at a fixed, large step.

Systems: :class:`RigidBody`, :class:`HeavyTop` (SO(3)), :class:`FreeBody`,
:class:`OrbitingBody` (SE(3)), :class:`Gyrostat` (reaction wheels). Integration:
:class:`Integrator` (``step``, ``run_until`` to a horizon or a tolerance, with
:class:`Event` zero crossings located on the steps' curves, ``linearize``, dense output), :func:`run_ensemble`, :mod:`lgsvi.montecarlo` (dispersion analysis, locally or on a
Dask cluster), :mod:`lgsvi.optimal` (minimum-energy slews). Control: :mod:`lgsvi.control`. Foundations:
:mod:`lgsvi.quadrature`, :mod:`lgsvi.chebyshev`, :mod:`lgsvi.lie`. Errors:
:class:`LgsviError` and its subclasses.

Conventions: ``R`` maps body to world (``world_from_body``), ``omega`` is the body angular
velocity (``dR/dt = R hat(omega)``), positions and velocities of bodies in space are in the
world frame, matrices are row-major ndarrays, quaternions ``(w, x, y, z)``.
"""

from ._lgsvi import (
    ChartError,
    ConvergenceError,
    Curve,
    FreeBody,
    Gyrostat,
    HeavyTop,
    Integrator,
    InternalError,
    InvalidInputError,
    LgsviError,
    ModelError,
    OrbitingBody,
    RigidBody,
    State,
    System,
    ToleranceError,
    __version__,
)
from ._events import Event, EventHit
from ._trajectory import EnsembleResult, Trajectory
from ._ensemble import run_ensemble
from . import chebyshev, control, lie, montecarlo, optimal, quadrature

__all__ = [
    "ChartError",
    "ConvergenceError",
    "Curve",
    "EnsembleResult",
    "Event",
    "EventHit",
    "FreeBody",
    "Gyrostat",
    "HeavyTop",
    "Integrator",
    "InternalError",
    "InvalidInputError",
    "LgsviError",
    "ModelError",
    "OrbitingBody",
    "RigidBody",
    "State",
    "System",
    "ToleranceError",
    "Trajectory",
    "chebyshev",
    "control",
    "lie",
    "montecarlo",
    "optimal",
    "quadrature",
    "run_ensemble",
    "__version__",
]
