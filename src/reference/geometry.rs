//! The fur as explicit geometry in object space: every strand of the tile, instantiated wherever
//! the lapped patches place its root, plus the skin it grows from.
//!
//! Lengyel et al. 2001, §2.2 sample the shells from hair grown in a toroidal tile; a shell at
//! height `h` is the mesh lifted by `h · fur_depth · length · g` with the growth direction `g`
//! (`mesh::shell_offset`), interpolated linearly over each triangle. A tile point `(x, y, z)` on
//! a triangle with corner UVs `uv_k` therefore stands at `Σ b_k (P_k + z · up_k)`, `b` the
//! barycentric coordinates of `(x, y)` among the `uv_k`. Each strand point is placed by the map
//! of the triangle whose UVs hold it, found by walking from the root's triangle across edges
//! inside its patch (the hybrid paper's neighbour walk through the prisms); a point past the
//! patch's border keeps the last triangle's map, extended linearly.

use glam::{Vec2, Vec3, Vec3A};
use rayon::prelude::*;

use crate::error::{Num, PeltError, Result};
use crate::hair::Strand;
use crate::lapped::{NO_PATCH, Patches};
use crate::mesh::FurMesh;
use crate::mesh::shell_offset::growth;
use crate::mesh::{NO_EDGE, Topology};
use crate::threads::pool;

/// Most strand points the reference holds (about 1 GiB of points): above it the asset is
/// refused before anything is allocated.
pub const MAX_POINTS: usize = 1 << 26;

/// One strand in object space.
#[derive(Debug, Clone, PartialEq)]
pub struct WorldStrand {
    /// Polyline points, root first; at least two.
    pub points: Vec<[f32; 3]>,
    /// Radius at each point, object units, finite and non-negative.
    pub radii: Vec<f32>,
    /// Linear albedo at the root.
    pub root_color: [f32; 3],
    /// Linear albedo at the tip; the albedo is linear in the point index in between.
    pub tip_color: [f32; 3],
}

/// Where a strand's points live in [`FurGeometry::points`] and its colors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StrandSpan {
    pub first: u32,
    pub count: u32,
    pub root_color: Vec3,
    pub tip_color: Vec3,
}

/// The opaque skin under the hair: triangles with smooth normals and a per-vertex albedo.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Skin {
    pub positions: Vec<Vec3A>,
    pub normals: Vec<Vec3A>,
    pub albedo: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

/// The skin at a point of one of its triangles, facing the viewer.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SkinPoint {
    /// Smooth unit normal.
    pub normal: Vec3A,
    /// Unit normal of the triangle's plane.
    pub face: Vec3A,
    pub albedo: Vec3,
}

impl Skin {
    /// Triangle `triangle` at barycentric weights `w`, both normals turned toward `view`.
    pub(crate) fn at(&self, triangle: u32, w: Vec3, view: Vec3A) -> SkinPoint {
        let t = self.triangles[triangle as usize].map(|v| v as usize);
        let p = t.map(|v| self.positions[v]);
        let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        let normal = (0..3)
            .fold(Vec3A::ZERO, |s, k| s + w[k] * self.normals[t[k]])
            .normalize_or(face);
        let albedo = (0..3).fold(Vec3::ZERO, |s, k| s + w[k] * self.albedo[t[k]]);
        let sign = if face.dot(view) < 0.0 { -1.0 } else { 1.0 };
        SkinPoint {
            normal: sign * normal,
            face: sign * face,
            albedo,
        }
    }
}

/// Strands and skin in object space, ready for [`super::ReferenceScene::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct FurGeometry {
    /// Every strand point: xyz and radius.
    pub(crate) points: Vec<[f32; 4]>,
    pub(crate) strands: Vec<StrandSpan>,
    pub(crate) skin: Option<Skin>,
}

impl FurGeometry {
    /// Strands given in object space, without a skin (for tests and hand-made scenes).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] for a strand with fewer than two points, radii that do
    /// not match its points, or a value that is not finite (named `strands[i]`).
    pub fn from_world_strands(strands: &[WorldStrand]) -> Result<Self> {
        let total: usize = strands.iter().map(|s| s.points.len()).sum();
        check_points(total)?;
        let mut points = Vec::with_capacity(total);
        let mut spans = Vec::with_capacity(strands.len());
        for (i, s) in strands.iter().enumerate() {
            let name = format!("strands[{i}]");
            if s.points.len() < 2 || s.radii.len() != s.points.len() {
                return Err(PeltError::parameter(
                    name,
                    format!(
                        "needs at least two points and one radius per point, got {} points and {} radii",
                        s.points.len(),
                        s.radii.len()
                    ),
                ));
            }
            let finite = s.points.iter().flatten().all(|v| v.is_finite())
                && s.radii.iter().all(|r| r.is_finite() && *r >= 0.0)
                && s.root_color.iter().chain(&s.tip_color).all(|c| c.is_finite());
            if !finite {
                return Err(PeltError::parameter(
                    name,
                    "points, colors must be finite and radii finite and non-negative",
                ));
            }
            spans.push(StrandSpan {
                first: points.len() as u32,
                count: s.points.len() as u32,
                root_color: Vec3::from(s.root_color),
                tip_color: Vec3::from(s.tip_color),
            });
            points.extend(s.points.iter().zip(&s.radii).map(|(p, &r)| [p[0], p[1], p[2], r]));
        }
        Ok(FurGeometry {
            points,
            strands: spans,
            skin: None,
        })
    }

    /// The fur of a bake: `strands` (the tile's, from `grow_strands` with the bake's
    /// `HairParams`) placed over `mesh` through the `patches`' corner UVs, `fur_depth` object
    /// units tall at length multiplier 1, colored by the strand's colors times the mesh's
    /// `pelt_color` at the root; and the skin, whose albedo is the strands' mean root color
    /// times `pelt_color` (the shells' opaque layer 0).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] when `fur_depth` is not positive and finite, the patches
    /// do not belong to the mesh, or the fur would need more than [`MAX_POINTS`] points.
    pub fn from_bake(mesh: &FurMesh, patches: &Patches, strands: &[Strand], fur_depth: f64) -> Result<Self> {
        if !(fur_depth.is_finite() && fur_depth > 0.0) {
            return Err(PeltError::parameter(
                "fur_depth",
                format!("must be positive and finite, got {}", Num(fur_depth)),
            ));
        }
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
        let placer = Placer::new(mesh, patches, fur_depth as f32);
        let roots = RootGrid::new(strands);
        let tris = mesh.triangles();
        // Count first, so the size is checked before the points are allocated.
        let counts: Vec<usize> = pool().install(|| {
            (0..tris.len())
                .into_par_iter()
                .map(|t| {
                    if patches.patch[t] == NO_PATCH {
                        return 0;
                    }
                    let mut n = 0;
                    roots.visit(&patches.uv[t], |k, di, dj| {
                        if placer
                            .root_weights(t, &patches.uv[t], &strands[k], [di, dj])
                            .is_some()
                        {
                            n += strands[k].points.len();
                        }
                    });
                    n
                })
                .collect()
        });
        check_points(counts.iter().sum())?;
        // Each triangle fills its own slice of one buffer: no per-triangle copies to join.
        let mut points = vec![[0.0f32; 4]; counts.iter().sum()];
        let mut slices = Vec::with_capacity(tris.len());
        let mut rest = points.as_mut_slice();
        let mut offset = 0u32;
        for &n in &counts {
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
        let spans: Vec<StrandSpan> = per_triangle.into_iter().flatten().collect();
        let mean_root = mean_root_color(strands);
        Ok(FurGeometry {
            points,
            strands: spans,
            skin: Some(skin_of(mesh, mean_root)),
        })
    }

    /// Number of strands.
    pub fn strand_count(&self) -> usize {
        self.strands.len()
    }

    /// Number of strand points.
    pub fn point_count(&self) -> usize {
        self.points.len()
    }

    /// Whether the skin is part of the geometry.
    pub fn has_skin(&self) -> bool {
        self.skin.is_some()
    }
}

fn check_points(total: usize) -> Result<()> {
    if total > MAX_POINTS {
        return Err(PeltError::parameter(
            "strands",
            format!(
                "the fur would need {total} strand points, the reference holds at most {MAX_POINTS}: \
                 lower the hair density or raise the tile size"
            ),
        ));
    }
    Ok(())
}

pub(crate) fn mean_root_color(strands: &[Strand]) -> Vec3 {
    if strands.is_empty() {
        return Vec3::ZERO;
    }
    let sum = strands
        .iter()
        .fold(glam::DVec3::ZERO, |s, k| s + Vec3::from(k.root_color).as_dvec3());
    (sum / strands.len() as f64).as_vec3()
}

/// The strands' roots bucketed in a grid over the unit tile, for finding those a triangle's UVs
/// cover in every tile repeat they span.
struct RootGrid {
    side: usize,
    /// Cell `c`'s strands are `order[start[c]..start[c + 1]]`.
    start: Vec<u32>,
    order: Vec<u32>,
    roots: Vec<Vec2>,
}

impl RootGrid {
    fn new(strands: &[Strand]) -> Self {
        let side = ((strands.len() as f64).sqrt().ceil() as usize).clamp(1, 1024);
        let roots: Vec<Vec2> = strands
            .iter()
            .map(|s| Vec2::new(s.root[0].rem_euclid(1.0) as f32, s.root[1].rem_euclid(1.0) as f32))
            .collect();
        let cell = |p: Vec2| {
            let i = ((p.x * side as f32) as usize).min(side - 1);
            let j = ((p.y * side as f32) as usize).min(side - 1);
            j * side + i
        };
        let mut start = vec![0u32; side * side + 1];
        for &p in &roots {
            start[cell(p) + 1] += 1;
        }
        for c in 0..side * side {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut order = vec![0u32; roots.len()];
        for (k, &p) in roots.iter().enumerate() {
            let c = cell(p);
            order[fill[c] as usize] = k as u32;
            fill[c] += 1;
        }
        RootGrid {
            side,
            start,
            order,
            roots,
        }
    }

    /// Calls `f(strand, tile_x, tile_y)` for every strand whose root, moved to tile repeat
    /// `(tile_x, tile_y)`, lies inside the UV triangle `uv` (in strand order within each cell).
    fn visit(&self, uv: &[[f32; 2]; 3], mut f: impl FnMut(usize, f32, f32)) {
        let [a, b, c] = uv.map(Vec2::from);
        let lo = a.min(b).min(c);
        let hi = a.max(b).max(c);
        let den = (b - a).perp_dot(c - a);
        if den.is_nan() || den.abs() <= 1e-12 || !(hi - lo).is_finite() || (hi - lo).max_element() > 1e4 {
            return;
        }
        let n = self.side as f32;
        for tj in lo.y.floor() as i64..=hi.y.floor() as i64 {
            for ti in lo.x.floor() as i64..=hi.x.floor() as i64 {
                let origin = Vec2::new(ti as f32, tj as f32);
                let (l, h) = ((lo - origin).max(Vec2::ZERO), (hi - origin).min(Vec2::ONE));
                if l.x > h.x || l.y > h.y {
                    continue;
                }
                let (i0, i1) = ((l.x * n) as usize, ((h.x * n) as usize).min(self.side - 1));
                let (j0, j1) = ((l.y * n) as usize, ((h.y * n) as usize).min(self.side - 1));
                for j in j0..=j1 {
                    for i in i0..=i1 {
                        let cell = j * self.side + i;
                        for &k in &self.order[self.start[cell] as usize..self.start[cell + 1] as usize] {
                            let p = self.roots[k as usize] + origin;
                            let w1 = (p - a).perp_dot(c - a) / den;
                            let w2 = (b - a).perp_dot(p - a) / den;
                            if w1 >= 0.0 && w2 >= 0.0 && w1 + w2 <= 1.0 {
                                f(k as usize, origin.x, origin.y);
                            }
                        }
                    }
                }
            }
        }
    }
}

/// Carries tile points to object space through the triangles' maps.
struct Placer<'a> {
    positions: &'a [[f32; 3]],
    triangles: &'a [[u32; 3]],
    patches: &'a Patches,
    topology: &'a Topology,
    colors: Option<&'a [[f32; 4]]>,
    /// Per vertex: the growth direction × fur depth × length.
    up: Vec<Vec3A>,
    lengths: Option<&'a [f32]>,
}

impl<'a> Placer<'a> {
    fn new(mesh: &'a FurMesh, patches: &'a Patches, fur_depth: f32) -> Self {
        let up = growth_vectors(mesh, fur_depth);
        Placer {
            positions: mesh.positions(),
            triangles: mesh.triangles(),
            patches,
            topology: mesh.topology(),
            colors: mesh.color(),
            up,
            lengths: mesh.length(),
        }
    }

    /// Barycentric weights of `p` among the UV corners (extended past the edges).
    fn weights(uv: &[[f32; 2]; 3], p: Vec2) -> Vec3 {
        let [a, b, c] = uv.map(Vec2::from);
        let den = (b - a).perp_dot(c - a);
        let w1 = (p - a).perp_dot(c - a) / den;
        let w2 = (b - a).perp_dot(p - a) / den;
        Vec3::new(1.0 - w1 - w2, w1, w2)
    }

    /// The root's barycentric weights when strand `k`, moved to tile repeat `tile`, stands on
    /// hair (its interpolated length above 0); `None` on a bald spot.
    fn root_weights(&self, t: usize, uv: &[[f32; 2]; 3], strand: &Strand, tile: [f32; 2]) -> Option<Vec3> {
        let root = Vec2::new(strand.root[0] as f32 + tile[0], strand.root[1] as f32 + tile[1]);
        let w = Self::weights(uv, root);
        let tri = self.triangles[t];
        let length = self.lengths.map_or(1.0, |l| w_dot(w, tri.map(|v| l[v as usize])));
        (length > 1e-6).then_some(w)
    }

    /// Writes strand points into `out`; the span's `first` is the caller's to set.
    fn place(
        &self,
        t: usize,
        uv: &[[f32; 2]; 3],
        strand: &Strand,
        tile: [f32; 2],
        root: Vec3,
        out: &mut [[f32; 4]],
    ) -> StrandSpan {
        let tri = self.triangles[t];
        let scale = lateral_scale(uv, &tri.map(|v| Vec3A::from(self.positions[v as usize])));
        let mut at = t;
        for ((point, &radius), slot) in strand.points.iter().zip(&strand.radii).zip(out.iter_mut()) {
            let target = Vec2::new(point[0] as f32 + tile[0], point[1] as f32 + tile[1]);
            let (found, w) = self.locate(at, target);
            at = found;
            let pos = self.lift(at, w, target, point[2] as f32);
            *slot = [pos.x, pos.y, pos.z, radius as f32 * scale];
        }
        let tint = self.colors.map_or(Vec3::ONE, |c| {
            (0..3).fold(Vec3::ZERO, |s, k| {
                let v = c[tri[k] as usize];
                s + root[k] * Vec3::new(v[0], v[1], v[2])
            })
        });
        StrandSpan {
            first: 0,
            count: strand.points.len() as u32,
            root_color: Vec3::from(strand.root_color) * tint,
            tip_color: Vec3::from(strand.tip_color) * tint,
        }
    }

    /// Tile point `(target, z)` through triangle `t`'s map, `w` its weights there. Past the
    /// triangle (a patch border) the weights are clamped to it and the rest of the way taken
    /// along the triangle's `∂P/∂u`, `∂P/∂v`: extending the weights instead would swing the
    /// growth directions of small triangles far out.
    fn lift(&self, t: usize, w: Vec3, target: Vec2, z: f32) -> Vec3A {
        let tri = self.triangles[t];
        let uv = self.patches.uv[t].map(Vec2::from);
        let p = tri.map(|v| Vec3A::from(self.positions[v as usize]));
        let clamped = w.max(Vec3::ZERO);
        let clamped = clamped / clamped.element_sum().max(f32::MIN_POSITIVE);
        let inside = uv[0] * clamped.x + uv[1] * clamped.y + uv[2] * clamped.z;
        let on = (0..3).fold(Vec3A::ZERO, |s, k| {
            s + clamped[k] * (p[k] + z * self.up[tri[k] as usize])
        });
        let rest = target - inside;
        if rest.length_squared() == 0.0 {
            return on;
        }
        let (u1, u2) = (uv[1] - uv[0], uv[2] - uv[0]);
        let den = u1.perp_dot(u2);
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let dpdu = (e1 * u2.y - e2 * u1.y) / den;
        let dpdv = (e2 * u1.x - e1 * u2.x) / den;
        on + dpdu * rest.x + dpdv * rest.y
    }

    /// The triangle whose UVs hold `target` and its weights there: from triangle `t`, step
    /// across the side facing away from the most negative weight while the neighbour shares the
    /// side's UVs (the same patch, no seam). Where the walk cannot go on (a patch border, a
    /// boundary, a degenerate triangle, 64 steps), the last triangle's weights are extended.
    fn locate(&self, mut t: usize, target: Vec2) -> (usize, Vec3) {
        let mut w = Self::weights(&self.patches.uv[t], target);
        for _ in 0..64 {
            let (k, least) = (0..3).fold(
                (0, f32::INFINITY),
                |(bk, bv), k| if w[k] < bv { (k, w[k]) } else { (bk, bv) },
            );
            if least >= -1e-5 {
                break;
            }
            let Some(next) = self.neighbour(t, (k + 1) % 3) else {
                break;
            };
            let wn = Self::weights(&self.patches.uv[next], target);
            if !wn.is_finite() {
                break;
            }
            (t, w) = (next, wn);
        }
        (t, w)
    }

    /// The triangle across side `side` (`side`, `side + 1`) of triangle `t` when the UVs run on
    /// across it.
    fn neighbour(&self, t: usize, side: usize) -> Option<usize> {
        let e = self.topology.face_edges()[t][side];
        if e == NO_EDGE {
            return None;
        }
        let edge = self.topology.edges()[e as usize];
        if edge.face_count != 2 {
            return None;
        }
        let n = if edge.faces[0] as usize == t {
            edge.faces[1]
        } else {
            edge.faces[0]
        } as usize;
        if self.patches.patch[n] != self.patches.patch[t] || self.patches.patch[n] == NO_PATCH {
            return None;
        }
        let uv_of = |tri: usize, v: u32| {
            let k = self.triangles[tri].iter().position(|&x| x == v)?;
            Some(self.patches.uv[tri][k])
        };
        let (a, b) = (self.triangles[t][side], self.triangles[t][(side + 1) % 3]);
        let same = |v: u32| uv_of(t, v).is_some_and(|x| uv_of(n, v) == Some(x));
        (same(a) && same(b)).then_some(n)
    }
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

/// The skin of `mesh`: its albedo the strands' mean root color `mean_root` times `pelt_color`
/// (the shells' opaque layer 0).
pub(crate) fn skin_of(mesh: &FurMesh, mean_root: Vec3) -> Skin {
    let albedo = (0..mesh.vertex_count())
        .map(|v| {
            let c = mesh.color().map_or([1.0; 4], |c| c[v]);
            mean_root * Vec3::new(c[0], c[1], c[2])
        })
        .collect();
    Skin {
        positions: mesh.positions().iter().map(|&p| Vec3A::from(p)).collect(),
        normals: mesh.normals().iter().map(|&n| Vec3A::from(n)).collect(),
        albedo,
        triangles: mesh.triangles().to_vec(),
    }
}

fn w_dot(w: Vec3, v: [f32; 3]) -> f32 {
    w.x * v[0] + w.y * v[1] + w.z * v[2]
}

/// Object units per tile unit across a triangle: √(object area / UV area).
pub(crate) fn lateral_scale(uv: &[[f32; 2]; 3], p: &[Vec3A; 3]) -> f32 {
    let [a, b, c] = uv.map(Vec2::from);
    let uv_area = (b - a).perp_dot(c - a).abs();
    let area = (p[1] - p[0]).cross(p[2] - p[0]).length();
    if uv_area > 0.0 {
        (area / uv_area).sqrt()
    } else {
        0.0
    }
}
