//! Carries a strand of the tile to object space through the map of the triangle whose patch UVs
//! hold each of its points (Lengyel et al. 2001, §2.2, as the shells are lifted; the walk across
//! edges inside a patch is the hybrid paper's neighbour walk through the prisms).

use glam::{Vec2, Vec3, Vec3A};

use super::{StrandSpan, growth_vectors, lateral_scale};
use crate::hair::Strand;
use crate::lapped::{NO_PATCH, Patches};
use crate::mesh::FurMesh;
use crate::mesh::{NO_EDGE, Topology};

/// Carries tile points to object space through the triangles' maps.
pub(super) struct Placer<'a> {
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
    pub(super) fn new(mesh: &'a FurMesh, patches: &'a Patches, fur_depth: f32) -> Self {
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
    pub(super) fn root_weights(
        &self,
        t: usize,
        uv: &[[f32; 2]; 3],
        strand: &Strand,
        tile: [f32; 2],
    ) -> Option<Vec3> {
        let root = Vec2::new(strand.root[0] as f32 + tile[0], strand.root[1] as f32 + tile[1]);
        let w = Self::weights(uv, root);
        let tri = self.triangles[t];
        let length = self.lengths.map_or(1.0, |l| w_dot(w, tri.map(|v| l[v as usize])));
        (length > 1e-6).then_some(w)
    }

    /// Writes strand points into `out`; the span's `first` is the caller's to set.
    pub(super) fn place(
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
            triangle: t as u32,
            weights: root.to_array(),
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

fn w_dot(w: Vec3, v: [f32; 3]) -> f32 {
    w.x * v[0] + w.y * v[1] + w.z * v[2]
}
