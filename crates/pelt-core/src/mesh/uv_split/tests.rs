//! The seam split against hand-made layouts and the parametric torus's analytic derivatives.

use super::split_at_uv_seams;
use crate::error::PeltError;
use crate::mesh::shapes::torus;
use crate::{FurMesh, MeshInput};

fn parameter_name(e: PeltError) -> String {
    match e {
        PeltError::InvalidParameter { name, .. } => name,
        other => panic!("expected an invalid parameter, got {other}"),
    }
}

/// A 2 × 2 square in the xy plane as two triangles sharing the diagonal 0–2.
pub(crate) fn square() -> FurMesh {
    let positions = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 2.0, 0.0], [0.0, 2.0, 0.0]];
    let triangles = [[0, 1, 2], [0, 2, 3]];
    FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap()
}

#[test]
fn vertices_split_only_where_uvs_differ_and_derivatives_match_the_map() {
    let mesh = square();
    // UV = position / 2: one chart, no seam.
    let uvs = [
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
        [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
    ];
    let split = split_at_uv_seams(&mesh, &uvs).unwrap();
    assert_eq!(split.len(), 4);
    for i in 0..split.len() {
        assert_eq!(split.dpdu[i], [2.0, 0.0, 0.0]);
        assert_eq!(split.dpdv[i], [0.0, 2.0, 0.0]);
        let p = mesh.positions()[split.source[i] as usize];
        assert_eq!(split.uvs[i], [p[0] / 2.0, p[1] / 2.0]);
    }
    // Every side is twice as long in 3D as in the tile.
    assert!((split.uv_scale - 0.5).abs() < 1e-12);
    for (f, tri) in mesh.triangles().iter().enumerate() {
        for k in 0..3 {
            let vertex = split.indices[3 * f + k] as usize;
            assert_eq!(split.source[vertex], tri[k]);
            assert_eq!(split.uvs[vertex], uvs[f][k]);
        }
    }

    // The second triangle shifted by a whole tile: the diagonal's two vertices split.
    let seam = [uvs[0], uvs[1].map(|[u, v]| [u + 1.0, v])];
    let split = split_at_uv_seams(&mesh, &seam).unwrap();
    assert_eq!(split.len(), 6);
    assert_eq!(split.source, [0, 0, 1, 2, 2, 3]);
    assert_eq!(split.expand(&[10u8, 11, 12, 13]), [10, 10, 11, 12, 12, 13]);
}

#[test]
fn negative_zero_shares_a_vertex_with_zero() {
    let mesh = square();
    let uvs = [
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
        [[-0.0, -0.0], [1.0, 1.0], [0.0, 1.0]],
    ];
    let split = split_at_uv_seams(&mesh, &uvs).unwrap();
    assert_eq!(split.len(), 4);
    assert!(split.uvs.iter().flatten().all(|c| c.is_sign_positive()));
}

#[test]
fn torus_derivatives_follow_the_parametric_surface() {
    let (around, across, repeats) = (48usize, 24usize, [4.0f64, 2.0]);
    let (positions, triangles) = torus(around, across);
    let mesh = FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap();
    // UVs of the parametric angles (θ around, φ across), scaled to a few tiles; the wrap-around
    // quads get the end of the range so no triangle spans the whole tile.
    let uv_of = |i: usize, j: usize| {
        [
            (repeats[0] * i as f64 / around as f64) as f32,
            (repeats[1] * j as f64 / across as f64) as f32,
        ]
    };
    let mut uvs = Vec::new();
    for i in 0..around {
        for j in 0..across {
            let (a, b, c, d) = (uv_of(i, j), uv_of(i + 1, j), uv_of(i + 1, j + 1), uv_of(i, j + 1));
            uvs.push([a, b, c]);
            uvs.push([a, c, d]);
        }
    }
    let split = split_at_uv_seams(&mesh, &uvs).unwrap();
    // Seams where i or j wraps: one extra column of `across + 1` and row of `around` vertices.
    assert_eq!(split.len(), (around + 1) * (across + 1));
    for (k, &src) in split.source.iter().enumerate() {
        let (i, j) = (src as usize / across, src as usize % across);
        let (theta, phi) = (
            std::f64::consts::TAU * i as f64 / around as f64,
            std::f64::consts::TAU * j as f64 / across as f64,
        );
        // P = ((1 + r cos φ) cos θ, (1 + r cos φ) sin θ, r sin φ), u = 4 θ / 2π, v = 2 φ / 2π.
        let r = 1.0 + 0.35 * phi.cos();
        let dpdu = [-r * theta.sin(), r * theta.cos(), 0.0].map(|c| c * std::f64::consts::TAU / repeats[0]);
        let dpdv = [
            -0.35 * phi.sin() * theta.cos(),
            -0.35 * phi.sin() * theta.sin(),
            0.35 * phi.cos(),
        ]
        .map(|c| c * std::f64::consts::TAU / repeats[1]);
        let uv = split.uvs[k];
        for (got, want) in [(split.dpdu[k], dpdu), (split.dpdv[k], dpdv)] {
            let scale = want.iter().map(|c| c * c).sum::<f64>().sqrt();
            let err = (0..3)
                .map(|c| (f64::from(got[c]) - want[c]).powi(2))
                .sum::<f64>()
                .sqrt();
            // Averaged chords of a 48 × 24 torus are a few percent off the tangent; a copy on a
            // seam only sees the faces on its side of it (one-sided chords, half a step off).
            let seam = uv[0] == 0.0 || uv[0] == 4.0 || uv[1] == 0.0 || uv[1] == 2.0;
            let tolerance = if seam { 0.2 } else { 0.03 };
            assert!(err < tolerance * scale, "vertex {src}: {got:?} vs {want:?}");
        }
    }
}

#[test]
fn bad_uvs_are_named() {
    let mesh = square();
    let short = [[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]];
    assert_eq!(
        parameter_name(split_at_uv_seams(&mesh, &short).unwrap_err()),
        "corner_uvs"
    );
    let nan = [
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
        [[0.0, 0.0], [f32::NAN, 1.0], [0.0, 1.0]],
    ];
    assert_eq!(
        parameter_name(split_at_uv_seams(&mesh, &nan).unwrap_err()),
        "corner_uvs[1]"
    );
    let flat = [[[0.5, 0.5]; 3]; 2];
    assert_eq!(
        parameter_name(split_at_uv_seams(&mesh, &flat).unwrap_err()),
        "corner_uvs"
    );
}

#[test]
fn a_mesh_bald_everywhere_needs_no_uv_layout() {
    let positions = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 2.0, 0.0], [0.0, 2.0, 0.0]];
    let triangles = [[0, 1, 2], [0, 2, 3]];
    let bald = [0.0; 4];
    let mesh = FurMesh::new(MeshInput::new(&positions, &triangles).with_length(&bald)).unwrap();
    // Bald faces get no patch, so all their UVs are zero.
    let flat = [[[0.0, 0.0]; 3]; 2];
    let split = split_at_uv_seams(&mesh, &flat).unwrap();
    assert_eq!(split.source.len(), 4);
    assert_eq!(split.uv_scale, 1.0);
    // The mesh's own frame: unit vectors in the square's plane.
    for (u, v) in split.dpdu.iter().zip(&split.dpdv) {
        let dot = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
        assert!(dot.abs() < 1e-6 && u[2] == 0.0 && v[2] == 0.0, "{u:?} {v:?}");
    }
    // One furred vertex is enough for the collapsed layout to be an error again.
    let one = [0.0, 0.0, 1.0, 0.0];
    let furred = FurMesh::new(MeshInput::new(&positions, &triangles).with_length(&one)).unwrap();
    assert_eq!(
        parameter_name(split_at_uv_seams(&furred, &flat).unwrap_err()),
        "corner_uvs"
    );
}
