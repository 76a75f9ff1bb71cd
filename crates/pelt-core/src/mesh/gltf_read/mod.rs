//! glTF 2.0 reading (`.glb`, or `.gltf` with its buffers in files beside it), so pipelines without
//! Blender can bake meshes that engines and DCC tools export (`pelt bake mesh.glb`).
//!
//! Only what a fur bake needs: per node that has a mesh, the triangles of its primitives
//! (`TRIANGLES`, `TRIANGLE_STRIP` and `TRIANGLE_FAN`; points and lines are skipped), `POSITION`
//! in world space (the node's transform chain applied), and `COLOR_0` when present (glTF colors
//! are linear, like `pelt_color`). glTF splits vertices wherever a UV or normal differs, which
//! would cut the surface into pieces for the comb field and the lapped patches, so the vertices of
//! one node are welded where their positions are bit-identical. Each triangle is its own polygon
//! (glTF keeps no polygons). Normals and UVs are not read: Pelt computes its own.
//!
//! Every bound is checked (`accessor.rs`, `container.rs`); a bad file is reported as a
//! [`PeltError`] naming the file.

mod accessor;
mod container;

use std::collections::HashMap;
use std::path::Path;

use gltf_json as json;
use json::accessor::Type;
use json::mesh::{Mode, Semantic};
use json::validation::Checked;

use super::obj::MeshData;
use crate::error::{PeltError, Result};
use accessor::Components;
use container::Document;

/// Color of vertices whose primitive has no `COLOR_0`, when another primitive of the node has
/// one: white, which leaves the texture's color as it is.
const WHITE: [f32; 4] = [1.0; 4];

/// Most objects (nodes with a mesh) baked from one file: each is a bake of its own, so a small
/// file listing thousands would run for hours.
pub const MAX_OBJECTS: usize = 1024;

/// One object of a glTF scene: a node with a mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedMesh {
    /// The node's name, else its mesh's, else `<file stem>.<node index>`; made unique with a
    /// `.<n>` suffix.
    pub name: String,
    /// The welded triangles in world space.
    pub mesh: MeshData,
}

/// Reads every node with a mesh of the default scene (or of the whole node graph when the file
/// has no scene) of the glTF file at `path`.
///
/// # Errors
/// [`PeltError::Io`] when the file (or a buffer file) cannot be read;
/// [`PeltError::InvalidParameter`] naming the file when it is not valid glTF 2.0, uses what Pelt
/// does not read (data URIs, sparse accessors, required extensions such as Draco), stores an
/// attribute in a type glTF does not allow, has an index out of range, or holds no triangles.
pub fn read_gltf(path: &Path) -> Result<Vec<NamedMesh>> {
    let bytes = std::fs::read(path).map_err(|source| PeltError::Io {
        path: path.display().to_string(),
        source,
    })?;
    let stem = path
        .file_stem()
        .map_or_else(|| "mesh".to_string(), |s| s.to_string_lossy().into_owned());
    parse_gltf(path, &bytes, &stem).map_err(|reason| PeltError::parameter(path.display().to_string(), reason))
}

/// [`read_gltf`] on bytes already read; `path` locates external buffers, `stem` names unnamed
/// nodes. Errors are messages without the file name.
fn parse_gltf(path: &Path, bytes: &[u8], stem: &str) -> std::result::Result<Vec<NamedMesh>, String> {
    let doc = container::parse(path, bytes)?;
    let mut objects = Vec::new();
    let mut names: HashMap<String, usize> = HashMap::new();
    for (node, mesh, transform) in mesh_instances(&doc.root)? {
        let data = read_mesh(&doc, mesh, &transform)?;
        let Some(data) = data else { continue };
        let base = doc
            .root
            .nodes
            .get(node.unwrap_or(usize::MAX))
            .and_then(|n| n.name.clone());
        let base = base
            .or_else(|| doc.root.meshes.get(mesh).and_then(|m| m.name.clone()))
            .unwrap_or_else(|| format!("{stem}.{}", node.unwrap_or(mesh)));
        let seen = names.entry(base.clone()).or_insert(0);
        *seen += 1;
        let name = if *seen == 1 {
            base
        } else {
            format!("{base}.{}", *seen - 1)
        };
        objects.push(NamedMesh { name, mesh: data });
    }
    if objects.is_empty() {
        return Err("the file holds no triangle mesh".into());
    }
    Ok(objects)
}

/// A column-major 4 × 4 transform.
type Matrix = [f64; 16];

const IDENTITY: Matrix = [
    1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
];

fn multiply(a: &Matrix, b: &Matrix) -> Matrix {
    std::array::from_fn(|i| {
        let (col, row) = (i / 4, i % 4);
        (0..4).map(|k| a[k * 4 + row] * b[col * 4 + k]).sum()
    })
}

/// The node's local transform: its matrix, or translation · rotation · scale.
fn local_transform(node: &json::Node) -> Matrix {
    if let Some(m) = node.matrix {
        return m.map(f64::from);
    }
    let t = node.translation.unwrap_or([0.0; 3]).map(f64::from);
    let [x, y, z, w] = node.rotation.map_or([0.0, 0.0, 0.0, 1.0], |q| q.0).map(f64::from);
    let s = node.scale.unwrap_or([1.0; 3]).map(f64::from);
    let r = [
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y + z * w),
        2.0 * (x * z - y * w),
        2.0 * (x * y - z * w),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z + x * w),
        2.0 * (x * z + y * w),
        2.0 * (y * z - x * w),
        1.0 - 2.0 * (x * x + y * y),
    ];
    [
        r[0] * s[0],
        r[1] * s[0],
        r[2] * s[0],
        0.0,
        r[3] * s[1],
        r[4] * s[1],
        r[5] * s[1],
        0.0,
        r[6] * s[2],
        r[7] * s[2],
        r[8] * s[2],
        0.0,
        t[0],
        t[1],
        t[2],
        1.0,
    ]
}

/// `(node, mesh, world transform)` of every mesh instance in scene order (depth first); without
/// nodes, every mesh once with the identity.
///
/// glTF node hierarchies are disjoint trees (specification §3.5.3: a node has at most one parent,
/// a scene lists only roots, each once), so every node is visited at most once and a file cannot
/// multiply its instances by sharing children; one that breaks the rule is refused.
fn mesh_instances(root: &json::Root) -> std::result::Result<Vec<(Option<usize>, usize, Matrix)>, String> {
    if root.nodes.is_empty() {
        if root.meshes.len() > MAX_OBJECTS {
            return Err(format!(
                "the file has {} meshes, more than the {MAX_OBJECTS} Pelt bakes from one file",
                root.meshes.len()
            ));
        }
        return Ok((0..root.meshes.len()).map(|m| (None, m, IDENTITY)).collect());
    }
    let mut parent: Vec<Option<usize>> = vec![None; root.nodes.len()];
    for (p, node) in root.nodes.iter().enumerate() {
        for c in node.children.iter().flatten().map(|c| c.value()) {
            let slot = parent
                .get_mut(c)
                .ok_or_else(|| format!("node {p} lists child {c}, which does not exist"))?;
            match slot.replace(p) {
                Some(first) if first == p => return Err(format!("node {p} lists child {c} twice")),
                Some(first) => {
                    return Err(format!(
                        "node {c} is a child of both node {first} and node {p}; glTF node hierarchies are trees"
                    ));
                }
                None => {}
            }
        }
    }
    let scene = root
        .scene
        .map(|s| s.value())
        .or((!root.scenes.is_empty()).then_some(0));
    let tops: Vec<usize> = match scene.and_then(|s| root.scenes.get(s)) {
        Some(scene) => {
            let tops: Vec<usize> = scene.nodes.iter().map(|n| n.value()).collect();
            let mut listed = vec![false; root.nodes.len()];
            for &n in &tops {
                match (listed.get_mut(n), parent.get(n)) {
                    (None, _) => return Err(format!("the scene lists node {n}, which does not exist")),
                    (Some(true), _) => return Err(format!("the scene lists node {n} twice")),
                    (_, Some(Some(p))) => {
                        return Err(format!("the scene lists node {n}, which is a child of node {p}"));
                    }
                    (Some(seen), _) => *seen = true,
                }
            }
            tops
        }
        // No scene: the nodes nobody lists as a child.
        None => (0..root.nodes.len()).filter(|&n| parent[n].is_none()).collect(),
    };
    let mut out = Vec::new();
    let mut visited = vec![false; root.nodes.len()];
    // Depth-first with an explicit stack, so a deep hierarchy cannot overflow the call stack.
    let mut stack: Vec<(usize, Matrix)> = tops.into_iter().rev().map(|n| (n, IDENTITY)).collect();
    while let Some((n, parent)) = stack.pop() {
        // One parent per node and roots without one leave a cycle as the only way back.
        if std::mem::replace(&mut visited[n], true) {
            return Err("the node hierarchy has a cycle".into());
        }
        let node = &root.nodes[n];
        let world = multiply(&parent, &local_transform(node));
        if let Some(mesh) = node.mesh {
            out.push((Some(n), mesh.value(), world));
            if out.len() > MAX_OBJECTS {
                return Err(format!(
                    "the scene has more than {MAX_OBJECTS} mesh instances, the most Pelt bakes from one file"
                ));
            }
        }
        for c in node.children.iter().flatten().rev() {
            stack.push((c.value(), world));
        }
    }
    Ok(out)
}

/// The triangle corners of a primitive of `mode` over `corners` vertex references.
fn triangle_corners(mode: Mode, corners: &[u32]) -> Vec<[u32; 3]> {
    let n = corners.len();
    match mode {
        Mode::Triangles => corners.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .map(|i| {
                // Every other triangle of a strip is reversed to keep one winding.
                if i % 2 == 0 {
                    [corners[i], corners[i + 1], corners[i + 2]]
                } else {
                    [corners[i + 1], corners[i], corners[i + 2]]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..n.saturating_sub(1))
            .map(|i| [corners[0], corners[i], corners[i + 1]])
            .collect(),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => Vec::new(),
    }
}

/// Pelt's glTF extension, which the engine export writes (`export::gltf::EXTENSION`).
pub const FUR_EXTENSION: &str = "PELT_shell_fur";

/// The primitives of `mesh` that a `PELT_shell_fur` primitive lists as its fallback: shells that
/// stand in for the fur, not part of the surface.
fn fur_fallbacks(mesh: &json::Mesh) -> Vec<usize> {
    mesh.primitives
        .iter()
        .filter_map(|p| {
            let fur = p.extensions.as_ref()?.others.get(FUR_EXTENSION)?;
            Some(fur.get("fallback")?.as_array()?.clone())
        })
        .flatten()
        .filter_map(|v| v.as_u64())
        .map(|v| v as usize)
        .collect()
}

/// The welded triangles of mesh `mesh` under `transform`, or `None` when it has none.
fn read_mesh(
    doc: &Document,
    mesh: usize,
    transform: &Matrix,
) -> std::result::Result<Option<MeshData>, String> {
    let gltf_mesh = doc
        .root
        .meshes
        .get(mesh)
        .ok_or_else(|| format!("mesh {mesh} does not exist"))?;
    let mut positions: Vec<[f32; 3]> = Vec::new();
    let mut colors: Vec<Option<[f32; 4]>> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let stand_ins = fur_fallbacks(gltf_mesh);
    for (p, primitive) in gltf_mesh.primitives.iter().enumerate() {
        if stand_ins.contains(&p) {
            continue;
        }
        let what = |attr: &str| format!("mesh {mesh} primitive {p} {attr}");
        let Checked::Valid(mode) = primitive.mode else {
            return Err(format!("{} has an unknown mode", what("")));
        };
        if matches!(
            mode,
            Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip
        ) {
            continue;
        }
        let position = primitive
            .attributes
            .get(&Checked::Valid(Semantic::Positions))
            .ok_or_else(|| format!("{} is missing", what("POSITION")))?;
        let (_, xyz) = accessor::read(
            doc,
            *position,
            &what("POSITION"),
            &[(Type::Vec3, 3)],
            Components::Float,
        )?;
        let count = xyz.len() / 3;
        let color = match primitive.attributes.get(&Checked::Valid(Semantic::Colors(0))) {
            Some(&c) => {
                let (dims, rgba) = accessor::read(
                    doc,
                    c,
                    &what("COLOR_0"),
                    &[(Type::Vec3, 3), (Type::Vec4, 4)],
                    Components::FloatOrUnorm,
                )?;
                if rgba.len() / dims != count {
                    return Err(format!(
                        "{} has {} elements but POSITION has {count}",
                        what("COLOR_0"),
                        rgba.len() / dims
                    ));
                }
                Some((dims, rgba))
            }
            None => None,
        };
        let corners: Vec<u32> = match primitive.indices {
            Some(i) => {
                let (_, idx) =
                    accessor::read(doc, i, &what("indices"), &[(Type::Scalar, 1)], Components::Index)?;
                if let Some(bad) = idx.iter().find(|&&v| v >= count as f64) {
                    return Err(format!(
                        "{} refers to vertex {bad}, but POSITION has {count}",
                        what("indices")
                    ));
                }
                idx.into_iter().map(|v| v as u32).collect()
            }
            None => (0..count as u32).collect(),
        };
        let base = u32::try_from(positions.len())
            .ok()
            .filter(|b| b.checked_add(count as u32).is_some() && count <= u32::MAX as usize)
            .ok_or_else(|| format!("mesh {mesh} has more vertices than 32-bit indices address"))?;
        for k in 0..count {
            let p = [xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]];
            let world: [f64; 3] = std::array::from_fn(|r| {
                (0..3).map(|c| transform[c * 4 + r] * p[c]).sum::<f64>() + transform[12 + r]
            });
            let world = world.map(|v| v as f32);
            // A NaN in the file, or a transform that carries a vertex past float32's range.
            if world.iter().any(|c| !c.is_finite()) {
                return Err(format!(
                    "{} element {k} is {p:?} in the file, {world:?} in world space: not finite",
                    what("POSITION")
                ));
            }
            positions.push(world);
            colors.push(color.as_ref().map(|(dims, rgba)| {
                let c = &rgba[dims * k..dims * (k + 1)];
                [c[0], c[1], c[2], if *dims == 4 { c[3] } else { 1.0 }].map(|v| v as f32)
            }));
        }
        triangles.extend(
            triangle_corners(mode, &corners)
                .into_iter()
                .map(|t| t.map(|v| v + base)),
        );
    }
    if triangles.is_empty() {
        return Ok(None);
    }
    Ok(Some(weld(positions, colors, triangles)))
}

/// Merges vertices with bit-identical positions (−0 folded into +0); the first vertex of each
/// group (in file order) keeps its place and color. Deterministic: groups are found by sorting.
fn weld(positions: Vec<[f32; 3]>, colors: Vec<Option<[f32; 4]>>, triangles: Vec<[u32; 3]>) -> MeshData {
    let key = |p: [f32; 3]| p.map(|c| (c + 0.0).to_bits());
    let mut order: Vec<u32> = (0..positions.len() as u32).collect();
    order.sort_by_key(|&i| (key(positions[i as usize]), i));
    let mut representative = vec![0u32; positions.len()];
    for (k, &i) in order.iter().enumerate() {
        let first = if k > 0 && key(positions[order[k - 1] as usize]) == key(positions[i as usize]) {
            representative[order[k - 1] as usize]
        } else {
            i
        };
        representative[i as usize] = first;
    }
    let mut new_index = vec![u32::MAX; positions.len()];
    let mut welded = Vec::new();
    let mut welded_colors = Vec::new();
    for (i, &p) in positions.iter().enumerate() {
        if representative[i] as usize == i {
            new_index[i] = welded.len() as u32;
            welded.push(p);
            welded_colors.push(colors[i]);
        }
    }
    let any_color = welded_colors.iter().any(Option::is_some);
    let triangles: Vec<[u32; 3]> = triangles
        .into_iter()
        .map(|t| t.map(|v| new_index[representative[v as usize] as usize]))
        .collect();
    MeshData {
        positions: welded,
        polygons: (0..triangles.len() as u32).collect(),
        triangles,
        color: any_color.then(|| welded_colors.into_iter().map(|c| c.unwrap_or(WHITE)).collect()),
    }
}

#[cfg(test)]
mod tests;
