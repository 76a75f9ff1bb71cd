//! glTF 2.0 binary (`.glb`) export of furred objects, in two modes (see [`GltfMode`]): the shells
//! and fins baked into geometry any viewer shows, or the base mesh with the attributes, textures
//! and shell-stack description an engine-side shader needs (Lengyel et al. 2001, §2.3–§2.4).
//!
//! Several objects go into one file as one node and one mesh each, in the order given, all in one
//! scene. An object's own materials stay on its bald faces as primitives of their own
//! ([`super::materials`]). The file depends only on the inputs: no timestamps, objects and primitives in a fixed
//! order, images stored once per distinct content, parallel work collected in order.
//!
//! Files: `builder.rs` (buffer views, accessors, images, samplers, the GLB container),
//! `vertices.rs` (the split mesh's attributes), `geometry.rs` and `engine.rs` (one per mode),
//! `guard.rs` (the guard hairs: lines for engines, crossed ribbons as geometry), `peak.rs` (the
//! memory estimate checked before each object's buffers are made).

mod builder;
mod engine;
mod geometry;
mod guard;
mod peak;
mod rig;
mod vertices;

pub use builder::glb_container;
pub use engine::{EXTENSION, EXTENSION_VERSION, FALLBACK_SHELLS, ShellFur};
pub use guard::{GuardHairRef, RADIUS_ATTRIBUTE};
pub use peak::glb_peak_bytes;

use std::collections::BTreeMap;
use std::path::Path;

use gltf_json as json;
use json::validation::Checked;
use serde::{Deserialize, Serialize};

use super::description::StackDescription;
use super::input::ExportInput;
use super::materials::{OwnMaterial, skin_groups};
use super::rig::{Skeleton, VertexWeights, WeightReport, validate_skeletons};
use super::save_to_path;
use crate::error::{PeltError, Result};
use builder::GlbBuilder;

/// What the GLB holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GltfMode {
    /// Shells and fins as real meshes with alpha-blended materials: any viewer shows the fur.
    Geometry,
    /// The base mesh with Pelt's attributes, the atlases and the stack description in `extras`,
    /// for engine-side shell shaders.
    #[default]
    Engine,
}

impl GltfMode {
    /// The mode's name as the command line and Python spell it.
    pub fn name(self) -> &'static str {
        match self {
            GltfMode::Geometry => "geometry",
            GltfMode::Engine => "engine",
        }
    }

    /// Parses `geometry` or `engine`.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `mode` for any other text.
    pub fn parse(text: &str) -> Result<Self> {
        match text {
            "geometry" => Ok(GltfMode::Geometry),
            "engine" => Ok(GltfMode::Engine),
            other => Err(PeltError::parameter(
                "mode",
                format!("must be \"geometry\" or \"engine\", got {other:?}"),
            )),
        }
    }
}

/// Options of [`encode_glb`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GltfOptions {
    /// What the file holds.
    pub mode: GltfMode,
    /// `geometry` mode: include the fins (one double-sided quad per edge).
    pub fins: bool,
}

impl Default for GltfOptions {
    fn default() -> Self {
        GltfOptions {
            mode: GltfMode::Engine,
            fins: true,
        }
    }
}

/// The GLB of `objects` (one node and mesh each, in order) and `skeletons` (their nodes,
/// skins and animations) in one scene.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `objects` when there is none or the file would exceed
/// 4 GiB, `objects[i].<field>` for a field [`ExportInput::validate`] or
/// [`crate::export::rig::SkinBinding::validate`] rejects, or `skeletons[s].<field>`.
pub fn encode_glb(
    objects: &[ExportInput<'_>],
    skeletons: &[Skeleton],
    options: &GltfOptions,
) -> Result<Vec<u8>> {
    encode(objects, skeletons, options).map(|(bytes, _)| bytes)
}

/// [`encode_glb`] into a new file at `path`; returns, per object, what binding it to its
/// skeleton changed (`None` for an object without skin).
///
/// # Errors
/// As [`encode_glb`]; I/O failures name `path`. Nothing is written when the input is invalid.
pub fn save_glb(
    path: impl AsRef<Path>,
    objects: &[ExportInput<'_>],
    skeletons: &[Skeleton],
    options: &GltfOptions,
) -> Result<Vec<Option<WeightReport>>> {
    let (bytes, reports) = encode(objects, skeletons, options)?;
    save_to_path(path.as_ref(), |out| {
        std::io::Write::write_all(out, &bytes).map_err(super::writer_error)
    })?;
    Ok(reports)
}

/// The four strongest influences of every skinned object's vertices, after checking its binding.
fn reduced_weights(
    objects: &[ExportInput<'_>],
    skeletons: &[Skeleton],
) -> Result<Vec<Option<VertexWeights>>> {
    objects
        .iter()
        .enumerate()
        .map(|(i, input)| {
            input
                .skin
                .map(|skin| {
                    skin.validate(input.mesh.vertex_count(), skeletons)?;
                    Ok(skin.reduce())
                })
                .transpose()
                .map_err(|e| in_object(i, input.name, e))
        })
        .collect()
}

fn encode(
    objects: &[ExportInput<'_>],
    skeletons: &[Skeleton],
    options: &GltfOptions,
) -> Result<(Vec<u8>, Vec<Option<WeightReport>>)> {
    validate_objects(objects)?;
    validate_skeletons(skeletons)?;
    let weights = reduced_weights(objects, skeletons)?;
    let mut builder = GlbBuilder::new();
    let mut scene_nodes = Vec::with_capacity(objects.len());
    for (i, (input, weights)) in objects.iter().zip(&weights).enumerate() {
        let mesh = match options.mode {
            GltfMode::Geometry => geometry::add_object(&mut builder, input, options.fins, weights.as_ref()),
            GltfMode::Engine => engine::add_object(&mut builder, input, weights.as_ref()),
        }
        .map_err(|e| in_object(i, input.name, e))?;
        // A skinned node stays at the origin: its joints place it.
        let transform = if input.skin.is_some() {
            super::rig::Transform::IDENTITY
        } else {
            input.transform
        };
        scene_nodes.push(builder.root.push(json::Node {
            mesh: Some(mesh),
            ..rig::placed_node(input.name, &transform)
        }));
    }
    let object_nodes = scene_nodes.clone();
    let mut skeleton_nodes = Vec::with_capacity(skeletons.len());
    for skeleton in skeletons {
        let (nodes, roots) = rig::add_skeleton(&mut builder, skeleton);
        scene_nodes.extend(roots);
        skeleton_nodes.push(nodes);
    }
    for (input, &node) in objects.iter().zip(&object_nodes) {
        if let Some(binding) = input.skin {
            let s = binding.skeleton;
            let skin = rig::add_skin(
                &mut builder,
                input.name,
                &skeletons[s],
                &skeleton_nodes[s],
                &input.transform,
            );
            builder.root.nodes[node.value()].skin = Some(skin);
        }
    }
    for (skeleton, nodes) in skeletons.iter().zip(&skeleton_nodes) {
        rig::add_animations(&mut builder, skeleton, nodes);
    }
    for (input, &node) in objects.iter().zip(&object_nodes) {
        rig::add_node_animations(&mut builder, input.animations, &[input.transform], &[node]);
    }
    let scene = builder.root.push(json::Scene {
        extensions: None,
        extras: None,
        name: Some("Pelt".into()),
        nodes: scene_nodes,
    });
    builder.root.scene = Some(scene);
    let reports = weights.iter().map(|w| w.as_ref().map(|w| w.report)).collect();
    Ok((builder.finish()?, reports))
}

/// Checks that there is at least one object and each is valid, naming the object at fault.
pub(crate) fn validate_objects(objects: &[ExportInput<'_>]) -> Result<()> {
    if objects.is_empty() {
        return Err(PeltError::parameter("objects", "must hold at least one object"));
    }
    for (i, input) in objects.iter().enumerate() {
        input.validate().map_err(|e| in_object(i, input.name, e))?;
    }
    Ok(())
}

/// Prefixes a parameter error with the object it is about.
pub(crate) fn in_object(index: usize, name: &str, error: PeltError) -> PeltError {
    match error {
        PeltError::InvalidParameter { name: field, reason } => PeltError::parameter(
            format!("objects[{index}].{field}"),
            format!("(object {name:?}) {reason}"),
        ),
        other => other,
    }
}

/// The four attributes every primitive has.
#[derive(Debug, Clone, Copy)]
struct Primitive {
    position: json::Index<json::Accessor>,
    normal: json::Index<json::Accessor>,
    uv: json::Index<json::Accessor>,
    color: json::Index<json::Accessor>,
}

/// A vertex attribute of a primitive and its accessor.
type Attribute = (json::mesh::Semantic, json::Index<json::Accessor>);

impl Primitive {
    /// A triangle-list primitive of these attributes plus `extra` ones.
    fn primitive(
        &self,
        indices: json::Index<json::Accessor>,
        material: json::Index<json::Material>,
        extra: &[Attribute],
    ) -> json::mesh::Primitive {
        let color = (json::mesh::Semantic::Colors(0), self.color);
        self.without_color(indices, material, &[&[color], extra].concat())
    }

    /// [`Primitive::primitive`] without `COLOR_0`, which would tint a plain material's base
    /// color with the hair color.
    fn without_color(
        &self,
        indices: json::Index<json::Accessor>,
        material: json::Index<json::Material>,
        extra: &[Attribute],
    ) -> json::mesh::Primitive {
        use json::mesh::Semantic;
        let attributes = [
            (Semantic::Positions, self.position),
            (Semantic::Normals, self.normal),
            (Semantic::TexCoords(0), self.uv),
        ]
        .into_iter()
        .chain(extra.iter().cloned());
        mesh_primitive(attributes, indices, material, json::mesh::Mode::Triangles)
    }
}

/// A primitive of `attributes`, drawn as `mode` through `indices` with `material`.
fn mesh_primitive(
    attributes: impl IntoIterator<Item = Attribute>,
    indices: json::Index<json::Accessor>,
    material: json::Index<json::Material>,
    mode: json::mesh::Mode,
) -> json::mesh::Primitive {
    json::mesh::Primitive {
        attributes: attributes
            .into_iter()
            .map(|(semantic, accessor)| (Checked::Valid(semantic), accessor))
            .collect::<BTreeMap<_, _>>(),
        extensions: None,
        extras: None,
        indices: Some(indices),
        material: Some(material),
        mode: Checked::Valid(mode),
        targets: None,
    }
}

/// A rough, non-metallic material whose base color is `texture` (read with `TEXCOORD_<tex_coord>`,
/// multiplied by `COLOR_0`), opaque, alpha-tested (cutoff 0.5) or alpha-blended, single- or
/// double-sided.
fn material(
    builder: &mut GlbBuilder,
    name: String,
    texture: json::Index<json::Texture>,
    tex_coord: u32,
    alpha: json::material::AlphaMode,
    double_sided: bool,
) -> json::Index<json::Material> {
    builder.root.push(json::Material {
        alpha_mode: Checked::Valid(alpha),
        double_sided,
        name: Some(name),
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_texture: Some(json::texture::Info {
                index: texture,
                tex_coord,
                extensions: None,
                extras: None,
            }),
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(1.0),
            ..json::material::PbrMetallicRoughness::default()
        },
        ..json::Material::default()
    })
}

/// The skin split by material ([`crate::export::materials::skin_groups`]): Pelt's skin over the
/// furred faces (and the bald ones without a material of their own) with `skin_material` and
/// `fur` attributes, then one plain primitive per own material over its bald faces; all share
/// `base`'s vertices and the `skinned` joints and weights.
fn skin_primitives(
    builder: &mut GlbBuilder,
    input: &ExportInput<'_>,
    v: &vertices::SplitVertices,
    base: &Primitive,
    skin_material: json::Index<json::Material>,
    fur: &[Attribute],
    skinned: &[Attribute],
) -> (json::mesh::Primitive, Vec<json::mesh::Primitive>) {
    let (pelt, own) = skin_groups(&v.split.indices, &v.lengths, input.materials.as_ref());
    let indices = builder.indices(&pelt);
    let skin = base.primitive(indices, skin_material, &[fur, skinned].concat());
    let own = own
        .into_iter()
        .map(|(material, triangles)| {
            let material = plain_material(builder, material);
            let indices = builder.indices(&triangles);
            base.without_color(indices, material, skinned)
        })
        .collect();
    (skin, own)
}

/// An object's own material as glTF's: its base color factor, metallic and roughness, opaque
/// or (alpha below 1) alpha-blended.
fn plain_material(builder: &mut GlbBuilder, material: &OwnMaterial) -> json::Index<json::Material> {
    let alpha = if material.base_color[3] < 1.0 {
        json::material::AlphaMode::Blend
    } else {
        json::material::AlphaMode::Opaque
    };
    builder.root.push(json::Material {
        alpha_mode: Checked::Valid(alpha),
        name: Some(material.name.clone()),
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor(material.base_color),
            metallic_factor: json::material::StrengthFactor(material.metallic),
            roughness_factor: json::material::StrengthFactor(material.roughness),
            ..json::material::PbrMetallicRoughness::default()
        },
        ..json::Material::default()
    })
}

/// Indices (into the glTF `textures` array) of the engine mode's textures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EngineTextures {
    /// Layer 0 (the skin), also the material's base color.
    pub skin: u32,
    /// Every shell layer in the atlas (sRGB color, straight alpha).
    pub shells_atlas: u32,
    /// Every tangent layer in the atlas (`0.5·d + 0.5`, linear).
    pub tangents_atlas: u32,
    /// The fin texture (sRGB color, straight alpha).
    pub fin: u32,
    /// The 8-bit transfer textures, each an atlas of the layers.
    pub transfer: Vec<u32>,
}

/// The engine mode's vertex attribute names.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EngineAttributes {
    /// Patch UVs in tile units.
    pub uv: String,
    /// Hair color, linear RGBA.
    pub color: String,
    /// Length multiplier.
    pub length: String,
    /// Comb vector, object space.
    pub comb: String,
    /// `∂P/∂u` (object units per tile unit).
    pub dpdu: String,
    /// `∂P/∂v`.
    pub dpdv: String,
}

impl EngineAttributes {
    /// The names the engine mode writes.
    pub fn names() -> Self {
        EngineAttributes {
            uv: "TEXCOORD_1".into(),
            color: "COLOR_0".into(),
            length: "_PELT_LENGTH".into(),
            comb: "_PELT_COMB".into(),
            dpdu: "_PELT_DPDU".into(),
            dpdv: "_PELT_DPDV".into(),
        }
    }
}

/// `extras.pelt` of a `geometry` mesh (the engine mode describes its fur in the
/// [`engine::ShellFur`] extension).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GltfExtras {
    /// Always `pelt-gltf`.
    pub format: String,
    /// Schema version, 1.
    pub version: u32,
    /// `geometry`.
    pub mode: String,
    /// The shell stack.
    pub stack: StackDescription,
}

/// `{"pelt": GltfExtras}` as a raw JSON value.
fn pelt_extras(mode: &str, stack: &StackDescription) -> Result<json::Extras> {
    let extras = GltfExtras {
        format: "pelt-gltf".into(),
        version: 1,
        mode: mode.into(),
        stack: stack.clone(),
    };
    let mut wrapper = BTreeMap::new();
    wrapper.insert("pelt", extras);
    let raw = serde_json::value::to_raw_value(&wrapper)
        .map_err(|e| PeltError::Internal(format!("glTF extras: {e}")))?;
    Ok(Some(raw))
}
