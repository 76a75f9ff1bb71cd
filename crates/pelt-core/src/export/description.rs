//! The description of a baked shell stack that engines need to draw it, shared by the glTF
//! `PELT_shell_fur` extension, the `geometry` mode's `extras` and the `pelt.json` manifest
//! (schema in `docs/export.md`).
//!
//! It states the geometry of Lengyel et al. 2001, §2.3 (layer `i` at `i · layer_spacing` of
//! `fur_depth · length` along the combed normal; shells pick evenly spaced layers), the atlas
//! layout of the layers, the fin texture mapping of §2.2, and the transfer packing of the PRT
//! shell-fur paper, §2.3.

use serde::{Deserialize, Serialize};

use super::input::ExportInput;
use crate::error::Result;
use crate::mesh::shell_offset::shell_layer;
use crate::prt::pack::DECODE;
use crate::texture::atlas::AtlasLayout;

/// The offset formula, in the attribute names of the glTF engine export.
pub const OFFSET_FORMULA: &str = "position + layer * layer_spacing * fur_depth * _PELT_LENGTH * \
     (NORMAL + _PELT_COMB - NORMAL * dot(NORMAL, _PELT_COMB))";

/// Where the renderer's reference shaders live in Pelt's sources.
pub const REFERENCE_SHADERS: &str = "crates/pelt-render/src/light_model.wgsl, \
     crates/pelt-render/src/common.wgsl, crates/pelt-render/src/surface.wgsl, \
     crates/pelt-render/src/shells.wgsl, crates/pelt-render/src/fins.wgsl, \
     crates/pelt-render/src/lighting.wgsl";

/// A baked shell stack as engines read it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StackDescription {
    /// Layers `L` of the stack, layer 0 the opaque skin.
    pub layers: usize,
    /// Side of a layer's tile in texels.
    pub resolution: usize,
    /// Height between layers, as a share of the fur depth.
    pub layer_spacing: f64,
    /// Object units from the skin to height 1 at hair length 1.
    pub fur_depth: f64,
    /// Shells to draw above the skin.
    pub shells: usize,
    /// The layer each shell shows, inner to outer: `round(s · (L − 1) / shells)` for
    /// `s = 1..=shells`, halves up.
    pub shell_layers: Vec<usize>,
    /// How a vertex of the shell showing layer `layer` is placed.
    pub offset: String,
    /// Tile units per object unit of the mesh (the fins map edge length with it).
    pub uv_scale: f64,
    /// Where each layer lies in the atlas images.
    pub atlas: AtlasLayout,
    /// The fin texture.
    pub fin: FinDescription,
    /// The baked transfer, if any.
    pub transfer: Option<TransferDescription>,
    /// Color encoding of the shell and fin images.
    pub color: String,
    /// The renderer's shaders, the reference for engine-side shaders.
    pub reference_shaders: String,
}

/// The fin texture and how fins map onto it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FinDescription {
    /// Width in texels (along the edge).
    pub width: usize,
    /// Height in texels (row 0 the top of the fur).
    pub height: usize,
    /// How fin quads are textured.
    pub mapping: String,
}

/// The transfer textures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TransferDescription {
    /// SH order n.
    pub order: usize,
    /// Coefficients `n²`.
    pub coefficients: usize,
    /// RGBA textures per layer, `⌈n² / 4⌉`.
    pub textures: usize,
    /// Where coefficient `k` lives.
    pub layout: String,
    /// The SH convention.
    pub basis: String,
    /// How 8-bit textures decode.
    pub decode_u8: String,
    /// Scale per coefficient of the 8-bit textures.
    pub scale: Vec<f32>,
    /// Bias per coefficient of the 8-bit textures.
    pub bias: Vec<f32>,
}

impl StackDescription {
    /// The description of `input`'s stack; `uv_scale` comes from the seam split.
    ///
    /// # Errors
    /// As [`AtlasLayout::new`] (sizes were validated before, so none is expected).
    pub fn new(input: &ExportInput<'_>, uv_scale: f64) -> Result<Self> {
        let volume = input.volume;
        let shells = input.shell_count();
        let [width, height] = volume.fin_size;
        Ok(StackDescription {
            layers: volume.layers,
            resolution: volume.resolution,
            layer_spacing: volume.layer_spacing,
            fur_depth: input.fur_depth,
            shells,
            shell_layers: (1..=shells)
                .map(|s| shell_layer(s, shells, volume.layers))
                .collect(),
            offset: OFFSET_FORMULA.into(),
            uv_scale,
            atlas: AtlasLayout::new(volume.layers, volume.resolution)?,
            fin: FinDescription {
                width,
                height,
                mapping: "one quad per mesh edge standing on it along each end's growth \
                          direction up to fur_depth * length; u = u0 + distance along the edge \
                          * uv_scale with u0 random in [0, 1) per edge (the texture repeats along \
                          u); v = 0 at the top of the fur, 1 at the skin"
                    .into(),
            },
            transfer: input.transfer.map(|t| {
                let sidecar = &t.u8.sidecar;
                TransferDescription {
                    order: t.order,
                    coefficients: t.order * t.order,
                    textures: t.u8.textures,
                    layout: "coefficient k is in texture k / 4, channel k % 4 (RGBA); each \
                             texture holds the layers as the shell stack does"
                        .into(),
                    basis: sidecar.basis.clone(),
                    decode_u8: DECODE.into(),
                    scale: sidecar.scale.clone(),
                    bias: sidecar.bias.clone(),
                }
            }),
            color: "sRGB-encoded color, straight (not premultiplied) alpha".into(),
            reference_shaders: REFERENCE_SHADERS.into(),
        })
    }
}
