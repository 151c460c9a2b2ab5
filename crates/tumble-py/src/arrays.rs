//! numpy arrays in and out: float64 only (other dtypes are refused, not converted), shapes checked
//! with messages that name the argument. Contiguous inputs are read in place; Python sequences
//! (lists, tuples) are converted by numpy first.

use crate::bad;
use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;
use std::borrow::Cow;

/// `obj` as a float64 numpy array: an ndarray of dtype float64 as it is; a list or tuple through
/// `numpy.asarray(obj, dtype=float64)`; any other ndarray dtype is an error.
pub fn f64_array<'py>(obj: &Bound<'py, PyAny>, name: &str) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    if let Ok(a) = obj.cast::<PyArrayDyn<f64>>() {
        return Ok(a.clone());
    }
    if let Ok(u) = obj.cast::<PyUntypedArray>() {
        return Err(bad(format!(
            "{name}: dtype {}, expected float64 (convert with x.astype(numpy.float64))",
            u.dtype()
        )));
    }
    if obj.is_instance_of::<pyo3::types::PyList>() || obj.is_instance_of::<pyo3::types::PyTuple>() {
        let np = obj.py().import("numpy")?;
        let converted = np
            .call_method1("asarray", (obj, "float64"))
            .map_err(|e| bad(format!("{name}: cannot be read as float64 numbers: {e}")))?;
        return converted.cast_into::<PyArrayDyn<f64>>().map_err(PyErr::from);
    }
    Err(bad(format!("{name}: expected a float64 numpy array, got {}", obj.get_type().name()?)))
}

/// Checks a shape against `expected` (`None` = any length on that axis), naming the argument.
pub fn check_shape(name: &str, shape: &[usize], expected: &[Option<usize>], meaning: &str) -> PyResult<()> {
    let fits = shape.len() == expected.len() && shape.iter().zip(expected).all(|(s, e)| e.is_none_or(|e| e == *s));
    if fits {
        return Ok(());
    }
    let want: Vec<String> = expected.iter().map(|e| e.map_or("B".to_string(), |e| e.to_string())).collect();
    let got: Vec<String> = shape.iter().map(|s| s.to_string()).collect();
    Err(bad(format!("{name}: shape {}, expected {} = {meaning}", tuple(&got), tuple(&want))))
}

/// `(a, b)`, or `(a,)` for one element, as numpy prints shapes.
fn tuple(items: &[String]) -> String {
    match items {
        [one] => format!("({one},)"),
        _ => format!("({})", items.join(", ")),
    }
}

/// The array's values in C order: borrowed when contiguous, else copied.
pub fn values<'a>(a: &'a numpy::PyReadonlyArrayDyn<'_, f64>) -> Cow<'a, [f64]> {
    match a.as_slice() {
        Ok(s) => Cow::Borrowed(s),
        Err(_) => Cow::Owned(a.as_array().iter().copied().collect()),
    }
}

/// A float64 vector argument of length `n`, every entry finite; copied out of Python.
pub fn finite_vector(obj: &Bound<'_, PyAny>, name: &str, n: usize, meaning: &str) -> PyResult<Vec<f64>> {
    let a = f64_array(obj, name)?;
    check_shape(name, a.shape(), &[Some(n)], meaning)?;
    let ro = a.try_readonly().map_err(|e| bad(format!("{name}: {e}")))?;
    let v = values(&ro).into_owned();
    check_finite(name, &v)?;
    Ok(v)
}

/// Errors on the first non-finite entry, naming its flat index.
pub fn check_finite(name: &str, v: &[f64]) -> PyResult<()> {
    match v.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(i) => Err(bad(format!("{name}: entry {i} is not finite (got {})", v[i]))),
    }
}

/// An `out=` argument: a writeable, C-contiguous float64 array of exactly this shape.
pub fn out_array<'py>(obj: &Bound<'py, PyAny>, shape: &[usize]) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let a = match obj.cast::<PyArrayDyn<f64>>() {
        Ok(a) => a.clone(),
        Err(_) => {
            let what = match obj.cast::<PyUntypedArray>() {
                Ok(u) => format!("an array of dtype {}", u.dtype()),
                Err(_) => obj.get_type().name()?.to_string(),
            };
            return Err(bad(format!("out: expected a float64 numpy array, got {what}")));
        }
    };
    if a.shape() != shape {
        let fmt = |v: &[usize]| tuple(&v.iter().map(|s| s.to_string()).collect::<Vec<_>>());
        return Err(bad(format!("out: shape {}, expected {}", fmt(a.shape()), fmt(shape))));
    }
    if !a.is_c_contiguous() {
        return Err(bad("out: must be C-contiguous (numpy.empty(shape) is)"));
    }
    Ok(a)
}
