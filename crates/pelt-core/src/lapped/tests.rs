//! Tests of the lapped patches: the acceptance figures on the test meshes, an exact flat case,
//! scale invariance, thread-count independence, whole polygons, bald faces and bad parameters.

use super::quality::metrics;
use super::*;
use crate::mesh::{MeshInput, shapes};
use glam::DVec3;

type Shape = (Vec<[f32; 3]>, Vec<[u32; 3]>);

fn mesh(shape: &Shape) -> FurMesh {
    FurMesh::new(MeshInput::new(&shape.0, &shape.1)).unwrap()
}

fn params(tile_size: f64) -> PatchParams {
    PatchParams {
        tile_size,
        ..PatchParams::default()
    }
}

/// The figures the lead reports, on stderr (`cargo test -- --nocapture`).
fn report(name: &str, m: &FurMesh, p: &Patches) {
    let q = &p.quality;
    eprintln!(
        "{name}: {} triangles, {} patches, seam fraction {:.3}, mean alignment {:.2}°, \
         stretch within [0.8, 1.25] on {:.1}% of the area, {} flipped, coverage {:.3}, {} singular faces",
        m.face_count(),
        q.patch_count,
        q.seam_length_fraction,
        q.mean_alignment_deg,
        100.0 * q.stretch_within_fraction,
        q.flipped_faces,
        q.coverage,
        q.singularities,
    );
}

/// Full coverage, no flips, finite UVs, ids in range, and one UV per vertex within a patch.
fn assert_valid(name: &str, m: &FurMesh, p: &Patches) {
    let q = &p.quality;
    assert_eq!(q.coverage, 1.0, "{name}");
    assert_eq!(q.flipped_faces, 0, "{name}");
    for f in 0..m.face_count() {
        assert!(p.uv[f].iter().flatten().all(|c| c.is_finite()), "{name} face {f}");
        assert!((p.patch[f] as usize) < q.patch_count, "{name} face {f}");
        // Independent flip check in 3D: the UV triangle's orientation against the face's.
        if !m.degenerate_faces()[f] {
            let [a, b, c] = p.uv[f].map(|x| x.map(f64::from));
            let signed = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            assert!(signed > 0.0, "{name} face {f} flipped in UV");
        }
    }
    // Within a patch a vertex has one UV.
    let mut seen: std::collections::HashMap<(u32, u32), [f32; 2]> = Default::default();
    for (f, tri) in m.triangles().iter().enumerate() {
        for (&v, &corner) in tri.iter().zip(&p.uv[f]) {
            let uv = *seen.entry((p.patch[f], v)).or_insert(corner);
            assert_eq!(
                uv, corner,
                "{name}: vertex {v} has two UVs in patch {}",
                p.patch[f]
            );
        }
    }
    for (i, d) in p.direction.iter().enumerate() {
        assert!(d.iter().all(|c| c.is_finite()), "{name} direction {i}");
    }
}

#[test]
fn metrics_of_known_jacobians() {
    // A rotation by 10°: rows ∇u = (cos, −sin), ∇v = (sin, cos) map the field direction (1, 0)
    // to (cos, sin); the u axis comes from the direction rotated by −10°.
    let (c, s) = (10f64.to_radians().cos(), 10f64.to_radians().sin());
    let m = metrics([[c, -s], [s, c]]);
    assert!((m.alignment.to_degrees() - 10.0).abs() < 1e-9);
    assert!((m.sigma[0] - 1.0).abs() < 1e-12 && (m.sigma[1] - 1.0).abs() < 1e-12);
    assert!((m.det - 1.0).abs() < 1e-12);
    let m = metrics([[2.0, 0.0], [0.0, 0.5]]);
    assert_eq!((m.sigma, m.alignment, m.det), ([2.0, 0.5], 0.0, 1.0));
    // Shear [[1, 1], [0, 1]]: singular values (√5 ± 1) / 2; the u axis is still the field.
    let m = metrics([[1.0, 1.0], [0.0, 1.0]]);
    let golden = (5f64.sqrt() + 1.0) / 2.0;
    assert!((m.sigma[0] - golden).abs() < 1e-12 && (m.sigma[1] - 1.0 / golden).abs() < 1e-12);
    assert!(m.alignment.abs() < 1e-12);
    // A mirror image is flipped.
    assert!(metrics([[1.0, 0.0], [0.0, -1.0]]).det < 0.0);
}

#[test]
fn a_vertical_plane_is_one_exact_patch() {
    // A grid in the XZ plane facing −Y: "down" lies in the plane, so the field is −Z everywhere
    // and the parameterization is exact up to the patch offset: u runs along −Z and v along
    // normal × field = (−Y) × (−Z) = +X, both one tile per `tile` units.
    let n = 12;
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push([i as f32 / n as f32, 0.0, j as f32 / n as f32]);
        }
    }
    let mut triangles = Vec::new();
    let g = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..n {
        for i in 0..n {
            triangles.push([g(i, j), g(i + 1, j), g(i + 1, j + 1)]);
            triangles.push([g(i, j), g(i + 1, j + 1), g(i, j + 1)]);
        }
    }
    let m = FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap();
    assert!(m.normals()[0][1] < -0.99, "the grid faces −Y");
    let tile = 0.25;
    let p = build_patches(&m, &params(tile)).unwrap();
    assert_valid("plane", &m, &p);
    assert_eq!(p.quality.patch_count, 1);
    let anchor = (triangles[0][0] as usize, p.uv[0][0]);
    for (f, tri) in triangles.iter().enumerate() {
        for c in 0..3 {
            let (q, q0) = (positions[tri[c] as usize], positions[anchor.0]);
            let expected = [-(q[2] - q0[2]) / tile as f32, (q[0] - q0[0]) / tile as f32];
            for (k, want) in expected.into_iter().enumerate() {
                let got = p.uv[f][c][k] - anchor.1[k];
                assert!((got - want).abs() < 1e-5, "face {f} corner {c}: {got} vs {want}");
            }
        }
    }
}

#[test]
fn the_uv_sphere_meets_the_acceptance_figures() {
    let (segments, rings) = (64, 32);
    let (positions, triangles) = shapes::uv_sphere(segments, rings);
    let polygons = shapes::uv_sphere_polygons(segments, rings);
    // As Blender hands it over (quads as polygons), and as bare triangles.
    let quads = FurMesh::new(MeshInput::new(&positions, &triangles).with_polygons(&polygons)).unwrap();
    let bare = FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap();
    for (name, m) in [
        ("uv sphere 64x32 (quads)", &quads),
        ("uv sphere 64x32 (triangles)", &bare),
    ] {
        let p = build_patches(m, &params(0.2)).unwrap();
        report(name, m, &p);
        assert_valid(name, m, &p);
        let q = &p.quality;
        assert!(q.mean_alignment_deg <= 3.0, "{name}: {}", q.mean_alignment_deg);
        assert!(
            q.stretch_within_fraction >= 0.95,
            "{name}: {}",
            q.stretch_within_fraction
        );
        assert!(q.patch_count <= 40, "{name}: {} patches", q.patch_count);
        // Independent check of the alignment figure on the undistorted bulk: away from the
        // poles, the surface image of the u axis must follow the meridians (−Z projected).
        let mut worst: f64 = 0.0;
        for (f, tri) in triangles.iter().enumerate() {
            let c = tri.map(|v| positions[v as usize].map(f64::from));
            let centroid = [0, 1, 2].map(|k| (c[0][k] + c[1][k] + c[2][k]) / 3.0);
            if centroid[2].abs() > 0.7 || q.face_stretch[f][0] > 1.25 || q.face_stretch[f][1] < 0.8 {
                continue;
            }
            worst = worst.max(u_axis_angle_deg(&c, &p.uv[f], [0.0, 0.0, -1.0]));
        }
        assert!(worst < 10.0, "{name}: u axis {worst}° off the meridian");
    }
}

/// Angle between the 3D direction along which v stays constant and u grows on the triangle with
/// corners `c` and UVs `uv`, and `direction` projected into the triangle's plane.
fn u_axis_angle_deg(c: &[[f64; 3]; 3], uv: &[[f32; 2]; 3], direction: [f64; 3]) -> f64 {
    let c = c.map(DVec3::from);
    let (e1, e2) = (c[1] - c[0], c[2] - c[0]);
    let (du1, dv1) = (f64::from(uv[1][0] - uv[0][0]), f64::from(uv[1][1] - uv[0][1]));
    let (du2, dv2) = (f64::from(uv[2][0] - uv[0][0]), f64::from(uv[2][1] - uv[0][1]));
    // Solve a·(du1, dv1) + b·(du2, dv2) = (1, 0): the 3D preimage is a·e1 + b·e2.
    let det = du1 * dv2 - du2 * dv1;
    let (a, b) = (dv2 / det, -dv1 / det);
    let w = a * e1 + b * e2;
    let n = e1.cross(e2);
    let direction = DVec3::from(direction);
    let d = direction.reject_from(n);
    w.angle_between(d).to_degrees()
}

#[test]
fn painted_combs_are_followed_by_the_patches() {
    // Combs along +Y (projected) on the half x > 0 of a sphere: the field there must be within
    // 2° of them, and the texture's u axis must follow the field.
    let (positions, triangles) = shapes::uv_sphere(64, 32);
    let comb: Vec<[f32; 3]> = positions
        .iter()
        .map(|p| if p[0] > 0.0 { [0.0, 1.0, 0.0] } else { [0.0; 3] })
        .collect();
    let m = FurMesh::new(MeshInput::new(&positions, &triangles).with_comb(&comb)).unwrap();
    let p = build_patches(&m, &params(0.2)).unwrap();
    assert_valid("painted", &m, &p);
    for (i, q) in positions.iter().enumerate() {
        // +Y is normal to the sphere at (0, ±1, 0): stay clear of where the comb has no direction.
        if q[0] > 0.05 && q[1].abs() < 0.9 {
            let n = m.normals()[i].map(f64::from);
            let along = n[1];
            let expected = [-along * n[0], 1.0 - along * n[1], -along * n[2]];
            let d = p.direction[i].map(f64::from);
            let cos = (d[0] * expected[0] + d[1] * expected[1] + d[2] * expected[2])
                / (expected.iter().map(|c| c * c).sum::<f64>()).sqrt();
            assert!(cos.clamp(-1.0, 1.0).acos().to_degrees() <= 2.0, "vertex {i}");
        }
    }
    let (mut area, mut weighted) = (0.0, 0.0);
    for (f, tri) in triangles.iter().enumerate() {
        let c = tri.map(|v| positions[v as usize].map(f64::from));
        if tri
            .iter()
            .all(|&v| positions[v as usize][0] > 0.05 && positions[v as usize][1].abs() < 0.9)
        {
            let a = face_area(&c);
            area += a;
            weighted += a * u_axis_angle_deg(&c, &p.uv[f], [0.0, 1.0, 0.0]);
        }
    }
    assert!(
        weighted / area <= 3.0,
        "mean u-axis error on the painted half {}°",
        weighted / area
    );
}

fn face_area(c: &[[f64; 3]; 3]) -> f64 {
    let c = c.map(DVec3::from);
    0.5 * (c[1] - c[0]).cross(c[2] - c[0]).length()
}

#[test]
fn awkward_meshes_are_fully_covered_without_flips() {
    let cases: Vec<(&str, Shape)> = vec![
        ("torus", shapes::torus(96, 32)),
        ("cube", shapes::cube(12)),
        ("sphere with holes", shapes::sphere_with_holes(48, 24)),
        ("two components", shapes::two_components()),
        ("non-manifold fin", shapes::fin(16)),
        ("zero-area faces", shapes::with_zero_area_faces(48, 24)),
    ];
    for (name, shape) in &cases {
        let m = mesh(shape);
        let p = build_patches(&m, &params(0.2)).unwrap();
        report(name, &m, &p);
        assert_valid(name, &m, &p);
    }
}

#[test]
fn a_large_bumpy_mesh_is_fully_covered_without_flips() {
    let shape = shapes::bumpy_torus(224, 224);
    let m = mesh(&shape);
    let p = build_patches(&m, &params(0.05)).unwrap();
    report("bumpy torus 100k", &m, &p);
    assert_valid("bumpy torus", &m, &p);
}

#[test]
fn scaling_mesh_and_tile_together_changes_nothing() {
    let shape = shapes::bumpy_torus(48, 24);
    let reference = build_patches(&mesh(&shape), &params(0.1)).unwrap();
    for scale in [1e-3f32, 1e3] {
        let scaled: Shape = (
            shape.0.iter().map(|q| q.map(|c| c * scale)).collect(),
            shape.1.clone(),
        );
        let p = build_patches(&mesh(&scaled), &params(0.1 * f64::from(scale))).unwrap();
        assert_eq!(p.patch, reference.patch, "scale {scale}");
        // The inputs differ by f32 rounding of the scaled positions, and the patch solves stop at
        // a relative residual of 1e-3, so UVs agree to the solver's accuracy, not to the last bit:
        // 1e-4 of the largest UV (tile units; a patch spans up to ~30 tiles here).
        let largest = reference
            .uv
            .iter()
            .flatten()
            .flatten()
            .fold(0.0f32, |m, x| m.max(x.abs()));
        let worst =
            p.uv.iter()
                .flatten()
                .flatten()
                .zip(reference.uv.iter().flatten().flatten())
                .fold(0.0f32, |m, (a, b)| m.max((a - b).abs()));
        assert!(worst <= 1e-4 * largest, "scale {scale}: {worst} of {largest}");
        eprintln!("scale {scale}: UVs within {worst:.2e} of the unscaled ones (largest UV {largest:.1})");
    }
}

/// Powers of two scale f32 positions exactly, so every stage, computed scale-free, gives the same
/// layout to the bit from 2⁻⁶⁶ (1.4e-20) to 2¹²⁰ (1.3e36): an f32 product of two coordinates
/// would overflow above about 2⁶⁴ and underflow below 2⁻⁶³, so the mesh's geometry is computed in
/// f64. (Below 2⁻⁶⁶ the sphere's smallest coordinates, about 1e-9, turn subnormal in f32 and lose
/// bits before Pelt sees them.)
#[test]
fn extreme_powers_of_two_change_nothing_but_the_scale() {
    let (positions, triangles) = shapes::uv_sphere(24, 12);
    let polygons = shapes::uv_sphere_polygons(24, 12);
    let build = |scale: f32| {
        let scaled: Vec<[f32; 3]> = positions.iter().map(|q| q.map(|c| c * scale)).collect();
        let input = MeshInput {
            polygons: Some(&polygons),
            ..MeshInput::new(&scaled, &triangles)
        };
        let m = FurMesh::new(input).unwrap();
        let p = build_patches(&m, &params(0.3 * f64::from(scale))).unwrap();
        (
            m.stats().surface_area / f64::from(scale).powi(2),
            m.normals().to_vec(),
            p,
        )
    };
    let (area, normals, reference) = build(1.0);
    assert!(reference.quality.patch_count > 4);
    for k in [-66, -40, 40, 66, 100, 120] {
        let scale = 2f32.powi(k);
        let (a, n, p) = build(scale);
        assert_eq!(a, area, "2^{k}: area / scale²");
        // Compared whole, without printing the arrays.
        assert!(n == normals, "2^{k}: normals differ");
        assert!(p.patch == reference.patch, "2^{k}: patches differ");
        assert!(p.uv == reference.uv, "2^{k}: UVs differ");
        assert!(p.direction == reference.direction, "2^{k}: directions differ");
        assert_eq!(
            p.quality.mean_alignment_deg, reference.quality.mean_alignment_deg,
            "2^{k}"
        );
        assert!(p.uv.iter().flatten().flatten().all(|c| c.is_finite()));
    }
}

/// A tile so small that f32 UVs could not place it, or so large that they could not tell the
/// mesh's corners apart, is refused by name instead of giving inf UVs or NaN figures.
#[test]
fn tiles_too_small_for_float_uvs_are_refused() {
    let m = mesh(&shapes::uv_sphere(12, 6));
    let error = build_patches(&m, &params(1e-7)).unwrap_err().to_string();
    assert!(
        error.contains("`tile_size`") && error.contains("tiles across"),
        "{error}"
    );
    assert!(build_patches(&m, &params(4.0 / MAX_TILES_ACROSS)).is_ok());
    // And so large that the whole mesh would fall within a few f32 steps of one UV (NaN figures).
    let error = build_patches(&m, &params(1e308)).unwrap_err().to_string();
    assert!(
        error.contains("`tile_size`") && error.contains("tiles across"),
        "{error}"
    );
    assert!(build_patches(&m, &params(1.0 / MIN_TILES_ACROSS)).is_ok());
}

#[test]
fn the_layout_does_not_depend_on_the_thread_count() {
    let shape = shapes::bumpy_torus(96, 48);
    let m = mesh(&shape);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| build(&m, &params(0.1), None).unwrap())
    };
    let (one, two) = (run(1), run(2));
    let bits = |p: &Patches| -> Vec<u32> { p.uv.iter().flatten().flatten().map(|x| x.to_bits()).collect() };
    assert_eq!(one.patch, two.patch);
    assert_eq!(bits(&one), bits(&two));
    assert_eq!(one.quality, two.quality);
}

#[test]
fn other_seeds_give_other_layouts() {
    let shape = shapes::uv_sphere(32, 16);
    let m = mesh(&shape);
    let a = build_patches(&m, &params(0.2)).unwrap();
    let b = build_patches(
        &m,
        &PatchParams {
            seed: 7,
            ..params(0.2)
        },
    )
    .unwrap();
    assert_ne!(a.uv, b.uv);
}

#[test]
fn polygons_stay_whole() {
    let (segments, rings) = (48, 24);
    let (positions, triangles) = shapes::uv_sphere(segments, rings);
    let polygons = shapes::uv_sphere_polygons(segments, rings);
    let m = FurMesh::new(MeshInput::new(&positions, &triangles).with_polygons(&polygons)).unwrap();
    let p = build_patches(&m, &params(0.2)).unwrap();
    assert_valid("quads", &m, &p);
    let mut patch_of = std::collections::HashMap::new();
    for (t, &polygon) in polygons.iter().enumerate() {
        let first = *patch_of.entry(polygon).or_insert(p.patch[t]);
        assert_eq!(first, p.patch[t], "polygon {polygon} split");
    }
}

#[test]
fn bald_faces_get_no_patch() {
    let (positions, triangles) = shapes::uv_sphere(32, 16);
    // Bald below the equator; faces on the equator keep a furred vertex.
    let length: Vec<f32> = positions
        .iter()
        .map(|p| if p[2] < -0.01 { 0.0 } else { 1.0 })
        .collect();
    let m = FurMesh::new(MeshInput::new(&positions, &triangles).with_length(&length)).unwrap();
    let p = build_patches(&m, &params(0.2)).unwrap();
    let mut furred = 0;
    for (f, tri) in triangles.iter().enumerate() {
        let bald = tri.iter().all(|&v| length[v as usize] == 0.0);
        if bald {
            assert_eq!(p.patch[f], NO_PATCH, "face {f}");
            assert_eq!(p.uv[f], [[0.0; 2]; 3]);
        } else {
            furred += 1;
            assert_ne!(p.patch[f], NO_PATCH, "face {f}");
        }
    }
    assert_eq!(p.quality.furred_faces, furred);
    assert_eq!(p.quality.coverage, 1.0);
    // All bald: nothing to do, nothing fails.
    let zero = vec![0.0; positions.len()];
    let m = FurMesh::new(MeshInput::new(&positions, &triangles).with_length(&zero)).unwrap();
    let p = build_patches(&m, &params(0.2)).unwrap();
    assert_eq!(p.quality.patch_count, 0);
    assert!(p.patch.iter().all(|&id| id == NO_PATCH));
}

#[test]
fn a_cancelled_build_returns_cancelled() {
    let m = mesh(&shapes::uv_sphere(32, 16));
    let stop = |_: f64| false;
    let outcome = build_patches_with_progress(&m, &params(0.2), Some(&stop));
    assert!(matches!(outcome, Err(PeltError::Cancelled)));
}

#[test]
fn bad_parameters_name_the_field() {
    let m = mesh(&shapes::uv_sphere(8, 4));
    let cases = [
        (
            PatchParams {
                tile_size: 0.0,
                ..PatchParams::default()
            },
            "tile_size",
        ),
        (
            PatchParams {
                tile_size: -1.0,
                ..PatchParams::default()
            },
            "tile_size",
        ),
        (
            PatchParams {
                tile_size: f64::NAN,
                ..PatchParams::default()
            },
            "tile_size",
        ),
        (
            PatchParams {
                tile_size: f64::INFINITY,
                ..PatchParams::default()
            },
            "tile_size",
        ),
        (
            PatchParams {
                max_alignment_deg: 0.0,
                ..PatchParams::default()
            },
            "max_alignment_deg",
        ),
        (
            PatchParams {
                max_face_alignment_deg: 1.0,
                ..PatchParams::default()
            },
            "max_face_alignment_deg",
        ),
        (
            PatchParams {
                stretch_tolerance: 0.9,
                ..PatchParams::default()
            },
            "stretch_tolerance",
        ),
        (
            PatchParams {
                max_stretched_fraction: 1.5,
                ..PatchParams::default()
            },
            "max_stretched_fraction",
        ),
        (
            PatchParams {
                max_stretch: 1.1,
                ..PatchParams::default()
            },
            "max_stretch",
        ),
        (
            PatchParams {
                field: FieldParams {
                    blend: -1.0,
                    ..FieldParams::default()
                },
                ..PatchParams::default()
            },
            "blend",
        ),
    ];
    for (params, name) in cases {
        match build_patches(&m, &params) {
            Err(PeltError::InvalidParameter { name: got, .. }) => assert_eq!(got, name),
            other => panic!("expected InvalidParameter({name}), got {other:?}"),
        }
    }
}

/// Two unit squares facing −Y (towards a camera looking along +Y): a near one at y = 0 on the
/// left half of the view and a far one at y = 1 covering the whole view.
fn two_squares() -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let positions = vec![
        [-1.0, 0.0, -1.0],
        [0.0, 0.0, -1.0],
        [0.0, 0.0, 1.0],
        [-1.0, 0.0, 1.0],
        [-1.0, 1.0, -1.0],
        [1.0, 1.0, -1.0],
        [1.0, 1.0, 1.0],
        [-1.0, 1.0, 1.0],
    ];
    let triangles = vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
    (positions, triangles)
}

#[test]
fn the_picture_shows_the_nearest_face_in_its_patch_color() {
    let (positions, triangles) = two_squares();
    // The far square is bald (length 0 at its vertices), the near one furred.
    let length = [1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0];
    let m = FurMesh::new(MeshInput::new(&positions, &triangles).with_length(&length)).unwrap();
    let p = build_patches(&m, &params(0.5)).unwrap();
    assert_eq!(p.patch[2..], [NO_PATCH, NO_PATCH]);
    let picture_params = PictureParams {
        size: [40, 40],
        view: [0.0, 1.0, 0.0],
        hair_length: 0.0,
        hair_every: 1,
    };
    let rgba = picture(&m, &p, &picture_params).unwrap();
    assert_eq!(rgba.len(), 40 * 40 * 4);
    let pixel =
        |x: usize, y: usize| -> [u8; 4] { rgba[4 * (y * 40 + x)..4 * (y * 40 + x) + 4].try_into().unwrap() };
    // Patch 0 faces the camera squarely: hue 0 (red) lifted to 25% floor, full shade.
    let (left, right) = (pixel(12, 20), pixel(28, 20));
    assert_eq!(left, [255, 63, 63, 255], "near furred square");
    assert_eq!(right, [153, 153, 153, 255], "far bald square (grey 0.6)");
    assert_eq!(pixel(0, 0), [255, 255, 255, 0], "background");
    // With hair lines on, some pixels of the furred square turn dark.
    let with_hair = picture(
        &m,
        &p,
        &PictureParams {
            hair_length: 0.2,
            ..picture_params.clone()
        },
    )
    .unwrap();
    assert!(with_hair.chunks(4).any(|c| c == [20, 20, 20, 255]));
}

#[test]
fn bad_picture_parameters_name_the_field() {
    let m = mesh(&shapes::uv_sphere(8, 4));
    let p = build_patches(&m, &params(0.5)).unwrap();
    let other = mesh(&shapes::uv_sphere(10, 4));
    for (params, name, on) in [
        (
            PictureParams {
                size: [0, 10],
                ..PictureParams::default()
            },
            "size",
            &m,
        ),
        (
            PictureParams {
                size: [10, MAX_SIDE + 1],
                ..PictureParams::default()
            },
            "size",
            &m,
        ),
        (
            PictureParams {
                view: [0.0; 3],
                ..PictureParams::default()
            },
            "view",
            &m,
        ),
        (
            PictureParams {
                hair_length: 2.0,
                ..PictureParams::default()
            },
            "hair_length",
            &m,
        ),
        (
            PictureParams {
                hair_every: 0,
                ..PictureParams::default()
            },
            "hair_every",
            &m,
        ),
        (PictureParams::default(), "patches", &other),
    ] {
        match picture(on, &p, &params) {
            Err(PeltError::InvalidParameter { name: got, .. }) => assert_eq!(got, name),
            other => panic!("expected InvalidParameter({name}), got {other:?}"),
        }
    }
}

#[test]
fn the_picture_keeps_object_up_at_the_top() {
    // A furred square above a bald one, seen from the front (−Y looking along +Y).
    let positions = vec![
        [-1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 0.0, 1.0],
        [-1.0, 0.0, 1.0],
        [-1.0, 0.0, -1.0],
        [1.0, 0.0, -1.0],
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
    ];
    let triangles = vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
    let length = [1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0];
    let m = FurMesh::new(MeshInput::new(&positions, &triangles).with_length(&length)).unwrap();
    let p = build_patches(&m, &params(0.5)).unwrap();
    let size = 20;
    let pictured = PictureParams {
        size: [size, size],
        view: [0.0, 1.0, 0.0],
        hair_length: 0.0,
        hair_every: 1,
    };
    let rgba = picture(&m, &p, &pictured).unwrap();
    let grey = |y: usize| rgba[4 * (y * size as usize + 10)] == 153;
    assert!(
        !grey(5) && grey(15),
        "furred (upper) half on top, bald half below"
    );
}
