"""Every bad input raises the right exception, naming the argument; a failing step raises
the error of its cause, with the library's advice; a Rust panic becomes an exception."""

import numpy as np
import pytest

import lgsvi

BODY = lgsvi.RigidBody([1.0, 2.0, 2.5])


@pytest.mark.parametrize(
    "make, says",
    [
        (lambda: lgsvi.RigidBody([1.0, 2.0]), "inertia"),
        (lambda: lgsvi.RigidBody(np.ones((2, 2))), "inertia"),
        (lambda: lgsvi.RigidBody(["a", "b", "c"]), "inertia"),
        (lambda: lgsvi.RigidBody([1.0, np.nan, 2.0]), "inertia"),
        (lambda: lgsvi.RigidBody([-1.0, 2.0, 2.5]), "inertia"),
        (lambda: lgsvi.RigidBody([1.0, 1.0, 5.0]), "triangle"),
        (lambda: lgsvi.RigidBody(np.array([[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])), "symmetric"),
        (lambda: lgsvi.RigidBody(), "inertia"),
        (lambda: lgsvi.RigidBody([1.0, 2.0, 2.5], inertia_d=[1.0, 1.0, 1.0]), "not both"),
        (lambda: lgsvi.RigidBody([1.0, 2.0, 2.5], damping=-1.0), "damping"),
        (lambda: lgsvi.RigidBody([1.0, 2.0, 2.5], torque=[1.0, np.inf, 0.0]), "torque"),
        (lambda: lgsvi.HeavyTop([1.0, 2.0, 2.5], mass=-1.0), "mass"),
        (lambda: lgsvi.HeavyTop([1.0, 2.0, 2.5], gravity_direction=[0.0, 0.0, 0.0]), "direction"),
        (lambda: lgsvi.FreeBody([1.0, 2.0, 2.5], mass=0.0), "mass"),
        (lambda: lgsvi.OrbitingBody([1.0, 2.0, 2.5], mass=1.0, mu=-1.0), "mu"),
        (lambda: lgsvi.Gyrostat(np.eye(3), np.eye(3), [0.1, 0.1]), "one per wheel"),
        (lambda: lgsvi.Gyrostat(np.eye(3) * 0.01, np.eye(3), [0.1, 0.1, 0.1]), "positive definite"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8, omega=[1.0, 2.0, 3.0, 4.0]), "omega"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8, omega=[np.nan, 0.0, 0.0]), "omega"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8, attitude=np.eye(3) * 2.0), "attitude"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8, attitude=np.diag([1.0, 1.0, -1.0])), "attitude"),
        (lambda: lgsvi.Integrator(BODY, -0.5, 8), "h"),
        (lambda: lgsvi.Integrator(BODY, np.nan, 8), "h"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 1), "nodes"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8, chart="quaternion"), "chart"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8, matching="other"), "matching"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8, position=[1.0, 0.0, 0.0]), "position"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8, wheel_speeds=[1.0]), "wheel_speeds"),
        (lambda: lgsvi.Integrator("a body", 0.5, 8), "system"),
        (lambda: lgsvi.Integrator(lgsvi.Gyrostat(np.diag([10.0, 12.0, 8.0]), np.eye(3), [0.05] * 3), 0.5, wheel_speeds=[1.0]), "wheel_speeds"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8).set_input([1.0, 2.0]), "u"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8).set_input([1.0, np.nan, 2.0]), "u"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8).run_until(-1.0), "t_end"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8).run_until(np.inf), "t_end"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8).run_until(1.0, tol=0.0), "tol"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8).run_until(1.0, dense=[0.5, 0.2]), "ascending"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8).run_until(1.0, dense=[0.5, 2.0]), "within"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8).run_until(1.0, every=0), "every"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8).run_until(10.0, tol=1e-30), "tol"),
        (lambda: lgsvi.Integrator(BODY, 0.5, 8).linearize(coordinates="polar"), "coordinates"),
        (lambda: lgsvi.control.dlqr(np.eye(2), np.eye(3), np.eye(2), np.eye(2)), "B"),
        (lambda: lgsvi.control.dlqr(np.eye(2), np.eye(2), np.eye(2), -np.eye(2)), "R"),
        (lambda: lgsvi.run_ensemble(BODY, 0.5, 8, np.stack([np.eye(3)] * 2), np.zeros((3, 3)), 1.0), "omegas"),
        (lambda: lgsvi.quadrature.gauss_legendre(0), "point"),
        (lambda: lgsvi.quadrature.gauss_laguerre(5, -2.0), "alpha"),
        (lambda: lgsvi.chebyshev.Chebyshev.fit(np.sin, 1.0, 0.0), "interval"),
        (lambda: lgsvi.chebyshev.Chebyshev.fit(lambda x: np.sin(x)[:-1], 0.0, 1.0), "one value per point"),
        (lambda: lgsvi.chebyshev.Chebyshev.fit(lambda x: np.where(x > 0.5, np.nan, x), -1.0, 1.0), "finite"),
        (lambda: lgsvi.lie.so3_log(np.eye(3) * 2), "rotation"),
        (lambda: lgsvi.lie.so3_exp(np.zeros(4)), "shape"),
    ],
)
def test_bad_input_raises_invalid_input_naming_it(make, says):
    with pytest.raises(lgsvi.InvalidInputError) as error:
        make()
    assert says.lower() in str(error.value).lower(), str(error.value)
    assert isinstance(error.value, ValueError) and isinstance(error.value, lgsvi.LgsviError)


def test_a_step_the_chart_cannot_follow_raises_chart_error():
    it = lgsvi.Integrator(BODY, 2.0, 8, omega=[5.0, 0.0, 0.0], chart="cayley")
    with pytest.raises(lgsvi.ChartError, match='smaller step h .*chart="exp"'):
        it.step()
    assert it.t == 0.0  # the state is kept


def test_newton_that_does_not_converge_raises_convergence_error():
    it = lgsvi.Integrator(BODY, 0.5, 8, omega=[1.0, 2.0, 0.5], max_newton_iterations=1)
    with pytest.raises(lgsvi.ConvergenceError, match="Newton did not converge"):
        it.step()


def test_an_unmeetable_tolerance_raises_tolerance_error():
    it = lgsvi.Integrator(lgsvi.RigidBody([3.3, 2.5, 3.4]), 0.1, 8, omega=[30.0, 0.1, 0.1])
    with pytest.raises(lgsvi.ToleranceError, match="not met"):
        it.run_until(10.0, tol=1e-12, step=0.1)


def test_a_state_outside_the_model_raises_model_error():
    # A fall from rest at r = 3: the step that would end within twice the body's radius
    # of gyration (2 sqrt(1.75) = 2.65) is refused, the last state the model holds at kept.
    body = lgsvi.OrbitingBody([1.0, 1.0, 1.5], mass=1.0, mu=1.0)
    it = lgsvi.Integrator(body, 0.5, 8, position=[3.0, 0.0, 0.0])
    with pytest.raises(lgsvi.ModelError, match="ends outside .*wider orbit"):
        it.run_until(20.0)
    assert np.linalg.norm(it.state.position) >= 2 * np.sqrt(1.75)


def test_a_panic_becomes_an_internal_error():
    with pytest.raises(lgsvi.InternalError, match="on purpose"):
        lgsvi._lgsvi._panic_for_tests()
    # The interpreter and the library go on.
    assert lgsvi.Integrator(BODY, 0.5, 8, omega=[1.0, 2.0, 0.5]).step() >= 1


def test_the_hierarchy():
    for kind in [lgsvi.ConvergenceError, lgsvi.ChartError, lgsvi.ToleranceError,
                 lgsvi.ModelError, lgsvi.InternalError, lgsvi.InvalidInputError]:
        assert issubclass(kind, lgsvi.LgsviError)
    assert issubclass(lgsvi.LgsviError, Exception)
    assert issubclass(lgsvi.InvalidInputError, ValueError)


def test_an_orbit_starting_inside_its_own_far_field_is_refused():
    """An orbiting body whose attracting point lies within twice its radius of gyration
    (sqrt(tr J / 2m) = 2.14 here) is outside MacCullagh's far-field model: refused up
    front, as the command line refuses it, by the integrator, the ensemble and Monte Carlo."""
    from lgsvi import montecarlo

    body = lgsvi.OrbitingBody([3.3, 2.5, 3.4], mass=1.0, mu=1.0)
    start = dict(position=[3.0, 0.0, 0.0], velocity=[0.0, 0.55, 0.05])
    with pytest.raises(lgsvi.InvalidInputError, match="radius of gyration"):
        lgsvi.Integrator(body, h=0.5, nodes=10, **start)
    with pytest.raises(lgsvi.InvalidInputError, match="member 1: .*radius of gyration"):
        lgsvi.run_ensemble(body, 0.5, 10, np.stack([np.eye(3)] * 2), np.zeros((2, 3)), 1.0,
                           positions=[[9.0, 0.0, 0.0], [3.0, 0.0, 0.0]],
                           velocities=np.zeros((2, 3)))
    with pytest.raises(lgsvi.InvalidInputError, match="radius of gyration"):
        montecarlo.run(body, np.eye(3), [0.1, 0.0, 0.2], members=2, t_end=1.0, h=0.5, nodes=10,
                       **start)
    # Further out it runs.
    lgsvi.Integrator(body, h=0.5, nodes=10, position=[5.0, 0.0, 0.0])
