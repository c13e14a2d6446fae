"""Optimal control on the group with lgsvi's variational step as the dynamics: a rigid
body's slew at the least input energy in a fixed time, or in the least time, the torques
bounded per axis (per wheel for the motor torques of a spacecraft's three reaction wheels);
a heavy top's, or a spacecraft's by its wheels, likewise (:func:`slew`); and a body in
space's manoeuvre, its attitude and centre of mass driven by a body wrench at the least
input energy or in the least time (:func:`manoeuvre`).

The problem: ``K`` steps of a common length ``h`` (each one lgsvi step of ``nodes``
nodes), the body torque ``u_k`` held over step ``k``; from ``(attitude0, omega0)`` to
``(attitude_final, omega_final)`` with ``|u_k,i| <= torque_max_i``, minimise either
``sum_k h |u_k|^2`` (the integral of ``|u|^2``, no 1/2) with ``h = t_end / K``
(``cost="energy"``) or the final time ``K h`` (``cost="time"``; ``t_end`` is then a first
guess). Solved by sequential quadratic programming over the torques (and ``h``) with the
steps' exact Jacobians and clarabel for the QP subproblems, to a scaled KKT residual of
``tolerance``: for the energy, Gauss-Newton (the cost's Hessian is exact, the dynamics'
curvature is left out); for the time, the Lagrangian's Hessian by differences of its exact
gradient on the torques off their bounds. The states are the integrator's own: an
:class:`lgsvi.Integrator` driven with the optimal torques (``set_input`` then ``step``,
the result's ``h`` and ``nodes`` the same) lands on the target.

With the torque constant over each step the optimal cost converges to the continuous one
at second order in ``h``, whatever the integrator's order.

Example::

    import numpy as np
    from lgsvi import lie, optimal

    result = optimal.slew([3.0, 4.0, 5.5], 30.0, lie.so3_exp([1.5, 0.4, -0.9]),
                          steps=30, torque_max=0.06)
    result.cost, result.inputs.shape     # (30, 3)

    # Betts's minimum-time reorientation: 150 degrees about x, |u_i| <= 50 N m.
    fastest = optimal.slew([5621.0, 4547.0, 2364.0], None, lie.so3_exp([np.radians(150), 0, 0]),
                           steps=100, nodes=8, torque_max=50.0, cost="time")
    fastest.t_end                        # 28.6325..., the published 28.6304077 to 7.5e-5
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np

from . import _lgsvi

__all__ = ["InfeasibleError", "ManoeuvreResult", "SlewResult", "manoeuvre", "slew"]

InfeasibleError = _lgsvi.InfeasibleError


class SlewResult:
    """A solved slew.

    Attributes
    ----------
    cost : float
        ``sum_k h |u_k|^2`` for ``cost="energy"``, the final time for ``cost="time"``.
    t : ndarray (K+1,)
        The step boundaries' times.
    attitude : ndarray (K+1, 3, 3)
        ``R_k``, body to world.
    omega : ndarray (K+1, 3)
        The body rates at the step boundaries.
    wheel_speeds : ndarray (K+1, 3)
        With ``wheels``, the wheels' rates relative to the body at the step boundaries;
        ``(0, 3)`` otherwise.
    inputs : ndarray (K, 3)
        The torque of each step (body frame, N m; with ``wheels``, the three motor torques;
        a ``disturbance`` not included); with ``inputs="polynomial"`` each step's
        mean over its Gauss points (the constant torque of the same impulse).
    inputs_at_points : ndarray (K, m, 3)
        With ``inputs="polynomial"``, each step's torques at its ``m`` Gauss points, which
        replay through :meth:`lgsvi.Integrator.set_input_at_points`; ``(0, 0, 3)``
        otherwise.
    quadrature_nodes : ndarray (m,)
        The Gauss points as fractions of a step.
    multipliers : ndarray (6,)
        The terminal constraint's multipliers, ``dJ*/de`` (``dT*/de`` with ``cost="time"``)
        for the miss ``e`` = (``log(R_K^T R_f)``, ``Omega_f - Omega_K``), body frame.
    h, t_end : float
        The step and the duration (for ``cost="time"`` the least time found).
    converged : bool
    iterations : int
        SQP iterations.
    kkt_residuals : ndarray
        The scaled KKT residual at each iterate.
    time_s : float
        The solve's wall time.
    """

    __slots__ = (
        "cost", "t", "attitude", "omega", "wheel_speeds", "inputs", "inputs_at_points", "quadrature_nodes",
        "multipliers", "h", "t_end",
        "converged", "iterations", "kkt_residuals", "time_s",
    )

    def __init__(self, **fields: Any) -> None:
        for name in self.__slots__:
            setattr(self, name, fields[name])

    def __repr__(self) -> str:
        return (
            f"SlewResult(cost={self.cost:.6e}, steps={len(self.inputs)}, "
            f"iterations={self.iterations}, converged={self.converged})"
        )


def slew(
    inertia: Any,
    t_end: Optional[float],
    attitude_final: Any,
    *,
    attitude0: Optional[Any] = None,
    omega0: Optional[Any] = None,
    omega_final: Optional[Any] = None,
    steps: int = 40,
    nodes: int = 10,
    torque_max: Optional[Any] = None,
    tolerance: float = 1e-10,
    max_iterations: int = 100,
    warm_start: Optional[Any] = None,
    cost: str = "energy",
    inputs: str = "constant",
    track: Optional[Any] = None,
    terminal_cost: Optional[Any] = None,
    gravity: Optional[float] = None,
    mass: float = 1.0,
    com: Optional[Any] = None,
    gravity_direction: Optional[Any] = None,
    wheels: Optional[Any] = None,
    wheel_inertia: Optional[Any] = None,
    wheel_speeds0: Optional[Any] = None,
    disturbance: Optional[Any] = None,
) -> SlewResult:
    """The slew of the body of principal moments ``inertia`` (3,) to ``attitude_final``
    (3, 3) and ``omega_final`` (default rest), from ``attitude0`` (default identity) and
    ``omega0`` (default rest), in ``steps`` steps of ``nodes`` nodes; ``torque_max`` a bound
    for every axis or one per axis (N m); ``warm_start`` (K, 3) torques to start from.

    ``cost="energy"`` (the default) minimises the input energy in the time ``t_end`` (s);
    ``cost="time"`` minimises the final time, needs ``torque_max``, and takes ``t_end`` as
    a first guess (``None``: the bang-bang turn about the rotation's axis).

    ``inputs="constant"`` holds the torque over each step (the optimal cost converges at
    second order in ``h``); ``inputs="polynomial"`` (energy cost only) makes it a
    polynomial within each step, given at the step's Gauss points, and the cost converges
    at the integrator's order ``2 (nodes - 1)``.

    ``track=(attitudes, omegas, [q_theta, q_omega])`` (``(K, 3, 3)``, ``(K, 3)``, one state per
    step boundary after the start) adds ``sum_k h (q_theta |log(R_ref^T R_k)|^2 +
    q_omega |Omega_k - Omega_ref|^2)``; ``terminal_cost=[q_theta, q_omega]`` replaces the exact
    terminal state by ``q_theta |log(R_f^T R_K)|^2 + q_omega |Omega_K - Omega_f|^2`` (energy
    cost only; Gauss-Newton on the least squares).

    ``gravity=g`` makes the body a heavy top about its fixed point (as
    :class:`lgsvi.HeavyTop`: ``l = 1/2 Omega^T J Omega + m g d^T R rho``) of ``mass`` (default
    1), centre of mass ``com`` (body frame, default ``(0, 0, 1)``) and gravity pulling along
    ``gravity_direction`` (world frame, default ``(0, 0, 1)``). The torques
    then also hold it against gravity.

    ``wheels`` (3, 3), three wheel axes in the body frame (one per row), slews a spacecraft
    by its reaction wheels (as :class:`lgsvi.Gyrostat`): the torques solved for (and bounded
    by ``torque_max``) are then the wheels' motor torques, ``inertia`` the spacecraft's with
    its wheels locked, ``wheel_inertia`` the wheels' axial inertias (one for all or three;
    default 0.05) and ``wheel_speeds0`` their rates relative to the body at the start
    (default rest; the final rates are free). Without gravity.

    ``disturbance`` (3,), a constant torque on the body (body frame, N m): a known
    disturbance (solar pressure, outgassing, a mean gravity-gradient torque) that the
    torques, or with ``wheels`` the motors, work against (the wheels then take up its
    momentum). It is not part of the cost nor of the result's ``inputs``: a replay adds it
    to them (with wheels, as the gyrostat's first three input entries).

    Raises
    ------
    InvalidInputError
        A setting out of range, named.
    InfeasibleError
        No torques within the bounds reach the target in the time.
    ConvergenceError
        The iterations ran out (the message gives the residual reached).
    """
    fields = _lgsvi._slew(
        inertia,
        t_end,
        attitude_final,
        attitude0=attitude0,
        omega0=omega0,
        omega_final=omega_final,
        steps=steps,
        nodes=nodes,
        torque_max=torque_max,
        tolerance=tolerance,
        max_iterations=max_iterations,
        warm_start=warm_start,
        cost=cost,
        inputs=inputs,
        track=track,
        terminal_cost=terminal_cost,
        gravity=gravity,
        mass=mass,
        com=com,
        gravity_direction=gravity_direction,
        wheels=wheels,
        wheel_inertia=wheel_inertia,
        wheel_speeds0=wheel_speeds0,
        disturbance=disturbance,
    )
    return SlewResult(**fields)


class ManoeuvreResult:
    """A solved manoeuvre of a body in space.

    Attributes
    ----------
    cost : float
        ``sum_k h |u_k|^2``, the integral of ``|tau|^2 + |f|^2`` (no 1/2); with
        ``cost="time"`` the final time (s).
    t : ndarray (K+1,)
        The step boundaries' times.
    attitude : ndarray (K+1, 3, 3)
        ``R_k``, body to world.
    position : ndarray (K+1, 3)
        The centre of mass, world frame.
    omega : ndarray (K+1, 3)
        The body rates.
    velocity : ndarray (K+1, 3)
        The centre of mass's velocity, world frame.
    inputs : ndarray (K, 6)
        Each step's body wrench ``(tau, f)`` (body frame, N m and N; a disturbance not
        included); with ``inputs="polynomial"`` its mean over the step's Gauss points.
    inputs_at_points : ndarray (K, m, 6)
        With ``inputs="polynomial"``, each step's wrenches at its ``m`` Gauss points, which
        replay through :meth:`lgsvi.Integrator.set_input_at_points`; ``(0, 0, 6)`` otherwise.
    quadrature_nodes : ndarray (m,)
        The Gauss points as fractions of a step.
    multipliers : ndarray (12,)
        The terminal constraint's multipliers, ``dJ*/de`` (``dT*/de`` with
        ``cost="time"``) for the miss ``e`` = (attitude
        ``log(R_K^T R_f)``, position ``x_f - x_K`` in the world frame, body rates
        ``Omega_f - Omega_K``, velocity ``xdot_f - xdot_K`` in the world frame).
    h, t_end : float
        The step and the duration.
    converged : bool
    iterations : int
        SQP iterations.
    kkt_residuals : ndarray
        The scaled KKT residual at each iterate.
    time_s : float
        The solve's wall time.
    """

    __slots__ = (
        "cost", "t", "attitude", "position", "omega", "velocity", "inputs", "inputs_at_points",
        "quadrature_nodes", "multipliers", "h", "t_end", "converged", "iterations",
        "kkt_residuals", "time_s",
    )

    def __init__(self, **fields: Any) -> None:
        for name in self.__slots__:
            setattr(self, name, fields[name])

    def __repr__(self) -> str:
        return (
            f"ManoeuvreResult(cost={self.cost:.6e}, steps={len(self.inputs)}, "
            f"iterations={self.iterations}, converged={self.converged})"
        )


def manoeuvre(
    inertia: Any,
    mass: float,
    t_end: Optional[float] = None,
    *,
    attitude_final: Optional[Any] = None,
    position_final: Optional[Any] = None,
    attitude0: Optional[Any] = None,
    position0: Optional[Any] = None,
    omega0: Optional[Any] = None,
    velocity0: Optional[Any] = None,
    omega_final: Optional[Any] = None,
    velocity_final: Optional[Any] = None,
    mu: Optional[float] = None,
    steps: int = 40,
    nodes: int = 10,
    torque_max: Optional[Any] = None,
    force_max: Optional[Any] = None,
    tolerance: float = 1e-10,
    max_iterations: int = 500,
    warm_start: Optional[Any] = None,
    inputs: str = "constant",
    track: Optional[Any] = None,
    terminal_cost: Optional[Any] = None,
    cost: str = "energy",
    disturbance: Optional[Any] = None,
    disturbance_force: Optional[Any] = None,
) -> ManoeuvreResult:
    """The manoeuvre of a rigid body in space of principal moments ``inertia`` (3,) and
    ``mass``, in the time ``t_end`` (s), at the least ``integral of |tau|^2 + |f|^2 dt``:
    driven by a body wrench ``(tau, f)`` (torque and force, both in the body frame) from
    ``attitude0`` (3, 3; default identity), ``position0`` (world frame; default the origin),
    ``omega0`` (body rates) and ``velocity0`` (the centre of mass's, world frame; both
    default rest) to ``attitude_final`` (default the start's), ``position_final`` (default
    the start's), ``omega_final`` and ``velocity_final`` (default rest). ``mu`` makes the
    body orbit a point mass of gravitational parameter ``mu`` at the origin (as
    :class:`lgsvi.OrbitingBody`); without it the body is free (:class:`lgsvi.FreeBody`).

    ``steps`` steps of ``nodes`` nodes; ``torque_max`` and ``force_max`` bound each body
    axis (one number for all three, or three); ``inputs="polynomial"`` makes the wrench a
    polynomial within each step (given at its Gauss points), ``"constant"`` holds it over
    each step; ``warm_start`` (K, 6) or (K m, 6) wrenches to start from.

    ``track=(attitudes, positions, omegas, velocities, [q_theta, q_x, q_omega, q_v])``
    (``(K, 3, 3)``, ``(K, 3)`` each, one state per step boundary after the start, positions
    and velocities in the world frame) adds ``h sum_k (q_theta |log(R_ref^T R_k)|^2 +
    q_x |x_k - x_ref|^2 + q_omega |Omega_k - Omega_ref|^2 + q_v |xdot_k - xdot_ref|^2)``;
    ``terminal_cost=[q_theta, q_x, q_omega, q_v]`` replaces the exact target by the same
    terms at the last state (a soft target; the multipliers are then zero).

    ``cost="energy"`` (the default) minimises the input energy in the time ``t_end``;
    ``cost="time"`` minimises the final time, needs ``torque_max`` and ``force_max``, holds
    the wrench over each step (the optimum is bang-bang), is built without ``track`` or
    ``terminal_cost``, and takes ``t_end`` as the first guess (default: the longest of the eigen-axis turn's, the straight move's and the
    velocity changes' bang-bang times at the weakest bounds).

    At the least energy it is solved by the slew's SQP with the body force measured in the
    world frame, which converges in about as many iterations as a slew however large the
    translation's share of the cost, with ``force_max`` or without. In the least time it is the slew's minimum-time SQP (the exact Lagrangian Hessian
    by differences of the exact gradient).

    ``disturbance`` and ``disturbance_force`` (3,) each, a constant torque (N m) and force
    (N) on the body, body frame: a known disturbance wrench (solar pressure, a leak, a
    thruster's misalignment) that the wrench works against. It is not part of the cost nor
    of the result's ``inputs``: a replay adds it to them.

    Raises
    ------
    InvalidInputError
        A setting out of range, named.
    InfeasibleError
        No wrenches within the bounds reach the target in the time.
    ConvergenceError
        The iterations ran out (the message gives the residual reached).
    """
    fields = _lgsvi._manoeuvre(
        inertia,
        mass,
        t_end,
        attitude_final=attitude_final,
        position_final=position_final,
        attitude0=attitude0,
        position0=position0,
        omega0=omega0,
        velocity0=velocity0,
        omega_final=omega_final,
        velocity_final=velocity_final,
        mu=mu,
        steps=steps,
        nodes=nodes,
        torque_max=torque_max,
        force_max=force_max,
        tolerance=tolerance,
        max_iterations=max_iterations,
        warm_start=warm_start,
        inputs=inputs,
        track=track,
        terminal_cost=terminal_cost,
        cost=cost,
        disturbance=disturbance,
        disturbance_force=disturbance_force,
    )
    return ManoeuvreResult(**fields)
