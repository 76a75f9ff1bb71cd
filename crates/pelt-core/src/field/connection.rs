//! The discrete connection Laplacian of Knöppel et al. 2013 (§4, "Smoothest fields") for n = 1:
//! one complex unknown per vertex in that vertex's tangent frame, cotangent edge weights, and a
//! unit-modulus transport per edge that carries a tangent vector from one frame to the other.
//!
//! The transport rotates vertex `a`'s tangent plane onto vertex `b`'s by the smallest rotation
//! taking `n_a` to `n_b` (discrete Levi-Civita transport); it is defined for any pair of normals
//! that are not opposite, so it needs no edge direction and works on non-manifold and degenerate
//! input. Cotangent weights are clamped to a positive range: negative weights (obtuse triangles)
//! would make the energy indefinite, and near-degenerate triangles would make it ill-conditioned.

use glam::{DVec3, Vec3};

use crate::mesh::{FurMesh, NO_EDGE};

/// Smallest edge weight; also the weight of an edge whose faces all have zero area.
const MIN_WEIGHT: f64 = 1e-2;
/// Largest edge weight (a cotangent of about 0.006°).
const MAX_WEIGHT: f64 = 1e4;

/// Complex product.
pub(super) fn mul(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0]]
}

/// Complex conjugate.
pub(super) fn conj(a: [f64; 2]) -> [f64; 2] {
    [a[0], -a[1]]
}

/// A stored f32 vector widened to f64, where the field's geometry is computed.
pub(super) fn wide(a: [f32; 3]) -> DVec3 {
    Vec3::from(a).as_dvec3()
}

/// Sparse Hermitian operator `Σ_e w_e |z_b - r_e z_a|²` in CSR form, one row per vertex.
pub(super) struct Connection {
    offsets: Vec<u32>,
    /// Per entry: the neighbour `j`, `w f` for the factor `f` with `z_i ≈ f z_j`, and `w`. Single
    /// precision halves the memory the solve streams through; `w f` and its conjugate round
    /// alike, so the operator stays exactly Hermitian.
    entries: Vec<(u32, [f32; 2], f32)>,
    /// Per vertex: the sum of its edge weights (the diagonal of the Laplacian).
    pub(super) degree: Vec<f64>,
    /// Per edge (in `Topology::edges` order): `r` with `z_hi ≈ r z_lo`.
    pub(super) transport: Vec<[f64; 2]>,
}

impl Connection {
    pub(super) fn build(mesh: &FurMesh) -> Self {
        let topology = mesh.topology();
        let weights = edge_weights(mesh);
        let transport: Vec<[f64; 2]> = topology
            .edges()
            .iter()
            .map(|e| {
                let [a, b] = e.vertices().map(|v| v as usize);
                transport_angle(mesh, a, b)
            })
            .map(|angle| [angle.cos(), angle.sin()])
            .collect();
        let n = mesh.vertex_count();
        let mut offsets = vec![0u32; n + 1];
        for e in topology.edges() {
            for v in e.vertices() {
                offsets[v as usize + 1] += 1;
            }
        }
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut entries = vec![(0u32, [0.0f32; 2], 0.0f32); offsets[n] as usize];
        let mut degree = vec![0.0; n];
        for (e, edge) in topology.edges().iter().enumerate() {
            let [lo, hi] = edge.vertices();
            // Degrees sum the weights as stored, so each row's balance is exact.
            let (w, r) = (weights[e] as f32, transport[e]);
            let wr = [(f64::from(w) * r[0]) as f32, (f64::from(w) * r[1]) as f32];
            entries[fill[lo as usize] as usize] = (hi, [wr[0], -wr[1]], w);
            fill[lo as usize] += 1;
            entries[fill[hi as usize] as usize] = (lo, wr, w);
            fill[hi as usize] += 1;
            degree[lo as usize] += f64::from(w);
            degree[hi as usize] += f64::from(w);
        }
        Connection {
            offsets,
            entries,
            degree,
            transport,
        }
    }

    /// `y = (L + diag(shift)) x` for interleaved complex vectors; `identity` replaces every
    /// transport by 1 (the scalar Laplacian, for the slant).
    pub(super) fn apply(&self, shift: &[f64], identity: bool, x: &[f64], y: &mut [f64]) {
        use rayon::prelude::*;
        const ROWS: usize = 512;
        y.par_chunks_mut(2 * ROWS).enumerate().for_each(|(chunk, out)| {
            for (k, out) in out.chunks_mut(2).enumerate() {
                let i = chunk * ROWS + k;
                let d = self.degree[i] + shift[i];
                let mut acc = [d * x[2 * i], d * x[2 * i + 1]];
                let row = &self.entries[self.offsets[i] as usize..self.offsets[i + 1] as usize];
                for &(j, wf, w) in row {
                    let xj = [x[2 * j as usize], x[2 * j as usize + 1]];
                    let t = if identity {
                        [f64::from(w) * xj[0], f64::from(w) * xj[1]]
                    } else {
                        mul([f64::from(wf[0]), f64::from(wf[1])], xj)
                    };
                    acc[0] -= t[0];
                    acc[1] -= t[1];
                }
                out.copy_from_slice(&acc);
            }
        });
    }
}

/// Cotangent weight per edge, `(cot α + cot β) / 2` summed over all faces of the edge, clamped
/// to `[MIN_WEIGHT, MAX_WEIGHT]`. Zero-area faces add nothing.
fn edge_weights(mesh: &FurMesh) -> Vec<f64> {
    let topology = mesh.topology();
    let positions = mesh.positions();
    let mut weights = vec![0.0f64; topology.edges().len()];
    for (f, tri) in mesh.triangles().iter().enumerate() {
        if mesh.degenerate_faces()[f] {
            continue;
        }
        let p = tri.map(|v| wide(positions[v as usize]));
        for k in 0..3 {
            let u = p[(k + 1) % 3] - p[k];
            let v = p[(k + 2) % 3] - p[k];
            let sine = u.cross(v).length();
            let edge = topology.face_edges()[f][(k + 1) % 3];
            if edge != NO_EDGE && sine > 0.0 {
                weights[edge as usize] += 0.5 * u.dot(v) / sine;
            }
        }
    }
    weights
        .iter()
        .map(|&w| {
            if w.is_finite() {
                w.clamp(MIN_WEIGHT, MAX_WEIGHT)
            } else {
                MIN_WEIGHT
            }
        })
        .collect()
}

/// Angle `ρ` such that a tangent vector at angle `φ` in `a`'s frame has angle `φ + ρ` in `b`'s
/// frame after the smallest rotation taking `n_a` to `n_b`.
fn transport_angle(mesh: &FurMesh, a: usize, b: usize) -> f64 {
    let (na, nb) = (wide(mesh.normals()[a]), wide(mesh.normals()[b]));
    let ta = wide(mesh.tangents()[a]);
    let (tb, bb) = (wide(mesh.tangents()[b]), wide(mesh.bitangents()[b]));
    let c = na.dot(nb);
    let moved = if c > -1.0 + 1e-9 {
        // Rodrigues' formula with axis·sin = na × nb and 1 - cos folded into 1/(1 + c).
        let v = na.cross(nb);
        let vxt = v.cross(ta);
        let k = v.dot(ta) / (1.0 + c);
        ta * c + vxt + v * k
    } else {
        // Opposite normals: no smallest rotation; project onto b's plane instead.
        ta - ta.dot(nb) * nb
    };
    let (x, y) = (moved.dot(tb), moved.dot(bb));
    if x == 0.0 && y == 0.0 { 0.0 } else { y.atan2(x) }
}
