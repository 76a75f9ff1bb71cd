//! The mesh as the skin and shell passes draw it: vertices split where the tile UVs of the lapped
//! patches jump (a vertex on a patch seam has one UV per patch), with the surface derivatives
//! `∂P/∂u`, `∂P/∂v` that carry the hair-direction map from the tile frame to the surface
//! (Lengyel et al. 2001, §2.1 and §2.4: the shells are textured through each patch's own
//! parameterization, and lighting needs the hair tangent on the surface).

use crate::vec3::{cross, dot};
use bytemuck::{Pod, Zeroable};

use crate::FurMesh;
use crate::error::{PeltError, Result};

/// One GPU vertex of the skin and shells (vertex buffer 0; color and length live in buffers of
/// their own so that [`super::FurScene::update_attributes`] rewrites only those).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub(super) struct SurfaceVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    /// `∂P/∂u`: object units per tile unit along the tile's x, in the tangent plane.
    pub dpdu: [f32; 3],
    /// `∂P/∂v`: along the tile's y.
    pub dpdv: [f32; 3],
    pub uv: [f32; 2],
    pub comb: [f32; 3],
}

/// The split mesh.
#[derive(Debug, Clone)]
pub(super) struct SurfaceMesh {
    pub vertices: Vec<SurfaceVertex>,
    /// The mesh vertex each GPU vertex came from (to expand per-vertex colors and lengths).
    pub source: Vec<u32>,
    /// Three per triangle, in the mesh's triangle order.
    pub indices: Vec<u32>,
    /// Tile units per object unit: summed UV side lengths over summed 3D side lengths. The fins
    /// map edge length to fin-texture length with it (Lengyel §2.2: the same scale as the faces).
    pub uv_scale: f64,
}

/// Checks that there is one finite UV triple per triangle.
pub(super) fn validate_uvs(mesh: &FurMesh, corner_uvs: &[[[f32; 2]; 3]]) -> Result<()> {
    if corner_uvs.len() != mesh.face_count() {
        return Err(PeltError::parameter(
            "corner_uvs",
            format!(
                "must have one row per triangle ({}), got {}",
                mesh.face_count(),
                corner_uvs.len()
            ),
        ));
    }
    if let Some(f) = corner_uvs
        .iter()
        .position(|c| !c.iter().flatten().all(|v| v.is_finite()))
    {
        return Err(PeltError::parameter(
            format!("corner_uvs[{f}]"),
            format!("must be finite, got {:?}", corner_uvs[f]),
        ));
    }
    Ok(())
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f64; 3] {
    std::array::from_fn(|i| f64::from(a[i]) - f64::from(b[i]))
}

/// `v` without its component along the unit vector `n`.
fn tangential(v: [f64; 3], n: [f64; 3]) -> [f64; 3] {
    let d = dot(v, n);
    std::array::from_fn(|i| v[i] - d * n[i])
}

/// Bits of a UV with −0 folded into +0, so equal UVs always share a GPU vertex.
fn uv_key(uv: [f32; 2]) -> [u32; 2] {
    uv.map(|c| (c + 0.0).to_bits())
}

/// Splits the mesh at UV seams and computes the surface derivatives. Serial: every sum runs in
/// a fixed order, so the buffers are bit-identical on every run.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `corner_uvs` when its length or a value is wrong, or
/// when no triangle has a usable UV layout (all UVs collapse to points or lines).
pub(super) fn build(mesh: &FurMesh, corner_uvs: &[[[f32; 2]; 3]]) -> Result<SurfaceMesh> {
    validate_uvs(mesh, corner_uvs)?;
    let triangles = mesh.triangles();
    let positions = mesh.positions();

    // Corners sorted by (vertex, uv): runs of equal keys become one GPU vertex.
    let mut corners: Vec<(u32, [u32; 2], usize)> = (0..3 * triangles.len())
        .map(|c| (triangles[c / 3][c % 3], uv_key(corner_uvs[c / 3][c % 3]), c))
        .collect();
    corners.sort_unstable();
    let mut indices = vec![0u32; corners.len()];
    let mut source = Vec::new();
    let mut uvs = Vec::new();
    for (i, &(vertex, key, corner)) in corners.iter().enumerate() {
        if i == 0 || (corners[i - 1].0, corners[i - 1].1) != (vertex, key) {
            source.push(vertex);
            uvs.push(corner_uvs[corner / 3][corner % 3].map(|c| c + 0.0));
        }
        indices[corner] = (source.len() - 1) as u32;
    }

    let mut uv_length = 0.0f64;
    let mut length_3d = 0.0f64;
    let mut sums = vec![([0.0f64; 3], [0.0f64; 3], 0.0f64); source.len()];
    for (f, tri) in triangles.iter().enumerate() {
        let uv = corner_uvs[f].map(|c| c.map(f64::from));
        for k in 0..3 {
            let (a, b) = (k, (k + 1) % 3);
            let e = sub(positions[tri[b] as usize], positions[tri[a] as usize]);
            uv_length += (uv[b][0] - uv[a][0]).hypot(uv[b][1] - uv[a][1]);
            length_3d += dot(e, e).sqrt();
        }
        let e1 = sub(positions[tri[1] as usize], positions[tri[0] as usize]);
        let e2 = sub(positions[tri[2] as usize], positions[tri[0] as usize]);
        let (du1, dv1) = (uv[1][0] - uv[0][0], uv[1][1] - uv[0][1]);
        let (du2, dv2) = (uv[2][0] - uv[0][0], uv[2][1] - uv[0][1]);
        let det = du1 * dv2 - du2 * dv1;
        let n = cross(e1, e2);
        let area = dot(n, n).sqrt();
        // A face whose UVs collapse has no parameterization to contribute.
        if det.abs() <= 1e-12 * (du1.abs() + du2.abs() + dv1.abs() + dv2.abs()).powi(2) || area == 0.0 {
            continue;
        }
        let dpdu: [f64; 3] = std::array::from_fn(|i| (e1[i] * dv2 - e2[i] * dv1) / det);
        let dpdv: [f64; 3] = std::array::from_fn(|i| (e2[i] * du1 - e1[i] * du2) / det);
        for k in 0..3 {
            let s = &mut sums[indices[3 * f + k] as usize];
            for i in 0..3 {
                // Area-weighted: large faces define the local scale more reliably than slivers.
                s.0[i] += area * dpdu[i];
                s.1[i] += area * dpdv[i];
            }
            s.2 += area;
        }
    }
    let uv_scale = uv_length / length_3d;
    if !(uv_scale.is_finite() && uv_scale > 0.0) || sums.iter().all(|s| s.2 == 0.0) {
        return Err(PeltError::parameter(
            "corner_uvs",
            "no triangle has a usable UV layout (every triangle's UVs collapse to a point or a line)",
        ));
    }

    let normals = mesh.normals();
    let (tangents, bitangents) = (mesh.tangents(), mesh.bitangents());
    let comb = mesh.comb();
    let vertices = source
        .iter()
        .zip(&uvs)
        .zip(&sums)
        .map(|((&v, &uv), &(su, sv, w))| {
            let v = v as usize;
            let n = normals[v].map(f64::from);
            let (mut dpdu, mut dpdv) = if w > 0.0 {
                (tangential(su.map(|c| c / w), n), tangential(sv.map(|c| c / w), n))
            } else {
                ([0.0; 3], [0.0; 3])
            };
            // A vertex only on collapsed faces (or whose derivatives are normal to the surface)
            // falls back to the mesh's own frame at the mean scale.
            if dot(dpdu, dpdu) == 0.0 || dot(dpdv, dpdv) == 0.0 {
                dpdu = tangents[v].map(|c| f64::from(c) / uv_scale);
                dpdv = bitangents[v].map(|c| f64::from(c) / uv_scale);
            }
            SurfaceVertex {
                position: positions[v],
                normal: normals[v],
                dpdu: dpdu.map(|c| c as f32),
                dpdv: dpdv.map(|c| c as f32),
                uv,
                comb: comb.map_or([0.0; 3], |c| c[v]),
            }
        })
        .collect();
    Ok(SurfaceMesh {
        vertices,
        source,
        indices,
        uv_scale,
    })
}

/// `values` (one per mesh vertex) gathered for each GPU vertex.
pub(super) fn expand<T: Copy>(values: &[T], source: &[u32]) -> Vec<T> {
    source.iter().map(|&v| values[v as usize]).collect()
}

/// For each of `vertex_count` mesh vertices, its first surface vertex (the copies of a vertex
/// split at a seam are adjacent, sorted by UV), or `u32::MAX` for a vertex on no triangle.
pub(super) fn first_copies(source: &[u32], vertex_count: usize) -> Vec<u32> {
    let mut first = vec![u32::MAX; vertex_count];
    for (i, &v) in source.iter().enumerate().rev() {
        first[v as usize] = i as u32;
    }
    first
}
