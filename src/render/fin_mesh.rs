//! Fin geometry: the quads of [`crate::mesh::fins`] (one per mesh edge, Lengyel et al. 2001, §2.3,
//! Figure 3) as GPU vertices, extruded in the vertex shader along each end's growth direction
//! (normal + comb shear) and textured with the fin texture (§2.2, "Fin texture").
//!
//! Each fin carries its own normal and midpoint so that the shader can fade it by
//! `max(0, 2|p| − 1)` with the same `p` at all four corners and drop a faded-out fin whole.

use bytemuck::{Pod, Zeroable};

use crate::FurMesh;
use crate::mesh::{fin_quads, quad_triangles};

/// One GPU vertex of a fin (vertex buffer 0 of the fin pass).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub(super) struct FinVertex {
    /// The edge end this corner stands on.
    pub position: [f32; 3],
    /// That end's vertex normal.
    pub normal: [f32; 3],
    /// That end's comb vector.
    pub comb: [f32; 3],
    /// Unit normal of the fin plane (edge × averaged normal).
    pub fin_normal: [f32; 3],
    /// Midpoint of the edge, where the fade is evaluated.
    pub center: [f32; 3],
    /// Fin texture coordinate: `u` along the edge (tile units, wraps), `v` 0 at the top of the
    /// fur (the fin texture's row 0) and 1 at the skin.
    pub uv: [f32; 2],
    /// The surface (GPU) vertices of the edge's two ends, whose rotated PRT lighting the fin
    /// interpolates (the same at all four corners).
    pub ends: [u32; 2],
    /// 0 at the first end, 1 at the second: the weight of `ends[1]`.
    pub along: f32,
}

/// All fins of a mesh.
#[derive(Debug, Clone)]
pub(super) struct FinMesh {
    pub vertices: Vec<FinVertex>,
    /// The mesh vertex each fin corner stands on.
    pub source: Vec<u32>,
    /// Two triangles per fin.
    pub indices: Vec<u32>,
}

/// Builds the fins of every edge that has a length and a well-defined fin plane; `uv_scale` is
/// tile units per object unit, `surface_vertex[v]` a surface (GPU) vertex made from mesh vertex
/// `v` (every edge end has one: edges come from triangles).
pub(super) fn build(mesh: &FurMesh, uv_scale: f64, surface_vertex: &[u32]) -> FinMesh {
    let (positions, normals) = (mesh.positions(), mesh.normals());
    let comb = mesh.comb();
    let quads = fin_quads(mesh, uv_scale);
    let mut fins = FinMesh {
        vertices: Vec::with_capacity(4 * quads.len()),
        source: Vec::with_capacity(4 * quads.len()),
        indices: Vec::with_capacity(6 * quads.len()),
    };
    for (k, quad) in quads.iter().enumerate() {
        let [a, b] = quad.vertices;
        let ends = [a, b].map(|v| surface_vertex[v as usize]);
        for (vertex, u, v) in [
            (a, quad.u0, 1.0),
            (b, quad.u1, 1.0),
            (a, quad.u0, 0.0),
            (b, quad.u1, 0.0),
        ] {
            fins.vertices.push(FinVertex {
                position: positions[vertex as usize],
                normal: normals[vertex as usize],
                comb: comb.map_or([0.0; 3], |c| c[vertex as usize]),
                fin_normal: quad.normal,
                center: quad.center,
                uv: [u as f32, v],
                ends,
                along: if vertex == a { 0.0 } else { 1.0 },
            });
            fins.source.push(vertex);
        }
        fins.indices.extend(quad_triangles(k as u32));
    }
    fins
}
