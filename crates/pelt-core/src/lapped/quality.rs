//! Quality figures of a patch layout (Lengyel et al. 2001 §2.1 and Praun et al. 2000 §4.2 judge
//! a patch by how well its texture follows the field and how little it stretches): per face the
//! angle between the field and the surface image of the texture's u axis and the singular values
//! of the Jacobian relative to the target scale; over the mesh flipped faces, coverage, seam
//! length and area-weighted summaries.

use rayon::prelude::*;
use serde::Serialize;

use super::faces::Face;
use crate::mesh::FurMesh;
use crate::threads::deterministic_sum;

/// Singular values and orientation of one face's Jacobian.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct FaceMetrics {
    /// Largest and smallest singular value (1 = target scale).
    pub sigma: [f64; 2],
    /// Determinant: ≤ 0 means the face is flipped (or collapsed) in the texture.
    pub det: f64,
    /// Angle between the field (the frame's first axis) and the preimage of the u axis, radians.
    pub alignment: f64,
}

impl FaceMetrics {
    /// Whether the face is flipped or collapsed in the texture (or its Jacobian is not finite).
    pub(super) fn flipped(&self) -> bool {
        self.det.is_nan() || self.det <= 0.0
    }
}

/// Metrics of the Jacobian whose rows are `∇u` and `∇v` in the face's field frame.
pub(super) fn metrics(gradients: [[f64; 2]; 2]) -> FaceMetrics {
    let [[a, b], [c, d]] = gradients;
    // Closed-form 2×2 singular values: σ = |q| ± |r| for the conformal and anticonformal parts.
    let q = ((a + d) / 2.0).hypot((c - b) / 2.0);
    let r = ((a - d) / 2.0).hypot((c + b) / 2.0);
    let det = a * d - b * c;
    // The u axis maps back to J⁻¹ e_u = (d, −c) / det.
    let alignment = if det < 0.0 { c.atan2(-d) } else { (-c).atan2(d) }.abs();
    FaceMetrics {
        sigma: [q + r, (q - r).abs()],
        det,
        alignment,
    }
}

/// Figures of a whole layout (serializable for reports).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PatchQuality {
    /// Number of patches.
    pub patch_count: usize,
    /// Faces that are not bald (some vertex has a nonzero length).
    pub furred_faces: usize,
    /// Share of the furred faces that lie in a patch (1 when every one does).
    pub coverage: f64,
    /// Furred faces of nonzero area whose texture image is flipped or collapsed.
    pub flipped_faces: usize,
    /// Area-weighted mean of the per-face alignment error, degrees.
    pub mean_alignment_deg: f64,
    /// Share of the furred area whose two singular values both lie in `[0.8, 1.25]`.
    pub stretch_within_fraction: f64,
    /// Length of the edges between two patches over the length of all edges of furred faces.
    pub seam_length_fraction: f64,
    /// Number of singular faces of the direction field.
    pub singularities: usize,
    /// Per face: the angle between the field and the surface image of the texture's u axis,
    /// degrees (0 for bald and zero-area faces).
    pub face_alignment_deg: Vec<f32>,
    /// Per face: largest and smallest singular value of the Jacobian relative to the target
    /// scale, `[1, 1]` for bald and zero-area faces.
    pub face_stretch: Vec<[f32; 2]>,
}

/// Range of the "within" stretch figure, as the acceptance criterion states it.
pub const STRETCH_WITHIN: [f64; 2] = [0.8, 1.25];

/// Measures the layout `uv` (tile units, per corner) / `patch` (per face) of `mesh`.
#[allow(clippy::too_many_arguments)]
pub(super) fn measure(
    mesh: &FurMesh,
    faces: &[Face],
    bald: &[bool],
    uv: &[[[f32; 2]; 3]],
    patch: &[u32],
    tile_size: f64,
    patch_count: usize,
    singularities: usize,
) -> PatchQuality {
    let per_face: Vec<Option<FaceMetrics>> = (0..mesh.face_count())
        .into_par_iter()
        .map(|f| {
            let face = &faces[f];
            if bald[f] || face.area <= 0.0 || patch[f] == u32::MAX {
                return None;
            }
            // Back to world units: the target Jacobian is then the identity.
            let gradients = [0, 1].map(|k| {
                let mut g = [0.0; 2];
                for (corner, grad) in uv[f].iter().zip(face.grad_area) {
                    let x = f64::from(corner[k]) * tile_size;
                    g[0] += x * grad[0];
                    g[1] += x * grad[1];
                }
                [g[0] / face.area, g[1] / face.area]
            });
            Some(metrics(gradients))
        })
        .collect();
    let n = mesh.face_count();
    let furred_area = deterministic_sum(n, |f| if bald[f] { 0.0 } else { faces[f].area });
    let weighted = |g: &(dyn Fn(&FaceMetrics) -> f64 + Sync)| {
        deterministic_sum(n, |f| per_face[f].as_ref().map_or(0.0, |m| faces[f].area * g(m)))
    };
    let share = |x: f64| if furred_area > 0.0 { x / furred_area } else { 0.0 };
    let mean_alignment_deg = share(weighted(&|m| m.alignment)).to_degrees();
    let within = |m: &FaceMetrics| {
        let ok = !m.flipped() && m.sigma[1] >= STRETCH_WITHIN[0] && m.sigma[0] <= STRETCH_WITHIN[1];
        if ok { 1.0 } else { 0.0 }
    };
    let stretch_within_fraction = if furred_area > 0.0 {
        share(weighted(&within))
    } else {
        1.0
    };
    let furred_faces = bald.iter().filter(|&&b| !b).count();
    let covered = (0..n).filter(|&f| !bald[f] && patch[f] != u32::MAX).count();
    PatchQuality {
        patch_count,
        furred_faces,
        coverage: if furred_faces > 0 {
            covered as f64 / furred_faces as f64
        } else {
            1.0
        },
        flipped_faces: per_face.iter().flatten().filter(|m| m.flipped()).count(),
        mean_alignment_deg,
        stretch_within_fraction,
        seam_length_fraction: seam_fraction(mesh, bald, patch),
        singularities,
        face_alignment_deg: per_face
            .iter()
            .map(|m| m.map_or(0.0, |m| m.alignment.to_degrees() as f32))
            .collect(),
        face_stretch: per_face
            .iter()
            .map(|m| m.map_or([1.0, 1.0], |m| m.sigma.map(|s| s as f32)))
            .collect(),
    }
}

/// Seam length over the length of all edges that touch a furred face. An edge is a seam when at
/// least two furred faces meet there and not all of them lie in one patch.
fn seam_fraction(mesh: &FurMesh, bald: &[bool], patch: &[u32]) -> f64 {
    let topology = mesh.topology();
    let edges = topology.edges();
    let classify = |e: usize| -> (f64, bool) {
        let edge = edges[e];
        let [a, b] = edge.vertices();
        let (pa, pb) = (mesh.positions()[a as usize], mesh.positions()[b as usize]);
        let length = f64::from(pa[0] - pb[0])
            .hypot(f64::from(pa[1] - pb[1]))
            .hypot(f64::from(pa[2] - pb[2]));
        let mut furred = topology
            .vertex_faces(a as usize)
            .iter()
            .filter(|&&f| mesh.triangles()[f as usize].contains(&b) && !bald[f as usize]);
        let Some(&first) = furred.next() else {
            return (0.0, false);
        };
        let mut seam = false;
        let mut others = 0;
        for &f in furred {
            others += 1;
            seam |= patch[f as usize] != patch[first as usize];
        }
        (length, others > 0 && seam)
    };
    let total = deterministic_sum(edges.len(), |e| classify(e).0);
    let seams = deterministic_sum(edges.len(), |e| {
        let (length, seam) = classify(e);
        if seam { length } else { 0.0 }
    });
    if total > 0.0 { seams / total } else { 0.0 }
}
