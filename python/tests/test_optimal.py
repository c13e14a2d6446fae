"""Minimum-energy slews from Python: the spherical body's single-axis turn against the
continuous optimum 12 j^2 theta^2 / T^3 (above it by the zero-order hold's O(h^2)), the
replay of the torques by an Integrator onto the target, bounds, and errors."""

import numpy as np
import pytest

import lgsvi
from lgsvi import lie, optimal


def test_single_axis_turn_converges_at_second_order():
    j, theta, t_end = 2.0, 1.2, 10.0
    continuous = 12 * j * j * theta**2 / t_end**3
    target = lie.so3_exp(np.array([1.0, 2.0, 2.0]) / 3 * theta)
    errors = [
        (optimal.slew([j] * 3, t_end, target, steps=k, nodes=6).cost - continuous) / continuous
        for k in (20, 40)
    ]
    # Measured 2.506e-3 and 6.254e-4 (docs/guide/optimal.md): the ratio is 4 to 1%.
    assert errors[0] > 0 and abs(np.log2(errors[0] / errors[1]) - 2) < 0.02


def test_the_torques_replay_onto_the_target():
    target = lie.so3_exp([1.5, 0.4, -0.9])
    result = optimal.slew([3.0, 4.0, 5.5], 30.0, target, steps=30, torque_max=0.06,
                          omega_final=[0.0, 0.01, 0.0])
    assert result.converged and result.kkt_residuals[-1] <= 1e-10
    assert np.abs(result.inputs).max() <= 0.06 + 1e-12
    it = lgsvi.Integrator(lgsvi.RigidBody([3.0, 4.0, 5.5]), result.h, 10)
    for u in result.inputs:
        it.set_input(u)
        it.step()
    miss = lie.so3_log(it.state.attitude.T @ target)
    assert np.abs(miss).max() <= 1e-10
    assert np.abs(it.state.omega - [0.0, 0.01, 0.0]).max() <= 1e-10
    assert result.attitude.shape == (31, 3, 3) and result.t[-1] == pytest.approx(30.0)


def test_errors():
    target = lie.so3_exp([0.0, 0.0, 1.0])
    with pytest.raises(optimal.InfeasibleError, match="infeasible"):
        optimal.slew([3.0, 4.0, 5.0], 10.0, target, steps=20, torque_max=0.05)
    with pytest.raises(lgsvi.InvalidInputError, match="t_end"):
        optimal.slew([3.0, 4.0, 5.0], -1.0, target)
    with pytest.raises(lgsvi.InvalidInputError, match="inertia"):
        optimal.slew([1.0, 1.0, 5.0], 10.0, target)
    with pytest.raises(lgsvi.ConvergenceError, match="not converged"):
        optimal.slew([3.0, 4.0, 5.5], 10.0, lie.so3_exp([1.5, 0.4, -0.9]), max_iterations=1)
    assert issubclass(optimal.InfeasibleError, lgsvi.LgsviError)


def test_minimum_time_matches_the_published_reorientation():
    # Betts's problem (Fleming, Sekhavat & Ross 2008): t_f* = 28.6304077 s; the discrete
    # optimum with the torque constant per step lies above it by O(h^2): 7.5e-5 relative
    # at 100 steps (docs/guide/optimal.md). The first guess of the time is the library's own.
    target = lie.so3_exp([np.radians(150.0), 0.0, 0.0])
    result = optimal.slew([5621.0, 4547.0, 2364.0], None, target, steps=100, nodes=8,
                          torque_max=50.0, cost="time")
    error = (result.t_end - 28.6304077) / 28.6304077
    assert result.converged and 0 < error < 1e-4
    assert result.cost == result.t_end and result.t[-1] == pytest.approx(result.t_end)
    assert np.abs(result.inputs).max() == 50.0
    # Replayed at the solution's step, the torques land on the target at rest.
    it = lgsvi.Integrator(lgsvi.RigidBody([5621.0, 4547.0, 2364.0]), result.h, 8)
    for u in result.inputs:
        it.set_input(u)
        it.step()
    assert np.abs(lie.so3_log(it.state.attitude.T @ target)).max() <= 1e-10
    assert np.abs(it.state.omega).max() <= 1e-10


def test_minimum_time_errors():
    target = lie.so3_exp([0.0, 0.0, 1.0])
    with pytest.raises(lgsvi.InvalidInputError, match="torque_max"):
        optimal.slew([3.0, 4.0, 5.0], None, target, cost="time")
    with pytest.raises(lgsvi.InvalidInputError, match="cost"):
        optimal.slew([3.0, 4.0, 5.0], 10.0, target, cost="fuel")
    with pytest.raises(lgsvi.InvalidInputError, match="t_end"):
        optimal.slew([3.0, 4.0, 5.0], None, target)


def _lands_on(it, result, target):
    """Drives `it` by the slew's torques at the Gauss points: it ends at rest on `target`
    to 1e-10."""
    for u in result.inputs_at_points:
        it.set_input_at_points(u)
        it.step()
    assert np.abs(lie.so3_log(it.state.attitude.T @ target)).max() <= 1e-10
    assert np.abs(it.state.omega).max() <= 1e-10


def test_polynomial_inputs_meet_pontryagins_optimum():
    # The indirect (Pontryagin) reference of optimal/tests/data/pontryagin_slew.py; with the
    # torque a polynomial within each step the cost converges at the integrator's order:
    # 8 nodes and 10 steps meet it to 7e-14 (docs/guide/optimal.md), here to 1e-9.
    import json
    import pathlib

    data = pathlib.Path(__file__).resolve().parents[2] / "optimal/tests/data/pontryagin_slew.json"
    reference = json.loads(data.read_text())
    target = lie.so3_exp(reference["attitude_final"])
    result = optimal.slew(reference["inertia"], reference["t_end"], target, steps=10, nodes=8,
                          inputs="polynomial")
    assert abs(result.cost - reference["cost"]) <= 1e-9 * reference["cost"]
    m = len(result.quadrature_nodes)
    assert result.inputs_at_points.shape == (10, m, 3)
    # Replay through the inputs at the Gauss points.
    it = lgsvi.Integrator(lgsvi.RigidBody(reference["inertia"]), result.h, 8)
    assert np.allclose(it.quadrature_nodes, result.quadrature_nodes, rtol=0, atol=1e-15)
    assert abs(it.quadrature_weights.sum() - 1.0) < 1e-14
    _lands_on(it, result, target)
    with pytest.raises(lgsvi.InvalidInputError, match="inputs"):
        optimal.slew([3.0, 4.0, 5.5], 30.0, target, inputs="quadratic")
    with pytest.raises(lgsvi.InvalidInputError):
        it.set_input_at_points(np.zeros((2, 3)))


def test_a_heavy_tops_slew_meets_pontryagins_optimum():
    # The indirect reference with the gravity torque (optimal/tests/data/pontryagin_slew.py,
    # pontryagin_heavy_top.json): 8 nodes and 10 steps of polynomial torques meet it to
    # 1e-9; the torques replay through lgsvi.HeavyTop's integrator onto the target.
    import json
    import pathlib

    data = pathlib.Path(__file__).resolve().parents[2] / "optimal/tests/data/pontryagin_heavy_top.json"
    ref = json.loads(data.read_text())
    target = lie.so3_exp(ref["attitude_final"])
    result = optimal.slew(ref["inertia"], ref["t_end"], target, steps=10, nodes=8,
                          inputs="polynomial", gravity=ref["gravity"], mass=ref["mass"],
                          com=ref["com"], gravity_direction=ref["gravity_direction"])
    assert abs(result.cost - ref["cost"]) <= 1e-9 * ref["cost"]
    top = lgsvi.HeavyTop(ref["inertia"], mass=ref["mass"], gravity=ref["gravity"], com=ref["com"],
                         gravity_direction=ref["gravity_direction"])
    it = lgsvi.Integrator(top, result.h, 8)
    _lands_on(it, result, target)
    with pytest.raises(lgsvi.InvalidInputError, match="gravity"):
        optimal.slew(ref["inertia"], 30.0, target, mass=2.0)
    # The least time: below it the fixed-time solver finds the target out of reach (started
    # from the least-time torques), above it within reach.
    turn = lie.so3_exp([1.0, 0.0, 0.0])
    heavy = dict(gravity=ref["gravity"], mass=ref["mass"], com=ref["com"],
                 gravity_direction=ref["gravity_direction"], steps=40, nodes=8, torque_max=0.1)
    fastest = optimal.slew(ref["inertia"], 30.0, turn, cost="time", **heavy)
    assert fastest.converged
    optimal.slew(ref["inertia"], fastest.t_end * 1.001, turn, warm_start=fastest.inputs, **heavy)
    with pytest.raises(optimal.InfeasibleError):
        optimal.slew(ref["inertia"], fastest.t_end * 0.999, turn, warm_start=fastest.inputs,
                     **heavy)


def test_tracking_and_a_soft_target():
    # Tracking a rotation about a fixed axis with a soft target: the torques follow; the
    # soft target's miss falls as its weight rises (optimal/tests/tracking.rs has the
    # checks against an independent least squares and the true cost's stationarity).
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    k, t_end, theta = 12, 10.0, 1.2
    attitudes = np.array([lie.so3_exp(axis * theta * (i + 1) / k) for i in range(k)])
    omegas = np.tile(axis * theta / t_end, (k, 1))
    target = lie.so3_exp(axis * theta)
    misses = []
    for q in (1.0, 100.0):
        result = optimal.slew([2.0, 2.0, 2.0], t_end, target, steps=k, nodes=6,
                              track=(attitudes, omegas, [3.0, 0.5]), terminal_cost=[q, q])
        assert result.converged and result.kkt_residuals[-1] <= 1e-10
        misses.append(np.linalg.norm(lie.so3_log(result.attitude[-1].T @ target)))
    assert misses[1] < misses[0]
    with pytest.raises(lgsvi.InvalidInputError, match="track"):
        optimal.slew([2.0, 2.0, 2.0], t_end, target, steps=k,
                     track=(attitudes[:3], omegas[:3], [1.0, 1.0]))


def test_a_slew_by_reaction_wheels_replays_onto_its_target():
    # Wheels along the body axes with J_b = J - I = 2 I: at rest the body turns as a
    # spherical rigid body of inertia 2 under minus the motor torques, so polynomial motor
    # torques meet the single-axis optimum 12 j^2 theta^2 / T^3 to rounding.
    j, i, theta, t_end = 2.0, 0.25, 1.2, 10.0
    target = lie.so3_exp(np.array([1.0, 2.0, 2.0]) / 3 * theta)
    result = optimal.slew([j + i] * 3, t_end, target, steps=5, nodes=6, inputs="polynomial",
                          wheels=np.eye(3), wheel_inertia=i)
    assert result.cost == pytest.approx(12 * j * j * theta**2 / t_end**3, rel=1e-12)
    assert result.wheel_speeds.shape == (6, 3)
    # A biased, bounded slew of an asymmetric craft, replayed by the integrator.
    axes = np.array([[1.0, 0.2, 0.0], [0.0, 1.0, 0.3], [0.2, 0.0, 1.0]])
    target = lie.so3_exp([0.6, -0.4, 0.9])
    result = optimal.slew([8.0, 10.0, 6.0], 30.0, target, steps=30, nodes=8, inputs="polynomial",
                          torque_max=0.05, wheels=axes, wheel_inertia=[0.05] * 3,
                          wheel_speeds0=[20.0, -10.0, 5.0])
    assert result.converged and np.abs(result.inputs_at_points).max() <= 0.05 * (1 + 1e-9)
    craft = lgsvi.Gyrostat(np.diag([8.0, 10.0, 6.0]), axes, [0.05] * 3)
    it = lgsvi.Integrator(craft, result.h, 8, wheel_speeds=[20.0, -10.0, 5.0])
    for step in result.inputs_at_points:
        it.set_input_at_points(np.hstack([np.zeros_like(step), step]))
        it.step()
    # The replay takes the solver's steps: it meets the target to the KKT tolerance.
    assert np.abs(lie.so3_log(it.state.attitude.T @ target)).max() <= 1e-9
    assert np.abs(it.state.omega).max() <= 1e-9
    assert np.abs(it.state.wheel_speeds - result.wheel_speeds[-1]).max() <= 1e-9
    with pytest.raises(lgsvi.InvalidInputError, match="wheels"):
        optimal.slew([8.0, 10.0, 6.0], 30.0, target, wheel_inertia=0.05)
    with pytest.raises(lgsvi.InvalidInputError, match="three wheel axes"):
        optimal.slew([8.0, 10.0, 6.0], 30.0, target, wheels=np.eye(3)[:2])
    # The least time by the same wheels, at rest, is the spherical rigid body's (J - I = 2 I).
    turn = lie.so3_exp([1.2, -0.5, 0.4])
    rigid = optimal.slew([2.0] * 3, None, turn, steps=40, nodes=8, torque_max=0.1, cost="time")
    by_wheels = optimal.slew([2.25] * 3, None, turn, steps=40, nodes=8, torque_max=0.1,
                             cost="time", wheels=np.eye(3), wheel_inertia=0.25)
    assert by_wheels.t_end == pytest.approx(rigid.t_end, rel=1e-8)


def test_wheel_errors_name_the_argument():
    target = lie.so3_exp([0.0, 0.0, 0.5])
    for kwargs, name in [
        (dict(wheels=[[1, 0, 0], [0, 1, 0], [0, 0, 0]]), "wheels"),
        (dict(wheels=np.eye(3), wheel_inertia=0.0), "wheel_inertia"),
        (dict(wheels=np.eye(3), wheel_inertia=float("nan")), "wheel_inertia"),
        (dict(wheels=np.eye(3), wheel_inertia=3.0), "inertia and wheel_inertia"),
        (dict(wheels=[[1, 0, 0], [2, 0, 0], [0, 0, 1]]), "span"),
    ]:
        with pytest.raises(lgsvi.InvalidInputError, match=name):
            optimal.slew([3.0, 4.0, 5.0], 10.0, target, **kwargs)


def test_a_slew_works_against_a_disturbance():
    # Along a spherical body's single-axis turn a disturbance d along the axis leaves the
    # problem in u + d the undisturbed one: the cost grows by |d|^2 T exactly and the
    # torques fall by d (optimal/tests/disturbance.rs derives it); 1e-12 relative is the
    # two solves' KKT tolerance squared through the cost.
    j, theta, t_end = 2.0, 1.2, 10.0
    axis = np.array([1.0, 2.0, 2.0]) / 3
    target = lie.so3_exp(axis * theta)
    d = 0.03 * axis
    free = optimal.slew([j] * 3, t_end, target, steps=20, nodes=6)
    disturbed = optimal.slew([j] * 3, t_end, target, steps=20, nodes=6, disturbance=d)
    assert disturbed.cost == pytest.approx(free.cost + d @ d * t_end, rel=1e-12)
    assert np.abs(free.inputs - (disturbed.inputs + d)).max() <= 1e-11
    # By reaction wheels, an asymmetric craft: the run given the motors' torques and d as
    # the gyrostat's body torque lands on the target.
    target = lie.so3_exp([0.6, -0.4, 0.9])
    d = np.array([0.004, -0.003, 0.005])
    result = optimal.slew([8.0, 10.0, 6.0], 30.0, target, steps=30, nodes=8,
                          wheels=np.eye(3), wheel_speeds0=[20.0, -10.0, 5.0], disturbance=d)
    assert result.converged
    craft = lgsvi.Gyrostat(np.diag([8.0, 10.0, 6.0]), np.eye(3), [0.05] * 3)
    it = lgsvi.Integrator(craft, result.h, 8, wheel_speeds=[20.0, -10.0, 5.0])
    for u in result.inputs:
        it.set_input(np.concatenate([d, u]))
        it.step()
    assert np.abs(lie.so3_log(it.state.attitude.T @ target)).max() <= 1e-9
    assert np.abs(it.state.omega).max() <= 1e-9
    with pytest.raises(lgsvi.InvalidInputError, match="disturbance"):
        optimal.slew([3.0, 4.0, 5.0], 10.0, target, disturbance=[0.0, np.nan, 0.0])
    with pytest.raises(lgsvi.InvalidInputError, match="disturbance"):
        optimal.slew([3.0, 4.0, 5.0], 10.0, target, disturbance=[0.0, 1.0])


def test_a_manoeuvre_works_against_a_disturbance_wrench():
    # A spherical body turning about z and moving along z, the disturbance wrench along z:
    # the same law in space (optimal/tests/manoeuvres.rs), (tau_d^2 + f_d^2) T more.
    kwargs = dict(attitude_final=lie.so3_exp([0.0, 0.0, 1.2]), position_final=[0.0, 0.0, 0.8],
                  steps=5, nodes=6, inputs="polynomial")
    free = optimal.manoeuvre([2.0] * 3, 5.0, 10.0, **kwargs)
    disturbed = optimal.manoeuvre([2.0] * 3, 5.0, 10.0, disturbance=[0.0, 0.0, 0.02],
                                  disturbance_force=[0.0, 0.0, -0.05], **kwargs)
    assert disturbed.cost == pytest.approx(free.cost + (0.02**2 + 0.05**2) * 10.0, rel=1e-12)
    # The wrenches are the undisturbed ones less the disturbance (which also tells a sign or
    # the torque and force swapped).
    d = np.array([0.0, 0.0, 0.02, 0.0, 0.0, -0.05])
    assert np.abs(free.inputs_at_points - (disturbed.inputs_at_points + d)).max() <= 1e-10
    with pytest.raises(lgsvi.InvalidInputError, match="disturbance_force"):
        optimal.manoeuvre([2.0] * 3, 5.0, 10.0, disturbance_force=[0.0, 1.0], **kwargs)


def test_a_manoeuvre_in_space_meets_the_split_optimum_and_replays():
    # A spherical body turned and moved rest to rest: the optimum splits into the two
    # single-axis cubics, 12 (j^2 theta^2 + m^2 |d|^2) / T^3, which polynomial wrenches meet
    # to rounding (optimal/tests/manoeuvres.rs derives it).
    j, m, theta, t_end = 2.0, 5.0, 1.2, 10.0
    d = np.array([0.6, -0.3, 0.2])
    target = lie.so3_exp(np.array([1.0, 2.0, 2.0]) / 3 * theta)
    result = optimal.manoeuvre([j] * 3, m, t_end, attitude_final=target, position_final=d,
                               steps=5, nodes=6, inputs="polynomial")
    exact = 12 * (j * j * theta**2 + m * m * d @ d) / t_end**3
    assert result.cost == pytest.approx(exact, rel=1e-12)
    assert result.inputs.shape == (5, 6) and result.inputs_at_points.shape == (5, 6, 6)
    assert np.abs(result.position[-1] - d).max() <= 1e-9
    # Bounded, between moving states, replayed by the integrator with its held wrenches.
    body = lgsvi.FreeBody([1.0, 1.5, 2.0], mass=10.0)
    start_velocity = np.array([0.05, 0.0, 0.0])
    result = optimal.manoeuvre([1.0, 1.5, 2.0], 10.0, 30.0, attitude_final=lie.so3_exp([0, 0, 1.5]),
                               position_final=[2.0, 0.0, 0.5], velocity0=start_velocity,
                               steps=30, nodes=6, torque_max=0.05, force_max=0.2)
    assert result.converged and np.abs(result.inputs[:, 3:]).max() <= 0.2 * (1 + 1e-9)
    it = lgsvi.Integrator(body, result.h, 6, velocity=start_velocity)
    for u in result.inputs:
        it.set_input(u)
        it.step()
    assert np.abs(it.state.position - [2.0, 0.0, 0.5]).max() <= 1e-9
    assert np.abs(it.state.velocity).max() <= 1e-9
    assert np.abs(lie.so3_log(it.state.attitude.T @ lie.so3_exp([0, 0, 1.5]))).max() <= 1e-9


def test_a_manoeuvre_between_moving_states_takes_world_velocities():
    # Velocities are given and reported in the world frame; a turned target with a moving
    # centre of mass is reached as given (a wrong frame would miss it by the rotation).
    attitude_final = lie.so3_exp([0.4, 0.8, 0.8])
    result = optimal.manoeuvre([1.0, 1.5, 2.0], 3.0, 20.0, attitude0=lie.so3_exp([0.3, -0.2, 0.5]),
                               velocity0=[0.02, 0.0, 0.0], attitude_final=attitude_final,
                               position_final=[1.0, 1.0, 0.0], velocity_final=[0.05, -0.02, 0.01],
                               omega_final=[0.0, 0.0, 0.01], steps=10, nodes=6)
    assert np.abs(result.velocity[0] - [0.02, 0.0, 0.0]).max() <= 1e-12
    assert np.abs(result.velocity[-1] - [0.05, -0.02, 0.01]).max() <= 1e-9
    assert np.abs(result.position[-1] - [1.0, 1.0, 0.0]).max() <= 1e-9
    assert np.abs(result.omega[-1] - [0.0, 0.0, 0.01]).max() <= 1e-9
    assert np.abs(lie.so3_log(result.attitude[-1].T @ attitude_final)).max() <= 1e-9


def test_manoeuvre_errors_name_the_argument():
    for kwargs, error, name in [
        (dict(mass=0.0), lgsvi.InvalidInputError, "mass"),
        (dict(force_max=-1.0), lgsvi.InvalidInputError, "force_max"),
        (dict(torque_max=[1.0, 0.0, 1.0]), lgsvi.InvalidInputError, "torque_max"),
        (dict(mu=1.0), lgsvi.InvalidInputError, "position0"),
        (dict(inputs="cubic"), lgsvi.InvalidInputError, "inputs"),
        (dict(warm_start=np.zeros((3, 3))), lgsvi.InvalidInputError, "warm_start"),
        (dict(force_max=1e-6, position_final=[5.0, 0, 0]), optimal.InfeasibleError, "infeasible"),
    ]:
        args = dict(mass=1.0, position_final=[1.0, 0.0, 0.0])
        args.update(kwargs)
        mass = args.pop("mass")
        with pytest.raises(error, match=name):
            optimal.manoeuvre([1.0, 1.5, 2.0], mass, 10.0, **args)


def test_a_least_time_manoeuvre_meets_the_diagonal_closed_form():
    # A spherical body turned about the diagonal a = (1, 1, 1)/sqrt(3) and moved along it,
    # rest to rest, each body axis's torque bounded by tau and force by f: no box-bounded
    # wrench turns or pushes faster than the corner (1, 1, 1), so the least time is
    # max(2 sqrt(j theta / (sqrt3 tau)), 2 sqrt(m d / (sqrt3 f))), met by the eigen-axis
    # bang-bang, which an even step count resolves exactly (optimal/tests/manoeuvre_time.rs
    # derives it).
    j, m, tau, f, theta, d = 2.0, 5.0, 0.1, 0.2, 1.2, 0.3
    axis = np.ones(3) / np.sqrt(3.0)
    exact = max(2 * np.sqrt(j * theta / (np.sqrt(3) * tau)), 2 * np.sqrt(m * d / (np.sqrt(3) * f)))
    result = optimal.manoeuvre([j] * 3, m, attitude_final=lie.so3_exp(axis * theta),
                               position_final=axis * d, torque_max=tau, force_max=f,
                               steps=10, nodes=6, cost="time")
    assert result.converged
    assert result.cost == pytest.approx(exact, rel=1e-12) and result.t_end == result.cost
    assert np.abs(result.inputs[:, :3]).max() <= tau * (1 + 1e-12)
    assert np.abs(result.position[-1] - axis * d).max() <= 1e-9
    # The least time needs both bounds and held wrenches.
    for kwargs, name in [
        (dict(force_max=None), "force_max"),
        (dict(torque_max=None), "torque_max"),
        (dict(inputs="polynomial"), "inputs"),
        (dict(terminal_cost=[1.0] * 4), "tracking and terminal costs"),
        (dict(torque_max=0.0), "torque_max"),
        (dict(attitude_final=np.eye(3), position_final=[0.0, 0, 0]), "the target is the start"),
    ]:
        args = dict(attitude_final=lie.so3_exp(axis * theta), position_final=axis * d,
                    torque_max=tau, force_max=f, steps=10, nodes=6, cost="time")
        args.update(kwargs)
        with pytest.raises(lgsvi.InvalidInputError, match=name):
            optimal.manoeuvre([j] * 3, m, **args)


def test_a_manoeuvre_tracks_a_reference_and_takes_a_soft_target():
    # Tracking the exact manoeuvre's own states with its target soft: the residuals vanish
    # there, so the optimum spends less energy than the exact one (the energy pulls it off
    # the reference) and ends near the target; the multipliers of a soft target are zero.
    args = dict(attitude_final=lie.so3_exp([0.6, 0.2, -0.4]), position_final=[1.0, -0.5, 0.3],
                steps=6, nodes=6)
    exact = optimal.manoeuvre([3.0, 4.0, 5.5], 2.0, 12.0, **args)
    reference = (exact.attitude[1:], exact.position[1:], exact.omega[1:], exact.velocity[1:],
                 [10.0, 10.0, 10.0, 10.0])
    soft = optimal.manoeuvre([3.0, 4.0, 5.5], 2.0, 12.0, track=reference,
                             terminal_cost=[100.0] * 4, **args)
    assert soft.converged and 0.0 < soft.cost < exact.cost
    assert np.abs(soft.position[-1] - [1.0, -0.5, 0.3]).max() < 0.05
    assert np.all(soft.multipliers == 0.0)
    # Heavier weights pull the soft solution onto the exact one.
    heavy = optimal.manoeuvre([3.0, 4.0, 5.5], 2.0, 12.0, track=reference[:4] + ([1e3] * 4,),
                              terminal_cost=[1e3] * 4, **args)
    assert np.abs(heavy.position - exact.position).max() < np.abs(soft.position - exact.position).max()
    with pytest.raises(lgsvi.InvalidInputError, match="track"):
        optimal.manoeuvre([3.0, 4.0, 5.5], 2.0, 12.0, track=(exact.attitude[1:3],) + reference[1:],
                          **args)
    with pytest.raises(lgsvi.InvalidInputError, match="terminal_cost"):
        optimal.manoeuvre([3.0, 4.0, 5.5], 2.0, 12.0, terminal_cost=[1.0, -1.0, 1.0, 1.0], **args)
