"""Events located on the steps' curves, against closed forms: an axisymmetric body's
Omega_1(t) = a cos(lambda t) with lambda = (J3 - J1) Omega_3 / J1, and a spherical body's
rotation angle; terminal events, directions, a tolerance-driven run, errors."""

import math
import pickle

import numpy as np
import pytest

import lgsvi

# The bound on the located time (relative); the curves resolve these motions to
# ~1e-15 and the root is polished to a few ulps.
TIME_TOLERANCE = 1e-12
LAMBDA = 1.5  # J = diag(1, 1, 2), Omega_3 = 1.5


def axisymmetric(h=0.3, nodes=14):
    return lgsvi.Integrator(lgsvi.RigidBody([1.0, 1.0, 2.0]), h, nodes, omega=[0.3, 0.0, 1.5])


def test_every_crossing_is_located_in_both_directions():
    trajectory = axisymmetric().run_until(20.0, events=[lgsvi.Event(lambda s: s.omega[0], name="w1")])
    hits = trajectory.events
    assert len(hits) == 10
    for k, hit in enumerate(hits):
        exact = (math.pi / 2 + k * math.pi) / LAMBDA
        assert abs(hit.t - exact) <= TIME_TOLERANCE * exact
        assert hit.direction == ("falling" if k % 2 == 0 else "rising")
        assert hit.name == "w1" and hit.event == 0
        assert abs(hit.state.omega[0]) < 1e-14 and hit.state.t == hit.t
    assert trajectory.stats["stopped_by_event"] is False
    assert trajectory.t[-1] == pytest.approx(20.0, abs=1e-12)


def test_a_terminal_event_stops_the_run_and_records_its_step_end():
    it = axisymmetric(h=0.5)
    events = [
        lgsvi.Event(lambda s: s.omega[0], direction="rising"),
        lgsvi.Event(lambda s: s.omega[1], direction="falling", terminal=True, name="w2 falls"),
    ]
    trajectory = it.run_until(10.0, every=4, events=events)
    assert trajectory.stats["stopped_by_event"] is True
    assert [h.name for h in trajectory.events] == ["w2 falls"]
    exact = math.pi / LAMBDA
    assert abs(trajectory.events[0].t - exact) <= TIME_TOLERANCE * exact
    # Steps of 0.5: stopped at 2.5, which the recording holds though 5 is not a multiple
    # of every = 4; the integrator continues from there.
    assert trajectory.t[-1] == 2.5 and it.state.t == 2.5
    assert list(trajectory.t) == [0.0, 2.0, 2.5]


def test_an_attitude_event_of_a_spherical_body():
    w = 0.9
    it = lgsvi.Integrator(lgsvi.RigidBody([1.0, 1.0, 1.0]), 0.7, 10, omega=[0.0, 0.0, w])
    trajectory = it.run_until(8.0, events=[lgsvi.Event(lambda s: s.attitude[0, 0], direction="falling")])
    exact = math.pi / (2 * w)
    assert len(trajectory.events) == 1
    assert abs(trajectory.events[0].t - exact) <= TIME_TOLERANCE * exact


def test_events_in_a_tolerance_driven_run():
    trajectory = axisymmetric().run_until(5.0, tol=1e-10, events=[lgsvi.Event(lambda s: s.omega[0])])
    times = [hit.t for hit in trajectory.events]
    exact = [math.pi / 2 / LAMBDA, 3 * math.pi / 2 / LAMBDA]
    # Long steps (h = 5/3): the curve between the nodes is off by ~3e-7 in Omega_1, but
    # each crossing is refined by the method's own steps of the found length, whose ends
    # are as accurate as the run's (4e-13 here): the times to 1e-12 relative.
    assert len(times) == 2
    assert np.allclose(times, exact, rtol=TIME_TOLERANCE, atol=0)


def test_an_exception_in_the_function_is_raised_as_it_is():
    def bad(state):
        if state.t > 1.0:
            raise KeyError("from the event")
        return 1.0

    with pytest.raises(KeyError, match="from the event"):
        axisymmetric().run_until(3.0, events=[lgsvi.Event(bad)])


def test_bad_events_are_refused():
    with pytest.raises(lgsvi.InvalidInputError, match="direction"):
        lgsvi.Event(lambda s: 0.0, direction="up")
    with pytest.raises(lgsvi.InvalidInputError, match="callable"):
        lgsvi.Event(3.0)
    with pytest.raises(lgsvi.InvalidInputError, match="lgsvi.Event"):
        axisymmetric().run_until(1.0, events=[lambda s: 0.0])
    with pytest.raises(lgsvi.LgsviError, match="event"):
        axisymmetric().run_until(1.0, events=[lgsvi.Event(lambda s: float("nan"), name="nan")])


def test_hits_pickle_with_their_trajectory():
    trajectory = axisymmetric().run_until(3.0, events=[lgsvi.Event(lambda s: s.omega[0], name="w1")])
    back = pickle.loads(pickle.dumps(trajectory))
    assert [(h.event, h.name, h.t, h.direction) for h in back.events] == [
        (h.event, h.name, h.t, h.direction) for h in trajectory.events
    ]
    assert back.events[0].state.t == trajectory.events[0].t
