"""The minimum-energy rest-to-rest slew of an asymmetric rigid body by an indirect method
(Pontryagin's principle), independent of lgsvi: the reference of
`optimal/tests/slews.rs::polynomial_inputs_meet_pontryagins_optimum`.

Problem: J = diag(3, 4, 5.5) kg m^2, from rest at the identity to rest at
R_f = exp([1.5, 0.4, -0.9]^) (body to world) in T = 30 s, minimising the integral of |u|^2
(no 1/2), u the body torque; no bounds.

Attitude by modified Rodrigues parameters sigma (R = exp(phi e^) <-> sigma = tan(phi/4) e;
the path stays far below 360 degrees), Euler's equations for the body rates:

    sigma' = B(sigma) Omega,  B = ((1 - |sigma|^2) I + 2 sigma^ + 2 sigma sigma^T) / 4
    J Omega' = (J Omega) x Omega + u

With H = |u|^2 + p_s . B(sigma) Omega + p_w . J^-1 ((J Omega) x Omega + u), the control is
u = -J^-1 p_w / 2 and the costates follow p' = -dH/dx (derivatives in closed form below).
The two-point boundary-value problem is solved by scipy's solve_bvp (collocation) from a
cubic-time-law guess, then polished by single shooting on p(0) with DOP853 at rtol 1e-13
(Newton on the terminal miss, a finite-difference Jacobian), the cost integrated as a
13th state. Writes pontryagin_slew.json beside this script.

    python3 optimal/tests/data/pontryagin_slew.py
"""

import json
import pathlib

import numpy as np
from scipy.integrate import solve_bvp, solve_ivp

J = np.diag([3.0, 4.0, 5.5])
J_INV = np.linalg.inv(J)
THETA_F = np.array([1.5, 0.4, -0.9])
T = 30.0


def hat(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def mrp(theta):
    angle = np.linalg.norm(theta)
    return np.tan(angle / 4.0) * theta / angle


SIGMA_F = mrp(THETA_F)


def b_matrix(s):
    return ((1.0 - s @ s) * np.eye(3) + 2.0 * hat(s) + 2.0 * np.outer(s, s)) / 4.0


def rhs_one(y):
    s, w, ps, pw = y[0:3], y[3:6], y[6:9], y[9:12]
    u = -0.5 * J_INV @ pw
    jw = J @ w
    ds = b_matrix(s) @ w
    dw = J_INV @ (np.cross(jw, w) + u)
    # d(B(s) w)/ds = (-2 w s^T - 2 w^ + 2 (s.w) I + 2 s w^T) / 4
    dbw_ds = (-2.0 * np.outer(w, s) - 2.0 * hat(w) + 2.0 * (s @ w) * np.eye(3)
              + 2.0 * np.outer(s, w)) / 4.0
    # d(J^-1 ((J w) x w))/dw = J^-1 (-w^ J + (J w)^)
    dfw_dw = J_INV @ (-hat(w) @ J + hat(jw))
    dps = -dbw_ds.T @ ps
    dpw = -(b_matrix(s).T @ ps + dfw_dw.T @ pw)
    return np.concatenate([ds, dw, dps, dpw]), u


def rhs(t, y):
    return np.stack([rhs_one(y[:, i])[0] for i in range(y.shape[1])], axis=1)


def bc(ya, yb):
    return np.concatenate([ya[0:3], ya[3:6], yb[0:3] - SIGMA_F, yb[3:6]])


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


def shoot(p0):
    def f(t, z):
        dy, u = rhs_one(z[:12])
        return np.concatenate([dy, [u @ u]])

    z0 = np.concatenate([np.zeros(6), p0, [0.0]])
    sol = solve_ivp(f, (0.0, T), z0, method="DOP853", rtol=1e-13, atol=1e-15)
    end = sol.y[:, -1]
    return np.concatenate([end[0:3] - SIGMA_F, end[3:6]]), end[12]


def main():
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
    out = {
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
    path = pathlib.Path(__file__).with_name("pontryagin_slew.json")
    path.write_text(json.dumps(out, indent=2) + "\n")
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
