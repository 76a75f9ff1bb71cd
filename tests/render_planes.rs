//! The virtual planes (`ShellMethod::VirtualPlanes`, raycast-fur-virtual-planes §3) on the CPU
//! adapter: the furred torus with slices baked from the same hair as its volume. Checked
//! against the torus's geometry (where fur can stand), against the loop limit's meaning (a ray
//! crosses at most that many planes, so a higher limit never covers less), and for named errors
//! on a scene without slices or with bad settings. Their agreement with the reference renderer
//! is `tests/blender/test_picture.py`'s (a release build). Fails (never skips) without a CPU
//! adapter.
#![cfg(feature = "render")]

mod common;

use std::sync::OnceLock;

use pelt::export::{PngOptions, save_png};
use pelt::hair::grow_strands;
use pelt::render::{FurScene, RenderSettings, RgbaImage, ShellMethod};
use pelt::volume::{PlaneParams, PlaneSlices, bake_slices};

use common::parameter_name;
use common::torus::{FurredTorus, covered, differing, oblique_view, perspective_camera};
use common::volume::small_hair;

const SIZE: u32 = 96;
const FUR_DEPTH: f32 = 0.08;

struct Fixture {
    torus: FurredTorus,
    slices: PlaneSlices,
}

fn fixture() -> &'static Fixture {
    static FIXTURE: OnceLock<Fixture> = OnceLock::new();
    FIXTURE.get_or_init(|| {
        let torus = FurredTorus::new(32, 16, [8.0, 2.0], FUR_DEPTH);
        let strands = grow_strands(&small_hair()).unwrap();
        let params = PlaneParams {
            planes: 16,
            size: [64, 32],
        };
        let slices = bake_slices(&strands, |_| true, &params, None).unwrap();
        Fixture { torus, slices }
    })
}

fn planes_scene() -> FurScene {
    let f = fixture();
    let mut scene = f.torus.scene();
    scene.set_planes(&f.torus.renderer, Some(&f.slices)).unwrap();
    scene
}

fn settings(method: ShellMethod, loop_limit: u32) -> RenderSettings {
    RenderSettings {
        shell_method: method,
        plane_loop_limit: loop_limit,
        ..RenderSettings::default()
    }
}

fn render(scene: &FurScene, settings: &RenderSettings) -> RgbaImage {
    fixture()
        .torus
        .render(scene, &perspective_camera(oblique_view(), SIZE), settings)
}

#[test]
fn the_planes_cover_the_skin_and_its_fur_as_the_shells_do_and_look_their_own_way() {
    let scene = planes_scene();
    let planes = render(&scene, &settings(ShellMethod::VirtualPlanes, 16));
    let shells = render(&scene, &settings(ShellMethod::Instanced, 16));
    let skin = render(
        &scene,
        &RenderSettings {
            fins: false,
            shell_count: Some(0),
            ..settings(ShellMethod::Instanced, 16)
        },
    );
    let options = PngOptions {
        srgb: true,
        ..PngOptions::default()
    };
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    save_png(
        dir.join("render_planes_torus.png"),
        &planes.view().unwrap(),
        &options,
    )
    .unwrap();
    // The fur stands beyond the skin's silhouette, within a few pixels of where the shells'
    // does: both stand on the same hull and fins.
    let (planes_covered, shells_covered, skin_covered) = (covered(&planes), covered(&shells), covered(&skin));
    assert!(
        planes_covered > skin_covered,
        "{planes_covered} vs skin {skin_covered}"
    );
    let spread = (planes_covered as f64 - shells_covered as f64).abs() / shells_covered as f64;
    assert!(spread < 0.03, "{planes_covered} vs shells {shells_covered}");
    // Traced through other textures, the picture is not the shells'.
    assert!(differing(&planes, &shells, 8) > 0.2);
    // And the same bytes every time.
    assert_eq!(
        planes.pixels,
        render(&scene, &settings(ShellMethod::VirtualPlanes, 16)).pixels
    );
}

#[test]
fn a_higher_loop_limit_crosses_more_planes_and_never_covers_less() {
    let scene = planes_scene();
    let opacity = |limit| -> f64 {
        let image = render(&scene, &settings(ShellMethod::VirtualPlanes, limit));
        image.pixels.chunks_exact(4).map(|p| f64::from(p[3])).sum()
    };
    // One plane per ray lets the skin show between the hairs of one slice; more planes hide it.
    let (one, four, many) = (opacity(1), opacity(4), opacity(64));
    assert!(one < four && four <= many, "{one} {four} {many}");
    // The fur over the skin is what a limit changes: the silhouette is the hull's either way.
    let fewest = render(&scene, &settings(ShellMethod::VirtualPlanes, 1));
    assert_eq!(
        covered(&fewest),
        covered(&render(&scene, &settings(ShellMethod::VirtualPlanes, 64)))
    );
}

#[test]
fn planes_need_slices_and_bad_settings_are_named() {
    let f = fixture();
    let renderer = &f.torus.renderer;
    let camera = perspective_camera(oblique_view(), 32);
    let lighting = pelt::render::Lighting::default();
    let mut scene = f.torus.scene();
    let planes = settings(ShellMethod::VirtualPlanes, 16);
    let err = renderer.render(&scene, &camera, &lighting, &planes).unwrap_err();
    assert_eq!(parameter_name(err), "shell_method");
    for limit in [0, 257] {
        scene.set_planes(renderer, Some(&f.slices)).unwrap();
        let err = renderer
            .render(
                &scene,
                &camera,
                &lighting,
                &settings(ShellMethod::VirtualPlanes, limit),
            )
            .unwrap_err();
        assert_eq!(parameter_name(err), "plane_loop_limit");
    }
    // Slices that do not match their sizes leave the scene's own in place.
    let short = PlaneSlices {
        rgba: f.slices.rgba[4..].to_vec(),
        ..f.slices.clone()
    };
    assert_eq!(
        parameter_name(scene.set_planes(renderer, Some(&short)).unwrap_err()),
        "planes.rgba"
    );
    let leaning = PlaneSlices {
        tilt: [f32::NAN, 0.0],
        ..f.slices.clone()
    };
    assert_eq!(
        parameter_name(scene.set_planes(renderer, Some(&leaning)).unwrap_err()),
        "planes.tilt"
    );
    renderer.render(&scene, &camera, &lighting, &planes).unwrap();
    // Removed, the scene refuses the method again and the shells still draw.
    scene.set_planes(renderer, None).unwrap();
    assert!(renderer.render(&scene, &camera, &lighting, &planes).is_err());
    renderer
        .render(&scene, &camera, &lighting, &settings(ShellMethod::Instanced, 16))
        .unwrap();
}

#[test]
fn lod_and_shell_count_do_not_apply_to_the_planes() {
    let scene = planes_scene();
    let plain = render(&scene, &settings(ShellMethod::VirtualPlanes, 16));
    let with_count = render(
        &scene,
        &RenderSettings {
            shell_count: Some(2),
            ..settings(ShellMethod::VirtualPlanes, 16)
        },
    );
    assert_eq!(plain.pixels, with_count.pixels);
    let info = fixture()
        .torus
        .renderer
        .frame_info(
            &scene,
            &perspective_camera(oblique_view(), SIZE),
            &RenderSettings {
                lod: true,
                ..settings(ShellMethod::VirtualPlanes, 16)
            },
        )
        .unwrap();
    assert_eq!(info.shells, 7, "the 8-layer volume's every shell");
}
