//! How sharply the surface curves at each vertex, for the terminator band of PRT's directional
//! light (`prt_rotate.wgsl` in pelt-render): hair `h` tall on a surface curving at κ sees √(2hκ)
//! past the body's terminator in N·L, none on a flat surface. The shaded passes take κ from screen
//! derivatives (`surface_curvature`, `lighting.wgsl`); the PRT rotation runs per vertex, so it
//! takes it from the mesh.

use glam::Vec3;
use rayon::prelude::*;

use super::surface_mesh::SurfaceMesh;

/// Per vertex of `mesh`, the largest curvature along its triangles' edges: how fast the normal
/// turns per unit of the edge toward the edge, `(n₁ − n₀)·e / |e|²` (as the fins measure theirs,
/// `edge_curvature`); 0 where flat or concave and at isolated vertices. On a sphere of radius `R`
/// this is `1/R`.
pub fn vertex_curvature(mesh: &SurfaceMesh) -> Vec<f32> {
    let vertices = &mesh.vertices;
    let edge = |a: u32, b: u32| -> f32 {
        let (a, b) = (&vertices[a as usize], &vertices[b as usize]);
        let e = Vec3::from(b.position) - Vec3::from(a.position);
        let turn = Vec3::from(b.normal).normalize_or_zero() - Vec3::from(a.normal).normalize_or_zero();
        let length = e.length_squared();
        if length > 0.0 {
            (turn.dot(e) / length).max(0.0)
        } else {
            0.0
        }
    };
    // Each triangle's three edges, then the largest at each corner: max is order-free, so the
    // result does not depend on the thread count.
    let per_triangle: Vec<[f32; 3]> = mesh
        .indices
        .par_chunks_exact(3)
        .map(|t| {
            let (ab, bc, ca) = (edge(t[0], t[1]), edge(t[1], t[2]), edge(t[2], t[0]));
            [ab.max(ca), ab.max(bc), bc.max(ca)]
        })
        .collect();
    let mut curvature = vec![0.0f32; vertices.len()];
    for (t, corners) in mesh.indices.chunks_exact(3).zip(&per_triangle) {
        for (&v, &k) in t.iter().zip(corners) {
            let slot = &mut curvature[v as usize];
            *slot = slot.max(if k.is_finite() { k } else { 0.0 });
        }
    }
    curvature
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::surface_mesh::SurfaceVertex;

    /// A latitude–longitude grid of `n × 2n` quads over a sphere of `radius`, its normals pointing
    /// out (or in, `inward`).
    fn sphere(radius: f32, n: usize, inward: bool) -> SurfaceMesh {
        let mut vertices = Vec::new();
        for i in 0..=n {
            for j in 0..=2 * n {
                let (theta, phi) = (
                    std::f32::consts::PI * (0.1 + 0.8 * i as f32 / n as f32),
                    std::f32::consts::PI * j as f32 / n as f32,
                );
                let d = Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
                vertices.push(SurfaceVertex {
                    position: (radius * d).to_array(),
                    normal: (if inward { -d } else { d }).to_array(),
                    dpdu: [0.0; 3],
                    dpdv: [0.0; 3],
                    uv: [0.0; 2],
                    comb: [0.0; 3],
                    border: [0.0; 2],
                });
            }
        }
        let at = |i: usize, j: usize| (i * (2 * n + 1) + j) as u32;
        let indices = (0..n)
            .flat_map(|i| (0..2 * n).map(move |j| (i, j)))
            .flat_map(|(i, j)| {
                [
                    at(i, j),
                    at(i + 1, j),
                    at(i + 1, j + 1),
                    at(i, j),
                    at(i + 1, j + 1),
                    at(i, j + 1),
                ]
            })
            .collect();
        let source = (0..vertices.len() as u32).collect();
        SurfaceMesh {
            vertices,
            source,
            indices,
            uv_scale: 1.0,
        }
    }

    #[test]
    fn a_sphere_curves_at_one_over_its_radius_a_plane_and_a_hollow_not_at_all() {
        // Normals along the radius turn by e / R along any edge e: (e / R)·e / |e|² = 1 / R.
        for k in vertex_curvature(&sphere(2.5, 8, false)) {
            assert!((k - 0.4).abs() < 1e-5, "{k}");
        }
        assert!(vertex_curvature(&sphere(2.5, 8, true)).iter().all(|&k| k == 0.0));
        let mut flat = sphere(1.0, 4, false);
        for v in &mut flat.vertices {
            v.position[2] = 0.0;
            v.normal = [0.0, 0.0, 1.0];
        }
        assert!(vertex_curvature(&flat).iter().all(|&k| k == 0.0));
    }
}
