//! The per-vertex arrays both glTF modes write: the mesh split at patch seams
//! ([`crate::mesh::uv_split`], the renderer's own split) with every attribute gathered per split
//! vertex, in glTF's conventions (unit normals, colors in `[0, 1]`).

use super::super::input::ExportInput;
use crate::error::{PeltError, Result};
use crate::mesh::shell_offset::lifted;
use crate::mesh::{UvSplit, split_at_uv_seams};
use crate::threads::pool;
use rayon::prelude::*;

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

    /// Checks the surface derivatives: a UV layout whose triangles are almost collapsed in the tile
    /// can push them past the f32 range, and glTF accessors must hold finite values.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `corner_uvs` and the mesh vertex.
    pub fn check_derivatives(&self) -> Result<()> {
        let bad = |d: &[[f32; 3]]| d.iter().position(|v| !v.iter().all(|c| c.is_finite()));
        if let Some(i) = bad(&self.split.dpdu).or_else(|| bad(&self.split.dpdv)) {
            return Err(PeltError::parameter(
                "corner_uvs",
                format!(
                    "the UVs around mesh vertex {} are so compressed that dP/du or dP/dv exceeds the \
                     f32 range",
                    self.split.source[i]
                ),
            ));
        }
        Ok(())
    }

    /// Length multipliers per mesh vertex (1 where the mesh has none).
    pub fn mesh_lengths(input: &ExportInput<'_>) -> Vec<f32> {
        input.mesh.length().map_or_else(
            || vec![DEFAULT_LENGTH; input.mesh.vertex_count()],
            <[f32]>::to_vec,
        )
    }

    /// The vertices lifted to each of `layers` (`layer · spacing · fur_depth · length` along the
    /// combed normal), one position list per layer, in parallel.
    ///
    /// # Errors
    /// As [`check_lifted`].
    pub fn lift(&self, input: &ExportInput<'_>, layers: &[usize]) -> Result<Vec<Vec<[f32; 3]>>> {
        let spacing = input.volume.layer_spacing;
        let lifted_layers: Vec<Vec<[f32; 3]>> = pool().install(|| {
            layers
                .par_iter()
                .map(|&layer| {
                    let height = layer as f64 * spacing;
                    (0..self.positions.len())
                        .map(|i| {
                            lifted(
                                self.positions[i],
                                self.normals[i],
                                self.comb[i],
                                height,
                                input.fur_depth,
                                self.lengths[i],
                            )
                        })
                        .collect()
                })
                .collect()
        });
        for positions in &lifted_layers {
            check_lifted(positions, |i| self.split.source[i])?;
        }
        Ok(lifted_layers)
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

/// Checks lifted positions (shells or fins): the offset `fur_depth · length · (n + c − n (n · c))`
/// can leave the f32 range for a huge comb vector, and glTF accessors must hold finite values.
/// `vertex(i)` is the mesh vertex of position `i`.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `comb[v]` of the first vertex whose position is not
/// finite.
pub(super) fn check_lifted(positions: &[[f32; 3]], vertex: impl Fn(usize) -> u32) -> Result<()> {
    match positions.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        None => Ok(()),
        Some(i) => {
            let v = vertex(i);
            Err(PeltError::parameter(
                format!("comb[{v}]"),
                format!(
                    "lifts vertex {v} out of the f32 range (position + fur_depth · length · \
                     (n + comb − n (n · comb)) is not finite)"
                ),
            ))
        }
    }
}
