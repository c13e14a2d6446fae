#!/usr/bin/env python3
"""Reference Gauss-Hermite, Gauss-Laguerre, Gauss-Jacobi and Gauss-Chebyshev rules in mpmath.

Independent of the Rust code under test: every node is a root of the family's polynomial
found by Newton's iteration at 60 significant digits from scipy's double-precision node
(`scipy.special.roots_*`; for Laguerre LAPACK's eigenvalues of its Jacobi matrix), the polynomial and its derivative from
the classical recurrences with mpmath numbers, and every weight from the family's closed
form in that derivative and the Gamma function (not the Christoffel sum the crate uses):

  Hermite   w_i = 2^(m-1) m! sqrt(pi) / (m^2 H_(m-1)(x_i)^2)                  (e^(-x^2) on R)
  Laguerre  w_i = Gamma(m+a+1) / (m! x_i L_m^(a)'(x_i)^2)                     (x^a e^(-x) on [0, inf))
  Jacobi    w_i = Gamma(m+a+1) Gamma(m+b+1) 2^(a+b+1)
                  / (Gamma(m+a+b+1) m! (1-x_i^2) P_m^(a,b)'(x_i)^2)           ((1-x)^a (1+x)^b on [-1, 1])
  Chebyshev first kind  x_i = cos((2i-1) pi / 2m), w_i = pi/m;   second kind  x_i = cos(i pi/(m+1)),
            w_i = pi/(m+1) sin^2(i pi/(m+1))                                   (closed forms)

For small m every rule is checked here against the polynomial moments of its weight
(exactness to degree 2m-1) and the roots against mpmath's own special functions
(mp.hermite, mp.laguerre, mp.jacobi: hypergeometric series, another route again).

For m <= 200 every node is written; for larger m a sample (the three at each end, every
37th between), which is what the tests compare. Each line: `family params m i node weight`
with 34 significant digits (weights below 1e-300 are written too; the tests skip them).

Run:  python3 quadrature/tests/data/generate_classical.py    (mpmath >= 1.1, scipy; two processes)
"""
import os
import mpmath as mp
import numpy as np
import scipy.special as sp

mp.mp.dps = 60
DIGITS = 34
ORDERS = [1, 2, 3, 4, 5, 8, 13, 21, 50, 100, 200, 500, 1000]
HERE = os.path.dirname(os.path.abspath(__file__))
TOL = mp.mpf(10) ** (-(mp.mp.dps - 8))


def hermite(m, x):
    """(H_m(x), H_m'(x), H_(m-1)(x)), physicists' Hermite polynomials."""
    h0, h1 = mp.mpf(1), 2 * x
    if m == 0:
        return h0, mp.mpf(0), mp.mpf(0)
    for k in range(1, m):
        h0, h1 = h1, 2 * x * h1 - 2 * k * h0
    return h1, 2 * m * h0, h0


def laguerre(m, a, x):
    """(L_m^(a)(x), L_m^(a)'(x))."""
    l0, l1 = mp.mpf(1), 1 + a - x
    if m == 0:
        return l0, mp.mpf(0)
    for k in range(1, m):
        l0, l1 = l1, ((2 * k + 1 + a - x) * l1 - (k + a) * l0) / (k + 1)
    # x L_m' = m L_m - (m + a) L_(m-1)
    return l1, (m * l1 - (m + a) * l0) / x


def jacobi(m, a, b, x):
    """(P_m^(a,b)(x), P_m^(a,b)'(x)) by the standard recurrence and its derivative."""
    p0, d0 = mp.mpf(1), mp.mpf(0)
    if m == 0:
        return p0, d0
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
    for _ in range(60):
        f, d = f_df(x)
        dx = f / d
        x -= dx
        if abs(dx) <= TOL * max(1, abs(x)):
            return x
    raise RuntimeError("Newton did not converge")


def sample(m):
    if m <= 200:
        return list(range(m))
    keep = set(range(3)) | set(range(m - 3, m)) | set(range(0, m, 37))
    return sorted(keep)


def hermite_rule(m, _params):
    guesses, _ = sp.roots_hermite(m)
    out = []
    for i in sample(m):
        if m % 2 == 1 and i == m // 2:
            x = mp.mpf(0)
        else:
            x = newton(lambda t: hermite(m, t)[:2], guesses[i])
        h_prev = hermite(m, x)[2]
        w = mp.mpf(2) ** (m - 1) * mp.factorial(m) * mp.sqrt(mp.pi) / (m * m * h_prev ** 2)
        out.append((i, x, w))
    return out


def laguerre_rule(m, params):
    (a,) = params
    # scipy's roots_genlaguerre overflows from m ~ 200: LAPACK's eigenvalues of the Jacobi
    # matrix instead (diagonal 2k + a + 1, off-diagonal sqrt(k (k + a))).
    k = np.arange(m)
    guesses = np.linalg.eigvalsh(np.diag(2.0 * k + float(a) + 1.0)
                                 + np.diag(np.sqrt(k[1:] * (k[1:] + float(a))), 1)
                                 + np.diag(np.sqrt(k[1:] * (k[1:] + float(a))), -1))
    out = []
    for i in sample(m):
        x = newton(lambda t: laguerre(m, a, t), guesses[i])
        d = laguerre(m, a, x)[1]
        w = mp.gamma(m + a + 1) / (mp.factorial(m) * x * d * d)
        out.append((i, x, w))
    return out


def jacobi_rule(m, params):
    a, b = params
    guesses, _ = sp.roots_jacobi(m, float(a), float(b))
    out = []
    for i in sample(m):
        x = newton(lambda t: jacobi(m, a, b, t), guesses[i])
        d = jacobi(m, a, b, x)[1]
        w = (mp.gamma(m + a + 1) * mp.gamma(m + b + 1) * mp.mpf(2) ** (a + b + 1)
             / (mp.gamma(m + a + b + 1) * mp.factorial(m) * (1 - x * x) * d * d))
        out.append((i, x, w))
    return out


def chebyshev_first(m, _params):
    # ascending: x_i = -cos((2i+1) pi / 2m), i = 0..m-1
    return [(i, -mp.cos((2 * i + 1) * mp.pi / (2 * m)), mp.pi / m) for i in sample(m)]


def chebyshev_second(m, _params):
    out = []
    for i in sample(m):
        t = (i + 1) * mp.pi / (m + 1)
        out.append((i, -mp.cos(t), mp.pi / (m + 1) * mp.sin(t) ** 2))
    return out


def moments(family, params, k):
    """Exact moments of the weight: int x^k w(x) dx."""
    if family == "hermite":
        return mp.mpf(0) if k % 2 else mp.gamma((k + 1) / mp.mpf(2))
    if family == "laguerre":
        return mp.gamma(k + params[0] + 1)
    a, b = params
    # x = 2t - 1: 2^(a+b+1) sum_j C(k, j) 2^j (-1)^(k-j) B(j + b + 1, a + 1).
    return mp.mpf(2) ** (a + b + 1) * mp.fsum(
        mp.binomial(k, j) * mp.mpf(2) ** j * (-1) ** (k - j) * mp.beta(j + b + 1, a + 1)
        for j in range(k + 1))


FAMILIES = [
    ("hermite", [()], hermite_rule),
    ("laguerre", [(mp.mpf(0),), (mp.mpf("0.5"),), (mp.mpf("-0.5"),), (mp.mpf(2),)], laguerre_rule),
    ("jacobi", [(mp.mpf("0.5"), mp.mpf("-0.5")), (mp.mpf(2), mp.mpf(1)),
                # The doubles nearest -0.7 and 0.3, exactly: the rule the tests build.
                (mp.mpf(-0.7), mp.mpf(0.3))], jacobi_rule),
    ("chebyshev1", [()], chebyshev_first),
    ("chebyshev2", [()], chebyshev_second),
]


def cross_check(family, params, m, rule):
    """Small m: roots against mpmath's special functions, exactness against the moments."""
    xs = [x for _, x, _ in rule]
    ws = [w for _, _, w in rule]
    for x in xs:
        if family == "hermite":
            v, scale = mp.hermite(m, x, zeroprec=2000), mp.hermite(m, 1 + abs(x))
        elif family == "laguerre":
            v = mp.laguerre(m, params[0], x, zeroprec=2000)
            scale = mp.laguerre(m, params[0], -1 - abs(x))
        elif family == "jacobi":
            v = mp.jacobi(m, params[0], params[1], x, zeroprec=2000)
            scale = mp.jacobi(m, params[0], params[1], 1)
        else:
            v, scale = (mp.chebyt(m, x), 1) if family == "chebyshev1" else (mp.chebyu(m, x), m + 1)
        assert abs(v) < mp.mpf(10) ** -40 * abs(scale), (family, params, m, x, v)
    if family.startswith("chebyshev"):
        return
    for k in range(0, 2 * m):
        q = mp.fsum(w * x ** k for x, w in zip(xs, ws))
        exact = moments(family, params, k)
        assert abs(q - exact) <= mp.mpf(10) ** -30 * max(1, abs(exact)), (family, params, m, k)


def fmt(x):
    return mp.nstr(x, DIGITS, min_fixed=1, max_fixed=0) if x != 0 else "0.0"


def task(args):
    family, params, build = args
    label = ",".join(mp.nstr(p, 6) for p in params) or "-"
    lines = []
    for m in ORDERS:
        rule = build(m, params)
        if m <= 8:
            cross_check(family, params, m, rule)
        for i, x, w in rule:
            lines.append(f"{family} {label} {m} {i} {fmt(x)} {fmt(w)}\n")
    print(family, label, "done", flush=True)
    return lines


def main():
    import multiprocessing
    tasks = [(family, params, build) for family, param_sets, build in FAMILIES for params in param_sets]
    with multiprocessing.Pool(2) as pool:
        results = pool.map(task, tasks)
    path = os.path.join(HERE, "gauss_classical.txt")
    with open(path, "w") as out:
        out.write("# gauss_classical.txt: family params m i node weight, generated by "
                  f"generate_classical.py (mpmath {mp.__version__}, {mp.mp.dps} digits)\n")
        for lines in results:
            out.writelines(lines)


if __name__ == "__main__":
    main()
