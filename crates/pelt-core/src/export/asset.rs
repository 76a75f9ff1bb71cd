//! A whole exported folder: the texture set of every object, one GLB per glTF mode holding every
//! object, and the `pelt.json` manifest listing all of it (what `pelt bake` and `pelt export`
//! write).

use std::path::Path;

use super::gltf::{GltfMode, GltfOptions, encode_glb};
use super::input::{ExportInput, file_stem};
use super::manifest::{Manifest, ManifestFile};
use super::texture_set::{TextureFormats, texture_set};
use crate::error::{PeltError, Result};
use crate::pipeline::FurAsset;

/// What [`write_asset`] writes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AssetOptions {
    /// Texture containers.
    pub formats: TextureFormats,
    /// One GLB per mode, in this order (none: textures only).
    pub modes: Vec<GltfMode>,
    /// `geometry` mode: include the fins.
    pub fins: bool,
    /// Stem of the GLB files: `<stem>_<mode>.glb`.
    pub glb_stem: String,
}

impl Default for AssetOptions {
    fn default() -> Self {
        AssetOptions {
            formats: TextureFormats::default(),
            modes: vec![GltfMode::Engine, GltfMode::Geometry],
            fins: true,
            glb_stem: "pelt".into(),
        }
    }
}

impl<'a> ExportInput<'a> {
    /// The export input of a pipeline bake: its mesh, patch UVs, volume, transfer (when baked),
    /// fur depth and guard hairs (when baked), with every layer above the skin as a shell.
    pub fn from_asset(name: &'a str, asset: &'a FurAsset) -> Self {
        ExportInput {
            name,
            mesh: &asset.mesh,
            corner_uvs: &asset.patches.uv,
            volume: &asset.volume,
            transfer: asset.transfer.as_deref().map(|t| super::TransferTextures {
                order: t.transfer.order,
                f16: &t.packed_f16,
                u8: &t.packed_u8,
            }),
            fur_depth: asset.params.fur_depth(),
            shells: None,
            transform: Default::default(),
            skin: None,
            materials: None,
            animations: &[],
            guard_hairs: asset.guard_hairs.as_deref(),
        }
    }
}

/// Writes the texture set, the GLBs and `pelt.json` of `objects` into `folder`; returns the
/// manifest. The files are written beside `folder` and moved in when all are written
/// ([`super::StagedFolder`]): a failure leaves `folder` as it was.
///
/// # Errors
/// As [`super::write_texture_set`] and [`encode_glb`]; [`PeltError::InvalidParameter`] naming
/// `glb_stem` when it is empty.
pub fn write_asset(objects: &[ExportInput<'_>], folder: &Path, options: &AssetOptions) -> Result<Manifest> {
    let staged = super::StagedFolder::new(folder)?;
    let manifest = write_asset_files(objects, staged.path(), options)?;
    staged.commit(&manifest.paths())?;
    Ok(manifest)
}

/// [`write_asset`] straight into `folder`, for callers that stage the folder themselves to add
/// files of their own (`pelt bake` adds `bake.json`).
///
/// # Errors
/// As [`write_asset`].
pub fn write_asset_files(
    objects: &[ExportInput<'_>],
    folder: &Path,
    options: &AssetOptions,
) -> Result<Manifest> {
    let stem = file_stem(&options.glb_stem);
    if stem.is_empty() {
        return Err(PeltError::parameter("glb_stem", "must not be empty"));
    }
    let mut manifest = texture_set(objects, folder, options.formats)?;
    for &mode in &options.modes {
        let glb = encode_glb(
            objects,
            &[],
            &GltfOptions {
                mode,
                fins: options.fins,
            },
        )?;
        let name = format!("{stem}_{}.glb", mode.name());
        let path = folder.join(&name);
        std::fs::write(&path, &glb).map_err(|source| PeltError::Io {
            path: path.display().to_string(),
            source,
        })?;
        manifest.files.push(ManifestFile {
            path: name,
            kind: "gltf".into(),
            format: "glb".into(),
            pixel_format: None,
            color_space: None,
            width: None,
            height: None,
            layers: None,
            layer: None,
            texture: None,
            levels: None,
            layout: None,
            mode: Some(mode.name().into()),
            bytes: glb.len() as u64,
            meaning: match mode {
                GltfMode::Geometry => "every object with its shells and fins as meshes (alpha-blended \
                                       materials): shows the fur in any glTF viewer"
                    .into(),
                GltfMode::Engine => "every object's base mesh with Pelt's attributes, its fur described \
                                     by the PELT_shell_fur extension (atlases, stack) for engine \
                                     shaders, and alpha-tested fallback shells for other viewers"
                    .into(),
            },
        });
    }
    manifest.save(folder)?;
    Ok(manifest)
}
