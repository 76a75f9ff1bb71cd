//! The per-vertex arrays both glTF modes write: the mesh split at patch seams
//! ([`crate::mesh::uv_split`], the renderer's own split) with every attribute gathered per split
//! vertex, in glTF's conventions (unit normals, colors in `[0, 1]`).

use super::super::input::ExportInput;
use crate::error::Result;
use crate::mesh::{UvSplit, split_at_uv_seams};

/// Hair color where the mesh has none: white, so the texture's own color shows (as the renderer).
const DEFAULT_COLOR: [f32; 4] = [1.0; 4];
/// Length multiplier where the mesh has none.
const DEFAULT_LENGTH: f32 = 1.0;

/// One object's split vertices and their attributes.
pub(super) struct SplitVertices {
    pub split: UvSplit,
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    /// Linear RGBA clamped to `[0, 1]` (glTF's range for `COLOR_0`).
    pub colors: Vec<[f32; 4]>,
    pub comb: Vec<[f32; 3]>,
    pub lengths: Vec<f32>,
}

impl SplitVertices {
    /// Splits `input`'s mesh at its UV seams and gathers the attributes.
    ///
    /// # Errors
    /// As [`split_at_uv_seams`].
    pub fn new(input: &ExportInput<'_>) -> Result<Self> {
        let mesh = input.mesh;
        let split = split_at_uv_seams(mesh, input.corner_uvs)?;
        let positions = split.expand(mesh.positions());
        let normals = split.expand(mesh.normals());
        let colors = match mesh.color() {
            Some(c) => split
                .expand(c)
                .into_iter()
                .map(|c| c.map(|v| v.clamp(0.0, 1.0)))
                .collect(),
            None => vec![DEFAULT_COLOR; split.len()],
        };
        let comb = match mesh.comb() {
            Some(c) => split.expand(c),
            None => vec![[0.0; 3]; split.len()],
        };
        let lengths = match mesh.length() {
            Some(l) => split.expand(l),
            None => vec![DEFAULT_LENGTH; split.len()],
        };
        Ok(SplitVertices {
            split,
            positions,
            normals,
            colors,
            comb,
            lengths,
        })
    }

    /// Length multipliers per mesh vertex (1 where the mesh has none).
    pub fn mesh_lengths(input: &ExportInput<'_>) -> Vec<f32> {
        input.mesh.length().map_or_else(
            || vec![DEFAULT_LENGTH; input.mesh.vertex_count()],
            <[f32]>::to_vec,
        )
    }

    /// Indices of the triangles that grow hair: not bald at all three corners (the renderer
    /// discards a shell fragment where the interpolated length is 0, which inside a triangle
    /// happens only when all three corners are 0).
    pub fn furred_indices(&self) -> Vec<u32> {
        self.split
            .indices
            .chunks_exact(3)
            .filter(|t| t.iter().any(|&v| self.lengths[v as usize] > 0.0))
            .flatten()
            .copied()
            .collect()
    }
}
