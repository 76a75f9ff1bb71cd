//! Fin placement: one quad per mesh edge (Lengyel et al. 2001, §2.3, Figure 3), standing on the
//! edge along each end's growth direction, textured with the fin texture over a random interval
//! whose length scales with the edge (§2.2, "Fin texture").
//!
//! The renderer extrudes these quads in its vertex shader and the glTF export bakes them into
//! geometry; both read the same quads, so an exported fin lies where the preview draws it.

use glam::Vec3;

use crate::FurMesh;
use crate::rng::Rng;

/// Seed of the fin texture intervals (any fixed value: fins look the same on every run).
const FIN_SEED: u64 = 0x5045_4c54_4649_4e53;

/// The fin of one edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FinQuad {
    /// The edge's index in [`crate::mesh::Topology::edges`] (or in the edges given to
    /// [`fin_quads_of_edges`]).
    pub edge: u32,
    /// The edge's end vertices `[a, b]`, `a < b`.
    pub vertices: [u32; 2],
    /// Unit normal of the fin plane: edge × (sum of the end normals).
    pub normal: [f32; 3],
    /// Midpoint of the edge (where the renderer evaluates its view-dependent fade).
    pub center: [f32; 3],
    /// Fin texture `u` at `a`, in `[0, 1)` (tile units; the texture wraps along `u`).
    pub u0: f64,
    /// Fin texture `u` at `b`: `u0 + edge length · uv_scale`.
    pub u1: f64,
}

/// The two triangles of fin `quad` when its four corners are vertices `4·quad ..`, written as
/// the edge's ends `a`, `b` at one height and then `a`, `b` at the other (the renderer's and the
/// glTF export's layout).
pub fn quad_triangles(quad: u32) -> [u32; 6] {
    [0, 1, 3, 0, 3, 2].map(|k| 4 * quad + k)
}

/// The unit normal of the fin plane over the edge `ends` with unit vertex `normals` (edge ×
/// the sum of the end normals) and the edge's length, or `None` for a collapsed edge or one
/// whose end normals cancel or run along it (no fin plane).
pub fn fin_plane(ends: [[f32; 3]; 2], normals: [[f32; 3]; 2]) -> Option<([f32; 3], f64)> {
    let wide = |v: [f32; 3]| Vec3::from(v).as_dvec3();
    let e = wide(ends[1]) - wide(ends[0]);
    let len = e.length();
    let f = (wide(normals[0]) + wide(normals[1])).cross(e);
    let f_len = f.length();
    if len == 0.0 || f_len.is_nan() || f_len <= 1e-9 * len {
        return None;
    }
    Some(((f / f_len).as_vec3().to_array(), len))
}

/// The midpoint of the edge `a`–`b` (where a fin's fade is evaluated), summed in f64.
pub fn midpoint(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    ((Vec3::from(a).as_dvec3() + Vec3::from(b).as_dvec3()) * 0.5)
        .as_vec3()
        .to_array()
}

/// The fins of every edge that has a length and a well-defined fin plane, in edge order;
/// `uv_scale` is tile units per object unit (see [`crate::mesh::UvSplit::uv_scale`]).
pub fn fin_quads(mesh: &FurMesh, uv_scale: f64) -> Vec<FinQuad> {
    let edges = mesh.topology().edges().iter().map(|edge| edge.vertices());
    fin_quads_of_edges(mesh, edges, uv_scale)
}

/// [`fin_quads`] of other edges over the mesh's vertices (a simplified version of its surface,
/// say), numbered in the order given: `edge` is an index into `edges`, which also picks the
/// fin's random texture interval.
pub fn fin_quads_of_edges(
    mesh: &FurMesh,
    edges: impl IntoIterator<Item = [u32; 2]>,
    uv_scale: f64,
) -> Vec<FinQuad> {
    let (positions, normals) = (mesh.positions(), mesh.normals());
    let mut fins = Vec::new();
    for (index, [a, b]) in edges.into_iter().enumerate() {
        let (pa, pb) = (positions[a as usize], positions[b as usize]);
        let Some((normal, len)) = fin_plane([pa, pb], [normals[a as usize], normals[b as usize]]) else {
            continue;
        };
        let u0 = Rng::stream(FIN_SEED, 0, index as u64).next_f64();
        fins.push(FinQuad {
            edge: index as u32,
            vertices: [a, b],
            normal,
            center: midpoint(pa, pb),
            u0,
            u1: u0 + len * uv_scale,
        });
    }
    fins
}

#[cfg(test)]
mod tests;
