//! `engine` mode: the base mesh only, with everything an engine-side shell shader needs (Lengyel
//! et al. 2001, §2.3–§2.4 draw the shells in a vertex shader; the PRT shell-fur paper, §2.4,
//! lights them from the transfer textures).
//!
//! Vertex attributes: `TEXCOORD_0` and `TEXCOORD_1` the patch UVs (`PeltUV`; Pelt's mesh carries
//! no other UV set, so both hold it), `COLOR_0` the hair color, `_PELT_LENGTH` the length
//! multiplier, `_PELT_COMB` the comb vector, `_PELT_DPDU` / `_PELT_DPDV` the surface derivatives
//! that carry the tangent map to the surface. Images: the skin layer (the material's base color,
//! so plain viewers show the skin), the shell and tangent atlases, the fin texture and the 8-bit
//! transfer atlases. The mesh's `extras.pelt` describes the stack (`docs/export.md`).

use gltf_json as json;
use json::mesh::Semantic;

use super::super::description::StackDescription;
use super::super::input::ExportInput;
use super::super::stack_png::{StackImage, encode_all};
use super::builder::{GlbBuilder, SamplerKind};
use super::rig::skin_attributes;
use super::vertices::SplitVertices;
use super::{EngineTextures, Primitive, material, pelt_extras};
use crate::error::Result;
use crate::export::rig::VertexWeights;

/// Adds `input` as one mesh with the engine attributes, images and extras, and returns it.
pub(super) fn add_object(
    builder: &mut GlbBuilder,
    input: &ExportInput<'_>,
    weights: Option<&VertexWeights>,
) -> Result<json::Index<json::Mesh>> {
    let v = SplitVertices::new(input)?;
    v.check_derivatives()?;
    let volume = input.volume;
    let mut jobs = vec![
        StackImage::Layer(volume, 0),
        StackImage::ShellAtlas(volume),
        StackImage::TangentAtlas(volume),
        StackImage::Fin(volume),
    ];
    if let Some(transfer) = &input.transfer {
        jobs.extend((0..transfer.u8.textures).map(|t| StackImage::Transfer(transfer.u8, t)));
    }
    let pngs = encode_all(&jobs)?;
    let stem = input.file_stem();
    let mut textures = Vec::with_capacity(pngs.len());
    for (k, png) in pngs.into_iter().enumerate() {
        let (name, sampler) = match k {
            0 => (format!("{stem}_layer_000"), SamplerKind::Tile),
            1 => (format!("{stem}_shells_atlas"), SamplerKind::Clamp),
            2 => (format!("{stem}_tangents_atlas"), SamplerKind::Clamp),
            3 => (format!("{stem}_fin"), SamplerKind::Fin),
            t => (format!("{stem}_transfer_{}", t - 4), SamplerKind::Clamp),
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
        transfer: textures[4..].iter().map(|&t| index(t)).collect(),
    };

    let base = Primitive {
        position: builder.attribute(&v.positions, true),
        normal: builder.attribute(&v.normals, false),
        uv: builder.attribute(&v.split.uvs, false),
        color: builder.attribute(&v.colors, false),
    };
    let lengths: Vec<[f32; 1]> = v.lengths.iter().map(|&l| [l]).collect();
    let mut extra = vec![
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
    if let Some(weights) = weights {
        let source = &v.split.source;
        extra.extend(skin_attributes(builder, weights, source.len(), |i| {
            source[i] as usize
        }));
    }
    let skin = material(
        builder,
        format!("{} skin", input.name),
        textures[0],
        1,
        false,
        false,
    );
    let indices = builder.indices(&v.split.indices);
    let description = StackDescription::new(input, v.split.uv_scale)?;
    Ok(builder.root.push(json::Mesh {
        extensions: None,
        extras: pelt_extras("engine", &description, Some(engine))?,
        name: Some(input.name.into()),
        primitives: vec![base.primitive(indices, skin, &extra)],
        weights: None,
    }))
}
