//! `pelt.pack_atlas`: shell layers laid out in one image, for Blender materials and engines
//! (neither has texture arrays everywhere); see [`crate::export::atlas`].

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::detached;
use crate::error::PeltError;
use crate::export::atlas::{AtlasLayout, pack_atlas};

/// Packs ``layers`` (``[L, R, R, C] uint8``, C in 1..4) into a grid atlas of ``ceil(sqrt(L))``
/// columns, layer 0 top left, row by row; returns ``(image [H, W, C] uint8, layout dict)``.
#[pyfunction(name = "pack_atlas")]
pub(super) fn pack_atlas_py<'py>(
    py: Python<'py>,
    layers: PyReadonlyArrayDyn<'py, u8>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyDict>)> {
    let shape = layers.shape().to_vec();
    let [count, rows, cols, channels] = shape[..] else {
        return Err(
            PeltError::parameter("layers", format!("must be [L, R, R, C], got shape {shape:?}")).into(),
        );
    };
    if rows != cols {
        return Err(
            PeltError::parameter("layers", format!("layers must be square, got {rows}x{cols}")).into(),
        );
    }
    let data = layers
        .as_slice()
        .map_err(|_| PeltError::parameter("layers", "must be C-contiguous"))?;
    let (layout, image) = detached(py, || {
        let layout = AtlasLayout::new(count, rows)?;
        let image = pack_atlas(&layout, channels, data)?;
        Ok((layout, image))
    })?;
    let d = PyDict::new(py);
    for (key, value) in [
        ("layers", layout.layers),
        ("tile", layout.tile),
        ("columns", layout.columns),
        ("rows", layout.rows),
        ("width", layout.width),
        ("height", layout.height),
    ] {
        d.set_item(key, value)?;
    }
    let pixels =
        PyArray1::from_vec(py, image.into_data()).reshape([layout.height, layout.width, channels])?;
    Ok((pixels.into_any(), d))
}
