"""Motions against scipy's ``solve_ivp`` at tight tolerance, on the equations of motion
written here from the Lagrangians (independent of lgsvi): the heavy top in a tilted field,
a gyrostat under motor torques, a damped body, and the dense output between the steps."""

import numpy as np
from scipy.integrate import solve_ivp

import lgsvi


def hat(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def so3_rhs(inertia, torque):
    """dR/dt = R hat(w), J dw/dt = (J w) x w + tau(t, R, w)."""
    j_inv = np.linalg.inv(inertia)

    def rhs(t, y):
        r, w = y[:9].reshape(3, 3), y[9:]
        dr = r @ hat(w)
        dw = j_inv @ (np.cross(inertia @ w, w) + torque(t, r, w))
        return np.concatenate([dr.ravel(), dw])

    return rhs


def reference(rhs, y0, times):
    sol = solve_ivp(rhs, (0.0, times[-1]), y0, method="DOP853", rtol=1e-13, atol=1e-14,
                    t_eval=times)
    assert sol.success
    return sol.y.T


def test_heavy_top_in_a_tilted_field():
    """l = 1/2 w.Jw + m g d.(R rho): the torque is m g rho x (R^T d). DOP853 at rtol 1e-13
    is good to ~1e-12 over T = 5; lgsvi at h = 0.25, n = 14 far better: 1e-10 bounds
    their difference."""
    j = np.diag([4.8, 3.0, 3.8])
    rho, d, mg = np.array([0.1, -0.2, 1.0]), np.array([0.3, 0.0, 1.0]) / np.hypot(0.3, 1.0), 9.81
    top = lgsvi.HeavyTop(j, mass=1.0, gravity=9.81, com=rho, gravity_direction=[0.3, 0.0, 1.0])
    w0 = np.array([0.5, -0.5, 0.4])
    traj = lgsvi.Integrator(top, 0.25, 14, omega=w0).run_until(5.0)
    rhs = so3_rhs(j, lambda t, r, w: mg * np.cross(rho, r.T @ d))
    ref = reference(rhs, np.concatenate([np.eye(3).ravel(), w0]), traj.t)
    assert np.max(np.abs(traj.attitude.reshape(-1, 9) - ref[:, :9])) < 1e-10
    assert np.max(np.abs(traj.omega - ref[:, 9:])) < 1e-10
    # Noether: the momentum about the field's direction is conserved to rounding.
    pi_d = traj.spatial_momentum @ d
    assert np.max(np.abs(pi_d - pi_d[0])) < 1e-13


def test_a_damped_body_loses_the_energy_its_work_says():
    """Damping tau = -c w: the energy falls as the work of the damping, E(t) - E(0) = W(t),
    and the motion follows solve_ivp's to 1e-10 over T = 5."""
    j = np.diag([3.3, 2.5, 3.4])
    body = lgsvi.RigidBody(j, damping=0.2)
    w0 = np.array([-2.0, 1.9, -1.0])
    it = lgsvi.Integrator(body, 0.1, 12, omega=w0)
    traj = it.run_until(5.0)
    ref = reference(so3_rhs(j, lambda t, r, w: -0.2 * w), np.concatenate([np.eye(3).ravel(), w0]), traj.t)
    assert np.max(np.abs(traj.omega - ref[:, 9:])) < 1e-10
    assert traj.energy[-1] < traj.energy[0]
    assert abs(traj.stats["work"] - (traj.energy[-1] - traj.energy[0])) < 1e-10


def test_a_gyrostat_under_motor_torques():
    """l = 1/2 w.Jw + sum I_i (a_i.w) phidot_i + 1/2 sum I_i phidot_i^2 (J locked): the body
    momentum h = Jw + A I phidot obeys dh/dt = h x w, each wheel's p_i = I_i (a_i.w +
    phidot_i) gains its motor torque, dp_i/dt = tau_i. Against solve_ivp on (R, h, p, phi)
    to 1e-10 over T = 4."""
    j = np.array([[10.0, 0.3, 0.0], [0.3, 12.0, -0.2], [0.0, -0.2, 8.0]])
    axes = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    inertias = np.array([0.05, 0.06, 0.04])
    torques = np.array([0.002, -0.001, 0.003])
    craft = lgsvi.Gyrostat(j, axes, inertias)
    w0, s0 = np.array([0.02, -0.01, 0.03]), np.array([5.0, -3.0, 2.0])
    it = lgsvi.Integrator(craft, 0.1, 10, omega=w0, wheel_speeds=s0)
    it.set_input(torques)
    traj = it.run_until(4.0)

    a_i = axes.T * inertias  # columns a_i I_i
    mass = np.block([[j, a_i], [a_i.T, np.diag(inertias)]])

    def rhs(t, y):
        r, h, p = y[:9].reshape(3, 3), y[9:12], y[12:15]
        xi = np.linalg.solve(mass, np.concatenate([h, p]))
        w, phidot = xi[:3], xi[3:]
        return np.concatenate([(r @ hat(w)).ravel(), np.cross(h, w), torques, phidot])

    mu0 = mass @ np.concatenate([w0, s0])
    y0 = np.concatenate([np.eye(3).ravel(), mu0, np.zeros(3)])
    ref = reference(rhs, y0, traj.t)
    assert np.max(np.abs(traj.attitude.reshape(-1, 9) - ref[:, :9])) < 1e-10
    assert np.max(np.abs(traj.wheel_angles - ref[:, 15:18])) < 1e-10
    assert np.max(np.abs(traj.momentum - ref[:, 9:15])) < 1e-10
    # The motor torques move momentum between body and wheels, not out of the craft.
    assert np.max(np.abs(traj.spatial_momentum - traj.spatial_momentum[0])) < 1e-14


def test_dense_output_between_the_nodes():
    """The Galerkin curves inside the steps are the motion to the method's accuracy: at
    h = 0.5, n = 16 the curve's error on the free body is ~1e-13; 1e-11 leaves room."""
    j = np.diag([3.3, 2.5, 3.4])
    w0 = np.array([-2.0, 1.9, -1.0])
    times = np.linspace(0.0, 3.0, 61)
    traj = lgsvi.Integrator(lgsvi.RigidBody(j), 0.5, 16, omega=w0).run_until(3.0, dense=times)
    assert np.array_equal(traj.t, times)
    ref = reference(so3_rhs(j, lambda t, r, w: np.zeros(3)), np.concatenate([np.eye(3).ravel(), w0]), times)
    assert np.max(np.abs(traj.attitude.reshape(-1, 9) - ref[:, :9])) < 1e-11
    assert np.max(np.abs(traj.omega - ref[:, 9:])) < 1e-11
    # The last step's curve, called directly.
    it = lgsvi.Integrator(lgsvi.RigidBody(j), 0.5, 16, omega=w0)
    it.run_until(3.0)
    curve = it.curve()
    assert (curve.start, curve.h) == (2.5, 0.5)
    mid = curve(2.75)
    k = np.searchsorted(times, 2.75)
    assert np.max(np.abs(mid.attitude.ravel() - ref[k, :9])) < 1e-11
