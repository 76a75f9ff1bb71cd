//! Writes the glTF exports that `make check-gltf` hands to the Khronos glTF-Validator: Suzanne
//! and a multi-object scene (Suzanne, a torus with a bald band, a sphere), each in `geometry` and
//! `engine` mode, into `target/tmp/gltf-check/` (or `$PELT_GLTF_OUT`). The bakes are real (patches,
//! volume, transfer), small enough for a debug build. The test itself checks what needs no
//! validator: the files re-read with Pelt's glTF reader give back each object's mesh.

use std::path::PathBuf;

use pelt::export::{ExportInput, GltfMode, GltfOptions, TransferTextures, save_glb};
use pelt::hair::HairParams;
use pelt::lapped::{PatchParams, build_patches};
use pelt::mesh::gltf_read::read_gltf;
use pelt::mesh::shapes::{suzanne, torus, uv_sphere};
use pelt::prt::pack::{PackedF16, PackedU8, pack_f16, pack_u8};
use pelt::prt::volume_input::VolumeInput;
use pelt::prt::{TransferParams, bake_transfer};
use pelt::volume::{HairVolume, VolumeParams, bake_volume};
use pelt::{FurMesh, MeshInput};

/// Fur depth, object units (Suzanne is about 2.7 units wide).
const FUR_DEPTH: f64 = 0.12;

struct Object {
    name: &'static str,
    mesh: FurMesh,
    uvs: Vec<[[f32; 2]; 3]>,
    patches: pelt::lapped::Patches,
}

impl Object {
    /// Paints a color gradient, a comb toward −z and lengths (0 where `bald` says), and grows
    /// patches.
    fn new(
        name: &'static str,
        positions: &[[f32; 3]],
        triangles: &[[u32; 3]],
        bald: impl Fn([f32; 3]) -> bool,
    ) -> Self {
        let color: Vec<[f32; 4]> = positions
            .iter()
            .map(|p| [0.6 + 0.3 * p[0].tanh(), 0.45, 0.3 + 0.2 * p[2].tanh(), 1.0])
            .collect();
        let comb: Vec<[f32; 3]> = positions.iter().map(|_| [0.0, 0.0, -0.5]).collect();
        let length: Vec<f32> = positions
            .iter()
            .map(|&p| if bald(p) { 0.0 } else { 1.0 })
            .collect();
        let mesh = FurMesh::new(
            MeshInput::new(positions, triangles)
                .with_color(&color)
                .with_comb(&comb)
                .with_length(&length),
        )
        .unwrap();
        let params = PatchParams {
            tile_size: 0.5,
            ..PatchParams::default()
        };
        let patches = build_patches(&mesh, &params).unwrap();
        Object {
            name,
            mesh,
            uvs: patches.uv.clone(),
            patches,
        }
    }
}

struct Bake {
    volume: HairVolume,
    f16: PackedF16,
    u8: PackedU8,
    order: usize,
}

/// A small volume of `hair` (the undercoat alone with `guard_hairs`).
fn small_volume(hair: &HairParams, guard_hairs: bool) -> HairVolume {
    let params = VolumeParams {
        resolution: 32,
        layers: 8,
        fin_size: [64, 16],
        guard_hairs,
        ..VolumeParams::default()
    };
    bake_volume(hair, &params, None).unwrap()
}

fn bake() -> Bake {
    let hair = HairParams {
        density: 800,
        ..HairParams::default()
    };
    let volume = small_volume(&hair, false);
    let input = VolumeInput::new(&volume, 0.25);
    let order = 3;
    let transfer = bake_transfer(
        &input.transfer_volume(&volume),
        &TransferParams {
            order,
            ..TransferParams::default()
        },
        None,
    )
    .unwrap();
    Bake {
        f16: pack_f16(&transfer).unwrap(),
        u8: pack_u8(&transfer).unwrap(),
        volume,
        order,
    }
}

fn input<'a>(object: &'a Object, bake: &'a Bake) -> ExportInput<'a> {
    ExportInput {
        name: object.name,
        mesh: &object.mesh,
        corner_uvs: &object.uvs,
        volume: &bake.volume,
        transfer: Some(TransferTextures {
            order: bake.order,
            f16: &bake.f16,
            u8: &bake.u8,
        }),
        fur_depth: FUR_DEPTH,
        shells: None,
        transform: Default::default(),
        skin: None,
        materials: None,
        animations: &[],
        guard_hairs: None,
    }
}

/// The JSON chunk of a GLB file.
fn glb_json(path: &std::path::Path) -> serde_json::Value {
    let bytes = std::fs::read(path).unwrap();
    let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    serde_json::from_slice(&bytes[20..20 + length]).unwrap()
}

fn out_dir() -> PathBuf {
    let dir = std::env::var_os("PELT_GLTF_OUT").map_or_else(
        || PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("gltf-check"),
        PathBuf::from,
    );
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn suzanne_and_a_scene_export_in_both_modes_and_read_back() {
    let monkey = suzanne();
    let suzanne = Object::new("Suzanne", &monkey.positions, &monkey.triangles, |_| false);
    let (p, t) = torus(32, 16);
    // A bald band around the torus's inside.
    let ring = Object::new("Torus", &p, &t, |q| q[0] * q[0] + q[1] * q[1] < 0.5);
    let (p, t) = uv_sphere(24, 12);
    let ball = Object::new("Sphere", &p, &t, |_| false);
    let bake = bake();

    let dir = out_dir();
    let scene = [input(&suzanne, &bake), input(&ring, &bake), input(&ball, &bake)];
    for mode in [GltfMode::Geometry, GltfMode::Engine] {
        let options = GltfOptions {
            mode,
            ..GltfOptions::default()
        };
        let single = dir.join(format!("suzanne_{}.glb", mode.name()));
        save_glb(&single, &scene[..1], &[], &options).unwrap();
        let multi = dir.join(format!("scene_{}.glb", mode.name()));
        save_glb(&multi, &scene, &[], &options).unwrap();

        if mode == GltfMode::Engine {
            // The base meshes come back welded to the vertices they were exported from.
            let objects = read_gltf(&multi).unwrap();
            let names: Vec<&str> = objects.iter().map(|o| o.name.as_str()).collect();
            assert_eq!(names, ["Suzanne", "Torus", "Sphere"]);
            for (read, object) in objects.iter().zip([&suzanne, &ring, &ball]) {
                assert_eq!(read.mesh.triangles.len(), object.mesh.face_count());
                let mut got = read.mesh.positions.clone();
                let mut want = object.mesh.positions().to_vec();
                got.sort_by(|a, b| a.partial_cmp(b).unwrap());
                want.sort_by(|a, b| a.partial_cmp(b).unwrap());
                want.dedup();
                assert_eq!(got, want, "{}", object.name);
            }
        }
    }
}

/// Suzanne bound to a two-bone skeleton under a Y-up armature node, with an animation that nods
/// the upper bone, her eyes bald in a material of their own, and a torus placed beside her: the
/// skinned file the validator checks and the three.js runtime draws. The prop spins.
#[test]
fn a_skinned_character_and_a_placed_prop_export_in_both_modes() {
    use glam::{Quat, Vec3};
    use pelt::export::{Animation, Skeleton, SkeletonNode, SkinBinding, Transform};

    use pelt::export::{MaterialSlots, OwnMaterial};

    let monkey = suzanne();
    // Suzanne's eyes are her first 66 vertices (two pieces of their own).
    let eye_vertex = |v: u32| v < 66;
    let eyes: Vec<[f32; 3]> = monkey.positions[..66].to_vec();
    let character = Object::new("Character", &monkey.positions, &monkey.triangles, |p| {
        eyes.contains(&p)
    });
    let triangle_slot: Vec<u32> = character
        .mesh
        .triangles()
        .iter()
        .map(|t| u32::from(t.iter().all(|&v| eye_vertex(v))))
        .collect();
    let eye_triangles = triangle_slot.iter().filter(|&&s| s == 1).count();
    assert!(eye_triangles > 100);
    let slots = [
        None,
        Some(OwnMaterial {
            name: "Eyes".into(),
            base_color: [0.02, 0.02, 0.025, 1.0],
            metallic: 0.0,
            roughness: 0.2,
        }),
    ];
    let (p, t) = torus(32, 16);
    let prop = Object::new("Prop", &p, &t, |_| false);
    let bake = bake();
    let at = |translation: [f32; 3], rotation: Quat| Transform {
        translation: Vec3::from(translation),
        rotation,
        scale: Vec3::ONE,
    };
    let nodes = vec![
        SkeletonNode {
            name: "Armature".into(),
            parent: None,
            rest: at([0.0; 3], Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2)),
        },
        SkeletonNode {
            name: "Neck".into(),
            parent: Some(0),
            rest: at([0.0, 0.0, -1.0], Quat::IDENTITY),
        },
        SkeletonNode {
            name: "Head".into(),
            parent: Some(1),
            rest: at([0.0, 0.0, 1.0], Quat::IDENTITY),
        },
    ];
    let times = vec![0.0, 0.5, 1.0];
    let poses = times
        .iter()
        .flat_map(|&t: &f32| {
            let nod = at([0.0, 0.0, 1.0], Quat::from_rotation_x(0.6 * (t * 3.0).sin()));
            [nodes[0].rest, nodes[1].rest, nod]
        })
        .collect();
    let skeleton = Skeleton {
        nodes,
        animations: vec![Animation {
            name: "Nod".into(),
            times,
            poses,
        }],
    };
    // Blend from the neck (bottom) to the head (top) over Suzanne's height, plus a third, weak
    // influence on the armature node.
    let mut joints = Vec::new();
    let mut weights = Vec::new();
    for p in character.mesh.positions() {
        let head = ((p[2] + 1.0) / 2.0).clamp(0.0, 1.0);
        joints.extend([1u32, 2, 0]);
        weights.extend([1.0 - head, head, 0.05]);
    }
    let skinned = ExportInput {
        transform: at(
            [0.0, 0.0, 0.0],
            Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2),
        ),
        skin: Some(SkinBinding {
            skeleton: 0,
            influences: 3,
            joints: &joints,
            weights: &weights,
        }),
        materials: Some(MaterialSlots {
            slots: &slots,
            triangle_slot: &triangle_slot,
        }),
        ..input(&character, &bake)
    };
    // The prop spins about its own axis: an animation of its node.
    let spin = [Animation {
        name: "Spin".into(),
        times: vec![0.0, 0.5, 1.0],
        poses: [0.0f32, 1.5, 3.0]
            .map(|a| at([3.0, 0.0, 0.0], Quat::from_rotation_y(0.3 + a)))
            .to_vec(),
    }];
    let placed = ExportInput {
        transform: at([3.0, 0.0, 0.0], Quat::from_rotation_y(0.3)),
        animations: &spin,
        ..input(&prop, &bake)
    };
    let dir = out_dir();
    for mode in [GltfMode::Geometry, GltfMode::Engine] {
        let options = GltfOptions {
            mode,
            ..GltfOptions::default()
        };
        let path = dir.join(format!("character_{}.glb", mode.name()));
        let reports = save_glb(
            &path,
            &[skinned, placed],
            std::slice::from_ref(&skeleton),
            &options,
        )
        .unwrap();
        let report = reports[0].unwrap();
        assert_eq!(report.vertices, character.mesh.vertex_count());
        // Every vertex summed 1.05.
        assert_eq!(report.renormalized, report.vertices);
        assert_eq!(report.reduced, 0);
        assert!(reports[1].is_none());
        let names: Vec<String> = glb_json(&path)["animations"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| a["name"].as_str().unwrap().to_owned())
            .collect();
        assert_eq!(names, ["Nod", "Spin"]);

        // The eyes: one plain primitive of their own (no hair color, no fur), outside the fur
        // extension's fallback list; Pelt's skin keeps every other triangle.
        let document = glb_json(&path);
        let primitives = document["meshes"][0]["primitives"].as_array().unwrap();
        let count = |p: &serde_json::Value| {
            document["accessors"][p["indices"].as_u64().unwrap() as usize]["count"]
                .as_u64()
                .unwrap() as usize
        };
        let material =
            |p: &serde_json::Value| &document["materials"][p["material"].as_u64().unwrap() as usize];
        let eyes: Vec<_> = primitives
            .iter()
            .filter(|p| material(p)["name"] == "Eyes")
            .collect();
        assert_eq!(eyes.len(), 1, "{mode:?}");
        assert_eq!(count(eyes[0]), 3 * eye_triangles);
        assert!(eyes[0]["attributes"].get("COLOR_0").is_none());
        assert!(eyes[0]["attributes"].get("JOINTS_0").is_some());
        assert!(eyes[0].get("extensions").is_none());
        let pbr = &material(eyes[0])["pbrMetallicRoughness"];
        assert_eq!(pbr["roughnessFactor"].as_f64().unwrap() as f32, 0.2);
        assert_eq!(pbr["baseColorFactor"][0].as_f64().unwrap() as f32, 0.02);
        assert_eq!(
            count(&primitives[0]),
            3 * (character.mesh.face_count() - eye_triangles)
        );
        if mode == GltfMode::Engine {
            let fur = &primitives[0]["extensions"]["PELT_shell_fur"];
            let eyes_index = primitives
                .iter()
                .position(|p| material(p)["name"] == "Eyes")
                .unwrap();
            let fallback: Vec<usize> = serde_json::from_value(fur["fallback"].clone()).unwrap();
            assert_eq!(fallback.len(), 4);
            assert!(!fallback.contains(&eyes_index));
        }
    }
}

/// A 30k-triangle torus skinned to two bones, one of which swings it, with 32 shells + fins
/// (Kajiya–Kay, no transfer): the size the three.js runtime must draw in two fur calls.
#[test]
fn a_30k_triangle_skinned_character_with_32_shells_exports() {
    use glam::{Quat, Vec3};
    use pelt::export::{Animation, Skeleton, SkeletonNode, SkinBinding, Transform};
    use pelt::mesh::shapes::torus_uvs;

    let (around, across) = (128, 120);
    let (positions, triangles) = torus(around, across);
    assert_eq!(triangles.len(), 30_720);
    let comb: Vec<[f32; 3]> = positions.iter().map(|_| [0.0, 0.0, -0.5]).collect();
    let mesh = FurMesh::new(MeshInput::new(&positions, &triangles).with_comb(&comb)).unwrap();
    let uvs = torus_uvs(around, across, [24.0, 4.0]);
    let params = VolumeParams {
        resolution: 32,
        layers: 33,
        fin_size: [64, 16],
        ..VolumeParams::default()
    };
    let hair = HairParams {
        density: 800,
        ..HairParams::default()
    };
    let volume = bake_volume(&hair, &params, None).unwrap();
    let still = |rotation: Quat| Transform {
        translation: Vec3::ZERO,
        rotation,
        scale: Vec3::ONE,
    };
    let nodes = vec![
        SkeletonNode {
            name: "Rig".into(),
            parent: None,
            rest: still(Quat::IDENTITY),
        },
        SkeletonNode {
            name: "Left".into(),
            parent: Some(0),
            rest: still(Quat::IDENTITY),
        },
        SkeletonNode {
            name: "Right".into(),
            parent: Some(0),
            rest: still(Quat::IDENTITY),
        },
    ];
    let times = vec![0.0, 0.5, 1.0];
    let poses = times
        .iter()
        .flat_map(|&t: &f32| {
            [
                nodes[0].rest,
                nodes[1].rest,
                still(Quat::from_rotation_y(0.8 * t)),
            ]
        })
        .collect();
    let skeleton = Skeleton {
        nodes,
        animations: vec![Animation {
            name: "Swing".into(),
            times,
            poses,
        }],
    };
    // The right half (x > 0) on the swinging bone, blended over the middle.
    let mut joints = Vec::new();
    let mut weights = Vec::new();
    for p in mesh.positions() {
        let right = (0.5 + p[0] / 0.6).clamp(0.0, 1.0);
        joints.extend([1u32, 2]);
        weights.extend([1.0 - right, right]);
    }
    let input = ExportInput {
        name: "Big",
        mesh: &mesh,
        corner_uvs: &uvs,
        volume: &volume,
        transfer: None,
        fur_depth: 0.06,
        shells: None,
        transform: Transform::IDENTITY,
        skin: Some(SkinBinding {
            skeleton: 0,
            influences: 2,
            joints: &joints,
            weights: &weights,
        }),
        materials: None,
        animations: &[],
        guard_hairs: None,
    };
    let path = out_dir().join("big_character_engine.glb");
    let options = GltfOptions {
        mode: GltfMode::Engine,
        ..GltfOptions::default()
    };
    save_glb(&path, &[input], std::slice::from_ref(&skeleton), &options).unwrap();
    let document = glb_json(&path);
    let fur = &document["meshes"][0]["primitives"][0]["extensions"]["PELT_shell_fur"];
    assert_eq!(fur["stack"]["shells"], 32);
}

/// Suzanne with guard hairs (the overcoat as strands, the shells baked from the undercoat) in
/// both modes: lines described by the extension for engines, crossed ribbons as geometry; the
/// validator checks both files.
#[test]
fn guard_hairs_export_as_lines_for_engines_and_ribbons_as_geometry() {
    let monkey = suzanne();
    let object = Object::new("Guarded", &monkey.positions, &monkey.triangles, |_| false);
    let hair = HairParams {
        density: 800,
        guard_fraction: 0.1,
        ..HairParams::default()
    };
    let volume = small_volume(&hair, true);
    let guard = pelt::guard::guard_hairs(&object.mesh, &object.patches, &hair, FUR_DEPTH, 1.0).unwrap();
    assert!(guard.spans.len() > 100);
    let bake = bake();
    let input = ExportInput {
        volume: &volume,
        transfer: None,
        guard_hairs: Some(&guard),
        ..input(&object, &bake)
    };
    let dir = out_dir();
    for mode in [GltfMode::Engine, GltfMode::Geometry] {
        let path = dir.join(format!("guard_hairs_{}.glb", mode.name()));
        let options = GltfOptions {
            mode,
            ..GltfOptions::default()
        };
        save_glb(&path, &[input], &[], &options).unwrap();
        let json = glb_json(&path);
        let primitives = json["meshes"][0]["primitives"].as_array().unwrap();
        let accessor_count = |p: &serde_json::Value, attribute: &str| {
            let index = p["attributes"][attribute].as_u64().unwrap() as usize;
            json["accessors"][index]["count"].as_u64().unwrap() as usize
        };
        match mode {
            GltfMode::Engine => {
                let fur = &primitives[0]["extensions"]["PELT_shell_fur"];
                let reference = &fur["guardHairs"];
                assert_eq!(reference["strands"], guard.spans.len());
                assert_eq!(reference["radius"], "_PELT_RADIUS");
                let lines = &primitives[reference["primitive"].as_u64().unwrap() as usize];
                assert_eq!(lines["mode"], 1, "LINES");
                assert_eq!(accessor_count(lines, "POSITION"), guard.points.len());
                assert_eq!(accessor_count(lines, "_PELT_RADIUS"), guard.points.len());
                // The root's surface normal per point, which lights the runtime's ribbons (the
                // validator checks that each is unit length).
                assert_eq!(accessor_count(lines, "NORMAL"), guard.points.len());
                let segments = guard.points.len() - guard.spans.len();
                let indices = lines["indices"].as_u64().unwrap() as usize;
                assert_eq!(json["accessors"][indices]["count"], 2 * segments);
            }
            GltfMode::Geometry => {
                let ribbons = primitives.last().unwrap();
                assert_eq!(ribbons["mode"].as_u64().unwrap_or(4), 4, "TRIANGLES");
                assert_eq!(accessor_count(ribbons, "POSITION"), 4 * guard.points.len());
                assert!(ribbons["attributes"]["COLOR_0"].is_u64());
            }
        }
    }
}
