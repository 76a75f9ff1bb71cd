//! The mesh as the skin and shell passes draw it: [`crate::mesh::uv_split`] splits vertices where
//! the tile UVs of the lapped patches jump and gives each copy its surface derivatives; this file
//! packs them into GPU vertices (Lengyel et al. 2001, §2.1 and §2.4).

use bytemuck::{Pod, Zeroable};

use crate::FurMesh;
use crate::error::Result;
use crate::mesh::{border_distances, split_at_uv_seams};

/// One GPU vertex of the skin and shells (vertex buffer 0; color and length live in buffers of
/// their own so that `FurScene::update_attributes` (pelt-render) rewrites only those).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct SurfaceVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    /// `∂P/∂u`: object units per tile unit along the tile's x, in the tangent plane.
    pub dpdu: [f32; 3],
    /// `∂P/∂v`: along the tile's y.
    pub dpdv: [f32; 3],
    pub uv: [f32; 2],
    pub comb: [f32; 3],
    /// Tile units over the surface to the mesh's nearest open border edge and to the nearest
    /// running another way ([`crate::mesh::border_distances`]; [`BORDERLESS`] where there is
    /// none): where the marched shells' view ray leaves the mesh (`march.wgsl`).
    pub border: [f32; 2],
}

/// [`SurfaceVertex::border`] of a vertex on a closed piece: no march reaches that far, and the
/// value stays exact when the shaders interpolate it.
pub const BORDERLESS: f32 = 1.0e6;

/// The split mesh.
#[derive(Debug, Clone)]
pub struct SurfaceMesh {
    pub vertices: Vec<SurfaceVertex>,
    /// The mesh vertex each GPU vertex came from (to expand per-vertex colors and lengths).
    pub source: Vec<u32>,
    /// Three per triangle, in the mesh's triangle order.
    pub indices: Vec<u32>,
    /// Tile units per object unit (see [`crate::mesh::UvSplit::uv_scale`]).
    pub uv_scale: f64,
}

/// Splits the mesh at UV seams and packs the GPU vertices.
///
/// # Errors
/// As [`split_at_uv_seams`].
pub fn build(mesh: &FurMesh, corner_uvs: &[[[f32; 2]; 3]]) -> Result<SurfaceMesh> {
    let split = split_at_uv_seams(mesh, corner_uvs)?;
    let (positions, normals, comb) = (mesh.positions(), mesh.normals(), mesh.comb());
    let border = border_distances(mesh);
    let uv_scale = split.uv_scale as f32;
    let vertices = (0..split.len())
        .map(|i| {
            let v = split.source[i] as usize;
            SurfaceVertex {
                position: positions[v],
                normal: normals[v],
                dpdu: split.dpdu[i],
                dpdv: split.dpdv[i],
                uv: split.uvs[i],
                comb: comb.map_or([0.0; 3], |c| c[v]),
                border: border[v].map(|d| d.map_or(BORDERLESS, |d| (d * uv_scale).min(BORDERLESS))),
            }
        })
        .collect();
    Ok(SurfaceMesh {
        vertices,
        source: split.source,
        indices: split.indices,
        uv_scale: split.uv_scale,
    })
}

/// `values` (one per mesh vertex) gathered for each GPU vertex.
pub fn expand<T: Copy>(values: &[T], source: &[u32]) -> Vec<T> {
    source.iter().map(|&v| values[v as usize]).collect()
}

/// For each of `vertex_count` mesh vertices, its first surface vertex (of the copies a seam
/// split makes), or `u32::MAX` for a vertex on no triangle.
pub fn first_copies(source: &[u32], vertex_count: usize) -> Vec<u32> {
    let mut first = vec![u32::MAX; vertex_count];
    for (i, &v) in source.iter().enumerate().rev() {
        first[v as usize] = i as u32;
    }
    first
}
