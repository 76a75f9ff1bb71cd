//! numpy → Rust slices. An array that already is C-contiguous with the wanted dtype is read in
//! place (zero-copy); any other numeric array or sequence is converted once by numpy. Shapes and
//! dtypes that cannot be meant (strings, complex, floats as indices, wrong column counts) raise
//! `pelt.InvalidMeshError` naming the array.

use numpy::{
    Element, PyArrayDescrMethods, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyAnyMethods;
use rayon::prelude::*;

use crate::errors::IntoPyErr;
use pelt_core::error::{MeshError, PeltError};

/// A triangle index array: borrowed when it already is `uint32`, otherwise widened to `int64`
/// so negative and too-large indices can be reported as they were given.
pub(super) enum IndexArray<'py> {
    Native(PyReadonlyArrayDyn<'py, u32>),
    Wide(PyReadonlyArrayDyn<'py, i64>),
}

fn mesh_error(e: MeshError) -> PyErr {
    PeltError::from(e).into_pyerr()
}

fn shape_text(shape: &[usize]) -> String {
    let parts: Vec<String> = shape.iter().map(usize::to_string).collect();
    format!("[{}]", parts.join(", "))
}

/// `obj` as a numpy array (sequences go through `numpy.asarray`), with its shape checked against
/// `[N]` (`cols == None`) or `[N, cols]`.
fn as_checked_array<'py>(
    obj: &Bound<'py, PyAny>,
    name: &'static str,
    cols: Option<usize>,
) -> PyResult<Bound<'py, PyUntypedArray>> {
    let expected = cols.map_or("[N]".to_string(), |c| format!("[N, {c}]"));
    if obj.is_none() {
        return Err(mesh_error(MeshError::Shape {
            array: name,
            expected,
            got: "None".into(),
        }));
    }
    let array = match obj.cast::<PyUntypedArray>() {
        Ok(array) => array.clone(),
        Err(_) => {
            let numpy = obj.py().import("numpy")?;
            let converted = numpy.call_method1("asarray", (obj,)).map_err(|e| {
                mesh_error(MeshError::Shape {
                    array: name,
                    expected: expected.clone(),
                    got: format!("something numpy cannot read as an array ({e})"),
                })
            })?;
            converted.cast_into::<PyUntypedArray>()?
        }
    };
    let shape = array.shape();
    let fits = match cols {
        None => shape.len() == 1,
        Some(c) => shape.len() == 2 && shape[1] == c,
    };
    if !fits {
        return Err(mesh_error(MeshError::Shape {
            array: name,
            expected,
            got: shape_text(shape),
        }));
    }
    Ok(array)
}

fn dtype_name(array: &Bound<'_, PyUntypedArray>) -> String {
    array
        .dtype()
        .str()
        .map(|s| s.to_string())
        .unwrap_or_else(|_| "unknown".into())
}

/// `array` as a C-contiguous `T` array, borrowed if it already is one, else converted by numpy.
fn contiguous<'py, T: Element>(
    array: &Bound<'py, PyUntypedArray>,
    name: &str,
    numpy_dtype: &str,
) -> PyResult<PyReadonlyArrayDyn<'py, T>> {
    let py = array.py();
    let fits = array.dtype().is_equiv_to(&numpy::dtype::<T>(py)) && array.is_c_contiguous();
    let typed = if fits {
        array.clone()
    } else {
        let numpy = py.import("numpy")?;
        let kwargs = pyo3::types::PyDict::new(py);
        kwargs.set_item("dtype", numpy.getattr(numpy_dtype)?)?;
        numpy
            .call_method("ascontiguousarray", (array,), Some(&kwargs))?
            .cast_into::<PyUntypedArray>()?
    };
    let typed = typed.cast_into::<PyArrayDyn<T>>()?;
    typed.try_readonly().map_err(|e| {
        PeltError::parameter(name, format!("the array is being written elsewhere ({e})")).into_pyerr()
    })
}

/// Reads a float array of shape `[N]` or `[N, cols]` as `float32`.
pub(super) fn float_array<'py>(
    obj: &Bound<'py, PyAny>,
    name: &'static str,
    cols: Option<usize>,
) -> PyResult<PyReadonlyArrayDyn<'py, f32>> {
    let array = as_checked_array(obj, name, cols)?;
    if !matches!(array.dtype().kind(), b'f' | b'i' | b'u') {
        return Err(mesh_error(MeshError::DType {
            array: name,
            expected: "a real number type (float32 preferred)",
            got: dtype_name(&array),
        }));
    }
    contiguous::<f32>(&array, name, "float32")
}

/// Rejects arrays whose dtype is not an integer type, naming the array.
fn require_integer(array: &Bound<'_, PyUntypedArray>, name: &'static str) -> PyResult<()> {
    if matches!(array.dtype().kind(), b'i' | b'u') {
        Ok(())
    } else {
        Err(mesh_error(MeshError::DType {
            array: name,
            expected: "an integer type (uint32 preferred)",
            got: dtype_name(array),
        }))
    }
}

/// Reads a triangle array of shape `[M, 3]` of any integer type.
pub(super) fn index_array<'py>(obj: &Bound<'py, PyAny>, name: &'static str) -> PyResult<IndexArray<'py>> {
    let array = as_checked_array(obj, name, Some(3))?;
    require_integer(&array, name)?;
    if array.dtype().is_equiv_to(&numpy::dtype::<u32>(array.py())) {
        return Ok(IndexArray::Native(contiguous::<u32>(&array, name, "uint32")?));
    }
    if array.dtype().is_equiv_to(&numpy::dtype::<u64>(array.py())) {
        // Above i64::MAX a uint64 would wrap to a negative int64: report the value as given.
        let unsigned = contiguous::<u64>(&array, name, "uint64")?;
        let values = flat(&unsigned)?;
        if let Some(at) = values.iter().position(|&v| v > i64::MAX as u64) {
            return Err(PeltError::parameter(
                name,
                format!(
                    "triangle {} corner {} refers to vertex {}, far beyond any mesh",
                    at / 3,
                    at % 3,
                    values[at]
                ),
            )
            .into_pyerr());
        }
    }
    Ok(IndexArray::Wide(contiguous::<i64>(&array, name, "int64")?))
}

/// Reads a one-dimensional array of non-negative integers (polygon indices) as `uint32`.
pub(super) fn uint_array<'py>(
    obj: &Bound<'py, PyAny>,
    name: &'static str,
) -> PyResult<PyReadonlyArrayDyn<'py, u32>> {
    let array = as_checked_array(obj, name, None)?;
    require_integer(&array, name)?;
    if array.dtype().is_equiv_to(&numpy::dtype::<u32>(array.py())) {
        return contiguous::<u32>(&array, name, "uint32");
    }
    // Widen first so that negative or too large values are reported, not wrapped.
    let wide = contiguous::<i64>(&array, name, "int64")?;
    check_u32_range(flat(&wide)?, name, "row")?;
    contiguous::<u32>(&array, name, "uint32")
}

/// Refuses the first value outside `[0, u32::MAX]`, naming `name` and the `what` it is.
fn check_u32_range(values: &[i64], name: &str, what: &str) -> PyResult<()> {
    match values
        .iter()
        .position(|&v| !(0..=i64::from(u32::MAX)).contains(&v))
    {
        None => Ok(()),
        Some(at) => Err(PeltError::parameter(
            name,
            format!("{what} {at} is {}, outside [0, 4294967295]", values[at]),
        )
        .into_pyerr()),
    }
}

/// The values of an array this module made contiguous (a failure here is a bug in Pelt).
pub(super) fn flat<'a, T: Element>(array: &'a PyReadonlyArrayDyn<'_, T>) -> PyResult<&'a [T]> {
    array
        .as_slice()
        .map_err(|e| PeltError::Internal(format!("array not contiguous after conversion: {e}")).into_pyerr())
}

/// The rows of a contiguous array whose last axis has `C` entries.
pub(super) fn rows<'a, T: Element, const C: usize>(
    array: &'a PyReadonlyArrayDyn<'_, T>,
) -> PyResult<&'a [[T; C]]> {
    Ok(flat(array)?.as_chunks::<C>().0)
}

/// Checks widened indices against `vertex_count` and narrows them to `u32`.
pub(super) fn narrow_indices(wide: &[[i64; 3]], vertex_count: usize) -> Result<Vec<[u32; 3]>, MeshError> {
    let bad = |i: i64| i < 0 || i as u64 >= vertex_count as u64;
    if let Some(triangle) = wide.par_iter().position_first(|t| t.iter().any(|&i| bad(i))) {
        let corner = wide[triangle].iter().position(|&i| bad(i)).unwrap_or(0);
        return Err(MeshError::IndexOutOfRange {
            triangle,
            corner,
            index: wide[triangle][corner],
            vertex_count,
        });
    }
    Ok(wide.par_iter().map(|t| t.map(|i| i as u32)).collect())
}

/// `obj` as a numpy array (sequences go through `numpy.asarray`) whose shape passes `fits`
/// (described by `expected`), with that shape; otherwise `pelt.InvalidParameterError` naming
/// `name`.
fn shaped_array<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    expected: &str,
    fits: impl Fn(&[usize]) -> bool,
) -> PyResult<(Bound<'py, PyUntypedArray>, Vec<usize>)> {
    let array = match obj.cast::<PyUntypedArray>() {
        Ok(array) => array.clone(),
        Err(_) => obj
            .py()
            .import("numpy")?
            .call_method1("asarray", (obj,))
            .and_then(|a| Ok(a.cast_into::<PyUntypedArray>()?))
            .map_err(|e| {
                PeltError::parameter(name, format!("must be an array of shape {expected} ({e})")).into_pyerr()
            })?,
    };
    let shape = array.shape().to_vec();
    if !fits(&shape) {
        return Err(PeltError::parameter(
            name,
            format!("must have shape {expected}, got {}", shape_text(&shape)),
        )
        .into_pyerr());
    }
    Ok((array, shape))
}

/// Reads a real-valued array whose shape passes `fits` (described by `expected`, e.g.
/// `[L, R, R]`) as C-contiguous `float32`; any other shape or dtype raises
/// `pelt.InvalidParameterError` naming `name`.
pub(super) fn float_ndarray<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    expected: &str,
    fits: impl Fn(&[usize]) -> bool,
) -> PyResult<(PyReadonlyArrayDyn<'py, f32>, Vec<usize>)> {
    let (array, shape) = shaped_array(obj, name, expected, fits)?;
    if !matches!(array.dtype().kind(), b'f' | b'i' | b'u') {
        return Err(PeltError::parameter(
            name,
            format!(
                "must hold real numbers (float32 preferred), got dtype {}",
                dtype_name(&array)
            ),
        )
        .into_pyerr());
    }
    Ok((contiguous::<f32>(&array, name, "float32")?, shape))
}

/// Reads an integer array whose shape passes `fits` (described by `expected`) as `uint32`
/// values; any other shape or dtype, or a value outside `[0, 4294967295]`, raises
/// `pelt.InvalidParameterError` naming `name`.
pub(super) fn uint_ndarray(
    obj: &Bound<'_, PyAny>,
    name: &str,
    expected: &str,
    fits: impl Fn(&[usize]) -> bool,
) -> PyResult<(Vec<u32>, Vec<usize>)> {
    let (array, shape) = shaped_array(obj, name, expected, fits)?;
    if !matches!(array.dtype().kind(), b'i' | b'u') {
        return Err(PeltError::parameter(
            name,
            format!("must hold integers, got dtype {}", dtype_name(&array)),
        )
        .into_pyerr());
    }
    // Widened first, so that negative or too large values are reported, not wrapped.
    let wide = contiguous::<i64>(&array, name, "int64")?;
    let values = flat(&wide)?;
    check_u32_range(values, name, "entry")?;
    Ok((values.iter().map(|&v| v as u32).collect(), shape))
}
