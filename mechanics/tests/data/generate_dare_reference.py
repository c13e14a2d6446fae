"""Reference solutions of the discrete algebraic Riccati equation and of the
finite-horizon LQR recursion, for mechanics/tests/control.rs.

Independent of lgsvi: scipy.linalg.solve_discrete_are (a QZ/Schur method) for P, numpy
for K = (R + BᵀPB)⁻¹BᵀPA and the backward recursion. Regenerate with

    python3 mechanics/tests/data/generate_dare_reference.py > mechanics/tests/data/dare_reference.json

(numpy 2.4, scipy 1.17; the matrices come from a seeded generator and closed forms).
"""
import json

import numpy as np
from scipy.linalg import solve_discrete_are


def gain(a, b, r, p):
    return np.linalg.solve(r + b.T @ p @ b, b.T @ p @ a)


def case(name, a, b, q, r, horizon=None, qf=None):
    p = solve_discrete_are(a, b, q, r)
    out = {
        "name": name,
        "a": a.tolist(), "b": b.tolist(), "q": q.tolist(), "r": r.tolist(),
        "p": p.tolist(), "k": gain(a, b, r, p).tolist(),
    }
    if horizon is not None:
        # Time-invariant steps for the recursion: P_N = Q_f, then backwards.
        pk = qf.copy()
        gains = []
        for _ in range(horizon):
            k = gain(a, b, r, pk)
            pk = q + a.T @ pk @ (a - b @ k)
            pk = 0.5 * (pk + pk.T)
            gains.append(k)
        gains.reverse()
        out["horizon"] = horizon
        out["qf"] = qf.tolist()
        out["first_gain"] = gains[0].tolist()
        out["last_gain"] = gains[-1].tolist()
    return out


rng = np.random.default_rng(20261124)
cases = []

# A double integrator sampled with h = 0.1 (zero-order hold).
h = 0.1
a = np.array([[1.0, h], [0.0, 1.0]])
b = np.array([[h * h / 2], [h]])
cases.append(case("double integrator", a, b, np.diag([1.0, 0.1]), np.array([[0.01]]),
                  horizon=50, qf=np.diag([10.0, 1.0])))

# The zero-order hold of a rigid body at rest, full inertia tensor, h = 0.05.
j = np.array([[0.5, 0.1, 0.0], [0.1, 0.9, -0.05], [0.0, -0.05, 0.7]])
ji = np.linalg.inv(j)
h = 0.05
a = np.block([[np.eye(3), h * np.eye(3)], [np.zeros((3, 3)), np.eye(3)]])
b = np.vstack([0.5 * h * h * ji, h * ji])
cases.append(case("rigid body at rest", a, b, np.diag([10.0, 10, 10, 1, 1, 1]),
                  np.diag([0.1, 0.2, 0.3])))

# An unstable 6-state system with 3 inputs (spectral radius ~1.3).
a = rng.normal(size=(6, 6))
a *= 1.3 / max(abs(np.linalg.eigvals(a)))
b = rng.normal(size=(6, 3))
m = rng.normal(size=(6, 6))
q = m @ m.T / 6 + 0.1 * np.eye(6)
cases.append(case("unstable 6 x 3", a, b, q, np.diag([1.0, 0.5, 2.0]),
                  horizon=30, qf=np.eye(6)))

# A body in space's size: 12 states, 6 inputs, a marginally stable A.
a = np.eye(12) + 0.05 * rng.normal(size=(12, 12))
b = 0.1 * rng.normal(size=(12, 6))
cases.append(case("12 x 6", a, b, np.eye(12), 0.1 * np.eye(6)))

print(json.dumps({"generator": "mechanics/tests/data/generate_dare_reference.py", "cases": cases}, indent=1))
