#!/usr/bin/env python3
"""Reference values for `lgsvi_mechanics::exact` (Jacobi elliptic functions and the exact
free rigid body), computed with mpmath at 40 significant digits.

    python3 mechanics/tests/data/generate_exact_reference.py > mechanics/tests/data/exact_reference.json

Independence from the Rust code under test:
- sn, cn, dn come from mpmath's `ellipfun` (its own algorithm, at 40 digits).
- The free-body trajectories use the classical Landau-Lifshitz formulas for mu(t), but the
  precession angle psi(t) is integrated by adaptive quadrature (`mp.quad`) of
  psi' = M (mu_x^2/J_x + mu_y^2/J_y)/(mu_x^2 + mu_y^2) directly, not through the third-kind
  integral, argument reduction and Carlson forms the Rust code uses.
- The script validates itself: (1) case A of the shared references, recomputed here from its
  exact decimal inputs, must agree with the shared Taylor-series trajectory to 1e-30;
  (2) for every body, Euler's equations mu' = mu x J^-1 mu and R' = R hat(Omega) are checked
  by numerical differentiation at two times.
- Inputs are the *double-precision* numbers the Rust tests pass (Python floats are IEEE
  doubles, converted exactly), so the references are exact for the problem the code is
  given: input rounding is not part of the measured error.

Requires mpmath (pure Python). Run time: about a minute.
"""
import json
import math
import sys

import mpmath as mp

mp.mp.dps = 40
DIGITS = 25


def s(x):
    return mp.nstr(mp.mpf(x), DIGITS, strip_zeros=False)


def jacobi_table():
    us = [0.0, 1e-8, 0.37, -1.1, 2.6, -7.9, 31.4, 100.3]
    ms = [0.0, 1e-9, 0.2, 0.5, 0.8, 0.99, 1.0 - 1e-9, 1.0 - 2.0**-40, 1.0]
    rows = []
    for m in ms:
        for u in us:
            mm, uu = mp.mpf(m), mp.mpf(u)
            rows.append({
                "u": repr(u),
                "m": repr(m),
                "sn": s(mp.ellipfun("sn", uu, m=mm)),
                "cn": s(mp.ellipfun("cn", uu, m=mm)),
                "dn": s(mp.ellipfun("dn", uu, m=mm)),
            })
    return rows


def hat(w):
    return mp.matrix([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


class Body:
    """The exact free motion, Landau-Lifshitz section 37, in mpmath."""

    def __init__(self, J, omega0, R0):
        self.J = [mp.mpf(x) for x in J]
        self.R0 = mp.matrix(R0)
        mu = [self.J[i] * mp.mpf(omega0[i]) for i in range(3)]
        self.mu0 = mu
        J = self.J
        order = sorted(range(3), key=lambda i: J[i])
        lo, mid, hi = order
        n_mid = mu[lo] ** 2 * (J[lo] - J[mid]) / J[lo] + mu[hi] ** 2 * (J[hi] - J[mid]) / J[hi]
        a, c = (lo, hi) if n_mid >= 0 else (hi, lo)
        b = mid
        self.a, self.b, self.c = a, b, c
        M2 = sum(x * x for x in mu)
        E2 = sum(mu[i] ** 2 / J[i] for i in range(3))
        self.M = mp.sqrt(M2)
        Na, Nc = M2 - E2 * J[a], E2 * J[c] - M2
        Aa = mp.sqrt(J[a] * Nc / (J[c] - J[a]))
        Ab = mp.sqrt(J[b] * Nc / (J[c] - J[b]))
        Ac = mp.sqrt(J[c] * Na / (J[c] - J[a]))
        self.lam = mp.sqrt((J[c] - J[b]) * Na / (J[a] * J[b] * J[c]))
        self.m = (J[b] - J[a]) * Nc / ((J[c] - J[b]) * Na)
        alpha = -1 if mu[a] < 0 else 1
        gamma = -1 if mu[c] < 0 else 1
        eps = 1 if (a + 1) % 3 == b else -1
        beta = eps * gamma * mp.sign(J[c] - J[b])
        self.amp = [alpha * Aa, alpha * beta * Ab, gamma * Ac]
        phi0 = mp.atan2(mu[b] / self.amp[1], mu[a] / self.amp[0])
        self.u0 = mp.ellipf(phi0, self.m)
        self.P0 = self.polhode_frame(mu)
        self.cache = {mp.mpf(0): mp.mpf(0)}

    def mu(self, t):
        u = self.lam * t + self.u0
        out = [0, 0, 0]
        out[self.a] = self.amp[0] * mp.ellipfun("cn", u, m=self.m)
        out[self.b] = self.amp[1] * mp.ellipfun("sn", u, m=self.m)
        out[self.c] = self.amp[2] * mp.ellipfun("dn", u, m=self.m)
        return out

    def psi_dot(self, t):
        mu = self.mu(t)
        x, y = (self.c + 1) % 3, (self.c + 2) % 3
        num = mu[x] ** 2 / self.J[x] + mu[y] ** 2 / self.J[y]
        return self.M * num / (mu[x] ** 2 + mu[y] ** 2)

    def psi(self, t):
        t = mp.mpf(t)
        start = max(k for k in self.cache if k <= t)
        grid = [start + k * mp.mpf("0.25") for k in range(int((t - start) / mp.mpf("0.25")) + 1)]
        if grid[-1] < t:
            grid.append(t)
        value = self.cache[start] + mp.quad(self.psi_dot, grid)
        self.cache[t] = value
        return value

    def polhode_frame(self, mu):
        c = self.c
        x, y = (c + 1) % 3, (c + 2) % 3
        rho = mp.sqrt(mu[x] ** 2 + mu[y] ** 2)
        sp, cp = mu[x] / rho, mu[y] / rho
        st, ct = rho / self.M, mu[c] / self.M
        rows = mp.matrix([[cp, -sp, 0], [ct * sp, ct * cp, -st], [st * sp, st * cp, ct]])
        P = mp.matrix(3, 3)
        for i in range(3):
            P[i, x], P[i, y], P[i, c] = rows[i, 0], rows[i, 1], rows[i, 2]
        return P

    def attitude(self, t):
        psi = self.psi(t)
        Rz = mp.matrix([[mp.cos(psi), -mp.sin(psi), 0], [mp.sin(psi), mp.cos(psi), 0], [0, 0, 1]])
        return self.R0 * self.P0.T * Rz * self.polhode_frame(self.mu(t))

    def self_check(self, t):
        """Euler's equations and R' = R hat(Omega) by numerical differentiation."""
        t = mp.mpf(t)
        mu = self.mu(t)
        om = [mu[i] / self.J[i] for i in range(3)]
        dmu = [mp.diff(lambda s, i=i: self.mu(s)[i], t) for i in range(3)]
        rhs = [mu[1] * om[2] - mu[2] * om[1], mu[2] * om[0] - mu[0] * om[2], mu[0] * om[1] - mu[1] * om[0]]
        euler = max(abs(dmu[i] - rhs[i]) for i in range(3))
        # R'(t) from a 4th-order central difference at step 1e-8 (error ~1e-32 + cancellation).
        d = mp.mpf("1e-8")
        Rp = (-self.attitude(t + 2 * d) + 8 * self.attitude(t + d) - 8 * self.attitude(t - d) + self.attitude(t - 2 * d)) / (12 * d)
        kin = mp.mnorm(Rp - self.attitude(t) * hat(om), 1)
        assert euler < mp.mpf("1e-25"), ("Euler residual", euler)
        assert kin < mp.mpf("1e-20"), ("kinematic residual", kin)
        return float(euler), float(kin)


def trajectory(name, J, omega0, R0, times, note):
    body = Body(J, omega0, R0)
    checks = [body.self_check(t) for t in (mp.mpf("0.7"), mp.mpf(times[-1]) / 2)]
    states = []
    for t in times:
        R = body.attitude(mp.mpf(t))
        mu = body.mu(mp.mpf(t))
        states.append({
            "t": repr(t),
            "R": [s(R[i, j]) for i in range(3) for j in range(3)],
            "omega": [s(mu[i] / body.J[i]) for i in range(3)],
        })
    M2 = sum(x * x for x in body.mu0)
    n_mid = M2 - sum(x * x / j for x, j in zip(body.mu0, body.J)) * sorted(body.J)[1]
    print(f"{name}: N_mid/M^2 = {mp.nstr(n_mid / M2, 4)}, m = {mp.nstr(body.m, 6)}, 1 - m = {mp.nstr(1 - body.m, 6)}, "
          f"checks {checks}", file=sys.stderr)
    return {
        "name": name,
        "note": note,
        "J": [repr(x) for x in J],
        "omega0": [repr(x) for x in omega0],
        "R0": [repr(x) for row in R0 for x in row],
        "m": s(body.m),
        "states": states,
    }


def rotation_from_quaternion(w, x, y, z):
    """A rotation matrix in doubles (normalised in floating point: the reference uses these
    very doubles, orthogonal only to rounding, as R(0))."""
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]


def check_case_a():
    """Case A from its exact decimal inputs against the shared Taylor-series reference."""
    import os
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    refs = json.load(open(os.path.join(root, "tests", "data", "rigid_body_refs.json")))
    case = refs["cases"]["A"]
    body = Body([mp.mpf(x) for x in case["J"]], [mp.mpf(x) for x in case["omega0"]],
                [[mp.mpf(case["R0"][3 * i + j]) for j in range(3)] for i in range(3)])
    worst = 0
    for st in case["states"]:
        R = body.attitude(mp.mpf(st["t"]))
        worst = max(worst, max(abs(R[i, j] - mp.mpf(st["R"][3 * i + j])) for i in range(3) for j in range(3)))
    assert worst < mp.mpf("1e-30"), worst
    print(f"case A, decimal inputs, vs shared Taylor reference: {mp.nstr(worst, 3)}", file=sys.stderr)
    return float(worst)


def main():
    agreement = check_case_a()
    I = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    times_a = [0.5 * k for k in range(21)] + [100.0]
    times = [0.0, 0.3, 1.0, 2.5, 5.0, 10.0, 30.0]
    bodies = [
        trajectory("A_double", [3.3, 2.5, 3.4], [-2.0, 1.9, -1.0], I, times_a,
                   "the paper's rigid body (case A) with its inputs rounded to doubles; "
                   "rotation about the smallest axis"),
        trajectory("largest_axis", [1.0, 2.0, 3.0], [0.3, -0.5, 1.9],
                   rotation_from_quaternion(0.8, 0.1, -0.5, 0.3), times,
                   "rotation about the largest axis, general R(0)"),
        trajectory("prolate_symmetric", [2.0, 3.0, 2.0], [0.7, -0.3, 1.1],
                   rotation_from_quaternion(0.2, -0.9, 0.3, 0.1), times,
                   "symmetric body J1 = J3 < J2: uniform precession"),
        trajectory("oblate_symmetric", [3.0, 3.0, 2.0], [0.5, 1.0, -2.0], I, times,
                   "symmetric body J1 = J2 > J3: uniform precession"),
        trajectory("near_separatrix_outside", [1.0, 2.0, 3.0], [1.0, 0.5, 0.5773503], I, times,
                   "just outside the separatrix, (M^2 - 2E J_mid)/M^2 = +2e-8: "
                   "polhode about the largest axis"),
        trajectory("near_separatrix_inside", [1.0, 2.0, 3.0], [1.0, 0.5, 0.5773502], I, times,
                   "just inside the separatrix, (M^2 - 2E J_mid)/M^2 = -4e-8: "
                   "polhode about the smallest axis"),
        trajectory("separatrix", [3.0, 4.0, 6.0], [2.0, 0.5, 1.0], I, times,
                   "exactly on the separatrix (mu = (6, 2, 6)): mu tends to the middle axis"),
    ]
    print(json.dumps({
        "about": "Generated by generate_exact_reference.py (mpmath, 40 digits); do not edit.",
        "case_a_formula_vs_shared_taylor": agreement,
        "jacobi": jacobi_table(),
        "bodies": bodies,
    }, indent=1))


if __name__ == "__main__":
    main()
