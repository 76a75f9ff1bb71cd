//! A furred mesh in a pose (an armature's skinning, shape keys): the skin's GPU vertices rebuilt
//! from the posed positions and normals, with nothing re-baked and no texture re-sent; the shells
//! are drawn from those vertices and the fins read their ends from them (`fins.wgsl`), so they
//! follow. The fur stays where the rest shape put it: each vertex keeps its tile UV (the lapped
//! patches ride on the skin, Lengyel et al. 2001, §2.1), its surface derivatives `∂P/∂u`, `∂P/∂v`
//! are recomputed over the posed triangles (so a stretched skin stretches its texture, as any
//! UV-mapped texture does), and its comb vector turns with the frame it was painted in (a shear
//! relative to the normal, §3, so it turns without stretching). Fins keep their texture interval
//! and stand in the posed edge's plane.

use glam::Vec3;
use rayon::prelude::*;

use super::surface_mesh::{SurfaceMesh, SurfaceVertex};
use crate::FurMesh;
use crate::error::Result;
use crate::mesh::{FaceDerivatives, SplitLayout};

/// What a scene keeps of its rest shape to pose it.
pub struct Deformer {
    /// The rest mesh: its triangles and adjacency give the posed normals.
    rest: FurMesh,
    /// The split vertices and the full mesh's triangles over them (the first level of the
    /// index buffer).
    layout: SplitLayout,
    uv_scale: f64,
    /// Each surface vertex's comb vector in its rest frame `(t, b, n)`, `t` along `∂P/∂u`.
    comb_in_frame: Vec<[f32; 3]>,
    /// Those rest frames, to take a new comb in ([`Deformer::set_comb`]).
    rest_frames: Vec<[Vec3; 3]>,
    /// Each surface vertex's distance to the open border, in tile units: the pose keeps it, as
    /// it keeps the tile UV.
    border: Vec<[f32; 2]>,
    /// The last pose's skin vertices and its triangles' derivatives: kept, so that a pose
    /// allocates neither again (fresh pages cost as much as the arithmetic here).
    surface: Vec<SurfaceVertex>,
    faces: FaceDerivatives,
}

/// The orthonormal frame `(t, b, n)` of a surface vertex: `t` along `∂P/∂u` (tangential), `b`
/// completing it.
fn frame(normal: [f32; 3], dpdu: [f32; 3]) -> [Vec3; 3] {
    let n = Vec3::from(normal);
    let t = Vec3::from(dpdu).normalize_or(n.any_orthonormal_vector());
    [t, n.cross(t), n]
}

impl Deformer {
    /// Keeps what posing needs of `mesh` as `surface` split it.
    pub fn new(mesh: &FurMesh, surface: &SurfaceMesh) -> Self {
        let rest_frames: Vec<[Vec3; 3]> = surface
            .vertices
            .par_iter()
            .map(|v| frame(v.normal, v.dpdu))
            .collect();
        let comb_in_frame = surface
            .vertices
            .par_iter()
            .zip(&rest_frames)
            .map(|(v, axes)| axes.map(|axis| axis.dot(Vec3::from(v.comb))))
            .collect();
        Deformer {
            rest: mesh.clone(),
            layout: SplitLayout::new(
                surface.source.clone(),
                surface.vertices.iter().map(|v| v.uv).collect(),
                surface.indices.clone(),
            ),
            uv_scale: surface.uv_scale,
            comb_in_frame,
            rest_frames,
            border: surface.vertices.iter().map(|v| v.border).collect(),
            surface: surface.vertices.clone(),
            faces: FaceDerivatives::default(),
        }
    }

    /// The full mesh's triangles over the skin's GPU vertices, three indices each.
    pub fn triangles(&self) -> &[u32] {
        &self.layout.indices
    }

    /// The mesh at rest, as given.
    pub fn rest(&self) -> &FurMesh {
        &self.rest
    }

    /// The skin's GPU vertices of the current pose (the rest shape's before any).
    pub fn current(&self) -> &[SurfaceVertex] {
        &self.surface
    }

    /// The skin's GPU vertices at `positions` (one row per mesh vertex) with unit `normals`
    /// given or computed from the posed triangles, and those normals (for the fins' planes,
    /// `fin_pose.rs`).
    ///
    /// # Errors
    /// As [`FurMesh::pose_normals`]: the first bad row of `positions` or `normals`; nothing
    /// changes then.
    pub fn pose(
        &mut self,
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
    ) -> Result<(&[SurfaceVertex], Vec<[f32; 3]>)> {
        let Deformer {
            rest,
            layout,
            uv_scale,
            comb_in_frame,
            border,
            surface,
            faces,
            ..
        } = self;
        let normals = rest.pose_normals(positions, normals)?;
        layout.derivatives_into(
            (positions, &normals),
            rest.triangles(),
            *uv_scale,
            (faces, surface),
            |i, dpdu, dpdv| {
                let v = layout.source[i] as usize;
                let [t, b, n] = frame(normals[v], dpdu);
                let [ct, cb, cn] = comb_in_frame[i];
                SurfaceVertex {
                    position: positions[v],
                    normal: normals[v],
                    dpdu,
                    dpdv,
                    uv: layout.uvs[i],
                    comb: (ct * t + cb * b + cn * n).into(),
                    border: border[i],
                }
            },
        );
        Ok((surface, normals))
    }

    /// Takes `comb` (one row per mesh vertex, object space at rest, checked finite) as the
    /// comb painted on the rest shape, and returns the skin's GPU vertices of the current pose
    /// with it: each vertex's comb turned with its frame, as [`Deformer::pose`] turns it (the
    /// shear of Lengyel et al. 2001, §3, with no patch re-run).
    pub fn set_comb(&mut self, comb: &[[f32; 3]]) -> &[SurfaceVertex] {
        let source = &self.layout.source;
        self.comb_in_frame
            .par_iter_mut()
            .zip(&self.rest_frames)
            .zip(&mut self.surface)
            .enumerate()
            .for_each(|(i, ((in_frame, rest), vertex))| {
                let c = Vec3::from(comb[source[i] as usize]);
                *in_frame = rest.map(|axis| axis.dot(c));
                let [t, b, n] = frame(vertex.normal, vertex.dpdu);
                let [ct, cb, cn] = *in_frame;
                vertex.comb = (ct * t + cb * b + cn * n).into();
            });
        &self.surface
    }
}
