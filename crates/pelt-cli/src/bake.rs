//! `pelt bake MESH --out DIR`: bakes every object of a mesh file with the staged pipeline and
//! writes the texture set, one GLB per glTF mode and `pelt.json` (`pelt_core::export::write_asset`),
//! plus `bake.json`, the arguments of the bake, from which `pelt export` writes the folder again
//! and `pelt view` loads it.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use clap::Args;
use pelt_core::FurMesh;
use pelt_core::export::{
    AssetOptions, ExportInput, GltfMode, StagedFolder, TextureFormats, write_asset_files,
};
use pelt_core::mesh::obj::MeshData;
use pelt_core::pipeline::{BakeKeywords, BakeParams, FurAsset, Pipeline};
use pelt_core::presets::FurPreset;
use serde::{Deserialize, Serialize};

use crate::meshes::read_objects;

/// File in the output folder that records the bake's arguments.
pub const BAKE_RECORD: &str = "bake.json";

#[derive(Args, Clone, Serialize, Deserialize)]
pub struct BakeArgs {
    /// The mesh: .obj (one object) or .glb / .gltf (one object per node with a mesh).
    pub mesh: PathBuf,
    /// Folder to write into (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Comb vector for every vertex, object space, e.g. 0,0,-1 (hair falls along -z).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub comb: Option<[f32; 3]>,
    /// Fur preset (see `pelt presets`).
    #[arg(long, value_name = "NAME", default_value = "mink")]
    pub preset: String,
    /// glTF files to write: geometry, engine or both.
    #[arg(long, value_name = "MODE", default_value = "both")]
    pub mode: String,
    /// Texture containers, comma-separated: png, ktx2, exr.
    #[arg(long, value_name = "LIST", default_value = "png,ktx2,exr")]
    pub formats: String,
    /// Shell layers including the skin (overrides the default 16).
    #[arg(long)]
    pub layers: Option<usize>,
    /// Shell texture side in texels (overrides the default 128).
    #[arg(long)]
    pub resolution: Option<usize>,
    /// Fur height at length 1, object units (overrides the preset).
    #[arg(long)]
    pub fur_depth: Option<f64>,
    /// Object units per hair tile (overrides the preset).
    #[arg(long)]
    pub tile_size: Option<f64>,
    /// Skip the PRT transfer bake.
    #[arg(long)]
    pub no_transfer: bool,
    /// SH order of the transfer (default: picked by band selection).
    #[arg(long)]
    pub order: Option<usize>,
    /// Leave the fins out of the geometry glTF.
    #[arg(long)]
    pub no_fins: bool,
    /// Draw guard hairs as strands (glTF lines for engines, ribbons as geometry), a
    /// --guard-share of them, and bake the rest of the coat into the shells.
    #[arg(long)]
    #[serde(default)]
    pub guard_hairs: bool,
    /// With --guard-hairs, the share of the guard hairs drawn as strands, (0, 1]; the rest stay
    /// in the shells.
    #[arg(long, value_name = "SHARE")]
    #[serde(default)]
    pub guard_share: Option<f64>,
    /// Also bake the virtual planes' slices, N per axis, [0, 256] (0: none), for the raycast renderer
    /// (`pelt view`, key V).
    #[arg(long, value_name = "N")]
    #[serde(default)]
    pub planes: Option<usize>,
}

/// `x,y,z` as three finite floats.
fn parse_vec3(text: &str) -> Result<[f32; 3], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let values: Vec<f32> = parts
        .iter()
        .map(|p| p.parse::<f32>().ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(|| format!("{text:?} is not three numbers x,y,z"))?;
    <[f32; 3]>::try_from(values).map_err(|_| format!("{text:?} is not three numbers x,y,z"))
}

/// The glTF modes of `--mode`.
fn modes(text: &str) -> Result<Vec<GltfMode>, String> {
    match text {
        "both" => Ok(vec![GltfMode::Engine, GltfMode::Geometry]),
        other => GltfMode::parse(other)
            .map(|m| vec![m])
            .map_err(|_| format!("--mode must be geometry, engine or both, got {other:?}")),
    }
}

/// The pipeline's parameters for these arguments.
fn bake_params(args: &BakeArgs) -> Result<BakeParams, String> {
    let mut params = BakeParams::default();
    FurPreset::find(&args.preset)
        .map_err(|e| e.to_string())?
        .apply(&mut params);
    if let Some(layers) = args.layers {
        params.volume.layers = layers;
    }
    if let Some(resolution) = args.resolution {
        params.volume.resolution = resolution;
    }
    if let Some(tile) = args.tile_size {
        params.patches.tile_size = tile;
    }
    params.volume.guard_hairs = args.guard_hairs;
    if let Some(share) = args.guard_share {
        params.volume.guard_share = share;
    }
    // The bake's own switches read as `Pipeline.bake` reads its keywords.
    let keywords = BakeKeywords {
        fur_depth: args.fur_depth.or(params.fur_depth),
        transfer: !args.no_transfer,
        order: args.order,
        planes: args.planes.unwrap_or(0),
        ..BakeKeywords::default()
    };
    let params = keywords.apply(params);
    params.validate().map_err(|e| e.to_string())?;
    Ok(params)
}

pub fn run(args: BakeArgs) -> Result<(), String> {
    let formats = TextureFormats::parse(&args.formats).map_err(|e| e.to_string())?;
    let modes = modes(&args.mode)?;
    let assets = bake_objects(&args)?;

    let inputs: Vec<ExportInput<'_>> = assets
        .iter()
        .map(|(name, asset)| ExportInput::from_asset(name, asset))
        .collect();
    let options = AssetOptions {
        formats,
        modes,
        fins: !args.no_fins,
        glb_stem: stem(&args.mesh),
    };
    // The folder and bake.json move into place together, or nothing changes.
    let staged = StagedFolder::new(&args.out).map_err(|e| e.to_string())?;
    let manifest = write_asset_files(&inputs, staged.path(), &options).map_err(|e| e.to_string())?;
    record(&args, staged.path())?;
    let mut paths = manifest.paths();
    paths.push(BAKE_RECORD.into());
    staged.commit(&paths).map_err(|e| e.to_string())?;
    let files = manifest.objects.iter().map(|o| o.files.len()).sum::<usize>() + manifest.files.len();
    println!(
        "pelt: wrote {} objects, {files} files and {} into {}",
        manifest.objects.len(),
        pelt_core::export::MANIFEST_NAME,
        args.out.display()
    );
    Ok(())
}

/// Bakes every object of the mesh file with the arguments.
fn bake_objects(args: &BakeArgs) -> Result<Vec<(String, FurAsset)>, String> {
    let (params, objects) = prepare(args)?;
    objects
        .into_iter()
        .map(|(name, data)| {
            let asset = bake_object(args, &params, &name, &data)?;
            Ok((name, asset))
        })
        .collect()
}

/// The pipeline's parameters and the mesh file's objects for these arguments.
pub fn prepare(args: &BakeArgs) -> Result<(BakeParams, Vec<(String, MeshData)>), String> {
    Ok((bake_params(args)?, read_objects(&args.mesh)?))
}

/// Bakes one object, reporting each stage on stderr. The bake is deterministic, so this is also
/// how a baked folder is loaded again (`pelt view`).
pub fn bake_object(
    args: &BakeArgs,
    params: &BakeParams,
    name: &str,
    data: &MeshData,
) -> Result<FurAsset, String> {
    let comb = args.comb.map(|c| vec![c; data.positions.len()]);
    let input = match &comb {
        Some(comb) => data.input().with_comb(comb),
        None => data.input(),
    };
    let mesh = FurMesh::new(input).map_err(|e| format!("{name}: {e}"))?;
    let asset = Pipeline::new()
        .bake(Arc::new(mesh), params, None)
        .map_err(|e| format!("{name}: {e}"))?;
    for stage in &asset.report {
        eprintln!(
            "{name}: {} {:.2} s: {}",
            stage.stage, stage.seconds, stage.summary
        );
    }
    Ok(asset)
}

/// The arguments recorded in `dir`'s `bake.json`.
pub fn load_record(dir: &Path) -> Result<BakeArgs, String> {
    let path = dir.join(BAKE_RECORD);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: not a Pelt bake record: {e}", path.display()))
}

/// The mesh file's stem, naming the GLB files.
fn stem(path: &Path) -> String {
    path.file_stem()
        .map_or_else(|| "pelt".into(), |s| s.to_string_lossy().into_owned())
}

/// Writes the arguments into `bake.json` in the output folder, the mesh path made absolute so
/// `pelt export` finds it from anywhere.
fn record(args: &BakeArgs, folder: &Path) -> Result<(), String> {
    let mut recorded = args.clone();
    recorded.mesh = std::path::absolute(&args.mesh).map_err(|e| format!("{}: {e}", args.mesh.display()))?;
    let path = folder.join(BAKE_RECORD);
    let text = serde_json::to_string_pretty(&recorded).map_err(|e| e.to_string())?;
    std::fs::write(&path, text + "\n").map_err(|e| format!("{}: {e}", path.display()))
}
