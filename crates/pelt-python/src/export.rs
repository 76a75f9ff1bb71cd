//! `pelt.pack_atlas` (shell layers laid out in one image, for Blender materials and engines
//! without texture arrays; see [`pelt_core::texture::atlas`]), `pelt.save_png`, `pelt.encode_png`,
//! `pelt.save_exr`, and the exports of baked assets: `pelt.export_gltf`,
//! `pelt.write_texture_set`, `pelt.write_asset` (see [`pelt_core::export`]).

use std::path::PathBuf;

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use super::detached;
use super::pipeline::PyFurAsset;
use crate::errors::{IntoPyErr, py_err};
use pelt_core::error::PeltError;
use pelt_core::export::{
    AssetOptions, ExportInput, ExrOptions, GltfMode, GltfOptions, Manifest, MaterialSlots, PngCompression,
    PngOptions, Skeleton, SkinBinding, TextureFormats, save_exr, save_glb, save_png, write_asset, write_png,
    write_texture_set,
};
use pelt_core::pipeline::FurAsset;
use pelt_core::texture::ImageRef;
use pelt_core::texture::atlas::{AtlasLayout, pack_atlas};

/// Packs ``layers`` (``[L, R, R, C]`` uint8, float16 or float32; C in 1..4) into a grid atlas of
/// ``ceil(sqrt(L))`` columns, layer 0 top left, row by row; returns ``(image [H, W, C], layout)``.
#[pyfunction(name = "pack_atlas")]
pub(super) fn pack_atlas_py<'py>(
    py: Python<'py>,
    layers: &Bound<'py, PyAny>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyDict>)> {
    if let Ok(a) = layers.extract::<PyReadonlyArrayDyn<'py, u8>>() {
        return pack_typed(py, &a);
    }
    if let Ok(a) = layers.extract::<PyReadonlyArrayDyn<'py, half::f16>>() {
        return pack_typed(py, &a);
    }
    if let Ok(a) = layers.extract::<PyReadonlyArrayDyn<'py, f32>>() {
        return pack_typed(py, &a);
    }
    Err(PeltError::parameter("layers", "must be a uint8, float16 or float32 numpy array").into_pyerr())
}

fn pack_typed<'py, T: numpy::Element + Copy + Default + Send + Sync>(
    py: Python<'py>,
    layers: &PyReadonlyArrayDyn<'py, T>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyDict>)> {
    let shape = layers.shape().to_vec();
    let [count, rows, cols, channels] = shape[..] else {
        return Err(
            PeltError::parameter("layers", format!("must be [L, R, R, C], got shape {shape:?}")).into_pyerr(),
        );
    };
    if rows != cols {
        return Err(
            PeltError::parameter("layers", format!("layers must be square, got {rows}x{cols}")).into_pyerr(),
        );
    }
    let data = contiguous(layers)?;
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

/// Writes ``image`` (``[H, W, C] uint8 or uint16``, C in 1..4, rows top to bottom, straight
/// alpha) as a PNG; ``srgb`` adds the sRGB chunk (color, not data).
#[pyfunction(name = "save_png")]
#[pyo3(signature = (path, image, *, srgb=true))]
pub(super) fn save_png_py(
    py: Python<'_>,
    path: PathBuf,
    image: &Bound<'_, PyAny>,
    srgb: bool,
) -> PyResult<()> {
    let options = PngOptions {
        srgb,
        ..PngOptions::default()
    };
    with_png_image(image, |image| detached(py, || image.save(&path, &options)))
}

/// ``image`` as PNG file bytes (for packing into a .blend without a file): as ``save_png``, with
/// the fast deflate setting.
#[pyfunction(name = "encode_png")]
#[pyo3(signature = (image, *, srgb=true))]
pub(super) fn encode_png_py<'py>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
    srgb: bool,
) -> PyResult<Bound<'py, PyBytes>> {
    let options = PngOptions {
        srgb,
        compression: PngCompression::Fast,
    };
    let bytes = with_png_image(image, |image| {
        detached(py, || {
            let mut bytes = Vec::new();
            image.write(&mut bytes, &options)?;
            Ok(bytes)
        })
    })?;
    Ok(PyBytes::new(py, &bytes))
}

/// An 8- or 16-bit image for the PNG writer.
enum PngImage<'a> {
    U8(ImageRef<'a, u8>),
    U16(ImageRef<'a, u16>),
}

impl PngImage<'_> {
    fn write(&self, out: &mut Vec<u8>, options: &PngOptions) -> pelt_core::Result<()> {
        match self {
            PngImage::U8(image) => write_png(out, image, options),
            PngImage::U16(image) => write_png(out, image, options),
        }
    }

    fn save(&self, path: &std::path::Path, options: &PngOptions) -> pelt_core::Result<()> {
        match self {
            PngImage::U8(image) => save_png(path, image, options),
            PngImage::U16(image) => save_png(path, image, options),
        }
    }
}

/// Calls `write` with `image` (a uint8 or uint16 `[H, W, C]` array) borrowed as a [`PngImage`].
fn with_png_image<R>(
    image: &Bound<'_, PyAny>,
    write: impl FnOnce(&PngImage<'_>) -> PyResult<R>,
) -> PyResult<R> {
    if let Ok(array) = image.extract::<PyReadonlyArrayDyn<'_, u16>>() {
        let (w, h, c) = image_shape(array.shape())?;
        return write(&PngImage::U16(
            ImageRef::new(w, h, c, contiguous(&array)?).map_err(py_err)?,
        ));
    }
    let array: PyReadonlyArrayDyn<'_, u8> = image
        .extract()
        .map_err(|_| PeltError::parameter("image", "must be a uint8 or uint16 numpy array").into_pyerr())?;
    let (w, h, c) = image_shape(array.shape())?;
    write(&PngImage::U8(
        ImageRef::new(w, h, c, contiguous(&array)?).map_err(py_err)?,
    ))
}

/// Writes ``image`` (``[H, W, C] float32 or float16``, C in 1..4) as a ZIP-compressed OpenEXR
/// with channels Y / Y A / R G B / R G B A.
#[pyfunction(name = "save_exr")]
pub(super) fn save_exr_py(py: Python<'_>, path: PathBuf, image: &Bound<'_, PyAny>) -> PyResult<()> {
    let options = ExrOptions::default();
    if let Ok(array) = image.extract::<PyReadonlyArrayDyn<'_, half::f16>>() {
        let (w, h, c) = image_shape(array.shape())?;
        let data = contiguous(&array)?;
        return detached(py, || save_exr(&path, &ImageRef::new(w, h, c, data)?, &options));
    }
    let array: PyReadonlyArrayDyn<'_, f32> = image.extract().map_err(|_| {
        PeltError::parameter("image", "must be a float32 or float16 numpy array").into_pyerr()
    })?;
    let (w, h, c) = image_shape(array.shape())?;
    let data = contiguous(&array)?;
    detached(py, || save_exr(&path, &ImageRef::new(w, h, c, data)?, &options))
}

/// `(width, height, channels)` of an `[H, W, C]` shape.
fn image_shape(shape: &[usize]) -> PyResult<(usize, usize, usize)> {
    match *shape {
        [h, w, c] => Ok((w, h, c)),
        _ => {
            Err(PeltError::parameter("image", format!("must be [H, W, C], got shape {shape:?}")).into_pyerr())
        }
    }
}

fn contiguous<'a, T: numpy::Element>(array: &'a PyReadonlyArrayDyn<'_, T>) -> PyResult<&'a [T]> {
    array
        .as_slice()
        .map_err(|_| PeltError::parameter("array", "must be C-contiguous").into_pyerr())
}

/// The assets and their names: one `FurAsset` or a sequence of them; `names` one string, a
/// sequence of strings, or `None` (`Object`, `Object.1`, …).
fn assets_and_names(
    asset: &Bound<'_, PyAny>,
    names: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<(String, FurAsset)>> {
    let assets: Vec<FurAsset> = match asset.cast::<PyFurAsset>() {
        Ok(one) => vec![one.get().inner.clone()],
        Err(_) => {
            let mut list = Vec::new();
            for item in asset.try_iter().map_err(|_| {
                PeltError::parameter("asset", "must be a FurAsset or a sequence of them").into_pyerr()
            })? {
                let item = item?;
                let one = item.cast::<PyFurAsset>().map_err(|_| {
                    PeltError::parameter("asset", "must be a FurAsset or a sequence of them").into_pyerr()
                })?;
                list.push(one.get().inner.clone());
            }
            list
        }
    };
    let names: Vec<String> = match names {
        None => (0..assets.len())
            .map(|i| {
                if i == 0 {
                    "Object".into()
                } else {
                    format!("Object.{i}")
                }
            })
            .collect(),
        Some(n) => match n.extract::<String>() {
            Ok(one) => vec![one],
            Err(_) => n.extract::<Vec<String>>().map_err(|_| {
                PeltError::parameter("name", "must be a string or a sequence of strings").into_pyerr()
            })?,
        },
    };
    if names.len() != assets.len() {
        return Err(PeltError::parameter(
            "name",
            format!("gives {} names for {} assets", names.len(), assets.len()),
        )
        .into_pyerr());
    }
    Ok(names.into_iter().zip(assets).collect())
}

/// The export inputs of named assets, with `shells` shells when given.
fn inputs(assets: &[(String, FurAsset)], shells: Option<usize>) -> Vec<ExportInput<'_>> {
    assets
        .iter()
        .map(|(name, asset)| ExportInput {
            shells,
            ..ExportInput::from_asset(name, asset)
        })
        .collect()
}

/// Texture containers from ``"png,ktx2"`` or ``["png", "ktx2"]``.
fn parse_formats(formats: &Bound<'_, PyAny>) -> PyResult<TextureFormats> {
    let list = match formats.extract::<String>() {
        Ok(text) => text,
        Err(_) => formats
            .extract::<Vec<String>>()
            .map_err(|_| {
                PeltError::parameter("formats", "must be a string or a sequence of strings").into_pyerr()
            })?
            .join(","),
    };
    TextureFormats::parse(&list).map_err(py_err)
}

/// The manifest as a Python object (through JSON).
fn manifest_object<'py>(py: Python<'py>, manifest: &Manifest) -> PyResult<Bound<'py, PyAny>> {
    let json = manifest.to_json().map_err(py_err)?;
    py.import("json")?.call_method1("loads", (json,))
}

/// Writes ``asset`` (a ``FurAsset`` or a sequence of them, one glTF node each, named by ``name``)
/// as a glTF binary: ``mode="engine"`` (base mesh, Pelt's attributes, atlases, stack description
/// in the ``PELT_shell_fur`` extension, fallback shells) or ``"geometry"`` (shells and fins as meshes). ``transform`` places each object
/// (4×4 row-major); ``skeletons`` (dicts of ``names``, ``parents``, ``rest``, ``animations``) and
/// ``skin`` (per object ``None`` or ``{"skeleton", "joints", "weights"}``) make skinned,
/// animated characters; ``materials`` (per object ``None`` or ``{"slots": [None | {"name",
/// "base_color", "metallic", "roughness"}], "triangle_slot": [T]}``) keeps the object's own
/// materials on its bald faces; ``animations`` (per object ``None``, a dict or a list of
/// ``{"name", "times": [T], "poses": [T, 4, 4]}``) moves an unskinned object's node. Returns per
/// object what the binding changed (``None`` when unskinned).
/// GIL released.
#[pyfunction(name = "export_gltf")]
#[pyo3(signature = (asset, path, *, mode="engine", name=None, fins=true, shells=None, transform=None, skin=None, skeletons=None, materials=None, animations=None))]
#[allow(clippy::too_many_arguments)]
pub(super) fn export_gltf_py<'py>(
    py: Python<'py>,
    asset: &Bound<'py, PyAny>,
    path: PathBuf,
    mode: &str,
    name: Option<&Bound<'py, PyAny>>,
    fins: bool,
    shells: Option<i128>,
    transform: Option<&Bound<'py, PyAny>>,
    skin: Option<&Bound<'py, PyAny>>,
    skeletons: Option<&Bound<'py, PyAny>>,
    materials: Option<&Bound<'py, PyAny>>,
    animations: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let shells: Option<usize> = super::ints::unsigned_opt("shells", shells)?;
    let mode = GltfMode::parse(mode).map_err(py_err)?;
    let assets = assets_and_names(asset, name)?;
    let transforms = super::rig::object_transforms(transform, assets.len())?;
    let skins = super::rig::object_skins(skin, assets.len())?;
    let materials = super::materials::object_materials(materials, assets.len())?;
    let animations = super::rig::object_animations(animations, assets.len())?;
    let skeletons: Vec<Skeleton> = match skeletons.filter(|s| !s.is_none()) {
        None => Vec::new(),
        Some(list) => super::rig::sequence(list, "skeletons")?
            .enumerate()
            .map(|(s, entry)| super::rig::skeleton(&entry?, &format!("skeletons[{s}]")))
            .collect::<PyResult<_>>()?,
    };
    let mut objects = inputs(&assets, shells);
    let per_object = transforms
        .into_iter()
        .zip(&skins)
        .zip(&materials)
        .zip(&animations);
    for (input, (((transform, skin), slots), animations)) in objects.iter_mut().zip(per_object) {
        input.transform = transform;
        input.animations = animations;
        input.skin = skin.as_ref().map(|s| SkinBinding {
            skeleton: s.skeleton,
            influences: s.influences,
            joints: &s.joints,
            weights: &s.weights,
        });
        input.materials = slots.as_ref().map(|m| MaterialSlots {
            slots: &m.slots,
            triangle_slot: &m.triangle_slot,
        });
    }
    let reports = detached(py, || {
        save_glb(&path, &objects, &skeletons, &GltfOptions { mode, fins })
    })?;
    let json = serde_json::to_string(&reports)
        .map_err(|e| PeltError::Internal(format!("report: {e}")).into_pyerr())?;
    py.import("json")?.call_method1("loads", (json,))
}

/// Writes the texture set of ``asset`` (one or a sequence, named by ``name``) into ``folder`` in
/// ``formats`` (``"png,ktx2,exr"`` or a list) with its ``pelt.json``; returns the manifest.
#[pyfunction(name = "write_texture_set")]
#[pyo3(signature = (asset, folder, *, formats=None, name=None))]
pub(super) fn write_texture_set_py<'py>(
    py: Python<'py>,
    asset: &Bound<'py, PyAny>,
    folder: PathBuf,
    formats: Option<&Bound<'py, PyAny>>,
    name: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let formats = formats.map_or(Ok(TextureFormats::default()), parse_formats)?;
    let assets = assets_and_names(asset, name)?;
    let manifest = detached(py, || write_texture_set(&inputs(&assets, None), &folder, formats))?;
    manifest_object(py, &manifest)
}

/// Writes the texture set, one GLB per mode in ``modes`` (``<glb_stem>_<mode>.glb``) and
/// ``pelt.json`` of ``asset`` (one or a sequence) into ``folder``; returns the manifest.
#[pyfunction(name = "write_asset")]
#[pyo3(signature = (asset, folder, *, formats=None, modes=None, name=None, fins=true, glb_stem=String::from("pelt")))]
#[allow(clippy::too_many_arguments)]
pub(super) fn write_asset_py<'py>(
    py: Python<'py>,
    asset: &Bound<'py, PyAny>,
    folder: PathBuf,
    formats: Option<&Bound<'py, PyAny>>,
    modes: Option<Vec<String>>,
    name: Option<&Bound<'py, PyAny>>,
    fins: bool,
    glb_stem: String,
) -> PyResult<Bound<'py, PyAny>> {
    let modes = match modes {
        Some(modes) => modes
            .iter()
            .map(|m| GltfMode::parse(m))
            .collect::<pelt_core::Result<_>>()
            .map_err(py_err)?,
        None => AssetOptions::default().modes,
    };
    let options = AssetOptions {
        formats: formats.map_or(Ok(TextureFormats::default()), parse_formats)?,
        modes,
        fins,
        glb_stem,
    };
    let assets = assets_and_names(asset, name)?;
    let manifest = detached(py, || write_asset(&inputs(&assets, None), &folder, &options))?;
    manifest_object(py, &manifest)
}
