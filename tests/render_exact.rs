//! The CPU adapter reads the stored colors and blends the shells as exactly as the arithmetic
//! they stand for: a tile seen straight down, a pixel per texel, is the "over" of its layers
//! computed here in f64, at every LOD level and in both outputs. (Lavapipe's sRGB8 texture decode
//! strays by up to 2.5% per byte value, and its half-float and sRGB8 targets round every blend.)

#![cfg(feature = "render")]

mod common;

use common::volume::paint_skin;
use common::{column_major, orthographic, view_matrix};
use pelt::hair::HairParams;
use pelt::render::{
    AdapterChoice, Camera, FurScene, KajiyaKay, LightModel, Lighting, RenderSettings, Renderer,
};
use pelt::texture::color::srgb_to_linear;
use pelt::volume::{HairVolume, VolumeParams, bake_volume};
use pelt::{FurMesh, MeshInput};

/// The ambient light, the only one: a shell texel shows its premultiplied color × this.
const AMBIENT: f32 = 0.5;

/// A 2 × 2 quad over `[-1, 1]²` facing +z, one tile across (u along +x, v along +y).
fn quad() -> (FurMesh, Vec<[[f32; 2]; 3]>) {
    let positions = [
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    ];
    let normals = [[0.0, 0.0, 1.0]; 4];
    let mesh =
        FurMesh::new(MeshInput::new(&positions, &[[0, 1, 2], [0, 2, 3]]).with_normals(&normals)).unwrap();
    let uvs = vec![
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
        [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
    ];
    (mesh, uvs)
}

/// Orthographic, straight down, one pixel per texel: every pixel centre is a texel centre.
fn straight_down(side: usize) -> Camera {
    Camera {
        view: column_major(view_matrix([0.0, 0.0, 3.0], [0.0; 3], [0.0, 1.0, 0.0])),
        projection: orthographic(1.0, 0.5, 5.5),
        width: side as u32,
        height: side as u32,
    }
}

/// The ambient light alone (no sun, no Banks darkening): the skin shows black, the hair its
/// premultiplied color × [`AMBIENT`].
fn ambient_only() -> Lighting {
    Lighting {
        self_shadow: 0.0,
        model: LightModel::KajiyaKay(KajiyaKay {
            ambient: [AMBIENT; 3],
            diffuse: 0.0,
            specular: 0.0,
            ..KajiyaKay::default()
        }),
        ..Lighting::default()
    }
}

fn plain() -> RenderSettings {
    RenderSettings {
        fins: false,
        body_shadow: false,
        ..RenderSettings::default()
    }
}

/// Exactly `shells` shells: the LOD level that has them.
fn level_of(shells: u32) -> RenderSettings {
    RenderSettings {
        lod: true,
        min_shells: shells,
        max_shells: shells,
        ..plain()
    }
}

fn luminance(rgb: [f64; 3]) -> f64 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// The mean luminance of the hair layers `1..count` of `stack` (straight sRGB RGBA8) composited
/// inner to outer over black, per texel in f64, × [`AMBIENT`].
fn over_of_the_layers(volume: &HairVolume, stack: &[u8], count: usize) -> f64 {
    let texels = volume.resolution * volume.resolution;
    let sum: f64 = (0..texels)
        .map(|t| {
            let mut rgb = [0.0f64; 3];
            for layer in 1..count {
                let px = &stack[4 * (layer * texels + t)..][..4];
                let a = f64::from(px[3]) / 255.0;
                for (c, v) in rgb.iter_mut().enumerate() {
                    *v = f64::from(srgb_to_linear(f32::from(px[c]) / 255.0)) * a + (1.0 - a) * *v;
                }
            }
            luminance(rgb)
        })
        .sum();
    f64::from(AMBIENT) * sum / texels as f64
}

fn mean_linear(pixels: &[f32]) -> f64 {
    let n = pixels.len() / 4;
    let sum: f64 = pixels
        .chunks_exact(4)
        .map(|p| luminance([0, 1, 2].map(|c| f64::from(p[c]))))
        .sum();
    sum / n as f64
}

fn mean_srgb8(pixels: &[u8]) -> f64 {
    let n = pixels.len() / 4;
    let sum: f64 = pixels
        .chunks_exact(4)
        .map(|p| luminance([0, 1, 2].map(|c| f64::from(srgb_to_linear(f32::from(p[c]) / 255.0)))))
        .sum();
    sum / n as f64
}

#[test]
fn a_deep_stack_seen_straight_down_is_the_over_of_its_layers_at_every_level() {
    let renderer = Renderer::new(AdapterChoice::Cpu).expect("a CPU adapter (lavapipe) must exist");
    let params = VolumeParams {
        layers: 32,
        resolution: 128,
        ..VolumeParams::default()
    };
    let mut volume = bake_volume(&HairParams::default(), &params, None).unwrap();
    paint_skin(&mut volume, |px| px.copy_from_slice(&[0, 0, 0, 255]));
    let (mesh, uvs) = quad();
    let scene = FurScene::new(&renderer, &mesh, &uvs, &volume, 0.2).unwrap();
    let camera = straight_down(volume.resolution);
    let lighting = ambient_only();
    let last = volume.lod.len() - 2;
    // 31 hair layers; the level of one group, all of them composited by the bake.
    for (settings, want) in [
        (
            plain(),
            over_of_the_layers(&volume, &volume.shells, volume.layers),
        ),
        (level_of(1), over_of_the_layers(&volume, &volume.lod[last], 2)),
    ] {
        let linear = renderer
            .render_linear(&scene, &camera, &lighting, &settings)
            .unwrap();
        let got = mean_linear(&linear.pixels);
        // Lavapipe's sRGB8 decode put the composite 0.45% above it and its half-float target the
        // 31 layers 0.37% below; exact, both are within 0.08%.
        assert!(
            (got / want - 1.0).abs() < 0.0015,
            "linear, lod {}: {got} against {want}",
            settings.lod
        );
        let srgb8 = renderer.render(&scene, &camera, &lighting, &settings).unwrap();
        let got = mean_srgb8(&srgb8.pixels);
        // The 8-bit image rounds each pixel once, unbiased on the whole.
        assert!(
            (got / want - 1.0).abs() < 0.0025,
            "8-bit, lod {}: {got} against {want}",
            settings.lod
        );
    }
}

#[test]
fn every_srgb_byte_of_a_shell_reads_as_its_linear_value() {
    let renderer = Renderer::new(AdapterChoice::Cpu).expect("a CPU adapter (lavapipe) must exist");
    // A 16² tile of one opaque hair layer over black skin, texel `t` of gray byte `t`.
    let side = 16;
    let texels = side * side;
    let mut shells = [0u8, 0, 0, 255].repeat(texels);
    shells.extend((0..texels).flat_map(|t| [t as u8, t as u8, t as u8, 255]));
    let volume = HairVolume {
        resolution: side,
        layers: 2,
        shells,
        coverage: vec![1.0; 2 * texels],
        tangents: vec![128; 2 * 4 * texels],
        lod: Vec::new(),
        mips: Vec::new(),
        ..common::volume::small_volume(2)
    };
    let (mesh, uvs) = quad();
    let scene = FurScene::new(&renderer, &mesh, &uvs, &volume, 0.2).unwrap();
    let image = renderer
        .render_linear(&scene, &straight_down(side), &ambient_only(), &plain())
        .unwrap();
    let mut read: Vec<f32> = image.pixels.chunks_exact(4).map(|p| p[0] / AMBIENT).collect();
    read.sort_by(f32::total_cmp);
    for (byte, got) in read.into_iter().enumerate() {
        let want = srgb_to_linear(byte as f32 / 255.0);
        // Half-float storage rounds by 2⁻¹¹ at most; lavapipe's own decode read bytes 1–10 2.5%
        // bright and 15 2.3% dark.
        assert!(
            (got - want).abs() <= 5e-4 * want + 1e-7,
            "byte {byte} read {got}, is {want}"
        );
    }
}
