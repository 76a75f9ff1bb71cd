//! Fin geometry: the quads of [`crate::mesh::fins`] (one per mesh edge, Lengyel et al. 2001, §2.3,
//! Figure 3) as GPU vertices, extruded in the vertex shader along each end's growth direction
//! (normal + comb shear) and textured with the fin texture (§2.2, "Fin texture").
//!
//! A fin vertex holds only what is its own (texture coordinate, the edge's two ends): the shader
//! reads the ends' positions, normals and comb from the skin's vertex buffer, and the fin's plane
//! and midpoint from both ends, so that it fades the fin by `max(0, 2|p| − 1)` with the same `p`
//! at all four corners, and a pose (`deform.rs`), which rewrites the skin's vertices, moves the
//! fins with nothing of theirs re-sent.

use bytemuck::{Pod, Zeroable};

use std::ops::Range;

use crate::mesh::{FinQuad, quad_triangles};

/// One GPU vertex of a fin (vertex buffer 0 of the fin pass).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct FinVertex {
    /// Fin texture coordinate: `u` along the edge (tile units, wraps), `v` 0 at the top of the
    /// fur (the fin texture's row 0) and 1 at the skin.
    pub uv: [f32; 2],
    /// The surface (GPU) vertices of the edge's two ends (the same at all four corners): the
    /// corner stands on one, the fin's plane and its PRT lighting come from both.
    pub ends: [u32; 2],
    /// 0 at the first end, 1 at the second: which end the corner stands on, the weight of
    /// `ends[1]`.
    pub along: f32,
}

/// The fins of every geometric level of detail, one after another.
#[derive(Debug, Clone)]
pub struct FinMesh {
    pub vertices: Vec<FinVertex>,
    /// The mesh vertex each fin corner stands on.
    pub source: Vec<u32>,
    /// Two triangles per fin, as many as the largest level has: the index buffer's size, into
    /// which each frame writes the fins it draws.
    pub indices: Vec<u32>,
    /// The fins (numbered across levels) of each level.
    pub levels: Vec<Range<u32>>,
    /// Each level's mean fin (edge) length over level 0's, 1 where either has no fins: how many
    /// times as far apart its fins stand ([`super::scene_levels::MeshLevel::fin_spacing`]).
    pub spacing: Vec<f32>,
    /// Each fin's plane (as `fins.wgsl` finds it): the edge's midpoint and unit normal, from
    /// which the CPU collects the fins a frame draws.
    pub centers: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
}

impl FinMesh {
    /// Each fin's edge ends (mesh vertices), which a pose moves its plane with.
    pub fn ends(&self) -> Vec<[u32; 2]> {
        self.source.chunks_exact(4).map(|c| [c[0], c[1]]).collect()
    }
}

/// Mean edge length of `quads` in fin texture units (their `u` interval), 0 for none.
fn mean_length(quads: &[FinQuad]) -> f64 {
    let sum: f64 = quads.iter().map(|q| q.u1 - q.u0).sum();
    sum / quads.len().max(1) as f64
}

/// Packs the fins of each level (`levels[k]`: the quads of level `k`'s edges), `surface_vertex[v]`
/// a surface (GPU) vertex made from mesh vertex `v` (every edge end has one: edges come from
/// triangles).
pub fn build(levels: &[Vec<FinQuad>], surface_vertex: &[u32]) -> FinMesh {
    let total: usize = levels.iter().map(Vec::len).sum();
    let mut fins = FinMesh {
        vertices: Vec::with_capacity(4 * total),
        source: Vec::with_capacity(4 * total),
        indices: Vec::new(),
        levels: Vec::with_capacity(levels.len()),
        spacing: Vec::with_capacity(levels.len()),
        centers: Vec::with_capacity(total),
        normals: Vec::with_capacity(total),
    };
    let full = levels.first().map_or(0.0, |q| mean_length(q));
    for quads in levels {
        let first = (fins.vertices.len() / 4) as u32;
        for quad in quads {
            let [a, b] = quad.vertices;
            let ends = [a, b].map(|v| surface_vertex[v as usize]);
            for (vertex, u, v) in [
                (a, quad.u0, 1.0),
                (b, quad.u1, 1.0),
                (a, quad.u0, 0.0),
                (b, quad.u1, 0.0),
            ] {
                fins.vertices.push(FinVertex {
                    uv: [u as f32, v],
                    ends,
                    along: if vertex == a { 0.0 } else { 1.0 },
                });
                fins.source.push(vertex);
            }
            fins.centers.push(quad.center);
            fins.normals.push(quad.normal);
        }
        fins.levels.push(first..first + quads.len() as u32);
        fins.spacing.push(match mean_length(quads) / full {
            r if r.is_finite() && r > 0.0 => r as f32,
            _ => 1.0,
        });
    }
    let most = levels.iter().map(Vec::len).max().unwrap_or(0) as u32;
    fins.indices = (0..most).flat_map(quad_triangles).collect();
    fins
}
