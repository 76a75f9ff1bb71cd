//! Python bindings (the crate `pelt-python`, which maturin builds): the only place that touches pyo3.
//!
//! Each binding extracts its arguments, runs the core call with the GIL released and panics
//! caught ([`detached`]), and converts the result. The compiled module is `pelt._pelt`; the pure
//! Python package `pelt` (under `python/pelt/`) re-exports it and ships the `.pyi` stub.

mod arrays;
mod errors;
mod export;
mod ints;
mod lapped;
mod materials;
mod mesh;
mod pipeline;
mod progress;
mod prt;
mod reference;
mod render;
mod rig;
mod volume;

use std::panic::{AssertUnwindSafe, catch_unwind};

use pyo3::prelude::*;

use crate::errors::{IntoPyErr, py_err};
use pelt_core::error::{Num, PeltError};

/// Runs `work` without the GIL; a panic inside becomes `pelt.PeltError` instead of crossing into
/// the host process (Blender) as a `PanicException` or an abort.
pub(crate) fn detached<T, F>(py: Python<'_>, work: F) -> PyResult<T>
where
    F: FnOnce() -> pelt_core::Result<T> + Send,
    T: Send,
{
    let outcome = py.detach(|| catch_unwind(AssertUnwindSafe(work)));
    match outcome {
        Ok(result) => result.map_err(py_err),
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(PeltError::Internal(format!("{what} (this is a bug in Pelt; please report it)")).into_pyerr())
        }
    }
}

/// Number of worker threads Pelt uses (`PELT_THREADS`, default: all cores).
#[pyfunction]
fn thread_count() -> usize {
    pelt_core::threads::thread_count()
}

/// Sets the number of worker threads for later work (0: one per core), in `[0, 1024]`.
#[pyfunction]
fn set_thread_count(threads: i128) -> PyResult<()> {
    // Any int, so that a negative or huge count is named here rather than an OverflowError.
    let count = usize::try_from(threads)
        .map_err(|_| pelt_core::threads::thread_count_out_of_range(threads).into_pyerr())?;
    pelt_core::threads::set_thread_count(count).map_err(py_err)
}

/// The memory limit in bytes that bakes are checked against (see `pelt_core::memory`).
#[pyfunction]
fn memory_limit() -> u64 {
    pelt_core::memory::limit()
}

/// Sets the memory limit in bytes for later work (`None`: `PELT_MEMORY_LIMIT` or half of the
/// physical memory).
#[pyfunction]
#[pyo3(signature = (limit))]
fn set_memory_limit(limit: Option<f64>) -> PyResult<()> {
    // A float, so that a negative or huge value is named here rather than an OverflowError.
    let bytes = match limit {
        None => None,
        Some(b) if b.is_finite() && b >= 0.0 && b < u64::MAX as f64 => Some(b as u64),
        Some(b) => {
            let reason = format!(
                "must be a byte count of at least {} (or None), got {}",
                pelt_core::memory::MIN_LIMIT,
                Num(b)
            );
            return Err(pelt_core::PeltError::parameter("memory_limit", reason).into_pyerr());
        }
    };
    pelt_core::memory::set_limit(bytes).map_err(py_err)?;
    Ok(())
}

/// Physical memory in bytes (the container's limit when smaller), as the default limit sees it.
#[pyfunction]
fn physical_memory() -> u64 {
    pelt_core::memory::physical_memory()
}

/// Panics inside [`detached`] on purpose, so tests can check that no panic crosses into Python.
#[pyfunction]
fn _panic_for_test(py: Python<'_>, message: String) -> PyResult<()> {
    detached(py, move || -> pelt_core::Result<()> { panic!("{message}") })
}

/// The fur presets (their one home is `presets.json`, through [`pelt_core::presets::presets`]) as
/// `{name: {label, description, setting: value, ...}}`, in the add-on's order, ranges and colors
/// as lists.
fn presets(py: Python<'_>) -> PyResult<Bound<'_, pyo3::types::PyDict>> {
    let text = serde_json::to_string(pelt_core::presets::presets())
        .map_err(|e| pelt_core::PeltError::Internal(format!("presets: {e}")).into_pyerr())?;
    let list = py.import("json")?.call_method1("loads", (text,))?;
    let out = pyo3::types::PyDict::new(py);
    for item in list.try_iter()? {
        let preset = item?.cast_into::<pyo3::types::PyDict>()?;
        let name = preset
            .get_item("name")?
            .ok_or_else(|| pelt_core::PeltError::Internal("a preset without a name".into()))
            .map_err(py_err)?;
        preset.del_item("name")?;
        out.set_item(name, preset)?;
    }
    Ok(out)
}

/// The parameter sets' schemas ([`pelt_core::params`], the renderer's
/// [`pelt_render::RenderSettings::schema`]) as `{set: {"defaults": {...}, "ranges":
/// {name: {"min", "max", "min_open", "unit"}}}}`: each number's range stated once, which the
/// add-on's properties are tested against.
fn schema(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    let mut sets = pelt_core::pipeline::schemas();
    sets.push(pelt_render::RenderSettings::schema());
    let sets: serde_json::Map<String, serde_json::Value> = sets
        .into_iter()
        .map(|set| {
            let ranges: serde_json::Map<String, serde_json::Value> = set
                .ranges
                .iter()
                .map(|r| {
                    let range = serde_json::json!({
                        "min": r.min, "max": r.max, "min_open": r.min_open,
                        "min_field": r.min_field, "unit": r.unit,
                    });
                    (r.name.to_string(), range)
                })
                .collect();
            let value = serde_json::json!({"defaults": set.defaults, "ranges": ranges});
            (set.name.to_string(), value)
        })
        .collect();
    let text = serde_json::to_string(&sets)
        .map_err(|e| pelt_core::PeltError::Internal(format!("schema: {e}")).into_pyerr())?;
    py.import("json")?.call_method1("loads", (text,))
}

#[pymodule]
fn _pelt(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", pelt_core::VERSION)?;
    // The bake's stage names in order, for progress bars (one list, the pipeline's).
    m.add(
        "STAGES",
        pyo3::types::PyTuple::new(m.py(), pelt_core::pipeline::STAGES)?,
    )?;
    m.add("PRESETS", presets(m.py())?)?;
    m.add("SCHEMA", schema(m.py())?)?;
    errors::register(m)?;
    m.add_class::<mesh::PyFurMesh>()?;
    m.add_class::<volume::PyHairParams>()?;
    m.add_function(wrap_pyfunction!(volume::bake_volume_py, m)?)?;
    m.add_function(wrap_pyfunction!(export::pack_atlas_py, m)?)?;
    m.add_function(wrap_pyfunction!(export::save_png_py, m)?)?;
    m.add_function(wrap_pyfunction!(export::encode_png_py, m)?)?;
    m.add_function(wrap_pyfunction!(export::save_exr_py, m)?)?;
    m.add_function(wrap_pyfunction!(export::export_gltf_py, m)?)?;
    m.add_function(wrap_pyfunction!(export::write_texture_set_py, m)?)?;
    m.add_function(wrap_pyfunction!(export::write_asset_py, m)?)?;
    m.add_class::<lapped::PyPatches>()?;
    m.add_function(wrap_pyfunction!(lapped::build_patches, m)?)?;
    m.add_function(wrap_pyfunction!(thread_count, m)?)?;
    m.add_function(wrap_pyfunction!(set_thread_count, m)?)?;
    m.add_function(wrap_pyfunction!(memory_limit, m)?)?;
    m.add_function(wrap_pyfunction!(set_memory_limit, m)?)?;
    m.add_function(wrap_pyfunction!(physical_memory, m)?)?;
    m.add_function(wrap_pyfunction!(prt::bake_transfer, m)?)?;
    m.add_function(wrap_pyfunction!(prt::sh_project_equirect, m)?)?;
    m.add_function(wrap_pyfunction!(prt::sh_project_light, m)?)?;
    m.add_function(wrap_pyfunction!(prt::sh_rotate, m)?)?;
    m.add_class::<pipeline::PyPipeline>()?;
    m.add_class::<pipeline::PyFurAsset>()?;
    m.add_class::<render::PyPreview>()?;
    m.add_function(wrap_pyfunction!(reference::render_reference_py, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_for_test, m)?)?;
    Ok(())
}
