//! A scene's geometric levels of detail made ready to upload: the simplified triangles of
//! [`super::geometry_lod`] one after another in one surface index buffer, the fins of each
//! level's edges ([`super::fin_mesh`]), and where each level stands after a repaint
//! ([`super::level_hosts`]).

use std::ops::Range;

use super::fin_mesh::{self, FinMesh};
use super::geometry_lod;
use super::level_hosts::LevelHosts;
use super::surface_mesh::{SurfaceMesh, first_copies};
use crate::FurMesh;
use crate::mesh::{fin_quads, fin_quads_of_edges};

/// One geometric level of detail of a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshLevel {
    /// Object units the level may stray from the full mesh.
    pub error: f64,
    /// Its triangles in the surface index buffer.
    pub indices: Range<u32>,
    /// Its fins (numbered across levels).
    pub fins: Range<u32>,
    /// Its fins' mean edge length over the full mesh's: fins stand this many times as far
    /// apart, and `fins.wgsl` scales each one's opacity by it (up to opaque), so that as much
    /// light passes them as the full mesh's fins.
    pub fin_spacing: f32,
}

/// Every level of a scene.
pub struct SceneLevels {
    /// The full mesh first.
    pub levels: Vec<MeshLevel>,
    /// The triangles of every level, one level after another.
    pub surface_indices: Vec<u32>,
    pub fins: FinMesh,
    /// Where the vertices each coarser level dropped lie on it (levels 1 on).
    pub hosts: Vec<LevelHosts>,
}

impl SceneLevels {
    /// Simplifies `surface` (split from `mesh`) under the colors and lengths it is uploaded
    /// with: `attributes` per mesh vertex, `surface_attributes` the same per surface vertex.
    pub fn new(
        mesh: &FurMesh,
        surface: &SurfaceMesh,
        attributes: (&[[f32; 4]], &[f32]),
        surface_attributes: (&[[f32; 4]], &[f32]),
    ) -> Self {
        let tile = 1.0 / surface.uv_scale;
        let made = geometry_lod::simplify_levels(
            &surface.vertices,
            &surface.indices,
            surface_attributes.0,
            surface_attributes.1,
            tile,
        );
        let level_fins: Vec<_> = made
            .iter()
            .enumerate()
            .map(|(k, level)| match k {
                0 => fin_quads(mesh, surface.uv_scale),
                _ => fin_quads_of_edges(
                    mesh,
                    geometry_lod::edges(&level.indices, &surface.source),
                    surface.uv_scale,
                ),
            })
            .collect();
        let first = first_copies(&surface.source, mesh.vertex_count());
        let fins = fin_mesh::build(&level_fins, &first);
        let hosts = made
            .iter()
            .skip(1)
            .map(|level| {
                LevelHosts::new(
                    &surface.vertices,
                    &surface.source,
                    &level.indices,
                    attributes,
                    level.error,
                    tile,
                )
            })
            .collect();
        let mut start = 0;
        let levels = made
            .iter()
            .zip(&fins.levels)
            .zip(&fins.spacing)
            .map(|((level, fins), &fin_spacing)| {
                let indices = start..start + level.indices.len() as u32;
                start = indices.end;
                MeshLevel {
                    error: level.error,
                    indices,
                    fins: fins.clone(),
                    fin_spacing,
                }
            })
            .collect();
        SceneLevels {
            levels,
            surface_indices: made.into_iter().flat_map(|l| l.indices).collect(),
            fins,
            hosts,
        }
    }
}

/// How many levels, finest first, still stand for the full mesh under these colors and lengths
/// (per mesh vertex): the full mesh and every coarser level up to the first that would smear
/// them.
pub fn drawable(hosts: &[LevelHosts], colors: &[[f32; 4]], lengths: &[f32]) -> usize {
    1 + hosts.iter().take_while(|h| h.holds(colors, lengths)).count()
}
