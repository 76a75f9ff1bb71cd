//! The skeletons of a glTF export as nodes, skins and animations (glTF 2.0 §3.7.3, §3.11), and
//! the `JOINTS_0` / `WEIGHTS_0` of the skinned primitives ([`crate::export::rig`]).
//!
//! A skinned object's node stands at the scene root without a transform (glTF ignores a skinned
//! node's transform; three.js would apply it twice), and its inverse bind matrices carry the
//! object's own transform, so at rest every joint places the mesh where the object stood.

use gltf_json as json;
use json::validation::Checked;

use super::builder::GlbBuilder;
use crate::export::rig::{Animation, Skeleton, Transform, VertexWeights};

/// A sample further than this from the rest value makes a channel worth writing.
const STILL: f32 = 1e-6;

/// The glTF nodes of one skeleton, by skeleton node index.
pub(super) struct SkeletonNodes(pub Vec<json::Index<json::Node>>);

/// A node's transform fields, leaving out the identity parts (glTF's defaults).
fn set_transform(node: &mut json::Node, t: &Transform) {
    if t.translation != glam::Vec3::ZERO {
        node.translation = Some(t.translation.to_array());
    }
    if t.rotation != glam::Quat::IDENTITY {
        node.rotation = Some(json::scene::UnitQuaternion(t.rotation.normalize().to_array()));
    }
    if t.scale != glam::Vec3::ONE {
        node.scale = Some(t.scale.to_array());
    }
}

/// A node named `name` placed by `transform`.
pub(super) fn placed_node(name: &str, transform: &Transform) -> json::Node {
    let mut node = json::Node {
        name: Some(name.into()),
        ..json::Node::default()
    };
    set_transform(&mut node, transform);
    node
}

/// Adds a skeleton's nodes in order (children lists and rest transforms); returns them and its
/// roots, which go into the scene.
pub(super) fn add_skeleton(
    builder: &mut GlbBuilder,
    skeleton: &Skeleton,
) -> (SkeletonNodes, Vec<json::Index<json::Node>>) {
    let base = builder.root.nodes.len();
    let index = |j: usize| json::Index::<json::Node>::new((base + j) as u32);
    let mut children: Vec<Vec<json::Index<json::Node>>> = vec![Vec::new(); skeleton.nodes.len()];
    let mut roots = Vec::new();
    for (j, node) in skeleton.nodes.iter().enumerate() {
        match node.parent {
            Some(p) => children[p].push(index(j)),
            None => roots.push(index(j)),
        }
    }
    let nodes = skeleton
        .nodes
        .iter()
        .zip(children)
        .map(|(node, children)| {
            let mut gltf = placed_node(&node.name, &node.rest);
            gltf.children = (!children.is_empty()).then_some(children);
            builder.root.push(gltf)
        })
        .collect();
    (SkeletonNodes(nodes), roots)
}

/// A skin of every node of `skeleton` for an object placed by `bind` at rest.
pub(super) fn add_skin(
    builder: &mut GlbBuilder,
    name: &str,
    skeleton: &Skeleton,
    nodes: &SkeletonNodes,
    bind: &Transform,
) -> json::Index<json::Skin> {
    let matrices: Vec<[f32; 16]> = skeleton
        .inverse_binds(bind)
        .iter()
        .map(|m| m.to_cols_array())
        .collect();
    let inverse_bind_matrices = Some(builder.data(&matrices, false));
    builder.root.push(json::Skin {
        extensions: None,
        extras: None,
        inverse_bind_matrices,
        joints: nodes.0.clone(),
        name: Some(format!("{name} skin")),
        skeleton: None,
    })
}

/// `JOINTS_0` and `WEIGHTS_0` of `weights` gathered by `vertex(i)` (the mesh vertex of primitive
/// vertex `i`), as extra attributes of a primitive.
pub(super) fn skin_attributes(
    builder: &mut GlbBuilder,
    weights: &VertexWeights,
    count: usize,
    vertex: impl Fn(usize) -> usize,
) -> [(json::mesh::Semantic, json::Index<json::Accessor>); 2] {
    let joints: Vec<[u16; 4]> = (0..count).map(|i| weights.joints[vertex(i)]).collect();
    let values: Vec<[f32; 4]> = (0..count).map(|i| weights.weights[vertex(i)]).collect();
    [
        (json::mesh::Semantic::Joints(0), builder.joints(&joints)),
        (
            json::mesh::Semantic::Weights(0),
            builder.attribute(&values, false),
        ),
    ]
}

/// One glTF animation per animation of `skeleton` ([`add_node_animations`]).
pub(super) fn add_animations(builder: &mut GlbBuilder, skeleton: &Skeleton, nodes: &SkeletonNodes) {
    let rests: Vec<Transform> = skeleton.nodes.iter().map(|n| n.rest).collect();
    add_node_animations(builder, &skeleton.animations, &rests, &nodes.0);
}

/// One glTF animation per one of `animations` of the glTF `nodes` (whose transforms are
/// `rests`; the poses hold one transform per node and time): a translation, rotation and scale
/// channel for every node whose samples leave its rest value (the others keep their rest
/// transform), linear interpolation (spherical for rotations, each sample on the same side as
/// the one before).
pub(super) fn add_node_animations(
    builder: &mut GlbBuilder,
    animations: &[Animation],
    rests: &[Transform],
    nodes: &[json::Index<json::Node>],
) {
    use json::animation::{Channel, Interpolation, Property, Sampler, Target};
    let n = rests.len();
    for animation in animations {
        let times: Vec<[f32; 1]> = animation.times.iter().map(|&t| [t]).collect();
        let mut input = None;
        let (mut channels, mut samplers) = (Vec::new(), Vec::new());
        for (j, &rest) in rests.iter().enumerate() {
            let poses: Vec<&Transform> = (0..times.len()).map(|t| &animation.poses[t * n + j]).collect();
            let moved = |f: &dyn Fn(&Transform) -> [f32; 4]| {
                let r = f(&rest);
                poses
                    .iter()
                    .any(|p| f(p).iter().zip(r).any(|(a, b)| (a - b).abs() > STILL))
            };
            let translation = |t: &Transform| t.translation.extend(0.0).to_array();
            let rotation = |t: &Transform| t.rotation.to_array();
            let scale = |t: &Transform| t.scale.extend(0.0).to_array();
            let mut outputs: Vec<(Property, json::Index<json::Accessor>)> = Vec::new();
            if moved(&translation) {
                let values: Vec<[f32; 3]> = poses.iter().map(|p| p.translation.to_array()).collect();
                outputs.push((Property::Translation, builder.data(&values, false)));
            }
            if moved(&rotation) {
                let mut previous = glam::Quat::IDENTITY;
                let values: Vec<[f32; 4]> = poses
                    .iter()
                    .map(|p| {
                        let q = p.rotation.normalize();
                        let q = if q.dot(previous) < 0.0 { -q } else { q };
                        previous = q;
                        q.to_array()
                    })
                    .collect();
                outputs.push((Property::Rotation, builder.data(&values, false)));
            }
            if moved(&scale) {
                let values: Vec<[f32; 3]> = poses.iter().map(|p| p.scale.to_array()).collect();
                outputs.push((Property::Scale, builder.data(&values, false)));
            }
            for (path, output) in outputs {
                let input = *input.get_or_insert_with(|| builder.data(&times, true));
                let sampler = json::Index::new(samplers.len() as u32);
                samplers.push(Sampler {
                    extensions: None,
                    extras: None,
                    input,
                    interpolation: Checked::Valid(Interpolation::Linear),
                    output,
                });
                channels.push(Channel {
                    sampler,
                    target: Target {
                        extensions: None,
                        extras: None,
                        node: nodes[j],
                        path: Checked::Valid(path),
                    },
                    extensions: None,
                    extras: None,
                });
            }
        }
        // A glTF animation needs a channel: an animation that moves nothing is left out.
        if !channels.is_empty() {
            builder.root.push(json::Animation {
                extensions: None,
                extras: None,
                channels,
                name: Some(animation.name.clone()),
                samplers,
            });
        }
    }
}
