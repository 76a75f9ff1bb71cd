//! `FurMesh`: the validated input every later stage reads.
//!
//! Positions, triangles and the optional per-vertex attributes of DESIGN.md §3 (`pelt_color`,
//! `pelt_comb`, `pelt_length`) arrive as borrowed slices ([`MeshInput`]) and are checked once
//! ([`validate`]); then the mesh builds what the stages share: the edge map with 64-bit edge keys
//! (as in the hybrid-fur paper's prism adjacency), vertex→face adjacency and connected components
//! ([`topology`]), area-weighted vertex normals and per-vertex tangent frames ([`frames`]),
//! statistics ([`stats`]) and the bounding sphere ([`bounding_sphere`]). For consumers that store one UV per vertex (the renderer, glTF) the
//! mesh is split at the seams of the lapped patches' UVs ([`uv_split`]); fins stand on its edges
//! ([`fins`]) and shells off its skin ([`shell_offset`]). Degenerate (zero-area) triangles and
//! non-manifold edges are accepted and counted: later stages must cope with them, never crash on
//! them.

mod border_distance;
mod bounds;
pub mod fins;
mod frames;
pub mod gltf_read;
pub mod obj;
pub mod shapes;
pub mod shell_offset;
mod stats;
mod topology;
pub mod uv_split;
mod validate;

pub use border_distance::border_distances;
pub use bounds::bounding_sphere;
pub use fins::{FinQuad, fin_plane, fin_quads, fin_quads_of_edges, midpoint, quad_triangles};
pub use frames::orthonormal_basis;
pub use stats::MeshStats;
pub use topology::{Edge, NO_COMPONENT, NO_EDGE, Topology, edge_key};
pub use uv_split::{FaceDerivatives, SplitLayout, UvSplit, split_at_uv_seams};

use crate::error::Result;
use crate::params::Range;
use crate::threads::pool;

/// Largest allowed hair length multiplier (`pelt_length`).
pub const MAX_LENGTH: f32 = 1e3;

/// Longest fur at length multiplier 1, object units.
pub const MAX_FUR_DEPTH: f64 = 1e6;

/// The fur's height at length multiplier 1: one range for the bake, the renderer and the exports
/// (a fur of no height has no shells to stand apart; switch the fur off instead).
pub const FUR_DEPTH: Range = Range::open_below("fur_depth", 0.0, MAX_FUR_DEPTH, "object units");

/// Borrowed input arrays for [`FurMesh::new`]. Row `i` of every per-vertex array belongs to vertex `i`.
#[derive(Debug, Clone, Copy)]
pub struct MeshInput<'a> {
    /// Vertex positions, object space.
    pub positions: &'a [[f32; 3]],
    /// Triangles as vertex indices, counter-clockwise seen from outside.
    pub triangles: &'a [[u32; 3]],
    /// Vertex normals; computed (area-weighted) when `None`. Need not be unit length.
    pub normals: Option<&'a [[f32; 3]]>,
    /// Hair color, linear RGBA (`pelt_color`).
    pub color: Option<&'a [[f32; 4]]>,
    /// Comb vectors, object space (`pelt_comb`).
    pub comb: Option<&'a [[f32; 3]]>,
    /// Hair length multipliers in `[0, MAX_LENGTH]`, 0 = bald (`pelt_length`).
    pub length: Option<&'a [f32]>,
    /// Per triangle, the polygon it was cut from (Blender's loop triangles): triangles with the
    /// same value are kept in one lapped patch. Any values; only equality matters.
    pub polygons: Option<&'a [u32]>,
}

impl<'a> MeshInput<'a> {
    /// Positions and triangles only; attach attributes with the `with_*` methods.
    pub fn new(positions: &'a [[f32; 3]], triangles: &'a [[u32; 3]]) -> Self {
        MeshInput {
            positions,
            triangles,
            normals: None,
            color: None,
            comb: None,
            length: None,
            polygons: None,
        }
    }

    /// Sets vertex normals.
    pub fn with_normals(mut self, normals: &'a [[f32; 3]]) -> Self {
        self.normals = Some(normals);
        self
    }

    /// Sets hair colors.
    pub fn with_color(mut self, color: &'a [[f32; 4]]) -> Self {
        self.color = Some(color);
        self
    }

    /// Sets comb vectors.
    pub fn with_comb(mut self, comb: &'a [[f32; 3]]) -> Self {
        self.comb = Some(comb);
        self
    }

    /// Sets hair length multipliers.
    pub fn with_length(mut self, length: &'a [f32]) -> Self {
        self.length = Some(length);
        self
    }

    /// Sets the polygon index of every triangle (one row per triangle).
    pub fn with_polygons(mut self, polygons: &'a [u32]) -> Self {
        self.polygons = Some(polygons);
        self
    }
}

/// A validated triangle mesh with its derived adjacency, normals and frames.
#[derive(Debug, Clone)]
pub struct FurMesh {
    positions: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
    normals: Vec<[f32; 3]>,
    normals_given: bool,
    tangents: Vec<[f32; 3]>,
    bitangents: Vec<[f32; 3]>,
    color: Option<Vec<[f32; 4]>>,
    comb: Option<Vec<[f32; 3]>>,
    length: Option<Vec<f32>>,
    polygons: Option<Vec<u32>>,
    degenerate: Vec<bool>,
    topology: Topology,
    stats: MeshStats,
}

impl FurMesh {
    /// Validates `input` and builds the edge map, normals, tangent frames and statistics.
    ///
    /// Runs in Pelt's thread pool; the result does not depend on the thread count.
    ///
    /// # Errors
    /// [`crate::PeltError::InvalidMesh`] naming the first bad element: an empty mesh, a NaN or
    /// infinity, an index out of range, an attribute array of the wrong length, a length outside
    /// `[0, MAX_LENGTH]`, a zero-length given normal, or a polygon array whose length is not the
    /// triangle count.
    pub fn new(input: MeshInput<'_>) -> Result<Self> {
        pool().install(|| Self::build(input))
    }

    fn build(input: MeshInput<'_>) -> Result<Self> {
        validate::validate(&input)?;
        let positions = input.positions.to_vec();
        let triangles = input.triangles.to_vec();
        let topology = Topology::build(positions.len(), &triangles);
        let face_normals = frames::face_normals(&positions, &triangles);
        let degenerate = frames::degenerate_faces(&positions, &triangles, &face_normals);
        let normals = match input.normals {
            Some(given) => frames::normalize_given(given),
            None => frames::vertex_normals(&topology, &face_normals),
        };
        let (tangents, bitangents) = frames::tangent_frames(&normals);
        let stats = MeshStats::compute(&positions, &triangles, &topology, &face_normals, &degenerate);
        Ok(FurMesh {
            positions,
            triangles,
            normals,
            normals_given: input.normals.is_some(),
            tangents,
            bitangents,
            color: input.color.map(<[_]>::to_vec),
            comb: input.comb.map(<[_]>::to_vec),
            length: input.length.map(<[_]>::to_vec),
            polygons: input.polygons.map(<[_]>::to_vec),
            degenerate,
            topology,
            stats,
        })
    }

    /// Unit vertex normals of this mesh's vertices and triangles moved to `positions` (a pose
    /// of it: one row per vertex, the same triangles): `normals` scaled to unit length when
    /// given, else area-weighted as [`FurMesh::new`] computes them. What a renderer needs to
    /// follow a skinned or shape-keyed mesh without building a new one.
    ///
    /// # Errors
    /// [`crate::PeltError::InvalidMesh`] naming the first bad row of `positions` or `normals`
    /// (wrong row count, a NaN or infinity, a zero normal), as [`FurMesh::new`] would.
    pub fn pose_normals(
        &self,
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
    ) -> Result<Vec<[f32; 3]>> {
        pool().install(|| {
            validate::validate_pose(positions, normals, self.positions.len())?;
            Ok(match normals {
                Some(given) => frames::normalize_given(given),
                None => {
                    frames::vertex_normals(&self.topology, &frames::face_normals(positions, &self.triangles))
                }
            })
        })
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[[f32; 3]] {
        &self.positions
    }

    /// Triangles.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Unit vertex normals (given ones normalized, or area-weighted ones).
    pub fn normals(&self) -> &[[f32; 3]] {
        &self.normals
    }

    /// Whether the normals came with the input rather than being computed.
    pub fn normals_given(&self) -> bool {
        self.normals_given
    }

    /// Unit tangent per vertex, orthogonal to the normal: the reference direction of the vertex's
    /// tangent frame (angles of the comb field are measured from it).
    pub fn tangents(&self) -> &[[f32; 3]] {
        &self.tangents
    }

    /// `normal × tangent` per vertex, completing a right-handed frame.
    pub fn bitangents(&self) -> &[[f32; 3]] {
        &self.bitangents
    }

    /// Hair colors, if given.
    pub fn color(&self) -> Option<&[[f32; 4]]> {
        self.color.as_deref()
    }

    /// Comb vectors, if given.
    pub fn comb(&self) -> Option<&[[f32; 3]]> {
        self.comb.as_deref()
    }

    /// Hair length multipliers, if given.
    pub fn length(&self) -> Option<&[f32]> {
        self.length.as_deref()
    }

    /// Polygon index per triangle, if given.
    pub fn polygons(&self) -> Option<&[u32]> {
        self.polygons.as_deref()
    }

    /// Per triangle: true when it has (numerically) zero area.
    pub fn degenerate_faces(&self) -> &[bool] {
        &self.degenerate
    }

    /// Edge map and adjacency.
    pub fn topology(&self) -> &Topology {
        &self.topology
    }

    /// Counts, area and bounding box.
    pub fn stats(&self) -> &MeshStats {
        &self.stats
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn face_count(&self) -> usize {
        self.triangles.len()
    }
}

#[cfg(test)]
mod tests;
