//! How far each vertex lies from the mesh's open border (its edges used by one triangle), along
//! the surface: what lets the marched shells stop a view ray where the mesh ends, as the
//! instanced shells do (a shell is the mesh lifted, so it ends there too). A shader extrapolates
//! each distance linearly along its ray, which follows one straight side; near a corner two sides
//! are in reach, so each vertex keeps two: to the nearest border edge, and to the nearest that
//! runs another way (more than [`TURN`] apart), the corner's other side.
//!
//! Dijkstra searches over the edges from the border's vertices, carrying to each vertex the
//! border edge it was reached from and taking its distance to that edge's segment (not the path
//! along edges, which on a triangulated grid overstates the distance by up to 8%). Kept here
//! rather than taken from a geodesics crate: it is a few dozen lines over the adjacency
//! [`super::Topology`] already holds, and needs nearest-segment distances, not point sources.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::Vec3;

use super::FurMesh;

/// Two border edges run "another way" when their directions are further apart than this
/// (cosine of 45°): a square's sides do, the edges of one side or of a gentle curve do not.
const TURN: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// No border edge.
const NONE: u32 = u32::MAX;

/// Per vertex of `mesh`, its distances in object units over the surface to the nearest open
/// border edge and to the nearest running another way from it (the first again where none
/// does); `None` on a closed piece or a vertex on no triangle.
pub fn border_distances(mesh: &FurMesh) -> Vec<[Option<f32>; 2]> {
    let search = BorderSearch::new(mesh);
    let (first, nearest) = search.run(|_, _| true, &[]);
    let (second, _) = search.run(
        |v, edge| nearest[v as usize] != NONE && !search.parallel(edge, nearest[v as usize]),
        &nearest,
    );
    let finite = |d: f32| d.is_finite().then_some(d);
    // Where no edge runs another way (a border of parallel lines), the second is the first: the
    // two stay alike across every triangle (a huge value beside a small one would make a steep
    // slope out of nothing).
    first
        .into_iter()
        .zip(second)
        .map(|(a, b)| [finite(a), finite(b).or(finite(a))])
        .collect()
}

/// The mesh's border edges and what the searches over it share.
struct BorderSearch<'a> {
    mesh: &'a FurMesh,
    border: Vec<[u32; 2]>,
}

impl<'a> BorderSearch<'a> {
    fn new(mesh: &'a FurMesh) -> Self {
        let border = mesh
            .topology()
            .edges()
            .iter()
            .filter(|e| e.face_count == 1)
            .map(|e| e.vertices())
            .collect();
        BorderSearch { mesh, border }
    }

    fn at(&self, v: u32) -> Vec3 {
        Vec3::from(self.mesh.positions()[v as usize])
    }

    fn direction(&self, edge: u32) -> Vec3 {
        let [a, b] = self.border[edge as usize];
        (self.at(b) - self.at(a)).normalize_or_zero()
    }

    /// Whether border edges `a` and `b` run the same way (within 45°, either sense).
    fn parallel(&self, a: u32, b: u32) -> bool {
        self.direction(a).dot(self.direction(b)).abs() >= TURN
    }

    fn distance(&self, v: u32, edge: u32) -> f32 {
        let [a, b] = self.border[edge as usize];
        segment_distance(self.at(v), self.at(a), self.at(b))
    }

    /// Per vertex, the distance to the nearest border edge `allowed` for it, and that edge: a
    /// search seeded at each border edge's ends (and, given `neighbours`' labels from an earlier
    /// search, at every vertex next to one labelled with an allowed edge) that hands each vertex's
    /// edge on to its neighbours.
    fn run(&self, allowed: impl Fn(u32, u32) -> bool, neighbours: &[u32]) -> (Vec<f32>, Vec<u32>) {
        let n = self.mesh.positions().len();
        let mut front = Front {
            distance: vec![f32::INFINITY; n],
            nearest: vec![NONE; n],
            queue: BinaryHeap::new(),
        };
        let offer = |front: &mut Front, v: u32, edge: u32| {
            if edge != NONE && allowed(v, edge) {
                front.offer(v, edge, self.distance(v, edge));
            }
        };
        for (k, &[a, b]) in self.border.iter().enumerate() {
            offer(&mut front, a, k as u32);
            offer(&mut front, b, k as u32);
        }
        let topology = self.mesh.topology();
        let triangles = self.mesh.triangles();
        let around = |v: u32| {
            topology
                .vertex_faces(v as usize)
                .iter()
                .flat_map(|&face| triangles[face as usize])
        };
        if !neighbours.is_empty() {
            for v in 0..n as u32 {
                for w in around(v) {
                    offer(&mut front, v, neighbours[w as usize]);
                }
            }
        }
        while let Some(Reverse((bits, v))) = front.queue.pop() {
            if bits != front.distance[v as usize].to_bits() {
                continue;
            }
            let edge = front.nearest[v as usize];
            for w in around(v) {
                offer(&mut front, w, edge);
            }
        }
        (front.distance, front.nearest)
    }
}

/// A search's state: per vertex the best distance and edge so far, and the vertices to visit.
struct Front {
    distance: Vec<f32>,
    nearest: Vec<u32>,
    // Min-heap on (distance bits, vertex): non-negative floats order as their bits, and the
    // vertex breaks ties, so the search visits vertices in the same order on every run.
    queue: BinaryHeap<Reverse<(u32, u32)>>,
}

impl Front {
    fn offer(&mut self, v: u32, edge: u32, d: f32) {
        if d < self.distance[v as usize] {
            self.distance[v as usize] = d;
            self.nearest[v as usize] = edge;
            self.queue.push(Reverse((d.to_bits(), v)));
        }
    }
}

/// Distance from `p` to the segment `a`–`b`.
fn segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let ab = b - a;
    let t = (p - a).dot(ab) / ab.length_squared().max(f32::MIN_POSITIVE);
    p.distance(a + ab * t.clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MeshInput;
    use crate::mesh::shapes;

    #[test]
    fn a_grid_vertex_lies_as_far_from_the_border_as_its_nearest_side_and_the_nearest_across() {
        let n = 8usize;
        let (positions, triangles) = shapes::square(n);
        let distances = border_distances(&FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap());
        // The square is 2 across: a cell is 2 / n.
        let cell = 2.0 / n as f32;
        for j in 0..=n {
            for i in 0..=n {
                // The nearest side along x and along y: one is the nearest, the other runs
                // across it.
                let (x, y) = (i.min(n - i) as f32 * cell, j.min(n - j) as f32 * cell);
                let got = distances[j * (n + 1) + i].map(Option::unwrap);
                assert!(
                    (got[0] - x.min(y)).abs() < 1e-5,
                    "({i}, {j}): {got:?}, nearest {}",
                    x.min(y)
                );
                assert!(
                    (got[1] - x.max(y)).abs() < 1e-5,
                    "({i}, {j}): {got:?}, across {}",
                    x.max(y)
                );
            }
        }
    }

    #[test]
    fn a_closed_mesh_has_no_border() {
        let (positions, triangles) = shapes::uv_sphere(12, 8);
        let mesh = FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap();
        assert!(border_distances(&mesh).iter().flatten().all(Option::is_none));
    }

    #[test]
    fn a_sphere_with_holes_measures_from_their_rims() {
        let (positions, triangles) = shapes::sphere_with_holes(12, 8);
        let mesh = FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap();
        let distances: Vec<Option<f32>> = border_distances(&mesh).iter().map(|d| d[0]).collect();
        // The rims are at 0, the rest of the sphere further, and nothing is further than half
        // a great circle.
        assert!(distances.iter().flatten().any(|&d| d == 0.0));
        assert!(distances.iter().flatten().any(|&d| d > 0.3));
        assert!(distances.iter().flatten().all(|&d| d < std::f32::consts::PI));
    }
}
