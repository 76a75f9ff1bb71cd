//! Geometric level of detail: simplified versions of the surface that every pass (skin, fins,
//! shells) draws instead of the full mesh where the difference projects to under a pixel.
//! Lengyel et al. 2001 (§4, with Table 1) render fur on low-polygon models and observe that the
//! fur's mottled look hides the coarse silhouettes; the reverse holds too: a dense mesh seen
//! whole gains nothing under fur from triangles a pixel or two across, while a CPU adapter pays
//! for each of them (vertex work and triangle setup run on one thread, and tiny triangles leave
//! most of a fragment block idle).
//!
//! Each level is an index buffer over the same surface vertices, so that colors and lengths are
//! updated in place for all levels at once. It is made by quadric edge collapse
//! (meshoptimizer's simplifier) to about a quarter of the triangles of the level above; seams
//! between lapped patches stay put (the simplifier keeps vertices that share a position but
//! differ in attributes on their seam). Besides the positions, the error metric weighs each
//! vertex's tile UV, normal, comb, color, length and distance to the open border, one unit of
//! attribute as far as a tile's size in object units, so that a level neither slides the
//! texture nor smears painted colors and lengths, nor cuts a mesh's corner (a triangle from one
//! border side to the next had the marched shells run past both). A level's error is the sum of its steps' errors, each twice the simplifier's
//! estimate: a bound, in object units, on how far it strays from the full mesh.

use meshopt::{SimplifyOptions, VertexDataAdapter, simplify_scale, simplify_with_attributes_and_locks};

use super::surface_mesh::SurfaceVertex;

/// Each level asks for this fraction of the triangles of the level above.
const REDUCTION: usize = 4;
/// A level is kept only if it has at most half the triangles of the level above (the simplifier
/// stops short where seams and borders leave nothing to collapse).
const MIN_GAIN: usize = 2;
/// No level is made with fewer triangles: below this the geometry costs nothing to draw.
const MIN_TRIANGLES: usize = 256;
/// Attribute floats per vertex: UV 2, normal 3, comb 3, color 4, length 1, border 2.
const ATTRIBUTES: usize = 15;
/// Tile units beyond which the distance to the open border is weighed as this far: the marched
/// shells extrapolate it linearly over a triangle to stop at the border, so a level must keep
/// it linear where a march reaches (at most six fur depths sideways, a few tiles), and beyond
/// it nothing needs holding (a closed piece's [`super::surface_mesh::BORDERLESS`] included).
const BORDER_REACH: f32 = 8.0;
/// The simplifier's error is a quadric estimate: how far the kept vertices lie from the planes
/// of the faces they replace, not how far the new triangles' interiors stray. Against an
/// analytic torus the interiors strayed up to 1.45 times the estimate (beyond the full mesh's
/// own chords), so a level counts twice it.
const ESTIMATE_SLACK: f64 = 2.0;

/// One level: its triangles (three surface vertex indices each) and the bound, in object units,
/// on its distance from the full mesh (0 for the full mesh, level 0).
#[derive(Debug, Clone, PartialEq)]
pub struct GeometryLevel {
    pub indices: Vec<u32>,
    pub error: f64,
}

/// The full mesh (`indices` over `vertices`) as level 0, then coarser levels while they pay.
/// `colors` and `lengths` are per surface vertex; `tile` is a tile's size in object units, the
/// distance one unit of any attribute counts as.
pub fn simplify_levels(
    vertices: &[SurfaceVertex],
    indices: &[u32],
    colors: &[[f32; 4]],
    lengths: &[f32],
    tile: f64,
) -> Vec<GeometryLevel> {
    let mut levels = vec![GeometryLevel {
        indices: indices.to_vec(),
        error: 0.0,
    }];
    if indices.len() / 3 < MIN_GAIN * MIN_TRIANGLES {
        return levels;
    }
    let positions: &[u8] = bytemuck::cast_slice(vertices);
    let Ok(adapter) = VertexDataAdapter::new(positions, size_of::<SurfaceVertex>(), 0) else {
        return levels;
    };
    let scale = f64::from(simplify_scale(&adapter));
    // The simplifier scales positions to the mesh's extent and weighs attributes against that.
    let weight = tile / scale;
    if !(weight.is_finite() && weight > 0.0) {
        return levels;
    }
    let attributes: Vec<f32> = vertices
        .iter()
        .zip(colors.iter().zip(lengths))
        .flat_map(|(v, (color, &length))| {
            let mut row = [0.0f32; ATTRIBUTES];
            row[..2].copy_from_slice(&v.uv);
            row[2..5].copy_from_slice(&v.normal);
            row[5..8].copy_from_slice(&v.comb);
            row[8..12].copy_from_slice(color);
            row[12] = length;
            row[13..].copy_from_slice(&v.border.map(|d| d.min(BORDER_REACH)));
            row
        })
        .collect();
    let weights = [weight as f32; ATTRIBUTES];
    let unlocked = vec![false; vertices.len()];
    while let Some(above) = levels.last() {
        let triangles = above.indices.len() / 3;
        if triangles / REDUCTION < MIN_TRIANGLES {
            break;
        }
        let mut step = 0.0f32;
        let indices = simplify_with_attributes_and_locks(
            &above.indices,
            &adapter,
            &attributes,
            &weights,
            ATTRIBUTES * size_of::<f32>(),
            &unlocked,
            3 * (triangles / REDUCTION),
            f32::MAX,
            SimplifyOptions::ErrorAbsolute,
            Some(&mut step),
        );
        if MIN_GAIN * indices.len() > above.indices.len() || !step.is_finite() {
            break;
        }
        let error = above.error + ESTIMATE_SLACK * f64::from(step);
        levels.push(GeometryLevel { indices, error });
    }
    levels
}

/// The coarsest of `errors` (ascending, object units; level 0 first) within `most_pixels` at
/// `pixels_per_unit`, the finest scale the object is seen at; level 0 without a scale (the camera
/// inside the object's bounds) or with `most_pixels` 0.
pub fn choose(errors: &[f64], pixels_per_unit: Option<f64>, most_pixels: f32) -> usize {
    let Some(ppu) = pixels_per_unit.filter(|_| most_pixels > 0.0) else {
        return 0;
    };
    errors
        .iter()
        .rposition(|&e| e * ppu <= f64::from(most_pixels))
        .unwrap_or(0)
}

/// The distinct edges `[a, b]` (`a < b`) of `triangles` (three indices each) after mapping each
/// index through `source`, in ascending order.
pub fn edges(triangles: &[u32], source: &[u32]) -> Vec<[u32; 2]> {
    let mut edges: Vec<[u32; 2]> = triangles
        .chunks_exact(3)
        .flat_map(|t| (0..3).map(move |k| [t[k], t[(k + 1) % 3]]))
        .map(|[a, b]| [source[a as usize], source[b as usize]])
        .filter(|[a, b]| a != b)
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

#[cfg(test)]
pub mod tests {
    use super::*;
    use crate::mesh::shapes::{square, torus, torus_uvs};
    use crate::scene::surface_mesh;
    use crate::{FurMesh, MeshInput};

    const MAJOR: f64 = 1.0;
    const MINOR: f64 = 0.35;

    /// Distance from `p` to the torus of [`torus`] (major radius 1, minor 0.35, around z).
    fn torus_distance(p: [f64; 3]) -> f64 {
        let ring = p[0].hypot(p[1]) - MAJOR;
        (ring.hypot(p[2]) - MINOR).abs()
    }

    /// The farthest from the torus of the points at barycentric (i, j, k) / 8 of each triangle.
    fn farthest(vertices: &[SurfaceVertex], indices: &[u32]) -> f64 {
        let mut most = 0.0f64;
        for t in indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|v| vertices[v as usize].position.map(f64::from));
            for i in 0..=8 {
                for j in 0..=8 - i {
                    let (u, v) = (f64::from(i) / 8.0, f64::from(j) / 8.0);
                    let w = 1.0 - u - v;
                    let p = std::array::from_fn(|k| u * a[k] + v * b[k] + w * c[k]);
                    most = most.max(torus_distance(p));
                }
            }
        }
        most
    }

    const AROUND: usize = 128;

    /// A torus of 128 × 64 quads with tile UVs 12 × 4 tiles around, as the GPU vertices split.
    pub fn dense_torus() -> (FurMesh, surface_mesh::SurfaceMesh) {
        let (around, across) = (AROUND, 64);
        let (positions, triangles) = torus(around, across);
        let mesh = FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap();
        let surface = surface_mesh::build(&mesh, &torus_uvs(around, across, [12.0, 4.0])).unwrap();
        (mesh, surface)
    }

    /// The levels of `surface` under white and `lengths` (per surface vertex).
    pub fn levels_of(surface: &surface_mesh::SurfaceMesh, lengths: &[f32]) -> Vec<GeometryLevel> {
        let colors = vec![[1.0; 4]; surface.vertices.len()];
        simplify_levels(
            &surface.vertices,
            &surface.indices,
            &colors,
            lengths,
            1.0 / surface.uv_scale,
        )
    }

    #[test]
    fn each_level_halves_the_triangles_at_least_and_strays_no_further_than_its_bound() {
        let (_, surface) = dense_torus();
        let levels = levels_of(&surface, &vec![1.0; surface.vertices.len()]);
        assert!(levels.len() >= 3, "{} levels", levels.len());
        assert_eq!(levels[0].indices, surface.indices);
        assert_eq!(levels[0].error, 0.0);
        // The full mesh's own chords: how far a flat triangle of it lies from the torus.
        let chord = farthest(&surface.vertices, &surface.indices);
        for pair in levels.windows(2) {
            assert!(2 * pair[1].indices.len() <= pair[0].indices.len());
            assert!(pair[1].error >= pair[0].error);
        }
        for (k, level) in levels.iter().enumerate() {
            assert!(
                level
                    .indices
                    .iter()
                    .all(|&v| (v as usize) < surface.vertices.len())
            );
            let strays = farthest(&surface.vertices, &level.indices);
            // Checked against the analytic surface, beyond the full mesh's own chords.
            assert!(
                strays <= level.error + chord,
                "level {k}: {} triangles stray {strays:.5} from the torus, bound {:.5} (chord {chord:.5})",
                level.indices.len() / 3,
                level.error
            );
        }
    }

    #[test]
    fn levels_keep_a_painted_bald_band_and_the_same_input_gives_the_same_levels() {
        let (_, surface) = dense_torus();
        // Bald over the first quarter turn of the ring.
        let lengths: Vec<f32> = surface
            .vertices
            .iter()
            .map(|v| {
                if v.position[0] > 0.0 && v.position[1] > 0.0 {
                    0.0
                } else {
                    1.0
                }
            })
            .collect();
        let levels = levels_of(&surface, &lengths);
        assert_eq!(levels, levels_of(&surface, &lengths));
        // The ring angle of a vertex: the band's edges run across the tube at angles 0 and 90°.
        let angle = |v: u32| {
            let p = surface.vertices[v as usize].position;
            f64::from(p[1]).atan2(f64::from(p[0]))
        };
        let step = std::f64::consts::TAU / AROUND as f64;
        // A level within a tenth of a tile keeps the band's edges sharp: an edge from a bald
        // vertex to a haired one spans at most two of the full mesh's steps around the ring
        // (one in the full mesh), however far it runs along the edge.
        let tile = 1.0 / surface.uv_scale;
        let kept: Vec<_> = levels.iter().skip(1).filter(|l| l.error < 0.1 * tile).collect();
        assert!(!kept.is_empty(), "no level within a tenth of a tile");
        for level in kept {
            for t in level.indices.chunks_exact(3) {
                for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                    if lengths[a as usize] != lengths[b as usize] {
                        let turn = (angle(a) - angle(b)).abs();
                        let turn = turn.min(std::f64::consts::TAU - turn);
                        assert!(
                            turn <= 2.0 * step + 1e-6,
                            "an edge spans {:.2} steps across the band's edge",
                            turn / step
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn levels_keep_the_distance_to_a_square_patchs_border_linear_within_their_bound() {
        // A flat 2 × 2 patch of 64 × 64 quads, tile 0.3: its border distances are min and max of
        // 1 − |x| and 1 − |y|, creased along the diagonals, which a level that cut a corner
        // would flatten.
        let (positions, triangles) = square(64);
        let mesh = FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap();
        let uvs: Vec<[[f32; 2]; 3]> = triangles
            .iter()
            .map(|t| t.map(|v| positions[v as usize]).map(|p| [p[0] / 0.3, p[1] / 0.3]))
            .collect();
        let surface = surface_mesh::build(&mesh, &uvs).unwrap();
        let tile = 1.0 / surface.uv_scale;
        let levels = levels_of(&surface, &vec![1.0; surface.vertices.len()]);
        assert!(levels.len() >= 3, "{} levels", levels.len());
        let strays = |indices: &[u32]| {
            let mut most = 0.0f64;
            for t in indices.chunks_exact(3) {
                let [a, b, c] = [t[0], t[1], t[2]].map(|v| surface.vertices[v as usize]);
                for (u, v) in [(1.0, 1.0), (2.0, 1.0), (1.0, 2.0), (0.5, 0.5), (2.5, 0.25)] {
                    let (u, v) = (u / 3.0, v / 3.0);
                    let w = 1.0 - u - v;
                    let p: [f64; 2] = std::array::from_fn(|i| {
                        u * f64::from(a.position[i])
                            + v * f64::from(b.position[i])
                            + w * f64::from(c.position[i])
                    });
                    // The nearest side and the one across it.
                    let (x, y) = ((1.0 - p[0].abs()) / tile, (1.0 - p[1].abs()) / tile);
                    for (k, truth) in [x.min(y), x.max(y)].into_iter().enumerate() {
                        let drawn = u * f64::from(a.border[k])
                            + v * f64::from(b.border[k])
                            + w * f64::from(c.border[k]);
                        most = most.max((drawn - truth).abs());
                    }
                }
            }
            most
        };
        // The full mesh's own cells across a crease.
        let own = strays(&levels[0].indices);
        for (k, level) in levels.iter().enumerate() {
            let most = strays(&level.indices);
            // Tile units of border distance count as tiles of object distance.
            assert!(
                most <= (level.error / tile) + own + 1e-4,
                "level {k}: the border distance strays {most:.4} tiles, bound {:.4} (+ {own:.4})",
                level.error / tile
            );
        }
    }

    #[test]
    fn the_coarsest_level_within_the_pixels_is_chosen() {
        let errors = [0.0, 0.001, 0.01, 0.1];
        assert_eq!(choose(&errors, Some(100.0), 1.0), 2);
        assert_eq!(choose(&errors, Some(1000.0), 1.0), 1);
        assert_eq!(choose(&errors, Some(1.0), 1.0), 3);
        assert_eq!(choose(&errors, Some(1.0), 0.0), 0);
        assert_eq!(choose(&errors, None, 1.0), 0);
        assert_eq!(choose(&[0.0, 0.0], Some(10.0), 0.0), 0);
    }

    #[test]
    fn edges_are_distinct_mesh_vertex_pairs() {
        // Two triangles over four surface vertices; surface vertex 3 is a seam copy of mesh
        // vertex 0.
        let source = [0, 1, 2, 0];
        let triangles = [0, 1, 2, 2, 1, 3];
        assert_eq!(edges(&triangles, &source), [[0, 1], [0, 2], [1, 2]]);
    }
}
