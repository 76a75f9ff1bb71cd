//! Skeletons, skin weights and animations for the glTF export, so that a furred character's
//! shells and fins deform with the skin they stand on (glTF 2.0 §3.7.3 "Skins", §3.11
//! "Animations").
//!
//! Lengyel et al. 2001, §2.3 place each shell at a fixed offset from the skin. A shell or fin
//! vertex here carries the joints and weights of the skin vertex it is lifted from, so linear
//! blend skinning moves the lifted point with the same blended matrix as its root: the offset
//! turns with the skin's frame, as the preview's pose does (`render::deform`).
//!
//! A [`Skeleton`] is a node hierarchy (the rest transform of each node relative to its parent) with
//! sampled animations; every node may be a joint. An object bound to it gives per vertex any number
//! of `(joint, weight)` influences ([`SkinBinding`]); the export keeps the four strongest and
//! normalizes them ([`SkinBinding::reduce`], glTF's `JOINTS_0` / `WEIGHTS_0`), reporting how many
//! vertices that changed. The inverse bind matrices are computed here from the rest hierarchy and
//! the object's transform, so a file is always in its bind pose at rest.

use glam::{Mat4, Quat, Vec3};
use serde::Serialize;

use crate::error::{PeltError, Result};

/// Influences per vertex a glTF `JOINTS_0` / `WEIGHTS_0` pair holds.
pub const MAX_INFLUENCES: usize = 4;
/// Most nodes of a skeleton: joint indices are written as unsigned shorts.
pub const MAX_NODES: usize = u16::MAX as usize;
/// A weight sum further than this from 1 counts as renormalized in the [`WeightReport`].
const NORMALIZED_TOLERANCE: f32 = 1e-3;
/// A rotation quaternion whose length is further than this from 1 is refused (glTF wants unit
/// quaternions; a longer one is a scale mixed into the rotation).
const UNIT_TOLERANCE: f32 = 1e-3;

/// Translation, rotation and scale: a glTF node's transform.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    pub translation: Vec3,
    /// Unit quaternion.
    pub rotation: Quat,
    pub scale: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Transform::IDENTITY
    }
}

impl Transform {
    pub const IDENTITY: Transform = Transform {
        translation: Vec3::ZERO,
        rotation: Quat::IDENTITY,
        scale: Vec3::ONE,
    };

    /// The transform of an affine matrix given row by row (translation in the last column, as
    /// numpy prints Blender's `matrix_world`). A shear, which glTF nodes cannot hold, is dropped;
    /// `None` when the matrix is not finite, not affine or singular.
    pub fn from_rows(rows: [[f32; 4]; 4]) -> Option<Transform> {
        let affine = rows[3] == [0.0, 0.0, 0.0, 1.0];
        let matrix = Mat4::from_cols_array_2d(&rows).transpose();
        if !affine || !matrix.is_finite() || matrix.determinant().abs() < f32::MIN_POSITIVE {
            return None;
        }
        let (scale, rotation, translation) = matrix.to_scale_rotation_translation();
        let transform = Transform {
            translation,
            rotation: rotation.normalize(),
            scale,
        };
        transform.is_valid().then_some(transform)
    }

    /// `T · R · S`.
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }

    /// Finite, a unit rotation and no zero scale (the matrix is invertible).
    fn is_valid(&self) -> bool {
        self.translation.is_finite()
            && self.rotation.is_finite()
            && (self.rotation.length() - 1.0).abs() <= UNIT_TOLERANCE
            && self.scale.is_finite()
            && self.scale.abs().min_element() >= f32::MIN_POSITIVE
    }

    /// Checks the transform, naming `name`.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `name` when a component is not finite, the rotation
    /// is not a unit quaternion or a scale is zero.
    pub fn validate(&self, name: &str) -> Result<()> {
        if self.is_valid() {
            Ok(())
        } else {
            Err(PeltError::parameter(
                name,
                format!(
                    "must be finite with a unit rotation and no zero scale, got translation {}, \
                     rotation {} (length {}), scale {}",
                    self.translation,
                    self.rotation,
                    self.rotation.length(),
                    self.scale
                ),
            ))
        }
    }
}

/// One node of a skeleton.
#[derive(Debug, Clone, PartialEq)]
pub struct SkeletonNode {
    /// The glTF node name (a bone's name).
    pub name: String,
    /// Index of the parent node in [`Skeleton::nodes`]; `None` for a root, which stands in the
    /// scene.
    pub parent: Option<usize>,
    /// Transform relative to the parent (to the scene for a root) in the rest pose.
    pub rest: Transform,
}

/// One animation of a skeleton, sampled: every node's transform relative to its parent at every
/// time, interpolated linearly (rotations spherically) between samples.
#[derive(Debug, Clone, PartialEq)]
pub struct Animation {
    /// The glTF animation name.
    pub name: String,
    /// Sample times in seconds, at least one, non-negative and strictly increasing.
    pub times: Vec<f32>,
    /// `times.len() × nodes` transforms, time-major (`poses[t · nodes + j]`).
    pub poses: Vec<Transform>,
}

/// A node hierarchy with its animations. Several objects may be bound to one skeleton.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Skeleton {
    /// The nodes; a parent may come before or after its children.
    pub nodes: Vec<SkeletonNode>,
    pub animations: Vec<Animation>,
}

impl Skeleton {
    /// Checks the hierarchy (parents in range, no cycle), the transforms and the animations.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `nodes`, `nodes[j].parent`, `nodes[j].rest`,
    /// `animations[a].times`, `animations[a].poses` or `animations[a].poses[i]`.
    pub fn validate(&self) -> Result<()> {
        let n = self.nodes.len();
        if !(1..=MAX_NODES).contains(&n) {
            return Err(PeltError::parameter(
                "nodes",
                format!("must hold 1 to {MAX_NODES} nodes, got {n}"),
            ));
        }
        for (j, node) in self.nodes.iter().enumerate() {
            if let Some(p) = node.parent
                && p >= n
            {
                return Err(PeltError::parameter(
                    format!("nodes[{j}].parent"),
                    format!("is node {p}, but the skeleton has {n} nodes"),
                ));
            }
            node.rest.validate(&format!("nodes[{j}].rest"))?;
        }
        // Each node's chain up to a root, walked once: a node found to reach a root is marked, so
        // a long chain costs its length, not its length squared.
        let mut rooted = vec![false; n];
        let mut path = Vec::new();
        for j in 0..n {
            path.clear();
            let mut at = j;
            while !rooted[at] {
                path.push(at);
                // A chain longer than the node count has gone round a cycle.
                match self.nodes[at].parent {
                    Some(_) if path.len() > n => {
                        return Err(PeltError::parameter(
                            format!("nodes[{j}].parent"),
                            "leads round a cycle: a node cannot be its own ancestor",
                        ));
                    }
                    Some(p) => at = p,
                    None => break,
                }
            }
            for &k in &path {
                rooted[k] = true;
            }
        }
        for (a, animation) in self.animations.iter().enumerate() {
            animation.validate(a, n)?;
        }
        Ok(())
    }

    /// Every node's rest transform relative to the scene.
    pub fn world_rest(&self) -> Vec<Mat4> {
        self.world(|j| self.nodes[j].rest.matrix())
    }

    /// Every node's transform relative to the scene, from its transform relative to its parent.
    pub fn world(&self, local: impl Fn(usize) -> Mat4) -> Vec<Mat4> {
        let mut world: Vec<Option<Mat4>> = vec![None; self.nodes.len()];
        for j in 0..self.nodes.len() {
            if world[j].is_some() {
                continue;
            }
            // Walk up to the first known ancestor, then back down (validate ruled out cycles).
            let (mut chain, mut at) = (vec![j], j);
            while let Some(p) = self.nodes[at].parent {
                if world[p].is_some() || chain.len() > self.nodes.len() {
                    break;
                }
                chain.push(p);
                at = p;
            }
            for &k in chain.iter().rev() {
                let parent = self.nodes[k]
                    .parent
                    .and_then(|p| world[p])
                    .unwrap_or(Mat4::IDENTITY);
                world[k] = Some(parent * local(k));
            }
        }
        world.into_iter().map(|m| m.unwrap_or(Mat4::IDENTITY)).collect()
    }

    /// The inverse bind matrix of every node for an object whose vertices are placed by `bind`
    /// at rest: `world_rest⁻¹ · bind`, so that at rest every joint's skinning matrix is `bind`.
    pub fn inverse_binds(&self, bind: &Transform) -> Vec<Mat4> {
        let bind = bind.matrix();
        self.world_rest()
            .into_iter()
            .map(|world| world.inverse() * bind)
            .collect()
    }
}

impl Animation {
    /// Checks the times (finite, non-negative, increasing) and that there are `nodes` valid
    /// transforms per time; errors name `animations[index].*`.
    pub(crate) fn validate(&self, index: usize, nodes: usize) -> Result<()> {
        let name = |field: &str| format!("animations[{index}].{field}");
        let t = &self.times;
        if t.is_empty() {
            return Err(PeltError::parameter(name("times"), "must hold at least one time"));
        }
        if let Some(i) = t.iter().position(|x| !(x.is_finite() && *x >= 0.0)) {
            return Err(PeltError::parameter(
                name("times"),
                format!("time {i} is {}; times must be finite and non-negative", t[i]),
            ));
        }
        if let Some(i) = t.windows(2).position(|w| w[1] <= w[0]) {
            return Err(PeltError::parameter(
                name("times"),
                format!(
                    "must increase strictly, but time {} is {} after {}",
                    i + 1,
                    t[i + 1],
                    t[i]
                ),
            ));
        }
        if Some(self.poses.len()) != t.len().checked_mul(nodes) {
            return Err(PeltError::parameter(
                name("poses"),
                format!(
                    "must hold {} times × {nodes} nodes transforms, got {}",
                    t.len(),
                    self.poses.len()
                ),
            ));
        }
        for (i, pose) in self.poses.iter().enumerate() {
            pose.validate(&name(&format!("poses[{i}]")))?;
        }
        Ok(())
    }
}

/// One object's binding to a skeleton: per vertex `influences` pairs of a node index and a weight
/// (zero weights are ignored; a vertex must have a positive one).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SkinBinding<'a> {
    /// Index of the skeleton in the list the export is given.
    pub skeleton: usize,
    /// Pairs per vertex, at least 1.
    pub influences: usize,
    /// `vertices × influences` node indices, vertex-major.
    pub joints: &'a [u32],
    /// `vertices × influences` weights, finite and non-negative.
    pub weights: &'a [f32],
}

/// What [`SkinBinding::reduce`] changed, for the user.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct WeightReport {
    /// Vertices bound.
    pub vertices: usize,
    /// Vertices with more than four joints, of which the four strongest were kept.
    pub reduced: usize,
    /// Vertices whose weights did not sum to 1 (within 0.001) and were scaled to.
    pub renormalized: usize,
}

/// Four joints and weights per vertex, as `JOINTS_0` and `WEIGHTS_0` hold them.
#[derive(Debug, Clone, PartialEq)]
pub struct VertexWeights {
    pub joints: Vec<[u16; 4]>,
    /// Each row sums to 1; unused slots are joint 0 with weight 0.
    pub weights: Vec<[f32; 4]>,
    pub report: WeightReport,
}

impl SkinBinding<'_> {
    /// Checks the binding against the mesh's `vertices` and the `skeletons`.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `skin.skeleton`, `skin.influences`, `skin.joints`
    /// or `skin.weights`, with the vertex at fault.
    pub fn validate(&self, vertices: usize, skeletons: &[Skeleton]) -> Result<()> {
        let Some(skeleton) = skeletons.get(self.skeleton) else {
            return Err(PeltError::parameter(
                "skin.skeleton",
                format!(
                    "is skeleton {}, but the export has {}",
                    self.skeleton,
                    skeletons.len()
                ),
            ));
        };
        let k = self.influences;
        if k == 0 {
            return Err(PeltError::parameter(
                "skin.influences",
                "must be at least 1, got 0",
            ));
        }
        let expected = vertices.checked_mul(k);
        for (name, len) in [
            ("skin.joints", self.joints.len()),
            ("skin.weights", self.weights.len()),
        ] {
            if Some(len) != expected {
                return Err(PeltError::parameter(
                    name,
                    format!("must hold {vertices} vertices × {k} influences values, got {len}"),
                ));
            }
        }
        let nodes = skeleton.nodes.len();
        if let Some(i) = self.joints.iter().position(|&j| j as usize >= nodes) {
            return Err(PeltError::parameter(
                "skin.joints",
                format!(
                    "vertex {} names node {}, but its skeleton has {nodes} nodes (a joint missing \
                     from the hierarchy)",
                    i / k,
                    self.joints[i]
                ),
            ));
        }
        if let Some(i) = self.weights.iter().position(|w| !(w.is_finite() && *w >= 0.0)) {
            return Err(PeltError::parameter(
                "skin.weights",
                format!(
                    "vertex {} has weight {}; weights must be finite and non-negative",
                    i / k,
                    self.weights[i]
                ),
            ));
        }
        if let Some(v) = self
            .weights
            .chunks_exact(k)
            .position(|row| row.iter().all(|&w| w == 0.0))
        {
            return Err(PeltError::parameter(
                "skin.weights",
                format!(
                    "vertex {v} has no weight: every vertex of a skinned mesh needs a joint (bind \
                     unweighted vertices to the skeleton's root)"
                ),
            ));
        }
        Ok(())
    }

    /// The four strongest joints of every vertex (a joint listed twice counts once with the sum
    /// of its weights; ties go to the lower node index), normalized to sum 1. Call after
    /// [`SkinBinding::validate`].
    pub fn reduce(&self) -> VertexWeights {
        let k = self.influences.max(1);
        let mut report = WeightReport::default();
        let mut joints = Vec::with_capacity(self.joints.len() / k);
        let mut weights = Vec::with_capacity(self.joints.len() / k);
        let mut pairs: Vec<(u32, f32)> = Vec::with_capacity(k);
        for (row_joints, row_weights) in self.joints.chunks_exact(k).zip(self.weights.chunks_exact(k)) {
            pairs.clear();
            for (&j, &w) in row_joints.iter().zip(row_weights) {
                if w <= 0.0 {
                    continue;
                }
                match pairs.iter_mut().find(|(pj, _)| *pj == j) {
                    Some((_, pw)) => *pw += w,
                    None => pairs.push((j, w)),
                }
            }
            let total: f32 = pairs.iter().map(|p| p.1).sum();
            pairs.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
            report.vertices += 1;
            if pairs.len() > MAX_INFLUENCES {
                report.reduced += 1;
                pairs.truncate(MAX_INFLUENCES);
            }
            if (total - 1.0).abs() > NORMALIZED_TOLERANCE {
                report.renormalized += 1;
            }
            let kept: f32 = pairs.iter().map(|p| p.1).sum();
            let (mut row_j, mut row_w) = ([0u16; 4], [0f32; 4]);
            for (slot, &(j, w)) in pairs.iter().enumerate() {
                row_j[slot] = j as u16;
                row_w[slot] = if kept > 0.0 { w / kept } else { 0.0 };
            }
            joints.push(row_j);
            weights.push(row_w);
        }
        VertexWeights {
            joints,
            weights,
            report,
        }
    }
}

/// Validates every skeleton, naming the one at fault.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `skeletons[s].<field>`.
pub fn validate_skeletons(skeletons: &[Skeleton]) -> Result<()> {
    for (s, skeleton) in skeletons.iter().enumerate() {
        skeleton.validate().map_err(|e| match e {
            PeltError::InvalidParameter { name, reason } => {
                PeltError::parameter(format!("skeletons[{s}].{name}"), reason)
            }
            other => other,
        })?;
    }
    Ok(())
}
