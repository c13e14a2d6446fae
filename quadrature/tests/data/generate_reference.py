#!/usr/bin/env python3
"""Reference Gauss-Legendre, Gauss-Lobatto and Gauss-Radau rules on [-1, 1] in mpmath.

Independent of the Rust code under test: nodes are found by bracketed Newton iteration on
the Legendre three-term recurrence at 60 significant digits, each bracket proven to hold
exactly one root by interlacing (see below), and every rule is checked here for its count,
ordering, weight sum and polynomial exactness before it is written.

Writes, beside this script, `gauss_legendre.txt`, `gauss_lobatto.txt` and
`gauss_radau.txt`; each line is `m i node weight` with 34 significant digits (more than
enough: a double's correctly rounded value is all the tests need).

Run:  python3 quadrature/tests/data/generate_reference.py     (mpmath >= 1.1; ~1 minute)
"""
import os
import mpmath as mp

mp.mp.dps = 60
DIGITS = 34
ORDERS = [1, 2, 3, 4, 5, 8, 13, 21, 50, 100, 500]
HERE = os.path.dirname(os.path.abspath(__file__))


def legendre(n, x):
    """(P_n(x), P_{n-1}(x), P_n'(x), P_n''(x)) by the recurrence and its derivatives."""
    p0, d0, s0 = mp.mpf(1), mp.mpf(0), mp.mpf(0)
    if n == 0:
        return p0, mp.mpf(0), d0, s0
    p1, d1, s1 = x, mp.mpf(1), mp.mpf(0)
    for k in range(1, n):
        p2 = ((2 * k + 1) * x * p1 - k * p0) / (k + 1)
        d2 = ((2 * k + 1) * (p1 + x * d1) - k * d0) / (k + 1)
        s2 = ((2 * k + 1) * (2 * d1 + x * s1) - k * s0) / (k + 1)
        p0, p1, d0, d1, s0, s1 = p1, p2, d1, d2, s1, s2
    return p1, p0, d1, s1


def safe_newton(f, df, lo, hi):
    """Root of f in [lo, hi] (f(lo), f(hi) of opposite signs): Newton kept inside the bracket."""
    flo = f(lo)
    fhi = f(hi)
    assert flo * fhi < 0, "bracket does not straddle a root"
    x = (lo + hi) / 2
    tol = mp.mpf(10) ** (-(mp.mp.dps - 5))
    for _ in range(400):
        fx = f(x)
        if fx == 0:
            return x
        if (fx < 0) == (flo < 0):
            lo, flo = x, fx
        else:
            hi = x
        step = fx / df(x)
        xn = x - step
        if not (lo < xn < hi):
            xn = (lo + hi) / 2
        if abs(xn - x) < tol:
            return xn
        x = xn
    raise RuntimeError("no convergence")


def gauss_nodes(m):
    """Roots of P_m, ascending. Newton from the classic guesses, then proven by sign changes."""
    if m == 1:
        return [mp.mpf(0)]
    roots = []
    for i in range(1, m + 1):
        x = -mp.cos(mp.pi * (i - mp.mpf(1) / 4) / (m + mp.mpf(1) / 2))
        for _ in range(100):
            p, _, d, _ = legendre(m, x)
            dx = p / d
            x -= dx
            if abs(dx) < mp.mpf(10) ** (-(mp.mp.dps - 5)):
                break
        roots.append(x)
    roots.sort()
    # Proof that these are the m distinct roots: P_m changes sign between midpoints.
    probes = [mp.mpf(-1)] + [(a + b) / 2 for a, b in zip(roots, roots[1:])] + [mp.mpf(1)]
    signs = [mp.sign(legendre(m, t)[0]) for t in probes]
    assert all(s != 0 for s in signs)
    assert all(a * b < 0 for a, b in zip(signs, signs[1:])), f"roots of P_{m} not separated"
    return roots


def gauss_rule(m):
    xs = gauss_nodes(m)
    ws = []
    for x in xs:
        _, _, d, _ = legendre(m, x)
        ws.append(2 / ((1 - x * x) * d * d))
    return xs, ws


def lobatto_rule(m):
    """m >= 2 points: +-1 and the m-2 roots of P'_{m-1}, one between consecutive roots of P_{m-1}."""
    n = m - 1
    inner = []
    if n >= 2:
        g = gauss_nodes(n)
        for a, b in zip(g, g[1:]):  # Rolle: exactly one root of P'_n in each gap
            inner.append(safe_newton(lambda t: legendre(n, t)[2], lambda t: legendre(n, t)[3], a, b))
    xs = [mp.mpf(-1)] + inner + [mp.mpf(1)]
    ws = [2 / (m * (m - 1) * legendre(n, x)[0] ** 2) for x in xs]
    return xs, ws


def radau_rule(m):
    """m >= 1 points: -1 and the m-1 roots of P_{m-1} + P_m, one between consecutive roots of P_m
    (at the roots of P_m the sum equals P_{m-1}, whose sign alternates there)."""
    inner = []
    if m >= 2:
        g = gauss_nodes(m)

        def f(t):
            p, pm1, _, _ = legendre(m, t)
            return p + pm1

        def df(t):
            _, _, d, _ = legendre(m, t)
            return d + legendre(m - 1, t)[2]

        for a, b in zip(g, g[1:]):
            inner.append(safe_newton(f, df, a, b))
    xs = [mp.mpf(-1)] + inner
    ws = [mp.mpf(2) / (m * m)]
    for x in inner:
        pm1 = legendre(m - 1, x)[0]
        ws.append((1 - x) / (m * m * pm1 * pm1))
    return xs, ws


def check(xs, ws, exact_degree):
    assert all(a < b for a, b in zip(xs, xs[1:])), "nodes not ascending"
    assert abs(mp.fsum(ws) - 2) < mp.mpf(10) ** (-(mp.mp.dps - 15))
    for k in sorted({0, 1, 2, exact_degree - 1, exact_degree}):
        if k < 0 or k > exact_degree:
            continue
        exact = mp.mpf(2) / (k + 1) if k % 2 == 0 else mp.mpf(0)
        got = mp.fsum(w * x**k for x, w in zip(xs, ws))
        assert abs(got - exact) < mp.mpf(10) ** (-(mp.mp.dps - 15)), (len(xs), k)


def write(name, rules):
    path = os.path.join(HERE, name)
    with open(path, "w") as fh:
        fh.write(f"# {name}: m i node weight on [-1, 1], generated by generate_reference.py "
                 f"(mpmath {mp.__version__}, {mp.mp.dps} digits)\n")
        for m, (xs, ws) in rules:
            for i, (x, w) in enumerate(zip(xs, ws)):
                fh.write(f"{m} {i} {mp.nstr(x, DIGITS, min_fixed=1, max_fixed=0)} "
                         f"{mp.nstr(w, DIGITS, min_fixed=1, max_fixed=0)}\n")
    print("wrote", path)


def main():
    gauss, lobatto, radau = [], [], []
    for m in ORDERS:
        xs, ws = gauss_rule(m)
        check(xs, ws, 2 * m - 1)
        gauss.append((m, (xs, ws)))
        if m >= 2:
            xs, ws = lobatto_rule(m)
            check(xs, ws, 2 * m - 3)
            lobatto.append((m, (xs, ws)))
        xs, ws = radau_rule(m)
        check(xs, ws, 2 * m - 2)
        radau.append((m, (xs, ws)))
        print("m =", m, "done", flush=True)
    write("gauss_legendre.txt", gauss)
    write("gauss_lobatto.txt", lobatto)
    write("gauss_radau.txt", radau)


if __name__ == "__main__":
    main()
