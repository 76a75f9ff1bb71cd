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
        let uvs = build_patches(&mesh, &params).unwrap().uv;
        Object { name, mesh, uvs }
    }
}

struct Bake {
    volume: HairVolume,
    f16: PackedF16,
    u8: PackedU8,
    order: usize,
}

fn bake() -> Bake {
    let hair = HairParams {
        density: 800,
        ..HairParams::default()
    };
    let params = VolumeParams {
        resolution: 32,
        layers: 8,
        fin_size: [64, 16],
        ..VolumeParams::default()
    };
    let volume = bake_volume(&hair, &params, None).unwrap();
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
    }
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
        save_glb(&single, &scene[..1], &options).unwrap();
        let multi = dir.join(format!("scene_{}.glb", mode.name()));
        save_glb(&multi, &scene, &options).unwrap();

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
