//! Whether a geometric level of detail ([`super::geometry_lod`]) still stands for the full mesh
//! after its colors or lengths are repainted. The simplifier weighed the colors and lengths the
//! scene was uploaded with; a repaint can put a feature where a level has no vertex to hold it
//! (a bald spot one vertex wide between two coarse corners), which that level would smear.
//!
//! At upload, every surface vertex that a level dropped is placed on the level: on the nearest
//! point of the nearest level triangle that faces the same way (the other side of a thin part,
//! an ear, faces away), kept as the triangle's three corners and the point's barycentric
//! weights. What the level draws at that vertex is then the weights' blend of the corners'
//! colors and lengths, and its distance from the vertex's own values, the largest over the
//! dropped vertices, is the level's deviation: O(vertices) to measure after each repaint.
//! A level stays drawable while its deviation stays within its tolerance: its error bound in
//! attribute units (the simplifier counted one unit of attribute as a tile's size in object
//! units), or the deviation it had as uploaded when that is larger, so that the uploaded paint
//! always passes.

use rayon::prelude::*;

use super::surface_mesh::SurfaceVertex;
use glam::{DVec3, Vec3};

/// Faces whose area is below this fraction of the squared cell size hold no host: their
/// nearest point is ill-defined, and the triangles around them cover the same place.
const DEGENERATE: f64 = 1e-12;
/// Cells per axis at most: the grid stays small for any mesh.
const MAX_CELLS: usize = 128;
/// Rings of cells (about a level edge each) searched around a vertex for its host: far enough
/// for a facing triangle across a crease, near enough that a vertex whose part of the mesh the
/// level dropped costs a bounded search.
const MAX_RINGS: usize = 4;

/// Where the vertices one level dropped lie on it.
#[derive(Debug, Clone, Default)]
pub struct LevelHosts {
    /// The dropped vertices, as mesh vertices (the rows of colors and lengths).
    vertices: Vec<u32>,
    /// The mesh vertices at the corners of each one's host triangle.
    corners: Vec<[u32; 3]>,
    /// Its barycentric weights there.
    weights: Vec<[f32; 3]>,
    /// The largest deviation the level may show, attribute units.
    tolerance: f64,
}

impl LevelHosts {
    /// Places the surface `vertices` that `indices` (one level's triangles) dropped on it;
    /// `source` maps surface vertices to mesh vertices, `attributes` are the colors and lengths
    /// per mesh vertex as uploaded, `error` is the level's bound (object units) and `tile` a
    /// tile's size in object units.
    pub fn new(
        vertices: &[SurfaceVertex],
        source: &[u32],
        indices: &[u32],
        attributes: (&[[f32; 4]], &[f32]),
        error: f64,
        tile: f64,
    ) -> Self {
        let mut kept = vec![false; vertices.len()];
        for &v in indices {
            kept[v as usize] = true;
        }
        let faces = Faces::new(vertices, indices);
        let hosts: Vec<(u32, [u32; 3], [f32; 3])> = (0..vertices.len())
            .into_par_iter()
            .filter(|&v| !kept[v])
            .filter_map(|v| {
                let (face, weights) = faces.host(&vertices[v])?;
                let corners = faces.corners[face].map(|c| source[c as usize]);
                Some((source[v], corners, weights.map(|w| w as f32)))
            })
            .collect();
        let mut level = LevelHosts {
            vertices: hosts.iter().map(|h| h.0).collect(),
            corners: hosts.iter().map(|h| h.1).collect(),
            weights: hosts.iter().map(|h| h.2).collect(),
            tolerance: 0.0,
        };
        let bound = error / tile;
        level.tolerance = if bound.is_finite() { bound } else { 0.0 };
        level.tolerance = level.tolerance.max(level.deviation(attributes.0, attributes.1));
        level
    }

    /// The farthest any dropped vertex's color and length (one row per mesh vertex) lie from
    /// the blend the level draws there: the Euclidean distance over the four color channels
    /// and the length.
    pub fn deviation(&self, colors: &[[f32; 4]], lengths: &[f32]) -> f64 {
        let row = |v: u32| {
            let (c, l) = (colors[v as usize], lengths[v as usize]);
            [c[0], c[1], c[2], c[3], l].map(f64::from)
        };
        (0..self.vertices.len())
            .into_par_iter()
            .map(|i| {
                let own = row(self.vertices[i]);
                let mut blend = [0.0f64; 5];
                for (&corner, &w) in self.corners[i].iter().zip(&self.weights[i]) {
                    let r = row(corner);
                    for (b, x) in blend.iter_mut().zip(r) {
                        *b += f64::from(w) * x;
                    }
                }
                own.iter()
                    .zip(blend)
                    .map(|(a, b)| (a - b) * (a - b))
                    .sum::<f64>()
                    .sqrt()
            })
            .reduce(|| 0.0, f64::max)
    }

    /// Whether the level still stands for the full mesh under these colors and lengths.
    pub fn holds(&self, colors: &[[f32; 4]], lengths: &[f32]) -> bool {
        self.deviation(colors, lengths) <= self.tolerance
    }

    /// Dropped vertices placed on the level.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.vertices.len()
    }
}

/// One level's triangles in a uniform grid of cells, each listing the triangles whose bounding
/// box meets it.
struct Faces {
    corners: Vec<[u32; 3]>,
    points: Vec<[DVec3; 3]>,
    normals: Vec<DVec3>,
    lo: DVec3,
    cell: f64,
    dims: [usize; 3],
    /// Cell `c`'s triangles are `items[starts[c]..starts[c + 1]]`.
    starts: Vec<u32>,
    items: Vec<u32>,
}

impl Faces {
    fn new(vertices: &[SurfaceVertex], indices: &[u32]) -> Self {
        let position = |v: u32| Vec3::from(vertices[v as usize].position).as_dvec3();
        let corners: Vec<[u32; 3]> = indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        let points: Vec<[DVec3; 3]> = corners.iter().map(|t| t.map(position)).collect();
        let (mut lo, mut hi) = (DVec3::MAX, DVec3::MIN);
        let mut edge_sum = 0.0;
        for p in &points {
            for (k, &q) in p.iter().enumerate() {
                lo = lo.min(q);
                hi = hi.max(q);
                edge_sum += p[(k + 1) % 3].distance(q);
            }
        }
        let extent = (hi - lo).max_element().max(0.0);
        // A mean edge a cell: a handful of triangles in each.
        let mean_edge = edge_sum / (3 * points.len()).max(1) as f64;
        let cell = mean_edge.max(extent / MAX_CELLS as f64).max(f64::MIN_POSITIVE);
        let dims = std::array::from_fn(|i| (((hi[i] - lo[i]) / cell) as usize + 1).min(MAX_CELLS));
        let mut faces = Faces {
            normals: points.iter().map(|p| (p[1] - p[0]).cross(p[2] - p[0])).collect(),
            corners,
            points,
            lo,
            cell,
            dims,
            starts: Vec::new(),
            items: Vec::new(),
        };
        // Counting sort of (cell, triangle) pairs: triangles in ascending order in each cell.
        let degenerate = DEGENERATE * cell * cell;
        let boxes: Vec<Option<([usize; 3], [usize; 3])>> = (0..faces.points.len())
            .map(|f| {
                let n = faces.normals[f];
                (n.length() > degenerate).then(|| {
                    let p = faces.points[f];
                    let low = p[0].min(p[1]).min(p[2]);
                    let high = p[0].max(p[1]).max(p[2]);
                    (faces.cell_of(low), faces.cell_of(high))
                })
            })
            .collect();
        let cells = dims.iter().product::<usize>();
        let mut counts = vec![0u32; cells + 1];
        let each_cell = |b: &([usize; 3], [usize; 3]), f: &mut dyn FnMut(usize)| {
            for z in b.0[2]..=b.1[2] {
                for y in b.0[1]..=b.1[1] {
                    for x in b.0[0]..=b.1[0] {
                        f((z * dims[1] + y) * dims[0] + x);
                    }
                }
            }
        };
        for b in boxes.iter().flatten() {
            each_cell(b, &mut |c| counts[c + 1] += 1);
        }
        for c in 0..cells {
            counts[c + 1] += counts[c];
        }
        let mut next = counts.clone();
        let mut items = vec![0u32; counts[cells] as usize];
        for (f, b) in boxes.iter().enumerate() {
            if let Some(b) = b {
                each_cell(b, &mut |c| {
                    items[next[c] as usize] = f as u32;
                    next[c] += 1;
                });
            }
        }
        faces.starts = counts;
        faces.items = items;
        faces
    }

    fn cell_of(&self, p: DVec3) -> [usize; 3] {
        std::array::from_fn(|i| {
            let c = ((p[i] - self.lo[i]) / self.cell).floor();
            (c.max(0.0) as usize).min(self.dims[i] - 1)
        })
    }

    /// The triangle `v` lies on and its weights there: the nearest that faces the way `v`'s
    /// normal does, else the nearest at all, within [`MAX_RINGS`] rings of cells; `None` where
    /// the level has no triangle that near (it dropped the part of the mesh `v` is on, which
    /// its error bound already counts).
    fn host(&self, v: &SurfaceVertex) -> Option<(usize, [f64; 3])> {
        let p = Vec3::from(v.position).as_dvec3();
        let n = Vec3::from(v.normal).as_dvec3();
        let home = self.cell_of(p);
        // How far p lies inside its cell: a cell beyond ring r is at least this plus r cells
        // away (0 for a point outside the grid, clamped to its border cell).
        let inside = (0..3)
            .map(|i| {
                let low = self.lo[i] + home[i] as f64 * self.cell;
                (p[i] - low).min(low + self.cell - p[i])
            })
            .fold(f64::MAX, f64::min)
            .max(0.0);
        // (squared distance, triangle, weights) of the nearest facing and of the nearest.
        type Best = Option<(f64, usize, [f64; 3])>;
        let (mut facing, mut any): (Best, Best) = (None, None);
        let nearer =
            |best: &Best, d: f64, f: usize| best.is_none_or(|(bd, bf, _)| d < bd || (d == bd && f < bf));
        let rings = MAX_RINGS.min(*self.dims.iter().max()?);
        for r in 0..rings {
            self.each_in_shell(home, r, |f| {
                let t = self.points[f];
                let w = nearest_weights(p, t);
                let q = w[0] * t[0] + w[1] * t[1] + w[2] * t[2];
                let d = q.distance_squared(p);
                if nearer(&any, d, f) {
                    any = Some((d, f, w));
                }
                if self.normals[f].dot(n) > 0.0 && nearer(&facing, d, f) {
                    facing = Some((d, f, w));
                }
            });
            // Nothing in a cell beyond ring r is nearer.
            if let Some((d, _, _)) = facing
                && d.sqrt() <= inside + r as f64 * self.cell
            {
                break;
            }
        }
        facing.or(any).map(|(_, f, w)| (f, w))
    }

    /// Calls `f` with the triangles of the cells at Chebyshev distance `r` from `home` (each
    /// cell once; a triangle in several cells is called for each).
    fn each_in_shell(&self, home: [usize; 3], r: usize, mut f: impl FnMut(usize)) {
        let low = home.map(|h| h as isize - r as isize);
        let high = home.map(|h| h + r);
        let inner = |i: usize| low[i].max(0) as usize..=high[i].min(self.dims[i] - 1);
        let mut cell = |x: usize, y: usize, z: usize| {
            let c = (z * self.dims[1] + y) * self.dims[0] + x;
            for &t in &self.items[self.starts[c] as usize..self.starts[c + 1] as usize] {
                f(t as usize);
            }
        };
        for z in inner(2) {
            for y in inner(1) {
                let on_face = z as isize == low[2] || z == high[2] || y as isize == low[1] || y == high[1];
                if on_face {
                    inner(0).for_each(|x| cell(x, y, z));
                } else {
                    // Inside the cube's y-z extent: only its two x faces belong to the shell.
                    if low[0] >= 0 {
                        cell(low[0] as usize, y, z);
                    }
                    if r > 0 && high[0] < self.dims[0] {
                        cell(high[0], y, z);
                    }
                }
            }
        }
    }
}

/// The barycentric weights of the point of triangle `t` nearest `p` (Ericson, Real-Time
/// Collision Detection, §5.1.5: by the Voronoi region of the triangle's corners, edges and
/// face that `p` falls in). `t` must have a nonzero area.
fn nearest_weights(p: DVec3, t: [DVec3; 3]) -> [f64; 3] {
    let [a, b, c] = t;
    let (ab, ac) = (b - a, c - a);
    let ap = p - a;
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return [0.0, 1.0, 0.0];
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let s = d1 / (d1 - d3);
        return [1.0 - s, s, 0.0];
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return [0.0, 0.0, 1.0];
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let s = d2 / (d2 - d6);
        return [1.0 - s, 0.0, s];
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 >= d3 && d5 >= d6 {
        let s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return [0.0, 1.0 - s, s];
    }
    let total = va + vb + vc;
    let (v, w) = (vb / total, vc / total);
    [1.0 - v - w, v, w]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::geometry_lod::tests::{dense_torus, levels_of};

    /// The torus's levels 1 on, each with its hosts under white and length 1.
    fn torus_hosts() -> (crate::FurMesh, Vec<(f64, Vec<u32>, LevelHosts)>) {
        let (mesh, surface) = dense_torus();
        let levels = levels_of(&surface, &vec![1.0; surface.vertices.len()]);
        let white = vec![[1.0f32; 4]; mesh.vertex_count()];
        let ones = vec![1.0f32; mesh.vertex_count()];
        let tile = 1.0 / surface.uv_scale;
        let hosts = levels
            .into_iter()
            .skip(1)
            .map(|level| {
                let hosts = LevelHosts::new(
                    &surface.vertices,
                    &surface.source,
                    &level.indices,
                    (&white, &ones),
                    level.error,
                    tile,
                );
                (level.error, level.indices, hosts)
            })
            .collect();
        (mesh, hosts)
    }

    #[test]
    fn every_dropped_vertex_lies_on_its_host_within_the_levels_bound() {
        let (mesh, levels) = torus_hosts();
        let (_, surface) = dense_torus();
        assert!(levels.len() >= 2);
        let positions = mesh.positions();
        for (k, (error, indices, hosts)) in levels.iter().enumerate() {
            let mut kept = vec![false; surface.vertices.len()];
            indices.iter().for_each(|&v| kept[v as usize] = true);
            assert_eq!(hosts.len(), kept.iter().filter(|&&k| !k).count());
            let mut farthest = 0.0f64;
            for i in 0..hosts.len() {
                let own = Vec3::from(positions[hosts.vertices[i] as usize]).as_dvec3();
                let w = hosts.weights[i];
                assert!(w.iter().all(|&x| (0.0..=1.0).contains(&x)));
                let at: DVec3 = (0..3)
                    .map(|c| f64::from(w[c]) * Vec3::from(positions[hosts.corners[i][c] as usize]).as_dvec3())
                    .sum();
                farthest = farthest.max(at.distance(own));
            }
            // The vertex is on the torus and the level within its bound of it: the host point,
            // the level's nearest, is no farther.
            assert!(farthest <= *error, "level {}: {farthest} against {error}", k + 1);
        }
    }

    #[test]
    fn smooth_repaints_keep_a_level_and_a_bald_spot_it_cannot_hold_drops_it() {
        let (mesh, levels) = torus_hosts();
        let n = mesh.vertex_count();
        let positions = mesh.positions();
        let (white, ones) = (vec![[1.0f32; 4]; n], vec![1.0f32; n]);
        let red = vec![[1.0, 0.2, 0.2, 1.0]; n];
        let half = vec![0.5f32; n];
        // A color ramp along x, from 0.16 to 0.84 across the torus.
        let ramp: Vec<[f32; 4]> = positions
            .iter()
            .map(|p| [0.5 + 0.25 * p[0], 0.5, 0.5, 1.0])
            .collect();
        for (k, (_, _, hosts)) in levels.iter().enumerate() {
            // A blend of equal values is that value (to the f32 weights' rounding).
            assert!(hosts.deviation(&white, &ones) < 1e-6);
            assert!(hosts.holds(&white, &ones));
            assert!(hosts.deviation(&red, &half) < 1e-6);
            assert!(hosts.holds(&ramp, &ones), "level {}", k + 1);
            // One dropped vertex bald under haired corners: the level draws length 1 there.
            let bald = hosts
                .vertices
                .iter()
                .zip(&hosts.corners)
                .find(|(v, corners)| !corners.contains(v))
                .map(|(&v, _)| v)
                .unwrap();
            let mut spot = ones.clone();
            spot[bald as usize] = 0.0;
            assert!((hosts.deviation(&white, &spot) - 1.0).abs() < 1e-6);
            assert!(!hosts.holds(&white, &spot), "level {}", k + 1);
        }
        assert_eq!(super::super::scene_levels::drawable(&[], &white, &ones), 1);
    }

    #[test]
    fn the_shells_of_cells_visit_every_cell_once_at_its_chebyshev_distance() {
        // One "triangle" per cell, numbered as the cells are.
        let dims = [5, 4, 3];
        let cells = 5 * 4 * 3;
        let grid = Faces {
            corners: Vec::new(),
            points: Vec::new(),
            normals: Vec::new(),
            lo: DVec3::ZERO,
            cell: 1.0,
            dims,
            starts: (0..=cells as u32).collect(),
            items: (0..cells as u32).collect(),
        };
        for home in [[0, 0, 0], [2, 1, 1], [4, 3, 2], [1, 3, 0]] {
            let mut seen = vec![0; cells];
            for r in 0..6 {
                grid.each_in_shell(home, r, |c| {
                    seen[c] += 1;
                    let at = [c % 5, c / 5 % 4, c / 20];
                    let ring = (0..3).map(|i| at[i].abs_diff(home[i])).max().unwrap();
                    assert_eq!(ring, r, "cell {at:?} from {home:?}");
                });
            }
            assert!(seen.iter().all(|&n| n == 1), "{home:?}: {seen:?}");
        }
    }

    #[test]
    fn nearest_weights_match_a_brute_force_search_over_the_triangle() {
        let t = [DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0), DVec3::new(0.5, 1.5, 0.0)];
        let at = |w: [f64; 3]| w[0] * t[0] + w[1] * t[1] + w[2] * t[2];
        let mut rng = crate::rng::Rng::new(7);
        for _ in 0..200 {
            let mut uniform = |lo: f64, hi: f64| lo + (hi - lo) * rng.next_f64();
            let p = DVec3::new(uniform(-1.5, 3.5), uniform(-1.5, 3.0), uniform(-1.0, 1.0));
            let w = nearest_weights(p, t);
            assert!(w.iter().all(|&x| (-1e-12..=1.0 + 1e-12).contains(&x)));
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            let d = |q: DVec3| q.distance(p);
            let got = d(at(w));
            // Brute force: a fine lattice of the triangle's points.
            let steps = 400;
            let mut least = f64::MAX;
            for i in 0..=steps {
                for j in 0..=steps - i {
                    let (u, v) = (i as f64 / steps as f64, j as f64 / steps as f64);
                    least = least.min(d(at([1.0 - u - v, u, v])));
                }
            }
            assert!(got <= least + 1e-12, "{p:?}: {got} against {least}");
            assert!(least - got < 1e-2, "{p:?}: {got} against {least}");
        }
    }
}
