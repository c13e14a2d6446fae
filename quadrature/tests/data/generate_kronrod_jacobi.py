#!/usr/bin/env python3
"""Reference Gauss-Kronrod-Jacobi rules (2n+1 points extending the n-point Gauss-Jacobi rule
of the weight (1-x)^a (1+x)^b) in mpmath, and where none exists.

Independent of the Rust code under test (Laurie's algorithm on the Jacobi recurrence):
here the Stieltjes polynomial E_(n+1) is found from its definition, the monic polynomial of
degree n+1 orthogonal to every x^k, k <= n, against the sign-changing weight
P_n(x) (1-x)^a (1+x)^b on [-1, 1] (a linear system in the monomial basis at 150 digits,
with the weight's moments in closed form, int x^p w = 2^(a+b+1) sum_j C(p, j) 2^j (-1)^(p-j)
B(j + b + 1, a + 1)); the Kronrod nodes are its roots (mpmath's polyroots) and the Gauss
nodes P_n's; the weights solve the exactness conditions for x^0 .. x^(2n) (a Vandermonde
system at 150 digits). Each rule is checked here: 2n+1 distinct real nodes in (-1, 1)
(not on an end),
positive weights, exactness through degree 3n+1. An extension that fails any of these is
written as `none`.

Writes `gauss_kronrod_jacobi.txt` beside this script: lines `a,b n i node kronrod_weight
gauss_weight` (the Gauss weight 0 at the added nodes), 34 significant digits, or
`a,b n none`.

Run:  python3 quadrature/tests/data/generate_kronrod_jacobi.py     (mpmath >= 1.1; a minute)
"""
import os
import mpmath as mp

mp.mp.dps = 150
ORDERS = [1, 2, 3, 4, 5, 7, 10, 15, 20]
EXPONENTS = [(0.5, 0.5), (-0.5, -0.5), (1.5, 1.5), (0.5, -0.5), (2.0, 1.0), (3.0, 3.0)]
HERE = os.path.dirname(os.path.abspath(__file__))


def moment(a, b, p):
    return mp.mpf(2) ** (a + b + 1) * mp.fsum(
        mp.binomial(p, j) * mp.mpf(2) ** j * (-1) ** (p - j) * mp.beta(j + b + 1, a + 1)
        for j in range(p + 1))


def jacobi_coefficients(n, a, b):
    """P_n^(a,b)'s coefficients, highest first, by the standard recurrence on lists."""
    p0 = [mp.mpf(1)]
    p1 = [(a + b + 2) / 2, (a - b) / 2]
    if n == 0:
        return p0
    for m in range(1, n):
        k = m + 1
        c = 2 * k + a + b
        a1 = 2 * k * (k + a + b) * (c - 2)
        a2 = (c - 1) * (a * a - b * b)
        a3 = (c - 2) * (c - 1) * c
        a4 = 2 * (k + a - 1) * (k + b - 1) * c
        x_p1 = p1 + [mp.mpf(0)]
        c_p1 = [mp.mpf(0)] + p1
        prev = [mp.mpf(0)] * (len(x_p1) - len(p0)) + p0
        p0, p1 = p1, [(a3 * u + a2 * v - a4 * w) / a1 for u, v, w in zip(x_p1, c_p1, prev)]
    return p1


def roots(coefficients):
    out = []
    for r in mp.polyroots(coefficients, maxsteps=800, extraprec=1500):
        if abs(mp.im(r)) > mp.mpf(10) ** -100:
            return None
        out.append(mp.re(r))
    return sorted(out)


def rule(n, a, b):
    pn = jacobi_coefficients(n, a, b)
    mom = [moment(a, b, p) for p in range(3 * n + 3)]
    # int x^p P_n w = sum_j pn_j mom[p + n - j]
    def pn_moment(p):
        return mp.fsum(c * mom[p + n - j] for j, c in enumerate(pn))
    size = n + 1
    m = mp.matrix(size, size)
    rhs = mp.matrix(size, 1)
    for k in range(size):
        for j in range(size):
            m[k, j] = pn_moment(k + j)
        rhs[k] = -pn_moment(k + n + 1)
    c = mp.lu_solve(m, rhs)
    stieltjes = [mp.mpf(1)] + [c[j] for j in reversed(range(size))]
    gauss = roots(pn)
    added = roots(stieltjes)
    if gauss is None or added is None:
        return None
    nodes = sorted(gauss + added)
    # Inside (-1, 1), not on an end (to rounding at 150 digits: the Chebyshev weight of the
    # first kind puts Kronrod nodes on +-1).
    end = mp.mpf(10) ** -100
    if not all(-1 + end < x < 1 - end for x in nodes):
        return None
    if any(abs(nodes[i] - nodes[i + 1]) < mp.mpf(10) ** -60 for i in range(len(nodes) - 1)):
        return None
    size = len(nodes)
    v = mp.matrix(size, size)
    rhs = mp.matrix(size, 1)
    for k in range(size):
        for i, x in enumerate(nodes):
            v[k, i] = x ** k
        rhs[k] = mom[k]
    w = mp.lu_solve(v, rhs)
    kronrod = [w[i] for i in range(size)]
    if not all(wk > 0 for wk in kronrod):
        return None
    for k in range(3 * n + 2):
        q = mp.fsum(wk * x ** k for x, wk in zip(nodes, kronrod))
        assert abs(q - mom[k]) < mp.mpf(10) ** -90 * max(1, abs(mom[k])), (n, a, b, k)
    # The Gauss weights from the closed form.
    gw = {}
    for x in gauss:
        d = mp.fsum((n - j) * cj * x ** (n - j - 1) for j, cj in enumerate(pn[:-1]))
        gw[x] = (mp.gamma(n + a + 1) * mp.gamma(n + b + 1) * mp.mpf(2) ** (a + b + 1)
                 / (mp.gamma(n + a + b + 1) * mp.factorial(n) * (1 - x * x) * d * d))
    # Interlacing: a Gauss node at every odd index.
    assert all(abs(nodes[2 * i + 1] - g) < mp.mpf(10) ** -100 for i, g in enumerate(gauss))
    return nodes, kronrod, [gw.get(x, mp.mpf(0)) for x in nodes]


def fmt(x):
    return mp.nstr(x, 34, min_fixed=1, max_fixed=0) if abs(x) > mp.mpf(10) ** -140 else "0.0"


def main():
    with open(os.path.join(HERE, "gauss_kronrod_jacobi.txt"), "w") as out:
        out.write("# gauss_kronrod_jacobi.txt: a,b n i node kronrod_weight gauss_weight (or a,b n none), "
                  f"generated by generate_kronrod_jacobi.py (mpmath {mp.__version__}, {mp.mp.dps} digits)\n")
        for a, b in EXPONENTS:
            name = f"{a!r},{b!r}"
            for n in ORDERS:
                found = rule(n, mp.mpf(a), mp.mpf(b))
                if found is None:
                    out.write(f"{name} {n} none\n")
                    print(name, n, "none", flush=True)
                    continue
                for i, (x, k, g) in enumerate(zip(*found)):
                    out.write(f"{name} {n} {i} {fmt(x)} {fmt(k)} {fmt(g)}\n")
                print(name, n, "done", flush=True)


if __name__ == "__main__":
    main()
