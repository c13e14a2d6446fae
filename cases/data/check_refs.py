#!/usr/bin/env python3
"""Recomputes the stored states of the references from their inputs alone and compares.

An independent route to every stored state of rigid_body_refs.json (the free rigid body
and the heavy top: A, B, C, B_mg1, C_mg1) and se3_forced_refs.json (FJ1, a free body with a
full inertia tensor; F1, a constant body torque; O1, a body orbiting a point mass under
MacCullagh's potential): a Taylor-series integrator in decimal arithmetic (Python's
`decimal`, default 60 significant digits), written for this check from the equations in
the two READMEs. With `y = Rᵀx` the body-frame position and `r² = x·x`:

    dR/dt = R hat(Ω),
    J dΩ/dt = (JΩ) × Ω + τ + m g ρ × (Rᵀe₃) + (3μ/r⁵) y × (J y),
    dx/dt = ẋ,
    m dẋ/dt = −μ m x/r³ − (3μ/(2r⁵))(tr J − 5 yᵀJy/r²) x − (3μ/r⁵) R J y,

each term where its case has it (gravity m g ρ for the heavy tops, τ for F1, μ for O1).
Every right-hand side is a sum of products of series, the powers r⁻³, r⁻⁵, r⁻⁷ by the
recurrence of `u^α`; order 40, the step chosen from the decay of the last coefficients so
that the truncation stays below 1e-(digits + 5). Prints, per case and output time, the
largest difference of R, Ω (and x, ẋ for O1) from the stored 40-digit values; exits
non-zero if any exceeds 1e-35 (or ten times the state's stored `abs_err_bound`, where that
is larger).

    python3 cases/data/check_refs.py              # t <= 10, about 17 s
    python3 cases/data/check_refs.py --full       # every stored time, about 160 s
    python3 cases/data/check_refs.py --full --cases C,O1 --digits 80

Measured (60 digits, --full): every one of the 176 states within 5e-40 of its stored value,
the rounding of its 40 digits, the chaotic case C at t = 100 included (2.0e-40; at 80 digits
the same). Only the standard library is needed.
"""

import argparse
import ast
import json
import sys
from decimal import Decimal, getcontext
from pathlib import Path

ORDER = 40


def parse(value):
    """A stored value: a list, or a list written as a string."""
    return ast.literal_eval(value) if isinstance(value, str) else value


def cross(u, v):
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


def dot(u, v):
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def mat_vec(m, v):
    return [dot(m[a], v) for a in range(3)]


def mat_t_vec(m, v):
    return [m[0][a] * v[0] + m[1][a] * v[1] + m[2][a] * v[2] for a in range(3)]


def hat_times(r, w):
    a, b, c = w
    return [[r[i][1] * c - r[i][2] * b, r[i][2] * a - r[i][0] * c, r[i][0] * b - r[i][1] * a] for i in range(3)]


def inverse(m):
    (a, b, c), (d, e, f), (g, h, i) = m
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    return [
        [(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det],
        [(f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det],
        [(d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det],
    ]


def vsum(terms):
    out = [Decimal(0)] * 3
    for t in terms:
        out = [out[a] + t[a] for a in range(3)]
    return out


def vscale(s, v):
    return [s * x for x in v]


class Model:
    def __init__(self, case):
        self.kind = case["kind"]
        if "J_full" in case:
            self.j = [[Decimal(x) for x in row] for row in parse(case["J_full"])]
        else:
            d = [Decimal(x) for x in parse(case["J"])]
            z = Decimal(0)
            self.j = [[d[0], z, z], [z, d[1], z], [z, z, d[2]]]
        self.j_inv = inverse(self.j)
        self.tau = [Decimal(x) for x in parse(case.get("tau_const", "['0', '0', '0']"))]
        self.mg = Decimal(case.get("mg", "0"))
        self.rho = [Decimal(x) for x in parse(case.get("rho", "['0', '0', '0']"))]
        self.orbit = self.kind == "orbit"
        if self.orbit:
            self.mu = Decimal(case["mu"])
            self.m = Decimal(case["m"])
            self.trace = self.j[0][0] + self.j[1][1] + self.j[2][2]

    def taylor(self, r0, w0, x0, v0, order):
        """Taylor coefficients of (R, Ω, x, ẋ), k = 0..order."""
        zero = Decimal(0)
        rs, ws, xs, vs = [r0], [w0], [x0], [v0]
        u, p3, p5, p7, ys, jys, q, g, c = [], [], [], [], [], [], [], [], []
        for k in range(order):
            torque = vsum(cross(mat_vec(self.j, ws[i]), ws[k - i]) for i in range(k + 1))
            if k == 0:
                torque = vsum([torque, self.tau])
            if self.mg != 0:
                # m g ρ × (R_k)ᵀe₃: the third row of R_k.
                torque = vsum([torque, vscale(self.mg, cross(self.rho, rs[k][2]))])
            force = [zero, zero, zero]
            if self.orbit:
                u.append(sum(dot(xs[i], xs[k - i]) for i in range(k + 1)))
                for p, alpha in ((p3, Decimal(-3) / 2), (p5, Decimal(-5) / 2), (p7, Decimal(-7) / 2)):
                    if k == 0:
                        p.append(u[0] ** alpha)
                    else:
                        p.append(sum((alpha * j - (k - j)) * u[j] * p[k - j] for j in range(1, k + 1)) / (k * u[0]))
                ys.append(vsum(mat_t_vec(rs[i], xs[k - i]) for i in range(k + 1)))
                jys.append(mat_vec(self.j, ys[k]))
                q.append(sum(dot(ys[i], jys[k - i]) for i in range(k + 1)))
                # g = tr J r⁻⁵ − 5 yᵀJy r⁻⁷; c = y × Jy.
                g.append(self.trace * p5[k] - 5 * sum(p7[i] * q[k - i] for i in range(k + 1)))
                c.append(vsum(cross(ys[i], jys[k - i]) for i in range(k + 1)))
                three_mu = 3 * self.mu
                torque = vsum([torque, vscale(three_mu, vsum(vscale(p5[i], c[k - i]) for i in range(k + 1)))])
                rjy = [vsum(mat_vec(rs[i], jys[j - i]) for i in range(j + 1)) for j in range(k + 1)]
                force = vsum([
                    vscale(-self.mu * self.m, vsum(vscale(p3[i], xs[k - i]) for i in range(k + 1))),
                    vscale(-three_mu / 2, vsum(vscale(g[i], xs[k - i]) for i in range(k + 1))),
                    vscale(-three_mu, vsum(vscale(p5[i], rjy[k - i]) for i in range(k + 1))),
                ])
            kp = Decimal(k + 1)
            dr = [[zero] * 3 for _ in range(3)]
            for i in range(k + 1):
                t = hat_times(rs[i], ws[k - i])
                dr = [[dr[a][b] + t[a][b] for b in range(3)] for a in range(3)]
            rs.append([[x / kp for x in row] for row in dr])
            ws.append([x / kp for x in mat_vec(self.j_inv, torque)])
            xs.append([x / kp for x in vs[k]])
            vs.append([x / (self.m * kp) for x in force] if self.orbit else [zero] * 3)
        return rs, ws, xs, vs


def largest(coefficient):
    r, w, x, v = coefficient
    return max([abs(e) for row in r for e in row] + [abs(e) for e in w + x + v])


def evaluate(series, h):
    rs, ws, xs, vs = series
    r = [[Decimal(0)] * 3 for _ in range(3)]
    w, x, v = [Decimal(0)] * 3, [Decimal(0)] * 3, [Decimal(0)] * 3
    for k in range(len(rs) - 1, -1, -1):
        r = [[r[a][b] * h + rs[k][a][b] for b in range(3)] for a in range(3)]
        w = [w[a] * h + ws[k][a] for a in range(3)]
        x = [x[a] * h + xs[k][a] for a in range(3)]
        v = [v[a] * h + vs[k][a] for a in range(3)]
    return r, w, x, v


def integrate(case, times, digits):
    model = Model(case)
    r0 = parse(case["R0"])
    r = [[Decimal(r0[3 * a + b]) for b in range(3)] for a in range(3)]
    w = [Decimal(x) for x in parse(case["omega0"])]
    x = [Decimal(e) for e in parse(case.get("x0", "['0', '0', '0']"))]
    v = [Decimal(e) for e in parse(case.get("v0", "['0', '0', '0']"))]
    eps = Decimal(10) ** (-(digits + 5))
    t = Decimal(0)
    for target in times:
        target = Decimal(target)
        while t < target:
            series = model.taylor(r, w, x, v, ORDER)
            tail = max(largest([s[-1] for s in series]), largest([s[-2] for s in series]), Decimal(10) ** -300)
            h = min((eps / tail) ** (Decimal(1) / Decimal(ORDER)), target - t)
            r, w, x, v = evaluate(series, h)
            t += h
        yield target, r, w, x, v


FILES = ("rigid_body_refs.json", "se3_forced_refs.json")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--full", action="store_true", help="every stored time, t = 100 too")
    parser.add_argument("--digits", type=int, default=60, help="working digits (default 60)")
    parser.add_argument("--cases", help="comma-separated case names (default: every case)")
    args = parser.parse_args()
    getcontext().prec = args.digits
    wanted = args.cases.split(",") if args.cases else None
    all_ok, checked = True, 0
    for file in FILES:
        data = json.loads(Path(__file__).with_name(file).read_text())
        for name, case in data["cases"].items():
            if wanted is not None and name not in wanted:
                continue
            states = [s for s in case["states"] if args.full or Decimal(s["t"]) <= 10]
            worst = 0.0
            results = integrate(case, [s["t"] for s in states], args.digits)
            for (t, r, w, x, v), stored in zip(results, states):
                diffs = [abs(r[a][b] - Decimal(parse(stored["R"])[3 * a + b])) for a in range(3) for b in range(3)]
                diffs += [abs(w[a] - Decimal(parse(stored["omega"])[a])) for a in range(3)]
                if "position" in stored:
                    diffs += [abs(x[a] - Decimal(parse(stored["position"])[a])) for a in range(3)]
                    diffs += [abs(v[a] - Decimal(parse(stored["velocity"])[a])) for a in range(3)]
                diff = float(max(diffs))
                tolerance = max(1e-35, 10 * float(stored.get("abs_err_bound", 0)))
                ok = diff <= tolerance
                all_ok &= ok
                worst = max(worst, diff)
                mark = "" if ok else f"  <-- exceeds {tolerance:.0e}"
                print(f"{name:6} t = {str(t):>5}: largest difference {diff:.1e}{mark}")
            checked += len(states)
            print(f"{name} ({file}): {len(states)} states, largest difference {worst:.1e}")
    print(f"{checked} states checked: {'all within tolerance' if all_ok else 'SOME EXCEED IT'}")
    sys.exit(0 if all_ok else 1)


if __name__ == "__main__":
    main()
