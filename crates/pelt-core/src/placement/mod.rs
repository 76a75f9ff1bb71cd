//! The tile's strands placed over a mesh: every strand instantiated wherever a triangle's patch
//! UVs cover its root, every point carried to object space by the map of the triangle whose UVs
//! hold it, lifted along the shells' growth direction and by the same per-vertex length
//! (`mesh::shell_offset`), with its radius scaled from tile to object units.
//!
//! Lengyel et al. 2001, §2.2 sample the shells from hair grown in a toroidal tile; a shell at
//! height `h` is the mesh lifted by `h · fur_depth · length · g` with the growth direction `g`,
//! interpolated linearly over each triangle. A tile point `(x, y, z)` on a triangle with corner
//! UVs `uv_k` therefore stands at `Σ b_k (P_k + z · up_k)`, `b` the barycentric coordinates of
//! `(x, y)` among the `uv_k`. A point past the patch's border is clamped to the last triangle and
//! taken the rest of the way along its `∂P/∂u`, `∂P/∂v` (`placer.rs`). Placed strands therefore stand exactly where the shells show them: the
//! reference renderer traces all of them, the guard hairs draw the overcoat's.
//!
//! Files: `grid.rs` (roots by tile cell), `placer.rs` (one strand to object space).

mod grid;
mod placer;

use glam::{Vec2, Vec3, Vec3A};
use rayon::prelude::*;

use crate::error::{PeltError, Result};
use crate::hair::Strand;
use crate::lapped::{NO_PATCH, Patches};
use crate::mesh::FurMesh;
use crate::mesh::shell_offset::growth;
use crate::threads::pool;
use grid::RootGrid;
use placer::Placer;

/// Where a strand's points live in [`PlacedStrands::points`], and its colors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrandSpan {
    /// Index of the strand's root in the points.
    pub first: u32,
    /// Points of the strand, root first.
    pub count: u32,
    /// Linear albedo at the root (the strand's color times the mesh's painted color).
    pub root_color: Vec3,
    /// Linear albedo at the tip.
    pub tip_color: Vec3,
    /// The mesh triangle the root stands on ([`NO_TRIANGLE`] for strands given in object space).
    pub triangle: u32,
    /// The root's barycentric weights in that triangle, by corner.
    pub weights: [f32; 3],
}

/// [`StrandSpan::triangle`] of a strand that stands on no triangle of a mesh.
pub const NO_TRIANGLE: u32 = u32::MAX;

/// Strands in object space: their points (xyz and radius) one strand after another, and where
/// each strand's points are.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PlacedStrands {
    /// Every strand point: xyz and radius, object units.
    pub points: Vec<[f32; 4]>,
    /// Per strand, in triangle order (and tile-strand order within a triangle).
    pub spans: Vec<StrandSpan>,
}

/// `strands` (the tile's, from `grow_strands`) placed over `mesh` through the `patches`' corner
/// UVs, `fur_depth` object units tall at length multiplier 1 and colored by the strand's colors
/// times the mesh's painted color at the root. Roots on a bald spot (length 0) are left out.
/// `limit(strands, points)` sees the counts before anything is allocated and may refuse them.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `patches` when they do not belong to the mesh;
/// whatever `limit` returns.
pub fn place_strands(
    mesh: &FurMesh,
    patches: &Patches,
    strands: &[Strand],
    fur_depth: f32,
    limit: impl FnOnce(usize, usize) -> Result<()>,
) -> Result<PlacedStrands> {
    if patches.uv.len() != mesh.face_count() || patches.patch.len() != mesh.face_count() {
        return Err(PeltError::parameter(
            "patches",
            format!(
                "hold {} triangles, the mesh has {}",
                patches.uv.len(),
                mesh.face_count()
            ),
        ));
    }
    let placer = Placer::new(mesh, patches, fur_depth);
    let roots = RootGrid::new(strands);
    let tris = mesh.triangles();
    // Count first, so the sizes are checked before the points are allocated.
    let counts: Vec<(usize, usize)> = pool().install(|| {
        (0..tris.len())
            .into_par_iter()
            .map(|t| {
                if patches.patch[t] == NO_PATCH {
                    return (0, 0);
                }
                let (mut s, mut n) = (0, 0);
                roots.visit(&patches.uv[t], |k, di, dj| {
                    if placer
                        .root_weights(t, &patches.uv[t], &strands[k], [di, dj])
                        .is_some()
                    {
                        s += 1;
                        n += strands[k].points.len();
                    }
                });
                (s, n)
            })
            .collect()
    });
    let strand_count = counts.iter().map(|c| c.0).sum();
    let point_count = counts.iter().map(|c| c.1).sum();
    limit(strand_count, point_count)?;
    // Each triangle fills its own slice of one buffer: no per-triangle copies to join.
    let mut points = vec![[0.0f32; 4]; point_count];
    let mut slices = Vec::with_capacity(tris.len());
    let mut rest = points.as_mut_slice();
    let mut offset = 0u32;
    for &(_, n) in &counts {
        let (mine, tail) = rest.split_at_mut(n);
        slices.push((offset, mine));
        offset += n as u32;
        rest = tail;
    }
    let per_triangle: Vec<Vec<StrandSpan>> = pool().install(|| {
        slices
            .into_par_iter()
            .enumerate()
            .map(|(t, (offset, out))| {
                let mut spans = Vec::new();
                let mut filled = 0;
                if patches.patch[t] != NO_PATCH {
                    let uv = &patches.uv[t];
                    roots.visit(uv, |k, di, dj| {
                        if let Some(root) = placer.root_weights(t, uv, &strands[k], [di, dj]) {
                            let n = strands[k].points.len();
                            let mut span = placer.place(
                                t,
                                uv,
                                &strands[k],
                                [di, dj],
                                root,
                                &mut out[filled..filled + n],
                            );
                            span.first = offset + filled as u32;
                            filled += n;
                            spans.push(span);
                        }
                    });
                }
                spans
            })
            .collect()
    });
    let mut spans = Vec::with_capacity(strand_count);
    spans.extend(per_triangle.into_iter().flatten());
    Ok(PlacedStrands { points, spans })
}

/// Per vertex: the growth direction × `fur_depth` × the vertex's length, the height a tile
/// point at `z = 1` stands above the skin (as `mesh::shell_offset` lifts the shells).
pub(crate) fn growth_vectors(mesh: &FurMesh, fur_depth: f32) -> Vec<Vec3A> {
    let normals = mesh.normals();
    (0..mesh.vertex_count())
        .map(|v| {
            let comb = mesh.comb().map_or([0.0; 3], |c| c[v]);
            let g = growth(normals[v], comb);
            let length = mesh.length().map_or(1.0, |l| l[v]);
            Vec3A::new(g[0] as f32, g[1] as f32, g[2] as f32) * (fur_depth * length)
        })
        .collect()
}

/// Object units per tile unit across a triangle: √(object area / UV area), in f64 so that the
/// squared lengths of a mesh at ×1e20 (or ×1e-20) neither overflow nor vanish.
pub(crate) fn lateral_scale(uv: &[[f32; 2]; 3], p: &[Vec3A; 3]) -> f32 {
    let [a, b, c] = uv.map(|q| Vec2::from(q).as_dvec2());
    let uv_area = (b - a).perp_dot(c - a).abs();
    let [p0, p1, p2] = p.map(|q| Vec3::from(q).as_dvec3());
    let area = (p1 - p0).cross(p2 - p0).length();
    if uv_area > 0.0 {
        (area / uv_area).sqrt() as f32
    } else {
        0.0
    }
}
