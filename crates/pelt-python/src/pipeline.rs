//! `pelt.Pipeline` and `pelt.FurAsset`: the staged, cached bake of [`pelt_core::pipeline`].

use std::sync::Mutex;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use super::detached;
use super::lapped::PyPatches;
use super::mesh::PyFurMesh;
use super::progress::PyProgress;
use super::prt::{parse_phase, transfer_dict};
use super::volume::{PyHairParams, array, volume_dict};
use crate::errors::{IntoPyErr, py_err};
use pelt_core::error::PeltError;
use pelt_core::pipeline::{BakeKeywords, BakeParams, FurAsset, Pipeline, StageCallback};
use pelt_core::placement::StrandSpan;
use pelt_core::volume::VolumeParams;
use pelt_core::volume::coverage::CoverageMode;

/// A bake cache: keeps the last result of every stage, so a re-bake runs only what changed.
/// One per furred object. Thread-safe: a bake holds the cache for its whole run. Over a mesh
/// with colors the coat's colors count only as shading, so the painted colors show as painted.
#[pyclass(name = "Pipeline", module = "pelt", frozen)]
pub(super) struct PyPipeline {
    inner: Mutex<Pipeline>,
}

/// The result of a bake: mesh, patches, hair volume, optional transfer, and the stage report.
#[pyclass(name = "FurAsset", module = "pelt", frozen)]
pub(crate) struct PyFurAsset {
    pub(crate) inner: FurAsset,
}

#[pymethods]
impl PyPipeline {
    #[new]
    fn new() -> Self {
        PyPipeline {
            inner: Mutex::new(Pipeline::new()),
        }
    }

    /// Forgets every cached stage.
    fn clear(&self) {
        self.lock().clear();
    }

    /// Bakes `mesh` (GIL released), reusing stages whose inputs did not change; see the stub.
    #[pyo3(signature = (
        mesh, *, tile_size=1.0, seed=1, down=None, hair=None, layers=16, resolution=128,
        coverage="exact", fin_size=(512, 128), fur_depth=None, transfer=true, order=None,
        tolerance=pelt_core::prt::bands::DEFAULT_TOLERANCE, directions=256, phase="kajiya-kay",
        guard_hairs=false, guard_share=1.0, planes=0, progress=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn bake(
        &self,
        py: Python<'_>,
        mesh: &PyFurMesh,
        tile_size: f64,
        seed: i128,
        down: Option<(f32, f32, f32)>,
        hair: Option<PyRef<'_, PyHairParams>>,
        layers: i128,
        resolution: i128,
        coverage: &str,
        fin_size: (i128, i128),
        fur_depth: Option<f64>,
        transfer: bool,
        order: Option<i128>,
        tolerance: f64,
        directions: i128,
        phase: &str,
        guard_hairs: bool,
        guard_share: f64,
        planes: i128,
        progress: Option<Bound<'_, PyAny>>,
    ) -> PyResult<PyFurAsset> {
        #[rustfmt::skip]
        let params = bake_params(
            tile_size, seed, down, hair, layers, resolution, coverage, fin_size, fur_depth, transfer, order,
            tolerance, directions, phase, guard_hairs, guard_share, planes,
        )?;
        let reporter = PyProgress::new(progress);
        let mesh = mesh.inner.clone();
        let outcome = detached(py, || {
            let report = |stage: &str, f: f64| reporter.report_stage(stage, f);
            let callback: Option<StageCallback<'_>> = reporter.is_some().then_some(&report);
            self.lock().bake(mesh, &params, callback)
        });
        let inner = reporter.finish(outcome)?;
        Ok(PyFurAsset { inner })
    }

    /// Estimated peak memory in bytes of a bake with these arguments (those of `bake` without
    /// the mesh), after checking them all; see the stub.
    #[staticmethod]
    #[pyo3(signature = (
        *, tile_size=1.0, seed=1, down=None, hair=None, layers=16, resolution=128, coverage="exact",
        fin_size=(512, 128), fur_depth=None, transfer=true, order=None,
        tolerance=pelt_core::prt::bands::DEFAULT_TOLERANCE, directions=256, phase="kajiya-kay",
        guard_hairs=false, guard_share=1.0, planes=0
    ))]
    #[allow(clippy::too_many_arguments)]
    fn peak_bytes(
        tile_size: f64,
        seed: i128,
        down: Option<(f32, f32, f32)>,
        hair: Option<PyRef<'_, PyHairParams>>,
        layers: i128,
        resolution: i128,
        coverage: &str,
        fin_size: (i128, i128),
        fur_depth: Option<f64>,
        transfer: bool,
        order: Option<i128>,
        tolerance: f64,
        directions: i128,
        phase: &str,
        guard_hairs: bool,
        guard_share: f64,
        planes: i128,
    ) -> PyResult<f64> {
        #[rustfmt::skip]
        let params = bake_params(
            tile_size, seed, down, hair, layers, resolution, coverage, fin_size, fur_depth, transfer, order,
            tolerance, directions, phase, guard_hairs, guard_share, planes,
        )?;
        params.validate_ranges().map_err(py_err)?;
        Ok(params.peak_bytes())
    }

    fn __repr__(&self) -> String {
        "<pelt.Pipeline>".into()
    }
}

/// The bake parameters of `Pipeline.bake`'s keyword arguments.
#[allow(clippy::too_many_arguments)]
fn bake_params(
    tile_size: f64,
    seed: i128,
    down: Option<(f32, f32, f32)>,
    hair: Option<PyRef<'_, PyHairParams>>,
    layers: i128,
    resolution: i128,
    coverage: &str,
    fin_size: (i128, i128),
    fur_depth: Option<f64>,
    transfer: bool,
    order: Option<i128>,
    tolerance: f64,
    directions: i128,
    phase: &str,
    guard_hairs: bool,
    guard_share: f64,
    planes: i128,
) -> PyResult<BakeParams> {
    // Any Python int is taken and narrowed by name (an unnamed OverflowError otherwise).
    let seed: u64 = super::ints::unsigned("seed", seed)?;
    let layers: usize = super::ints::unsigned("layers", layers)?;
    let resolution: usize = super::ints::unsigned("resolution", resolution)?;
    let fin_size: (usize, usize) = super::ints::unsigned_pair("fin_size", fin_size)?;
    let order: Option<usize> = super::ints::unsigned_opt("order", order)?;
    let directions: usize = super::ints::unsigned("directions", directions)?;
    let planes: usize = super::ints::unsigned("planes", planes)?;
    let base = BakeParams {
        hair: hair.map(|h| h.inner.clone()).unwrap_or_default(),
        volume: VolumeParams {
            layers,
            resolution,
            coverage: coverage.parse::<CoverageMode>().map_err(py_err)?,
            fin_size: [fin_size.0, fin_size.1],
            guard_hairs,
            guard_share,
            ..VolumeParams::default()
        },
        ..BakeParams::default()
    };
    let keywords = BakeKeywords {
        fur_depth,
        transfer,
        order,
        tolerance,
        phase: parse_phase(phase)?,
        planes,
    };
    let mut params = keywords.apply(base);
    params.patches.tile_size = tile_size;
    params.patches.seed = seed;
    if let Some((x, y, z)) = down {
        params.patches.field.down = [x, y, z];
    }
    if let Some(choice) = &mut params.transfer {
        choice.params.directions = directions;
    }
    Ok(params)
}

impl PyPipeline {
    /// The cache; a bake that panicked left it in a valid state (each slot is replaced whole).
    fn lock(&self) -> std::sync::MutexGuard<'_, Pipeline> {
        self.inner.lock().unwrap_or_else(|e| e.into_inner())
    }
}

#[pymethods]
impl PyFurAsset {
    /// The mesh the bake read.
    #[getter]
    fn mesh(&self) -> PyFurMesh {
        PyFurMesh {
            inner: self.inner.mesh.clone(),
        }
    }

    /// The lapped patches (UVs in tile units, patch ids).
    #[getter]
    fn patches(&self) -> PyPatches {
        PyPatches {
            inner: self.inner.patches.clone(),
        }
    }

    /// The hair volume as `bake_volume` returns it (arrays copied out of the asset).
    #[getter]
    fn volume<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        volume_dict(py, (*self.inner.volume).clone())
    }

    /// The transfer as `bake_transfer` returns it, or `None` when the bake had none.
    #[getter]
    fn transfer<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(baked) = &self.inner.transfer else {
            return Ok(None);
        };
        let sidecar = serde_json::to_string_pretty(&baked.packed_u8.sidecar)
            .map_err(|e| PeltError::Internal(format!("sidecar: {e}")).into_pyerr())?;
        let d = transfer_dict(
            py,
            baked.transfer.clone(),
            baked.bands.as_ref(),
            baked.packed_f16.clone(),
            baked.packed_u8.clone(),
            sidecar,
        )?;
        d.set_item("depth_in_tiles", baked.depth_in_tiles)?;
        Ok(Some(d))
    }

    /// The guard hairs (a bake with `guard_hairs=True`), else `None`: `positions` `(P, 3)` and
    /// `radii` `(P,)` float32 of every strand point, object units, root first; `counts` `(S,)`
    /// uint32, the points of each strand; `root_colors` and `tip_colors` `(S, 3)` float32, linear;
    /// `root_triangles` `(S,)` uint32 and `root_weights` `(S, 3)` float32, where each root stands.
    #[getter]
    fn guard_hairs<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(placed) = &self.inner.guard_hairs else {
            return Ok(None);
        };
        let (p, s) = (placed.points.len(), placed.spans.len());
        let d = PyDict::new(py);
        let xyz: Vec<f32> = placed.points.iter().flat_map(|q| [q[0], q[1], q[2]]).collect();
        d.set_item("positions", array(py, xyz, &[p, 3])?)?;
        d.set_item(
            "radii",
            array(py, placed.points.iter().map(|q| q[3]).collect(), &[p])?,
        )?;
        d.set_item(
            "counts",
            array(py, placed.spans.iter().map(|k| k.count).collect(), &[s])?,
        )?;
        let colors =
            |f: fn(&StrandSpan) -> [f32; 3]| -> Vec<f32> { placed.spans.iter().flat_map(f).collect() };
        d.set_item(
            "root_colors",
            array(py, colors(|k| k.root_color.into()), &[s, 3])?,
        )?;
        d.set_item("tip_colors", array(py, colors(|k| k.tip_color.into()), &[s, 3])?)?;
        let triangles = placed.spans.iter().map(|k| k.triangle).collect();
        d.set_item("root_triangles", array(py, triangles, &[s])?)?;
        d.set_item("root_weights", array(py, colors(|k| k.weights), &[s, 3])?)?;
        Ok(Some(d))
    }

    /// The virtual planes' slices (a bake with `planes`), else `None`: `planes` (N per axis),
    /// `tilt` (their lean), `slices` `[2N, height, width, 4]` uint8 (straight, sRGB color; the
    /// first N across u, the rest across v).
    #[getter]
    fn planes<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(p) = &self.inner.planes else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("planes", p.planes)?;
        d.set_item("tilt", (p.tilt[0], p.tilt[1]))?;
        let [w, h] = p.size;
        d.set_item("slices", array(py, p.rgba.clone(), &[2 * p.planes, h, w, 4])?)?;
        Ok(Some(d))
    }

    /// Per stage, in order: `{"stage", "ran", "seconds", "summary"}`.
    #[getter]
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for stage in &self.inner.report {
            let d = PyDict::new(py);
            d.set_item("stage", &stage.stage)?;
            d.set_item("ran", stage.ran)?;
            d.set_item("seconds", stage.seconds)?;
            d.set_item("summary", &stage.summary)?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// Object-space width of one texture tile.
    #[getter]
    fn tile_size(&self) -> f64 {
        self.inner.params.patches.tile_size
    }

    /// Fur height at length 1, object units.
    #[getter]
    fn fur_depth(&self) -> f64 {
        self.inner.params.fur_depth()
    }

    /// Shell layers kept (after the trim), including the skin.
    #[getter]
    fn layers(&self) -> usize {
        self.inner.volume.layers
    }

    /// Shell texture side.
    #[getter]
    fn resolution(&self) -> usize {
        self.inner.volume.resolution
    }

    fn __repr__(&self) -> String {
        let v = &self.inner.volume;
        format!(
            "<pelt.FurAsset {} triangles, {} patches, {} layers of {}², transfer {}>",
            self.inner.mesh.face_count(),
            self.inner.patches.quality.patch_count,
            v.layers,
            v.resolution,
            self.inner
                .transfer
                .as_ref()
                .map_or("none".into(), |t| format!("order {}", t.transfer.order))
        )
    }
}
