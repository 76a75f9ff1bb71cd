//! The fur renderer on the CPU adapter (lavapipe): a furred torus with parametric UVs and a small
//! baked hair volume. Properties are checked against renders of the same scene with passes
//! switched off and against the torus's analytic geometry, never against stored output. The test
//! fails (never skips) when no CPU adapter exists.
#![cfg(feature = "render")]

mod common;

use std::path::Path;
use std::sync::OnceLock;

use pelt::export::{PngOptions, save_png};
use pelt::render::{
    AdapterChoice, Camera, FurScene, KajiyaKay, LightModel, Lighting, Prt, RenderSettings, Renderer,
    RgbaImage, ShellMethod,
};
use pelt::volume::HairVolume;
use pelt::{FurMesh, MeshInput};

use common::torus::{FurredTorus, covered};
use common::volume::{paint_skin, small_transfer};
use common::{column_major, look_at, parameter_name, perspective};

const AROUND: usize = 32;
const ACROSS: usize = 16;
/// Tile repeats around the ring and around the tube (about one object unit per tile).
const REPEATS: [f32; 2] = [6.0, 2.0];
const SIZE: u32 = 128;
/// Fur depth in object units: a few pixels at 128².
const FUR_DEPTH: f32 = 0.08;

fn fixture() -> &'static FurredTorus {
    static FIXTURE: OnceLock<FurredTorus> = OnceLock::new();
    FIXTURE.get_or_init(|| FurredTorus::new(AROUND, ACROSS, REPEATS, FUR_DEPTH))
}

fn scene() -> FurScene {
    fixture().scene()
}

/// Perspective camera (60° field of view) looking at the torus from above and to the side.
fn oblique(size: u32) -> Camera {
    Camera {
        view: look_at([0.0, -2.6, 2.2], [0.0, 0.0, 1.0]),
        projection: column_major(perspective(60.0, 0.5, 10.0)),
        width: size,
        height: size,
    }
}

/// Half the side of the orthographic top view, object units.
const TOP_HALF: f64 = 1.6;

/// Orthographic camera at `eye` looking at the origin: pixel centres map to `[-half, half]²`,
/// view depths 0.5 .. 5.5 to clip depths 0 .. 1.
fn orthographic(eye: [f64; 3], up: [f64; 3], half: f64, size: u32) -> Camera {
    Camera {
        view: look_at(eye, up),
        projection: common::orthographic(half, 0.5, 5.5),
        width: size,
        height: size,
    }
}

/// Orthographic camera looking down the torus's axis: pixel centres map to `[-TOP_HALF, TOP_HALF]²`.
fn top() -> Camera {
    orthographic([0.0, 0.0, 3.0], [0.0, 1.0, 0.0], TOP_HALF, SIZE)
}

fn settings() -> RenderSettings {
    RenderSettings::default()
}

fn skin_only() -> RenderSettings {
    RenderSettings {
        shell_count: Some(0),
        fins: false,
        ..settings()
    }
}

fn render(scene: &FurScene, camera: &Camera, settings: &RenderSettings) -> RgbaImage {
    fixture().render(scene, camera, settings)
}

#[test]
fn furred_torus_renders_and_is_saved_for_viewing() {
    let scene = scene();
    assert_eq!(scene.layers(), 8);
    let image = render(&scene, &oblique(512), &settings());
    let skin = render(&scene, &oblique(512), &skin_only());
    // The torus fills a good part of the frame, and its skin is opaque.
    let fraction = covered(&skin) as f64 / (512.0 * 512.0);
    assert!((0.2..0.8).contains(&fraction), "skin covers {fraction}");
    let opaque = skin.pixels.chunks_exact(4).filter(|p| p[3] == 255).count();
    assert!(opaque as f64 > 0.9 * covered(&skin) as f64);
    // Lit fur is neither black nor blown out: a brown coat under a white light.
    let lit: Vec<&[u8]> = image.pixels.chunks_exact(4).filter(|p| p[3] == 255).collect();
    let mean = |c: usize| lit.iter().map(|p| f64::from(p[c])).sum::<f64>() / lit.len() as f64;
    assert!(mean(0) > 30.0 && mean(0) < 220.0, "mean red {}", mean(0));
    assert!(mean(0) > mean(2), "brown hair: red above blue");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let options = PngOptions {
        srgb: true,
        ..PngOptions::default()
    };
    save_png(
        dir.join("render_furred_torus.png"),
        &image.view().unwrap(),
        &options,
    )
    .unwrap();
    save_png(dir.join("render_skin_torus.png"), &skin.view().unwrap(), &options).unwrap();
}

#[test]
fn fur_extends_the_silhouette_beyond_the_skin() {
    let scene = scene();
    let camera = oblique(SIZE);
    let fur = render(&scene, &camera, &settings());
    let skin = render(&scene, &camera, &skin_only());
    // Blending "over" never removes coverage; the fur adds a rim.
    for (f, s) in fur.pixels.chunks_exact(4).zip(skin.pixels.chunks_exact(4)) {
        assert!(f[3] >= s[3]);
    }
    let (f, s) = (covered(&fur), covered(&skin));
    assert!(f as f64 > 1.02 * s as f64, "fur covers {f} pixels, skin {s}");
}

#[test]
fn a_new_fur_depth_draws_as_a_scene_built_with_it_and_uploads_nothing() {
    let f = fixture();
    let camera = oblique(SIZE);
    let deeper = 2.0 * FUR_DEPTH;
    let built = FurScene::new(&f.renderer, &f.mesh, &f.uvs, &f.volume, deeper).unwrap();
    let expected = render(&built, &camera, &settings());
    // The projected fur depth the LOD follows doubles with it.
    let fur_pixels = |scene: &FurScene| {
        let info = f.renderer.frame_info(scene, &camera, &settings()).unwrap();
        info.fur_pixels.unwrap()
    };
    let mut scene = scene();
    let (before, shallow) = (render(&scene, &camera, &settings()), fur_pixels(&scene));
    let uploads = scene.uploads();
    scene.set_fur_depth(deeper).unwrap();
    assert_eq!(scene.fur_depth(), deeper);
    assert_eq!(scene.uploads(), uploads);
    let after = render(&scene, &camera, &settings());
    assert_eq!(after.pixels, expected.pixels);
    assert!(covered(&after) > covered(&before));
    let deep = fur_pixels(&scene);
    assert!((deep / shallow - 2.0).abs() < 1e-4, "{shallow} → {deep}");
}

#[test]
fn more_shells_never_cover_less_and_change_the_image() {
    let scene = scene();
    let camera = oblique(SIZE);
    // Shell sets {}, {7}, {2, 5, 7}, {1..7}: each contains the one before.
    let images: Vec<RgbaImage> = [0, 1, 3, 7]
        .into_iter()
        .map(|n| {
            let s = RenderSettings {
                shell_count: Some(n),
                fins: false,
                ..settings()
            };
            render(&scene, &camera, &s)
        })
        .collect();
    for pair in images.windows(2) {
        assert!(covered(&pair[1]) >= covered(&pair[0]));
    }
    assert_ne!(images[0], images[3]);
    assert!(covered(&images[3]) > covered(&images[0]));
}

#[test]
fn zero_length_everywhere_renders_exactly_the_skin() {
    let mut scene = scene();
    let camera = oblique(SIZE);
    let before = scene.uploads();
    scene
        .update_attributes(None, Some(&vec![0.0; fixture().mesh.vertex_count()]))
        .unwrap();
    let skin = render(&scene, &camera, &skin_only());
    let bald = render(&scene, &camera, &settings());
    assert!(
        bald == skin,
        "a bald torus with shells and fins must equal its skin render"
    );
    assert_eq!(scene.uploads().texture_bytes, before.texture_bytes);
    assert_eq!(scene.uploads().geometry_bytes, before.geometry_bytes);
}

#[test]
fn fins_change_only_pixels_near_the_silhouette() {
    let scene = scene();
    let camera = top();
    let with = render(&scene, &camera, &settings());
    let without = render(
        &scene,
        &camera,
        &RenderSettings {
            fins: false,
            ..settings()
        },
    );
    // Seen down the axis, the tube point at angle φ from the outer equator has normal
    // (cos φ cos θ, cos φ sin θ, sin φ) and lies at radius 1 + 0.35 cos φ. A fin's normal is
    // perpendicular to the surface normal, so |p| ≤ |cos φ|, and max(0, 2|p| − 1) > 0 needs
    // |cos φ| > 1/2: fins show only where |radius − 1| > 0.175 (both silhouettes, outer and inner).
    // The margin covers the mesh's chords and averaged normals (22.5° steps) and a pixel.
    let band = 0.35 * 0.5 - 0.03;
    let mut changed = 0;
    for y in 0..SIZE {
        for x in 0..SIZE {
            if with.pixel(x, y).unwrap() == without.pixel(x, y).unwrap() {
                continue;
            }
            changed += 1;
            let px = (f64::from(x) + 0.5) / f64::from(SIZE) * 2.0 * TOP_HALF - TOP_HALF;
            let py = TOP_HALF - (f64::from(y) + 0.5) / f64::from(SIZE) * 2.0 * TOP_HALF;
            let radius = px.hypot(py);
            assert!(
                (radius - 1.0).abs() > band,
                "pixel ({x}, {y}) at radius {radius:.3} changed by fins: {:?} vs {:?}",
                with.pixel(x, y),
                without.pixel(x, y)
            );
        }
    }
    assert!(changed > 50, "fins changed only {changed} pixels");
}

#[test]
fn updating_colors_rewrites_only_the_attribute_buffers() {
    let mut scene = scene();
    let camera = oblique(SIZE);
    let white = render(&scene, &camera, &settings());
    let before = scene.uploads();
    let red = vec![[1.0, 0.0, 0.0, 1.0]; fixture().mesh.vertex_count()];
    scene.update_attributes(Some(&red), None).unwrap();
    let after = scene.uploads();
    assert_eq!(after.texture_bytes, before.texture_bytes);
    assert_eq!(after.geometry_bytes, before.geometry_bytes);
    // One RGBA f32 row per GPU vertex of the surface and per fin corner.
    let rows = scene.surface_vertex_count() + 4 * scene.uploaded_fin_count();
    assert_eq!(after.attribute_bytes - before.attribute_bytes, 16 * rows as u64);
    let reddened = render(&scene, &camera, &settings());
    // The default color is white, so red keeps the red channel's computation exactly and leaves
    // green and blue only the (white) specular highlight.
    let (mut green_before, mut green_after) = (0u64, 0u64);
    for (w, r) in white.pixels.chunks_exact(4).zip(reddened.pixels.chunks_exact(4)) {
        assert_eq!((w[0], w[3]), (r[0], r[3]));
        assert!(r[1] <= w[1] && r[2] <= w[2]);
        green_before += u64::from(w[1]);
        green_after += u64::from(r[1]);
    }
    assert!(
        green_after * 2 < green_before,
        "green {green_before} -> {green_after}"
    );
}

#[test]
fn renders_are_deterministic() {
    let camera = oblique(SIZE);
    let (a, b) = (scene(), scene());
    let first = render(&a, &camera, &settings());
    assert!(
        first == render(&a, &camera, &settings()),
        "same scene, same frame"
    );
    assert!(
        first == render(&b, &camera, &settings()),
        "a second upload of the same inputs"
    );
    // A frame of another size in between does not disturb the cached targets.
    let _ = render(&a, &oblique(48), &settings());
    assert!(first == render(&a, &camera, &settings()));
}

#[test]
fn bad_input_is_named_and_the_renderer_survives() {
    let f = fixture();
    let mut scene = scene();
    let lighting = Lighting::default();
    let mut nan = oblique(SIZE);
    nan.projection[0] = f32::NAN;
    let zero = Camera {
        width: 0,
        ..oblique(SIZE)
    };
    for (camera, name) in [(nan, "camera.projection"), (zero, "camera.width")] {
        let e = f
            .renderer
            .render(&scene, &camera, &lighting, &settings())
            .unwrap_err();
        assert_eq!(parameter_name(e), name);
    }
    let e = FurScene::new(&f.renderer, &f.mesh, &f.uvs[1..], &f.volume, FUR_DEPTH)
        .err()
        .unwrap();
    assert_eq!(parameter_name(e), "corner_uvs");
    let mut broken = f.volume.clone();
    broken.shells.pop();
    let e = FurScene::new(&f.renderer, &f.mesh, &f.uvs, &broken, FUR_DEPTH)
        .err()
        .unwrap();
    assert_eq!(parameter_name(e), "volume.shells");
    let too_deep = 2.0 * pelt::mesh::MAX_FUR_DEPTH as f32;
    for depth in [-1.0, 0.0, f32::NAN, f32::INFINITY, too_deep] {
        let e = FurScene::new(&f.renderer, &f.mesh, &f.uvs, &f.volume, depth)
            .err()
            .unwrap();
        assert_eq!(parameter_name(e), "fur_depth");
        let e = scene.set_fur_depth(depth).unwrap_err();
        assert_eq!(parameter_name(e), "fur_depth");
        assert_eq!(scene.fur_depth(), FUR_DEPTH);
    }
    let e = scene.update_attributes(None, Some(&[1.0; 3])).unwrap_err();
    assert_eq!(parameter_name(e), "length");
    let mut lengths = vec![1.0; f.mesh.vertex_count()];
    lengths[7] = f32::NAN;
    let e = scene.update_attributes(None, Some(&lengths)).unwrap_err();
    assert_eq!(parameter_name(e), "length[7]");
    let other = Renderer::new(AdapterChoice::Cpu).unwrap();
    let e = other
        .render(&scene, &oblique(SIZE), &lighting, &settings())
        .unwrap_err();
    assert_eq!(parameter_name(e), "scene");
    // The device is still fine.
    let image = f
        .renderer
        .render(&scene, &oblique(SIZE), &lighting, &settings())
        .unwrap();
    assert!(covered(&image) > 0);
}

/// Vertices, triangles and corner UVs of flat grids in planes of constant z facing +z.
#[derive(Default)]
struct Sheets {
    positions: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
    uvs: Vec<[[f32; 2]; 3]>,
}

impl Sheets {
    /// Adds a `cols × rows` grid over `x` × `[-1, 1]` at height `z`, UVs `(x + 1, y + 1)` tiles.
    fn add(&mut self, x: (f32, f32), z: f32, cols: usize, rows: usize) {
        let base = self.positions.len() as u32;
        let at = |i: usize, j: usize| {
            [
                x.0 + (x.1 - x.0) * i as f32 / cols as f32,
                2.0 * j as f32 / rows as f32 - 1.0,
            ]
        };
        for i in 0..=cols {
            for j in 0..=rows {
                let [x, y] = at(i, j);
                self.positions.push([x, y, z]);
            }
        }
        let index = |i: usize, j: usize| base + (i * (rows + 1) + j) as u32;
        let uv = |i: usize, j: usize| at(i, j).map(|c| c + 1.0);
        for i in 0..cols {
            for j in 0..rows {
                self.triangles
                    .push([index(i, j), index(i + 1, j), index(i + 1, j + 1)]);
                self.uvs.push([uv(i, j), uv(i + 1, j), uv(i + 1, j + 1)]);
                self.triangles
                    .push([index(i, j), index(i + 1, j + 1), index(i, j + 1)]);
                self.uvs.push([uv(i, j), uv(i + 1, j + 1), uv(i, j + 1)]);
            }
        }
    }
}

/// A flat `n × n` grid over `[-1, 1]²` in the xy plane (facing +z) with UVs `(x + 1, y + 1)`
/// tiles and the given comb vector at every vertex.
fn combed_plane(n: usize, comb: [f32; 3]) -> (FurMesh, Vec<[[f32; 2]; 3]>) {
    let mut sheet = Sheets::default();
    sheet.add((-1.0, 1.0), 0.0, n, n);
    let Sheets {
        positions,
        triangles,
        uvs,
    } = sheet;
    let combs = vec![comb; positions.len()];
    let mesh = FurMesh::new(MeshInput::new(&positions, &triangles).with_comb(&combs)).unwrap();
    (mesh, uvs)
}

#[test]
fn comb_shears_the_fur_along_the_comb() {
    let f = fixture();
    // Orthographic, from 20° above the plane along +y: image columns are world x exactly.
    let (s, c) = 20f64.to_radians().sin_cos();
    let camera = Camera {
        view: look_at([0.0, -3.0 * c, 3.0 * s], [0.0, 0.0, 1.0]),
        ..top()
    };
    let depth = 0.3;
    let column_x = |x: u32| (f64::from(x) + 0.5) / f64::from(SIZE) * 2.0 * TOP_HALF - TOP_HALF;
    let pixel = 2.0 * TOP_HALF / f64::from(SIZE);
    // The covered extent along x, in object units.
    let extent = |comb: [f32; 3]| {
        let (mesh, uvs) = combed_plane(8, comb);
        let scene = FurScene::new(&f.renderer, &mesh, &uvs, &f.volume, depth).unwrap();
        let image = render(&scene, &camera, &settings());
        let columns: Vec<f64> = (0..SIZE)
            .filter(|&x| (0..SIZE).any(|y| image.pixel(x, y).unwrap()[3] > 0))
            .map(column_x)
            .collect();
        (columns[0], columns[columns.len() - 1])
    };
    let (left, right) = extent([0.0; 3]);
    assert!(
        left > -1.0 - 2.0 * pixel && right < 1.0 + 2.0 * pixel,
        "uncombed: {left}..{right}"
    );
    // Combed along +x with slope 1, layer i stands at i/L of the depth shifted by as much in x:
    // the top layer (7/8) overhangs the plane's right edge by 0.2625, the left edge not at all.
    let (left, right) = extent([1.0, 0.0, 0.0]);
    let overhang = f64::from(depth) * 7.0 / 8.0;
    assert!(left > -1.0 - 2.0 * pixel, "combed left edge {left}");
    assert!(
        right > 1.0 + 0.5 * overhang && right < 1.0 + overhang + 2.0 * pixel,
        "combed right edge {right}"
    );
}

/// LOD settings whose schedule asks for `shells` shells on `camera` (through `shells_per_pixel`,
/// or `max_shells` for none).
fn lod_for(scene: &FurScene, camera: &Camera, shells: f64) -> RenderSettings {
    let lod = RenderSettings {
        lod: true,
        min_shells: 0,
        ..settings()
    };
    if shells == 0.0 {
        return RenderSettings { max_shells: 0, ..lod };
    }
    let fur = fixture().renderer.frame_info(scene, camera, &lod).unwrap();
    let pixels = f64::from(fur.fur_pixels.unwrap());
    RenderSettings {
        shells_per_pixel: (shells / pixels) as f32,
        ..lod
    }
}

#[test]
fn lod_at_full_detail_is_the_plain_render() {
    let scene = scene();
    let camera = oblique(SIZE);
    let full = lod_for(&scene, &camera, 50.0);
    let info = fixture().renderer.frame_info(&scene, &camera, &full).unwrap();
    assert_eq!((info.shells, info.level, info.blend), (7, 0, 0.0));
    assert!(render(&scene, &camera, &full) == render(&scene, &camera, &settings()));
}

#[test]
fn lod_cross_fades_into_each_coarser_level_without_a_pop() {
    let scene = scene();
    let camera = oblique(SIZE);
    // 8 layers: levels of 7, 4, 2, 1 and 0 shells (each level keeps the skin and halves the
    // hair above it). Just above a level's count the finer level is drawn almost fully faded
    // into the coarser one; just below, the coarser one almost alone.
    for (count, level) in [(4.0f64, 1), (2.0, 2), (1.0, 3), (0.0, 4)] {
        let before = lod_for(&scene, &camera, count + 1e-5);
        let at = lod_for(&scene, &camera, (count - 1e-5).max(0.0));
        let renderer = &fixture().renderer;
        let (i, j) = (
            renderer.frame_info(&scene, &camera, &before).unwrap(),
            renderer.frame_info(&scene, &camera, &at).unwrap(),
        );
        assert_eq!((i.level, j.level), (level - 1, level));
        assert!(i.blend > 0.99 && j.blend < 0.01, "blends {} {}", i.blend, j.blend);
        // Compared premultiplied: the straight color of a pixel a few units from transparent is
        // its premultiplied value divided by those units, 8-bit rounding and all.
        let worst = |a: &RgbaImage, b: &RgbaImage| {
            a.pixels
                .chunks_exact(4)
                .zip(b.pixels.chunks_exact(4))
                .flat_map(|(x, y)| {
                    (0..4).map(move |c| {
                        let scale = |p: &[u8]| if c == 3 { 1.0 } else { f32::from(p[3]) / 255.0 };
                        (f32::from(x[c]) * scale(x) - f32::from(y[c]) * scale(y)).abs()
                    })
                })
                .fold(0.0f32, f32::max)
        };
        let (a, b) = (render(&scene, &camera, &before), render(&scene, &camera, &at));
        // A 1e-5 share of the other level is left, and the shells stand 1e-5 of the way from
        // where the other level's stand: a unit or two of 8-bit rounding. (At 1e-3, a shell's
        // edge crossed the centres of a few pixels of the fringe.)
        assert!(
            worst(&a, &b) <= 3.0,
            "level {level}: images differ by up to {}",
            worst(&a, &b)
        );
        // Switching levels without the cross-fade would pop.
        let finer = lod_for(&scene, &camera, [7.0, 4.0, 2.0, 1.0][level as usize - 1]);
        let pop = worst(&render(&scene, &camera, &finer), &b);
        assert!(
            pop >= 10.0,
            "level {level}: the levels themselves differ by only {pop}"
        );
        // Fewer shells cover no more than the full stack.
        assert!(covered(&b) <= covered(&render(&scene, &camera, &settings())));
    }
}

#[test]
fn a_coarse_lod_level_keeps_the_all_shells_brightness_its_fins_included() {
    // A coarse level's shell holds the hair of a group of layers. Stood at the group's top, where
    // Lengyel §2.4 puts a pair's composite, it reached the fur's full depth at the silhouette
    // with all that hair, where the full stack thins out toward the tips, and hid more of the
    // fins drawn over it: 2% darker than all shells here at two shells, 3% on the benchmark's
    // long-furred sphere. It stands where its coverage seen edge on matches the layers' it holds.
    // (Levels of 2 shells and more; one shell is all the fur in one.)
    // Seen from the side, so that much of the image is silhouette, lit from the eye.
    let view = LitView::torus();
    let camera = view.camera(2 * SIZE);
    let all = view.mean(&camera, &settings());
    for shells in [8.0, 4.0, 2.0] {
        let lod = lod_for(&view.scene, &camera, shells - 1e-4);
        let info = fixture().renderer.frame_info(&view.scene, &camera, &lod);
        assert!(info.unwrap().blend < 1e-3);
        let lod = view.mean(&camera, &lod);
        assert!(
            (lod / all - 1.0).abs() < 0.01,
            "{shells} shells: {lod} against all shells' {all}"
        );
    }
}

/// A furred scene lit from the eye, rendered linear, and its covered pixels' mean luminance.
struct LitView {
    scene: FurScene,
    eye: [f64; 3],
    lighting: Lighting,
}

impl LitView {
    /// The torus under the 16-layer volume seen from the side: much of the image is fur seen at
    /// a slant.
    fn torus() -> Self {
        let f = fixture();
        let volume = common::volume::small_volume(16);
        let eye = [0.0, -3.4, 0.6];
        LitView {
            scene: FurScene::new(&f.renderer, &f.mesh, &f.uvs, &volume, 0.25).unwrap(),
            eye,
            lighting: sun(eye.map(|c| c as f32), 1.0, 0.5),
        }
    }

    /// The flat 2 × 2 plane (tiles one unit wide) under fur `depth` deep of `layers` layers,
    /// seen from `elevation` degrees above it.
    fn plane(layers: usize, depth: f32, elevation: f64) -> Self {
        Self::plane_under(&common::volume::small_volume(layers), depth, elevation)
    }

    /// [`LitView::plane`] under `volume`.
    fn plane_under(volume: &HairVolume, depth: f32, elevation: f64) -> Self {
        let f = fixture();
        let (mesh, uvs) = combed_plane(8, [0.0; 3]);
        let (s, c) = elevation.to_radians().sin_cos();
        let eye = [0.0, -3.4 * c, 3.4 * s];
        LitView {
            scene: FurScene::new(&f.renderer, &mesh, &uvs, volume, depth).unwrap(),
            eye,
            lighting: sun(eye.map(|c| c as f32), 1.0, 0.5),
        }
    }

    fn camera(&self, size: u32) -> Camera {
        Camera {
            view: look_at(self.eye, [0.0, 0.0, 1.0]),
            ..oblique(size)
        }
    }

    /// The linear RGBA channels, pixel after pixel.
    fn render(&self, camera: &Camera, settings: &RenderSettings) -> Vec<f32> {
        fixture()
            .renderer
            .render_linear(&self.scene, camera, &self.lighting, settings)
            .unwrap()
            .pixels
    }

    fn mean(&self, camera: &Camera, settings: &RenderSettings) -> f64 {
        let (lum, alpha) = self
            .render(camera, settings)
            .chunks_exact(4)
            .fold((0.0, 0.0), |(l, a), p| {
                let lum = 0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2]);
                (l + f64::from(p[3]) * lum, a + f64::from(p[3]))
            });
        lum / alpha
    }
}

#[test]
fn a_marched_lod_cross_fade_passes_its_middle_without_a_step() {
    // During a cross-fade the march composites the level drawn and its coarser twin apart. Lit
    // once, at the layer the heavier of the two shows, the image stepped as the blend passed one
    // half (Kajiya–Kay reads the hair tangent at that layer); each composite is now lit and the
    // colors mixed.
    let view = LitView::torus();
    let camera = view.camera(2 * SIZE);
    let renderer = &fixture().renderer;
    let marched = |shells: f64| RenderSettings {
        shell_method: ShellMethod::Marched,
        ..lod_for(&view.scene, &camera, shells)
    };
    for (fine, coarse) in [(15.0, 8.0), (8.0, 4.0), (4.0, 2.0)] {
        let middle = 0.5 * (fine + coarse);
        let (before, after) = (marched(middle + 1e-4), marched(middle - 1e-4));
        let (i, j) = (
            renderer.frame_info(&view.scene, &camera, &before).unwrap(),
            renderer.frame_info(&view.scene, &camera, &after).unwrap(),
        );
        assert!(
            i.level == j.level && i.blend < 0.5 && j.blend > 0.5,
            "{fine} to {coarse} shells: levels {} {}, blends {} {}",
            i.level,
            j.level,
            i.blend,
            j.blend
        );
        let (a, b) = (view.render(&camera, &before), view.render(&camera, &after));
        let worst = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f32, f32::max);
        // The blend moves by 3e-5: the images differ by 4e-5 at most (by 0.02 when one of the
        // two composites' layers was lit).
        assert!(
            worst < 1e-3,
            "{fine} to {coarse} shells: the image steps by {worst} at mid-fade"
        );
    }
}

#[test]
fn the_march_without_lod_keeps_the_brightness_of_the_march_layer_by_layer() {
    // Without LOD each pixel marches the coarsest groups of the LOD chain that its ray crosses
    // within a texel of the mip it reads. A group is lit at its middle height; one or two groups
    // for the whole depth put that height far from where the ray sees the hair, and the pixels
    // switched to them together as the mip level rose with distance (the short-furred patch of
    // the benchmark stepped by 8%; this plane, short-furred and seen 20° above it, strayed 7%
    // at 64²). The groups stop at a quarter of the layers. LOD at full detail marches layer by
    // layer.
    let view = LitView::plane(17, 0.05, 20.0);
    for size in [4 * SIZE, 2 * SIZE, SIZE, SIZE / 2, SIZE / 4] {
        let camera = view.camera(size);
        let marched = RenderSettings {
            shell_method: ShellMethod::Marched,
            ..settings()
        };
        let layered = RenderSettings {
            shell_method: ShellMethod::Marched,
            ..lod_for(&view.scene, &camera, 50.0)
        };
        let info = fixture()
            .renderer
            .frame_info(&view.scene, &camera, &layered)
            .unwrap();
        assert_eq!((info.level, info.blend), (0, 0.0));
        let (grouped, layered) = (view.mean(&camera, &marched), view.mean(&camera, &layered));
        assert!(
            (grouped / layered - 1.0).abs() < 0.02,
            "{size}²: {grouped} grouped against {layered} layer by layer"
        );
    }
}

#[test]
fn a_marched_lod_group_reads_its_hair_direction_at_its_middle() {
    // A composite of the LOD chain holds the hair of a group of layers; the march lit it with the
    // hair direction of the group's top layer (the tips), the instanced shells with that of its
    // middle. Where the hair bends with height that lit the marched LOD apart from the layers it
    // stands for (the benchmark's short-furred patch 10% bright at its coarsest level). Here
    // the tangent map turns from upright at the skin to 23° toward the eye at the tips: two
    // shells were 5.7% dark, now within 1%.
    let mut volume = common::volume::small_volume(17);
    let plane = 4 * volume.resolution * volume.resolution;
    for (layer, texels) in volume.tangents.chunks_exact_mut(plane).enumerate() {
        let lean = 0.3 * layer as f32 / 16.0;
        let d = [0.0, lean, 1.0 - lean];
        let length = (d[1] * d[1] + d[2] * d[2]).sqrt();
        let packed = d.map(|c| (255.0 * (0.5 * c / length + 0.5)).round() as u8);
        texels
            .chunks_exact_mut(4)
            .for_each(|t| t[..3].copy_from_slice(&packed));
    }
    let view = LitView::plane_under(&volume, 0.17, 20.0);
    let camera = view.camera(SIZE);
    let marched = |shells: f64| RenderSettings {
        shell_method: ShellMethod::Marched,
        ..lod_for(&view.scene, &camera, shells)
    };
    let all = view.mean(&camera, &marched(50.0));
    for shells in [8.0, 4.0, 2.0] {
        let lod = view.mean(&camera, &marched(shells - 1e-4));
        assert!(
            (lod / all - 1.0).abs() < 0.02,
            "{shells} shells: {lod} against all shells' {all}"
        );
    }
}

#[test]
fn lod_draws_fewer_shells_far_away() {
    let scene = scene();
    let lod = RenderSettings {
        lod: true,
        min_shells: 1,
        ..settings()
    };
    let at = |distance: f64| Camera {
        view: look_at([0.0, -distance * 0.76, distance * 0.65], [0.0, 0.0, 1.0]),
        ..oblique(SIZE)
    };
    let renderer = &fixture().renderer;
    let near = renderer.frame_info(&scene, &at(3.4), &lod).unwrap();
    let far = renderer.frame_info(&scene, &at(34.0), &lod).unwrap();
    // Ten times as far: a tenth of the pixels per unit.
    let ratio = near.fur_pixels.unwrap() / far.fur_pixels.unwrap();
    assert!((ratio - 10.0).abs() < 0.05, "ratio {ratio}");
    assert!(far.shells < near.shells || far.level > near.level);
    assert!(far.target_shells >= 1.0);
}

#[test]
fn linear_output_encodes_to_the_srgb_image() {
    let scene = scene();
    let camera = oblique(SIZE);
    let renderer = &fixture().renderer;
    for (settings, alpha_bound, mean_bound) in [(skin_only(), 1.0, 0.25), (settings(), 3.0, 1.5)] {
        let srgb = render(&scene, &camera, &settings);
        let linear = renderer
            .render_linear(&scene, &camera, &Lighting::default(), &settings)
            .unwrap();
        assert_eq!((linear.width, linear.height), (SIZE, SIZE));
        let mut total = 0.0;
        for (l, s) in linear.pixels.chunks_exact(4).zip(srgb.pixels.chunks_exact(4)) {
            assert!(l.iter().all(|v| v.is_finite()));
            // Alpha and color in 8-bit sRGB from the float image.
            let alpha = (l[3] * 255.0).round();
            assert!((alpha - f32::from(s[3])).abs() <= alpha_bound, "{l:?} vs {s:?}");
            if s[3] == 255 {
                for c in 0..3 {
                    let encoded =
                        (pelt::texture::color::linear_to_srgb(l[c].clamp(0.0, 1.0)) * 255.0).round();
                    total += f64::from((encoded - f32::from(s[c])).abs());
                }
            }
        }
        // The skin is opaque and unblended: only the half floats' precision and the sRGB
        // encoders' (lavapipe's is approximate) tell them apart, a rounding step on about one
        // value in ten. With fur, the 8-bit target also rounds after every blended shell (1.3
        // levels on average since the default self-shadow is lighter).
        let mean = total / (3 * covered(&srgb)) as f64;
        assert!(mean < mean_bound, "mean difference {mean}");
    }
}

#[test]
fn auto_shells_march_on_the_cpu_adapter() {
    let renderer = &fixture().renderer;
    assert_eq!(renderer.adapter().device_type, "Cpu");
    assert!(renderer.is_cpu());
    assert_eq!(renderer.shell_method(ShellMethod::Auto), ShellMethod::Marched);
    let scene = scene();
    let with = |shell_method| {
        render(
            &scene,
            &oblique(SIZE),
            &RenderSettings {
                shell_method,
                ..settings()
            },
        )
    };
    let auto = with(ShellMethod::Auto);
    assert_eq!(auto.pixels, with(ShellMethod::Marched).pixels);
    assert_ne!(auto.pixels, with(ShellMethod::Instanced).pixels);
}

/// The torus with a uniform skin albedo (layer 0 and its mips set to one sRGB value) and that
/// albedo, linear.
fn uniform_skin() -> (FurScene, f64) {
    let f = fixture();
    let mut volume = f.volume.clone();
    paint_skin(&mut volume, |texel| texel.copy_from_slice(&[188, 188, 188, 255]));
    let albedo = f64::from(pelt::texture::color::srgb_to_linear(188.0 / 255.0));
    (
        FurScene::new(&f.renderer, &f.mesh, &f.uvs, &volume, FUR_DEPTH).unwrap(),
        albedo,
    )
}

/// A sun of strength `strength` from `direction` with Banks strength `self_shadow`, Kajiya–Kay
/// without ambient or highlight and `Kd = 1`.
fn sun(direction: [f32; 3], strength: f32, self_shadow: f32) -> Lighting {
    Lighting {
        direction,
        color: [strength; 3],
        self_shadow,
        model: LightModel::KajiyaKay(KajiyaKay {
            ambient: [0.0; 3],
            diffuse: 1.0,
            specular: 0.0,
            ..KajiyaKay::default()
        }),
    }
}

/// The red channel of the skin over the top of the tube (distance 1 from the axis, normal +z
/// within 4°) in the top view, one value per pixel.
fn skin_over_the_top(scene: &FurScene, lighting: &Lighting) -> Vec<f64> {
    let f = fixture();
    let image = f
        .renderer
        .render_linear(scene, &top(), lighting, &skin_only())
        .unwrap();
    let mut reds = Vec::new();
    for (i, p) in image.pixels.chunks_exact(4).enumerate() {
        let (x, y) = ((i as u32 % SIZE) as f64 + 0.5, (i as u32 / SIZE) as f64 + 0.5);
        let at = |c: f64| (2.0 * c / f64::from(SIZE) - 1.0) * TOP_HALF;
        let rho = at(x).hypot(at(y));
        if (rho - 1.0).abs() < 0.02 && p[3] == 1.0 {
            reds.push(f64::from(p[0]));
        }
    }
    assert!(reds.len() > 20, "{} pixels over the top of the tube", reds.len());
    reds
}

#[test]
fn a_sun_of_strength_e_lights_the_skin_facing_it_to_e_over_pi() {
    // Blender's light units, which the reference and Cycles share: a Lambertian surface of
    // albedo ρ facing a sun of strength E shows ρ E / π. Every other term is switched off.
    let (scene, albedo) = uniform_skin();
    let strength = 2.5f32;
    let expected = albedo * f64::from(strength) / std::f64::consts::PI;
    for red in skin_over_the_top(&scene, &sun([0.0, 0.0, 1.0], strength, 0.0)) {
        assert!((red / expected - 1.0).abs() < 0.02, "skin {red}, ρE/π {expected}");
    }
}

#[test]
fn a_light_from_the_eye_sees_no_self_shadow_and_a_slanted_one_crosses_more_fur() {
    // Banks darkening is the fur's shadow on what lies under it. A light from the eye lights what
    // the eye sees (the view ray is known clear, and the light follows it): no darkening there,
    // where the linear model darkened the skin by the whole strength b. A light 60° off the
    // normal crosses twice the fur: (1 − b)² at the skin, Beer–Lambert, less the hot spot's
    // e^(−60°/0.35 rad) = 5% that remains at 60° from the view (the linear model: 1 − b).
    let (scene, _) = uniform_skin();
    let b = 0.6f32;
    let ratio = |direction: [f32; 3]| {
        let shadowed = skin_over_the_top(&scene, &sun(direction, 2.5, b));
        let clear = skin_over_the_top(&scene, &sun(direction, 2.5, 0.0));
        shadowed.iter().sum::<f64>() / clear.iter().sum::<f64>()
    };
    let from_the_eye = ratio([0.0, 0.0, 1.0]);
    assert!((from_the_eye - 1.0).abs() < 0.02, "from the eye: {from_the_eye}");
    let (s, c) = 60f32.to_radians().sin_cos();
    let slanted = ratio([s, 0.0, c]);
    let hot_spot = (-60f64.to_radians() / 0.35).exp();
    let expected = f64::from(1.0 - b).powf(2.0 * (1.0 - hot_spot));
    assert!(
        (slanted / expected - 1.0).abs() < 0.03,
        "60°: {slanted}, expected {expected}"
    );
}

#[test]
fn painted_length_sets_how_much_fur_shadows_the_skin_and_bald_skin_has_none() {
    // Banks darkening stands for the fur over the skin: hair painted l times as long crosses l
    // times as much of it, (1 − b)^l at the skin under the ambient light and l times the
    // exponent under a slanted sun (60°: 2 (1 − hot spot)). Bald skin (l = 0) is not darkened at
    // all; before, it was darkened by the whole b, as under fur of length 1 (0.4 of the clear
    // skin under the ambient light here, 0.18 under the sun).
    let (mut scene, _) = uniform_skin();
    let b = 0.6f32;
    let (s, c) = 60f32.to_radians().sin_cos();
    let ambient = |self_shadow: f32| Lighting {
        color: [0.0; 3],
        model: LightModel::KajiyaKay(KajiyaKay {
            ambient: [0.4; 3],
            diffuse: 1.0,
            specular: 0.0,
            ..KajiyaKay::default()
        }),
        ..sun([s, 0.0, c], 0.0, self_shadow)
    };
    let hot_spot = (-60f64.to_radians() / 0.35).exp();
    let vertices = fixture().mesh.vertex_count();
    for length in [0.0f32, 0.5] {
        scene
            .update_attributes(None, Some(&vec![length; vertices]))
            .unwrap();
        let ratio = |shadowed: &Lighting, clear: &Lighting| {
            let shadowed = skin_over_the_top(&scene, shadowed);
            let clear = skin_over_the_top(&scene, clear);
            shadowed.iter().sum::<f64>() / clear.iter().sum::<f64>()
        };
        let l = f64::from(length);
        let under_sky = ratio(&ambient(b), &ambient(0.0));
        let expected = f64::from(1.0 - b).powf(l);
        assert!(
            (under_sky / expected - 1.0).abs() < 0.01,
            "length {length}, ambient: {under_sky}, expected {expected}"
        );
        let under_sun = ratio(&sun([s, 0.0, c], 2.5, b), &sun([s, 0.0, c], 2.5, 0.0));
        let expected = f64::from(1.0 - b).powf(2.0 * (1.0 - hot_spot) * l);
        assert!(
            (under_sun / expected - 1.0).abs() < 0.02,
            "length {length}, 60° sun: {under_sun}, expected {expected}"
        );
    }
}

#[test]
fn bald_skin_under_prt_is_a_bare_lambertian_surface() {
    // PRT's transfer is the tile's, baked for hair of length 1; bald skin has no hair to shadow
    // it or to scatter as hair does: it shows albedo × Kd × (E/π cos θ + the sky's radiance),
    // as Kajiya–Kay's bald skin and the reference's Lambertian skin do (Kd the default 0.9).
    // Before, the layer-0 transfer lit it as furred skin: 1.17 of that with the sun at the
    // zenith, 0.63 at 50°; with the sky unscaled by Kd, 1.04 under the sky. Length 1 keeps the
    // transfer: darker than bald under the slanted sun (its shadow).
    let f = fixture();
    let (mut scene, albedo) = uniform_skin();
    let transfer = small_transfer(&f.volume, f64::from(FUR_DEPTH) / 0.5);
    scene.set_transfer(&f.renderer, &transfer).unwrap();
    let vertices = f.mesh.vertex_count();
    let strength = 2.5f32;
    for (degrees, sky) in [(0.0f32, 0.0f32), (50.0, 0.0), (50.0, 0.3)] {
        let (s, c) = degrees.to_radians().sin_cos();
        let lighting = Lighting {
            model: LightModel::Prt(Prt {
                // A uniform sky of radiance `sky`: only Y_0^0, √(4π) · sky.
                environment: vec![[sky * (4.0 * std::f32::consts::PI).sqrt(); 3]],
                ..Prt::default()
            }),
            ..sun([s, 0.0, c], strength, 0.0)
        };
        let mean = |scene: &mut FurScene, length: f32| {
            scene
                .update_attributes(None, Some(&vec![length; vertices]))
                .unwrap();
            let reds = skin_over_the_top(scene, &lighting);
            reds.iter().sum::<f64>() / reds.len() as f64
        };
        let (bald, furred) = (mean(&mut scene, 0.0), mean(&mut scene, 1.0));
        let kd = f64::from(KajiyaKay::default().diffuse);
        let sun = f64::from(strength) / std::f64::consts::PI * f64::from(c);
        let expected = albedo * kd * (sun + f64::from(sky));
        assert!(
            (bald / expected - 1.0).abs() < 0.02,
            "{degrees}°, sky {sky}: bald {bald}, expected {expected}"
        );
        if degrees > 0.0 {
            assert!(furred < 0.95 * bald, "{degrees}°: furred {furred}, bald {bald}");
        }
    }
}

#[test]
fn light_along_a_flat_surface_lights_none_of_its_fur_and_a_curved_one_keeps_its_band() {
    // The wrapped terminator lights hair past the body's shadow line only where the surface
    // curves away under it (√(2 h κ) in N·L, at most 0.3): on a flat grid a sun along the surface
    // lights nothing (it lit the fur to 0.29 of a 45° sun before, 6× the reference on the flat
    // patch), while the torus's top, curving at 1 / 0.35 under 0.08 of fur, keeps its band.
    let f = fixture();
    let (plane, uvs) = combed_plane(8, [0.0; 3]);
    let flat = FurScene::new(&f.renderer, &plane, &uvs, &f.volume, FUR_DEPTH).unwrap();
    let curved = scene();
    let no_fins = RenderSettings {
        fins: false,
        ..settings()
    };
    let light = |scene: &FurScene, direction: [f32; 3]| -> f64 {
        let image = f
            .renderer
            .render_linear(scene, &top(), &sun(direction, 2.5, 0.0), &no_fins)
            .unwrap();
        image.pixels.chunks_exact(4).map(|p| f64::from(p[0] * p[3])).sum()
    };
    let (along, above) = ([1.0, 0.0, 0.0], [1.0, 0.0, 1.0]);
    let flat_ratio = light(&flat, along) / light(&flat, above);
    // Measured: 0.005; with the fixed 0.3 band 0.29.
    assert!(flat_ratio < 0.01, "flat, sun along it: {flat_ratio} of a 45° sun");
    let curved_ratio = light(&curved, along) / light(&curved, above);
    // Measured: 0.39.
    assert!(
        curved_ratio > 0.1,
        "torus, sun along its top: {curved_ratio} of a 45° sun"
    );
}

/// A lower furred sheet over `[-1, 1]²` at z = 0 and, half a unit above its right half, a second
/// one over `[0, 1] × [-1, 1]`: both facing +z, `n` quads along x per unit, UVs their x and y.
fn sheet_under_a_ledge(n: usize) -> (FurMesh, Vec<[[f32; 2]; 3]>) {
    let mut sheets = Sheets::default();
    sheets.add((-1.0, 1.0), 0.0, 2 * n, 2 * n);
    sheets.add((0.0, 1.0), 0.5, n, 2 * n);
    let mesh = FurMesh::new(MeshInput::new(&sheets.positions, &sheets.triangles)).unwrap();
    (mesh, sheets.uvs)
}

#[test]
fn a_ledge_casts_its_shadow_on_the_fur_below_it() {
    // One part of a body shadows another: a sun 45° from +z toward +x throws the ledge
    // (x in [0, 1], half a unit up) onto x in [-0.5, 0.5] of the sheet below. Seen from above,
    // the sheet's fur at x in [-0.4, -0.1] lies in that shadow, at x in [-0.95, -0.7] in the
    // sun; without ambient the shadowed fur shows nothing of the sun, under Kajiya–Kay and PRT
    // alike. Before the body's shadow map both were lit alike (ratio 1.0).
    let f = fixture();
    let (mesh, uvs) = sheet_under_a_ledge(8);
    let mut scene = FurScene::new(&f.renderer, &mesh, &uvs, &f.volume, FUR_DEPTH).unwrap();
    // The sheets' tiles are half a unit.
    let transfer = small_transfer(&f.volume, 2.0 * f64::from(FUR_DEPTH));
    scene.set_transfer(&f.renderer, &transfer).unwrap();
    let (s, c) = 45f32.to_radians().sin_cos();
    let kajiya_kay = sun([s, 0.0, c], 2.5, 0.0);
    let prt = Lighting {
        model: LightModel::Prt(Prt {
            environment: Vec::new(),
            ..Prt::default()
        }),
        ..kajiya_kay.clone()
    };
    // With `body_shadow` off the two places are lit alike again (the runtimes' view).
    for (model, lighting, method, body_shadow) in [
        ("Kajiya–Kay", &kajiya_kay, ShellMethod::Instanced, true),
        ("Kajiya–Kay", &kajiya_kay, ShellMethod::Marched, true),
        ("PRT", &prt, ShellMethod::Instanced, true),
        ("PRT", &prt, ShellMethod::Marched, true),
        ("Kajiya–Kay", &kajiya_kay, ShellMethod::Instanced, false),
        ("PRT", &prt, ShellMethod::Marched, false),
    ] {
        let settings = RenderSettings {
            shell_method: method,
            body_shadow,
            ..settings()
        };
        let image = f
            .renderer
            .render_linear(&scene, &top(), lighting, &settings)
            .unwrap();
        let column_x = |x: u32| (f64::from(x) + 0.5) / f64::from(SIZE) * 2.0 * TOP_HALF - TOP_HALF;
        let mean_red = |from: f64, to: f64| {
            let (mut sum, mut count) = (0.0, 0usize);
            for y in 0..SIZE {
                let row_y = TOP_HALF - (f64::from(y) + 0.5) / f64::from(SIZE) * 2.0 * TOP_HALF;
                for x in 0..SIZE {
                    let p = &image.pixels[4 * (y * SIZE + x) as usize..][..4];
                    if (from..to).contains(&column_x(x)) && row_y.abs() < 0.8 && p[3] > 0.0 {
                        sum += f64::from(p[0]);
                        count += 1;
                    }
                }
            }
            assert!(count > 50, "{count} pixels in {from}..{to}");
            sum / count as f64
        };
        let (shadowed, lit) = (mean_red(-0.4, -0.1), mean_red(-0.95, -0.7));
        // Measured: Kajiya–Kay 0 against 0.061 (instanced) and 0.063 (marched); PRT, shadowed
        // per vertex, 0.0006 against 0.072 and 0.071. Without the shadow: 0.994 and 0.992 of lit.
        let bounds = if body_shadow { 0.0..0.02 } else { 0.95..1.05 };
        assert!(
            lit > 0.0 && bounds.contains(&(shadowed / lit)),
            "{model} {method:?}, body_shadow {body_shadow}: shadowed {shadowed}, lit {lit}"
        );
    }
}

#[test]
fn the_body_s_shadow_follows_a_pose() {
    // The map is drawn again when the light, the pose or the mesh level changes. A pose that
    // slides the ledge from x in [0, 1] to [-1, 0] keeps the bounding box (so the light's view
    // of it is the same) but moves the shadow: on the sheet's uncovered x in [0.2, 0.45] a stale
    // map would still cast the old ledge's shadow (the sun at 45° passes 0.5 over x + 0.5).
    let f = fixture();
    let (mesh, uvs) = sheet_under_a_ledge(8);
    let mut scene = FurScene::new(&f.renderer, &mesh, &uvs, &f.volume, FUR_DEPTH).unwrap();
    let (s, c) = 45f32.to_radians().sin_cos();
    let lighting = sun([s, 0.0, c], 2.5, 0.0);
    let mean_red = |scene: &FurScene, from: f64, to: f64| {
        let image = f
            .renderer
            .render_linear(scene, &top(), &lighting, &settings())
            .unwrap();
        let column_x = |x: u32| (f64::from(x) + 0.5) / f64::from(SIZE) * 2.0 * TOP_HALF - TOP_HALF;
        let row = &image.pixels[4 * (SIZE / 2 * SIZE) as usize..][..4 * SIZE as usize];
        let reds: Vec<f64> = (0..SIZE)
            .filter(|&x| (from..to).contains(&column_x(x)))
            .map(|x| f64::from(row[4 * x as usize]))
            .collect();
        reds.iter().sum::<f64>() / reds.len() as f64
    };
    // A frame first, so that the map holds the ledge where it was.
    assert!(mean_red(&scene, -0.4, -0.1) < 0.02 * mean_red(&scene, -0.95, -0.7));
    let moved: Vec<[f32; 3]> = mesh
        .positions()
        .iter()
        .map(|&[x, y, z]| if z > 0.25 { [x - 1.0, y, z] } else { [x, y, z] })
        .collect();
    scene.deform(&moved, None).unwrap();
    let ratio = mean_red(&scene, 0.2, 0.45) / mean_red(&scene, 0.6, 0.95);
    // Measured: 0.98 (0 when the pose left the map as it was).
    assert!(
        ratio > 0.9,
        "where the ledge's shadow was: {ratio} of the sunlit fur"
    );
}

#[test]
fn goldman_attenuation_splits_the_hairs_direct_light_into_reflected_and_transmitted() {
    // Goldman's factor (1 + κ)/2 ρ_reflect + (1 − κ)/2 ρ_transmit scales the hair's direct
    // light, which is otherwise linear in it: image(ρr, ρt) = S + ρr R + ρt T, S the skin and
    // ambient (none here), so image(1, 0) + image(0, 1) = image(1, 1) + image(0, 0). With the
    // light exactly from the (orthographic) eye every hair shows its lit side, κ = 1, and
    // ρ_transmit changes nothing.
    let f = fixture();
    let scene = scene();
    let image = |direction: [f32; 3], reflect: f32, transmit: f32| -> Vec<f32> {
        let lighting = Lighting {
            direction,
            color: [2.5; 3],
            self_shadow: 0.0,
            model: LightModel::KajiyaKay(KajiyaKay {
                ambient: [0.0; 3],
                reflect,
                transmit,
                ..KajiyaKay::default()
            }),
        };
        let linear = f
            .renderer
            .render_linear(&scene, &top(), &lighting, &settings())
            .unwrap();
        // Premultiplied, so that sums of images are sums of light.
        linear
            .pixels
            .chunks_exact(4)
            .flat_map(|p| [p[0] * p[3], p[1] * p[3], p[2] * p[3]])
            .collect()
    };
    let close = |a: &[f32], b: &[f32]| {
        a.iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() <= 2e-3 * (1.0 + y.abs()))
    };
    let eye = [0.0, 0.0, 1.0];
    assert!(close(&image(eye, 1.0, 0.0), &image(eye, 1.0, 1.0)));
    let side = [0.8, 0.0, 0.6];
    let (reflected, transmitted) = (image(side, 1.0, 0.0), image(side, 0.0, 1.0));
    let (both, neither) = (image(side, 1.0, 1.0), image(side, 0.0, 0.0));
    let sum: Vec<f32> = reflected.iter().zip(&transmitted).map(|(a, b)| a + b).collect();
    let expected: Vec<f32> = both.iter().zip(&neither).map(|(a, b)| a + b).collect();
    assert!(close(&sum, &expected));
    // Both parts light some hair: the light from the side falls on seen and unseen sides.
    let total = |v: &[f32], base: &[f32]| v.iter().zip(base).map(|(a, b)| f64::from(a - b)).sum::<f64>();
    assert!(total(&reflected, &neither) > 1.0 && total(&transmitted, &neither) > 1.0);
    // Bad factors are named.
    let bad = Lighting {
        model: LightModel::KajiyaKay(KajiyaKay {
            transmit: 1.5,
            ..KajiyaKay::default()
        }),
        ..Lighting::default()
    };
    let err = f.renderer.render(&scene, &top(), &bad, &settings()).unwrap_err();
    assert_eq!(parameter_name(err), "kajiya_kay.transmit");
}

/// Mean alpha of each row of `rgba` (`width` texels a row), `[0, 1]`.
fn row_alpha(rgba: &[u8], width: usize) -> Vec<f64> {
    rgba.chunks_exact(4 * width)
        .map(|row| row.chunks_exact(4).map(|p| f64::from(p[3])).sum::<f64>() / (255.0 * width as f64))
        .collect()
}

/// The fin tests' scene: one long edge facing an orthographic camera, its fin eight tiles long
/// but hardly taller than its texture, the shells off.
struct FaceOnFin {
    renderer: Renderer,
    volume: HairVolume,
    scene: FurScene,
    camera: Camera,
    settings: RenderSettings,
}

/// Half the face-on fin camera's view, object units.
const FIN_VIEW_HALF: f64 = 1.2;
/// The face-on fin's fur depth.
const FIN_DEPTH: f32 = 0.5;
/// The face-on fin's tile, object units.
const FIN_TILE: f32 = 0.25;

fn face_on_fin(size: u32) -> FaceOnFin {
    let renderer = Renderer::new(AdapterChoice::Cpu).expect("a CPU adapter (lavapipe) must exist");
    let volume = common::volume::small_volume(8);
    // The edge (−1, 0, 0)–(1, 0, 0) faces −y; the other two run almost along y, so their fins
    // face sideways and fade out. The triangle itself, and every shell, is seen edge-on.
    let positions = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 10.0, 0.0]];
    let uv = positions.map(|p| [p[0] / FIN_TILE, p[1] / FIN_TILE]);
    let mesh = FurMesh::new(MeshInput::new(&positions, &[[0, 1, 2]])).unwrap();
    let scene = FurScene::new(&renderer, &mesh, &[uv], &volume, FIN_DEPTH).unwrap();
    let camera = orthographic([0.0, -5.0, 0.0], [0.0, 0.0, 1.0], FIN_VIEW_HALF, size);
    let settings = RenderSettings {
        shell_count: Some(0),
        ..RenderSettings::default()
    };
    FaceOnFin {
        renderer,
        volume,
        scene,
        camera,
        settings,
    }
}

#[test]
fn a_fin_seen_face_on_shows_its_textures_height_profile_however_often_the_texture_repeats() {
    // One long edge facing an orthographic camera, its fin eight tiles long but hardly taller
    // than its texture: the fin texture is squeezed 10× across and barely along its height. A
    // mip level picked by the larger squeeze blurred the fin's rows into a few texels, spilling
    // the opaque roots up to the tips (the fringe stood too opaque, too high). Each pixel row
    // must show the texture row it stands at, averaged along the fin.
    let size = 128;
    let FaceOnFin {
        renderer,
        volume,
        scene,
        camera,
        settings,
    } = face_on_fin(size);
    let (half, depth) = (FIN_VIEW_HALF, FIN_DEPTH);
    let image = renderer
        .render(&scene, &camera, &Lighting::default(), &settings)
        .unwrap();
    let [fin_width, fin_height] = volume.fin_size;
    let texture = row_alpha(&volume.fin, fin_width);
    let (mut worst, mut sum, mut rows) = (0.0f64, 0.0, 0);
    for y in 0..size {
        let z = half - (f64::from(y) + 0.5) / f64::from(size) * 2.0 * half;
        let height = z / f64::from(depth);
        if !(0.04..=0.96).contains(&height) {
            continue;
        }
        // Pixel columns well inside the edge's ends (x in [−0.8, 0.8]).
        let inside = (0..size).filter(|&x| {
            let px = (f64::from(x) + 0.5) / f64::from(size) * 2.0 * half - half;
            px.abs() < 0.8
        });
        let (count, shown) = inside.fold((0, 0.0), |(n, s), x| {
            (n + 1, s + f64::from(image.pixel(x, y).unwrap()[3]) / 255.0)
        });
        let shown = shown / f64::from(count);
        // The texture's row mean at this height, linearly between row centres (row 0 on top).
        let t = ((1.0 - height) * fin_height as f64 - 0.5).clamp(0.0, fin_height as f64 - 1.0);
        let (r, f) = (t.floor() as usize, t.fract());
        let expected = texture[r] * (1.0 - f) + texture[(r + 1).min(fin_height - 1)] * f;
        worst = worst.max((shown - expected).abs());
        sum += (shown - expected).abs();
        rows += 1;
    }
    assert!(rows > 20, "{rows} pixel rows on the fin");
    assert!(
        worst < 0.04 && sum / f64::from(rows) < 0.015,
        "fin alpha against its texture's rows: worst {worst:.3}, mean {:.3}",
        sum / f64::from(rows)
    );
}

#[test]
fn a_fin_is_lit_by_its_hairs_spread_about_the_growth_direction() {
    // The fin of the face-on edge above under Kajiya–Kay diffuse light alone, from a sun along
    // the growth direction and from one 37° off it toward the eye. The fin stands for hair that
    // leans about the growth direction; lit by that one tangent, a light along it lit nothing
    // (the patch's near edge came out black under a sun overhead where the reference's strands
    // are lit). The ratio of the two images must be what the tangent map's own directions give,
    // averaged here texel by texel: E[sin(T, L)] × N·L for each sun (measured 0.216 against
    // 0.215; before, 0).
    let FaceOnFin {
        renderer,
        volume,
        scene,
        camera,
        settings,
    } = face_on_fin(64);
    let (tile, depth) = (FIN_TILE, FIN_DEPTH);
    let suns = [[0.0f32, 0.0, 1.0], [0.0, -0.6, 0.8]];
    let lit = suns.map(|direction| {
        let lighting = Lighting {
            direction,
            color: [1.0; 3],
            self_shadow: 0.0,
            model: LightModel::KajiyaKay(KajiyaKay {
                ambient: [0.0; 3],
                specular: 0.0,
                ..KajiyaKay::default()
            }),
        };
        let image = renderer
            .render_linear(&scene, &camera, &lighting, &settings)
            .unwrap();
        image.pixels.chunks_exact(4).map(|p| f64::from(p[1])).sum::<f64>()
    });
    // The tangent map's directions in object space (x along u, y along v, z up: the tile is
    // `tile` across and the fur `depth` deep), each hair texel weighed by its coverage.
    let texels = volume.resolution * volume.resolution;
    let mut sines = [0.0f64; 2];
    let mut weight = 0.0;
    for (i, t) in volume.tangents.chunks_exact(4).enumerate().skip(texels) {
        let w = f64::from(volume.coverage[i]);
        let d = [0, 1, 2].map(|k| f64::from(t[k]) / 127.5 - 1.0);
        let o = [
            d[0] * f64::from(tile),
            d[1] * f64::from(tile),
            d[2] * f64::from(depth),
        ];
        let len = (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt();
        if !(w > 0.0 && len > 0.0) {
            continue;
        }
        for (s, sun) in sines.iter_mut().zip(&suns) {
            let c = (o[0] * f64::from(sun[0]) + o[1] * f64::from(sun[1]) + o[2] * f64::from(sun[2])) / len;
            *s += w * (1.0 - c * c).max(0.0).sqrt();
        }
        weight += w;
    }
    let expected = (sines[0] / weight * 1.0) / (sines[1] / weight * 0.8);
    let ratio = lit[0] / lit[1];
    assert!(lit[1] > 0.0, "the fin drew nothing");
    assert!(
        (ratio / expected - 1.0).abs() < 0.03,
        "sun along the hair over sun 37° off it: {ratio:.3}, the tangent map gives {expected:.3}"
    );
}
