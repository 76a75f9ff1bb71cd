//! The shells' hair thins out with height over a convex skin as the strands do. A strand stands on
//! the same lift as the shells (the mesh lifted along its growth directions) and keeps its width,
//! so over a sphere of radius R a layer at height h covers (R / (R + h))² of the area the tile's
//! texel covers there: fewer hairs per unit area, each as thin. Checked against that figure in
//! the fringe beyond the skin, where only the top shell is seen, for both shell methods and
//! both lighting models; and a fin whose edge widens up its height.
#![cfg(feature = "render")]

mod common;

use common::look_at;
use common::volume::{small_transfer, small_volume};
use pelt::mesh::shapes::uv_sphere;
use pelt::render::{
    AdapterChoice, Camera, FurScene, LightModel, Lighting, Prt, RenderSettings, Renderer, ShellMethod,
};
use pelt::volume::HairVolume;
use pelt::{FurMesh, MeshInput};

/// Fur depth over the unit sphere, object units.
const FUR_DEPTH: f32 = 0.6;
/// Layers of the volume: the skin, two empty layers and the top one.
const LAYERS: usize = 4;
/// The top layer's straight alpha, 8-bit.
const TOP_ALPHA: u8 = 128;
/// Image side, pixels; the orthographic view spans `[-HALF, HALF]²`.
const SIZE: u32 = 64;
const HALF: f64 = 1.6;

/// A volume whose hair layers are empty but the top one, white at `TOP_ALPHA` everywhere (every
/// mip level too).
fn top_layer_only() -> HairVolume {
    let mut volume = small_volume(LAYERS);
    assert_eq!(volume.layers, LAYERS);
    let paint = |layers: &mut [u8], side: usize| {
        let plane = 4 * side * side;
        for (k, layer) in layers.chunks_exact_mut(plane).enumerate().skip(1) {
            let texel = if k == LAYERS - 1 {
                [255, 255, 255, TOP_ALPHA]
            } else {
                [0; 4]
            };
            layer.chunks_exact_mut(4).for_each(|t| t.copy_from_slice(&texel));
        }
    };
    paint(&mut volume.shells, volume.resolution);
    for (k, mip) in volume.mips.iter_mut().enumerate() {
        paint(mip, (volume.resolution >> (k + 1)).max(1));
    }
    volume
}

/// Mean alpha over the pixels whose centres lie `inner..outer` from the centre of the image.
fn ring_alpha(pixels: &[f32], inner: f64, outer: f64) -> (f64, usize) {
    let step = 2.0 * HALF / f64::from(SIZE);
    let (mut sum, mut count) = (0.0, 0usize);
    for (i, p) in pixels.chunks_exact(4).enumerate() {
        let x = -HALF + (((i as u32) % SIZE) as f64 + 0.5) * step;
        let y = -HALF + (((i as u32) / SIZE) as f64 + 0.5) * step;
        let r = x.hypot(y);
        if r > inner && r < outer {
            sum += f64::from(p[3]);
            count += 1;
        }
    }
    (sum / count as f64, count)
}

/// An orthographic camera at `eye` looking at the origin, z up, spanning `[-HALF, HALF]²`.
fn looking_from(eye: [f64; 3]) -> Camera {
    Camera {
        view: look_at(eye, [0.0, 0.0, 1.0]),
        projection: common::orthographic(HALF, 0.5, 9.5),
        width: SIZE,
        height: SIZE,
    }
}

/// Each lighting model's default lighting, by name.
fn models() -> [(&'static str, Lighting); 2] {
    let prt = Lighting {
        model: LightModel::Prt(Prt::default()),
        ..Lighting::default()
    };
    [("Kajiya–Kay", Lighting::default()), ("PRT", prt)]
}

#[test]
fn the_top_shell_over_a_sphere_thins_out_as_the_strands_do() {
    let renderer = Renderer::new(AdapterChoice::Cpu).expect("a CPU adapter (lavapipe) must exist");
    let (positions, triangles) = uv_sphere(64, 32);
    let mesh = FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap();
    let patches = common::patches_at(&mesh, 0.5);
    let volume = top_layer_only();
    let mut scene = FurScene::new(&renderer, &mesh, &patches.uv, &volume, FUR_DEPTH).unwrap();
    let transfer = small_transfer(&volume, f64::from(FUR_DEPTH) / 0.5);
    scene.set_transfer(&renderer, &transfer).unwrap();
    let camera = looking_from([0.0, -3.0, 0.0]);
    // The top layer stands (LAYERS - 1) / LAYERS of the fur depth up: the top shell is the unit
    // sphere lifted to 1 + h.
    let h = f64::from(FUR_DEPTH) * (LAYERS - 1) as f64 / LAYERS as f64;
    let alpha = f64::from(TOP_ALPHA) / 255.0;
    let expected = 1.0 - (1.0 - alpha).powf((1.0 / (1.0 + h)).powi(2));
    for (model, lighting) in models() {
        for method in [ShellMethod::Instanced, ShellMethod::Marched] {
            let settings = RenderSettings {
                shell_method: method,
                fins: false,
                ..RenderSettings::default()
            };
            let image = renderer
                .render_linear(&scene, &camera, &lighting, &settings)
                .unwrap();
            // Clear of the faceted skin's outline and of the top shell's, by two pixels.
            let (seen, pixels) = ring_alpha(&image.pixels, 1.1, 1.0 + h - 0.1);
            assert!(pixels > 300, "{pixels} pixels in the fringe");
            assert!(
                (seen - expected).abs() < 0.02,
                "{model}, {method:?}: the fringe's alpha is {seen:.3}, the strands' {expected:.3} \
                 (the tile's own {alpha:.3})"
            );
        }
    }
}

#[test]
fn a_fin_whose_edge_widens_with_height_thins_out_as_its_hair_spreads() {
    // One edge (−1, 0, 0)–(1, 0, 0) seen face-on from −y, its ends' normals leaning apart by
    // ±TILT in x: the fin widens from 2 at the skin to 2 s at the top, s = 1 + d t / √(1 + t²),
    // and its hair, as many and as thin as at the root, covers 1/s as much per unit width. The
    // fin texture is uniform; each pixel row must show it thinned by the width there (the
    // density is interpolated linearly up the fin, 1 at the root, 1/s at the top, as the fin's
    // width is linear but its inverse is not: within 0.02 here).
    const TILT: f32 = 0.6;
    const DEPTH: f32 = 0.8;
    let renderer = Renderer::new(AdapterChoice::Cpu).expect("a CPU adapter (lavapipe) must exist");
    let mut volume = small_volume(LAYERS);
    volume
        .fin
        .chunks_exact_mut(4)
        .for_each(|t| t.copy_from_slice(&[255, 255, 255, TOP_ALPHA]));
    let positions = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 10.0, 0.0]];
    let normals = [[-TILT, 0.0, 1.0], [TILT, 0.0, 1.0], [0.0, 0.0, 1.0]];
    let uv = positions.map(|p| [p[0] / 0.25, p[1] / 0.25]);
    let mesh = FurMesh::new(MeshInput::new(&positions, &[[0, 1, 2]]).with_normals(&normals)).unwrap();
    let mut scene = FurScene::new(&renderer, &mesh, &[uv], &volume, DEPTH).unwrap();
    scene
        .set_transfer(&renderer, &small_transfer(&volume, f64::from(DEPTH) / 0.25))
        .unwrap();
    let camera = looking_from([0.0, -5.0, 0.0]);
    let settings = RenderSettings {
        shell_count: Some(0),
        ..RenderSettings::default()
    };
    let cosine = 1.0 / (1.0 + f64::from(TILT).powi(2)).sqrt();
    let top_spread = 1.0 + f64::from(DEPTH) * f64::from(TILT) * cosine;
    let alpha = f64::from(TOP_ALPHA) / 255.0;
    for (model, lighting) in models() {
        let image = renderer
            .render_linear(&scene, &camera, &lighting, &settings)
            .unwrap();
        let step = 2.0 * HALF / f64::from(SIZE);
        let mut rows = 0;
        for row in 0..SIZE as usize {
            // Image rows run top down; the fin stands from z = 0 to d cos.
            let z = HALF - (row as f64 + 0.5) * step;
            let h = z / (f64::from(DEPTH) * cosine);
            if !(0.05..0.95).contains(&h) {
                continue;
            }
            let spread = 1.0 + h * (top_spread - 1.0);
            let expected = 1.0 - (1.0 - alpha).powf(1.0 / spread);
            // The middle columns, |x| < 0.3.
            let columns = (0..SIZE as usize).filter(|&c| (-HALF + (c as f64 + 0.5) * step).abs() < 0.3);
            let seen: Vec<f64> = columns
                .map(|c| f64::from(image.pixels[4 * (row * SIZE as usize + c) + 3]))
                .collect();
            let mean = seen.iter().sum::<f64>() / seen.len() as f64;
            assert!(
                (mean - expected).abs() < 0.02,
                "{model}, height {h:.2}: the fin's alpha is {mean:.3}, its hair's {expected:.3} \
                 (the texture's {alpha:.3})"
            );
            rows += 1;
        }
        assert!(rows > 10, "{rows} rows checked");
    }
}
