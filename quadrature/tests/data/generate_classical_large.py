#!/usr/bin/env python3
"""Reference nodes and weights of large Gauss-Hermite, -Laguerre and -Jacobi rules (m = 10^4
and 10^5), at sampled indices, in mpmath: the check of the crate's O(m) march.

Independent of the Rust code under test. For each sampled index i (ascending order), the
i-th root is bracketed by bisection on the Sturm count of the orthonormal three-term
recurrence in double precision (the number of sign changes of p_0(x), ..., p_m(x) is the
number of roots above x; the recurrence is rescaled by powers of two so it neither
overflows nor underflows), then refined by Newton's iteration at 40 significant digits on
the standard recurrences, and its weight is the family's closed form (not the crate's
1/(P y'^2) normalised by the total mass):

  Hermite   w_i = 2^(m-1) m! sqrt(pi) / (m^2 H_(m-1)(x_i)^2)
  Laguerre  w_i = Gamma(m+a+1) / (m! x_i L_m^(a)'(x_i)^2)
  Jacobi    w_i = Gamma(m+a+1) Gamma(m+b+1) 2^(a+b+1)
                  / (Gamma(m+a+b+1) m! (1-x_i^2) P_m^(a,b)'(x_i)^2)

Each line: `family params m i node weight` with 30 significant digits. Standard library and
mpmath only; about ten minutes on one core.

Run:  python3 quadrature/tests/data/generate_classical_large.py
"""
import math
import os

import mpmath as mp

mp.mp.dps = 40
DIGITS = 30
HERE = os.path.dirname(os.path.abspath(__file__))
SIZES = [10_000, 100_000]
TOL = mp.mpf(10) ** -36


def orthonormal(family, params, m):
    """The Jacobi matrix (diagonal a_k, off-diagonal s_k = sqrt(b_(k+1))), k < m, in floats."""
    if family == "hermite":
        return [0.0] * m, [math.sqrt(0.5 * (k + 1)) for k in range(m)]
    if family == "laguerre":
        (a,) = params
        return ([2 * k + 1 + a for k in range(m)],
                [math.sqrt((k + 1) * (k + 1 + a)) for k in range(m)])
    a, b = params
    s = a + b
    diag, off = [], []
    for k in range(m):
        c = 2 * k + s
        diag.append((b - a) / (s + 2) if k == 0 else (b * b - a * a) / (c * (c + 2)))
        n = k + 1
        c = 2 * n + s
        if n == 1:
            off.append(math.sqrt(4 * (1 + a) * (1 + b) / (c * c * (c + 1))))
        else:
            off.append(math.sqrt(4 * n * (n + a) * (n + b) * (n + s)
                                 / (c * c * (c + 1) * (c - 1))))
    return diag, off


def roots_above(diag, off, x):
    """Sign changes of the Sturm sequence p_0(x), ..., p_m(x)."""
    p_prev, p = 0.0, 1.0
    changes, sign = 0, 1.0
    for k in range(len(diag)):
        back = off[k - 1] if k > 0 else 0.0
        p_prev, p = p, ((x - diag[k]) * p - back * p_prev) / off[k]
        if p != 0.0:
            if (p > 0) != (sign > 0):
                changes += 1
            sign = 1.0 if p > 0 else -1.0
        if abs(p) > 1e150:
            p *= 1e-150
            p_prev *= 1e-150
    return changes


def bracket(diag, off, m, i, lo, hi):
    """The i-th root (ascending) to about an ulp by bisection on the count."""
    # count(x) = roots above x: m - i at or below the root, m - i - 1 above it.
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if roots_above(diag, off, mid) >= m - i:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def hermite(m, x):
    """(H_m(x), H_m'(x), H_(m-1)(x)), physicists' Hermite polynomials."""
    h0, h1 = mp.mpf(1), 2 * x
    for k in range(1, m):
        h0, h1 = h1, 2 * x * h1 - 2 * k * h0
    return h1, 2 * m * h0, h0


def laguerre(m, a, x):
    """(L_m^(a)(x), L_m^(a)'(x))."""
    l0, l1 = mp.mpf(1), 1 + a - x
    for k in range(1, m):
        l0, l1 = l1, ((2 * k + 1 + a - x) * l1 - (k + a) * l0) / (k + 1)
    return l1, (m * l1 - (m + a) * l0) / x


def jacobi(m, a, b, x):
    """(P_m^(a,b)(x), P_m^(a,b)'(x)) by the standard recurrence and its derivative."""
    p0, d0 = mp.mpf(1), mp.mpf(0)
    p1 = (a - b) / 2 + (a + b + 2) * x / 2
    d1 = (a + b + 2) / 2
    for n in range(1, m):
        k = n + 1
        c = 2 * k + a + b
        a1 = 2 * k * (k + a + b) * (c - 2)
        a2 = (c - 1) * (a * a - b * b)
        a3 = (c - 2) * (c - 1) * c
        a4 = 2 * (k + a - 1) * (k + b - 1) * c
        p0, p1, d0, d1 = (p1, ((a2 + a3 * x) * p1 - a4 * p0) / a1,
                          d1, ((a2 + a3 * x) * d1 + a3 * p1 - a4 * d0) / a1)
    return p1, d1


def newton(f_df, x):
    x = mp.mpf(x)
    for _ in range(20):
        f, d = f_df(x)
        dx = f / d
        x -= dx
        if abs(dx) <= TOL * max(1, abs(x)):
            return x
    raise RuntimeError("Newton did not converge")


def sample(m):
    """Both ends and five spread between."""
    return sorted(set([0, 1, 2, m - 3, m - 2, m - 1] + [m * k // 6 + 1 for k in range(1, 6)]))


def rule(family, params, m):
    diag, off = orthonormal(family, params, m)
    if family == "hermite":
        lo, hi = -math.sqrt(2 * m + 1) - 1, math.sqrt(2 * m + 1) + 1
    elif family == "laguerre":
        lo, hi = 0.0, 4 * m + 2 * params[0] + 10
    else:
        lo, hi = -1.0, 1.0
    mpp = [mp.mpf(p) for p in params]
    out = []
    for i in sample(m):
        guess = bracket(diag, off, m, i, lo, hi)
        if family == "hermite":
            x = newton(lambda t: hermite(m, t)[:2], guess)
            h_prev = hermite(m, x)[2]
            w = mp.mpf(2) ** (m - 1) * mp.factorial(m) * mp.sqrt(mp.pi) / (m * m * h_prev ** 2)
        elif family == "laguerre":
            (a,) = mpp
            x = newton(lambda t: laguerre(m, a, t), guess)
            d = laguerre(m, a, x)[1]
            w = mp.gamma(m + a + 1) / (mp.factorial(m) * x * d * d)
        else:
            a, b = mpp
            x = newton(lambda t: jacobi(m, a, b, t), guess)
            d = jacobi(m, a, b, x)[1]
            w = (mp.gamma(m + a + 1) * mp.gamma(m + b + 1) * mp.mpf(2) ** (a + b + 1)
                 / (mp.gamma(m + a + b + 1) * mp.factorial(m) * (1 - x * x) * d * d))
        # The bracket found the i-th root: Newton stayed on it.
        assert abs(x - guess) <= 1e-9 * max(1.0, abs(guess)), (family, params, m, i)
        out.append((i, x, w))
    return out


FAMILIES = [
    ("hermite", ()),
    ("laguerre", (0.0,)),
    ("laguerre", (2.0,)),
    ("jacobi", (0.5, -0.5)),
    ("jacobi", (-0.7, 0.3)),
    ("jacobi", (1.5, 1.5)),
]


def main():
    path = os.path.join(HERE, "gauss_classical_large.txt")
    with open(path, "w") as f:
        f.write("# gauss_classical_large.txt: family params m i node weight, generated by "
                f"generate_classical_large.py (mpmath {mp.__version__}, 40 digits)\n")
        for m in SIZES:
            for family, params in FAMILIES:
                name = ",".join(repr(float(p)) for p in params) or "-"
                for i, x, w in rule(family, params, m):
                    f.write(f"{family} {name} {m} {i} {mp.nstr(x, DIGITS)} {mp.nstr(w, DIGITS)}\n")
                f.flush()
                print(family, name, m, flush=True)


if __name__ == "__main__":
    main()
