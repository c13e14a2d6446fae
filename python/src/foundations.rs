//! The foundation crates on arrays: Gauss rules (`lgsvi.quadrature`), Chebyshev series
//! (`lgsvi.chebyshev`), SO(3)/SE(3) and the charts (`lgsvi.lie`).

use crate::convert::{array, array1, array_dyn, finite, rows3};
use crate::errors::{guarded, invalid, lie, quadrature, spectral};
use crate::run::chart_named;
use lgsvi_lie::{So3Chart, SE3, SO3};
use lgsvi_quadrature::Rule;
use lgsvi_spectral::{Chebyshev as RustChebyshev, SpectralError};
use nalgebra::{Matrix3, Matrix4, Vector3, Vector6};
use numpy::{PyArray1, PyArrayDyn};
use pyo3::prelude::*;
use pyo3::types::{PyTuple, PyType};

type Pair<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

fn pair<'py>(py: Python<'py>, rule: &Rule) -> Pair<'py> {
    (
        array1(py, rule.nodes().to_vec()),
        array1(py, rule.weights().to_vec()),
    )
}

fn rule<'py>(
    py: Python<'py>,
    make: impl FnOnce() -> Result<Rule, lgsvi_quadrature::QuadratureError> + Send,
) -> PyResult<Pair<'py>> {
    let rule = py.detach(|| guarded(|| make().map_err(quadrature)))?;
    Ok(pair(py, &rule))
}

/// The `m`-point Gauss–Legendre rule on [−1, 1]: `(nodes, weights)`, exact for polynomials
/// of degree `2m − 1`; nodes and weights to a few ulps at any size.
#[pyfunction]
fn gauss_legendre(py: Python<'_>, m: usize) -> PyResult<Pair<'_>> {
    rule(py, || lgsvi_quadrature::gauss_legendre(m))
}

/// The `m`-point Gauss–Lobatto rule on [−1, 1] (both ends among the nodes; exact to degree
/// `2m − 3`).
#[pyfunction]
fn gauss_lobatto(py: Python<'_>, m: usize) -> PyResult<Pair<'_>> {
    rule(py, || lgsvi_quadrature::gauss_lobatto(m))
}

/// The `m`-point Gauss–Radau rule on [−1, 1] with the node at `side` (`"left"`: −1, or
/// `"right"`: 1).
#[pyfunction]
#[pyo3(signature = (m, side="left"))]
fn gauss_radau<'py>(py: Python<'py>, m: usize, side: &str) -> PyResult<Pair<'py>> {
    match side {
        "left" => rule(py, || lgsvi_quadrature::gauss_radau_left(m)),
        "right" => rule(py, || lgsvi_quadrature::gauss_radau_right(m)),
        other => Err(invalid(format!(
            "side must be \"left\" or \"right\", got {other:?}"
        ))),
    }
}

/// The `m`-point Gauss–Hermite rule: weight `exp(−x²)` on the real line (physicists').
#[pyfunction]
fn gauss_hermite(py: Python<'_>, m: usize) -> PyResult<Pair<'_>> {
    rule(py, || lgsvi_quadrature::gauss_hermite(m))
}

/// The `m`-point generalised Gauss–Laguerre rule: weight `x^alpha exp(−x)` on [0, ∞),
/// `alpha > −1`.
#[pyfunction]
#[pyo3(signature = (m, alpha=0.0))]
fn gauss_laguerre(py: Python<'_>, m: usize, alpha: f64) -> PyResult<Pair<'_>> {
    rule(py, move || lgsvi_quadrature::gauss_laguerre(m, alpha))
}

/// The `m`-point Gauss–Jacobi rule: weight `(1 − x)^alpha (1 + x)^beta` on [−1, 1],
/// `alpha, beta > −1`.
#[pyfunction]
fn gauss_jacobi(py: Python<'_>, m: usize, alpha: f64, beta: f64) -> PyResult<Pair<'_>> {
    rule(py, move || lgsvi_quadrature::gauss_jacobi(m, alpha, beta))
}

/// The Gauss–Kronrod pair of `n` Gauss–Legendre points extended to `2n + 1` on [−1, 1]
/// (G7–K15 is `gauss_kronrod(7)`): `(nodes, weights)` of the Kronrod rule. The embedded
/// Gauss rule's weights, in the order of these nodes (zero at every other node, from the
/// first), are `gauss_kronrod_gauss_weights(n)`.
#[pyfunction]
fn gauss_kronrod(py: Python<'_>, n: usize) -> PyResult<Pair<'_>> {
    let pair_rule =
        py.detach(|| guarded(|| lgsvi_quadrature::gauss_kronrod(n).map_err(quadrature)))?;
    Ok(pair(py, pair_rule.kronrod()))
}

/// The embedded Gauss weights of `gauss_kronrod(n)`, in the order of its nodes.
#[pyfunction]
fn gauss_kronrod_gauss_weights(py: Python<'_>, n: usize) -> PyResult<Bound<'_, PyArray1<f64>>> {
    let pair_rule =
        py.detach(|| guarded(|| lgsvi_quadrature::gauss_kronrod(n).map_err(quadrature)))?;
    Ok(array1(py, pair_rule.gauss_weights().to_vec()))
}

/// A function on `[a, b]` held as its Chebyshev series `Σ c_k T_k(t)`,
/// `t = (2x − a − b)/(b − a)`: fitted adaptively to a tolerance, evaluated by Clenshaw's
/// recurrence on arrays, with its exact derivative, integral and roots.
///
/// Build one with `Chebyshev.fit(f, a, b)` (f takes an ndarray of points and returns the
/// values), `Chebyshev.from_values(values, a, b)` (at the Chebyshev–Lobatto points) or
/// `Chebyshev(coefficients, a, b)`.
#[pyclass(module = "lgsvi._lgsvi", frozen)]
pub struct Chebyshev {
    series: RustChebyshev,
}

/// A fit's function failed; the error is kept to be raised.
enum FitError {
    Spectral(SpectralError),
    Python(PyErr),
}

impl From<SpectralError> for FitError {
    fn from(e: SpectralError) -> Self {
        FitError::Spectral(e)
    }
}

#[pymethods]
impl Chebyshev {
    #[new]
    #[pyo3(signature = (coefficients, a=-1.0, b=1.0))]
    fn new(coefficients: &Bound<'_, PyAny>, a: f64, b: f64) -> PyResult<Self> {
        let c = crate::convert::vector(coefficients, "coefficients")?;
        let series = RustChebyshev::from_coefficients(c, a, b).map_err(spectral)?;
        Ok(Self { series })
    }

    /// Fits `f` on `[a, b]` to the relative tolerance `tol` (default machine precision,
    /// relative to the largest coefficient), sampling at 17, 33, 65, … Chebyshev–Lobatto
    /// points until the coefficients reach a plateau and chopping them there. `f` is called
    /// with an ndarray of points and returns an array of values (it may be called a few
    /// times). Raises ConvergenceError when 4097 points do not resolve `f` (not smooth on
    /// `[a, b]`: split the interval).
    #[classmethod]
    #[pyo3(signature = (f, a, b, tol=None))]
    fn fit(
        _cls: &Bound<'_, PyType>,
        f: &Bound<'_, PyAny>,
        a: f64,
        b: f64,
        tol: Option<f64>,
    ) -> PyResult<Self> {
        let py = f.py();
        let evaluate = |points: &[f64]| -> Result<Vec<f64>, FitError> {
            let x = array1(py, points.to_vec());
            let y = f.call1((x,)).map_err(FitError::Python)?;
            let values = array(&y, "f(x)").map_err(FitError::Python)?;
            let view = values.as_array();
            if view.len() != points.len() {
                return Err(FitError::Python(invalid(format!(
                    "f returned {} values at {} points: it must return one value per point \
                     (shape {:?} of f(x))",
                    view.len(),
                    points.len(),
                    view.shape()
                ))));
            }
            Ok(view.iter().copied().collect())
        };
        let tol = tol.unwrap_or(f64::EPSILON);
        match RustChebyshev::try_fit_batch(evaluate, a, b, tol) {
            Ok(series) => Ok(Self { series }),
            Err(FitError::Spectral(e)) => Err(spectral(e)),
            Err(FitError::Python(e)) => Err(e),
        }
    }

    /// The interpolant through `values` at the `len(values)` Chebyshev–Lobatto points of
    /// `[a, b]` (ascending).
    #[classmethod]
    #[pyo3(signature = (values, a=-1.0, b=1.0))]
    fn from_values(
        _cls: &Bound<'_, PyType>,
        values: &Bound<'_, PyAny>,
        a: f64,
        b: f64,
    ) -> PyResult<Self> {
        let v = crate::convert::vector(values, "values")?;
        let series = RustChebyshev::from_values(&v, a, b).map_err(spectral)?;
        Ok(Self { series })
    }

    /// The coefficients `c_0, c_1, …`.
    #[getter]
    fn coefficients<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.series.coefficients().to_vec())
    }

    /// The interval `(a, b)`.
    #[getter]
    fn interval(&self) -> (f64, f64) {
        self.series.interval()
    }

    /// The values at `x` (a float or an array of any shape, within `[a, b]`).
    fn __call__<'py>(&self, py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        if let Ok(x) = x.extract::<f64>() {
            return self
                .series
                .evaluate(x)
                .map_err(spectral)
                .and_then(|y| Ok(y.into_pyobject(py)?.into_any()));
        }
        let points = array(x, "x")?;
        let view = points.as_array();
        finite(&view, "x")?;
        let shape = view.shape().to_vec();
        let values = view
            .iter()
            .map(|&x| self.series.evaluate(x))
            .collect::<Result<Vec<f64>, _>>()
            .map_err(spectral)?;
        Ok(array_dyn(py, &shape, values)?.into_any())
    }

    /// The derivative, exact on the series.
    fn derivative(&self) -> Self {
        Self {
            series: self.series.derivative(),
        }
    }

    /// The indefinite integral, zero at `a`, exact on the series.
    fn integral(&self) -> Self {
        Self {
            series: self.series.integral(),
        }
    }

    /// The integral over `[a, b]`.
    fn definite_integral(&self) -> f64 {
        self.series.definite_integral()
    }

    /// The real roots in `[a, b]`, ascending (the colleague matrix's eigenvalues, each
    /// polished).
    fn roots<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array1(py, self.series.roots())
    }

    /// `(min, max)` of the function on `[a, b]`.
    fn range(&self) -> (f64, f64) {
        self.series.range()
    }

    fn __len__(&self) -> usize {
        self.series.len()
    }

    fn __add__(&self, other: PyRef<'_, Chebyshev>) -> PyResult<Self> {
        Ok(Self {
            series: self.series.add(&other.series).map_err(spectral)?,
        })
    }

    fn __mul__(&self, other: PyRef<'_, Chebyshev>) -> PyResult<Self> {
        Ok(Self {
            series: self.series.mul(&other.series).map_err(spectral)?,
        })
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<Chebyshev>()
            .is_ok_and(|o| o.get().series == self.series)
    }

    fn __repr__(&self) -> String {
        let (a, b) = self.series.interval();
        format!(
            "Chebyshev({} coefficients on [{a}, {b}])",
            self.series.len()
        )
    }

    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let py = slf.py();
        let s = &slf.get().series;
        let (a, b) = s.interval();
        let args = (array1(py, s.coefficients().to_vec()), a, b).into_pyobject(py)?;
        Ok((slf.get_type().into_any(), args))
    }
}

/// Applies `f` to every trailing block of `shape` (`inner` entries) of `x`, writing
/// `out_inner` entries each; the result's shape is the leading shape and `out_shape`.
fn batch<'py>(
    py: Python<'py>,
    x: &Bound<'py, PyAny>,
    name: &str,
    inner: &[usize],
    out_shape: &[usize],
    f: impl Fn(&[f64]) -> PyResult<Vec<f64>>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let a = array(x, name)?;
    let view = a.as_array();
    let shape = view.shape();
    if shape.len() < inner.len() || shape[shape.len() - inner.len()..] != *inner {
        return Err(invalid(format!(
            "{name} must have shape (..., {}), got {shape:?}",
            inner
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    finite(&view, name)?;
    let leading = &shape[..shape.len() - inner.len()];
    let size: usize = inner.iter().product();
    let flat: Vec<f64> = view.iter().copied().collect();
    let mut out =
        Vec::with_capacity(flat.len() / size.max(1) * out_shape.iter().product::<usize>());
    for block in flat.chunks(size) {
        out.extend(f(block)?);
    }
    let mut result_shape = leading.to_vec();
    result_shape.extend_from_slice(out_shape);
    array_dyn(py, &result_shape, out)
}

fn rotation_of(block: &[f64]) -> Matrix3<f64> {
    Matrix3::from_row_slice(block)
}

/// `exp(ŵ)`: rotation vectors (..., 3) to rotation matrices (..., 3, 3) (Rodrigues, with
/// its small-angle series).
#[pyfunction]
fn so3_exp<'py>(py: Python<'py>, w: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    batch(py, w, "w", &[3], &[3, 3], |b| {
        Ok(rows3(SO3::exp(&Vector3::from_column_slice(b)).matrix()).to_vec())
    })
}

/// The principal logarithm: rotation matrices (..., 3, 3) to rotation vectors (..., 3),
/// `|w| ≤ π`. Raises InvalidInputError for a matrix that is not a rotation (to 1e-9).
#[pyfunction]
#[allow(non_snake_case)]
fn so3_log<'py>(py: Python<'py>, R: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    batch(py, R, "R", &[3, 3], &[3], |b| {
        let r =
            SO3::try_from_matrix_with_tolerance(rotation_of(b), crate::convert::ROTATION_TOLERANCE)
                .map_err(lie)?;
        Ok(r.log().as_slice().to_vec())
    })
}

/// `exp` of SE(3): twists `(ω, v)` (..., 6) to homogeneous matrices (..., 4, 4).
#[pyfunction]
fn se3_exp<'py>(py: Python<'py>, xi: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    batch(py, xi, "xi", &[6], &[4, 4], |b| {
        let g = SE3::exp(&Vector6::from_column_slice(b));
        Ok(homogeneous(&g))
    })
}

/// The logarithm of SE(3): homogeneous matrices (..., 4, 4) to twists `(ω, v)` (..., 6).
#[pyfunction]
#[allow(non_snake_case)]
fn se3_log<'py>(py: Python<'py>, T: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    batch(py, T, "T", &[4, 4], &[6], |b| {
        let g = SE3::try_from_matrix(Matrix4::from_row_slice(b)).map_err(lie)?;
        Ok(g.log().as_slice().to_vec())
    })
}

fn homogeneous(g: &SE3) -> Vec<f64> {
    let r = g.rotation().matrix();
    let x = g.translation();
    vec![
        r[(0, 0)],
        r[(0, 1)],
        r[(0, 2)],
        x.x,
        r[(1, 0)],
        r[(1, 1)],
        r[(1, 2)],
        x.y,
        r[(2, 0)],
        r[(2, 1)],
        r[(2, 2)],
        x.z,
        0.0,
        0.0,
        0.0,
        1.0,
    ]
}

/// `ŵ`: vectors (..., 3) to skew matrices (..., 3, 3), `hat(a, b, c) = [[0, −c, b], [c, 0,
/// −a], [−b, a, 0]]`.
#[pyfunction]
fn hat<'py>(py: Python<'py>, w: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    batch(py, w, "w", &[3], &[3, 3], |b| {
        Ok(rows3(&lgsvi_lie::so3::hat(&Vector3::from_column_slice(b))).to_vec())
    })
}

/// The inverse of `hat`: skew matrices (..., 3, 3) to vectors (..., 3).
#[pyfunction]
#[allow(non_snake_case)]
fn vee<'py>(py: Python<'py>, M: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    batch(py, M, "M", &[3, 3], &[3], |b| {
        Ok(lgsvi_lie::so3::vee(&rotation_of(b)).as_slice().to_vec())
    })
}

/// A chart `Φ` of SO(3): chart coordinates (..., 3) to rotation matrices (..., 3, 3).
/// `chart`: `"exp"`, `"cayley"` or `"cayley-unscaled"` (the paper's `(I − q̂)(I + q̂)⁻¹`).
#[pyfunction]
#[pyo3(signature = (w, chart="exp"))]
fn chart_to_group<'py>(
    py: Python<'py>,
    w: &Bound<'py, PyAny>,
    chart: &str,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let c = chart_named(chart)?;
    batch(py, w, "w", &[3], &[3, 3], |b| {
        let v = Vector3::from_column_slice(b);
        c.check_rotation_domain(&v).map_err(lie)?;
        Ok(rows3(&c.rotation_matrix(&v)).to_vec())
    })
}

/// `Φ⁻¹`: rotation matrices (..., 3, 3) to chart coordinates (..., 3).
#[pyfunction]
#[pyo3(signature = (R, chart="exp"))]
#[allow(non_snake_case)]
fn chart_to_algebra<'py>(
    py: Python<'py>,
    R: &Bound<'py, PyAny>,
    chart: &str,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let c = chart_named(chart)?;
    batch(py, R, "R", &[3, 3], &[3], |b| {
        SO3::try_from_matrix_with_tolerance(rotation_of(b), crate::convert::ROTATION_TOLERANCE)
            .map_err(lie)?;
        Ok(c.rotation_vector(&rotation_of(b))
            .map_err(lie)?
            .as_slice()
            .to_vec())
    })
}

/// The chart's left-trivialised differential `A(w)` (`Φ(w)⁻¹ dΦ(w)[v] = (A(w) v)^`):
/// coordinates (..., 3) to matrices (..., 3, 3); `side="right"` gives the
/// right-trivialised one.
#[pyfunction]
#[pyo3(signature = (w, chart="exp", side="left"))]
fn chart_differential<'py>(
    py: Python<'py>,
    w: &Bound<'py, PyAny>,
    chart: &str,
    side: &str,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let c = chart_named(chart)?;
    let left = match side {
        "left" => true,
        "right" => false,
        other => {
            return Err(invalid(format!(
                "side must be \"left\" or \"right\", got {other:?}"
            )))
        }
    };
    batch(py, w, "w", &[3], &[3, 3], |b| {
        let v = Vector3::from_column_slice(b);
        c.check_rotation_domain(&v).map_err(lie)?;
        let m = if left {
            c.rotation_left_differential(&v)
        } else {
            c.rotation_right_differential(&v)
        };
        Ok(rows3(&m).to_vec())
    })
}

/// Rotation matrices (..., 3, 3) to unit quaternions `(w, x, y, z)` (..., 4), `w ≥ 0`.
#[pyfunction]
#[allow(non_snake_case)]
fn quaternion_from_matrix<'py>(
    py: Python<'py>,
    R: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    batch(py, R, "R", &[3, 3], &[4], |b| {
        SO3::try_from_matrix_with_tolerance(rotation_of(b), crate::convert::ROTATION_TOLERANCE)
            .map_err(lie)?;
        Ok(crate::state::quaternion(&rotation_of(b)).to_vec())
    })
}

/// Quaternions `(w, x, y, z)` (..., 4), normalised first, to rotation matrices (..., 3, 3).
#[pyfunction]
fn matrix_from_quaternion<'py>(
    py: Python<'py>,
    q: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    batch(py, q, "q", &[4], &[3, 3], |b| {
        let r = SO3::try_from_quaternion_wxyz([b[0], b[1], b[2], b[3]]).map_err(lie)?;
        Ok(rows3(r.matrix()).to_vec())
    })
}

/// Registers the functions and the class.
pub fn register(module: &Bound<'_, PyModule>) -> PyResult<()> {
    for f in [
        wrap_pyfunction!(gauss_legendre, module)?,
        wrap_pyfunction!(gauss_lobatto, module)?,
        wrap_pyfunction!(gauss_radau, module)?,
        wrap_pyfunction!(gauss_hermite, module)?,
        wrap_pyfunction!(gauss_laguerre, module)?,
        wrap_pyfunction!(gauss_jacobi, module)?,
        wrap_pyfunction!(gauss_kronrod, module)?,
        wrap_pyfunction!(gauss_kronrod_gauss_weights, module)?,
        wrap_pyfunction!(so3_exp, module)?,
        wrap_pyfunction!(so3_log, module)?,
        wrap_pyfunction!(se3_exp, module)?,
        wrap_pyfunction!(se3_log, module)?,
        wrap_pyfunction!(hat, module)?,
        wrap_pyfunction!(vee, module)?,
        wrap_pyfunction!(chart_to_group, module)?,
        wrap_pyfunction!(chart_to_algebra, module)?,
        wrap_pyfunction!(chart_differential, module)?,
        wrap_pyfunction!(quaternion_from_matrix, module)?,
        wrap_pyfunction!(matrix_from_quaternion, module)?,
    ] {
        module.add_function(f)?;
    }
    module.add_class::<Chebyshev>()?;
    Ok(())
}
