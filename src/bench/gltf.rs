//! Bench cases of the object exports: `export.gltf.engine` and `export.gltf.geometry` (the GLB of a
//! 100k-triangle bumpy torus with lapped patches and 32 shells of 128², transfer of order 5), and
//! `export.texture_set` (every format of the same stack). The bake runs once, untimed; the
//! timings cover the whole export into memory (split, geometry, PNG encoding, GLB assembly).

use super::{BenchOptions, CaseResult, time_fallible};
use crate::error::Result;
use crate::export::{
    ExportInput, GltfMode, GltfOptions, TextureFormats, TransferTextures, encode_glb, write_texture_set,
};
use crate::hair::HairParams;
use crate::lapped::{PatchParams, build_patches};
use crate::mesh::{FurMesh, MeshInput, shapes};
use crate::prt::pack::{pack_f16, pack_u8};
use crate::prt::volume_input::VolumeInput;
use crate::prt::{TransferParams, bake_transfer};
use crate::volume::{VolumeParams, bake_volume};

/// Shells above the skin.
const SHELLS: usize = 32;

pub(super) fn export_gltf(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let (positions, triangles) = shapes::bumpy_torus(224, 224);
    let mesh = FurMesh::new(MeshInput::new(&positions, &triangles))?;
    let patches = build_patches(
        &mesh,
        &PatchParams {
            tile_size: 0.05,
            ..PatchParams::default()
        },
    )?;
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
    };
    let reps = if options.quick { 3 } else { 7 };
    let mut results = Vec::new();
    for mode in [GltfMode::Engine, GltfMode::Geometry] {
        let options = GltfOptions {
            mode,
            ..GltfOptions::default()
        };
        let bytes = encode_glb(&[object], &options)?.len();
        let timing = time_fallible(reps, || encode_glb(&[object], &options))?;
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
