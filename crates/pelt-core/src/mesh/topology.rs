//! Edge map, vertex→face adjacency and connected components.
//!
//! Edges are keyed by a 64-bit integer `(min << 32) | max` of their two vertex indices, the key
//! the hybrid-fur paper uses to find the neighbouring prism across an edge. The map is built by a
//! counting sort on the smaller vertex (O(corners), no hashing), so edge ids come out in key order
//! and are identical on every run.

use rayon::prelude::*;

/// Marks a triangle side whose two corners are the same vertex (it is no edge).
pub const NO_EDGE: u32 = u32::MAX;

/// The 64-bit key of the undirected edge `{a, b}`.
pub fn edge_key(a: u32, b: u32) -> u64 {
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    (u64::from(lo) << 32) | u64::from(hi)
}

/// One undirected edge and the triangles around it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edge {
    /// `edge_key(a, b)`.
    pub key: u64,
    /// The first two triangles (in triangle order) using the edge; the second is `u32::MAX` on a
    /// boundary edge.
    pub faces: [u32; 2],
    /// How many triangle sides use the edge: 1 boundary, 2 manifold, more non-manifold.
    pub face_count: u32,
}

impl Edge {
    /// The two vertices, smaller first.
    pub fn vertices(&self) -> [u32; 2] {
        [(self.key >> 32) as u32, self.key as u32]
    }
}

/// Adjacency of a triangle mesh.
#[derive(Debug, Clone, Default)]
pub struct Topology {
    edges: Vec<Edge>,
    face_edges: Vec<[u32; 3]>,
    vertex_face_offsets: Vec<u32>,
    vertex_faces: Vec<u32>,
    components: usize,
    loose_vertices: usize,
}

impl Topology {
    /// Builds the adjacency of `triangles` over `vertex_count` vertices (indices already checked).
    pub fn build(vertex_count: usize, triangles: &[[u32; 3]]) -> Self {
        let (edges, face_edges) = build_edges(vertex_count, triangles);
        let (vertex_face_offsets, vertex_faces) = build_vertex_faces(vertex_count, triangles);
        let (components, loose_vertices) = count_components(vertex_count, &edges, &vertex_face_offsets);
        Topology {
            edges,
            face_edges,
            vertex_face_offsets,
            vertex_faces,
            components,
            loose_vertices,
        }
    }

    /// Number of vertices the adjacency was built for.
    pub fn vertex_count(&self) -> usize {
        self.vertex_face_offsets.len() - 1
    }

    /// All edges, sorted by key.
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// Per triangle, the edge index of sides (0→1, 1→2, 2→0), or [`NO_EDGE`] for a collapsed side.
    pub fn face_edges(&self) -> &[[u32; 3]] {
        &self.face_edges
    }

    /// Index of the edge `{a, b}`, if the mesh has it.
    pub fn find_edge(&self, a: u32, b: u32) -> Option<usize> {
        let key = edge_key(a, b);
        self.edges.binary_search_by_key(&key, |e| e.key).ok()
    }

    /// Triangles that use vertex `v`, in increasing order.
    pub fn vertex_faces(&self, v: usize) -> &[u32] {
        let start = self.vertex_face_offsets[v] as usize;
        let end = self.vertex_face_offsets[v + 1] as usize;
        &self.vertex_faces[start..end]
    }

    /// Connected components of the triangles (vertices joined by an edge belong together).
    pub fn components(&self) -> usize {
        self.components
    }

    /// Vertices used by no triangle.
    pub fn loose_vertices(&self) -> usize {
        self.loose_vertices
    }

    /// Component label per vertex: components are numbered `0..components()` in the order of
    /// their lowest vertex; a loose vertex gets [`NO_COMPONENT`].
    pub fn vertex_components(&self) -> Vec<u32> {
        let n = self.vertex_count();
        let mut parent: Vec<u32> = (0..n as u32).collect();
        union_edges(&mut parent, &self.edges);
        let mut label = vec![NO_COMPONENT; n];
        let mut next = 0;
        for v in 0..n {
            if self.vertex_face_offsets[v] == self.vertex_face_offsets[v + 1] {
                continue;
            }
            let r = root(&mut parent, v as u32) as usize;
            if label[r] == NO_COMPONENT {
                label[r] = next;
                next += 1;
            }
            label[v] = label[r];
        }
        label
    }
}

/// Component label of a vertex that no triangle uses.
pub const NO_COMPONENT: u32 = u32::MAX;

fn root(parent: &mut [u32], mut v: u32) -> u32 {
    while parent[v as usize] != v {
        let grand = parent[parent[v as usize] as usize];
        parent[v as usize] = grand;
        v = grand;
    }
    v
}

/// Joins the two ends of every edge; the root of a set is its smallest vertex.
fn union_edges(parent: &mut [u32], edges: &[Edge]) {
    for e in edges {
        let [a, b] = e.vertices();
        let (ra, rb) = (root(parent, a), root(parent, b));
        if ra != rb {
            parent[ra.max(rb) as usize] = ra.min(rb);
        }
    }
}

/// Counting sort of triangle sides by their smaller vertex, then by the larger one.
fn build_edges(vertex_count: usize, triangles: &[[u32; 3]]) -> (Vec<Edge>, Vec<[u32; 3]>) {
    let sides = || {
        triangles.iter().enumerate().flat_map(|(t, tri)| {
            (0..3).filter_map(move |c| {
                let (a, b) = (tri[c], tri[(c + 1) % 3]);
                (a != b).then(|| (a.min(b), a.max(b), (t * 3 + c) as u32))
            })
        })
    };
    let mut offsets = vec![0u32; vertex_count + 1];
    for (lo, _, _) in sides() {
        offsets[lo as usize + 1] += 1;
    }
    for i in 0..vertex_count {
        offsets[i + 1] += offsets[i];
    }
    // (larger vertex, side id) bucketed by the smaller vertex
    let mut entries = vec![(0u32, 0u32); offsets[vertex_count] as usize];
    let mut fill = offsets.clone();
    for (lo, hi, side) in sides() {
        entries[fill[lo as usize] as usize] = (hi, side);
        fill[lo as usize] += 1;
    }
    // Buckets are tiny (the valence); sort each by (larger vertex, side) in parallel.
    let mut rest: &mut [(u32, u32)] = &mut entries;
    let mut buckets = Vec::with_capacity(vertex_count);
    for v in 0..vertex_count {
        let (bucket, tail) = rest.split_at_mut((offsets[v + 1] - offsets[v]) as usize);
        buckets.push(bucket);
        rest = tail;
    }
    buckets.par_iter_mut().for_each(|b| b.sort_unstable());

    let mut edges = Vec::with_capacity(entries.len() / 2 + 1);
    let mut face_edges = vec![[NO_EDGE; 3]; triangles.len()];
    for lo in 0..vertex_count {
        let bucket = &entries[offsets[lo] as usize..offsets[lo + 1] as usize];
        let mut i = 0;
        while i < bucket.len() {
            let hi = bucket[i].0;
            let run = bucket[i..].iter().take_while(|e| e.0 == hi).count();
            let id = edges.len() as u32;
            let face_of = |k: usize| bucket[i + k].1 / 3;
            edges.push(Edge {
                key: edge_key(lo as u32, hi),
                faces: [face_of(0), if run > 1 { face_of(1) } else { u32::MAX }],
                face_count: run as u32,
            });
            for &(_, side) in &bucket[i..i + run] {
                face_edges[(side / 3) as usize][(side % 3) as usize] = id;
            }
            i += run;
        }
    }
    (edges, face_edges)
}

/// CSR lists of the triangles around each vertex, in triangle order.
fn build_vertex_faces(vertex_count: usize, triangles: &[[u32; 3]]) -> (Vec<u32>, Vec<u32>) {
    let mut offsets = vec![0u32; vertex_count + 1];
    for tri in triangles {
        for (c, &v) in tri.iter().enumerate() {
            // a vertex repeated within one triangle is listed once
            if !tri[..c].contains(&v) {
                offsets[v as usize + 1] += 1;
            }
        }
    }
    for i in 0..vertex_count {
        offsets[i + 1] += offsets[i];
    }
    let mut faces = vec![0u32; offsets[vertex_count] as usize];
    let mut fill = offsets.clone();
    for (t, tri) in triangles.iter().enumerate() {
        for (c, &v) in tri.iter().enumerate() {
            if !tri[..c].contains(&v) {
                faces[fill[v as usize] as usize] = t as u32;
                fill[v as usize] += 1;
            }
        }
    }
    (offsets, faces)
}

/// Union-find over the edges; returns (components among used vertices, unused vertices).
fn count_components(vertex_count: usize, edges: &[Edge], vertex_face_offsets: &[u32]) -> (usize, usize) {
    let mut parent: Vec<u32> = (0..vertex_count as u32).collect();
    union_edges(&mut parent, edges);
    let mut components = 0;
    let mut loose = 0;
    for v in 0..vertex_count {
        if vertex_face_offsets[v] == vertex_face_offsets[v + 1] {
            loose += 1;
        } else if root(&mut parent, v as u32) == v as u32 {
            components += 1;
        }
    }
    (components, loose)
}
