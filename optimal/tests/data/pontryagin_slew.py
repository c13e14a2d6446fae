"""Minimum-energy rest-to-rest slews by an indirect method (Pontryagin's principle),
independent of lgsvi: the references of
`optimal/tests/slews.rs::polynomial_inputs_meet_pontryagins_optimum` (a free asymmetric
body, pontryagin_slew.json) and `::a_heavy_tops_slew_meets_pontryagins_optimum` (the same
body as a heavy top, pontryagin_heavy_top.json).

Problem: J = diag(3, 4, 5.5) kg m^2, from rest at the identity to rest at
R_f = exp([1.5, 0.4, -0.9]^) (body to world) in T = 30 s, minimising the integral of |u|^2
(no 1/2), u the body torque; no bounds. The heavy top adds mass m = 1 kg, gravity
g = 0.02 m/s^2 pulling along d = e_3 (world) and the centre of mass rho = (0.1, -0.2, 1) m
(body): its gravity torque m g rho x (R^T d), about half the torques the slew needs, does
not vanish at the start or the target, where the rest is held against it.

The heavy top's Lagrangian is lgsvi's, l = 1/2 Omega^T J Omega + m g d^T R rho, so Euler's
equations read J Omega' = (J Omega) x Omega + m g rho x (R^T d) + u (m g = 0: the free
body). Attitude by modified Rodrigues parameters sigma (R = exp(phi e^) <-> sigma =
tan(phi/4) e; the path stays far below 360 degrees):

    sigma' = B(sigma) Omega,  B = ((1 - |sigma|^2) I + 2 sigma^ + 2 sigma sigma^T) / 4,
    R(sigma) = I + (8 sigma^2^ + 4 (1 - |sigma|^2) sigma^) / (1 + |sigma|^2)^2.

With H = |u|^2 + p_s . B(sigma) Omega + p_w . J^-1 ((J Omega) x Omega + tau_g(sigma) + u),
the control is u = -J^-1 p_w / 2 and the costates follow p' = -dH/dx (derivatives in closed
form below). The gravity term's sigma-derivative goes through the body rotation
eta = B(sigma)^-1 dsigma: with q = J^-1 p_w and b = R^T d,
d(q . m g rho x b) = -m g eta . (b x (q x rho)), so its gradient in sigma is
-m g B^-T (b x (q x rho)). The script checks every derivative of H against central
differences before it solves.

Each two-point boundary-value problem is solved by scipy's solve_bvp (collocation) from a
cubic-time-law guess, then polished by single shooting on p(0) with DOP853 at rtol 1e-13
(Newton on the terminal miss, a finite-difference Jacobian), the cost integrated as a 13th
state. Writes both JSON files beside this script.

    python3 optimal/tests/data/pontryagin_slew.py
"""

import json
import pathlib

import numpy as np
from scipy.integrate import solve_bvp, solve_ivp
from scipy.spatial.transform import Rotation

J = np.diag([3.0, 4.0, 5.5])
J_INV = np.linalg.inv(J)
THETA_F = np.array([1.5, 0.4, -0.9])
T = 30.0
# The heavy top's gravity: (m, g, rho, d); m g = 0 is the free body.
FREE = (0.0, 0.0, np.zeros(3), np.array([0.0, 0.0, 1.0]))
TOP = (1.0, 0.02, np.array([0.1, -0.2, 1.0]), np.array([0.0, 0.0, 1.0]))


def hat(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def mrp(theta):
    angle = np.linalg.norm(theta)
    return np.tan(angle / 4.0) * theta / angle


def rotation(s):
    n = s @ s
    return np.eye(3) + (8.0 * hat(s) @ hat(s) + 4.0 * (1.0 - n) * hat(s)) / (1.0 + n) ** 2


SIGMA_F = mrp(THETA_F)


def b_matrix(s):
    return ((1.0 - s @ s) * np.eye(3) + 2.0 * hat(s) + 2.0 * np.outer(s, s)) / 4.0


def gravity_torque(s, top):
    m, g, rho, d = top
    return m * g * np.cross(rho, rotation(s).T @ d)


def hamiltonian(s, w, ps, pw, top):
    u = -0.5 * J_INV @ pw
    f = J_INV @ (np.cross(J @ w, w) + gravity_torque(s, top) + u)
    return u @ u + ps @ (b_matrix(s) @ w) + pw @ f


def rhs_one(y, top):
    m, g, rho, d = top
    s, w, ps, pw = y[0:3], y[3:6], y[6:9], y[9:12]
    u = -0.5 * J_INV @ pw
    jw = J @ w
    ds = b_matrix(s) @ w
    dw = J_INV @ (np.cross(jw, w) + gravity_torque(s, top) + u)
    # d(B(s) w)/ds = (-2 w s^T - 2 w^ + 2 (s.w) I + 2 s w^T) / 4
    dbw_ds = (-2.0 * np.outer(w, s) - 2.0 * hat(w) + 2.0 * (s @ w) * np.eye(3)
              + 2.0 * np.outer(s, w)) / 4.0
    # d(J^-1 ((J w) x w))/dw = J^-1 (-w^ J + (J w)^)
    dfw_dw = J_INV @ (-hat(w) @ J + hat(jw))
    b = rotation(s).T @ d
    gravity_ds = -m * g * np.linalg.solve(b_matrix(s).T, np.cross(b, np.cross(J_INV @ pw, rho)))
    dps = -(dbw_ds.T @ ps + gravity_ds)
    dpw = -(b_matrix(s).T @ ps + dfw_dw.T @ pw)
    return np.concatenate([ds, dw, dps, dpw]), u


def check_derivatives(top):
    """dH/dsigma and dH/dOmega of rhs_one against central differences of H, and R(sigma)
    against scipy's rotation of the same rotation vector."""
    rng = np.random.default_rng(1)
    for _ in range(5):
        s, w, ps, pw = (rng.normal(size=3) * 0.3 for _ in range(4))
        dy, _ = rhs_one(np.concatenate([s, w, ps, pw]), top)
        for k in range(3):
            e = np.zeros(3)
            e[k] = 1e-6
            d_s = (hamiltonian(s + e, w, ps, pw, top) - hamiltonian(s - e, w, ps, pw, top)) / 2e-6
            d_w = (hamiltonian(s, w + e, ps, pw, top) - hamiltonian(s, w - e, ps, pw, top)) / 2e-6
            assert abs(-d_s - dy[6 + k]) < 1e-8, (k, -d_s, dy[6 + k])
            assert abs(-d_w - dy[9 + k]) < 1e-8, (k, -d_w, dy[9 + k])
    assert np.allclose(rotation(SIGMA_F), Rotation.from_rotvec(THETA_F).as_matrix(), atol=1e-14)


def guess(t):
    s = t / T
    law = 3 * s**2 - 2 * s**3
    y = np.zeros((12, t.size))
    y[0:3] = np.outer(SIGMA_F, law)
    y[3:6] = np.outer(4.0 * SIGMA_F, (6 * s - 6 * s**2) / T)
    # The single-axis optimum's torque u = (6 J theta / T^2)(1 - 2s): p_w = -2 J u.
    u = np.outer(J @ THETA_F * 6.0 / T**2, 1.0 - 2.0 * s)
    y[9:12] = -2.0 * J @ u
    return y


def solve(top):
    """The optimum of `top`: its cost, terminal miss, solve_bvp's cost and nodes, p(0)."""
    check_derivatives(top)

    def rhs(t, y):
        return np.stack([rhs_one(y[:, i], top)[0] for i in range(y.shape[1])], axis=1)

    def bc(ya, yb):
        return np.concatenate([ya[0:3], ya[3:6], yb[0:3] - SIGMA_F, yb[3:6]])

    def shoot(p0):
        def f(t, z):
            dy, u = rhs_one(z[:12], top)
            return np.concatenate([dy, [u @ u]])

        z0 = np.concatenate([np.zeros(6), p0, [0.0]])
        sol = solve_ivp(f, (0.0, T), z0, method="DOP853", rtol=1e-13, atol=1e-15)
        end = sol.y[:, -1]
        return np.concatenate([end[0:3] - SIGMA_F, end[3:6]]), end[12]

    t = np.linspace(0.0, T, 61)
    bvp = solve_bvp(rhs, bc, t, guess(t), tol=1e-8, max_nodes=200000)
    assert bvp.status == 0, bvp.message
    fine = np.linspace(0.0, T, 20001)
    u = -0.5 * J_INV @ bvp.sol(fine)[9:12]
    bvp_cost = np.trapezoid(np.sum(u * u, axis=0), fine)
    # Polish: Newton on p(0) against the terminal miss of a tight DOP853 run.
    p0 = bvp.sol(0.0)[6:12].copy()
    for _ in range(8):
        miss, cost = shoot(p0)
        if np.abs(miss).max() < 1e-13:
            break
        jac = np.zeros((6, 6))
        for k in range(6):
            dp = np.zeros(6)
            dp[k] = 1e-6 * max(1.0, abs(p0[k]))
            jac[:, k] = (shoot(p0 + dp)[0] - miss) / dp[k]
        p0 = p0 - np.linalg.solve(jac, miss)
    miss, cost = shoot(p0)
    return {
        "inertia": [3.0, 4.0, 5.5],
        "attitude_final": THETA_F.tolist(),
        "t_end": T,
        "cost": cost,
        "terminal_miss": float(np.abs(miss).max()),
        "solve_bvp_cost": float(bvp_cost),
        "solve_bvp_nodes": int(bvp.x.size),
        "costate0": p0.tolist(),
        "method": "Pontryagin: solve_bvp (tol 1e-8), then single shooting on p(0) with "
                  "DOP853 at rtol 1e-13, the cost integrated as a state",
    }


def main():
    here = pathlib.Path(__file__).parent
    free = solve(FREE)
    (here / "pontryagin_slew.json").write_text(json.dumps(free, indent=2) + "\n")
    m, g, rho, d = TOP
    top = solve(TOP)
    top.update(mass=m, gravity=g, com=rho.tolist(), gravity_direction=d.tolist(),
               gravity_torque_final=gravity_torque(SIGMA_F, TOP).tolist())
    (here / "pontryagin_heavy_top.json").write_text(json.dumps(top, indent=2) + "\n")
    print(json.dumps({"free": free, "heavy_top": top}, indent=2))


if __name__ == "__main__":
    main()
