//! `geometry` mode: the shells and fins baked into real meshes, so any glTF viewer shows the fur
//! without custom shaders (Lengyel et al. 2001, §2.3, with the offsets of §3 applied on the CPU).
//!
//! One glTF mesh per object with these primitives: the skin (layer 0, opaque), the object's own
//! materials on its bald faces (plain, one primitive each), one primitive per
//! shell (the layer it shows as an alpha-blended base color texture, vertices lifted by
//! `layer · spacing · fur_depth · length` along the combed normal), and the fins (one quad per
//! edge, double-sided, alpha-blended). The shells share the skin's normals, UVs and colors and
//! one index list of the furred triangles; only their positions differ. Vertex colors multiply
//! the textures as the renderer's hair color does. The renderer's view-dependent fin fade has no
//! glTF equivalent, so every fin shows.

use gltf_json as json;
use json::material::AlphaMode;

use super::super::description::StackDescription;
use super::super::input::ExportInput;
use super::super::stack_png::{StackImage, encode_all};
use super::builder::{GlbBuilder, SamplerKind};
use super::peak::{ObjectSizes, check_object};
use super::rig::skin_attributes;
use super::vertices::{SplitVertices, check_lifted};
use super::{GltfMode, Primitive, material, pelt_extras, skin_primitives};
use crate::error::Result;
use crate::export::rig::VertexWeights;
use crate::mesh::shell_offset::{lifted, shell_layer};
use crate::mesh::{fin_quads, quad_triangles};

/// Adds `input` as one mesh (skin, shells, fins) and returns it.
pub(super) fn add_object(
    builder: &mut GlbBuilder,
    input: &ExportInput<'_>,
    fins: bool,
    weights: Option<&VertexWeights>,
) -> Result<json::Index<json::Mesh>> {
    let v = SplitVertices::new(input)?;
    let sizes = ObjectSizes {
        split_vertices: v.positions.len(),
        skinned: weights.is_some(),
        fins,
    };
    check_object(input, GltfMode::Geometry, &sizes, builder.buffer_len())?;
    let volume = input.volume;
    let shells = input.shell_count();
    let layers: Vec<usize> = (1..=shells)
        .map(|s| shell_layer(s, shells, volume.layers))
        .collect();

    // The layer images each primitive samples: the skin's and every distinct shell layer's.
    let mut wanted: Vec<usize> = std::iter::once(0).chain(layers.iter().copied()).collect();
    wanted.sort_unstable();
    wanted.dedup();
    let mut jobs: Vec<StackImage<'_>> = wanted.iter().map(|&l| StackImage::Layer(volume, l)).collect();
    jobs.push(StackImage::Fin(volume));
    let mut pngs = encode_all(&jobs)?;
    let fin_png = pngs.pop().unwrap_or_default();
    let stem = input.file_stem();
    let mut layer_texture = vec![None; volume.layers];
    for (&l, png) in wanted.iter().zip(pngs) {
        let image = builder.png_image(&format!("{stem}_layer_{l:03}"), png);
        layer_texture[l] = Some(builder.texture(image, SamplerKind::Tile));
    }
    let texture_of = |l: usize| layer_texture[l].unwrap_or(json::Index::new(0));

    let shared = Primitive {
        position: builder.attribute(&v.positions, true),
        normal: builder.attribute(&v.normals, false),
        uv: builder.attribute(&v.split.uvs, false),
        color: builder.attribute(&v.colors, false),
    };
    let name = input.name;
    // The shells share the skin's joints and weights: a lifted vertex moves with its root.
    let source = &v.split.source;
    let skinned: Vec<_> = weights
        .map(|w| skin_attributes(builder, w, source.len(), |i| source[i] as usize).to_vec())
        .unwrap_or_default();
    let skin_material = material(
        builder,
        format!("{name} skin"),
        texture_of(0),
        0,
        AlphaMode::Opaque,
        false,
    );
    let (skin, own) = skin_primitives(builder, input, &v, &shared, skin_material, &[], &skinned);
    let mut primitives = vec![skin];
    primitives.extend(own);

    let furred = v.furred_indices();
    if !furred.is_empty() {
        let furred = builder.indices(&furred);
        let lifted_layers = v.lift(input, &layers)?;
        let mut shell_material = vec![None; volume.layers];
        for (&layer, positions) in layers.iter().zip(&lifted_layers) {
            let material = *shell_material[layer].get_or_insert_with(|| {
                material(
                    builder,
                    format!("{name} shell {layer}"),
                    texture_of(layer),
                    0,
                    AlphaMode::Blend,
                    false,
                )
            });
            let shell = Primitive {
                position: builder.attribute(positions, true),
                ..shared
            };
            primitives.push(shell.primitive(furred, material, &skinned));
        }
    }

    if fins {
        let fin = fin_primitive(builder, input, &v, fin_png, weights)?;
        primitives.extend(fin);
    }
    primitives.extend(super::guard::primitive_of(
        builder,
        input,
        weights,
        GltfMode::Geometry,
    )?);

    let description = StackDescription::new(input, v.split.uv_scale)?;
    Ok(builder.root.push(json::Mesh {
        extensions: None,
        extras: pelt_extras("geometry", &description)?,
        name: Some(name.into()),
        primitives,
        weights: None,
    }))
}

/// The fins as one double-sided primitive: per fin four vertices, the bottom pair on the edge
/// (`v = 1`) and the top pair lifted to the full fur height (`v = 0`), as the renderer's fin
/// pass places them. Fins whose ends are both bald have no area and are left out; `None` when no
/// fin remains.
fn fin_primitive(
    builder: &mut GlbBuilder,
    input: &ExportInput<'_>,
    v: &SplitVertices,
    fin_png: Vec<u8>,
    weights: Option<&VertexWeights>,
) -> Result<Option<json::mesh::Primitive>> {
    let mesh = input.mesh;
    let lengths = SplitVertices::mesh_lengths(input);
    let comb = mesh.comb();
    let (positions, normals) = (mesh.positions(), mesh.normals());
    let colors = mesh.color();
    let quads: Vec<_> = fin_quads(mesh, v.split.uv_scale)
        .into_iter()
        .filter(|q| q.vertices.iter().any(|&x| lengths[x as usize] > 0.0))
        .collect();
    if quads.is_empty() {
        return Ok(None);
    }
    let n = 4 * quads.len();
    let (mut pos, mut nor, mut uv, mut col) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    for quad in &quads {
        let [a, b] = quad.vertices;
        for (vertex, u, height) in [
            (a, quad.u0, 0.0),
            (b, quad.u1, 0.0),
            (a, quad.u0, 1.0),
            (b, quad.u1, 1.0),
        ] {
            let x = vertex as usize;
            let c = comb.map_or([0.0; 3], |c| c[x]);
            pos.push(lifted(
                positions[x],
                normals[x],
                c,
                height,
                input.fur_depth,
                lengths[x],
            ));
            nor.push(normals[x]);
            // v runs from 0 at the top of the fur (the texture's first row) to 1 at the skin.
            uv.push([u as f32, 1.0 - height as f32]);
            col.push(colors.map_or([1.0; 4], |c| c[x].map(|v| v.clamp(0.0, 1.0))));
        }
    }
    check_lifted(&pos, |i| quads[i / 4].vertices[i % 2])?;
    let indices: Vec<u32> = (0..quads.len() as u32).flat_map(quad_triangles).collect();
    let image = builder.png_image(&format!("{}_fin", input.file_stem()), fin_png);
    let texture = builder.texture(image, SamplerKind::Fin);
    let fin = Primitive {
        position: builder.attribute(&pos, true),
        normal: builder.attribute(&nor, false),
        uv: builder.attribute(&uv, false),
        color: builder.attribute(&col, false),
    };
    // Each fin vertex moves with the edge end it stands on.
    let skinned: Vec<_> = weights
        .map(|w| skin_attributes(builder, w, pos.len(), |i| quads[i / 4].vertices[i % 2] as usize).to_vec())
        .unwrap_or_default();
    let material = material(
        builder,
        format!("{} fins", input.name),
        texture,
        0,
        AlphaMode::Blend,
        true,
    );
    let indices = builder.indices(&indices);
    Ok(Some(fin.primitive(indices, material, &skinned)))
}
