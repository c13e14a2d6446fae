//! numpy and Python sequences in, nalgebra out (and back): every conversion checks the
//! shape and that the numbers are finite, and a refusal names the argument.

use crate::errors::invalid;
use lgsvi_lie::SO3;
use nalgebra::{DMatrix, Matrix3, Vector3};
use numpy::ndarray::{Array2, Array3, ArrayViewD, IxDyn};
use numpy::{
    AllowTypeChange, IntoPyArray, PyArray1, PyArray2, PyArray3, PyArrayLikeDyn,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;

/// The largest deviation from orthogonality an attitude may have (`‖RᵀR − I‖_F`): the
/// library's own for initial states.
pub const ROTATION_TOLERANCE: f64 = 1e-9;

/// An array of floats from anything numpy converts (a list, an int array), or an error
/// naming `name`.
pub fn array<'py>(
    value: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<PyArrayLikeDyn<'py, f64, AllowTypeChange>> {
    value
        .extract::<PyArrayLikeDyn<'py, f64, AllowTypeChange>>()
        .map_err(|e| {
            invalid(format!(
                "{name} must be an array of numbers: {}",
                e.value(value.py())
            ))
        })
}

/// Checks that every entry is finite.
pub fn finite(view: &ArrayViewD<'_, f64>, name: &str) -> PyResult<()> {
    if view.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(invalid(format!("{name} must be finite: {view}")))
    }
}

/// The entries of an array of shape `shape` (row-major), or an error naming `name`.
pub fn values(value: &Bound<'_, PyAny>, name: &str, shape: &[usize]) -> PyResult<Vec<f64>> {
    let a = array(value, name)?;
    let view = a.as_array();
    if view.shape() != shape {
        return Err(invalid(format!(
            "{name} must have shape {shape:?}, got {:?}",
            view.shape()
        )));
    }
    finite(&view, name)?;
    Ok(view.iter().copied().collect())
}

/// A vector of 3.
pub fn vector3(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Vector3<f64>> {
    Ok(Vector3::from_column_slice(&values(value, name, &[3])?))
}

/// A vector of any length.
pub fn vector(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    let a = array(value, name)?;
    let view = a.as_array();
    if view.ndim() != 1 {
        return Err(invalid(format!(
            "{name} must be one-dimensional, got shape {:?}",
            view.shape()
        )));
    }
    finite(&view, name)?;
    Ok(view.iter().copied().collect())
}

/// A 3 × 3 matrix (row-major input).
pub fn matrix3(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Matrix3<f64>> {
    Ok(Matrix3::from_row_slice(&values(value, name, &[3, 3])?))
}

/// A matrix of any shape.
pub fn matrix(value: &Bound<'_, PyAny>, name: &str) -> PyResult<DMatrix<f64>> {
    let a = array(value, name)?;
    let view = a.as_array();
    if view.ndim() != 2 {
        return Err(invalid(format!(
            "{name} must be a matrix (two-dimensional), got shape {:?}",
            view.shape()
        )));
    }
    finite(&view, name)?;
    let (rows, cols) = (view.shape()[0], view.shape()[1]);
    Ok(DMatrix::from_row_iterator(rows, cols, view.iter().copied()))
}

/// A rotation matrix (`world_from_body`), orthogonal with determinant 1 to
/// [`ROTATION_TOLERANCE`].
pub fn rotation(value: &Bound<'_, PyAny>, name: &str) -> PyResult<SO3> {
    let m = matrix3(value, name)?;
    SO3::try_from_matrix_with_tolerance(m, ROTATION_TOLERANCE)
        .map_err(|e| invalid(format!("{name} is not a rotation matrix: {e}")))
}

/// A stack of `(M, 3)` vectors.
pub fn vectors3(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<Vector3<f64>>> {
    let a = array(value, name)?;
    let view = a.as_array();
    if view.ndim() != 2 || view.shape()[1] != 3 {
        return Err(invalid(format!(
            "{name} must have shape (M, 3), got {:?}",
            view.shape()
        )));
    }
    finite(&view, name)?;
    let flat: Vec<f64> = view.iter().copied().collect();
    Ok(flat.chunks(3).map(Vector3::from_column_slice).collect())
}

/// A stack of `(M, 3, 3)` rotation matrices.
pub fn rotations(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<SO3>> {
    let a = array(value, name)?;
    let view = a.as_array();
    if view.ndim() != 3 || view.shape()[1..] != [3, 3] {
        return Err(invalid(format!(
            "{name} must have shape (M, 3, 3), got {:?}",
            view.shape()
        )));
    }
    finite(&view, name)?;
    let flat: Vec<f64> = view.iter().copied().collect();
    flat.chunks(9)
        .enumerate()
        .map(|(i, m)| {
            SO3::try_from_matrix_with_tolerance(Matrix3::from_row_slice(m), ROTATION_TOLERANCE)
                .map_err(|e| invalid(format!("{name}[{i}] is not a rotation matrix: {e}")))
        })
        .collect()
}

/// A 1-D ndarray.
pub fn array1<'py>(py: Python<'py>, values: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, values)
}

/// A 2-D ndarray from rows of equal length.
pub fn array2<'py>(
    py: Python<'py>,
    rows: usize,
    cols: usize,
    flat: Vec<f64>,
) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_vec((rows, cols), flat)
        .expect("the rows were collected with this shape")
        .into_pyarray(py)
}

/// A 3-D ndarray.
pub fn array3<'py>(
    py: Python<'py>,
    shape: (usize, usize, usize),
    flat: Vec<f64>,
) -> Bound<'py, PyArray3<f64>> {
    Array3::from_shape_vec(shape, flat)
        .expect("the entries were collected with this shape")
        .into_pyarray(py)
}

/// A matrix as a 2-D ndarray (row-major).
pub fn from_matrix<'py>(py: Python<'py>, m: &DMatrix<f64>) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = m.transpose().iter().copied().collect();
    array2(py, m.nrows(), m.ncols(), flat)
}

/// Matrices of one shape as a 3-D ndarray `(count, rows, columns)`, each row-major.
pub fn stacked<'py>(py: Python<'py>, matrices: &[DMatrix<f64>]) -> Bound<'py, PyArray3<f64>> {
    let (rows, cols) = matrices.first().map_or((0, 0), |m| m.shape());
    let mut flat = Vec::with_capacity(matrices.len() * rows * cols);
    for m in matrices {
        flat.extend(m.transpose().iter());
    }
    array3(py, (matrices.len(), rows, cols), flat)
}

/// A 3 × 3 matrix's entries, row-major.
pub fn rows3(m: &Matrix3<f64>) -> [f64; 9] {
    let t = m.transpose();
    std::array::from_fn(|i| t[i])
}

/// An n-dimensional array of `shape` from row-major entries.
pub fn array_dyn<'py>(
    py: Python<'py>,
    shape: &[usize],
    flat: Vec<f64>,
) -> PyResult<Bound<'py, numpy::PyArrayDyn<f64>>> {
    numpy::ndarray::ArrayD::from_shape_vec(IxDyn(shape), flat)
        .map(|a| a.into_pyarray(py))
        .map_err(|e| invalid(e.to_string()))
}

/// An array's shape.
pub fn shape_of(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<usize>> {
    Ok(array(value, name)?.shape().to_vec())
}
