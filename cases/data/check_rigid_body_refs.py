#!/usr/bin/env python3
"""Recomputes the states of rigid_body_refs.json from their inputs alone and compares.

An independent route to every stored state: a Taylor-series integrator of the free rigid
body and the heavy top in decimal arithmetic (Python's `decimal`, default 60 significant
digits), written for this check from the equations in rigid_body_refs.README.md:

    dR/dt = R hat(Ω),    J dΩ/dt = (JΩ) × Ω + m g ρ × (Rᵀ e₃).

Both right-hand sides are bilinear, so the Taylor coefficients follow by Cauchy products
(order 40; the step is chosen from the decay of the last coefficients so that the
truncation stays below 1e-(digits+5)). The inputs (J, m g, ρ, R(0), Ω(0)) are read from the
JSON as exact decimals. Prints, per case and output time, the largest difference of R and Ω
from the stored 40-digit values; exits non-zero if any exceeds the tolerance (1e-35, or
the stored `abs_err_bound` times 10 where that is larger).

    python3 cases/data/check_rigid_body_refs.py            # t <= 10, a few seconds
    python3 cases/data/check_rigid_body_refs.py --full     # every stored time, about 70 s
    python3 cases/data/check_rigid_body_refs.py --digits 80 --full --cases C,C_mg1

Measured (60 digits, --full): every state of the five cases within 5e-40 of the stored
value, the rounding of its 40 digits, the chaotic case C at t = 100 included (2.0e-40; at
80 digits the same). Only the standard library is needed.
"""

import argparse
import json
import sys
from decimal import Decimal, getcontext
from pathlib import Path

ORDER = 40


def hat_times(r, w):
    """R hat(w) for a 3x3 list R and a 3-vector w (hat(a,b,c) = [[0,-c,b],[c,0,-a],[-b,a,0]])."""
    a, b, c = w
    out = []
    for i in range(3):
        r0, r1, r2 = r[i]
        out.append([r1 * c - r2 * b, r2 * a - r0 * c, r0 * b - r1 * a])
    return out


def cross(u, v):
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


def taylor(r0, w0, j, mg, rho, order):
    """Taylor coefficients (R_k, Ω_k), k = 0..order, of the motion from (r0, w0)."""
    rs, ws = [r0], [w0]
    zero = Decimal(0)
    for k in range(order):
        dr = [[zero] * 3 for _ in range(3)]
        dmu = [zero, zero, zero]
        for i in range(k + 1):
            ri, wi = rs[i], ws[k - i]
            t = hat_times(ri, wi)
            for a in range(3):
                for b in range(3):
                    dr[a][b] += t[a][b]
            jw = [j[0] * ws[i][0], j[1] * ws[i][1], j[2] * ws[i][2]]
            c = cross(jw, ws[k - i])
            for a in range(3):
                dmu[a] += c[a]
        if mg != 0:
            third_row = rs[k][2]  # (R_k)ᵀ e₃
            g = cross(rho, third_row)
            for a in range(3):
                dmu[a] += mg * g[a]
        kp = Decimal(k + 1)
        rs.append([[x / kp for x in row] for row in dr])
        ws.append([dmu[a] / (j[a] * kp) for a in range(3)])
    return rs, ws


def size(coefficient):
    r, w = coefficient
    return max(max(abs(x) for row in r for x in row), max(abs(x) for x in w))


def evaluate(rs, ws, h):
    """The series at h (Horner)."""
    r = [[Decimal(0)] * 3 for _ in range(3)]
    w = [Decimal(0)] * 3
    for k in range(len(rs) - 1, -1, -1):
        r = [[r[a][b] * h + rs[k][a][b] for b in range(3)] for a in range(3)]
        w = [w[a] * h + ws[k][a] for a in range(3)]
    return r, w


def integrate(case, times, digits):
    j = [Decimal(x) for x in case["J"]]
    mg = Decimal(case["mg"])
    rho = [Decimal(x) for x in case["rho"]]
    r0 = case["R0"]
    r = [[Decimal(r0[3 * a + b]) for b in range(3)] for a in range(3)]
    w = [Decimal(x) for x in case["omega0"]]
    eps = Decimal(10) ** (-(digits + 5))
    t = Decimal(0)
    for target in times:
        target = Decimal(target)
        while t < target:
            rs, ws = taylor(r, w, j, mg, rho, ORDER)
            # The step at which the last two coefficients' terms fall below eps.
            last = max(size((rs[-1], ws[-1])), size((rs[-2], ws[-2])), Decimal(10) ** -300)
            h = (eps / last) ** (Decimal(1) / Decimal(ORDER))
            h = min(h, target - t)
            r, w = evaluate(rs, ws, h)
            t += h
        yield target, r, w


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--full", action="store_true", help="every stored time, t = 100 too")
    parser.add_argument("--digits", type=int, default=60, help="working digits (default 60)")
    parser.add_argument("--cases", default="A,B,C,B_mg1,C_mg1")
    args = parser.parse_args()
    getcontext().prec = args.digits
    path = Path(__file__).with_name("rigid_body_refs.json")
    data = json.loads(path.read_text())
    worst_ok = True
    for name in args.cases.split(","):
        case = data["cases"][name]
        states = [s for s in case["states"] if args.full or Decimal(s["t"]) <= 10]
        times = [s["t"] for s in states]
        largest = 0.0
        for (t, r, w), stored in zip(integrate(case, times, args.digits), states):
            dr = max(abs(r[a][b] - Decimal(stored["R"][3 * a + b])) for a in range(3) for b in range(3))
            dw = max(abs(w[a] - Decimal(stored["omega"][a])) for a in range(3))
            diff = float(max(dr, dw))
            bound = max(1e-35, 10 * float(stored.get("abs_err_bound", 0)))
            largest = max(largest, diff)
            ok = diff <= bound
            worst_ok &= ok
            print(f"{name:6} t = {str(t):>5}: largest difference {diff:.1e} (tolerance {bound:.0e}){'' if ok else '  <-- exceeds'}")
        print(f"{name}: {len(states)} states, largest difference {largest:.1e}")
    sys.exit(0 if worst_ok else 1)


if __name__ == "__main__":
    main()
