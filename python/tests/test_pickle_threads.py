"""Pickling (pickle and cloudpickle) and threads: objects come back equal and rerun bit for
bit; four threads stepping their own integrators give the sequential results."""

import pickle
import threading

import cloudpickle
import numpy as np
import pytest

import lgsvi

SYSTEMS = [
    lgsvi.RigidBody(inertia_d=[1.3, 2.1, 1.2], torque=[0.1, 0.0, 0.0], damping=0.01),
    lgsvi.RigidBody(np.array([[3.0, 0.4, -0.2], [0.4, 2.6, 0.3], [-0.2, 0.3, 3.3]])),
    lgsvi.HeavyTop([4.8, 3.0, 3.8], 1.0, 9.81, [0.0, 0.1, 1.0], [0.0, 0.0, 1.0]),
    lgsvi.FreeBody([1.0, 2.0, 2.5], mass=3.0, force=[0.0, 0.0, -1.0]),
    lgsvi.OrbitingBody([0.3, 0.2, 0.4], mass=1.0, mu=1.0),
    lgsvi.Gyrostat(np.diag([10.0, 12.0, 8.0]), np.eye(3), [0.05, 0.05, 0.05]),
]


def start(system):
    kwargs = {"omega": [0.2, -0.3, 0.5]}
    if system.group == "SE3":
        kwargs.update(position=[3.0, 0.0, 0.0], velocity=[0.0, 0.55, 0.05])
    if system.group.startswith("SO3xR"):
        kwargs.update(wheel_speeds=[1.0, -2.0, 0.5])
    return lgsvi.Integrator(system, 0.25, 8, **kwargs)


@pytest.mark.parametrize("dumps, loads", [(pickle.dumps, pickle.loads), (cloudpickle.dumps, pickle.loads)])
@pytest.mark.parametrize("system", SYSTEMS, ids=lambda s: repr(s)[:20])
def test_round_trips_come_back_equal_and_rerun_bit_for_bit(system, dumps, loads):
    assert loads(dumps(system)) == system
    assert type(loads(dumps(system))) is type(system)
    it = start(system)
    copy = loads(dumps(it))
    assert copy == it
    a, b = it.run_until(5.0), copy.run_until(5.0)
    assert a == b  # every array, bit for bit
    assert loads(dumps(a)) == a
    assert loads(dumps(it.state)) == it.state
    # Mid-run: the copy starts its predictor afresh; the steps agree to rounding.
    later = loads(dumps(it))
    x, y = it.run_until(7.0), later.run_until(7.0)
    assert np.max(np.abs(x.attitude - y.attitude)) < 1e-12


def test_the_classes_live_in_their_module():
    for cls in [lgsvi.RigidBody, lgsvi.Integrator, lgsvi.State, lgsvi.chebyshev.Chebyshev]:
        assert cls.__module__ == "lgsvi._lgsvi"
    assert lgsvi.Trajectory.__module__ == "lgsvi._trajectory"


def test_four_threads_give_the_sequential_results():
    """Each thread steps its own integrator (the GIL released during the steps): the results
    are the sequential runs', bit for bit."""
    body = lgsvi.RigidBody(inertia_d=[1.3, 2.1, 1.2])
    omegas = [[-2.0, 1.9, -1.0], [1.0, 0.1, 0.2], [0.3, 3.0, -0.5], [-1.5, -0.2, 2.0]]

    def run(w):
        it = lgsvi.Integrator(body, 0.5, 10, omega=w)
        for _ in range(200):
            it.step()
        return it.state

    sequential = [run(w) for w in omegas]
    results = [None] * 4

    def work(k):
        results[k] = run(omegas[k])

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert results == sequential


def test_one_integrator_shared_by_threads_stays_consistent():
    """Calls from several threads on one integrator are serialised by its lock: 4 threads
    x 50 steps take 200 steps."""
    it = lgsvi.Integrator(lgsvi.RigidBody([1.0, 2.0, 2.5]), 0.1, 6, omega=[0.1, 0.2, 0.3])
    threads = [threading.Thread(target=lambda: [it.step() for _ in range(50)]) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert it.stats["steps"] == 200
    assert abs(it.t - 20.0) < 1e-12
