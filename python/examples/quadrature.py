"""The foundation modules on their own: Gauss rules and Chebyshev series, no Lie groups.

Integrates exp(-x^2) cos(x) over the real line by Gauss-Hermite (exact: sqrt(pi) e^(-1/4)),
a Legendre-weighted integral by Gauss-Legendre and by a Chebyshev series, and finds the
zeros of a Bessel function by the series' roots; asserts each to 1e-14.

    python python/examples/quadrature.py
"""

import numpy as np
from scipy import special

from lgsvi import quadrature
from lgsvi.chebyshev import Chebyshev

x, w = quadrature.gauss_hermite(30)
value = w @ np.cos(x)
exact = np.sqrt(np.pi) * np.exp(-0.25)
print(f"Gauss-Hermite, 30 points: {value:.16f} (exact {exact:.16f})")
assert abs(value - exact) < 1e-14

x, w = quadrature.gauss_legendre(20)
f = lambda t: np.exp(t) * np.sin(3 * t)
legendre = w @ f(x)
series = Chebyshev.fit(f, -1.0, 1.0)
print(f"Gauss-Legendre {legendre:.16f}, Chebyshev series ({len(series)} terms) "
      f"{series.definite_integral():.16f}")
assert abs(legendre - series.definite_integral()) < 1e-14

j0 = Chebyshev.fit(lambda t: special.j0(t), 0.0, 20.0)
zeros = j0.roots()
print("zeros of J0 on [0, 20]:", np.array2string(zeros, precision=12))
assert np.max(np.abs(zeros - special.jn_zeros(0, len(zeros)))) < 1e-13
