"""lgsvi from Python, measured side by side in one process (ratios, not timed tests).

1. Step overhead: ``integrator.step()`` called from a Python loop against the same steps
   taken by the Rust loop (``integrator.advance(n)``), the paper's free body, n = 8,
   h = 0.5.
2. Run and ensemble overhead: ``run_until`` (every state recorded into ndarrays, with its
   energy and momenta) against the Rust library's own ``run_until`` on the same integrator
   (its states kept in Rust, ``Integrator._library_run_until``); ``run_ensemble`` (final
   states, one thread) against the same members stepped in Rust one after another
   (``advance``).
3. Against scipy: ``solve_ivp(DOP853)`` on the paper's free body over T = 100 (the
   quaternion form), at the loosest tolerance whose attitude error against the 40-digit
   reference (``cases/data``) is at most 1e-10 and 1e-12, against lgsvi's checked
   tolerance run (``run_until(100, tol=...)``) and its fastest fixed ``(h, n)`` as
   accurate.

Run after ``pip install ./python``:  python python/benches/bench.py
Each time is the median of repeated runs (``REPEATS``); the machine's noise moves single
runs by 10-30%.
"""

import json
import pathlib
import statistics
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

import lgsvi

REPEATS = 7
DATA = pathlib.Path(__file__).resolve().parents[2] / "cases" / "data" / "rigid_body_refs.json"
J = np.diag([3.3, 2.5, 3.4])
W0 = np.array([-2.0, 1.9, -1.0])


def median_time(f, repeats=REPEATS):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def reference_attitude():
    case = json.load(open(DATA))["cases"]["A"]
    final = [s for s in case["states"] if s["t"] == "100"][0]
    return np.array([float(x) for x in final["R"]]).reshape(3, 3)


def step_overhead():
    body = lgsvi.RigidBody(inertia_d=[1.3, 2.1, 1.2])
    steps = 2000

    def python_loop():
        it = lgsvi.Integrator(body, 0.5, 8, omega=W0)
        for _ in range(steps):
            it.step()

    def rust_loop():
        it = lgsvi.Integrator(body, 0.5, 8, omega=W0)
        it.advance(steps)

    python_loop(), rust_loop()  # warm the tables
    py_t, rs_t = [], []
    for _ in range(REPEATS):
        py_t.append(median_time(python_loop, 1))
        rs_t.append(median_time(rust_loop, 1))
    py_t, rs_t = statistics.median(py_t), statistics.median(rs_t)
    return {
        "python_step_us": py_t / steps * 1e6,
        "rust_step_us": rs_t / steps * 1e6,
        "ratio": py_t / rs_t,
    }


def run_overhead():
    body = lgsvi.RigidBody(inertia_d=[1.3, 2.1, 1.2])
    t_end, h = 1000.0, 0.5

    def recorded():
        lgsvi.Integrator(body, h, 8, omega=W0).run_until(t_end)

    def library():
        lgsvi.Integrator(body, h, 8, omega=W0)._library_run_until(t_end)

    rng = np.random.default_rng(0)
    members = 64
    attitudes = np.stack([np.eye(3)] * members)
    omegas = W0 + 0.1 * rng.normal(size=(members, 3))

    def ensemble():
        lgsvi.run_ensemble(body, h, 8, attitudes, omegas, 100.0, threads=1)

    def ensemble_bare():
        for w in omegas:
            lgsvi.Integrator(body, h, 8, omega=w).advance(200)

    recorded(), library(), ensemble(), ensemble_bare()
    # Alternated, so that the machine's drifts fall on both alike.
    r, b = [], []
    for _ in range(REPEATS):
        r.append(median_time(recorded, 1))
        b.append(median_time(library, 1))
    r, b = statistics.median(r), statistics.median(b)
    e, eb = median_time(ensemble), median_time(ensemble_bare)
    return {
        "run_until_s": r,
        "library_run_until_s": b,
        "run_until_over_library": r / b,
        "run_ensemble_s": e,
        "ensemble_by_advance_s": eb,
        "run_ensemble_over_advance": e / eb,
    }


def quaternion_rhs(t, y):
    q, w = y[:4], y[4:]
    qw, qv = q[0], q[1:]
    dq = 0.5 * np.concatenate([[-qv @ w], qw * w + np.cross(qv, w)])
    dw = np.linalg.solve(J, np.cross(J @ w, w))
    return np.concatenate([dq, dw])


def quaternion_matrix(q):
    q = q / np.linalg.norm(q)
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def scipy_run(rtol):
    y0 = np.concatenate([[1.0, 0.0, 0.0, 0.0], W0])
    sol = solve_ivp(quaternion_rhs, (0.0, 100.0), y0, method="DOP853", rtol=rtol, atol=rtol * 1e-2)
    return quaternion_matrix(sol.y[:4, -1])


def against_scipy():
    r_ref = reference_attitude()
    error = lambda r: float(np.max(np.abs(r - r_ref)))
    body = lgsvi.RigidBody(inertia_d=[1.3, 2.1, 1.2])
    rows = []
    for target in (1e-10, 1e-12):
        # scipy: the loosest rtol (in steps of 10^(1/4)) that reaches the target.
        scipy_rtol = None
        for k in range(28, 60):
            rtol = 10 ** (-k / 4)
            if error(scipy_run(rtol)) <= target:
                scipy_rtol = rtol
                break
        if scipy_rtol is None:
            rows.append({"target": target, "scipy": "does not reach it"})
            continue
        scipy_error = error(scipy_run(scipy_rtol))
        scipy_t = median_time(lambda: scipy_run(scipy_rtol), repeats=3)
        # lgsvi's checked tolerance run: tol = the target (accepted within 3 tol; it lands
        # far below).
        def checked():
            return lgsvi.Integrator(body, 0.5, omega=W0).run_until(100.0, tol=target)

        checked_error = error(checked().attitude[-1])
        checked_t = median_time(checked)
        # lgsvi's fastest fixed (h, n) as accurate, over a small grid.
        best = None
        for h in (0.5, 1.0, 1.25):
            for n in range(6, 20):
                run = lambda: lgsvi.Integrator(body, h, n, omega=W0).run_until(100.0, every=10**9)
                e = error(run().attitude[-1])
                if e <= target:
                    t = median_time(run)
                    if best is None or t < best[0]:
                        best = (t, h, n, e)
                    break
        rows.append({
            "target": target,
            "scipy_rtol": scipy_rtol,
            "scipy_error": scipy_error,
            "scipy_s": scipy_t,
            "lgsvi_checked_error": checked_error,
            "lgsvi_checked_s": checked_t,
            "scipy_over_checked": scipy_t / checked_t,
            "lgsvi_fixed": {"h": best[1], "n": best[2], "error": best[3], "s": best[0]},
            "scipy_over_fixed": scipy_t / best[0],
        })
    return rows


def main():
    results = {
        "step": step_overhead(),
        "runs": run_overhead(),
        "scipy": against_scipy(),
    }
    json.dump(results, sys.stdout, indent=2)
    print()


if __name__ == "__main__":
    main()
