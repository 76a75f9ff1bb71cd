//! The guard hairs ([`crate::guard`]) in glTF, beside the shells (the hybrid paper: the coarse
//! guard hairs as explicit strands, the undercoat as a volume).
//!
//! - `engine` mode: one `LINES` primitive of the strands' segments, per point `POSITION`,
//!   `NORMAL` (the surface's at the strand's root, which lights it as the shells there are lit),
//!   `COLOR_0` (root color to tip color along the strand) and `_PELT_RADIUS` (object units), so a
//!   plain viewer draws thin lines and an engine its own tapered, camera-facing ribbons;
//!   `PELT_shell_fur.guardHairs` names the primitive and the radius attribute.
//! - `geometry` mode: the strands as two crossed ribbons each (`TRIANGLES`, double-sided,
//!   `2·radius` wide at every point), visible from any side without a shader of their own.
//!
//! A skinned object's strands move with the vertex of their root triangle that holds the most of
//! the root (its joints and weights).

use gltf_json as json;
use json::mesh::Semantic;
use serde::{Deserialize, Serialize};

use super::Attribute;
use super::builder::GlbBuilder;
use super::rig::skin_attributes;
use crate::error::{PeltError, Result};
use crate::export::input::ExportInput;
use crate::export::rig::VertexWeights;
use crate::placement::{NO_TRIANGLE, PlacedStrands, StrandSpan};

/// The radius attribute's name in `engine` mode (glTF's application-specific `_` prefix).
pub const RADIUS_ATTRIBUTE: &str = "_PELT_RADIUS";

/// `PELT_shell_fur.guardHairs`: where the guard hairs are.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct GuardHairRef {
    /// Index (in the same mesh) of the `LINES` primitive of the strands.
    pub primitive: u32,
    /// Number of strands.
    pub strands: u32,
    /// The per-point radius attribute (object units).
    pub radius: String,
}

/// Per point: the strand it belongs to, and its share of the way from root to tip.
fn point_strands(guard: &PlacedStrands) -> (Vec<usize>, Vec<f32>) {
    let points = guard.points.len();
    let (mut strand, mut along) = (vec![0; points], vec![0.0; points]);
    for (s, span) in guard.spans.iter().enumerate() {
        let last = (span.count.max(2) - 1) as f32;
        for k in 0..span.count as usize {
            strand[span.first as usize + k] = s;
            along[span.first as usize + k] = k as f32 / last;
        }
    }
    (strand, along)
}

/// Linear RGBA per point, root color to tip color, clamped to glTF's `[0, 1]`.
fn point_colors(guard: &PlacedStrands, strand: &[usize], along: &[f32]) -> Vec<[f32; 4]> {
    strand
        .iter()
        .zip(along)
        .map(|(&s, &t)| {
            let span = &guard.spans[s];
            let c = span.root_color.lerp(span.tip_color, t);
            [c.x, c.y, c.z, 1.0].map(|v| v.clamp(0.0, 1.0))
        })
        .collect()
}

/// The mesh vertex a strand's root moves with: its triangle's corner of the largest weight.
fn root_vertex(input: &ExportInput<'_>, span: &StrandSpan) -> usize {
    let corner = (0..3).fold(0, |b, k| if span.weights[k] > span.weights[b] { k } else { b });
    input.mesh.triangles()[span.triangle as usize][corner] as usize
}

/// Checks that every strand stands on one of the mesh's triangles, with finite points.
fn check(input: &ExportInput<'_>, guard: &PlacedStrands) -> Result<()> {
    let triangles = input.mesh.face_count();
    if let Some(s) = guard
        .spans
        .iter()
        .position(|s| s.triangle == NO_TRIANGLE || s.triangle as usize >= triangles || s.count < 2)
    {
        return Err(PeltError::parameter(
            "guard_hairs",
            format!(
                "strand {s} does not stand on one of the mesh's {triangles} triangles with two points or more"
            ),
        ));
    }
    if let Some(p) = guard.points.iter().position(|p| !p.iter().all(|v| v.is_finite())) {
        return Err(PeltError::parameter(
            "guard_hairs",
            format!("point {p} is not finite"),
        ));
    }
    Ok(())
}

/// `input`'s guard hairs, checked, with each point's strand and share of the way to its tip;
/// `None` without guard hairs.
#[allow(clippy::type_complexity)]
fn checked<'a>(input: &ExportInput<'a>) -> Result<Option<(&'a PlacedStrands, Vec<usize>, Vec<f32>)>> {
    let Some(guard) = input.guard_hairs.filter(|g| !g.spans.is_empty()) else {
        return Ok(None);
    };
    check(input, guard)?;
    let (strand, along) = point_strands(guard);
    Ok(Some((guard, strand, along)))
}

/// `JOINTS_0`/`WEIGHTS_0` of `count` vertices, vertex `i` on point `vertex_point(i)`, which
/// belongs to strand `strand[point]`; none without `weights`.
fn skin_of(
    builder: &mut GlbBuilder,
    input: &ExportInput<'_>,
    guard: &PlacedStrands,
    strand: &[usize],
    weights: Option<&VertexWeights>,
    vertex_point: impl Fn(usize) -> usize,
    count: usize,
) -> Vec<Attribute> {
    let Some(w) = weights else {
        return Vec::new();
    };
    let roots: Vec<usize> = guard.spans.iter().map(|s| root_vertex(input, s)).collect();
    skin_attributes(builder, w, count, |i| roots[strand[vertex_point(i)]]).to_vec()
}

/// A vertex-colored, double-sided material without texture.
fn hair_material(builder: &mut GlbBuilder, name: String) -> json::Index<json::Material> {
    builder.root.push(json::Material {
        double_sided: true,
        name: Some(name),
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(0.6),
            ..json::material::PbrMetallicRoughness::default()
        },
        ..json::Material::default()
    })
}

/// The guard hairs' primitive: `LINES` for `engine` mode, crossed ribbons for `geometry` mode;
/// `None` without guard hairs.
pub(super) fn primitive_of(
    builder: &mut GlbBuilder,
    input: &ExportInput<'_>,
    weights: Option<&VertexWeights>,
    mode: super::GltfMode,
) -> Result<Option<json::mesh::Primitive>> {
    let Some((guard, strand, along)) = checked(input)? else {
        return Ok(None);
    };
    let colors = point_colors(guard, &strand, &along);
    let (mut attributes, indices, per_point, kind) = match mode {
        super::GltfMode::Engine => lines(builder, guard, &colors, &root_normals(input, guard, &strand)),
        super::GltfMode::Geometry => ribbons(builder, guard, &colors)?,
    };
    let count = per_point * guard.points.len();
    attributes.extend(skin_of(
        builder,
        input,
        guard,
        &strand,
        weights,
        |i| i / per_point,
        count,
    ));
    let indices = builder.indices(&indices);
    let material = hair_material(builder, format!("{} guard hairs", input.name));
    Ok(Some(super::mesh_primitive(attributes, indices, material, kind)))
}

/// A vertex's attributes, the indices, vertices per strand point and the primitive's mode.
type Geometry = (
    Vec<(Semantic, json::Index<json::Accessor>)>,
    Vec<u32>,
    usize,
    json::mesh::Mode,
);

/// Per point, the unit surface normal at its strand's root: the root triangle's vertex normals
/// weighted by the root's barycentric weights (the renderer's strand lighting uses it).
fn root_normals(input: &ExportInput<'_>, guard: &PlacedStrands, strand: &[usize]) -> Vec<[f32; 3]> {
    let (normals, triangles) = (input.mesh.normals(), input.mesh.triangles());
    let roots: Vec<[f32; 3]> = guard
        .spans
        .iter()
        .map(|span| {
            let corners = triangles[span.triangle as usize];
            let n = (0..3).fold(glam::Vec3::ZERO, |sum, k| {
                sum + span.weights[k] * glam::Vec3::from(normals[corners[k] as usize])
            });
            n.normalize_or(glam::Vec3::Z).to_array()
        })
        .collect();
    strand.iter().map(|&s| roots[s]).collect()
}

/// The strands' segments as lines: per point its position, root normal, color and radius.
fn lines(
    builder: &mut GlbBuilder,
    guard: &PlacedStrands,
    colors: &[[f32; 4]],
    normals: &[[f32; 3]],
) -> Geometry {
    let positions: Vec<[f32; 3]> = guard.points.iter().map(|p| [p[0], p[1], p[2]]).collect();
    let radii: Vec<[f32; 1]> = guard.points.iter().map(|p| [p[3]]).collect();
    let indices: Vec<u32> = guard
        .spans
        .iter()
        .flat_map(|s| (s.first..s.first + s.count - 1).flat_map(|i| [i, i + 1]))
        .collect();
    let attributes = vec![
        (Semantic::Positions, builder.attribute(&positions, true)),
        (Semantic::Normals, builder.attribute(normals, false)),
        (Semantic::Colors(0), builder.attribute(colors, false)),
        (
            Semantic::Extras(RADIUS_ATTRIBUTE[1..].into()),
            builder.attribute(&radii, false),
        ),
    ];
    (attributes, indices, 1, json::mesh::Mode::Lines)
}

/// Every strand as two crossed ribbons, `2 · radius` wide at each point.
fn ribbons(builder: &mut GlbBuilder, guard: &PlacedStrands, colors: &[[f32; 4]]) -> Result<Geometry> {
    // Per point four vertices: ribbon a's two edges, then ribbon b's.
    let n = 4 * guard.points.len();
    let (mut pos, mut nor, mut col) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    let mut indices = Vec::with_capacity(12 * guard.points.len());
    for span in &guard.spans {
        let points = &guard.points[span.first as usize..(span.first + span.count) as usize];
        let at = |k: usize| glam::Vec3::new(points[k][0], points[k][1], points[k][2]);
        let last = points.len() - 1;
        let root_tangent = (at(1) - at(0)).normalize_or(glam::Vec3::Z);
        // A direction across the root: a strand seldom bends a right angle onto it.
        let reference = root_tangent.any_orthonormal_vector();
        for k in 0..points.len() {
            let tangent =
                (at(k.min(last - 1) + 1) - at(k.saturating_sub(1).min(last - 1))).normalize_or(root_tangent);
            let side_a = tangent.cross(reference).normalize_or(reference);
            let side_b = tangent
                .cross(side_a)
                .normalize_or(tangent.any_orthonormal_vector());
            let r = points[k][3];
            let p = at(k);
            let color = colors[span.first as usize + k];
            for (side, normal) in [(side_a, side_b), (side_b, side_a)] {
                for sign in [-1.0, 1.0] {
                    pos.push((p + sign * r * side).to_array());
                    nor.push(normal.to_array());
                    col.push(color);
                }
            }
        }
        let base = 4 * span.first;
        for k in 0..last as u32 {
            for ribbon in [0, 2] {
                let (a, b) = (base + 4 * k + ribbon, base + 4 * (k + 1) + ribbon);
                indices.extend([a, a + 1, b + 1, a, b + 1, b]);
            }
        }
    }
    if !pos.iter().flatten().all(|v| v.is_finite()) {
        return Err(PeltError::parameter(
            "guard_hairs",
            "a ribbon's corner is not finite (a radius near the f32 range)",
        ));
    }
    let attributes = vec![
        (Semantic::Positions, builder.attribute(&pos, true)),
        (Semantic::Normals, builder.attribute(&nor, false)),
        (Semantic::Colors(0), builder.attribute(&col, false)),
    ];
    Ok((attributes, indices, 4, json::mesh::Mode::Triangles))
}
