//! Statistics of a [`super::FurMesh`], as shown in Blender's panel and by `pelt bench`.

use serde::Serialize;

use super::frames::norm;
use super::topology::Topology;
use crate::threads::deterministic_sum;

/// Counts, surface area and bounding box of a mesh.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MeshStats {
    /// Number of vertices.
    pub vertices: usize,
    /// Number of triangles.
    pub faces: usize,
    /// Number of distinct undirected edges of the triangles.
    pub edges: usize,
    /// Edges used by exactly one triangle.
    pub boundary_edges: usize,
    /// Edges used by more than two triangles.
    pub non_manifold_edges: usize,
    /// Triangles with (numerically) zero area.
    pub degenerate_faces: usize,
    /// Connected components of the triangles.
    pub components: usize,
    /// Vertices used by no triangle.
    pub loose_vertices: usize,
    /// Total triangle area, object units squared.
    pub surface_area: f64,
    /// Smallest corner of the axis-aligned bounding box.
    pub bbox_min: [f32; 3],
    /// Largest corner of the axis-aligned bounding box.
    pub bbox_max: [f32; 3],
}

impl MeshStats {
    pub(super) fn compute(
        positions: &[[f32; 3]],
        triangles: &[[u32; 3]],
        topology: &Topology,
        face_normals: &[[f64; 3]],
        degenerate: &[bool],
    ) -> Self {
        let edges = topology.edges();
        let mut bbox_min = [f32::INFINITY; 3];
        let mut bbox_max = [f32::NEG_INFINITY; 3];
        for p in positions {
            for k in 0..3 {
                bbox_min[k] = bbox_min[k].min(p[k]);
                bbox_max[k] = bbox_max[k].max(p[k]);
            }
        }
        MeshStats {
            vertices: positions.len(),
            faces: triangles.len(),
            edges: edges.len(),
            boundary_edges: edges.iter().filter(|e| e.face_count == 1).count(),
            non_manifold_edges: edges.iter().filter(|e| e.face_count > 2).count(),
            degenerate_faces: degenerate.iter().filter(|&&d| d).count(),
            components: topology.components(),
            loose_vertices: topology.loose_vertices(),
            surface_area: deterministic_sum(face_normals.len(), |f| 0.5 * norm(face_normals[f])),
            bbox_min,
            bbox_max,
        }
    }
}
