//! `pelt.build_patches` and `pelt.Patches`: the Python face of [`pelt_core::lapped`].

use std::sync::Arc;

use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::detached;
use super::mesh::{PyFurMesh, to_numpy};
use super::progress::PyProgress;
use pelt_core::lapped::{self, NO_PATCH, PatchParams, Patches, PictureParams};
use pelt_core::progress::ProgressCallback;

/// A patch layout: per-corner UVs, patch ids, the direction field and quality figures.
#[pyclass(name = "Patches", module = "pelt", frozen)]
pub(super) struct PyPatches {
    pub(super) inner: Arc<Patches>,
}

#[pymethods]
impl PyPatches {
    /// Per triangle and corner, the UV in tile units: `[T, 3, 2]` float32.
    #[getter]
    fn uv<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let flat: Vec<f32> = self.inner.uv.iter().flatten().flatten().copied().collect();
        Ok(PyArray1::from_vec(py, flat)
            .reshape([self.inner.uv.len(), 3, 2])?
            .into_any())
    }

    /// Per triangle, its patch: `[T]` int32, -1 for a bald face.
    #[getter]
    fn patch<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i32>> {
        let ids: Vec<i32> = self
            .inner
            .patch
            .iter()
            .map(|&p| if p == NO_PATCH { -1 } else { p as i32 })
            .collect();
        PyArray1::from_vec(py, ids)
    }

    /// Per vertex, the unit hair direction: `[V, 3]` float32.
    #[getter]
    fn direction<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_numpy(py, &self.inner.direction)
    }

    /// Per vertex, the hair's angle from the normal in radians: `[V]` float32.
    #[getter]
    fn slant<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        PyArray1::from_slice(py, &self.inner.slant)
    }

    /// Singular faces of the field as `[S, 2]` int32 rows `(face, index)`.
    #[getter]
    fn singularities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let rows: Vec<[i32; 2]> = self
            .inner
            .singularities
            .iter()
            .map(|s| [s.face as i32, s.index])
            .collect();
        to_numpy(py, &rows)
    }

    /// Number of patches.
    #[getter]
    fn patch_count(&self) -> usize {
        self.inner.quality.patch_count
    }

    /// Quality figures as a dict (per-face figures as numpy arrays).
    #[getter]
    fn quality<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let q = &self.inner.quality;
        let d = PyDict::new(py);
        d.set_item("patch_count", q.patch_count)?;
        d.set_item("furred_faces", q.furred_faces)?;
        d.set_item("coverage", q.coverage)?;
        d.set_item("flipped_faces", q.flipped_faces)?;
        d.set_item("mean_alignment_deg", q.mean_alignment_deg)?;
        d.set_item("stretch_within_fraction", q.stretch_within_fraction)?;
        d.set_item("seam_length_fraction", q.seam_length_fraction)?;
        d.set_item("singularities", q.singularities)?;
        d.set_item(
            "face_alignment_deg",
            PyArray1::from_slice(py, &q.face_alignment_deg),
        )?;
        d.set_item("face_stretch", to_numpy(py, &q.face_stretch)?)?;
        Ok(d)
    }

    /// An RGBA8 picture `[height, width, 4]` uint8 of the layout on `mesh`: patches in colors,
    /// hair directions as short dark lines, orthographic along `view`.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (mesh, *, width=512, height=512, view=(0.0, 1.0, -0.3), hair_length=0.03, hair_every=1))]
    fn picture<'py>(
        &self,
        py: Python<'py>,
        mesh: &PyFurMesh,
        width: i128,
        height: i128,
        view: (f32, f32, f32),
        hair_length: f32,
        hair_every: i128,
    ) -> PyResult<Bound<'py, PyAny>> {
        let width: u32 = super::ints::unsigned("width", width)?;
        let height: u32 = super::ints::unsigned("height", height)?;
        let hair_every: usize = super::ints::unsigned("hair_every", hair_every)?;
        let params = PictureParams {
            size: [width, height],
            view: [view.0, view.1, view.2],
            hair_length,
            hair_every,
        };
        let pixels = detached(py, || lapped::picture(&mesh.inner, &self.inner, &params))?;
        Ok(PyArray1::from_vec(py, pixels)
            .reshape([height as usize, width as usize, 4])?
            .into_any())
    }

    fn __repr__(&self) -> String {
        let q = &self.inner.quality;
        format!(
            "<pelt.Patches {} patches over {} furred faces, mean alignment {:.2}°>",
            q.patch_count, q.furred_faces, q.mean_alignment_deg
        )
    }
}

/// Builds the comb field and the lapped patches of `mesh` (GIL released). Optional arguments
/// left as `None` take the defaults of `PatchParams`.
#[pyfunction]
#[pyo3(signature = (
    mesh, tile_size, seed=1, *, max_alignment_deg=None, max_face_alignment_deg=None, stretch_tolerance=None,
    max_stretched_fraction=None, max_stretch=None, max_patch_faces=None, down=None, blend=None,
    comb_weight=None, progress=None
))]
#[allow(clippy::too_many_arguments)]
pub(super) fn build_patches(
    py: Python<'_>,
    mesh: &PyFurMesh,
    tile_size: f64,
    seed: i128,
    max_alignment_deg: Option<f64>,
    max_face_alignment_deg: Option<f64>,
    stretch_tolerance: Option<f64>,
    max_stretched_fraction: Option<f64>,
    max_stretch: Option<f64>,
    max_patch_faces: Option<i128>,
    down: Option<(f32, f32, f32)>,
    blend: Option<f64>,
    comb_weight: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<PyPatches> {
    let seed: u64 = super::ints::unsigned("seed", seed)?;
    let max_patch_faces: Option<usize> = super::ints::unsigned_opt("max_patch_faces", max_patch_faces)?;
    let defaults = PatchParams::default();
    let mut params = PatchParams {
        tile_size,
        seed,
        max_alignment_deg: max_alignment_deg.unwrap_or(defaults.max_alignment_deg),
        max_face_alignment_deg: max_face_alignment_deg.unwrap_or(defaults.max_face_alignment_deg),
        stretch_tolerance: stretch_tolerance.unwrap_or(defaults.stretch_tolerance),
        max_stretched_fraction: max_stretched_fraction.unwrap_or(defaults.max_stretched_fraction),
        max_stretch: max_stretch.unwrap_or(defaults.max_stretch),
        max_patch_faces: max_patch_faces.unwrap_or(defaults.max_patch_faces),
        field: defaults.field,
    };
    if let Some((x, y, z)) = down {
        params.field.down = [x, y, z];
    }
    params.field.blend = blend.unwrap_or(params.field.blend);
    params.field.comb_weight = comb_weight.unwrap_or(params.field.comb_weight);
    let reporter = PyProgress::new(progress.map(|p| p.into_bound(py)));
    let report = |fraction: f64| reporter.report(fraction);
    let callback: Option<ProgressCallback<'_>> = reporter.is_some().then_some(&report);
    let outcome = detached(py, || {
        lapped::build_patches_with_progress(&mesh.inner, &params, callback)
    });
    let inner = reporter.finish(outcome)?;
    Ok(PyPatches {
        inner: Arc::new(inner),
    })
}
