//! `pelt.Preview`: the wgpu preview ([`pelt_render`]) holding the device and one scene uploaded
//! from a `pelt.FurAsset`. Matrices arrive in the math convention with an OpenGL projection (as
//! Blender gives them) and are remapped by [`Camera::from_gl`]; frames render with the GIL
//! released.

use std::sync::Mutex;

use half::f16;
use numpy::{PyArray1, PyArrayDyn, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use super::arrays::{flat, float_array, float_ndarray, rows};
use super::detached;
use super::pipeline::PyFurAsset;
use crate::errors::{IntoPyErr, py_err};
use pelt_core::error::PeltError;
use pelt_core::prt::pack::PackedF16;
use pelt_render::{
    AdapterChoice, Camera, FrameInfo, FurScene, KajiyaKay, LightModel, Lighting, Occluders, Prt,
    RenderSettings, Renderer, ShellMethod, StrandOrder, check_environment,
};

/// The preview renderer of one baked asset.
#[pyclass(name = "Preview", module = "pelt", frozen)]
pub(super) struct PyPreview {
    renderer: Renderer,
    /// Frames read the scene, updates write it.
    scene: Mutex<FurScene>,
    last_frame: Mutex<Option<FrameInfo>>,
}

fn parse_adapter(adapter: &str) -> PyResult<AdapterChoice> {
    match adapter {
        "auto" => Ok(AdapterChoice::PreferHardware),
        "cpu" => Ok(AdapterChoice::Cpu),
        "gpu" => Ok(AdapterChoice::Gpu),
        other => Err(PeltError::parameter(
            "adapter",
            format!("must be \"auto\", \"cpu\" or \"gpu\", got {other:?}"),
        )
        .into_pyerr()),
    }
}

/// A 4 × 4 matrix given as rows (numpy or nested sequences).
pub(super) fn matrix(obj: &Bound<'_, PyAny>, name: &'static str) -> PyResult<[[f32; 4]; 4]> {
    let (array, _) = float_ndarray(obj, name, "[4, 4]", |s| s == [4, 4])?;
    let values = flat(&array)?;
    Ok(std::array::from_fn(|r| {
        std::array::from_fn(|c| values[4 * r + c])
    }))
}

/// An image side, checked into `u32` (the renderer checks the range).
fn side(value: i64, name: &str) -> PyResult<u32> {
    u32::try_from(value).map_err(|_| {
        PeltError::parameter(name, format!("must be a positive number of pixels, got {value}")).into_pyerr()
    })
}

fn triple(value: &Bound<'_, PyAny>, name: &str) -> PyResult<[f32; 3]> {
    value
        .extract::<[f32; 3]>()
        .map_err(|_| PeltError::parameter(name, "must be three numbers").into_pyerr())
}

fn number(value: &Bound<'_, PyAny>, name: &str) -> PyResult<f32> {
    value
        .extract::<f32>()
        .map_err(|_| PeltError::parameter(name, "must be a number").into_pyerr())
}

/// The occluders' depths `[height, width]` (window depth in `[0, 1]`, rows top first); the
/// renderer checks the values.
fn occluder_depth(obj: &Bound<'_, PyAny>, height: usize, width: usize) -> PyResult<Vec<f32>> {
    let (array, shape) = float_ndarray(obj, "occluders", "[height, width]", |s| s.len() == 2)?;
    if shape != [height, width] {
        return Err(PeltError::parameter(
            "occluders",
            format!("must be [height, width] = [{height}, {width}] (the frame's), got {shape:?}"),
        )
        .into_pyerr());
    }
    Ok(flat(&array)?.to_vec())
}

/// The lighting of a frame: `None` (PRT when the scene has a transfer, else Kajiya–Kay), a model
/// name, or a dict of fields over that model's defaults.
fn parse_lighting(obj: Option<&Bound<'_, PyAny>>, has_transfer: bool) -> PyResult<Lighting> {
    let model_of = |name: &str| -> PyResult<LightModel> {
        match name {
            "kajiya-kay" => Ok(LightModel::KajiyaKay(KajiyaKay::default())),
            "prt" => Ok(LightModel::Prt(Prt::default())),
            other => Err(PeltError::parameter(
                "lighting.model",
                format!("must be \"kajiya-kay\" or \"prt\", got {other:?}"),
            )
            .into_pyerr()),
        }
    };
    let default_model = if has_transfer { "prt" } else { "kajiya-kay" };
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(Lighting {
            model: model_of(default_model)?,
            ..Lighting::default()
        });
    };
    if let Ok(name) = obj.cast::<PyString>() {
        return Ok(Lighting {
            model: model_of(&name.to_cow()?)?,
            ..Lighting::default()
        });
    }
    let dict = obj.cast::<PyDict>().map_err(|_| {
        PeltError::parameter("lighting", "must be None, \"kajiya-kay\", \"prt\" or a dict").into_pyerr()
    })?;
    let model = match dict.get_item("model")? {
        Some(m) => m
            .extract::<String>()
            .map_err(|_| PeltError::parameter("lighting.model", "must be a string").into_pyerr())?,
        None => default_model.to_string(),
    };
    let mut lighting = Lighting {
        model: model_of(&model)?,
        ..Lighting::default()
    };
    for (key, value) in dict.iter() {
        let key: String = key
            .extract()
            .map_err(|_| PeltError::parameter("lighting", "keys must be strings").into_pyerr())?;
        let name = format!("lighting.{key}");
        match (key.as_str(), &mut lighting.model) {
            ("model", _) => {}
            ("direction", _) => lighting.direction = triple(&value, &name)?,
            ("color", _) => lighting.color = triple(&value, &name)?,
            ("self_shadow", _) => lighting.self_shadow = number(&value, &name)?,
            ("ambient", LightModel::KajiyaKay(kk)) => kk.ambient = triple(&value, &name)?,
            ("ambient_gradient", LightModel::KajiyaKay(kk)) => {
                let (array, _) =
                    float_ndarray(&value, "lighting.ambient_gradient", "[3, 3]", |s| s == [3, 3])?;
                let rows = flat(&array)?.as_chunks::<3>().0.to_vec();
                kk.ambient_gradient = [rows[0], rows[1], rows[2]];
            }
            ("environment", LightModel::KajiyaKay(kk)) => {
                let (array, _) = float_ndarray(&value, "lighting.environment", "[n², 3]", |s| {
                    s.len() == 2 && s[0] >= 1 && s[1] == 3
                })?;
                let sh = flat(&array)?.as_chunks::<3>().0.to_vec();
                check_environment("lighting.environment", &sh).map_err(py_err)?;
                *kk = kk.under_environment(&sh);
            }
            ("diffuse", LightModel::KajiyaKay(kk)) => kk.diffuse = number(&value, &name)?,
            ("specular", LightModel::KajiyaKay(kk)) => kk.specular = number(&value, &name)?,
            ("diffuse_power", LightModel::KajiyaKay(kk)) => kk.diffuse_power = number(&value, &name)?,
            ("specular_power", LightModel::KajiyaKay(kk)) => kk.specular_power = number(&value, &name)?,
            ("reflect", LightModel::KajiyaKay(kk)) => kk.reflect = number(&value, &name)?,
            ("transmit", LightModel::KajiyaKay(kk)) => kk.transmit = number(&value, &name)?,
            ("light_radius", LightModel::Prt(prt)) => prt.light_radius = number(&value, &name)?,
            ("environment", LightModel::Prt(prt)) => {
                let (array, _) = float_ndarray(&value, "lighting.environment", "[n², 3]", |s| {
                    s.len() == 2 && s[1] == 3
                })?;
                prt.environment = flat(&array)?.as_chunks::<3>().0.to_vec();
            }
            _ => {
                return Err(
                    PeltError::parameter(name, format!("is not a setting of the {model} lighting"))
                        .into_pyerr(),
                );
            }
        }
    }
    Ok(lighting)
}

/// A frame's report as a dict.
fn frame_dict<'py>(py: Python<'py>, info: &FrameInfo) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("shells", info.shells)?;
    d.set_item("level", info.level)?;
    d.set_item("blend", info.blend)?;
    d.set_item("target_shells", info.target_shells)?;
    d.set_item("radius_pixels", info.radius_pixels)?;
    d.set_item("fur_pixels", info.fur_pixels)?;
    d.set_item("mesh_level", info.mesh_level)?;
    d.set_item("triangles", info.triangles)?;
    Ok(d)
}

/// Reverses the order of `values`' rows of `row` values (top first ↔ bottom first).
fn bottom_up(values: &mut [f32], row: usize) {
    let rows = values.len() / row.max(1);
    for y in 0..rows / 2 {
        let (top, bottom) = values.split_at_mut((rows - 1 - y) * row);
        top[y * row..(y + 1) * row].swap_with_slice(&mut bottom[..row]);
    }
}

/// The packed float16 transfer of a `FurAsset` or of a `bake_transfer` dict.
fn packed_transfer(obj: &Bound<'_, PyAny>) -> PyResult<PackedF16> {
    if let Ok(asset) = obj.cast::<PyFurAsset>() {
        return asset
            .get()
            .inner
            .transfer
            .as_ref()
            .map(|t| t.packed_f16.clone())
            .ok_or_else(|| {
                PeltError::parameter("transfer", "the asset was baked without a transfer").into_pyerr()
            });
    }
    let array = obj.get_item("packed_f16").map_err(|_| {
        PeltError::parameter("transfer", "must be a FurAsset or a dict with \"packed_f16\"").into_pyerr()
    })?;
    let py = obj.py();
    let numpy = py.import("numpy")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", numpy.getattr("float16")?)?;
    let array = numpy
        .call_method("ascontiguousarray", (array,), Some(&kwargs))
        .map_err(|e| {
            PeltError::parameter("transfer.packed_f16", format!("must be a float16 array ({e})")).into_pyerr()
        })?
        .cast_into::<PyUntypedArray>()?;
    let shape = array.shape().to_vec();
    if shape.len() != 5 || shape[4] != 4 || shape[2] != shape[3] {
        return Err(PeltError::parameter(
            "transfer.packed_f16",
            format!("must have shape [textures, layers, R, R, 4], got {shape:?}"),
        )
        .into_pyerr());
    }
    let typed = array.cast_into::<PyArrayDyn<f16>>()?;
    let texels = typed.readonly().as_slice()?.to_vec();
    Ok(PackedF16 {
        textures: shape[0],
        layers: shape[1],
        resolution: shape[2],
        texels,
    })
}

#[pymethods]
impl PyPreview {
    /// Opens a device and uploads `asset` (with its transfer, when it has one); see the stub.
    #[new]
    #[pyo3(signature = (asset, *, adapter="auto"))]
    fn new(py: Python<'_>, asset: &PyFurAsset, adapter: &str) -> PyResult<Self> {
        let choice = parse_adapter(adapter)?;
        let asset = asset.inner.clone();
        detached(py, move || {
            let renderer = Renderer::new(choice)?;
            let scene = FurScene::from_asset(&renderer, &asset)?;
            Ok(PyPreview {
                renderer,
                scene: Mutex::new(scene),
                last_frame: Mutex::new(None),
            })
        })
    }

    /// Renders one frame (GIL released); `[height, width, 4]` uint8 sRGB, or float32 linear with
    /// `linear=True`, straight alpha, top row first; `texture=True` gives float32 (bytes over
    /// 255) bottom row first. See the stub for the arguments.
    #[pyo3(signature = (
        view_matrix, projection_matrix, width, height, *, lighting=None, shells=None, fins=true,
        body_shadow=true, lod=false, linear=false, texture=false,
        background=(0.0, 0.0, 0.0, 0.0), min_shells=4, max_shells=64, shells_per_pixel=1.0,
        shell_method="instanced", mesh_error=1.0, guard_hairs=true, strand_order="stochastic",
        strand_bands=4, strand_pixels=1.0, plane_loop_limit=16, occluders=None, occluder_bias=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        view_matrix: &Bound<'py, PyAny>,
        projection_matrix: &Bound<'py, PyAny>,
        width: i64,
        height: i64,
        lighting: Option<&Bound<'py, PyAny>>,
        shells: Option<i128>,
        fins: bool,
        body_shadow: bool,
        lod: bool,
        linear: bool,
        texture: bool,
        background: (f32, f32, f32, f32),
        min_shells: i128,
        max_shells: i128,
        shells_per_pixel: f32,
        shell_method: &str,
        mesh_error: f32,
        guard_hairs: bool,
        strand_order: &str,
        strand_bands: i128,
        strand_pixels: f32,
        plane_loop_limit: i128,
        occluders: Option<&Bound<'py, PyAny>>,
        occluder_bias: Option<f32>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let plane_loop_limit: u32 = super::ints::unsigned("plane_loop_limit", plane_loop_limit)?;
        let strand_bands: u32 = super::ints::unsigned("strand_bands", strand_bands)?;
        let strand_order = StrandOrder::from_name(strand_order, strand_bands).map_err(py_err)?;
        let shells: Option<u32> = super::ints::unsigned_opt("shells", shells)?;
        let min_shells: u32 = super::ints::unsigned("min_shells", min_shells)?;
        let max_shells: u32 = super::ints::unsigned("max_shells", max_shells)?;
        let shell_method = ShellMethod::from_name(shell_method).map_err(py_err)?;
        let camera = Camera::from_gl(
            matrix(view_matrix, "view_matrix")?,
            matrix(projection_matrix, "projection_matrix")?,
            side(width, "width")?,
            side(height, "height")?,
        );
        let (has_transfer, fur_depth) = {
            let scene = self.lock_scene();
            (scene.transfer_order().is_some(), scene.fur_depth())
        };
        let lighting = parse_lighting(lighting, has_transfer)?;
        let settings = RenderSettings {
            shell_count: shells,
            lod,
            shells_per_pixel,
            min_shells,
            max_shells,
            fins,
            body_shadow,
            shell_method,
            mesh_error,
            background: [background.0, background.1, background.2, background.3],
            guard_hairs,
            strand_order,
            strand_pixels,
            plane_loop_limit,
            ..RenderSettings::default()
        };
        let shape = [camera.height as usize, camera.width as usize, 4];
        let occluders = match occluders.filter(|o| !o.is_none()) {
            None => None,
            Some(depth) => Some(Occluders {
                depth: occluder_depth(depth, shape[0], shape[1])?,
                // Three fur heights: the fur's own shells drawn opaque in the other picture
                // stay behind it where the surface faces the view within about 60°.
                bias: occluder_bias.unwrap_or(3.0 * fur_depth),
            }),
        };
        let (info, pixels) = detached(py, || {
            let scene = self.lock_scene();
            let info = self.renderer.frame_info(&scene, &camera, &settings)?;
            let (r, o) = (&self.renderer, occluders.as_ref());
            let pixels = if linear {
                let mut floats = r
                    .render_linear_over(&scene, &camera, &lighting, &settings, o)?
                    .pixels;
                if texture {
                    bottom_up(&mut floats, shape[1] * 4);
                }
                Err(floats)
            } else {
                let image = r.render_over(&scene, &camera, &lighting, &settings, o)?;
                if texture {
                    Err(image.texture_floats())
                } else {
                    Ok(image.pixels)
                }
            };
            Ok((info, pixels))
        })?;
        *self.last_frame.lock().unwrap_or_else(|e| e.into_inner()) = Some(info);
        Ok(match pixels {
            Ok(bytes) => PyArray1::from_vec(py, bytes).reshape(shape)?.into_any(),
            Err(floats) => PyArray1::from_vec(py, floats).reshape(shape)?.into_any(),
        })
    }

    /// Rewrites the per-vertex colors (`[V, 4]` or `[V, 3]`, linear), lengths (`[V]`) and/or
    /// comb vectors (`[V, 3]`) in place; nothing else is uploaded. See the stub.
    #[pyo3(signature = (*, color=None, length=None, comb=None))]
    fn update(
        &self,
        py: Python<'_>,
        color: Option<&Bound<'_, PyAny>>,
        length: Option<&Bound<'_, PyAny>>,
        comb: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let color: Option<Vec<[f32; 4]>> = match color {
            None => None,
            Some(c) => {
                let (array, shape) = float_ndarray(c, "color", "[V, 4] or [V, 3]", |s| {
                    s.len() == 2 && (s[1] == 3 || s[1] == 4)
                })?;
                let values = flat(&array)?;
                Some(if shape[1] == 4 {
                    values.as_chunks::<4>().0.to_vec()
                } else {
                    values
                        .as_chunks::<3>()
                        .0
                        .iter()
                        .map(|&[r, g, b]| [r, g, b, 1.0])
                        .collect()
                })
            }
        };
        let length: Option<Vec<f32>> = match length {
            None => None,
            Some(l) => {
                let (array, _) = float_ndarray(l, "length", "[V]", |s| s.len() == 1)?;
                Some(flat(&array)?.to_vec())
            }
        };
        let comb = comb.map(|c| float_array(c, "comb", Some(3))).transpose()?;
        let comb = comb.as_ref().map(rows::<f32, 3>).transpose()?;
        detached(py, || {
            let mut scene = self.lock_scene();
            // Checked before anything is written, so a bad comb leaves the colors as they were.
            if let Some(c) = comb {
                scene.check_comb(c)?;
            }
            scene.update_attributes(color.as_deref(), length.as_deref())?;
            match comb {
                Some(c) => scene.update_comb(c),
                None => Ok(()),
            }
        })
    }

    /// Poses the preview: positions `[V, 3]` (object space, the bake's vertices and triangles)
    /// and optional normals `[V, 3]`; only the vertex buffers are rewritten. See the stub.
    #[pyo3(signature = (positions, normals=None))]
    fn deform(
        &self,
        py: Python<'_>,
        positions: &Bound<'_, PyAny>,
        normals: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let positions = float_array(positions, "positions", Some(3))?;
        let normals = normals.map(|n| float_array(n, "normals", Some(3))).transpose()?;
        let positions = rows::<f32, 3>(&positions)?;
        let normals = normals.as_ref().map(rows::<f32, 3>).transpose()?;
        detached(py, || self.lock_scene().deform(positions, normals))
    }

    /// Whether a repaint left the coarser geometric levels undrawn. See the stub.
    #[getter]
    fn levels_dropped(&self) -> bool {
        self.lock_scene().levels_dropped()
    }

    /// Simplifies the mesh again under the current colors and lengths (GIL released); whether it
    /// did. See the stub.
    fn remake_levels(&self, py: Python<'_>) -> PyResult<bool> {
        detached(py, || self.lock_scene().remake_levels(&self.renderer))
    }

    /// Replaces the PRT transfer textures: a `FurAsset`'s or a `bake_transfer` result's. A
    /// transfer from another bake (other layers or resolution) raises `InvalidParameterError`
    /// and leaves the preview as it was.
    fn set_transfer(&self, py: Python<'_>, transfer: &Bound<'_, PyAny>) -> PyResult<()> {
        let packed = packed_transfer(transfer)?;
        detached(py, || self.lock_scene().set_transfer(&self.renderer, &packed))
    }

    /// Guard hairs drawn as strands (the asset's, 0 without).
    #[getter]
    fn guard_strands(&self) -> usize {
        self.lock_scene().guard_strand_count()
    }

    /// The adapter: `{"name", "backend", "device_type"}`.
    #[getter]
    fn adapter<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let a = self.renderer.adapter();
        let d = PyDict::new(py);
        d.set_item("name", &a.name)?;
        d.set_item("backend", &a.backend)?;
        d.set_item("device_type", &a.device_type)?;
        Ok(d)
    }

    /// Bytes sent to the GPU so far: `{"texture_bytes", "geometry_bytes", "attribute_bytes",
    /// "transfer_bytes", "pose_bytes"}`.
    #[getter]
    fn uploads<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let u = self.lock_scene().uploads();
        let d = PyDict::new(py);
        d.set_item("texture_bytes", u.texture_bytes)?;
        d.set_item("geometry_bytes", u.geometry_bytes)?;
        d.set_item("attribute_bytes", u.attribute_bytes)?;
        d.set_item("transfer_bytes", u.transfer_bytes)?;
        d.set_item("pose_bytes", u.pose_bytes)?;
        Ok(d)
    }

    /// The fur depth in object units that frames draw with: the asset's at first. See the stub.
    #[getter]
    fn fur_depth(&self) -> f32 {
        self.lock_scene().fur_depth()
    }

    /// Sets the fur depth without a re-upload; a NaN, negative or too large value raises
    /// `InvalidParameterError` naming `fur_depth` and keeps the one set.
    #[setter]
    fn set_fur_depth(&self, py: Python<'_>, fur_depth: f32) -> PyResult<()> {
        detached(py, || self.lock_scene().set_fur_depth(fur_depth))
    }

    /// SH order of the scene's transfer, or `None`.
    #[getter]
    fn transfer_order(&self) -> Option<usize> {
        self.lock_scene().transfer_order()
    }

    /// What the last successful frame drew: `{"shells", "level", "blend", "target_shells",
    /// "radius_pixels", "fur_pixels"}`, or `None` before the first.
    #[getter]
    fn last_frame<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let info = *self.last_frame.lock().unwrap_or_else(|e| e.into_inner());
        info.map(|i| frame_dict(py, &i)).transpose()
    }

    fn __repr__(&self) -> String {
        let a = self.renderer.adapter();
        format!("<pelt.Preview on {} ({})>", a.name, a.backend)
    }
}

impl PyPreview {
    /// The scene; a frame that panicked left it valid (frames only read it).
    fn lock_scene(&self) -> std::sync::MutexGuard<'_, FurScene> {
        self.scene.lock().unwrap_or_else(|e| e.into_inner())
    }
}
