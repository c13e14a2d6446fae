"""Functions as Chebyshev series: :class:`Chebyshev`.

``f = Chebyshev.fit(np.sin, 0, 10)`` samples ``np.sin`` on arrays of Chebyshev-Lobatto
points until its coefficients reach machine precision; ``f(x)`` evaluates on arrays,
``f.roots()``, ``f.derivative()``, ``f.integral()``, ``f.definite_integral()``,
``f.coefficients``.
"""

from ._lgsvi import Chebyshev

__all__ = ["Chebyshev"]
