//! Guard hairs drawn as strands over the shells (`FurScene::set_guard_hairs`) on the CPU
//! adapter: a torus covered by lapped patches, its volume baked from the undercoat and its
//! overcoat placed as strands. Checked against the same scene without strands (which must be
//! the shells-only image exactly), against the torus's geometry (where strands can reach), and
//! against the rest scene seen through a pose's motion. Fails (never skips) without a CPU
//! adapter.
#![cfg(feature = "render")]

mod common;

use std::sync::OnceLock;

use glam::{DMat4, Vec3};
use pelt::guard::guard_hairs;
use pelt::hair::HairParams;
use pelt::lapped::Patches;
use pelt::mesh::shapes::torus;
use pelt::placement::PlacedStrands;
use pelt::render::{
    AdapterChoice, Camera, FurScene, LightModel, Lighting, Prt, RenderSettings, Renderer, RgbaImage,
    StrandOrder,
};
use pelt::volume::{HairVolume, VolumeParams, bake_volume};
use pelt::{FurMesh, MeshInput, PeltError};

use common::torus::{differing, oblique_view, perspective_camera};
use common::volume::small_transfer;

const SIZE: u32 = 128;
const FUR_DEPTH: f32 = 0.08;

struct Fixture {
    renderer: Renderer,
    mesh: FurMesh,
    patches: Patches,
    volume: HairVolume,
    strands: PlacedStrands,
}

fn fixture() -> &'static Fixture {
    static FIXTURE: OnceLock<Fixture> = OnceLock::new();
    FIXTURE.get_or_init(|| {
        let renderer =
            Renderer::new(AdapterChoice::Cpu).expect("a CPU adapter (lavapipe) must exist under make test");
        let (positions, triangles) = torus(32, 16);
        let mesh = FurMesh::new(MeshInput::new(&positions, &triangles)).unwrap();
        let patches = common::patches_at(&mesh, 0.4);
        let defaults = HairParams::default();
        let mut hair = HairParams {
            density: 2000,
            guard_fraction: 0.05,
            ..defaults.clone()
        };
        hair.overcoat.width = defaults.overcoat.width.map(|w| w * 3.0);
        let params = VolumeParams {
            layers: 8,
            resolution: 64,
            fin_size: [128, 32],
            guard_hairs: true,
            ..VolumeParams::default()
        };
        let volume = bake_volume(&hair, &params, None).unwrap();
        let strands = guard_hairs(&mesh, &patches, &hair, f64::from(FUR_DEPTH), 1.0).unwrap();
        Fixture {
            renderer,
            mesh,
            patches,
            volume,
            strands,
        }
    })
}

fn scene(mesh: &FurMesh) -> FurScene {
    let f = fixture();
    FurScene::new(&f.renderer, mesh, &f.patches.uv, &f.volume, FUR_DEPTH).unwrap()
}

fn settings() -> RenderSettings {
    RenderSettings {
        mesh_error: 0.0,
        ..RenderSettings::default()
    }
}

fn camera(view: DMat4) -> Camera {
    perspective_camera(view, SIZE)
}

fn render(scene: &FurScene, camera: &Camera, settings: &RenderSettings) -> RgbaImage {
    fixture()
        .renderer
        .render(scene, camera, &Lighting::default(), settings)
        .unwrap()
}

#[test]
fn without_guard_hairs_the_frame_is_the_shells_alone_exactly() {
    let f = fixture();
    let shells = scene(&f.mesh);
    let expected = render(&shells, &camera(oblique_view()), &settings());
    let mut emptied = scene(&f.mesh);
    emptied.set_guard_hairs(&f.renderer, &f.strands).unwrap();
    emptied
        .set_guard_hairs(&f.renderer, &PlacedStrands::default())
        .unwrap();
    assert_eq!(emptied.guard_strand_count(), 0);
    assert!(render(&emptied, &camera(oblique_view()), &settings()).pixels == expected.pixels);
    let mut hidden = scene(&f.mesh);
    hidden.set_guard_hairs(&f.renderer, &f.strands).unwrap();
    let off = RenderSettings {
        guard_hairs: false,
        ..settings()
    };
    assert!(render(&hidden, &camera(oblique_view()), &off).pixels == expected.pixels);
    // And with them drawn, the picture changes (the checks above can fail).
    let drawn = render(&hidden, &camera(oblique_view()), &settings());
    assert!(differing(&drawn, &expected, 8) > 0.02);
}

#[test]
fn strands_reach_past_the_shells_only_as_far_as_the_hair_is_long() {
    let f = fixture();
    let mut hybrid = scene(&f.mesh);
    hybrid.set_guard_hairs(&f.renderer, &f.strands).unwrap();
    assert_eq!(hybrid.guard_strand_count(), f.strands.spans.len());
    // A top view, orthographic: a pixel's distance from the torus's ring is known.
    let half = 1.6;
    let camera = Camera {
        view: common::look_at([0.0, 0.0, 3.0], [0.0, 1.0, 0.0]),
        projection: common::orthographic(half, 0.5, 5.5),
        width: SIZE,
        height: SIZE,
    };
    let shells = render(&scene(&f.mesh), &camera, &settings());
    let image = render(&hybrid, &camera, &settings());
    let (ring, tube) = (1.0, 0.35);
    let longest = f.strands.points.iter().fold(0.0f32, |m, p| {
        let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
        m.max(((r - ring).powi(2) + p[2].powi(2)).sqrt() + p[3])
    });
    assert!(
        longest > tube + 0.5 * FUR_DEPTH,
        "the strands stand {longest} from the ring"
    );
    let pixel = 2.0 * half / f64::from(SIZE);
    let (mut beyond_shells, mut beyond_hair) = (0, 0);
    for (i, (p, q)) in image
        .pixels
        .chunks_exact(4)
        .zip(shells.pixels.chunks_exact(4))
        .enumerate()
    {
        let x = -half + pixel * ((i as u32 % SIZE) as f64 + 0.5);
        let y = half - pixel * ((i as u32 / SIZE) as f64 + 0.5);
        let from_ring = ((x * x + y * y).sqrt() - f64::from(ring)).abs();
        // Outside the skin, where the strands thicken the fringe.
        if from_ring > f64::from(tube) + pixel && p[3] >= q[3].saturating_add(32) {
            beyond_shells += 1;
        }
        if p[3] > 0 && from_ring > f64::from(longest.max(tube + FUR_DEPTH)) + pixel {
            beyond_hair += 1;
        }
    }
    assert!(
        beyond_shells > 50,
        "{beyond_shells} pixels of the fringe thickened by strands"
    );
    assert_eq!(beyond_hair, 0);
}

#[test]
fn a_pose_carries_the_strands_with_the_surface() {
    let f = fixture();
    let mut rest = scene(&f.mesh);
    rest.set_guard_hairs(&f.renderer, &f.strands).unwrap();
    let mut posed = scene(&f.mesh);
    posed.set_guard_hairs(&f.renderer, &f.strands).unwrap();
    let turn = glam::Mat3::from_axis_angle(Vec3::new(1.0, 2.0, 0.5).normalize(), 0.7);
    let shift = Vec3::new(0.3, -0.2, 0.1);
    let moved = |rows: &[[f32; 3]], offset: Vec3| -> Vec<[f32; 3]> {
        rows.iter()
            .map(|&p| (turn * Vec3::from(p) + offset).to_array())
            .collect()
    };
    posed
        .deform(
            &moved(f.mesh.positions(), shift),
            Some(&moved(f.mesh.normals(), Vec3::ZERO)),
        )
        .unwrap();
    let motion = DMat4::from_translation(shift.as_dvec3()) * DMat4::from_mat3(turn.as_dmat3());
    let light = Lighting::default();
    let turned = Lighting {
        direction: (turn * Vec3::from(light.direction)).to_array(),
        ..light.clone()
    };
    let renderer = &f.renderer;
    let expected = renderer
        .render(&rest, &camera(oblique_view()), &light, &settings())
        .unwrap();
    let got = renderer
        .render(
            &posed,
            &camera(oblique_view() * motion.inverse()),
            &turned,
            &settings(),
        )
        .unwrap();
    let off = differing(&expected, &got, 6);
    assert!(off < 0.004, "{:.2}% of the pixels differ", 100.0 * off);
    let unmoved = renderer
        .render(&posed, &camera(oblique_view()), &turned, &settings())
        .unwrap();
    assert!(differing(&expected, &unmoved, 12) > 0.2);
}

/// `image` box-filtered to a quarter of its side (stochastic coverage is right on average).
fn quarter(image: &RgbaImage) -> Vec<[f64; 4]> {
    let side = (SIZE / 4) as usize;
    let mut out = vec![[0.0; 4]; side * side];
    for (i, p) in image.pixels.chunks_exact(4).enumerate() {
        let (x, y) = (i % SIZE as usize / 4, i / SIZE as usize / 4);
        for c in 0..4 {
            out[y * side + x][c] += f64::from(p[c]) / 16.0;
        }
    }
    out
}

/// Mean absolute difference, levels, of the quarter-size images.
fn mean_difference(a: &RgbaImage, b: &RgbaImage) -> f64 {
    let (a, b) = (quarter(a), quarter(b));
    let sum: f64 = a
        .iter()
        .zip(&b)
        .map(|(p, q)| (0..4).map(|c| (p[c] - q[c]).abs()).sum::<f64>())
        .sum();
    sum / (4 * a.len()) as f64
}

#[test]
fn every_strand_order_draws_close_to_the_sorted_composite() {
    let f = fixture();
    let mut hybrid = scene(&f.mesh);
    hybrid.set_guard_hairs(&f.renderer, &f.strands).unwrap();
    let with = |order| RenderSettings {
        strand_order: order,
        ..settings()
    };
    let sorted = render(&hybrid, &camera(oblique_view()), &with(StrandOrder::Sorted));
    let shells = render(&scene(&f.mesh), &camera(oblique_view()), &settings());
    let strands_change = mean_difference(&sorted, &shells);
    for order in [
        StrandOrder::Stochastic,
        StrandOrder::Depth,
        StrandOrder::Banded(4),
    ] {
        let image = render(&hybrid, &camera(oblique_view()), &with(order));
        let off = mean_difference(&image, &sorted);
        assert!(
            off < 0.5 * strands_change,
            "{order:?}: {off} levels from the sorted composite, the strands change it {strands_change}"
        );
    }
}

#[test]
fn bad_guard_hairs_and_settings_are_refused_by_name() {
    let f = fixture();
    let mut hybrid = scene(&f.mesh);
    let mut broken = f.strands.clone();
    broken.points[3][3] = f32::NAN;
    let e = hybrid.set_guard_hairs(&f.renderer, &broken).unwrap_err();
    assert!(
        matches!(&e, PeltError::InvalidParameter { name, .. } if name == "guard_hairs.points[3]"),
        "{e}"
    );
    assert_eq!(hybrid.guard_strand_count(), 0, "nothing set after a refusal");
    let other = Renderer::new(AdapterChoice::Cpu).unwrap();
    let e = hybrid.set_guard_hairs(&other, &f.strands).unwrap_err();
    assert!(e.to_string().contains("renderer"), "{e}");
    for bad in [
        RenderSettings {
            strand_pixels: f32::NAN,
            ..settings()
        },
        RenderSettings {
            strand_order: StrandOrder::Banded(0),
            ..settings()
        },
    ] {
        let e = f
            .renderer
            .render(&hybrid, &camera(oblique_view()), &Lighting::default(), &bad)
            .unwrap_err();
        assert!(e.to_string().contains("`strand_"), "{e}");
    }
}

#[test]
fn prt_lights_the_strands_with_the_hair_around_them() {
    let f = fixture();
    // The transfer of this scene's volume: a tile is 0.4 object units.
    let transfer = small_transfer(&f.volume, f64::from(FUR_DEPTH) / 0.4);
    let mut hybrid = scene(&f.mesh);
    hybrid.set_transfer(&f.renderer, &transfer).unwrap();
    let prt = Lighting {
        model: LightModel::Prt(Prt::default()),
        ..Lighting::default()
    };
    let render = |scene: &FurScene, settings: &RenderSettings| {
        f.renderer
            .render(scene, &camera(oblique_view()), &prt, settings)
            .unwrap()
    };
    let shells = render(&hybrid, &settings());
    hybrid.set_guard_hairs(&f.renderer, &f.strands).unwrap();
    let image = render(&hybrid, &settings());
    assert!(differing(&image, &shells, 8) > 0.02);
    // Lit by the same light as the shells around them: the strands' pixels are neither black
    // nor blown out next to the shells'.
    let mean = |img: &RgbaImage| {
        let lit: Vec<f64> = img
            .pixels
            .chunks_exact(4)
            .filter(|p| p[3] == 255)
            .map(|p| f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2]))
            .collect();
        lit.iter().sum::<f64>() / lit.len() as f64
    };
    let ratio = mean(&image) / mean(&shells);
    assert!(
        (0.7..1.6).contains(&ratio),
        "strands change the mean brightness {ratio}×"
    );
}

/// The strand LOD keeps a share of the thin strands and widens them by its inverse: the opacity
/// the strands add stays (the strands here are about 0.3 px wide).
#[test]
fn the_strand_lod_keeps_the_strands_coverage() {
    let f = fixture();
    let mut hybrid = scene(&f.mesh);
    hybrid.set_guard_hairs(&f.renderer, &f.strands).unwrap();
    let coverage = |s: &RenderSettings| -> f64 {
        let image = f
            .renderer
            .render_linear(&hybrid, &camera(oblique_view()), &Lighting::default(), s)
            .unwrap();
        image.pixels.chunks_exact(4).map(|p| f64::from(p[3])).sum()
    };
    let shells = coverage(&RenderSettings {
        guard_hairs: false,
        ..settings()
    });
    for order in [StrandOrder::Sorted, StrandOrder::Stochastic] {
        let with = |strand_pixels| RenderSettings {
            strand_order: order,
            strand_pixels,
            ..settings()
        };
        let kept = coverage(&with(1.0)) - shells;
        let all = coverage(&with(0.0)) - shells;
        assert!(all > 50.0, "{order:?}: the strands add {all}");
        assert!(
            (kept / all - 1.0).abs() < 0.1,
            "{order:?}: the strands add {kept} with the LOD, {all} without"
        );
    }
}
