//! CPU-side checks of the renderer: matrices, GPU vertices of the split mesh and the fins,
//! premultiplied colors and input validation (the split and the fin quads themselves are tested in
//! `mesh/`). The GPU passes are tested in `tests/render_fur.rs`.

use super::camera::{Camera, CameraFrame, invert};
use super::color_store::{premultiply, premultiply_half};
use super::image::RgbaImage;
use super::lighting::Lighting;
use super::settings::RenderSettings;
use glam::dcamera::rh::proj::directx;
use glam::dcamera::rh::view::look_at_mat4;
use glam::{DMat4, DVec4, Vec4};
use pelt_core::error::PeltError;
use pelt_core::scene::{fin_mesh, surface_mesh};
use pelt_core::texture::color::{linear_to_srgb, srgb_to_linear};
use pelt_core::{FurMesh, MeshInput};

/// A right-handed look-at view matrix, column-major.
fn look_at(eye: [f64; 3], target: [f64; 3], up: [f64; 3]) -> [f32; 16] {
    look_at_mat4(eye.into(), target.into(), up.into())
        .as_mat4()
        .to_cols_array()
}

/// A 90° vertical field of view (focal length 1) on a square image, view depths 0.1 to 10.
fn perspective() -> [f32; 16] {
    directx::perspective(std::f64::consts::FRAC_PI_2, 1.0, 0.1, 10.0)
        .as_mat4()
        .to_cols_array()
}

/// `[-half, half]²` of the view plane, view depths `near..far` to clip depth `0..1`.
fn orthographic(half: f64, near: f64, far: f64) -> [f32; 16] {
    directx::orthographic(-half, half, -half, half, near, far)
        .as_mat4()
        .to_cols_array()
}

#[test]
fn inverse_times_matrix_is_identity_and_singular_is_refused() {
    let m = DMat4::from_rows(
        DVec4::new(2.0, 0.5, -1.0, 3.0),
        DVec4::new(0.0, 1.5, 0.25, -2.0),
        DVec4::new(1.0, -0.5, 4.0, 0.5),
        DVec4::new(0.0, 0.0, 0.3, 1.0),
    );
    let product = m * invert(&m).unwrap();
    assert!(product.abs_diff_eq(DMat4::IDENTITY, 1e-12), "{product}");
    let mut singular = m;
    singular.set_row(3, DVec4::new(4.0, 1.0, -2.0, 6.0)); // twice row 0
    assert!(invert(&singular).is_none());
}

#[test]
fn camera_finds_the_eye_for_perspective_and_orthographic_projections() {
    let eye = [1.0, -3.0, 2.0];
    let view = look_at(eye, [0.0, 0.5, 0.0], [0.0, 0.0, 1.0]);
    let camera = Camera {
        view,
        projection: perspective(),
        width: 64,
        height: 32,
    };
    let frame = CameraFrame::of(&camera, 8192).unwrap();
    for (got, want) in frame.eye.to_array().iter().zip(eye) {
        assert!((f64::from(*got) - want).abs() < 1e-5, "{:?}", frame.eye);
    }
    assert_eq!(frame.eye.w, 1.0);
    // The target projects to the centre of the image.
    let clip = frame.view_proj * Vec4::new(0.0, 0.5, 0.0, 1.0);
    assert!(
        clip.x.abs() < 1e-5 && clip.y.abs() < 1e-5 && clip.w > 0.0,
        "{clip:?}"
    );

    let ortho = Camera {
        projection: orthographic(2.0, -5.0, 5.0),
        ..camera
    };
    let frame = CameraFrame::of(&ortho, 8192).unwrap();
    let toward = [1.0, -3.5, 2.0];
    let len = (1.0f64 + 3.5 * 3.5 + 4.0).sqrt();
    for (got, want) in frame.eye.to_array().iter().zip(toward) {
        assert!((f64::from(*got) - want / len).abs() < 1e-5, "{:?}", frame.eye);
    }
    assert_eq!(frame.eye.w, 0.0);
}

fn parameter_name(e: PeltError) -> String {
    match e {
        PeltError::InvalidParameter { name, .. } => name,
        other => panic!("expected an invalid parameter, got {other}"),
    }
}

#[test]
fn camera_lighting_and_settings_name_the_bad_field() {
    let good = Camera {
        view: look_at([0.0, 0.0, 3.0], [0.0; 3], [0.0, 1.0, 0.0]),
        projection: perspective(),
        width: 16,
        height: 16,
    };
    let mut nan = good;
    nan.view[5] = f32::NAN;
    assert_eq!(
        parameter_name(CameraFrame::of(&nan, 4096).unwrap_err()),
        "camera.view"
    );
    let zero_width = Camera { width: 0, ..good };
    assert_eq!(
        parameter_name(CameraFrame::of(&zero_width, 4096).unwrap_err()),
        "camera.width"
    );
    let too_tall = Camera { height: 5000, ..good };
    assert_eq!(
        parameter_name(CameraFrame::of(&too_tall, 4096).unwrap_err()),
        "camera.height"
    );
    let singular = Camera {
        view: [0.0; 16],
        ..good
    };
    assert_eq!(
        parameter_name(CameraFrame::of(&singular, 4096).unwrap_err()),
        "camera.view"
    );
    let mut skewed = good;
    skewed.projection[3] = 0.5; // last row (0.5, 0, -1, 0)
    assert_eq!(
        parameter_name(CameraFrame::of(&skewed, 4096).unwrap_err()),
        "camera.projection"
    );

    let dark = Lighting {
        direction: [0.0; 3],
        ..Lighting::default()
    };
    assert_eq!(parameter_name(dark.frame().unwrap_err()), "lighting.direction");
    let light = Lighting {
        direction: [0.0, 3.0, 4.0],
        ..Lighting::default()
    }
    .frame()
    .unwrap();
    assert_eq!(light.direction, [0.0, 0.6, 0.8]);

    let settings = RenderSettings::default();
    assert_eq!(settings.shells_to_draw(16).unwrap(), 15);
    let too_many = RenderSettings {
        shell_count: Some(16),
        ..settings
    };
    assert_eq!(
        parameter_name(too_many.shells_to_draw(16).unwrap_err()),
        "shell_count"
    );
}

/// A 2 × 2 square in the xy plane as two triangles sharing the diagonal 0–2.
fn square() -> FurMesh {
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
    let split = surface_mesh::build(&mesh, &uvs).unwrap();
    assert_eq!(split.vertices.len(), 4);
    for v in &split.vertices {
        assert_eq!(v.dpdu, [2.0, 0.0, 0.0]);
        assert_eq!(v.dpdv, [0.0, 2.0, 0.0]);
        let p = mesh.positions()[split.source[split.vertices.iter().position(|w| w == v).unwrap()] as usize];
        assert_eq!(v.uv, [p[0] / 2.0, p[1] / 2.0]);
    }
    // Every side is twice as long in 3D as in the tile.
    assert!((split.uv_scale - 0.5).abs() < 1e-12);
    for (f, tri) in mesh.triangles().iter().enumerate() {
        for k in 0..3 {
            let gpu = split.indices[3 * f + k] as usize;
            assert_eq!(split.source[gpu], tri[k]);
            assert_eq!(split.vertices[gpu].uv, uvs[f][k]);
        }
    }

    // The second triangle shifted by a whole tile: the diagonal's two vertices split.
    let seam = [uvs[0], uvs[1].map(|[u, v]| [u + 1.0, v])];
    let split = surface_mesh::build(&mesh, &seam).unwrap();
    assert_eq!(split.vertices.len(), 6);
    let mut sources = split.source.clone();
    sources.sort_unstable();
    assert_eq!(sources, [0, 0, 1, 2, 2, 3]);
}

#[test]
fn one_fin_per_edge_standing_on_it() {
    let mesh = square();
    // Surface vertex of mesh vertex v: 10 + v, to see that the fins name them.
    let fins = fin_mesh::build(&[pelt_core::mesh::fin_quads(&mesh, 0.5)], &[10, 11, 12, 13]);
    assert_eq!(fins.vertices.len(), 4 * 5);
    assert_eq!(fins.indices.len(), 6 * 5);
    assert_eq!((fins.centers.len(), fins.normals.len()), (5, 5));
    for (k, quad) in fins.vertices.chunks_exact(4).enumerate() {
        let source = &fins.source[4 * k..4 * k + 4];
        let (a, b) = (
            mesh.positions()[source[0] as usize],
            mesh.positions()[source[1] as usize],
        );
        let e = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let len = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        let f = fins.normals[k];
        // The fin stands on the edge along the (flat) normal +z: its normal is in the plane,
        // perpendicular to the edge.
        assert!(
            (f[0] * e[0] + f[1] * e[1]).abs() < 1e-6 && f[2].abs() < 1e-6,
            "{f:?}"
        );
        assert!(((f[0] * f[0] + f[1] * f[1]).sqrt() - 1.0).abs() < 1e-6);
        assert_eq!(fins.centers[k], [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0, 0.0]);
        // The texture interval is the edge length in tile units, starting in [0, 1).
        assert!((0.0..1.0).contains(&quad[0].uv[0]));
        assert!((quad[1].uv[0] - quad[0].uv[0] - 0.5 * len).abs() < 1e-5);
        assert_eq!(
            [quad[0].uv[1], quad[1].uv[1], quad[2].uv[1], quad[3].uv[1]],
            [1.0, 1.0, 0.0, 0.0]
        );
        assert_eq!((source[2], source[3]), (source[0], source[1]));
        // Each corner names both ends' surface vertices and stands on one of them.
        let ends = quad[0].ends;
        assert_eq!(ends.map(|e| mesh.positions()[e as usize - 10]), [a, b]);
        for (corner, along) in quad.iter().zip([0.0, 1.0, 0.0, 1.0]) {
            assert_eq!((corner.ends, corner.along), (ends, along));
        }
    }
}

#[test]
fn premultiplied_upload_and_straight_readback_agree_with_the_formulas() {
    let straight = [255, 128, 0, 128, 10, 200, 90, 255, 77, 77, 77, 0, 0, 0, 0, 3];
    let pm = premultiply(&straight);
    for (s, p) in straight.chunks_exact(4).zip(pm.chunks_exact(4)) {
        let a = f32::from(s[3]) / 255.0;
        for c in 0..3 {
            let want = linear_to_srgb(srgb_to_linear(f32::from(s[c]) / 255.0) * a) * 255.0;
            assert!((f32::from(p[c]) - want).abs() <= 0.5 + 1e-3, "{s:?} -> {p:?}");
        }
        assert_eq!(p[3], s[3]);
    }
    // Back to straight: within the rounding of 8-bit premultiplied values.
    let image = RgbaImage::from_premultiplied(4, 1, pm);
    for (s, back) in straight.chunks_exact(4).zip(image.pixels.chunks_exact(4)) {
        match s[3] {
            0 => assert_eq!(back, [0, 0, 0, 0]),
            3 => assert_eq!(back[3], 3),
            _ => {
                for c in 0..3 {
                    assert!(s[c].abs_diff(back[c]) <= 2, "{s:?} -> {back:?}");
                }
            }
        }
    }
}

#[test]
fn half_storage_holds_the_premultiplied_linear_values() {
    use half::f16;
    let straight = [
        255, 128, 0, 128, 10, 200, 90, 255, 77, 77, 77, 0, 0, 0, 0, 3, 1, 2, 3, 1,
    ];
    let stored = premultiply_half(&straight);
    assert_eq!(stored.len(), 2 * straight.len());
    for (s, h) in straight.chunks_exact(4).zip(stored.chunks_exact(8)) {
        let v: Vec<f32> = h
            .chunks_exact(2)
            .map(|p| f16::from_le_bytes([p[0], p[1]]).to_f32())
            .collect();
        let a = f32::from(s[3]) / 255.0;
        let want = [0, 1, 2].map(|c| srgb_to_linear(f32::from(s[c]) / 255.0) * a);
        for (got, want) in v.iter().zip(want.iter().chain([&a])) {
            // A half float's rounding: 2⁻¹¹ relative, 2⁻²⁵ absolute below its normal range.
            assert!((got - want).abs() <= want * 4.9e-4 + 3e-8, "{s:?} -> {v:?}");
        }
    }
}

#[test]
fn premultiplying_does_not_depend_on_the_thread_count() {
    // Enough texels for several parallel chunks, every (color, alpha) pair present.
    let straight: Vec<u8> = (0..3 * 65536u32)
        .flat_map(|i| {
            [
                (i % 256) as u8,
                (i / 7 % 256) as u8,
                (i / 256 % 256) as u8,
                (i * 13 % 256) as u8,
            ]
        })
        .collect();
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| (premultiply(&straight), premultiply_half(&straight)))
    };
    assert!(run(1) == run(2));
}

#[test]
fn transfer_layer_means_weigh_texels_by_opacity_for_any_thread_count() {
    use super::transfer::{layer_means, order_of};
    use half::f16;
    use pelt_core::prt::pack::{PackedF16, texel_index};
    let (order, layers, resolution) = (4, 3, 5);
    let n = order * order;
    // Order 4 fills every channel of its 4 textures, the last one to the end of the array.
    let textures = 4;
    assert_eq!(order_of(textures), Some(order));
    let voxels = layers * resolution * resolution;
    let value = |k: usize, v: usize| ((k * 7 + v * 13) % 17) as f32 / 8.0 - 1.0;
    let mut texels = vec![f16::ZERO; textures * voxels * 4];
    for v in 0..voxels {
        for k in 0..n {
            texels[texel_index(k, v, voxels)] = f16::from_f32(value(k, v));
        }
    }
    let packed = PackedF16 {
        textures,
        layers,
        resolution,
        texels,
    };
    // Layer 2 is empty: its plain mean stands in.
    let texels = resolution * resolution;
    let alpha: Vec<u8> = (0..voxels)
        .map(|v| if v / texels == 2 { 0 } else { (v * 37 % 256) as u8 })
        .collect();
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| layer_means(&packed, &alpha, order))
    };
    let means = run(1);
    assert!(means == run(2));
    for layer in 0..layers {
        for k in 0..n {
            let voxel = |i: usize| layer * texels + i;
            let weight: f64 = (0..texels).map(|i| f64::from(alpha[voxel(i)])).sum();
            let want = if weight > 0.0 {
                (0..texels)
                    .map(|i| f64::from(alpha[voxel(i)]) * f64::from(value(k, voxel(i))))
                    .sum::<f64>()
                    / weight
            } else {
                (0..texels).map(|i| f64::from(value(k, voxel(i)))).sum::<f64>() / texels as f64
            };
            // The values are multiples of 1/8, exact in f16.
            assert!((f64::from(means[layer * n + k]) - want).abs() < 1e-6);
        }
    }
    // One texture reads as order 2; two textures fit no order.
    assert_eq!(
        (order_of(1), order_of(2), order_of(7), order_of(16)),
        (Some(2), None, Some(5), Some(8))
    );
}

#[test]
fn lod_levels_keep_the_skin_and_halve_the_hair_down_to_one_layer() {
    use super::lod::Levels;
    let levels = Levels::new(17);
    assert_eq!(levels.counts, [17, 9, 5, 3, 2, 1]);
    assert_eq!(levels.bases, [0, 17, 26, 31, 34, 36]);
    assert_eq!(levels.total(), 37);
    assert_eq!(Levels::new(1).counts, [1]);
    assert_eq!(Levels::new(2).counts, [2, 1]);
    assert_eq!(Levels::new(16).counts, [16, 9, 5, 3, 2, 1]);
}

/// The LOD schedule's test view: a unit bounding sphere (painted length 1) at the origin, seen
/// orthographically over [-2, 2]² on 200² pixels: 50 pixels per unit.
fn unit_sphere_at_50_pixels_per_unit() -> (super::lod::Extent, Camera) {
    let extent = super::lod::Extent {
        center: glam::DVec3::ZERO,
        radius: 1.0,
        max_length: 1.0,
    };
    let camera = Camera {
        view: look_at([0.0, 0.0, 3.0], [0.0; 3], [0.0, 1.0, 0.0]),
        projection: orthographic(2.0, 0.5, 5.5),
        width: 200,
        height: 200,
    };
    (extent, camera)
}

#[test]
fn the_default_lod_draws_groups_of_a_quarter_of_the_layers_at_most() {
    // The two coarsest levels hold the hair in one or two groups, each lit at one height far
    // from where the eye sees most of its hair: from 2.4× its framed distance out the
    // benchmark's short-furred patch was 5% darker with them than with all shells. However
    // small the object, the default stops at four groups.
    use super::lod::{Levels, choose};
    let levels = Levels::new(65); // 64, 32, 16, 8, 4, 2, 1, 0 shells
    let (extent, camera) = unit_sphere_at_50_pixels_per_unit();
    let lod = RenderSettings {
        lod: true,
        ..RenderSettings::default()
    };
    // Fur 4, 1 and 0.05 pixels deep.
    for depth in [0.08, 0.02, 1e-3] {
        let info = choose(&levels, &lod, &camera, &extent, depth, 64);
        assert_eq!(
            (info.shells, info.level, info.blend),
            (4, 4, 0.0),
            "fur {depth} deep"
        );
    }
}

#[test]
fn lod_follows_the_projected_fur_depth_between_the_levels() {
    use super::lod::{Levels, choose};
    let levels = Levels::new(17); // 16, 8, 4, 2, 1, 0 shells
    // 50 pixels per unit: fur 0.1 deep = 5 pixels.
    let (extent, camera) = unit_sphere_at_50_pixels_per_unit();
    let settings = RenderSettings {
        lod: true,
        min_shells: 1,
        ..RenderSettings::default()
    };
    let info = choose(&levels, &settings, &camera, &extent, 0.1, 16);
    assert!((info.radius_pixels.unwrap() - 50.0).abs() < 1e-4);
    assert!((info.fur_pixels.unwrap() - 5.0).abs() < 1e-5);
    // 5 shells wanted: between level 1 (8) and level 2 (4), a quarter of the way from 4.
    assert_eq!((info.shells, info.level), (8, 1));
    assert!((info.blend - 0.75).abs() < 1e-6 && (info.target_shells - 5.0).abs() < 1e-5);
    // Twice the shells per pixel: 10, between 16 and 8.
    let dense = RenderSettings {
        shells_per_pixel: 2.0,
        ..settings
    };
    let info = choose(&levels, &dense, &camera, &extent, 0.1, 16);
    assert_eq!((info.shells, info.level), (16, 0));
    assert!((info.blend - 0.75).abs() < 1e-6);
    // Exactly a level's count draws that level without a blend; the bounds clamp.
    let exact = RenderSettings {
        shells_per_pixel: 0.8,
        ..settings
    };
    let info = choose(&levels, &exact, &camera, &extent, 0.1, 16);
    assert_eq!((info.shells, info.level, info.blend), (4, 2, 0.0));
    let capped = RenderSettings {
        max_shells: 2,
        ..settings
    };
    assert_eq!(choose(&levels, &capped, &camera, &extent, 0.1, 16).shells, 2);
    let thin = RenderSettings {
        shells_per_pixel: 1e-3,
        min_shells: 0,
        ..settings
    };
    let info = choose(&levels, &thin, &camera, &extent, 0.1, 16);
    assert_eq!((info.shells, info.level), (1, 4));
    assert!((info.blend - 0.995).abs() < 1e-6);
    // No fur depth: the skin alone.
    let info = choose(&levels, &thin, &camera, &extent, 0.0, 16);
    assert_eq!((info.shells, info.level, info.blend), (0, 5, 0.0));
    // LOD off: the fixed count, sizes still reported.
    let off = RenderSettings {
        lod: false,
        ..settings
    };
    let info = choose(&levels, &off, &camera, &extent, 0.1, 12);
    assert_eq!((info.shells, info.level, info.blend), (12, 0, 0.0));
    assert!(info.fur_pixels.is_some());

    // Perspective: pixels per unit = focal length in pixels / distance; inside the sphere, none.
    let at = |distance: f64| Camera {
        view: look_at([0.0, 0.0, distance], [0.0; 3], [0.0, 1.0, 0.0]),
        projection: perspective(),
        width: 100,
        height: 100,
    };
    // perspective() has t = 1: 50 pixels per unit at distance 1.
    let info = choose(&levels, &settings, &at(4.0), &extent, 0.1, 16);
    assert!((info.radius_pixels.unwrap() - 12.5).abs() < 1e-4);
    let inside = choose(&levels, &settings, &at(0.5), &extent, 0.1, 16);
    assert_eq!((inside.radius_pixels, inside.shells, inside.level), (None, 16, 0));
}

#[test]
fn lod_transfer_weighs_each_shell_by_what_over_leaves_of_it_premultiplied_and_its_light_by_its_color() {
    use super::lod::Levels;
    use super::transfer::{composite_members, level_alphas, premultiplied_levels};
    use half::f16;
    use pelt_core::prt::pack::PackedF16;
    use pelt_core::texture::color::srgb_to_linear;
    let (layers, resolution) = (5usize, 2usize);
    let texels = resolution * resolution;
    let voxels = layers * texels;
    // One texture (4 channels), values and opacities varied per layer and texel.
    let value = |v: usize, c: usize| ((v * 5 + c * 3) % 11) as f32 / 4.0 - 1.0;
    let texel_values: Vec<f16> = (0..voxels * 4)
        .map(|i| f16::from_f32(value(i / 4, i % 4)))
        .collect();
    let alpha: Vec<u8> = (0..voxels).map(|v| (1 + (v * 97) % 255) as u8).collect();
    // Each texel's color luminance (sRGB-encoded), which weighs the members' light too.
    let shade: Vec<u8> = (0..voxels).map(|v| (20 + (v * 53) % 230) as u8).collect();
    let packed = PackedF16 {
        textures: 1,
        layers,
        resolution,
        texels: texel_values,
    };
    let levels = Levels::new(layers as u32);
    // Order 2: four coefficients, the texture's four channels; member rows after 3 others.
    let (order, first_row) = (2usize, 3usize);
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let alphas = level_alphas(&alpha, &levels, texels);
            let out = premultiplied_levels(&packed, &alphas, &levels);
            let members = composite_members(&packed, &alphas, &shade, &levels, order, first_row);
            (out, members.ranges, members.rows)
        })
    };
    let (out, ranges, rows) = run(1);
    assert!((out.clone(), ranges.clone(), rows.clone()) == run(2));
    assert_eq!(ranges.len(), levels.total() as usize - layers);
    assert_eq!(rows.len(), (levels.counts.len() - 1) * layers * 4);
    assert_eq!(out.len(), 1);
    assert_eq!(out[0].len(), levels.total() as usize * texels * 4);
    for (k, (&count, &base)) in levels.counts.iter().zip(&levels.bases).enumerate() {
        for j in 0..count as usize {
            // The skin, group j (level-0 layers (j − 1)·2^k + 1 ..= j·2^k), or at the last
            // level everything, composited "over", outermost on top: each weighs its opacity
            // times the transparency of everything above it.
            let group = match (count, j) {
                (1, _) => 0..layers,
                (_, 0) => 0..1,
                _ => ((j - 1) << k) + 1..((j << k) + 1).min(layers),
            };
            // Each level-0 layer's transfer weighted by what the composite shows of it and by its
            // color's luminance, meaned over the tile.
            let mut shown = vec![[0.0f64; 4]; layers];
            for x in 0..texels {
                for c in 0..4 {
                    let (mut sum, mut weights, mut clear) = (0.0f64, 0.0f64, 1.0f64);
                    for i in group.clone().rev() {
                        let a = f64::from(alpha[i * texels + x]) / 255.0;
                        let light = f64::from(srgb_to_linear(f32::from(shade[i * texels + x]) / 255.0));
                        sum += a * clear * f64::from(value(i * texels + x, c));
                        weights += a * clear;
                        shown[i][c] +=
                            a * light * clear * f64::from(value(i * texels + x, c)) / texels as f64;
                        clear *= 1.0 - a;
                    }
                    // Stored premultiplied by the composite's opacity, 1 − clear.
                    let want = sum / weights * (1.0 - clear);
                    let got = f64::from(out[0][((base as usize + j) * texels + x) * 4 + c].to_f32());
                    assert!(
                        (got - want).abs() < 2e-3,
                        "level {k} layer {j} texel {x} channel {c}: {got} vs {want}"
                    );
                }
            }
            if k > 0 {
                // The composite's layers, and the row of the first's weighted transfer.
                let [first, end, row, _] = ranges[base as usize - layers + j].map(|v| v as usize);
                assert_eq!(first..end, group);
                for i in group.clone() {
                    for c in 0..4 {
                        let got = f64::from(rows[(row + i - first - first_row) * 4 + c]);
                        let want = shown[i][c];
                        assert!(
                            (got - want).abs() < 2e-3,
                            "level {k} layer {j} member {i} coefficient {c}: {got} vs {want}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn opengl_projections_map_near_and_far_to_wgpu_depth() {
    // glFrustum-style perspective: near 0.5, far 20, 60° vertical, aspect 2.
    let (near, far) = (0.5f64, 20.0f64);
    let t = 1.0 / 30f64.to_radians().tan();
    let gl = [
        [t / 2.0, 0.0, 0.0, 0.0],
        [0.0, t, 0.0, 0.0],
        [
            0.0,
            0.0,
            (far + near) / (near - far),
            2.0 * far * near / (near - far),
        ],
        [0.0, 0.0, -1.0, 0.0],
    ];
    let view = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, -3.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    let camera = Camera::from_gl(
        view.map(|r: [f64; 4]| r.map(|v| v as f32)),
        gl.map(|r| r.map(|v| v as f32)),
        200,
        100,
    );
    // Column-major and transposed from the rows given.
    assert_eq!(camera.view[4 * 3 + 2], -3.0);
    assert_eq!(camera.view[4 * 2 + 3], 0.0);
    let frame = CameraFrame::of(&camera, 4096).unwrap();
    // Object points straight ahead at view depth d (object z = 3 − d).
    let depth = |d: f64| {
        let clip = frame.view_proj * Vec4::new(0.0, 0.0, (3.0 - d) as f32, 1.0);
        f64::from(clip.z / clip.w)
    };
    assert!(depth(near).abs() < 1e-6, "{}", depth(near));
    assert!((depth(far) - 1.0).abs() < 1e-5, "{}", depth(far));
    // The wgpu perspective of the same frustum: z = far / (near − far), w-term near·far / (near − far).
    let d = 4.0;
    let want = (far / (near - far) * -d + near * far / (near - far)) / d;
    assert!((depth(d) - want).abs() < 1e-6);
    // Eye found as for any wgpu camera.
    assert!((frame.eye.z - 3.0).abs() < 1e-6 && frame.eye.w == 1.0);
}

#[test]
fn a_frame_weighs_the_hot_spot_gains_of_the_composites_it_draws_only() {
    use super::lod::{FrameInfo, Levels};
    // 32 layers and the LOD levels composited from them.
    let levels = Levels::new(32);
    let first = levels.counts[0];
    let at = |level: u32, blend: f32| {
        levels.composites_drawn(&FrameInfo {
            shells: 0,
            level,
            blend,
            target_shells: 0.0,
            radius_pixels: None,
            fur_pixels: None,
            mesh_level: 0,
            triangles: 0,
        })
    };
    let layers_of = |k: usize| levels.bases[k] - first..levels.bases[k] + levels.counts[k] - first;
    // All shells read no composite; fading toward level 1, its layers.
    assert!(at(0, 0.0).is_empty());
    assert_eq!(at(0, 0.5), layers_of(1));
    // Level 2 alone, then with level 3 fading in; the last level has nothing coarser.
    assert_eq!(at(2, 0.0), layers_of(2));
    assert_eq!(at(2, 0.3), layers_of(2).start..layers_of(3).end);
    let last = levels.counts.len() - 1;
    assert_eq!(at(last as u32, 0.5), layers_of(last));
    assert_eq!(layers_of(last).end, levels.total() - first);
}
