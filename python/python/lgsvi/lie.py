"""SO(3), SE(3) and the natural charts on arrays of any leading shape.

``so3_exp(w)`` (..., 3) -> (..., 3, 3), ``so3_log(R)``, ``se3_exp(xi)`` (..., 6) ->
(..., 4, 4) with ``xi = (omega, v)``, ``se3_log(T)``, ``hat``, ``vee``; the charts
``chart_to_group(w, chart)``, ``chart_to_algebra(R, chart)``,
``chart_differential(w, chart, side)`` (the left- or right-trivialised differential) for
``chart`` one of ``"exp"``, ``"cayley"``, ``"cayley-unscaled"`` (the paper's
``(I - hat(q))(I + hat(q))^-1``); ``quaternion_from_matrix``, ``matrix_from_quaternion``
(``(w, x, y, z)``).
"""

from ._lgsvi import (
    chart_differential,
    chart_to_algebra,
    chart_to_group,
    hat,
    matrix_from_quaternion,
    quaternion_from_matrix,
    se3_exp,
    se3_log,
    so3_exp,
    so3_log,
    vee,
)

__all__ = [
    "chart_differential",
    "chart_to_algebra",
    "chart_to_group",
    "hat",
    "matrix_from_quaternion",
    "quaternion_from_matrix",
    "se3_exp",
    "se3_log",
    "so3_exp",
    "so3_log",
    "vee",
]
