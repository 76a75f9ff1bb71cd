//! `pelt.HairParams` and `pelt.bake_volume`: the hair volume from Python.
//!
//! `HairParams` keeps a [`pelt_core::hair::HairParams`]; fields are read and written by name, and
//! every write goes through serde and [`pelt_core::hair::HairParams::validate`], so a bad value raises
//! `pelt.InvalidParameterError` naming the field and its range and leaves the object unchanged.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyAttributeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde_json::Value;

use super::detached;
use super::progress::PyProgress;
use crate::errors::{IntoPyErr, py_err};
use pelt_core::error::PeltError;
use pelt_core::hair::HairParams;
use pelt_core::volume::coverage::CoverageMode;
use pelt_core::volume::{HairVolume, VolumeParams, bake_volume};

/// Parameters of the hair grown in one tile (all lengths in tile units, heights in fur depths).
///
/// Construct with keywords, e.g. ``HairParams(density=8192, curl=0.3)``; read and assign fields
/// as attributes. Assigning a bad value raises ``InvalidParameterError`` (naming the field and
/// its range) and keeps the old value. Fields, with default and range:
///
/// - ``seed`` (1, any integer >= 0): seed of every random choice.
/// - ``density`` (16384, [0, 1048576]): hairs per tile.
/// - ``guard_fraction`` (0.05, [0, 1]): share of guard hairs (overcoat).
/// - ``undercoat`` ({"length": [0.55, 0.8], "width": [0.004, 0.006]}): tip height range in fur
///   depths, each in [0, 1], and base width range in tile units, each in [0, 0.1]; min <= max.
/// - ``overcoat`` ({"length": [0.85, 1.0], "width": [0.006, 0.0075]}): the same for guard hairs.
/// - ``segments`` (16, [1, 64]): polyline segments per strand.
/// - ``taper`` (0.2, [0, 1]): tip width over base width.
/// - ``curl`` (0.1, [0, 1]): parabolic curl, tip offset as a share of the height.
/// - ``helix_radius`` (0, [0, 0.1]) and ``helix_frequency`` (0, [0, 32] turns): helical curl.
/// - ``slant`` (0.2, [0, 1.396] radians) and ``slant_direction`` (0, [-2π, 2π] radians from +x):
///   tilt of the growth direction.
/// - ``length_jitter`` (0.1, [0, 1]): random shortening of each strand.
/// - ``clump_strength`` (0, [0, 1]) and ``clump_count`` (0, [0, 256]): clumping.
/// - ``root_color`` ([0.12, 0.08, 0.05]) and ``tip_color`` ([0.45, 0.32, 0.2]): linear RGB,
///   each in [0, 1]; over a mesh with painted colors only their ratio counts (`Pipeline`).
/// - ``color_jitter`` (0.15, [0, 1]): random darkening per strand.
#[pyclass(name = "HairParams", module = "pelt")]
pub(super) struct PyHairParams {
    pub(super) inner: HairParams,
}

fn to_json(params: &HairParams) -> Value {
    // A plain struct of numbers and arrays always serializes.
    serde_json::to_value(params).unwrap_or(Value::Null)
}

/// A Python value as JSON (through the `json` module: ints, floats, bools, lists, tuples, dicts).
fn py_to_json(value: &Bound<'_, PyAny>, field: &str) -> PyResult<Value> {
    let kwargs = pyo3::types::PyDict::new(value.py());
    // NaN and infinities are refused here: JSON has no spelling for them.
    kwargs.set_item("allow_nan", false)?;
    let text: String = value
        .py()
        .import("json")?
        .call_method("dumps", (value,), Some(&kwargs))
        .and_then(|s| s.extract())
        .map_err(|_| {
            PeltError::parameter(
                field,
                format!("cannot be set to {value} (not a finite number, or a list of them)"),
            )
        })
        .map_err(py_err)?;
    serde_json::from_str(&text)
        .map_err(|e| PeltError::parameter(field, format!("cannot be set to {value} ({e})")).into_pyerr())
}

fn json_to_py<'py>(py: Python<'py>, value: &Value) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (value.to_string(),))
}

/// Writes `value` into `slot`, merging into nested objects key by key (unknown keys rejected).
fn merge(slot: &mut Value, value: Value, path: &str) -> Result<(), PeltError> {
    match (slot, value) {
        (Value::Object(target), Value::Object(source)) => {
            for (key, v) in source {
                let path = format!("{path}.{key}");
                let inner = target
                    .get_mut(&key)
                    .ok_or_else(|| PeltError::parameter(&path, "is not a hair parameter"))?;
                merge(inner, v, &path)?;
            }
            Ok(())
        }
        (slot, value) => {
            *slot = value;
            Ok(())
        }
    }
}

/// `params` with field `name` set to `value`, validated.
fn with_field(params: &HairParams, name: &str, value: &Bound<'_, PyAny>) -> PyResult<HairParams> {
    let mut json = to_json(params);
    let slot = json.get_mut(name).ok_or_else(|| {
        PyAttributeError::new_err(format!(
            "HairParams has no field `{name}` (see help(pelt.HairParams))"
        ))
    })?;
    merge(slot, py_to_json(value, name)?, name).map_err(py_err)?;
    let updated: HairParams = serde_json::from_value(json)
        .map_err(|e| {
            PeltError::parameter(
                name,
                format!("has the wrong type or is out of range ({e}); see help(pelt.HairParams)"),
            )
        })
        .map_err(py_err)?;
    updated.validate().map_err(py_err)?;
    Ok(updated)
}

#[pymethods]
impl PyHairParams {
    #[new]
    #[pyo3(signature = (**fields))]
    fn new(fields: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let mut inner = HairParams::default();
        for (key, value) in fields.into_iter().flatten() {
            let key: String = key.extract()?;
            inner = with_field(&inner, &key, &value)?;
        }
        Ok(PyHairParams { inner })
    }

    fn __getattr__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        match to_json(&self.inner).get(name) {
            Some(value) => json_to_py(py, value),
            None => Err(PyAttributeError::new_err(format!(
                "HairParams has no field `{name}`"
            ))),
        }
    }

    fn __setattr__(&mut self, name: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.inner = with_field(&self.inner, name, value)?;
        Ok(())
    }

    /// All fields as a dict (nested dicts for the coats).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_to_py(py, &to_json(&self.inner))
    }

    /// The field names, in declaration order.
    #[staticmethod]
    fn fields() -> Vec<String> {
        match to_json(&HairParams::default()) {
            Value::Object(map) => map.keys().cloned().collect(),
            _ => Vec::new(),
        }
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyHairParams>()
            .is_ok_and(|o| o.borrow().inner == self.inner)
    }

    fn __repr__(&self) -> String {
        format!("pelt.HairParams({})", to_json(&self.inner))
    }
}

/// `data` as a numpy array of `shape`, without copying the buffer.
pub(super) fn array<'py, T: numpy::Element>(
    py: Python<'py>,
    data: Vec<T>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, data).reshape(shape)?.into_any())
}

pub(super) fn volume_dict<'py>(py: Python<'py>, v: HairVolume) -> PyResult<Bound<'py, PyDict>> {
    let (r, l) = (v.resolution, v.layers);
    let d = PyDict::new(py);
    d.set_item("resolution", r)?;
    d.set_item("layers", l)?;
    d.set_item("layer_spacing", v.layer_spacing)?;
    d.set_item("shells", array(py, v.shells, &[l, r, r, 4])?)?;
    let coverage = array(py, v.coverage, &[l, r, r])?;
    d.set_item("coverage", &coverage)?;
    d.set_item("density", &coverage)?;
    d.set_item("tangents", array(py, v.tangents, &[l, r, r, 4])?)?;
    let [fw, fh] = v.fin_size;
    d.set_item("fin", array(py, v.fin, &[fh, fw, 4])?)?;
    let lod = PyList::empty(py);
    for level in v.lod {
        let count = level.len() / (r * r * 4).max(1);
        lod.append(array(py, level, &[count, r, r, 4])?)?;
    }
    d.set_item("lod", lod)?;
    let mips = PyList::empty(py);
    for (k, level) in v.mips.into_iter().enumerate() {
        let side = (r >> (k + 1)).max(1);
        mips.append(array(py, level, &[l, side, side, 4])?)?;
    }
    d.set_item("mips", mips)?;
    let stats = serde_json::to_value(&v.stats).unwrap_or(Value::Null);
    d.set_item("stats", json_to_py(py, &stats)?)?;
    Ok(d)
}

/// Grows the hair of `params` and bakes its shell stack, fin texture, LOD chain, mipmaps, hair
/// tangents and density volume (see the module `pelt` docs for the layout of each array).
#[pyfunction(name = "bake_volume")]
#[pyo3(signature = (
    params=None, layers=16, resolution=128, *, coverage="exact", vertical_filter=0.0,
    fin_size=(512, 128), fin_slab=0.1, trim=true, lod=true, mipmaps=true, guard_hairs=false,
    guard_share=1.0, progress=None
))]
#[allow(clippy::too_many_arguments)]
pub(super) fn bake_volume_py<'py>(
    py: Python<'py>,
    params: Option<PyRef<'py, PyHairParams>>,
    layers: i128,
    resolution: i128,
    coverage: &str,
    vertical_filter: f64,
    fin_size: (i128, i128),
    fin_slab: f64,
    trim: bool,
    lod: bool,
    mipmaps: bool,
    guard_hairs: bool,
    guard_share: f64,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let layers: usize = super::ints::unsigned("layers", layers)?;
    let resolution: usize = super::ints::unsigned("resolution", resolution)?;
    let fin_size: (usize, usize) = super::ints::unsigned_pair("fin_size", fin_size)?;
    let hair = params.map(|p| p.inner.clone()).unwrap_or_default();
    let volume = VolumeParams {
        layers,
        resolution,
        coverage: coverage.parse::<CoverageMode>().map_err(py_err)?,
        vertical_filter,
        fin_size: [fin_size.0, fin_size.1],
        fin_slab,
        trim,
        lod,
        mipmaps,
        guard_hairs,
        guard_share,
    };
    let reporter = PyProgress::new(progress);
    let result = detached(py, || {
        let report = |f: f64| reporter.report(f);
        let callback: Option<&(dyn Fn(f64) -> bool + Sync)> =
            if reporter.is_some() { Some(&report) } else { None };
        bake_volume(&hair, &volume, callback)
    });
    let baked = reporter.finish(result)?;
    volume_dict(py, baked)
}
