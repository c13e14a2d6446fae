"""Ensembles: each member is the run an Integrator gives, bit for bit, whatever the number
of threads; a failed member is reported with its exception, the others stand."""

import numpy as np
from scipy.spatial.transform import Rotation

import lgsvi


def test_members_are_the_integrators_runs():
    body = lgsvi.RigidBody(inertia_d=[1.3, 2.1, 1.2])
    rng = np.random.default_rng(1)
    attitudes = Rotation.random(6, random_state=4).as_matrix()
    omegas = rng.normal(size=(6, 3))
    one = lgsvi.run_ensemble(body, 0.5, 8, attitudes, omegas, 10.3, threads=1)
    two = lgsvi.run_ensemble(body, 0.5, 8, attitudes, omegas, 10.3, threads=2)
    assert np.array_equal(one.attitude, two.attitude) and np.array_equal(one.omega, two.omega)
    for k in range(6):
        it = lgsvi.Integrator(body, 0.5, 8, attitude=attitudes[k], omega=omegas[k])
        traj = it.run_until(10.3)
        assert np.array_equal(one.attitude[k], traj.attitude[-1])
        assert np.array_equal(one.omega[k], traj.omega[-1])
        assert one.t[k] == traj.t[-1]
    assert one.ok.all() and one.errors == {}


def test_a_failing_member_is_reported_not_raised():
    """Member 1 spins too fast for the Cayley chart's reach at this step."""
    body = lgsvi.RigidBody([1.0, 2.0, 2.5])
    omegas = np.array([[0.1, 0.2, 0.3], [40.0, 0.0, 0.0], [0.3, 0.2, 0.1]])
    result = lgsvi.run_ensemble(body, 0.5, 8, np.stack([np.eye(3)] * 3), omegas, 2.0, chart="cayley")
    assert list(result.ok) == [True, False, True]
    assert set(result.errors) == {1}
    assert isinstance(result.errors[1], lgsvi.ChartError)
    assert np.isnan(result.attitude[1]).all()
    assert np.isfinite(result.attitude[[0, 2]]).all()


def test_bodies_in_space_and_gyrostats():
    body = lgsvi.OrbitingBody([0.3, 0.2, 0.4], mass=1.0, mu=1.0)
    n = 3
    result = lgsvi.run_ensemble(
        body, 0.5, 10, np.stack([np.eye(3)] * n), np.zeros((n, 3)), 5.0,
        positions=[[3.0, 0.0, 0.0]] * n, velocities=[[0.0, 0.55 + 0.01 * k, 0.05] for k in range(n)],
    )
    assert result.position.shape == (n, 3) and result.ok.all()
    craft = lgsvi.Gyrostat(np.diag([10.0, 12.0, 8.0]), np.eye(3), [0.05] * 3)
    result = lgsvi.run_ensemble(craft, 0.2, 8, np.stack([np.eye(3)] * 2), np.zeros((2, 3)), 2.0,
                                wheel_speeds=[[1.0, 2.0, 3.0], [0.0, 0.0, 0.0]])
    assert result.wheel_speeds.shape == (2, 3)
    # A body at rest with its wheels at rest stays so.
    assert np.max(np.abs(result.omega[1])) == 0.0
