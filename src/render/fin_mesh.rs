//! Fin geometry: one quad per mesh edge (Lengyel et al. 2001, §2.3, Figure 3), extruded in the
//! vertex shader along each end's growth direction (normal + comb shear), textured with the fin
//! texture over a random interval whose length scales with the edge (§2.2, "Fin texture").
//!
//! Each fin carries its own normal and midpoint so that the shader can fade it by
//! `max(0, 2|p| − 1)` with the same `p` at all four corners and drop a faded-out fin whole.

use bytemuck::{Pod, Zeroable};

use crate::FurMesh;
use crate::rng::Rng;

/// Seed of the fin texture intervals (any fixed value: fins look the same on every run).
const FIN_SEED: u64 = 0x5045_4c54_4649_4e53;

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
    let mut fins = FinMesh {
        vertices: Vec::new(),
        source: Vec::new(),
        indices: Vec::new(),
    };
    for (index, edge) in mesh.topology().edges().iter().enumerate() {
        let [a, b] = edge.vertices();
        let (pa, pb) = (positions[a as usize], positions[b as usize]);
        let e: [f64; 3] = std::array::from_fn(|i| f64::from(pb[i]) - f64::from(pa[i]));
        let len = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        let n: [f64; 3] =
            std::array::from_fn(|i| f64::from(normals[a as usize][i]) + f64::from(normals[b as usize][i]));
        let f = [
            n[1] * e[2] - n[2] * e[1],
            n[2] * e[0] - n[0] * e[2],
            n[0] * e[1] - n[1] * e[0],
        ];
        let f_len = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
        // A collapsed edge, or one whose end normals cancel or run along it, has no fin plane.
        if len == 0.0 || f_len.is_nan() || f_len <= 1e-9 * len {
            continue;
        }
        let fin_normal = f.map(|c| (c / f_len) as f32);
        let center = std::array::from_fn(|i| ((f64::from(pa[i]) + f64::from(pb[i])) * 0.5) as f32);
        let u0 = Rng::stream(FIN_SEED, 0, index as u64).next_f64();
        let u1 = u0 + len * uv_scale;
        let base = fins.vertices.len() as u32;
        let ends = [a, b].map(|v| surface_vertex[v as usize]);
        for (vertex, u, v) in [(a, u0, 1.0), (b, u1, 1.0), (a, u0, 0.0), (b, u1, 0.0)] {
            fins.vertices.push(FinVertex {
                position: positions[vertex as usize],
                normal: normals[vertex as usize],
                comb: comb.map_or([0.0; 3], |c| c[vertex as usize]),
                fin_normal,
                center,
                uv: [u as f32, v],
                ends,
                along: if vertex == a { 0.0 } else { 1.0 },
            });
            fins.source.push(vertex);
        }
        fins.indices.extend([0, 1, 3, 0, 3, 2].map(|k| base + k));
    }
    fins
}
