//! `pelt.FurMesh`: the Python face of [`pelt_core::FurMesh`].

use std::sync::Arc;

use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::arrays::{self, IndexArray};
use super::detached;
use pelt_core::mesh::{FurMesh, MeshInput};
use pelt_core::threads::pool;

/// A validated triangle mesh with per-vertex hair attributes.
#[pyclass(name = "FurMesh", module = "pelt", frozen)]
pub(super) struct PyFurMesh {
    pub(super) inner: Arc<FurMesh>,
}

/// `rows` as a new numpy array of shape `[len, C]`.
pub(super) fn to_numpy<'py, T: numpy::Element + Copy, const C: usize>(
    py: Python<'py>,
    rows: &[[T; C]],
) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_slice(py, rows.as_flattened())
        .reshape([rows.len(), C])?
        .into_any())
}

#[pymethods]
impl PyFurMesh {
    #[new]
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (positions, triangles, *, normals=None, color=None, comb=None, length=None, polygons=None))]
    fn new(
        py: Python<'_>,
        positions: &Bound<'_, PyAny>,
        triangles: &Bound<'_, PyAny>,
        normals: Option<&Bound<'_, PyAny>>,
        color: Option<&Bound<'_, PyAny>>,
        comb: Option<&Bound<'_, PyAny>>,
        length: Option<&Bound<'_, PyAny>>,
        polygons: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let positions = arrays::float_array(positions, "positions", Some(3))?;
        let triangles = arrays::index_array(triangles, "triangles")?;
        let normals = normals
            .map(|a| arrays::float_array(a, "normals", Some(3)))
            .transpose()?;
        let color = color
            .map(|a| arrays::float_array(a, "color", Some(4)))
            .transpose()?;
        let comb = comb
            .map(|a| arrays::float_array(a, "comb", Some(3)))
            .transpose()?;
        let length = length
            .map(|a| arrays::float_array(a, "length", None))
            .transpose()?;
        let polygons = polygons.map(|a| arrays::uint_array(a, "polygons")).transpose()?;

        let positions = arrays::rows::<f32, 3>(&positions)?;
        let normals = normals.as_ref().map(arrays::rows::<f32, 3>).transpose()?;
        let color = color.as_ref().map(arrays::rows::<f32, 4>).transpose()?;
        let comb = comb.as_ref().map(arrays::rows::<f32, 3>).transpose()?;
        let length = length.as_ref().map(arrays::rows::<f32, 1>).transpose()?;
        let polygons = polygons.as_ref().map(arrays::rows::<u32, 1>).transpose()?;
        let (native, wide) = match &triangles {
            IndexArray::Native(a) => (Some(arrays::rows::<u32, 3>(a)?), None),
            IndexArray::Wide(a) => (None, Some(arrays::rows::<i64, 3>(a)?)),
        };
        let inner = detached(py, move || {
            let narrowed;
            let triangles = match (native, wide) {
                (Some(t), _) => t,
                (None, Some(w)) => {
                    narrowed = pool().install(|| arrays::narrow_indices(w, positions.len()))?;
                    &narrowed[..]
                }
                (None, None) => &[],
            };
            let input = MeshInput {
                positions,
                triangles,
                normals,
                color,
                comb,
                length: length.map(<[[f32; 1]]>::as_flattened),
                polygons: polygons.map(<[[u32; 1]]>::as_flattened),
            };
            FurMesh::new(input)
        })?;
        Ok(PyFurMesh {
            inner: Arc::new(inner),
        })
    }

    /// Statistics as a dict: vertices, faces, edges, boundary_edges, non_manifold_edges,
    /// degenerate_faces, components, loose_vertices, surface_area, bbox_min, bbox_max.
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.inner.stats();
        let d = PyDict::new(py);
        d.set_item("vertices", s.vertices)?;
        d.set_item("faces", s.faces)?;
        d.set_item("edges", s.edges)?;
        d.set_item("boundary_edges", s.boundary_edges)?;
        d.set_item("non_manifold_edges", s.non_manifold_edges)?;
        d.set_item("degenerate_faces", s.degenerate_faces)?;
        d.set_item("components", s.components)?;
        d.set_item("loose_vertices", s.loose_vertices)?;
        d.set_item("surface_area", s.surface_area)?;
        d.set_item("bbox_min", s.bbox_min.to_vec())?;
        d.set_item("bbox_max", s.bbox_max.to_vec())?;
        Ok(d)
    }

    #[getter]
    fn vertex_count(&self) -> usize {
        self.inner.vertex_count()
    }

    #[getter]
    fn face_count(&self) -> usize {
        self.inner.face_count()
    }

    #[getter]
    fn normals_given(&self) -> bool {
        self.inner.normals_given()
    }

    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_numpy(py, self.inner.positions())
    }

    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_numpy(py, self.inner.triangles())
    }

    #[getter]
    fn normals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_numpy(py, self.inner.normals())
    }

    #[getter]
    fn tangents<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_numpy(py, self.inner.tangents())
    }

    #[getter]
    fn bitangents<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_numpy(py, self.inner.bitangents())
    }

    #[getter]
    fn color<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.inner.color().map(|c| to_numpy(py, c)).transpose()
    }

    #[getter]
    fn comb<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.inner.comb().map(|c| to_numpy(py, c)).transpose()
    }

    #[getter]
    fn length<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f32>>> {
        self.inner.length().map(|l| PyArray1::from_slice(py, l))
    }

    /// Edges as a `[E, 2]` uint32 array of vertex pairs (smaller index first), sorted.
    #[getter]
    fn edges<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let pairs: Vec<[u32; 2]> = self
            .inner
            .topology()
            .edges()
            .iter()
            .map(|e| e.vertices())
            .collect();
        to_numpy(py, &pairs)
    }

    fn __repr__(&self) -> String {
        let s = self.inner.stats();
        format!(
            "<pelt.FurMesh {} vertices, {} triangles, {} edges>",
            s.vertices, s.faces, s.edges
        )
    }
}
