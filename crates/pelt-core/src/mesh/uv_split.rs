//! The mesh split where the tile UVs of the lapped patches jump: a vertex on a patch seam has one
//! UV per patch, so every consumer that stores one UV per vertex (the GPU buffers of the renderer,
//! glTF meshes) needs a copy of it per UV. Each copy also gets the surface derivatives `∂P/∂u`,
//! `∂P/∂v` that carry the hair-direction map from the tile frame to the surface (Lengyel et al.
//! 2001, §2.1 and §2.4: the shells are textured through each patch's own parameterization, and
//! lighting needs the hair tangent on the surface).
//!
//! The renderer and the glTF export share this code, so an exported mesh has exactly the vertices,
//! UVs and order the preview draws.

use crate::FurMesh;
use crate::error::{PeltError, Result};
use crate::mesh::orthonormal_basis;
use glam::{DVec3, Vec3};
use rayon::prelude::*;

/// A mesh split at UV seams. Arrays indexed by split vertex have one row per copy.
#[derive(Debug, Clone, PartialEq)]
pub struct UvSplit {
    /// The mesh vertex each split vertex came from (to gather per-vertex attributes).
    pub source: Vec<u32>,
    /// The tile UV of each split vertex (−0 folded into +0).
    pub uvs: Vec<[f32; 2]>,
    /// `∂P/∂u`: object units per tile unit along the tile's x, in the tangent plane.
    pub dpdu: Vec<[f32; 3]>,
    /// `∂P/∂v`: along the tile's y.
    pub dpdv: Vec<[f32; 3]>,
    /// Three split-vertex indices per triangle, in the mesh's triangle order.
    pub indices: Vec<u32>,
    /// Tile units per object unit: summed UV side lengths over summed 3D side lengths. The fins
    /// map edge length to fin-texture length with it (Lengyel §2.2: the same scale as the faces).
    pub uv_scale: f64,
}

impl UvSplit {
    /// Number of split vertices.
    pub fn len(&self) -> usize {
        self.source.len()
    }

    /// Whether there are no vertices (never true for a split of a valid mesh).
    pub fn is_empty(&self) -> bool {
        self.source.is_empty()
    }

    /// `values` (one per mesh vertex) gathered for each split vertex.
    pub fn expand<T: Copy>(&self, values: &[T]) -> Vec<T> {
        self.source.iter().map(|&v| values[v as usize]).collect()
    }
}

/// Checks that there is one finite UV triple per triangle.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `corner_uvs` (wrong row count) or `corner_uvs[f]` (a
/// value that is not finite).
pub fn validate_uvs(mesh: &FurMesh, corner_uvs: &[[[f32; 2]; 3]]) -> Result<()> {
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

/// `v` without its component along the unit vector `n`.
fn tangential(v: DVec3, n: DVec3) -> DVec3 {
    v - v.dot(n) * n
}

/// Bits of a UV with −0 folded into +0, so equal UVs always share a vertex.
fn uv_key(uv: [f32; 2]) -> [u32; 2] {
    uv.map(|c| (c + 0.0).to_bits())
}

/// Splits `mesh` at the seams of `corner_uvs` (tile units, `corner_uvs[f][k]` for corner `k` of
/// triangle `f`) and computes the surface derivatives. Every sum runs in a fixed order (each
/// vertex's triangles in triangle order), so the result is bit-identical on every run and
/// thread count; split vertices are ordered by mesh vertex, then by UV bits.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `corner_uvs` when its length or a value is wrong, or
/// when no triangle has a usable UV layout (all UVs collapse to points or lines) on a mesh that
/// is not bald everywhere.
pub fn split_at_uv_seams(mesh: &FurMesh, corner_uvs: &[[[f32; 2]; 3]]) -> Result<UvSplit> {
    validate_uvs(mesh, corner_uvs)?;
    let triangles = mesh.triangles();
    let positions = mesh.positions();

    // Corners sorted by (vertex, uv): runs of equal keys become one split vertex.
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
    for (f, tri) in triangles.iter().enumerate() {
        let uv = corner_uvs[f].map(|c| c.map(f64::from));
        let p = tri.map(|v| Vec3::from(positions[v as usize]).as_dvec3());
        for k in 0..3 {
            let (a, b) = (k, (k + 1) % 3);
            let e = p[b] - p[a];
            uv_length += (uv[b][0] - uv[a][0]).hypot(uv[b][1] - uv[a][1]);
            length_3d += e.length();
        }
    }
    let layout = SplitLayout::new(source, uvs, indices);
    let sums = layout.derivative_sums(positions, triangles);
    let mut uv_scale = uv_length / length_3d;
    if !(uv_scale.is_finite() && uv_scale > 0.0) || sums.iter().all(|s| s.2 == 0.0) {
        // A mesh bald everywhere has no patches and needs no texture frame: the skin is drawn
        // alone, so the mesh's own frame at unit scale serves (no triangle has a UV layout, so
        // every vertex takes the fallback frame below).
        if bald_everywhere(mesh) {
            uv_scale = 1.0;
        } else {
            return Err(PeltError::parameter(
                "corner_uvs",
                "no triangle has a usable UV layout (every triangle's UVs collapse to a point or a line)",
            ));
        }
    }
    let (dpdu, dpdv) = frames_from_sums(&sums, mesh.normals(), &layout.source, uv_scale);
    let SplitLayout {
        source, uvs, indices, ..
    } = layout;
    Ok(UvSplit {
        source,
        uvs,
        dpdu,
        dpdv,
        indices,
        uv_scale,
    })
}

/// Area-weighted `∂P/∂u`, `∂P/∂v` and the area they weigh, of a face or summed over a vertex's.
type WeightedDerivatives = (DVec3, DVec3, f64);

/// A triangle's UV layout inverted, fixed for every pose: `∂P/∂u = a·e₁ + b·e₂` and
/// `∂P/∂v = c·e₁ + d·e₂` for its edges `e₁`, `e₂` from corner 0 (`[a, b, c, d]`); `None` where
/// its UVs collapse, so it has no parameterization to contribute.
type UvInverse = Option<[f64; 4]>;

/// Memory for each triangle's derivatives, kept between poses by
/// [`SplitLayout::derivatives_into`]'s caller so that a pose does not allocate it again.
#[derive(Debug, Clone, Default)]
pub struct FaceDerivatives(Vec<Option<WeightedDerivatives>>);

/// Where a split's vertices come from, without their derivatives: what
/// [`SplitLayout::derivatives_into`] needs to compute those at any pose of the mesh (the renderer
/// recomputes them for a deformed mesh: the UVs stay, so the patches ride on the skin).
#[derive(Debug, Clone)]
pub struct SplitLayout {
    /// As [`UvSplit::source`].
    pub source: Vec<u32>,
    /// As [`UvSplit::uvs`].
    pub uvs: Vec<[f32; 2]>,
    /// As [`UvSplit::indices`].
    pub indices: Vec<u32>,
    /// The corners (`3·triangle + k`) of each split vertex in ascending order, vertex `i`'s at
    /// `corners[corner_offsets[i]..corner_offsets[i + 1]]`: each vertex sums its triangles in
    /// triangle order, in parallel, with the same bits as a serial pass over the triangles.
    corner_offsets: Vec<u32>,
    corners: Vec<u32>,
    /// Per triangle, its UV layout inverted once here rather than at every pose.
    uv_inverse: Vec<UvInverse>,
}

impl SplitLayout {
    /// The layout of split vertices `source` with `uvs`, and the triangles' `indices` into them.
    pub fn new(source: Vec<u32>, uvs: Vec<[f32; 2]>, indices: Vec<u32>) -> Self {
        let mut corner_offsets = vec![0u32; source.len() + 1];
        for &i in &indices {
            corner_offsets[i as usize + 1] += 1;
        }
        for i in 0..source.len() {
            corner_offsets[i + 1] += corner_offsets[i];
        }
        let mut next = corner_offsets.clone();
        let mut corners = vec![0u32; indices.len()];
        for (corner, &i) in indices.iter().enumerate() {
            corners[next[i as usize] as usize] = corner as u32;
            next[i as usize] += 1;
        }
        let uv_inverse = indices
            .par_chunks_exact(3)
            .map(|corners| invert_uv_layout(corners.iter().map(|&i| uvs[i as usize])))
            .collect();
        SplitLayout {
            source,
            uvs,
            indices,
            corner_offsets,
            corners,
            uv_inverse,
        }
    }

    /// `∂P/∂u`, `∂P/∂v` of each split vertex over the mesh's `triangles` at (`positions`, unit
    /// vertex `normals`) (the area-weighted mean of its triangles' derivatives, projected
    /// into the tangent plane; a vertex with none takes the mesh frame of its normal at
    /// `uv_scale`, tile units per object unit), handed to `vertex` with the vertex's index as
    /// they are found; what it returns goes to `out[i]` of (`scratch`, `out`), one entry per
    /// split vertex. One pass over the vertices into memory the caller keeps, as a pose needs
    /// every frame.
    pub fn derivatives_into<T: Send>(
        &self,
        (positions, normals): (&[[f32; 3]], &[[f32; 3]]),
        triangles: &[[u32; 3]],
        uv_scale: f64,
        (scratch, out): (&mut FaceDerivatives, &mut [T]),
        vertex: impl Fn(usize, [f32; 3], [f32; 3]) -> T + Sync,
    ) {
        debug_assert_eq!(out.len(), self.source.len());
        self.face_derivatives(positions, triangles, &mut scratch.0);
        let faces = &scratch.0;
        out.par_iter_mut().enumerate().for_each(|(i, slot)| {
            let normal = normals[self.source[i] as usize];
            let (dpdu, dpdv) = frame_from_sum(self.vertex_sum(faces, i), normal, uv_scale);
            *slot = vertex(i, dpdu, dpdv);
        });
    }

    /// Per split vertex: area-weighted sums of its triangles' `∂P/∂u`, `∂P/∂v`, and the area,
    /// each summed in triangle order (the same bits on every run and thread count).
    fn derivative_sums(&self, positions: &[[f32; 3]], triangles: &[[u32; 3]]) -> Vec<WeightedDerivatives> {
        let mut faces = Vec::new();
        self.face_derivatives(positions, triangles, &mut faces);
        (0..self.source.len())
            .into_par_iter()
            .map(|i| self.vertex_sum(&faces, i))
            .collect()
    }

    /// Each triangle's area-weighted derivatives into `faces` (large faces define the local
    /// scale more reliably than slivers); `None` for one without a UV layout or an area.
    fn face_derivatives(
        &self,
        positions: &[[f32; 3]],
        triangles: &[[u32; 3]],
        faces: &mut Vec<Option<WeightedDerivatives>>,
    ) {
        faces.resize(triangles.len(), None);
        faces
            .par_iter_mut()
            .zip(triangles.par_iter().zip(self.uv_inverse.par_iter()))
            .for_each(|(face, (tri, inverse))| {
                *face = inverse.and_then(|[a, b, c, d]| {
                    let p = tri.map(|v| Vec3::from(positions[v as usize]).as_dvec3());
                    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
                    let area = e1.cross(e2).length();
                    if area == 0.0 {
                        return None;
                    }
                    Some((area * (a * e1 + b * e2), area * (c * e1 + d * e2), area))
                });
            });
    }

    /// Split vertex `i`'s sum of its triangles' `faces`, in triangle order.
    fn vertex_sum(&self, faces: &[Option<WeightedDerivatives>], i: usize) -> WeightedDerivatives {
        let range = self.corner_offsets[i] as usize..self.corner_offsets[i + 1] as usize;
        self.corners[range]
            .iter()
            .filter_map(|&c| faces[c as usize / 3])
            .fold((DVec3::ZERO, DVec3::ZERO, 0.0), |(su, sv, w), (u, v, a)| {
                (su + u, sv + v, w + a)
            })
    }
}

/// The inverse of a triangle's UV edge matrix from its corners' `uvs` ([`UvInverse`]).
fn invert_uv_layout(mut uvs: impl Iterator<Item = [f32; 2]>) -> UvInverse {
    let mut next = || uvs.next().map(|uv| uv.map(f64::from));
    let (uv0, uv1, uv2) = (next()?, next()?, next()?);
    let (du1, dv1) = (uv1[0] - uv0[0], uv1[1] - uv0[1]);
    let (du2, dv2) = (uv2[0] - uv0[0], uv2[1] - uv0[1]);
    let det = du1 * dv2 - du2 * dv1;
    if det.abs() <= 1e-12 * (du1.abs() + du2.abs() + dv1.abs() + dv2.abs()).powi(2) {
        return None;
    }
    Some([dv2 / det, -dv1 / det, -du2 / det, du1 / det])
}

/// The derivatives of [`SplitLayout::derivative_sums`], with the mesh frame where a vertex has none.
fn frames_from_sums(
    sums: &[WeightedDerivatives],
    normals: &[[f32; 3]],
    source: &[u32],
    uv_scale: f64,
) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    source
        .par_iter()
        .zip(sums)
        .map(|(&v, &sum)| frame_from_sum(sum, normals[v as usize], uv_scale))
        .unzip()
}

/// A vertex's `∂P/∂u`, `∂P/∂v` from its triangles' `sum` and its unit `normal`: their mean
/// projected into the tangent plane, or the mesh's own frame at the mean scale `uv_scale` for a
/// vertex only on collapsed faces (or whose derivatives are normal to the surface).
fn frame_from_sum((su, sv, w): WeightedDerivatives, normal: [f32; 3], uv_scale: f64) -> ([f32; 3], [f32; 3]) {
    let n = Vec3::from(normal).as_dvec3();
    let (mut dpdu, mut dpdv) = if w > 0.0 {
        (tangential(su / w, n), tangential(sv / w, n))
    } else {
        (DVec3::ZERO, DVec3::ZERO)
    };
    if dpdu.length_squared() == 0.0 || dpdv.length_squared() == 0.0 {
        let [t, b] = orthonormal_basis(normal);
        dpdu = Vec3::from(t).as_dvec3() / uv_scale;
        dpdv = Vec3::from(b).as_dvec3() / uv_scale;
    }
    (dpdu.as_vec3().to_array(), dpdv.as_vec3().to_array())
}

/// Whether every vertex has hair length 0.
fn bald_everywhere(mesh: &FurMesh) -> bool {
    mesh.length()
        .is_some_and(|length| length.iter().all(|&l| l == 0.0))
}

#[cfg(test)]
pub(crate) mod tests;
