"""Gauss quadrature rules, as ``(nodes, weights)`` ndarrays.

Golub-Welsch with Newton and double-double polish below 100 points and asymptotic or ODE
methods above: nodes and weights to a few ulps at any size. ``gauss_legendre(m)``,
``gauss_lobatto(m)`` and ``gauss_radau(m)`` on ``[-1, 1]``; ``gauss_hermite(m)`` (weight
``exp(-x^2)``), ``gauss_laguerre(m, alpha)`` (``x^alpha exp(-x)`` on ``[0, inf)``),
``gauss_jacobi(m, alpha, beta)``; ``gauss_kronrod(n)``: the ``2n + 1``-point Kronrod
extension of ``n`` Gauss-Legendre points (its embedded Gauss weights by
``gauss_kronrod_gauss_weights(n)``).
"""

from ._lgsvi import (
    gauss_hermite,
    gauss_jacobi,
    gauss_kronrod,
    gauss_kronrod_gauss_weights,
    gauss_laguerre,
    gauss_legendre,
    gauss_lobatto,
    gauss_radau,
)

__all__ = [
    "gauss_hermite",
    "gauss_jacobi",
    "gauss_kronrod",
    "gauss_kronrod_gauss_weights",
    "gauss_laguerre",
    "gauss_legendre",
    "gauss_lobatto",
    "gauss_radau",
]
