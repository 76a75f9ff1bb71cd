//! A furred scene in a pose (`FurScene::deform`) on the CPU adapter: checked against the rest
//! scene seen through the inverse motion (a rigid pose), against a scene built from the posed
//! mesh (a bend), and against itself before a pose (poses do not accumulate, bad poses change
//! nothing). The test fails (never skips) when no CPU adapter exists.
#![cfg(feature = "render")]

mod common;

use std::sync::OnceLock;

use glam::{DMat4, Mat3, Vec3};
use pelt::render::{Camera, FurScene, Lighting, RenderSettings, RgbaImage};
use pelt::{FurMesh, MeshInput, PeltError};

use common::torus::{FurredTorus, covered, differing, oblique_view, perspective_camera};

const SIZE: u32 = 128;
const FUR_DEPTH: f32 = 0.08;

fn fixture() -> &'static FurredTorus {
    static FIXTURE: OnceLock<FurredTorus> = OnceLock::new();
    FIXTURE.get_or_init(|| FurredTorus::new(32, 16, [6.0, 2.0], FUR_DEPTH))
}

fn settings() -> RenderSettings {
    RenderSettings {
        // The full mesh: a scene built from a posed mesh simplifies it otherwise.
        mesh_error: 0.0,
        ..RenderSettings::default()
    }
}

/// A perspective camera (60°) whose view matrix is `view` (object to eye, row-major).
fn camera(view: DMat4) -> Camera {
    perspective_camera(view, SIZE)
}

fn render(scene: &FurScene, camera: &Camera, lighting: &Lighting) -> RgbaImage {
    render_with(scene, camera, lighting, &settings())
}

fn render_with(
    scene: &FurScene,
    camera: &Camera,
    lighting: &Lighting,
    settings: &RenderSettings,
) -> RgbaImage {
    fixture()
        .renderer
        .render(scene, camera, lighting, settings)
        .unwrap()
}

/// The torus with a comb along its ring (a shear of 0.6), so that the comb's turn is seen.
fn combed_torus() -> FurMesh {
    let mesh = &fixture().mesh;
    let comb: Vec<[f32; 3]> = mesh
        .positions()
        .iter()
        .map(|p| (0.6 * Vec3::new(-p[1], p[0], 0.0).normalize()).to_array())
        .collect();
    FurMesh::new(MeshInput::new(mesh.positions(), mesh.triangles()).with_comb(&comb)).unwrap()
}

fn moved(positions: &[[f32; 3]], motion: impl Fn(Vec3) -> Vec3) -> Vec<[f32; 3]> {
    positions
        .iter()
        .map(|&p| motion(Vec3::from(p)).to_array())
        .collect()
}

#[test]
fn a_rigid_pose_draws_the_rest_seen_through_the_inverse_motion() {
    let f = fixture();
    let mesh = combed_torus();
    let rest = f.scene_of(&mesh);
    let mut posed = f.scene_of(&mesh);
    let turn = Mat3::from_axis_angle(Vec3::new(1.0, 2.0, 0.5).normalize(), 0.7);
    let shift = Vec3::new(0.3, -0.2, 0.1);
    let positions = moved(mesh.positions(), |p| turn * p + shift);
    let normals = moved(mesh.normals(), |n| turn * n);
    posed.deform(&positions, Some(&normals)).unwrap();

    // The eye moves with the mesh and the light turns with it: the same picture.
    let motion = DMat4::from_translation(shift.as_dvec3()) * DMat4::from_mat3(turn.as_dmat3());
    let light = Lighting::default();
    let turned_light = Lighting {
        direction: (turn * Vec3::from(light.direction)).to_array(),
        ..light.clone()
    };
    let expected = render(&rest, &camera(oblique_view()), &light);
    let got = render(&posed, &camera(oblique_view() * motion.inverse()), &turned_light);
    // Rasterization of the moved triangles may round differently at an edge (none do here).
    let off = differing(&expected, &got, 4);
    assert!(off < 0.002, "{:.2}% of the pixels differ", 100.0 * off);
    assert!(covered(&got) > 2000);

    // Seen from the rest camera, the pose has moved: the check above can fail.
    let unmoved = render(&posed, &camera(oblique_view()), &turned_light);
    assert!(differing(&expected, &unmoved, 12) > 0.2);
}

/// A bend and a stretch: every vertex turned about the torus axis by an angle that grows with
/// its height, and pushed outward.
fn bend(p: Vec3) -> Vec3 {
    let turn = Mat3::from_rotation_z(1.2 * p.z);
    turn * Vec3::new(p.x * (1.0 + 0.25 * p.z), p.y, 1.3 * p.z)
}

#[test]
fn a_pose_draws_what_a_scene_of_the_posed_mesh_draws() {
    let f = fixture();
    let mut posed = f.scene();
    let positions = moved(f.mesh.positions(), bend);
    posed.deform(&positions, None).unwrap();
    let bent = FurMesh::new(MeshInput::new(&positions, f.mesh.triangles())).unwrap();
    let built = f.scene_of(&bent);
    let camera = camera(oblique_view());
    let light = Lighting::default();
    // Without fins: a posed fin keeps the texture interval of its rest edge (its texture
    // stretches with the edge, as the shells' does with the skin), while a scene built from the
    // bent mesh measures the edges anew. The rigid pose above covers the fins.
    let no_fins = RenderSettings {
        fins: false,
        ..settings()
    };
    let expected = render_with(&built, &camera, &light, &no_fins);
    let got = render_with(&posed, &camera, &light, &no_fins);
    assert_eq!(differing(&expected, &got, 2), 0.0);
    assert!(differing(&expected, &render_with(&f.scene(), &camera, &light, &no_fins), 12) > 0.05);
}

#[test]
fn poses_start_from_the_rest_and_bad_poses_change_nothing() {
    let f = fixture();
    let mut scene = f.scene();
    let camera = camera(oblique_view());
    let light = Lighting::default();
    let rest = render(&scene, &camera, &light);
    let before = scene.uploads();

    scene.deform(&moved(f.mesh.positions(), bend), None).unwrap();
    let bent = render(&scene, &camera, &light);
    assert_ne!(bent.pixels, rest.pixels);
    let after = scene.uploads();
    // The skin's vertices alone: the shells and fins are drawn from them.
    assert_eq!(after.pose_bytes, 76 * scene.surface_vertex_count() as u64);
    assert_eq!(
        (
            after.texture_bytes,
            after.geometry_bytes,
            after.attribute_bytes,
            after.transfer_bytes
        ),
        (
            before.texture_bytes,
            before.geometry_bytes,
            before.attribute_bytes,
            before.transfer_bytes
        )
    );

    let name = |e: PeltError| match e {
        PeltError::InvalidMesh(m) => m.to_string(),
        other => panic!("expected InvalidMesh, got {other:?}"),
    };
    let positions = f.mesh.positions();
    let short = name(scene.deform(&positions[1..], None).unwrap_err());
    assert!(short.contains("positions"), "{short}");
    let mut nan = positions.to_vec();
    nan[7][1] = f32::NAN;
    let message = name(scene.deform(&nan, None).unwrap_err());
    assert!(
        message.contains("positions") && message.contains('7'),
        "{message}"
    );
    let mut zero = f.mesh.normals().to_vec();
    zero[3] = [0.0; 3];
    let message = name(scene.deform(positions, Some(&zero)).unwrap_err());
    assert!(message.contains("normal") && message.contains('3'), "{message}");
    assert_eq!(render(&scene, &camera, &light).pixels, bent.pixels);

    // Back at the rest positions: the rest's very bytes.
    scene.deform(positions, None).unwrap();
    assert_eq!(render(&scene, &camera, &light).pixels, rest.pixels);
}

#[test]
fn a_new_comb_draws_what_a_scene_built_with_it_draws_in_any_pose() {
    let f = fixture();
    let combed = combed_torus();
    let comb = combed.comb().unwrap().to_vec();
    let built = f.scene_of(&combed);
    let mut updated = f.scene();
    let before = f.scene().uploads();
    updated.update_comb(&comb).unwrap();
    assert_eq!(
        updated.uploads().geometry_bytes,
        before.geometry_bytes,
        "no geometry re-sent"
    );
    let camera = camera(oblique_view());
    let light = Lighting::default();
    let expected = render(&built, &camera, &light);
    // The comb rebuilt from its frame components rounds in the last bits.
    assert!(differing(&expected, &render(&updated, &camera, &light), 2) < 0.001);
    assert!(
        differing(&expected, &render(&f.scene(), &camera, &light), 12) > 0.02,
        "the comb shows"
    );

    // In a pose: combing after the pose and before it draw the same.
    let positions = moved(f.mesh.positions(), bend);
    let mut combed_then_posed = f.scene();
    combed_then_posed.update_comb(&comb).unwrap();
    combed_then_posed.deform(&positions, None).unwrap();
    let mut posed_then_combed = f.scene();
    posed_then_combed.deform(&positions, None).unwrap();
    posed_then_combed.update_comb(&comb).unwrap();
    let a = render(&combed_then_posed, &camera, &light);
    assert!(differing(&a, &render(&posed_then_combed, &camera, &light), 2) < 0.001);

    // A bad comb is named and changes nothing.
    let err = updated.update_comb(&comb[1..]).unwrap_err();
    assert!(
        matches!(&err, PeltError::InvalidParameter { name, .. } if name == "comb"),
        "{err}"
    );
    let mut nan = comb.clone();
    nan[5][1] = f32::NAN;
    let err = updated.update_comb(&nan).unwrap_err();
    assert!(
        matches!(&err, PeltError::InvalidParameter { name, .. } if name == "comb[5]"),
        "{err}"
    );
    assert!(differing(&expected, &render(&updated, &camera, &light), 2) < 0.001);
}
