//! `engine` mode: the base mesh with everything an engine-side shell shader needs, described by
//! the `PELT_shell_fur` extension (Lengyel et al. 2001, §2.3–§2.4 draw the shells in a vertex
//! shader; the PRT shell-fur paper, §2.4, lights them from the transfer textures), plus a few
//! alpha-tested shells for viewers without it.
//!
//! Vertex attributes: `TEXCOORD_0` and `TEXCOORD_1` the patch UVs (`PeltUV`; Pelt's mesh carries
//! no other UV set, so both hold it), `COLOR_0` the hair color, `_PELT_LENGTH` the length
//! multiplier, `_PELT_COMB` the comb vector, `_PELT_DPDU` / `_PELT_DPDV` the surface derivatives
//! that carry the tangent map to the surface. Images: the skin layer (the material's base color,
//! so plain viewers show the skin), the shell and tangent atlases, the fin texture, the 8-bit
//! transfer atlases and the fallback shells' layers, all ordinary glTF textures. The skin
//! primitive's `extensions.PELT_shell_fur` names them, the attributes, the stack and the fallback
//! primitives (`docs/export.md`, schema `docs/schema/PELT_shell_fur.schema.json`).

use gltf_json as json;
use json::material::AlphaMode;
use json::mesh::Semantic;
use serde::{Deserialize, Serialize};

use super::super::description::StackDescription;
use super::super::input::ExportInput;
use super::super::stack_png::{StackImage, encode_all};
use super::builder::{GlbBuilder, SamplerKind};
use super::guard::GuardHairRef;
use super::peak::{ObjectSizes, check_object};
use super::rig::skin_attributes;
use super::vertices::SplitVertices;
use super::{EngineAttributes, EngineTextures, GltfMode, Primitive, material, skin_primitives};
use crate::error::{PeltError, Result};
use crate::export::rig::VertexWeights;
use crate::mesh::shell_offset::shell_layer;

/// The extension's name, in `extensionsUsed` (not `extensionsRequired`: the fallback shows); it
/// lives with the reader, which skips the fallback shells by it.
pub use crate::mesh::gltf_read::FUR_EXTENSION as EXTENSION;
/// The extension's schema version.
pub const EXTENSION_VERSION: u32 = 1;
/// Alpha-tested shells for viewers without the extension: enough to read as fur, few enough to
/// stay light (each is a copy of the furred triangles' positions).
pub const FALLBACK_SHELLS: usize = 4;

/// `extensions.PELT_shell_fur` of a primitive: how to draw fur on it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShellFur {
    /// Schema version, 1.
    pub version: u32,
    /// The shell stack.
    pub stack: StackDescription,
    /// Vertex attribute names.
    pub attributes: EngineAttributes,
    /// Indices into the glTF `textures` array.
    pub textures: EngineTextures,
    /// Indices (in the same mesh) of the primitives that stand in for the fur where the
    /// extension is not supported; a runtime that draws the fur does not draw them.
    pub fallback: Vec<u32>,
    /// The guard hairs' `LINES` primitive, when the bake has guard hairs.
    #[serde(rename = "guardHairs", default, skip_serializing_if = "Option::is_none")]
    pub guard_hairs: Option<GuardHairRef>,
}

/// The layers the fallback shells show: `FALLBACK_SHELLS` evenly spaced (fewer on a short stack).
fn fallback_layers(input: &ExportInput<'_>) -> Vec<usize> {
    let layers = input.volume.layers;
    let shells = FALLBACK_SHELLS.min(layers.saturating_sub(1)).max(1);
    let mut picked: Vec<usize> = (1..=shells).map(|s| shell_layer(s, shells, layers)).collect();
    picked.dedup();
    picked
}

/// Adds `input` as one mesh: the skin with the engine attributes and the extension, then the
/// fallback shells; returns it.
pub(super) fn add_object(
    builder: &mut GlbBuilder,
    input: &ExportInput<'_>,
    weights: Option<&VertexWeights>,
) -> Result<json::Index<json::Mesh>> {
    let v = SplitVertices::new(input)?;
    v.check_derivatives()?;
    let sizes = ObjectSizes {
        split_vertices: v.positions.len(),
        skinned: weights.is_some(),
        fins: true,
    };
    check_object(input, GltfMode::Engine, &sizes, builder.buffer_len())?;
    let volume = input.volume;
    let shown = fallback_layers(input);
    let mut jobs = vec![
        StackImage::Layer(volume, 0),
        StackImage::ShellAtlas(volume),
        StackImage::TangentAtlas(volume),
        StackImage::Fin(volume),
    ];
    let transfer_count = input.transfer.map_or(0, |t| t.u8.textures);
    if let Some(transfer) = &input.transfer {
        jobs.extend((0..transfer.u8.textures).map(|t| StackImage::Transfer(transfer.u8, t)));
    }
    jobs.extend(shown.iter().map(|&l| StackImage::Layer(volume, l)));
    let pngs = encode_all(&jobs)?;
    let stem = input.file_stem();
    let mut textures = Vec::with_capacity(pngs.len());
    for (k, png) in pngs.into_iter().enumerate() {
        let (name, sampler) = match k {
            0 => (format!("{stem}_layer_000"), SamplerKind::Tile),
            1 => (format!("{stem}_shells_atlas"), SamplerKind::Clamp),
            2 => (format!("{stem}_tangents_atlas"), SamplerKind::Clamp),
            3 => (format!("{stem}_fin"), SamplerKind::Fin),
            t if t < 4 + transfer_count => (format!("{stem}_transfer_{}", t - 4), SamplerKind::Clamp),
            t => (
                format!("{stem}_layer_{:03}", shown[t - 4 - transfer_count]),
                SamplerKind::Tile,
            ),
        };
        let image = builder.png_image(&name, png);
        textures.push(builder.texture(image, sampler));
    }
    let index = |t: json::Index<json::Texture>| t.value() as u32;
    let engine = EngineTextures {
        skin: index(textures[0]),
        shells_atlas: index(textures[1]),
        tangents_atlas: index(textures[2]),
        fin: index(textures[3]),
        transfer: textures[4..4 + transfer_count]
            .iter()
            .map(|&t| index(t))
            .collect(),
    };

    let base = Primitive {
        position: builder.attribute(&v.positions, true),
        normal: builder.attribute(&v.normals, false),
        uv: builder.attribute(&v.split.uvs, false),
        color: builder.attribute(&v.colors, false),
    };
    let source = &v.split.source;
    let skinned: Vec<_> = weights
        .map(|w| skin_attributes(builder, w, source.len(), |i| source[i] as usize).to_vec())
        .unwrap_or_default();
    let lengths: Vec<[f32; 1]> = v.lengths.iter().map(|&l| [l]).collect();
    let extra = vec![
        (Semantic::TexCoords(1), base.uv),
        (
            Semantic::Extras("PELT_LENGTH".into()),
            builder.attribute(&lengths, false),
        ),
        (
            Semantic::Extras("PELT_COMB".into()),
            builder.attribute(&v.comb, false),
        ),
        (
            Semantic::Extras("PELT_DPDU".into()),
            builder.attribute(&v.split.dpdu, false),
        ),
        (
            Semantic::Extras("PELT_DPDV".into()),
            builder.attribute(&v.split.dpdv, false),
        ),
    ];
    let name = input.name;
    let skin = material(
        builder,
        format!("{name} skin"),
        textures[0],
        1,
        AlphaMode::Opaque,
        false,
    );
    let (skin, own) = skin_primitives(builder, input, &v, &base, skin, &extra, &skinned);
    let mut primitives = vec![skin];

    // Fallback shells, alpha-tested (no sorting needed), sharing the skin's other attributes.
    // The object's own materials come after them, outside the fallback list.
    let furred = v.furred_indices();
    if !furred.is_empty() {
        let furred = builder.indices(&furred);
        for ((&layer, positions), &texture) in shown
            .iter()
            .zip(v.lift(input, &shown)?)
            .zip(&textures[4 + transfer_count..])
        {
            let material = material(
                builder,
                format!("{name} fallback shell {layer}"),
                texture,
                0,
                AlphaMode::Mask,
                false,
            );
            let shell = Primitive {
                position: builder.attribute(&positions, true),
                ..base
            };
            primitives.push(shell.primitive(furred, material, &skinned));
        }
    }

    let fallback = (1..primitives.len() as u32).collect();
    primitives.extend(own);
    let guard_hairs = match super::guard::primitive_of(builder, input, weights, GltfMode::Engine)? {
        Some(lines) => {
            primitives.push(lines);
            Some(GuardHairRef {
                primitive: primitives.len() as u32 - 1,
                strands: input.guard_hairs.map_or(0, |g| g.spans.len() as u32),
                radius: super::guard::RADIUS_ATTRIBUTE.into(),
            })
        }
        None => None,
    };
    let fur = ShellFur {
        version: EXTENSION_VERSION,
        stack: StackDescription::new(input, v.split.uv_scale)?,
        attributes: EngineAttributes::names(),
        textures: engine,
        fallback,
        guard_hairs,
    };
    let value = serde_json::to_value(&fur).map_err(|e| PeltError::Internal(format!("{EXTENSION}: {e}")))?;
    let mut others = serde_json::Map::new();
    others.insert(EXTENSION.into(), value);
    primitives[0].extensions = Some(json::extensions::mesh::Primitive { others });
    if !builder.root.extensions_used.iter().any(|e| e == EXTENSION) {
        builder.root.extensions_used.push(EXTENSION.into());
    }
    Ok(builder.root.push(json::Mesh {
        extensions: None,
        extras: None,
        name: Some(name.into()),
        primitives,
        weights: None,
    }))
}
