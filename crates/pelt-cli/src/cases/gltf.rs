//! Bench cases of the object exports: `export.gltf.engine` and `export.gltf.geometry` (the GLB of a
//! 100k-triangle bumpy torus with lapped patches and 32 shells of 128², transfer of order 5),
//! `export.gltf.skinned.engine` and `.geometry` (a 30k-triangle torus bound to a ring of 24 bones,
//! six influences per vertex reduced to four, a 60-frame animation; the character of the issue's
//! goal), and `export.texture_set` (every format of the same stack). The bake runs once, untimed;
//! the timings cover the whole export into memory (split, geometry, weights, PNG encoding, GLB
//! assembly).

use super::{BenchOptions, CaseResult, time_fallible};
use pelt_core::error::Result;
use pelt_core::export::{
    Animation, ExportInput, GltfMode, GltfOptions, Skeleton, SkeletonNode, SkinBinding, TextureFormats,
    TransferTextures, Transform, encode_glb, write_texture_set,
};
use pelt_core::hair::HairParams;
use pelt_core::lapped::{PatchParams, build_patches};
use pelt_core::mesh::{FurMesh, MeshInput, shapes};
use pelt_core::prt::pack::{pack_f16, pack_u8};
use pelt_core::prt::volume_input::VolumeInput;
use pelt_core::prt::{TransferParams, bake_transfer};
use pelt_core::volume::{VolumeParams, bake_volume};

/// Shells above the skin.
const SHELLS: usize = 32;

/// A bumpy torus of `side × side` quads with lapped patches: its positions, triangles, mesh and
/// patches.
#[allow(clippy::type_complexity)]
fn patched_torus(side: usize) -> Result<(Vec<[f32; 3]>, Vec<[u32; 3]>, FurMesh, pelt_core::lapped::Patches)> {
    let (positions, triangles) = shapes::bumpy_torus(side, side);
    let mesh = FurMesh::new(MeshInput::new(&positions, &triangles))?;
    let patches = build_patches(
        &mesh,
        &PatchParams {
            tile_size: 0.05,
            ..PatchParams::default()
        },
    )?;
    Ok((positions, triangles, mesh, patches))
}

pub(super) fn export_gltf(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let (_, triangles, mesh, patches) = patched_torus(224)?;
    let volume = bake_volume(
        &HairParams::default(),
        &VolumeParams {
            layers: SHELLS + 1,
            trim: false,
            ..VolumeParams::default()
        },
        None,
    )?;
    let input = VolumeInput::new(&volume, 0.25);
    let transfer = bake_transfer(
        &input.transfer_volume(&volume),
        &TransferParams {
            order: 5,
            ..TransferParams::default()
        },
        None,
    )?;
    let (f16, u8) = (pack_f16(&transfer)?, pack_u8(&transfer)?);
    let object = ExportInput {
        name: "torus",
        mesh: &mesh,
        corner_uvs: &patches.uv,
        volume: &volume,
        transfer: Some(TransferTextures {
            order: transfer.order,
            f16: &f16,
            u8: &u8,
        }),
        fur_depth: 0.05,
        shells: Some(SHELLS),
        transform: Default::default(),
        skin: None,
        materials: None,
        animations: &[],
        guard_hairs: None,
    };
    let reps = if options.quick { 3 } else { 7 };
    let mut results = Vec::new();
    for mode in [GltfMode::Engine, GltfMode::Geometry] {
        let options = GltfOptions {
            mode,
            ..GltfOptions::default()
        };
        let bytes = encode_glb(&[object], &[], &options)?.len();
        let timing = time_fallible(reps, || encode_glb(&[object], &[], &options))?;
        let size = format!(
            "{} triangles, {SHELLS} shells of {}², transfer order 5: {:.1} MiB",
            triangles.len(),
            volume.resolution,
            bytes as f64 / 1048576.0
        );
        results.push(CaseResult::timed(
            &format!("export.gltf.{}", mode.name()),
            size,
            timing,
        ));
    }

    results.extend(skinned(&volume, object.transfer, reps)?);

    let dir = std::env::temp_dir().join(format!("pelt-bench-texture-set-{}", std::process::id()));
    let written = write_texture_set(&[object], &dir, TextureFormats::default())?;
    let bytes: u64 = written
        .objects
        .iter()
        .flat_map(|o| &o.files)
        .map(|f| f.bytes)
        .sum();
    let timing = time_fallible(reps, || {
        write_texture_set(&[object], &dir, TextureFormats::default())
    });
    // Remove the folder whatever the timing gave; a leftover temporary folder is harmless.
    let _ = std::fs::remove_dir_all(&dir);
    let size = format!(
        "{}² × {} layers + transfer order 5, PNG + EXR + KTX2: {} files, {:.1} MiB",
        volume.resolution,
        volume.layers,
        written.objects[0].files.len() + 1,
        bytes as f64 / 1048576.0
    );
    results.push(CaseResult::timed("export.texture_set", size, timing?));
    Ok(results)
}

/// Bones in the skinned character's ring, influences given per vertex, animation frames.
const BONES: usize = 24;
const INFLUENCES: usize = 6;
const FRAMES: usize = 60;

/// A ring of bones around the torus's axis, each turning about its own axis over the animation.
fn ring_skeleton() -> Skeleton {
    let angle = |b: usize| b as f32 * std::f32::consts::TAU / BONES as f32;
    let mut nodes = vec![SkeletonNode {
        name: "Armature".into(),
        parent: None,
        rest: Transform::IDENTITY,
    }];
    nodes.extend((0..BONES).map(|b| SkeletonNode {
        name: format!("bone.{b:02}"),
        parent: Some(0),
        rest: Transform {
            translation: glam::Vec3::new(angle(b).cos(), angle(b).sin(), 0.0),
            rotation: glam::Quat::from_rotation_z(angle(b)),
            scale: glam::Vec3::ONE,
        },
    }));
    let times: Vec<f32> = (0..FRAMES).map(|f| f as f32 / 30.0).collect();
    let poses = times
        .iter()
        .flat_map(|t| {
            nodes.iter().enumerate().map(move |(j, node)| {
                let mut pose = node.rest;
                pose.rotation *= glam::Quat::from_rotation_x(0.3 * (t * 4.0 + j as f32).sin());
                pose
            })
        })
        .collect();
    Skeleton {
        nodes,
        animations: vec![Animation {
            name: "Wave".into(),
            times,
            poses,
        }],
    }
}

/// `export.gltf.skinned.*`: a 30k-triangle torus, each vertex bound to its six nearest bones.
fn skinned(
    volume: &pelt_core::volume::HairVolume,
    transfer: Option<TransferTextures<'_>>,
    reps: usize,
) -> Result<Vec<CaseResult>> {
    let (positions, triangles, mesh, patches) = patched_torus(122)?;
    let skeleton = ring_skeleton();
    let mut joints = Vec::with_capacity(positions.len() * INFLUENCES);
    let mut weights = Vec::with_capacity(positions.len() * INFLUENCES);
    for p in &positions {
        let around =
            p[1].atan2(p[0]).rem_euclid(std::f32::consts::TAU) / std::f32::consts::TAU * BONES as f32;
        for k in 0..INFLUENCES {
            let bone = (around as usize + BONES + k - INFLUENCES / 2 + 1) % BONES;
            let distance = (around - (around.floor() + k as f32 - (INFLUENCES / 2 - 1) as f32)).abs();
            joints.push(1 + bone as u32);
            weights.push(1.0 / (1.0 + distance * distance));
        }
    }
    let object = ExportInput {
        name: "character",
        mesh: &mesh,
        corner_uvs: &patches.uv,
        volume,
        transfer,
        fur_depth: 0.05,
        shells: Some(SHELLS),
        transform: Transform::IDENTITY,
        skin: Some(SkinBinding {
            skeleton: 0,
            influences: INFLUENCES,
            joints: &joints,
            weights: &weights,
        }),
        materials: None,
        animations: &[],
        guard_hairs: None,
    };
    let skeletons = std::slice::from_ref(&skeleton);
    let mut results = Vec::new();
    for mode in [GltfMode::Engine, GltfMode::Geometry] {
        let options = GltfOptions {
            mode,
            ..GltfOptions::default()
        };
        let bytes = encode_glb(&[object], skeletons, &options)?.len();
        let timing = time_fallible(reps, || encode_glb(&[object], skeletons, &options))?;
        let size = format!(
            "{} triangles, {BONES} bones × {INFLUENCES} influences, {FRAMES} frames, {SHELLS} shells + fins: {:.1} MiB",
            triangles.len(),
            bytes as f64 / 1048576.0
        );
        results.push(CaseResult::timed(
            &format!("export.gltf.skinned.{}", mode.name()),
            size,
            timing,
        ));
    }
    Ok(results)
}
