"""The step's exact linearisation against central differences through ``step()``, and the
control designs against scipy (``solve_discrete_are``) and a numpy Riccati recursion."""

import numpy as np
import pytest
from scipy.linalg import expm, solve_discrete_are
from scipy.spatial.transform import Rotation

import lgsvi
from lgsvi import control


def next_state(system, h, nodes, attitude, omega, u):
    it = lgsvi.Integrator(system, h, nodes, attitude=attitude, omega=omega)
    it.set_input(u)
    it.step()
    s = it.state
    return s.attitude, s.omega


@pytest.mark.parametrize("coordinates", ["velocity"])
def test_linearize_matches_central_differences(coordinates):
    """A = dx+/dx, B = dx+/du in x = (theta, omega), R = Rbar expm(hat(theta)), by central
    differences of whole steps (eps = 1e-6: truncation ~1e-12 times the third derivative,
    rounding ~1e-16 / 1e-6 = 1e-10): 1e-8 of the entries' scale."""
    top = lgsvi.HeavyTop(inertia_d=[1.0, 2.8, 2.0])
    r0 = Rotation.from_rotvec([0.3, -0.2, 0.1]).as_matrix()
    w0 = np.array([0.5, -0.5, 0.4])
    u0 = np.array([0.1, 0.0, -0.05])
    h, n = 0.2, 8
    it = lgsvi.Integrator(top, h, n, attitude=r0, omega=w0)
    it.set_input(u0)
    a, b = it.linearize(coordinates=coordinates)
    assert it.t == 0.0  # linearize does not take the step
    r_bar, w_bar = next_state(top, h, n, r0, w0, u0)

    def x_plus(r, w):
        theta = Rotation.from_matrix(r_bar.T @ r).as_rotvec()
        return np.concatenate([theta, w - w_bar])

    eps = 1e-6
    numeric_a = np.zeros((6, 6))
    for k in range(6):
        e = np.zeros(6)
        e[k] = eps
        cols = []
        for sign in (1, -1):
            r = r0 @ expm(sign * np.array(lgsvi.lie.hat(e[:3])))
            cols.append(x_plus(*next_state(top, h, n, r, w0 + sign * e[3:], u0)))
        numeric_a[:, k] = (cols[0] - cols[1]) / (2 * eps)
    numeric_b = np.zeros((6, 3))
    for k in range(3):
        e = np.zeros(3)
        e[k] = eps
        plus = x_plus(*next_state(top, h, n, r0, w0, u0 + e))
        minus = x_plus(*next_state(top, h, n, r0, w0, u0 - e))
        numeric_b[:, k] = (plus - minus) / (2 * eps)
    assert np.max(np.abs(a - numeric_a)) < 1e-8 * np.max(np.abs(a))
    assert np.max(np.abs(b - numeric_b)) < 1e-8 * np.max(np.abs(b))
    # step_linearized takes the step and returns the same matrices.
    a2, b2 = it.step_linearized()
    assert it.t == h
    assert np.max(np.abs(a2 - a)) < 1e-12 and np.max(np.abs(b2 - b)) < 1e-12


def test_linearize_points_match_central_differences():
    """With inputs at the Gauss points, linearize(points=True) gives B_j = dx+/du_j, which sum
    to B, and dtheta_j/d(x, u), the configuration's derivative at each point, against central
    differences of whole steps read on their Galerkin curves at the points (eps = 1e-6, as
    above: 1e-8 of the entries' scale). With a held input B_points is None and the
    configurations have one input block."""
    top = lgsvi.HeavyTop(inertia_d=[1.0, 2.8, 2.0])
    r0 = Rotation.from_rotvec([0.3, -0.2, 0.1]).as_matrix()
    w0 = np.array([0.5, -0.5, 0.4])
    h, n = 0.2, 8
    it = lgsvi.Integrator(top, h, n, attitude=r0, omega=w0)
    c = it.quadrature_nodes
    m = len(c)
    u0 = np.array([[0.1 * np.sin(3.0 * cj), 0.05, -0.05 * cj] for cj in c])
    it.set_input_at_points(u0)
    a, b, b_points, configurations = it.linearize(points=True)
    assert b_points.shape == (m, 6, 3) and configurations.shape == (m, 3, 6 + 3 * m)
    # The points' B_j sum to B (the derivative in an input added at every point).
    assert np.max(np.abs(b_points.sum(axis=0) - b)) < 1e-13 * np.max(np.abs(b))

    def curve_points(attitude, omega, u):
        step = lgsvi.Integrator(top, h, n, attitude=attitude, omega=omega)
        step.set_input_at_points(u)
        step.step()
        curve = step.curve()
        return [curve(cj * h).attitude for cj in c]

    r_bar = curve_points(r0, w0, u0)

    def thetas(rs):
        return np.array([Rotation.from_matrix(rb.T @ r).as_rotvec() for rb, r in zip(r_bar, rs)])

    eps = 1e-6
    numeric = np.zeros((m, 3, 6 + 3 * m))
    for k in range(6 + 3 * m):
        sides = []
        for sign in (1, -1):
            e = np.zeros(6 + 3 * m)
            e[k] = sign * eps
            r = r0 @ expm(np.array(lgsvi.lie.hat(e[:3])))
            sides.append(thetas(curve_points(r, w0 + e[3:6], u0 + e[6:].reshape(m, 3))))
        numeric[:, :, k] = (sides[0] - sides[1]) / (2 * eps)
    scale = np.max(np.abs(configurations))
    assert np.max(np.abs(configurations - numeric)) < 1e-8 * scale
    # The last point's derivative in its own input is not zero: the points see the inputs.
    assert np.max(np.abs(configurations[-1, :, 6 + 3 * (m - 1):])) > 1e-6

    held = lgsvi.Integrator(top, h, n, attitude=r0, omega=w0)
    held.set_input(u0[0])
    a2, b2, none, held_configurations = held.linearize(points=True)
    assert none is None and held_configurations.shape == (m, 3, 9)
    # With the parameters too, the points' entries follow P and the names.
    assert len(held.linearize(parameters=True, points=True)) == 6


def test_dlqr_against_scipy():
    """K = (R + B'SB)^-1 B'SA with S scipy's solve_discrete_are (a Schur method): both
    solve the same equation to ~1e-12 here."""
    rng = np.random.default_rng(11)
    a = rng.normal(size=(6, 6)) * 0.5 + np.eye(6)
    b = rng.normal(size=(6, 3))
    q, r = np.eye(6), np.diag([1.0, 2.0, 0.5])
    k, s = control.dlqr(a, b, q, r)
    s_ref = solve_discrete_are(a, b, q, r)
    k_ref = np.linalg.solve(r + b.T @ s_ref @ b, b.T @ s_ref @ a)
    assert np.max(np.abs(s - s_ref)) < 1e-10 * np.max(np.abs(s_ref))
    assert np.max(np.abs(k - k_ref)) < 1e-10 * np.max(np.abs(k_ref))
    assert np.max(np.abs(control.dare(a, b, q, r) - s)) == 0.0
    # The closed loop is stable.
    assert np.max(np.abs(np.linalg.eigvals(a - b @ k))) < 1.0


def test_tvlqr_against_a_numpy_recursion():
    rng = np.random.default_rng(2)
    steps = [(np.eye(4) + 0.1 * rng.normal(size=(4, 4)), rng.normal(size=(4, 2))) for _ in range(5)]
    q, r, qf = np.eye(4), np.eye(2), 10 * np.eye(4)
    gains = control.tvlqr([s[0] for s in steps], [s[1] for s in steps], q, r, qf)
    p = qf
    expected = [None] * 5
    for k in reversed(range(5)):
        a, b = steps[k]
        kk = np.linalg.solve(r + b.T @ p @ b, b.T @ p @ a)
        p = q + a.T @ p @ (a - b @ kk)
        p = (p + p.T) / 2
        expected[k] = kk
    assert gains.shape == (5, 2, 4)
    assert np.max(np.abs(gains - np.array(expected))) < 1e-12


def test_an_lqr_regulator_holds_the_upright_pendulum():
    """The heavy top balanced upside down (R = diag(-1, 1, -1), an unstable equilibrium) by
    LQR on the step's exact linearisation, from a 0.1 rad tilt: the tilt falls below 1e-6
    in 20 s."""
    top = lgsvi.HeavyTop(inertia_d=[1.0, 2.8, 2.0])
    up = np.diag([-1.0, 1.0, -1.0])
    h = 0.05
    it = lgsvi.Integrator(top, h, 6, attitude=up)
    a, b = it.linearize()
    k, _ = control.dlqr(a, b, np.eye(6), 0.1 * np.eye(3))
    regulator = control.Regulator(it.state, k)
    tilt = Rotation.from_rotvec([0.1, 0.05, 0.0]).as_matrix()
    it.reset(attitude=up @ tilt)
    for _ in range(400):
        it.set_input(regulator.input(it.state))
        it.step()
    error = control.error_state(it.state, regulator_reference(up))
    assert np.max(np.abs(error)) < 1e-6


def regulator_reference(up):
    top = lgsvi.HeavyTop(inertia_d=[1.0, 2.8, 2.0])
    return lgsvi.Integrator(top, 0.05, 6, attitude=up).state
