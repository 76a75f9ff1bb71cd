//! The reference checked against independent answers: a single straight hair's coverage and
//! Kajiya–Kay radiance in closed form, a slab of random hairs against Beer–Lambert, the
//! unshadowed composite, convergence at the Monte Carlo rate, and determinism.

use std::sync::Arc;

use glam::camera::rh::proj::directx::{orthographic, perspective as perspective_projection};
use glam::camera::rh::view::look_at_mat4;
use glam::{DVec3, Vec3};

use super::*;
use crate::camera::Camera;
use crate::error::PeltError;
use crate::mesh::{FurMesh, MeshInput, shapes};
use crate::pipeline::{BakeParams, Pipeline};
use crate::rng::Rng;

/// An orthographic camera looking down −z at the square `[-half, half]²` of the plane z = 0.
fn top_camera(half: f32, side: u32) -> Camera {
    let view = look_at_mat4(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y);
    let projection = orthographic(-half, half, -half, half, 0.1, 10.0);
    Camera {
        view: view.to_cols_array(),
        projection: projection.to_cols_array(),
        width: side,
        height: side,
    }
}

fn sun(direction: [f32; 3], strength: f32) -> ReferenceLight {
    ReferenceLight::Sun {
        direction,
        strength,
        color: [1.0; 3],
    }
}

fn straight(a: [f32; 3], b: [f32; 3], radius: f32, color: [f32; 3]) -> WorldStrand {
    WorldStrand {
        points: vec![a, b],
        radii: vec![radius; 2],
        root_color: color,
        tip_color: color,
    }
}

fn fixed_samples(n: u32) -> ReferenceSettings {
    ReferenceSettings {
        min_samples: n,
        max_samples: n,
        samples_per_pass: n.min(4),
        ..ReferenceSettings::default()
    }
}

fn scene_of(strands: &[WorldStrand]) -> ReferenceScene {
    ReferenceScene::new(FurGeometry::from_world_strands(strands).unwrap()).unwrap()
}

fn mean_alpha(image: &ReferenceImage) -> f64 {
    image.pixels.iter().map(|p| f64::from(p[3])).sum::<f64>() / image.pixels.len() as f64
}

/// Σ premultiplied RGB / Σ coverage: the radiance of the covered part of the image.
fn covered_radiance(image: &ReferenceImage) -> [f64; 3] {
    let alpha: f64 = image.pixels.iter().map(|p| f64::from(p[3])).sum();
    std::array::from_fn(|c| image.pixels.iter().map(|p| f64::from(p[c])).sum::<f64>() / alpha)
}

/// Kajiya–Kay in f64 from its definition (Lengyel et al. 2001, §2.4), the preview's defaults.
fn kajiya_kay(t: [f64; 3], l: [f64; 3], v: [f64; 3], albedo: f64) -> f64 {
    let [t, l, v] = [t, l, v].map(|a| DVec3::from(a).normalize());
    let h = (l + v).normalize();
    let (u, w) = (t.dot(l), t.dot(h));
    0.9 * albedo * (1.0 - u * u).powf(0.5) + 0.25 * (1.0 - w * w).powf(24.0)
}

#[test]
fn a_single_straight_hair_has_its_analytic_coverage_and_radiance() {
    // A hair 0.02 wide across the whole 0.2-wide view: a tenth of the image.
    let scene = scene_of(&[straight([0.0, -1.0, 0.0], [0.0, 1.0, 0.0], 0.01, [0.5; 3])]);
    let light = [0.3f32, 0.6, 0.74];
    let image = render_reference(
        &scene,
        &top_camera(0.1, 64),
        &[sun(light, 2.0)],
        &fixed_samples(16),
        None,
    )
    .unwrap();
    let alpha = mean_alpha(&image);
    assert!((alpha - 0.1).abs() < 0.002, "coverage {alpha}, expected 0.1");
    let expected =
        2.0 / std::f64::consts::PI * kajiya_kay([0.0, 1.0, 0.0], light.map(f64::from), [0.0, 0.0, 1.0], 0.5);
    for c in covered_radiance(&image) {
        assert!(
            (c / expected - 1.0).abs() < 1e-4,
            "radiance {c}, expected {expected}"
        );
    }
}

/// `count` straight hairs 0.2 long, radius 0.001, centres uniform over `[-0.7, 0.7]²` at heights
/// in `[0, 0.1]`, lying in the plane (at random angles, or all along x).
fn slab(count: usize, random_angles: bool, seed: u64) -> Vec<WorldStrand> {
    (0..count)
        .map(|i| {
            let mut rng = Rng::stream(seed, 7, i as u64);
            let c = [
                (rng.next_f64() * 1.4 - 0.7) as f32,
                (rng.next_f64() * 1.4 - 0.7) as f32,
                (rng.next_f64() * 0.1) as f32,
            ];
            let angle = if random_angles {
                rng.next_f64() * std::f64::consts::TAU
            } else {
                0.0
            };
            let d = [(0.1 * angle.cos()) as f32, (0.1 * angle.sin()) as f32];
            straight(
                [c[0] - d[0], c[1] - d[1], c[2]],
                [c[0] + d[0], c[1] + d[1], c[2]],
                0.001,
                [0.4; 3],
            )
        })
        .collect()
}

#[test]
fn a_slab_of_random_hairs_transmits_by_beer_lambert() {
    // Hairs whose centres fall at random (a Boolean model) leave the share exp(−λ) of the view
    // uncovered, λ = N · 2r · ℓ / area: here 4900 · 0.002 · 0.2 / 1.96 = 1.
    let scene = scene_of(&slab(4900, true, 3));
    let image = render_reference(&scene, &top_camera(0.5, 96), &[], &fixed_samples(8), None).unwrap();
    let transmittance = 1.0 - mean_alpha(&image);
    let expected = (-1.0f64).exp();
    assert!(
        (transmittance - expected).abs() < 0.02,
        "transmittance {transmittance}, Beer–Lambert {expected}"
    );
}

#[test]
fn an_unshadowed_light_gives_the_analytic_composite_and_shadows_darken_it() {
    // Parallel hairs: every hit has the same tangent, so without shadows the covered radiance
    // is exactly the Kajiya–Kay value; with them, hairs below others lose light.
    let scene = scene_of(&slab(3000, false, 5));
    let light = [0.2f32, 0.3, 0.4];
    let mut settings = fixed_samples(4);
    settings.shadows = false;
    let camera = top_camera(0.5, 48);
    let open = render_reference(&scene, &camera, &[sun(light, 1.0)], &settings, None).unwrap();
    let expected =
        kajiya_kay([1.0, 0.0, 0.0], light.map(f64::from), [0.0, 0.0, 1.0], 0.4) / std::f64::consts::PI;
    for c in covered_radiance(&open) {
        assert!(
            (c / expected - 1.0).abs() < 1e-4,
            "radiance {c}, expected {expected}"
        );
    }
    settings.shadows = true;
    let shadowed = render_reference(&scene, &camera, &[sun(light, 1.0)], &settings, None).unwrap();
    assert_eq!(mean_alpha(&open), mean_alpha(&shadowed));
    let (a, b) = (covered_radiance(&open)[0], covered_radiance(&shadowed)[0]);
    assert!(b < 0.97 * a, "shadows {b} against {a}");
}

fn rms_difference(a: &ReferenceImage, b: &ReferenceImage) -> f64 {
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (0..4).map(|c| f64::from(p[c] - q[c]).powi(2)).sum::<f64>())
        .sum();
    (sum / a.pixels.len() as f64).sqrt()
}

#[test]
fn error_falls_as_one_over_the_square_root_of_the_samples() {
    let scene = scene_of(&slab(1500, true, 11));
    let sky = ReferenceLight::Environment {
        sh: vec![[1.0; 3], [0.0; 3], [0.8; 3], [0.0; 3]],
    };
    let camera = top_camera(0.25, 16);
    let render = |n: u32, seed: u64| {
        let settings = ReferenceSettings {
            seed,
            ..fixed_samples(n)
        };
        render_reference(&scene, &camera, std::slice::from_ref(&sky), &settings, None).unwrap()
    };
    let truth = render(1024, 99);
    let coarse = rms_difference(&render(4, 1), &truth);
    let fine = rms_difference(&render(64, 1), &truth);
    // 16 times the samples: a quarter of the error.
    let ratio = coarse / fine;
    assert!(
        (2.8..5.5).contains(&ratio),
        "error ratio {ratio} for 16× the samples"
    );
}

#[test]
fn the_image_is_bit_identical_for_any_thread_count() {
    let scene = scene_of(&slab(800, true, 2));
    let lights = [sun([0.3, 0.2, 1.0], 3.0)];
    let camera = top_camera(0.4, 24);
    crate::threads::set_thread_count(1).unwrap();
    let one = render_reference(&scene, &camera, &lights, &fixed_samples(8), None).unwrap();
    crate::threads::set_thread_count(3).unwrap();
    let three = render_reference(&scene, &camera, &lights, &fixed_samples(8), None).unwrap();
    crate::threads::set_thread_count(0).unwrap();
    assert_eq!(one.pixels, three.pixels);
}

#[test]
fn pixel_variances_match_the_spread_between_two_independent_renders() {
    // Two renders with other seeds differ by two draws of the same noise: the mean of
    // (A − B)² / 2 over the pixels estimates the variance each pixel's estimate has.
    let scene = scene_of(&slab(800, true, 2));
    let lights = [sun([0.3, 0.2, 1.0], 3.0)];
    let camera = top_camera(0.4, 48);
    let render = |seed| {
        let settings = ReferenceSettings {
            seed,
            ..fixed_samples(16)
        };
        render_reference(&scene, &camera, &lights, &settings, None).unwrap()
    };
    let (a, b) = (render(1), render(2));
    // Rec. 709, as the passes weigh their samples.
    let lum = |p: &[f32; 4]| 0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2]);
    let spread = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (lum(p) - lum(q)).powi(2) / 2.0)
        .sum::<f64>();
    let claimed = a.pixel_variance.iter().map(|&v| f64::from(v)).sum::<f64>();
    let ratio = claimed / spread;
    // Measured: 1.00.
    assert!(
        (0.85..1.18).contains(&ratio),
        "variance {claimed} vs spread {spread}: {ratio}"
    );
}

/// A small furred sphere (radius 1, fur depth 0.15) and a perspective camera at `eye`.
fn furred_sphere(density: u32) -> (Arc<FurMesh>, crate::pipeline::FurAsset) {
    let (positions, triangles) = shapes::uv_sphere(24, 12);
    let mesh = Arc::new(FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap());
    let mut params = BakeParams::default();
    params.patches.tile_size = 0.5;
    params.hair.density = density;
    params.volume.resolution = 32;
    params.volume.layers = 8;
    params.fur_depth = Some(0.15);
    let asset = Pipeline::new().bake(mesh.clone(), &params, None).unwrap();
    (mesh, asset)
}

fn perspective(eye: Vec3, side: u32) -> Camera {
    let view = look_at_mat4(eye, Vec3::ZERO, Vec3::Z);
    let projection = perspective_projection(0.6, 1.0, 0.1, 50.0);
    Camera {
        view: view.to_cols_array(),
        projection: projection.to_cols_array(),
        width: side,
        height: side,
    }
}

fn geometry_of(mesh: &FurMesh, asset: &crate::pipeline::FurAsset) -> crate::error::Result<FurGeometry> {
    let strands = crate::hair::grow_strands(&asset.params.grown_hair(&asset.mesh)).unwrap();
    FurGeometry::from_bake(mesh, &asset.patches, &strands, asset.params.fur_depth())
}

#[test]
fn a_baked_sphere_renders_its_strands_over_the_skin() {
    let (mesh, asset) = furred_sphere(256);
    let geometry = geometry_of(&mesh, &asset).unwrap();
    // Every tile's roots land once: strands ≈ density × surface area / tile².
    let expected = 256.0 * 4.0 * std::f64::consts::PI / 0.25;
    let ratio = geometry.strand_count() as f64 / expected;
    assert!(
        (0.9..1.1).contains(&ratio),
        "{} strands, expected about {expected}",
        geometry.strand_count()
    );
    let scene = ReferenceScene::new(geometry).unwrap();
    let image = render_reference(
        &scene,
        &perspective(Vec3::new(0.0, -6.0, 0.0), 32),
        &[sun([0.0, -1.0, 0.3], 3.0)],
        &fixed_samples(4),
        None,
    )
    .unwrap();
    assert!(image.pixels.iter().flatten().all(|v| v.is_finite()));
    let centre = image.pixels[16 * 32 + 16];
    assert_eq!(centre[3], 1.0, "the sphere covers the centre");
    assert!(centre[0] > 0.0, "lit from the eye's side");
    assert_eq!(image.pixels[0][3], 0.0, "the corner is background");
}

#[test]
fn bad_input_is_named_and_a_cancelled_render_returns_nothing() {
    let (mesh, asset) = furred_sphere(64);
    let scene = ReferenceScene::new(geometry_of(&mesh, &asset).unwrap()).unwrap();
    let lights = [sun([0.0, -1.0, 0.0], 1.0)];
    let name = |r: crate::error::Result<ReferenceImage>| match r {
        Err(PeltError::InvalidParameter { name, .. }) => name,
        other => panic!("expected a named parameter error, got {other:?}"),
    };
    let outside = perspective(Vec3::new(0.0, -6.0, 0.0), 8);
    let inside = perspective(Vec3::new(0.1, 0.0, 0.2), 8);
    assert_eq!(
        name(render_reference(
            &scene,
            &inside,
            &lights,
            &fixed_samples(1),
            None
        )),
        "camera.view"
    );
    let zero = ReferenceSettings {
        min_samples: 0,
        ..ReferenceSettings::default()
    };
    assert_eq!(
        name(render_reference(&scene, &outside, &lights, &zero, None)),
        "min_samples"
    );
    let cancel = |_: f64| false;
    assert!(matches!(
        render_reference(&scene, &outside, &lights, &fixed_samples(4), Some(&cancel)),
        Err(PeltError::Cancelled)
    ));

    let (mesh, bald) = furred_sphere(0);
    match ReferenceScene::new(geometry_of(&mesh, &bald).unwrap()) {
        Err(PeltError::InvalidParameter { name, .. }) => assert_eq!(name, "strands"),
        other => panic!("expected the strands error, got {:?}", other.err()),
    }
}

#[cfg(feature = "metrics")]
mod metrics;

#[test]
fn shadows_fall_for_axis_aligned_lights_with_signed_zeros() {
    // −0.0 in a direction once sent the BVH's traversal down the wrong octant, and no shadow
    // ray from a sun along an axis ever hit anything.
    let scene = scene_of(&slab(3000, false, 5));
    let camera = top_camera(0.5, 32);
    for direction in [[1.0, -0.0, 0.5], [-0.0, 1.0, 0.5], [-0.0, 1.0, -0.0]] {
        let mut settings = fixed_samples(2);
        settings.shadows = false;
        let open = render_reference(&scene, &camera, &[sun(direction, 1.0)], &settings, None).unwrap();
        settings.shadows = true;
        let shadowed = render_reference(&scene, &camera, &[sun(direction, 1.0)], &settings, None).unwrap();
        let (a, b) = (covered_radiance(&open)[0], covered_radiance(&shadowed)[0]);
        assert!(b < 0.97 * a, "{direction:?}: shadows {b} against {a}");
    }
}
mod volume;
