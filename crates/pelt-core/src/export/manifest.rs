//! `pelt.json`: the manifest of an exported folder, listing every file with what it holds (kind,
//! format, pixel format, size, layers, levels, color space, layout) next to each object's stack
//! description, so a pipeline can load the folder without knowing Pelt's naming. The schema is in
//! `docs/export.md`; fields come in a fixed order and nothing depends on the time, so the same bake gives the
//! same bytes.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::description::StackDescription;
use crate::error::{PeltError, Result};

/// File name of the manifest inside an exported folder.
pub const MANIFEST_NAME: &str = "pelt.json";

/// The manifest's `format` value.
pub const MANIFEST_FORMAT: &str = "pelt-asset";

/// An exported folder.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Always [`MANIFEST_FORMAT`].
    pub format: String,
    /// Schema version, 1.
    pub version: u32,
    /// `pelt <version>`.
    pub generator: String,
    /// One entry per object, in export order.
    pub objects: Vec<ManifestObject>,
    /// Files holding every object (the glTF exports).
    pub files: Vec<ManifestFile>,
}

/// One object's stack and files.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ManifestObject {
    /// The object's name.
    pub name: String,
    /// The shell stack.
    pub stack: StackDescription,
    /// The object's texture files.
    pub files: Vec<ManifestFile>,
}

/// One file of the folder.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ManifestFile {
    /// Path relative to the folder, `/`-separated.
    pub path: String,
    /// What it holds: `shell_layer`, `shell_atlas`, `shell_array`, `tangent_atlas`,
    /// `tangent_array`, `fin`, `density_atlas`, `transfer_atlas`, `transfer_array` or `gltf`.
    pub kind: String,
    /// Container: `png`, `exr`, `ktx2` or `glb`.
    pub format: String,
    /// Texel format (`RGBA8_SRGB`, `RGBA8_UNORM`, `RGBA16F`, `R32F`); absent for `glb`.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub pixel_format: Option<String>,
    /// `srgb` (color values sRGB-encoded) or `linear`; absent for `glb`.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub color_space: Option<String>,
    /// Image width in texels (of the base level).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub width: Option<usize>,
    /// Image height in texels.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub height: Option<usize>,
    /// Layers held (array layers, or atlas cells in use).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub layers: Option<usize>,
    /// The one stack layer a `shell_layer` holds.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub layer: Option<usize>,
    /// The transfer texture (coefficients `4t..4t + 3`) a transfer atlas holds.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub texture: Option<usize>,
    /// Mip levels, base included.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub levels: Option<usize>,
    /// `single`, `atlas` (see the stack's `atlas`), `array` (one array layer per stack layer) or
    /// `texture_major_array` (array layer `t · L + l` is transfer texture `t` of stack layer `l`).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub layout: Option<String>,
    /// `geometry` or `engine` for a `gltf` file.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub mode: Option<String>,
    /// The file's size.
    pub bytes: u64,
    /// What the file is for, in words.
    pub meaning: String,
}

impl Manifest {
    /// An empty manifest.
    pub fn new() -> Self {
        Manifest {
            format: MANIFEST_FORMAT.into(),
            version: 1,
            generator: format!("pelt {}", crate::VERSION),
            objects: Vec::new(),
            files: Vec::new(),
        }
    }

    /// The manifest as pretty-printed JSON with a final newline.
    ///
    /// # Errors
    /// [`PeltError::Internal`] if serialization fails (it cannot for these types).
    pub fn to_json(&self) -> Result<String> {
        serde_json::to_string_pretty(self)
            .map(|s| s + "\n")
            .map_err(|e| PeltError::Internal(format!("manifest JSON: {e}")))
    }

    /// Writes `pelt.json` into `folder`.
    ///
    /// # Errors
    /// [`PeltError::Io`] naming the file when it cannot be written.
    pub fn save(&self, folder: &Path) -> Result<()> {
        super::staging::write_file(&folder.join(MANIFEST_NAME), self.to_json()?.as_bytes())
    }

    /// Every file the manifest lists, `pelt.json` included, relative to its folder.
    pub fn paths(&self) -> Vec<String> {
        let objects = self.objects.iter().flat_map(|o| &o.files);
        objects
            .chain(&self.files)
            .map(|f| f.path.clone())
            .chain(std::iter::once(MANIFEST_NAME.to_string()))
            .collect()
    }

    /// Reads `pelt.json` from `folder`.
    ///
    /// # Errors
    /// [`PeltError::Io`] when it cannot be read; [`PeltError::InvalidParameter`] naming the file
    /// when it is not a Pelt manifest.
    pub fn load(folder: &Path) -> Result<Self> {
        let path = folder.join(MANIFEST_NAME);
        let text = std::fs::read_to_string(&path).map_err(|source| PeltError::Io {
            path: path.display().to_string(),
            source,
        })?;
        let manifest: Manifest = serde_json::from_str(&text).map_err(|e| {
            PeltError::parameter(path.display().to_string(), format!("not a Pelt manifest: {e}"))
        })?;
        if manifest.format != MANIFEST_FORMAT {
            return Err(PeltError::parameter(
                path.display().to_string(),
                format!("format is {:?}, expected {MANIFEST_FORMAT:?}", manifest.format),
            ));
        }
        Ok(manifest)
    }
}

impl Default for Manifest {
    fn default() -> Self {
        Self::new()
    }
}
