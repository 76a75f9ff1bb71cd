//! Face normals, area-weighted vertex normals and per-vertex tangent frames.
//!
//! Vertex normals sum the unnormalized face normals (|n| = twice the area) of the triangles around
//! the vertex, so large faces weigh more and degenerate ones weigh nothing. The tangent frame is the
//! branchless orthonormal basis of Duff et al., "Building an Orthonormal Basis, Revisited" (JCGT
//! 2017): continuous everywhere except where the normal points straight down, and cheap; the comb
//! field measures its angles against it, so only its consistency matters, not its direction.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::topology::Topology;

/// Fallback normal for a vertex whose triangles all have zero area (or that has none).
const FALLBACK_NORMAL: [f32; 3] = [0.0, 0.0, 1.0];

/// A triangle counts as degenerate when the sine of its corner angle at vertex 0 is below this.
const DEGENERATE_SINE: f64 = 1e-6;

/// A position or direction widened to f64: squares of any f32 magnitude (up to 6.8e38 for a
/// difference, and down to the subnormals) stay finite and non-zero, so every geometric test
/// below is scale-free.
fn wide(p: [f32; 3]) -> DVec3 {
    Vec3::from(p).as_dvec3()
}

/// Euclidean length in f64.
pub(super) fn norm(a: [f64; 3]) -> f64 {
    DVec3::from(a).length()
}

/// `a` scaled to unit length and rounded to f32, or `fallback` when it has none.
fn normalize_or(a: DVec3, fallback: [f32; 3]) -> [f32; 3] {
    let n = a.length();
    if n > 0.0 && n.is_finite() {
        (a / n).as_vec3().to_array()
    } else {
        fallback
    }
}

/// Unnormalized normal per triangle: `(p1 - p0) × (p2 - p0)` in f64, length twice the area.
pub(super) fn face_normals(positions: &[[f32; 3]], triangles: &[[u32; 3]]) -> Vec<[f64; 3]> {
    triangles
        .par_iter()
        .map(|t| {
            let p0 = wide(positions[t[0] as usize]);
            (wide(positions[t[1] as usize]) - p0)
                .cross(wide(positions[t[2] as usize]) - p0)
                .to_array()
        })
        .collect()
}

/// True for triangles with a repeated vertex or (numerically) collinear corners.
pub(super) fn degenerate_faces(
    positions: &[[f32; 3]],
    triangles: &[[u32; 3]],
    face_normals: &[[f64; 3]],
) -> Vec<bool> {
    triangles
        .par_iter()
        .zip(face_normals)
        .map(|(t, n)| {
            if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
                return true;
            }
            let p0 = wide(positions[t[0] as usize]);
            let e1 = (wide(positions[t[1] as usize]) - p0).length();
            let e2 = (wide(positions[t[2] as usize]) - p0).length();
            // |e1 × e2| = |e1| |e2| sin(angle): scale-free test for zero area
            norm(*n) <= DEGENERATE_SINE * e1 * e2
        })
        .collect()
}

/// Area-weighted unit vertex normals (summed in f64).
pub(super) fn vertex_normals(topology: &Topology, face_normals: &[[f64; 3]]) -> Vec<[f32; 3]> {
    (0..topology.vertex_count())
        .into_par_iter()
        .map(|v| {
            let sum = topology
                .vertex_faces(v)
                .iter()
                .fold(DVec3::ZERO, |acc, &f| acc + DVec3::from(face_normals[f as usize]));
            normalize_or(sum, FALLBACK_NORMAL)
        })
        .collect()
}

/// Given normals scaled to unit length (validation has rejected zero rows; in f64 every other
/// finite row has a length, however large or small).
pub(super) fn normalize_given(normals: &[[f32; 3]]) -> Vec<[f32; 3]> {
    normals
        .par_iter()
        .map(|&n| normalize_or(wide(n), FALLBACK_NORMAL))
        .collect()
}

/// Tangent and bitangent per vertex from its unit normal.
pub(super) fn tangent_frames(normals: &[[f32; 3]]) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    normals
        .par_iter()
        .map(|&n| {
            let [t, b] = orthonormal_basis(n);
            (t, b)
        })
        .unzip()
}

/// Two unit vectors `[t, b]` completing the unit vector `n` to a right-handed basis `(t, b, n)`
/// (Duff et al. 2017, as glam's `any_orthonormal_pair`).
pub fn orthonormal_basis(n: [f32; 3]) -> [[f32; 3]; 2] {
    let (t, b) = Vec3::from(n).any_orthonormal_pair();
    [t.to_array(), b.to_array()]
}
