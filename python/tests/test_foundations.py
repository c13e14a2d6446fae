"""The foundation modules against numpy and scipy: Gauss rules against
``scipy.special.roots_*`` and ``numpy.polynomial``, Chebyshev series against
``numpy.polynomial.chebyshev``, SO(3)/SE(3) against ``scipy.spatial.transform`` and
``scipy.linalg.expm``."""

import numpy as np
import pytest
from numpy.polynomial import chebyshev as npcheb
from numpy.polynomial import legendre as nplegendre
from scipy import special
from scipy.linalg import expm
from scipy.spatial.transform import Rotation

import lgsvi
from lgsvi import quadrature
from lgsvi.chebyshev import Chebyshev


def close(a, b, rel):
    """Entries within ``rel`` of the larger's scale."""
    a, b = np.asarray(a), np.asarray(b)
    return np.max(np.abs(a - b)) <= rel * max(np.max(np.abs(b)), 1e-300)


# scipy's roots are computed to ~1e-15 relative at these sizes (Golub-Welsch with a Newton
# step); lgsvi's to a few ulps: 1e-13 covers both.
@pytest.mark.parametrize("m", [1, 2, 5, 20, 64])
def test_gauss_legendre(m):
    x, w = quadrature.gauss_legendre(m)
    xs, ws = nplegendre.leggauss(m)
    assert close(x, xs, 1e-13) and close(w, ws, 1e-13)


@pytest.mark.parametrize("m", [1, 5, 20])
def test_gauss_hermite(m):
    x, w = quadrature.gauss_hermite(m)
    xs, ws = special.roots_hermite(m)
    assert close(x, xs, 1e-13) and close(w, ws, 1e-12)


@pytest.mark.parametrize("m, alpha", [(5, 0.0), (12, 0.5), (20, 2.0)])
def test_gauss_laguerre(m, alpha):
    x, w = quadrature.gauss_laguerre(m, alpha)
    xs, ws = special.roots_genlaguerre(m, alpha)
    assert close(x, xs, 1e-13) and close(w, ws, 1e-12)


@pytest.mark.parametrize("m, a, b", [(5, 0.5, -0.3), (16, 1.5, 2.0)])
def test_gauss_jacobi(m, a, b):
    x, w = quadrature.gauss_jacobi(m, a, b)
    xs, ws = special.roots_jacobi(m, a, b)
    assert close(x, xs, 1e-13) and close(w, ws, 1e-12)


@pytest.mark.parametrize("m", [3, 8, 17])
def test_gauss_lobatto_is_exact_to_degree_2m_minus_3(m):
    """Both ends and the roots of P'_{m-1} (numpy's Legendre derivative), exact for
    polynomials of degree 2m - 3."""
    x, w = quadrature.gauss_lobatto(m)
    interior = np.sort(nplegendre.legroots(nplegendre.legder([0] * (m - 1) + [1])))
    assert close(x, np.concatenate([[-1.0], interior, [1.0]]), 1e-13)
    for k in range(2 * m - 2):
        exact = 0.0 if k % 2 else 2.0 / (k + 1)
        assert abs(np.dot(w, x**k) - exact) < 1e-13


@pytest.mark.parametrize("n", [3, 7, 10])
def test_gauss_kronrod_is_exact_to_degree_3n_plus_1(n):
    """The Kronrod extension integrates polynomials of degree 3n + 1 exactly (n odd;
    3n + 2 for n even), and its Gauss points are Gauss-Legendre's."""
    x, w = quadrature.gauss_kronrod(n)
    assert len(x) == 2 * n + 1
    for k in range(3 * n + 2):
        exact = 0.0 if k % 2 else 2.0 / (k + 1)
        assert abs(np.dot(w, x**k) - exact) < 1e-13
    g = quadrature.gauss_kronrod_gauss_weights(n)
    xs, ws = nplegendre.leggauss(n)
    assert close(x[g != 0], xs, 1e-13) and close(g[g != 0], ws, 1e-13)


def test_chebyshev_fit_against_numpy():
    """The fit of exp on [0, 2] to machine precision: its coefficients are numpy's
    interpolant's on 40 Chebyshev points (both converge to the series' own), and it
    evaluates, differentiates and integrates as numpy's series does."""
    f = Chebyshev.fit(np.exp, 0.0, 2.0)
    reference = npcheb.Chebyshev.interpolate(np.exp, 40, domain=[0.0, 2.0])
    n = len(f.coefficients)
    assert close(f.coefficients, reference.coef[:n], 1e-14)
    assert np.max(np.abs(reference.coef[n:])) < 1e-15 * np.exp(2.0)
    x = np.linspace(0.0, 2.0, 101)
    assert close(f(x), np.exp(x), 4e-15)
    assert close(f.derivative()(x), np.exp(x), 1e-13)
    assert close(f.integral()(x), np.exp(x) - 1.0, 1e-14)
    assert abs(f.definite_integral() - (np.exp(2.0) - 1.0)) < 1e-14
    # f(x) on any shape of array.
    assert f(np.ones((2, 3))).shape == (2, 3)


def test_chebyshev_roots_and_the_vectorised_call():
    """cos(10 x) on [0, 3]: ten roots at (2k + 1) pi / 20, f called on arrays only."""
    calls = []

    def f(x):
        calls.append(np.shape(x))
        return np.cos(10.0 * x)

    series = Chebyshev.fit(f, 0.0, 3.0)
    assert all(len(s) == 1 and s[0] >= 17 for s in calls)
    expected = (2 * np.arange(10) + 1) * np.pi / 20
    assert close(series.roots(), expected, 1e-14)


def test_so3_exp_log_against_scipy():
    rng = np.random.default_rng(7)
    w = rng.normal(size=(50, 3)) * 1.2
    r = lgsvi.lie.so3_exp(w)
    assert np.max(np.abs(r - Rotation.from_rotvec(w).as_matrix())) < 1e-14
    back = lgsvi.lie.so3_log(r)
    assert np.max(np.abs(back - Rotation.from_matrix(r).as_rotvec())) < 1e-13
    # Quaternions: scipy's are (x, y, z, w).
    q = lgsvi.lie.quaternion_from_matrix(r)
    qs = Rotation.from_matrix(r).as_quat()
    qs = np.where(qs[:, 3:] < 0, -qs, qs)
    assert np.max(np.abs(q - qs[:, [3, 0, 1, 2]])) < 1e-14
    assert np.max(np.abs(lgsvi.lie.matrix_from_quaternion(q) - r)) < 1e-14
    assert np.array_equal(lgsvi.lie.vee(lgsvi.lie.hat(w)), w)


def test_se3_exp_log_against_expm():
    """exp of a twist (w, v) is expm of [[hat(w), v], [0, 0]]."""
    rng = np.random.default_rng(3)
    xi = rng.normal(size=(20, 6))
    t = lgsvi.lie.se3_exp(xi)
    for k in range(20):
        m = np.zeros((4, 4))
        m[:3, :3] = lgsvi.lie.hat(xi[k, :3])
        m[:3, 3] = xi[k, 3:]
        assert np.max(np.abs(t[k] - expm(m))) < 1e-13
    small = xi * 0.3
    assert np.max(np.abs(lgsvi.lie.se3_log(lgsvi.lie.se3_exp(small)) - small)) < 1e-13


@pytest.mark.parametrize("chart", ["cayley", "cayley-unscaled"])
def test_cayley_charts_against_their_formulas(chart):
    """Cayley: (I + hat(w)/2)(I - hat(w)/2)^-1; the paper's unscaled:
    (I - hat(q))(I + hat(q))^-1."""
    rng = np.random.default_rng(5)
    w = rng.normal(size=(10, 3)) * 0.4
    r = lgsvi.lie.chart_to_group(w, chart)
    for k in range(10):
        h = lgsvi.lie.hat(w[k])
        i = np.eye(3)
        if chart == "cayley":
            expected = (i + h / 2) @ np.linalg.inv(i - h / 2)
        else:
            expected = (i - h) @ np.linalg.inv(i + h)
        assert np.max(np.abs(r[k] - expected)) < 1e-14
    assert np.max(np.abs(lgsvi.lie.chart_to_algebra(r, chart) - w)) < 1e-14


def test_chart_differentials_against_differences():
    """A(w) v = vee(Phi(w)^T dPhi(w)[v]) by central differences (error ~1e-10 at
    eps = 1e-5)."""
    w = np.array([0.3, -0.7, 1.1])
    for chart in ["exp", "cayley"]:
        a = lgsvi.lie.chart_differential(w, chart)
        r = lgsvi.lie.chart_to_group(w, chart)
        eps = 1e-5
        for k in range(3):
            e = np.eye(3)[k] * eps
            d = (lgsvi.lie.chart_to_group(w + e, chart) - lgsvi.lie.chart_to_group(w - e, chart)) / (2 * eps)
            column = lgsvi.lie.vee(r.T @ d)
            assert np.max(np.abs(column - a[:, k])) < 1e-9, chart
