//! `pelt.render_reference`: a ground-truth image of a baked asset ([`pelt_core::reference`]) with the
//! same camera matrices as `Preview.render`, of its strands or (`mode="volume"`) its density
//! volume, the GIL released while the scene is built and traced.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use super::arrays::{flat, float_ndarray};
use super::detached;
use super::pipeline::PyFurAsset;
use super::progress::PyProgress;
use super::render::matrix;
use crate::errors::{IntoPyErr, py_err};
use pelt_core::camera::Camera;
use pelt_core::error::PeltError;
use pelt_core::hair::grow_strands;
use pelt_core::reference::{
    FurGeometry, ReferenceLight, ReferenceScene, ReferenceSettings, VolumeScene, render_reference,
    render_volume_reference,
};

fn triple(item: &Bound<'_, PyDict>, key: &str, name: &str, default: Option<[f32; 3]>) -> PyResult<[f32; 3]> {
    match item.get_item(key)? {
        Some(v) => v
            .extract::<[f32; 3]>()
            .map_err(|_| PeltError::parameter(format!("{name}.{key}"), "must be three numbers").into_pyerr()),
        None => {
            default.ok_or_else(|| PeltError::parameter(format!("{name}.{key}"), "is missing").into_pyerr())
        }
    }
}

/// `lights`: a list of dicts, `{"type": "sun", "direction": (x, y, z), "strength": E, "color":
/// (r, g, b)}` or `{"type": "environment", "sh": [[r, g, b], ...]}`.
fn parse_lights(lights: Option<&Bound<'_, PyList>>) -> PyResult<Vec<ReferenceLight>> {
    let Some(lights) = lights else {
        return Ok(vec![ReferenceLight::Sun {
            direction: [0.4, -0.5, 0.75],
            strength: std::f32::consts::PI,
            color: [1.0; 3],
        }]);
    };
    lights
        .iter()
        .enumerate()
        .map(|(i, item)| {
            let name = format!("lights[{i}]");
            let item = item
                .cast::<PyDict>()
                .map_err(|_| PeltError::parameter(&name, "must be a dict").into_pyerr())?;
            let kind: String = item
                .get_item("type")?
                .ok_or_else(|| PeltError::parameter(format!("{name}.type"), "is missing"))
                .map_err(py_err)?
                .extract()
                .map_err(|_| PeltError::parameter(format!("{name}.type"), "must be a string").into_pyerr())?;
            match kind.as_str() {
                "sun" => Ok(ReferenceLight::Sun {
                    direction: triple(item, "direction", &name, None)?,
                    strength: match item.get_item("strength")? {
                        Some(v) => v.extract().map_err(|_| {
                            PeltError::parameter(format!("{name}.strength"), "must be a number").into_pyerr()
                        })?,
                        None => 1.0,
                    },
                    color: triple(item, "color", &name, Some([1.0; 3]))?,
                }),
                "environment" => {
                    let sh = item
                        .get_item("sh")?
                        .ok_or_else(|| PeltError::parameter(format!("{name}.sh"), "is missing"))
                        .map_err(py_err)?;
                    let (array, shape) = float_ndarray(&sh, "sh", "[n², 3]", |s| s.len() == 2 && s[1] == 3)?;
                    let values = flat(&array)?;
                    Ok(ReferenceLight::Environment {
                        sh: (0..shape[0])
                            .map(|k| [values[3 * k], values[3 * k + 1], values[3 * k + 2]])
                            .collect(),
                    })
                }
                other => Err(PeltError::parameter(
                    format!("{name}.type"),
                    format!("must be \"sun\" or \"environment\", got {other:?}"),
                )
                .into_pyerr()),
            }
        })
        .collect()
}

/// Renders the reference image of `asset`; see the stub.
#[pyfunction]
#[pyo3(name = "render_reference", signature = (
    asset, view_matrix, projection_matrix, width, height, *, lights=None, samples=16,
    max_samples=1024, target_error=0.01, seed=0, shadows=true, mode="strands", progress=None
))]
#[allow(clippy::too_many_arguments)]
pub(super) fn render_reference_py<'py>(
    py: Python<'py>,
    asset: &PyFurAsset,
    view_matrix: &Bound<'py, PyAny>,
    projection_matrix: &Bound<'py, PyAny>,
    width: i128,
    height: i128,
    lights: Option<&Bound<'py, PyList>>,
    samples: i128,
    max_samples: i128,
    target_error: f64,
    seed: i128,
    shadows: bool,
    mode: &str,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyDict>)> {
    let width: u32 = super::ints::unsigned("width", width)?;
    let height: u32 = super::ints::unsigned("height", height)?;
    let samples: u32 = super::ints::unsigned("samples", samples)?;
    let max_samples: u32 = super::ints::unsigned("max_samples", max_samples)?;
    let seed: u64 = super::ints::unsigned("seed", seed)?;
    let volume_mode = match mode {
        "strands" => false,
        "volume" => true,
        other => {
            return Err(PeltError::parameter(
                "mode",
                format!("must be \"strands\" or \"volume\", got {other:?}"),
            )
            .into_pyerr());
        }
    };
    let camera = Camera::from_gl(
        matrix(view_matrix, "view_matrix")?,
        matrix(projection_matrix, "projection_matrix")?,
        width,
        height,
    );
    let lights = parse_lights(lights)?;
    let settings = ReferenceSettings {
        seed,
        min_samples: samples,
        max_samples: max_samples.max(samples),
        target_error,
        shadows,
        ..ReferenceSettings::default()
    };
    settings.validate().map_err(py_err)?;
    let asset = asset.inner.clone();
    let reporter = PyProgress::new(progress);
    let report = |f: f64| reporter.report(f);
    let callback: Option<pelt_core::progress::ProgressCallback<'_>> = reporter.is_some().then_some(&report);
    let result = detached(py, || {
        let strands = grow_strands(&asset.params.grown_hair(&asset.mesh))?;
        let fur_depth = asset.params.fur_depth();
        if volume_mode {
            let scene =
                VolumeScene::from_bake(&asset.mesh, &asset.patches, &asset.volume, &strands, fur_depth)?;
            return render_volume_reference(&scene, &camera, &lights, &settings, callback);
        }
        let geometry = FurGeometry::from_bake(&asset.mesh, &asset.patches, &strands, fur_depth)?;
        let scene = ReferenceScene::new(geometry)?;
        render_reference(&scene, &camera, &lights, &settings, callback)
    });
    let image = reporter.finish(result)?;
    let info = PyDict::new(py);
    info.set_item("samples", image.samples)?;
    info.set_item("relative_error", image.relative_error)?;
    info.set_item("pixel_error", image.pixel_error)?;
    info.set_item("seconds", image.seconds)?;
    let shape = [image.height as usize, image.width as usize, 4];
    let values: Vec<f32> = image.pixels.into_iter().flatten().collect();
    let array = PyArray1::from_vec(py, values).reshape(shape)?.into_any();
    Ok((array, info))
}
