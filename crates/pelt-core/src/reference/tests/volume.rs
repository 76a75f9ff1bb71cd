//! The volume mode checked against closed forms: a homogeneous slab of parallel hairs over a flat
//! skin, where transmittance is Beer–Lambert with the extinction of `density.rs`'s formula and
//! single scattering with shadows has a closed form; then against the strands themselves on a
//! baked sphere, determinism and bad input.

use std::f64::consts::PI;

use glam::{DVec3, Vec3, Vec3A};

use super::super::density::DensityField;
use super::super::volume::{MIN_SLICE_AREA, prism};
use super::*;
use crate::lapped::NO_PATCH;

/// A flat square `[-2, 2]²` at z = 0, 8 × 8 quads, UVs `xy / tile`.
fn flat_mesh(tile: f32) -> (FurMesh, Vec<[[f32; 2]; 3]>) {
    let n = 8u32;
    let positions: Vec<[f32; 3]> = (0..=n)
        .flat_map(|j| {
            (0..=n).map(move |i| {
                [
                    i as f32 * 4.0 / n as f32 - 2.0,
                    j as f32 * 4.0 / n as f32 - 2.0,
                    0.0,
                ]
            })
        })
        .collect();
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            triangles.push([a, a + 1, a + n + 2]);
            triangles.push([a, a + n + 2, a + n + 1]);
        }
    }
    let mesh = FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap();
    let uv = triangles
        .iter()
        .map(|t| t.map(|v| [positions[v as usize][0] / tile, positions[v as usize][1] / tile]))
        .collect();
    (mesh, uv)
}

/// A slab: every texel of every layer the same.
struct Slab {
    coverage: f32,
    /// Hair direction in the tile frame (x along u, z up), before packing.
    direction: [f32; 3],
    radius: f32,
    layers: usize,
    spacing: f32,
    hair_color: u8,
    skin: f32,
    tile: f32,
    fur_depth: f64,
}

impl Slab {
    fn packed(&self) -> [u8; 3] {
        self.direction.map(|d| ((0.5 * d + 0.5) * 255.0).round() as u8)
    }

    fn scene(&self) -> VolumeScene {
        let r = 4;
        let texels = r * r * self.layers;
        let t = self.packed();
        let field = DensityField::new(
            r,
            self.layers,
            self.spacing,
            vec![self.coverage; texels],
            [self.hair_color, self.hair_color, self.hair_color, 255].repeat(texels),
            [t[0], t[1], t[2], 255].repeat(texels),
            vec![self.radius; self.layers],
        )
        .unwrap();
        let (mesh, uv) = flat_mesh(self.tile);
        let patch = vec![0u32; uv.len()];
        VolumeScene::with_field(&mesh, &uv, &patch, field, Vec3::splat(self.skin), self.fur_depth).unwrap()
    }

    /// The hair's unit tangent in object space, from the packed bytes as the field decodes them.
    fn tangent(&self) -> DVec3 {
        let d = DVec3::from(self.packed().map(|b| f64::from(b) * 2.0 / 255.0 - 1.0));
        let tile = f64::from(self.tile);
        (d * DVec3::new(tile, tile, self.fur_depth)).normalize()
    }

    /// Optical depth straight up through the slab for a ray along unit `omega`: the layers'
    /// coverage is constant up to the last layer and fades to 0 one spacing above it.
    fn vertical_depth(&self, omega: DVec3) -> f64 {
        let t = self.tangent();
        let across = omega.cross(t).length();
        let sigma = 2.0 * f64::from(self.coverage) * across
            / (PI * f64::from(self.radius) * f64::from(self.tile) * t.z.abs().max(0.1));
        let height = (self.layers as f64 - 0.5) * f64::from(self.spacing) * self.fur_depth;
        sigma * height
    }
}

fn slab() -> Slab {
    Slab {
        coverage: 0.012,
        direction: [0.6, 0.0, 0.8],
        radius: 0.01,
        layers: 8,
        spacing: 0.125,
        hair_color: 0,
        skin: 1.0,
        tile: 0.5,
        fur_depth: 0.1,
    }
}

/// Kajiya–Kay's diffuse and specular parts with `Kd = 1`, `Ks = 0`, `Pd = 1`.
fn diffuse_only() -> ReferenceSettings {
    ReferenceSettings {
        shading: HairShading {
            diffuse: 1.0,
            specular: 0.0,
            ..HairShading::default()
        },
        ..fixed_samples(64)
    }
}

fn mean_red(image: &ReferenceImage) -> f64 {
    image.pixels.iter().map(|p| f64::from(p[0])).sum::<f64>() / image.pixels.len() as f64
}

#[test]
fn black_hair_over_a_white_skin_transmits_by_beer_lambert_toward_eye_and_light() {
    let slab = slab();
    let scene = slab.scene();
    let light = DVec3::new(0.6, 0.2, 0.8).normalize();
    let lights = [sun(light.as_vec3().to_array(), std::f32::consts::PI)];
    let camera = top_camera(0.25, 12);
    let view = (-slab.vertical_depth(DVec3::Z)).exp();
    let toward_light = (-slab.vertical_depth(light) / light.z).exp();
    assert!((0.2..0.8).contains(&view) && (0.2..0.8).contains(&toward_light));

    let mut settings = diffuse_only();
    settings.shadows = false;
    let open = mean_red(&render_volume_reference(&scene, &camera, &lights, &settings, None).unwrap());
    let expected = light.z * view;
    assert!(
        (open / expected - 1.0).abs() < 0.01,
        "unshadowed skin {open}, Beer–Lambert {expected}"
    );

    settings.shadows = true;
    let shadowed = mean_red(&render_volume_reference(&scene, &camera, &lights, &settings, None).unwrap());
    let expected = light.z * view * toward_light;
    assert!(
        (shadowed / expected - 1.0).abs() < 0.01,
        "shadowed skin {shadowed}, Beer–Lambert {expected}"
    );
}

#[test]
fn white_hair_over_a_black_skin_scatters_once_as_the_closed_form_says() {
    let slab = Slab {
        hair_color: 255,
        skin: 0.0,
        ..slab()
    };
    let scene = slab.scene();
    let light = DVec3::new(-0.5, 0.3, 0.8).normalize();
    let lights = [sun(light.as_vec3().to_array(), std::f32::consts::PI)];
    let camera = top_camera(0.25, 12);
    let u = slab.tangent().dot(light);
    let phase = (1.0 - u * u).sqrt();
    let a_view = slab.vertical_depth(DVec3::Z);
    let a_light = slab.vertical_depth(light) / light.z;

    let mut settings = diffuse_only();
    settings.shadows = false;
    let open = mean_red(&render_volume_reference(&scene, &camera, &lights, &settings, None).unwrap());
    let expected = phase * (1.0 - (-a_view).exp());
    assert!(
        (open / expected - 1.0).abs() < 0.01,
        "unshadowed fur {open}, closed form {expected}"
    );

    // Light attenuated on its way in: ∫ σ_v e^{−(a_v + a_l) s} ds over the slab's depth.
    settings.shadows = true;
    let shadowed = mean_red(&render_volume_reference(&scene, &camera, &lights, &settings, None).unwrap());
    let expected = phase * a_view / (a_view + a_light) * (1.0 - (-(a_view + a_light)).exp());
    assert!(
        (shadowed / expected - 1.0).abs() < 0.02,
        "shadowed fur {shadowed}, closed form {expected}"
    );
}

#[test]
fn the_volume_of_a_baked_sphere_agrees_with_its_strands() {
    let (mesh, asset) = furred_sphere(1024);
    let strands = crate::hair::grow_strands(&asset.params.grown_hair(&asset.mesh)).unwrap();
    let geometry = geometry_of(&mesh, &asset).unwrap();
    let strands_scene = ReferenceScene::new(geometry).unwrap();
    let volume = VolumeScene::from_bake(
        &mesh,
        &asset.patches,
        &asset.volume,
        &strands,
        asset.params.fur_depth(),
    )
    .unwrap();
    let camera = perspective(Vec3::new(0.0, -4.5, 1.0), 48);
    let lights = [sun([0.5, -0.6, 0.6], 3.0)];
    let settings = fixed_samples(16);
    let a = render_reference(&strands_scene, &camera, &lights, &settings, None).unwrap();
    let b = render_volume_reference(&volume, &camera, &lights, &settings, None).unwrap();
    let coverage = mean_alpha(&b) / mean_alpha(&a);
    let radiance = covered_radiance(&b)[0] / covered_radiance(&a)[0];
    eprintln!("volume / strands: coverage {coverage}, radiance {radiance}");
    assert!((0.97..1.03).contains(&coverage), "coverage ratio {coverage}");
    assert!((0.85..1.15).contains(&radiance), "radiance ratio {radiance}");
}

#[test]
fn the_volume_image_is_bit_identical_for_any_thread_count() {
    let scene = Slab {
        hair_color: 200,
        ..slab()
    }
    .scene();
    let lights = [sun([0.3, 0.2, 1.0], 3.0)];
    let camera = top_camera(0.4, 16);
    crate::threads::set_thread_count(1).unwrap();
    let one = render_volume_reference(&scene, &camera, &lights, &fixed_samples(8), None).unwrap();
    crate::threads::set_thread_count(3).unwrap();
    let three = render_volume_reference(&scene, &camera, &lights, &fixed_samples(8), None).unwrap();
    crate::threads::set_thread_count(0).unwrap();
    assert_eq!(one.pixels, three.pixels);
}

#[test]
fn an_empty_volume_a_bad_field_and_a_bald_mesh_are_named() {
    let slab = slab();
    let (mesh, uv) = flat_mesh(slab.tile);
    let empty = DensityField::new(2, 1, 1.0, vec![0.0; 4], vec![0; 16], vec![0; 16], vec![0.0]).unwrap();
    let patch = vec![0u32; uv.len()];
    let Err(PeltError::InvalidParameter { name, .. }) =
        VolumeScene::with_field(&mesh, &uv, &patch, empty, Vec3::ONE, 0.1)
    else {
        panic!("an empty volume was accepted");
    };
    assert_eq!(name, "volume");
    let bad = DensityField::new(2, 1, 1.0, vec![0.0; 3], vec![0; 16], vec![0; 16], vec![0.0]);
    assert!(matches!(bad, Err(PeltError::InvalidParameter { ref name, .. }) if name == "volume"));

    // A bald mesh has no fur for the volume to fill.
    let field = DensityField::new(2, 1, 1.0, vec![0.1; 4], vec![255; 16], vec![128; 16], vec![0.01]).unwrap();
    let bald = vec![NO_PATCH; uv.len()];
    let Err(PeltError::InvalidParameter { name, .. }) =
        VolumeScene::with_field(&mesh, &uv, &bald, field, Vec3::ONE, 0.1)
    else {
        panic!("a bald mesh was accepted");
    };
    assert_eq!(name, "volume");
}

#[test]
fn a_prism_over_a_sphere_grows_its_slices_as_the_sphere_lifted() {
    // A triangle with its corners on a sphere of radius 2 about the origin, each lifted along
    // its radius by the fur depth 0.5 per unit height: every slice is the triangle scaled about
    // the centre by (2 + 0.5 z) / 2, so its area is that squared, whatever the triangle.
    let p = [[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [1.2, 0.0, 1.6]].map(Vec3A::from_array);
    let lifted_by = |up: [Vec3A; 3]| {
        let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        prism(p, up, 1.0, uv, [Vec3::ONE; 3], [0, 1, 2])
    };
    let outward = lifted_by(p.map(|c| 0.25 * c));
    for z in [0.0f32, 0.3, 1.0] {
        let expected = ((2.0 + 0.5 * z) / 2.0).powi(2);
        let area = outward.slice_area(z);
        assert!((area - expected).abs() < 1e-5, "z {z}: {area}");
    }
    // A hollow (the same triangle lifted toward the centre) shrinks to its focus, then turns
    // over; the slice is held within the bounds.
    let inward = lifted_by(p.map(|c| -0.25 * c));
    assert!((inward.slice_area(1.0) - 0.5625).abs() < 1e-5);
    assert_eq!(inward.slice_area(4.0), MIN_SLICE_AREA);
}
