"""The largest Gauss–Legendre nodes and their weights for very large m, where 1 − x is
1e-10 or less and a double-precision evaluation of w = 2/((1 − x²)P_m'(x)²) at a node
rounded to a double loses digits: Newton on P_m by its three-term recurrence in 40-digit
mpmath, from the given first guesses (any within the root's basin). Prints `m i x w`,
i counted from the largest node (i = 0). About 6 s per node at m = 1e5, 60 s at 1e6.

    python3 quadrature/tests/data/generate_legendre_extremes.py > quadrature/tests/data/gauss_legendre_extremes.txt
"""
import mpmath as mp

mp.mp.dps = 40


def legendre(m, x):
    p0, p1 = mp.mpf(1), x
    for k in range(2, m + 1):
        p0, p1 = p1, ((2 * k - 1) * x * p1 - (k - 1) * p0) / k
    return p1, m * (x * p1 - p0) / (x * x - 1)


def node(m, k):
    # Tricomi's first approximation, then Newton to 40 digits.
    theta = (4 * k - 1) * mp.pi / (4 * m + 2)
    x = mp.cos(theta)
    for _ in range(6):
        p, dp = legendre(m, x)
        x -= p / dp
    p, dp = legendre(m, x)
    return x, 2 / ((1 - x * x) * dp * dp)


print("# gauss_legendre_extremes.txt: m i x w (i = 0: the largest node), 40-digit mpmath")
for m in (100_000, 1_000_000):
    for i in range(3):
        x, w = node(m, i + 1)
        print(m, i, mp.nstr(x, 30), mp.nstr(w, 30))
