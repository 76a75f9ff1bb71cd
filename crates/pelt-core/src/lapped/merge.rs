//! Merging small patches into their neighbours after growth.
//!
//! Where big patches meet, their irregular boundaries and the gaps left where a patch could not
//! close a loop strand single faces and short strips between them, which growth turns into tiny
//! patches of their own. A tiny patch joins a neighbour when the neighbour's existing
//! parameterization extends over it within the limits: the neighbour stays as it is, the small
//! patch's vertices that the neighbour already has take the neighbour's UVs, the others are
//! unfolded and relaxed against them (the fast local step of growth), and the merged faces must
//! keep the neighbour within the same limits as growth. This keeps Lengyel et al.'s rule that
//! patches are as large as the tolerance allows (§2.1) without growing them again.

use super::faces::Face;
use super::growth::{Limits, NONE, Sums};
use super::parameterization::{Element, System, stiffness};
use super::quality::metrics;
use crate::mesh::FurMesh;

/// Patches with at most this many faces try to join a neighbour.
const SMALL: usize = 128;
/// Gauss–Seidel sweeps over a small patch's free vertices (they may be several faces deep).
const SWEEPS: usize = 32;

/// Merges small patches of `patch` (per face) / `uv` (per corner, world units) into neighbours;
/// the ids of merged patches are left unused (see `Grown::compact`).
pub(super) fn merge_small(
    mesh: &FurMesh,
    faces: &[Face],
    limits: &Limits,
    patch: &mut [u32],
    uv: &mut [[[f64; 2]; 3]],
    patch_count: usize,
) {
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); patch_count];
    for (f, &p) in patch.iter().enumerate() {
        if p != NONE {
            members[p as usize].push(f as u32);
        }
    }
    let mut sums: Vec<Sums> = members
        .iter()
        .map(|list| {
            list.iter().fold(Sums::default(), |acc, &f| {
                let face = &faces[f as usize];
                if face.area <= 0.0 {
                    return acc;
                }
                let m = metrics(gradients(face, &uv[f as usize]));
                // Faces of a finished patch were accepted already; count them even if a final
                // solve left one just outside a hard limit.
                let s = limits.face(face, &m).unwrap_or(Sums {
                    area: face.area,
                    misaligned: face.area * m.alignment * face.confidence,
                    stretched: face.area,
                });
                acc.add(s)
            })
        })
        .collect();
    let mut order: Vec<u32> = (0..patch_count as u32)
        .filter(|&p| members[p as usize].len() <= SMALL)
        .collect();
    order.sort_by_key(|&p| (members[p as usize].len(), p));
    let mut system = System::default();
    for small in order {
        let small_faces = std::mem::take(&mut members[small as usize]);
        if small_faces.is_empty() {
            continue;
        }
        let mut joined = false;
        for target in neighbours_by_shared_edges(mesh, patch, &small_faces, small) {
            let Some((new_uv, added)) =
                extend(mesh, faces, limits, patch, uv, &small_faces, target, &mut system)
            else {
                continue;
            };
            let total = sums[target as usize].add(added);
            if !limits.within(&total) {
                continue;
            }
            for (&f, corners) in small_faces.iter().zip(new_uv) {
                patch[f as usize] = target;
                uv[f as usize] = corners;
            }
            sums[target as usize] = total;
            members[target as usize].extend_from_slice(&small_faces);
            joined = true;
            break;
        }
        if !joined {
            members[small as usize] = small_faces;
        }
    }
}

/// Gradients of u and v on `face` from its corner UVs.
fn gradients(face: &Face, corners: &[[f64; 2]; 3]) -> [[f64; 2]; 2] {
    [0, 1].map(|k| {
        let mut g = [0.0; 2];
        for (corner, grad) in corners.iter().zip(face.grad_area) {
            g[0] += corner[k] * grad[0];
            g[1] += corner[k] * grad[1];
        }
        [g[0] / face.area, g[1] / face.area]
    })
}

/// Patches sharing an edge with `small_faces`, most shared edges first (then lowest id).
fn neighbours_by_shared_edges(mesh: &FurMesh, patch: &[u32], small_faces: &[u32], small: u32) -> Vec<u32> {
    let topology = mesh.topology();
    let mut shared: Vec<(u32, u32)> = Vec::new();
    for &f in small_faces {
        let tri = mesh.triangles()[f as usize];
        for c in 0..3 {
            let (a, b) = (tri[c], tri[(c + 1) % 3]);
            if a == b {
                continue;
            }
            for &g in topology.vertex_faces(a as usize) {
                let p = patch[g as usize];
                if p != small && p != NONE && mesh.triangles()[g as usize].contains(&b) {
                    match shared.iter_mut().find(|(q, _)| *q == p) {
                        Some((_, n)) => *n += 1,
                        None => shared.push((p, 1)),
                    }
                }
            }
        }
    }
    shared.sort_by_key(|&(p, n)| (std::cmp::Reverse(n), p));
    shared.into_iter().map(|(p, _)| p).collect()
}

/// The UVs `small_faces` get in patch `target` and their sums, or `None` if a face breaks a
/// hard limit or cannot be reached from `target`'s vertices.
#[allow(clippy::too_many_arguments)]
fn extend(
    mesh: &FurMesh,
    faces: &[Face],
    limits: &Limits,
    patch: &[u32],
    uv: &[[[f64; 2]; 3]],
    small_faces: &[u32],
    target: u32,
    system: &mut System,
) -> Option<(Vec<[[f64; 2]; 3]>, Sums)> {
    system.clear();
    // Local vertices: first those `target` has (fixed), then the others (free).
    let mut vertices: Vec<u32> = small_faces
        .iter()
        .flat_map(|&f| mesh.triangles()[f as usize])
        .collect();
    vertices.sort_unstable();
    vertices.dedup();
    let known: Vec<Option<[f64; 2]>> = vertices
        .iter()
        .map(|&v| uv_in(mesh, patch, uv, v, target))
        .collect();
    let mut local = vec![NONE; vertices.len()];
    for (i, k) in known.iter().enumerate() {
        if let Some(x) = k {
            local[i] = system.add_vertex(*x);
        }
    }
    let first_free = system.vertex_count() as u32;
    if first_free == 0 {
        return None;
    }
    let index = |v: u32| vertices.binary_search(&v).unwrap_or(0);
    // Unfold free vertices from placed corners, face by face, until all are placed.
    let mut pending: Vec<u32> = small_faces.to_vec();
    while !pending.is_empty() {
        let before = pending.len();
        pending.retain(|&f| {
            let tri = mesh.triangles()[f as usize];
            let face = &faces[f as usize];
            let Some(c) = (0..3).find(|&c| local[index(tri[c])] != NONE) else {
                return true;
            };
            let l = local[index(tri[c])] as usize;
            let start = [system.uv[0][l], system.uv[1][l]];
            for (&v, corner) in tri.iter().zip(face.corners) {
                let i = index(v);
                if local[i] == NONE {
                    let x = [0, 1].map(|k| start[k] + corner[k] - face.corners[c][k]);
                    local[i] = system.add_vertex(x);
                }
            }
            false
        });
        if pending.len() == before {
            return None;
        }
    }
    let elements: Vec<Element<'_>> = small_faces
        .iter()
        .map(|&f| {
            let tri = mesh.triangles()[f as usize];
            let face = &faces[f as usize];
            (tri.map(|v| local[index(v)]), face, stiffness(face))
        })
        .collect();
    system.relax(first_free, &elements, SWEEPS);
    let mut sums = Sums::default();
    let mut corners = Vec::with_capacity(small_faces.len());
    for (l, face, _) in &elements {
        if face.area > 0.0 {
            sums = sums.add(limits.face(face, &metrics(system.gradients(*l, face)))?);
        }
        corners.push(l.map(|i| [system.uv[0][i as usize], system.uv[1][i as usize]]));
    }
    Some((corners, sums))
}

/// The UV of vertex `v` in patch `target`, if the patch has it.
fn uv_in(mesh: &FurMesh, patch: &[u32], uv: &[[[f64; 2]; 3]], v: u32, target: u32) -> Option<[f64; 2]> {
    mesh.topology().vertex_faces(v as usize).iter().find_map(|&g| {
        if patch[g as usize] != target {
            return None;
        }
        let c = mesh.triangles()[g as usize].iter().position(|&w| w == v)?;
        Some(uv[g as usize][c])
    })
}
