//! Per-face setup shared by growth, parameterization and quality: each furred face's frame
//! aligned to the direction field, its corners in that frame, its area-weighted hat-function
//! gradients, and the growth units (whole polygons).
//!
//! The frame's first axis is the field direction in the face plane, so the target Jacobian of
//! every face (texture u along the field, one tile per `tile_size`) is the same `I / tile_size`
//! in face coordinates (Praun et al. 2000, §4.2: the patch is parameterized so that the
//! texture's axes follow the tangent field).

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::mesh::{FurMesh, NO_EDGE, orthonormal_basis};

/// Marks a face that belongs to no unit (bald).
pub(super) const NO_UNIT: u32 = u32::MAX;

/// Widens an f32 vector to f64.
fn wide(a: [f32; 3]) -> DVec3 {
    Vec3::from(a).as_dvec3()
}

fn unit_or(v: DVec3, fallback: Option<DVec3>) -> Option<DVec3> {
    let l = v.length();
    if l > 0.0 && l.is_finite() {
        Some(v / l)
    } else {
        fallback
    }
}

/// One face in its field-aligned frame.
#[derive(Debug, Clone, Copy)]
pub(super) struct Face {
    /// Area (0 for a degenerate face, which then carries no weight).
    pub area: f64,
    /// Corners in the frame (field direction, normal × field direction), centroid at 0.
    pub corners: [[f64; 2]; 3],
    /// Area times the gradient of each corner's hat function, in the frame.
    pub grad_area: [[f64; 2]; 3],
    /// How well the field's direction is defined here, in `[MIN_CONFIDENCE, 1]`: the mean
    /// strength of the smoothest field at the corners relative to [`FULL_STRENGTH`]. It falls
    /// towards singularities, where no patch can follow the field closely.
    pub confidence: f64,
}

/// Field strength (see [`crate::field::DirectionField::strength`]) at and above which a face's
/// direction counts as fully defined. The strength of the unpainted field is the length of
/// "down" in the tangent plane, so 0.25 is a surface tilted 15° from horizontal.
pub(super) const FULL_STRENGTH: f64 = 0.25;
/// Smallest confidence, so that no face is ignored entirely.
pub(super) const MIN_CONFIDENCE: f64 = 0.05;

impl Face {
    /// Entries `A ∇φ_iᵀ diag(w) ∇φ_j` of the face's stiffness, ordered 00, 11, 22, 01, 12, 20:
    /// the cotangent stiffness for `w = [1, 1]`, an anisotropic one otherwise.
    pub(super) fn stiffness(&self, w: [f64; 2]) -> [f64; 6] {
        if self.area <= 0.0 {
            return [0.0; 6];
        }
        let g = self.grad_area;
        let d = |i: usize, j: usize| (w[0] * g[i][0] * g[j][0] + w[1] * g[i][1] * g[j][1]) / self.area;
        [d(0, 0), d(1, 1), d(2, 2), d(0, 1), d(1, 2), d(2, 0)]
    }
}

/// Normal and the field at the centroid of face `f`: the mean of the unnormalized field at the
/// corners (direction × strength), so that a corner on a parting (where the field passes through
/// zero between opposite directions) does not pull the face to the wrong side.
fn normal_and_field(mesh: &FurMesh, f: usize, direction: &[[f32; 3]], strength: &[f32]) -> (DVec3, DVec3) {
    let tri = mesh.triangles()[f];
    let p = tri.map(|v| wide(mesh.positions()[v as usize]));
    let vertex_normals = tri
        .iter()
        .map(|&v| wide(mesh.normals()[v as usize]))
        .fold(DVec3::ZERO, |s, n| s + n);
    let normal = (!mesh.degenerate_faces()[f])
        .then(|| unit_or((p[1] - p[0]).cross(p[2] - p[0]), None))
        .flatten()
        .or_else(|| unit_or(vertex_normals, None))
        .unwrap_or(DVec3::Z);
    let field = DVec3::from_array([0, 1, 2].map(|k| {
        tri.iter()
            .map(|&v| f64::from(strength[v as usize]).max(0.0) * f64::from(direction[v as usize][k]))
            .sum::<f64>()
            / 3.0
    }));
    (normal, field)
}

/// Frames of all faces; `direction` and `strength` are the per-vertex field. The faces of one
/// unit (polygon) share one target direction, the area-weighted mean of their fields, so that a
/// polygon straddling a parting is not torn between opposite targets.
pub(super) fn frames(mesh: &FurMesh, direction: &[[f32; 3]], strength: &[f32], units: &Units) -> Vec<Face> {
    let fields: Vec<(DVec3, DVec3)> = (0..mesh.face_count())
        .into_par_iter()
        .map(|f| normal_and_field(mesh, f, direction, strength))
        .collect();
    let area_of = |f: usize| {
        let p = mesh.triangles()[f].map(|v| wide(mesh.positions()[v as usize]));
        (p[1] - p[0]).cross(p[2] - p[0]).length() / 2.0
    };
    let unit_field: Vec<DVec3> = (0..units.len() as u32)
        .into_par_iter()
        .map(|u| {
            // The area-weighted mean, dimensionless like the other candidates below.
            let (sum, total) = units.faces(u).iter().fold((DVec3::ZERO, 0.0), |(s, t), &f| {
                let (a, v) = (area_of(f as usize), fields[f as usize].1);
                (s + a * v, t + a)
            });
            if total > 0.0 { sum / total } else { sum }
        })
        .collect();
    (0..mesh.face_count())
        .into_par_iter()
        .map(|f| {
            let tri = mesh.triangles()[f];
            let p = tri.map(|v| wide(mesh.positions()[v as usize]));
            let degenerate = mesh.degenerate_faces()[f];
            let (normal, field) = fields[f];
            let in_plane = |d: DVec3| d - d.dot(normal) * normal;
            let dirs = tri.map(|v| wide(direction[v as usize]));
            let sum = dirs[0] + dirs[1] + dirs[2];
            let unit = units.of_face[f];
            let shared = if unit == NO_UNIT {
                field
            } else {
                unit_field[unit as usize]
            };
            // At a singularity the directions cancel; then any one of them will do.
            let along = [shared, field, sum]
                .into_iter()
                .chain(dirs)
                .map(in_plane)
                .find(|d| d.length_squared() > 1e-12)
                .and_then(|d| unit_or(d, None))
                .unwrap_or_else(|| {
                    let [t, _] = orthonormal_basis(normal.as_vec3().to_array());
                    wide(t)
                });
            let across = normal.cross(along);
            let centroid = (p[0] + p[1] + p[2]) / 3.0;
            let corners = p.map(|q| {
                let r = q - centroid;
                [r.dot(along), r.dot(across)]
            });
            let (area, grad_area) = if degenerate {
                (0.0, [[0.0; 2]; 3])
            } else {
                let [a, b, c] = corners;
                let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
                // A ∇φ_i = perp(x_{i+2} − x_{i+1}) / 2, perp rotating by +90°.
                let g = |i: usize| {
                    let (from, to) = (corners[(i + 1) % 3], corners[(i + 2) % 3]);
                    [-(to[1] - from[1]) / 2.0, (to[0] - from[0]) / 2.0]
                };
                (area.max(0.0), [g(0), g(1), g(2)])
            };
            let mean_strength = tri.iter().map(|&v| f64::from(strength[v as usize])).sum::<f64>() / 3.0;
            Face {
                area,
                corners,
                grad_area,
                confidence: (mean_strength / FULL_STRENGTH).clamp(MIN_CONFIDENCE, 1.0),
            }
        })
        .collect()
}

/// Faces grouped into growth units: the furred triangles of one polygon (or each furred
/// triangle alone when no polygons are given). Bald faces belong to none.
pub(super) struct Units {
    offsets: Vec<u32>,
    faces: Vec<u32>,
    /// Unit of each face, or [`NO_UNIT`].
    pub of_face: Vec<u32>,
}

impl Units {
    pub(super) fn build(mesh: &FurMesh, bald: &[bool]) -> Self {
        let furred: Vec<u32> = (0..mesh.face_count() as u32)
            .filter(|&f| !bald[f as usize])
            .collect();
        let mut of_face = vec![NO_UNIT; mesh.face_count()];
        let (offsets, faces) = match mesh.polygons() {
            None => {
                for (u, &f) in furred.iter().enumerate() {
                    of_face[f as usize] = u as u32;
                }
                ((0..=furred.len() as u32).collect(), furred)
            }
            Some(polygons) => {
                let mut keyed: Vec<(u32, u32)> = furred.iter().map(|&f| (polygons[f as usize], f)).collect();
                keyed.sort_unstable();
                let mut offsets = vec![0u32];
                for (i, &(polygon, f)) in keyed.iter().enumerate() {
                    if i > 0 && keyed[i - 1].0 != polygon {
                        offsets.push(i as u32);
                    }
                    of_face[f as usize] = (offsets.len() - 1) as u32;
                }
                offsets.push(keyed.len() as u32);
                if keyed.is_empty() {
                    offsets.truncate(1);
                }
                (offsets, keyed.into_iter().map(|(_, f)| f).collect())
            }
        };
        Units {
            offsets,
            faces,
            of_face,
        }
    }

    /// Number of units.
    pub(super) fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Faces of unit `u`, in increasing order.
    pub(super) fn faces(&self, u: u32) -> &[u32] {
        &self.faces[self.offsets[u as usize] as usize..self.offsets[u as usize + 1] as usize]
    }
}

/// Faces across the sides of face `f` that a patch may grow into: across a manifold edge whose
/// two faces agree in orientation (a patch must not fold over onto itself), or any face across
/// an edge when one of the two has zero area (it carries no weight, so it cannot fold).
pub(super) fn neighbours(mesh: &FurMesh, f: u32, out: &mut Vec<u32>) {
    out.clear();
    let topology = mesh.topology();
    let tri = mesh.triangles()[f as usize];
    let degenerate = mesh.degenerate_faces();
    for c in 0..3 {
        let edge = topology.face_edges()[f as usize][c];
        if edge == NO_EDGE {
            continue;
        }
        let (a, b) = (tri[c], tri[(c + 1) % 3]);
        let e = topology.edges()[edge as usize];
        if e.face_count == 2 {
            let g = if e.faces[0] == f { e.faces[1] } else { e.faces[0] };
            if g == f {
                continue;
            }
            let other = mesh.triangles()[g as usize];
            // g runs the shared edge b→a when the two agree in orientation.
            let agrees = (0..3).any(|k| other[k] == b && other[(k + 1) % 3] == a);
            if agrees || degenerate[f as usize] || degenerate[g as usize] {
                out.push(g);
            }
        } else if e.face_count > 2 {
            for &g in topology.vertex_faces(a as usize) {
                let uses_b = mesh.triangles()[g as usize].contains(&b);
                if g != f && uses_b && (degenerate[f as usize] || degenerate[g as usize]) {
                    out.push(g);
                }
            }
        }
    }
}
