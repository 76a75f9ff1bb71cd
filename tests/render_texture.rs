//! Drawing into a caller's texture (what `pelt view` does with a window's surface) on the CPU
//! adapter: every accepted format gives the pixels of the offscreen render (within one 8-bit step on
//! golden images check; textures that do not fit are refused by name and the renderer survives.
//! Fails (never skips) when no CPU adapter exists.
#![cfg(feature = "render")]

mod common;

use pelt::hair::HairParams;
use pelt::mesh::shapes::{torus, torus_uvs};
use pelt::render::{AdapterChoice, Camera, FurScene, Lighting, RenderSettings, Renderer};
use pelt::volume::{VolumeParams, bake_volume};
use pelt::{FurMesh, MeshInput, PeltError};

use common::{column_major, look_at, perspective};

const SIZE: u32 = 48;

/// The most a CPU adapter's texture may stray from its offscreen frame, in 8-bit steps.
const STEPS: u8 = 1;

/// The mean linear luminance of an opaque frame's pixels.
fn mean_light(image: &pelt::render::RgbaImage) -> f64 {
    let linear = |c: u8| {
        let c = f64::from(c) / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let sum: f64 = image
        .pixels
        .chunks_exact(4)
        .map(|p| 0.2126 * linear(p[0]) + 0.7152 * linear(p[1]) + 0.0722 * linear(p[2]))
        .sum();
    sum / (image.pixels.len() / 4) as f64
}

fn camera(width: u32, height: u32) -> Camera {
    Camera {
        view: look_at([0.0, -2.6, 2.2], [0.0, 0.0, 1.0]),
        projection: column_major(perspective(60.0, 0.5, 10.0)),
        width,
        height,
    }
}

fn settings() -> RenderSettings {
    RenderSettings {
        background: [0.1, 0.2, 0.3, 1.0],
        ..RenderSettings::default()
    }
}

fn setup() -> (Renderer, FurScene) {
    let renderer =
        Renderer::new(AdapterChoice::Cpu).expect("a CPU adapter (lavapipe) must exist under make test");
    let (positions, triangles) = torus(24, 12);
    let mesh = FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap();
    let uvs = torus_uvs(24, 12, [6.0, 2.0]);
    let volume = bake_volume(
        &HairParams {
            density: 2000,
            ..HairParams::default()
        },
        &VolumeParams {
            layers: 6,
            resolution: 32,
            fin_size: [64, 16],
            trim: false,
            ..VolumeParams::default()
        },
        None,
    )
    .unwrap();
    let scene = FurScene::new(&renderer, &mesh, &uvs, &volume, 0.08).unwrap();
    (renderer, scene)
}

fn texture(
    renderer: &Renderer,
    format: wgpu::TextureFormat,
    view_formats: &[wgpu::TextureFormat],
    usage: wgpu::TextureUsages,
    size: u32,
) -> wgpu::Texture {
    renderer.device().create_texture(&wgpu::TextureDescriptor {
        label: Some("test target"),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats,
    })
}

fn parameter_name(e: PeltError) -> String {
    match e {
        PeltError::InvalidParameter { name, .. } => name,
        other => panic!("expected an invalid parameter, got {other}"),
    }
}

#[test]
fn every_accepted_format_draws_the_offscreen_pixels_and_bad_textures_are_refused() {
    use wgpu::TextureFormat as F;
    let (renderer, scene) = setup();
    let (camera, lighting, settings) = (camera(SIZE, SIZE), Lighting::default(), settings());
    let offscreen = renderer.render(&scene, &camera, &lighting, &settings).unwrap();
    // The frame shows both fur and background.
    let distinct: std::collections::HashSet<&[u8]> = offscreen.pixels.chunks_exact(4).collect();
    assert!(distinct.len() > 20, "{} colours", distinct.len());

    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
    let mut first: Option<pelt::render::RgbaImage> = None;
    for (format, view_formats) in [
        (F::Rgba8UnormSrgb, vec![]),
        (F::Bgra8UnormSrgb, vec![]),
        (F::Rgba8Unorm, vec![F::Rgba8UnormSrgb]),
        (F::Bgra8Unorm, vec![F::Bgra8UnormSrgb]),
    ] {
        let target = texture(&renderer, format, &view_formats, usage, SIZE);
        let info = renderer
            .render_to_texture(&scene, &camera, &lighting, &settings, &target)
            .unwrap();
        assert_eq!(info, renderer.frame_info(&scene, &camera, &settings).unwrap());
        let image = renderer.read_texture(&target).unwrap();
        if renderer.is_cpu() {
            // Both frames blend in single floats; the caller's texture is encoded by the
            // device (lavapipe's sRGB8 encode is a polynomial), the offscreen frame exactly.
            // Blended shell by shell in 8 bits instead, they were 4 steps and 0.5% apart here.
            let apart = image
                .pixels
                .iter()
                .zip(&offscreen.pixels)
                .map(|(a, b)| a.abs_diff(*b))
                .max();
            assert!(
                apart <= Some(STEPS),
                "{format:?} strays from the offscreen render by {apart:?} steps"
            );
            let light = mean_light(&image) / mean_light(&offscreen);
            assert!(
                (light - 1.0).abs() < 1e-3,
                "{format:?}: {light} times the offscreen frame's light"
            );
            let first = first.get_or_insert_with(|| image.clone());
            assert!(image == *first, "{format:?} differs from the other formats");
        } else {
            assert!(image == offscreen, "{format:?} differs from the offscreen render");
        }
    }
    // Half floats are drawn too (not read back).
    let half = texture(
        &renderer,
        F::Rgba16Float,
        &[],
        wgpu::TextureUsages::RENDER_ATTACHMENT,
        SIZE,
    );
    renderer
        .render_to_texture(&scene, &camera, &lighting, &settings, &half)
        .unwrap();

    let draw = |t: &wgpu::Texture| renderer.render_to_texture(&scene, &camera, &lighting, &settings, t);
    let small = texture(&renderer, F::Rgba8UnormSrgb, &[], usage, SIZE / 2);
    assert_eq!(parameter_name(draw(&small).unwrap_err()), "texture");
    let float = texture(&renderer, F::R32Float, &[], usage, SIZE);
    assert_eq!(parameter_name(draw(&float).unwrap_err()), "texture");
    let unreadable = texture(
        &renderer,
        F::Rgba8UnormSrgb,
        &[],
        wgpu::TextureUsages::COPY_SRC,
        SIZE,
    );
    assert_eq!(parameter_name(draw(&unreadable).unwrap_err()), "texture");
    let no_copy = texture(
        &renderer,
        F::Rgba8UnormSrgb,
        &[],
        wgpu::TextureUsages::RENDER_ATTACHMENT,
        SIZE,
    );
    assert_eq!(
        parameter_name(renderer.read_texture(&no_copy).unwrap_err()),
        "texture"
    );
    // A Unorm texture without its sRGB view format cannot be drawn through that view: a device
    // error, reported, and the device survives.
    let plain = texture(&renderer, F::Rgba8Unorm, &[], usage, SIZE);
    assert!(matches!(draw(&plain), Err(PeltError::Render(_))));
    assert!(renderer.render(&scene, &camera, &lighting, &settings).unwrap() == offscreen);
}
