//! The guard hairs as the strand pass reads them (hybrid-fur-volume-and-strands §3): each strand
//! tied to its root triangle's skin vertices, its points kept in the frame the surface has at
//! the root (origin, the tangent along `∂P/∂u`, the bitangent, the normal), so that a pose
//! carries the strands rigidly with the surface under them: [`root_frames`] makes the frames
//! anew from the posed skin vertices (once per strand on the CPU, where the vertex shader would
//! make them once per corner).

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use rayon::prelude::*;

use pelt_core::error::{Num, PeltError, Result};
use pelt_core::guard::MAX_GUARD_STRANDS;
use pelt_core::hair::MAX_SEGMENTS;
use pelt_core::placement::PlacedStrands;
use pelt_core::scene::surface_mesh::SurfaceVertex;
use pelt_core::threads::pool;

/// Random stream of the strands' LOD ranks.
const RANK_STREAM: u64 = 0x726f_6f74;

/// One strand as `GuardStrand` in `strands.wgsl` reads it.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub(super) struct GpuStrand {
    /// The root triangle's skin vertices and the strand's first point.
    pub corners: [u32; 4],
    /// The root's barycentric weights and the length multiplier there.
    pub shape: [f32; 4],
    /// Linear albedo at the root, and the strand's LOD rank in `[0, 1)`.
    pub root_color: [f32; 4],
    /// Linear albedo at the tip, and the strand's point count.
    pub tip_color: [f32; 4],
}

/// The guard hairs ready to upload.
#[derive(Debug)]
pub(super) struct GuardStrands {
    pub strands: Vec<GpuStrand>,
    /// Per point: its place in the root frame `(t, b, n)`, object units, and its radius.
    pub points: Vec<[f32; 4]>,
    /// Segments of the longest strand (every strand is drawn with this many, the shorter ones'
    /// extra segments dropped by the vertex shader).
    pub segments: u32,
    /// The thickest root's radius, object units.
    pub root_radius: f32,
}

/// A unit vector perpendicular to `n`, for a root where `∂P/∂u` gives no tangent.
fn perpendicular(n: Vec3) -> Vec3 {
    let axis = if n.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    n.cross(axis).normalize()
}

/// The frame `(origin, t, b, n)` at barycentric `w` of the skin vertices `ids`.
pub(super) fn root_frame(vertices: &[SurfaceVertex], ids: [u32; 3], w: [f32; 3]) -> [Vec3; 4] {
    let sum = |f: fn(&SurfaceVertex) -> [f32; 3]| {
        (0..3).fold(Vec3::ZERO, |acc, k| {
            acc + w[k] * Vec3::from(f(&vertices[ids[k] as usize]))
        })
    };
    let origin = sum(|v| v.position);
    let n = sum(|v| v.normal).try_normalize().unwrap_or(Vec3::Z);
    let d = sum(|v| v.dpdu);
    let t = (d - n * n.dot(d))
        .try_normalize()
        .unwrap_or_else(|| perpendicular(n));
    [origin, t, n.cross(t), n]
}

/// Each strand's root frame over the skin `vertices` as `GuardFrame` in `strands.wgsl` reads it:
/// origin, tangent and normal (the bitangent is their cross product), `w` 0.
pub(super) fn root_frames(vertices: &[SurfaceVertex], strands: &[GpuStrand]) -> Vec<[[f32; 4]; 3]> {
    pool().install(|| {
        strands
            .par_iter()
            .map(|s| {
                let ids = [s.corners[0], s.corners[1], s.corners[2]];
                let w = [s.shape[0], s.shape[1], s.shape[2]];
                let [origin, t, _, n] = root_frame(vertices, ids, w);
                [origin.extend(0.0), t.extend(0.0), n.extend(0.0)].map(|v| v.to_array())
            })
            .collect()
    })
}

/// Checks `strands` against a scene of `triangles` triangles and puts them in their root frames
/// over the rest skin `vertices` (`indices`: three per triangle); `lengths` are the surface
/// vertices' length multipliers.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `guard_hairs` (more than [`MAX_GUARD_STRANDS`]
/// strands, or a strand of more than [`MAX_SEGMENTS`] segments), `guard_hairs.spans[i]` (a root
/// off the mesh, points outside the point list, weights not finite) or
/// `guard_hairs.points[i]` (a coordinate not finite, a radius not positive and finite).
pub(super) fn prepare(
    placed: &PlacedStrands,
    vertices: &[SurfaceVertex],
    indices: &[u32],
    lengths: &[f32],
) -> Result<GuardStrands> {
    let spans = &placed.spans;
    if spans.len() > MAX_GUARD_STRANDS {
        return Err(PeltError::parameter(
            "guard_hairs",
            format!(
                "holds {} strands, at most {MAX_GUARD_STRANDS}: bake fewer (lower guard_share)",
                spans.len()
            ),
        ));
    }
    let triangles = indices.len() / 3;
    for (i, s) in spans.iter().enumerate() {
        let fault = if (s.triangle as usize) >= triangles {
            Some(format!(
                "stands on triangle {}, the scene has {triangles}",
                s.triangle
            ))
        } else if s.count < 2 || s.count > MAX_SEGMENTS + 1 {
            Some(format!(
                "has {} points, must have [2, {}]",
                s.count,
                MAX_SEGMENTS + 1
            ))
        } else if (s.first as usize).saturating_add(s.count as usize) > placed.points.len() {
            Some(format!("runs past the {} points", placed.points.len()))
        } else if !s.weights.iter().all(|w| w.is_finite())
            || !s.root_color.is_finite()
            || !s.tip_color.is_finite()
        {
            Some("has a weight or color that is not finite".to_string())
        } else {
            None
        };
        if let Some(fault) = fault {
            return Err(PeltError::parameter(format!("guard_hairs.spans[{i}]"), fault));
        }
    }
    if let Some(i) = placed
        .points
        .iter()
        .position(|p| !(p.iter().all(|v| v.is_finite()) && p[3] > 0.0))
    {
        let p = placed.points[i];
        return Err(PeltError::parameter(
            format!("guard_hairs.points[{i}]"),
            format!(
                "must be finite with a positive radius, got ({}, {}, {}) radius {}",
                Num(f64::from(p[0])),
                Num(f64::from(p[1])),
                Num(f64::from(p[2])),
                Num(f64::from(p[3]))
            ),
        ));
    }
    let segments = spans.iter().map(|s| s.count - 1).max().unwrap_or(0);
    let (strands, points) = pool().install(|| {
        spans
            .par_iter()
            .enumerate()
            .map(|(i, s)| {
                let t = s.triangle as usize;
                let ids = [indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]];
                let [origin, tangent, bitangent, normal] = root_frame(vertices, ids, s.weights);
                let length: f32 = (0..3).map(|k| s.weights[k] * lengths[ids[k] as usize]).sum();
                let first = s.first as usize;
                let local: Vec<[f32; 4]> = placed.points[first..first + s.count as usize]
                    .iter()
                    .map(|p| {
                        let d = Vec3::new(p[0], p[1], p[2]) - origin;
                        [d.dot(tangent), d.dot(bitangent), d.dot(normal), p[3]]
                    })
                    .collect();
                let rank = pelt_core::rng::Rng::stream(0, RANK_STREAM, i as u64).next_f64() as f32;
                let strand = GpuStrand {
                    corners: [ids[0], ids[1], ids[2], 0],
                    shape: [s.weights[0], s.weights[1], s.weights[2], length],
                    root_color: s.root_color.extend(rank).to_array(),
                    tip_color: s.tip_color.extend(s.count as f32).to_array(),
                };
                (strand, local)
            })
            .unzip::<_, _, Vec<_>, Vec<_>>()
    });
    // Rank order (ties by placement order): the LOD keeps a prefix.
    let mut order: Vec<usize> = (0..strands.len()).collect();
    order.sort_by(|&a, &b| {
        strands[a].root_color[3]
            .total_cmp(&strands[b].root_color[3])
            .then(a.cmp(&b))
    });
    let mut first = 0u32;
    let mut sorted = Vec::with_capacity(strands.len());
    let mut sorted_points = Vec::with_capacity(placed.points.len());
    for &i in &order {
        let mut s = strands[i];
        s.corners[3] = first;
        first += points[i].len() as u32;
        sorted_points.extend_from_slice(&points[i]);
        sorted.push(s);
    }
    Ok(GuardStrands {
        root_radius: points.iter().fold(0.0f32, |m, p| m.max(p[0][3])),
        strands: sorted,
        points: sorted_points,
        segments,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vertex(position: [f32; 3]) -> SurfaceVertex {
        SurfaceVertex {
            position,
            normal: [0.0, 0.0, 1.0],
            dpdu: [2.0, 0.0, 0.0],
            dpdv: [0.0, 2.0, 0.0],
            uv: [0.0; 2],
            comb: [0.0; 3],
            border: [0.0; 2],
        }
    }

    #[test]
    fn points_are_kept_in_the_root_frame_and_come_back_from_it() {
        let vertices = [vertex([0.0; 3]), vertex([1.0, 0.0, 0.0]), vertex([0.0, 1.0, 0.0])];
        let placed = PlacedStrands {
            points: vec![[0.25, 0.25, 0.0, 0.01], [0.3, 0.2, 0.5, 0.005]],
            spans: vec![pelt_core::placement::StrandSpan {
                first: 0,
                count: 2,
                root_color: Vec3::ONE,
                tip_color: Vec3::ONE,
                triangle: 0,
                weights: [0.5, 0.25, 0.25],
            }],
        };
        let g = prepare(&placed, &vertices, &[0, 1, 2], &[1.0, 2.0, 2.0]).unwrap();
        assert_eq!(g.segments, 1);
        // The root frame: origin at the root, t along x, b along y, n along z.
        assert_eq!(g.points[0], [0.0, 0.0, 0.0, 0.01]);
        let tip = g.points[1];
        assert!((tip[0] - 0.05).abs() < 1e-6 && (tip[1] + 0.05).abs() < 1e-6);
        assert!((tip[2] - 0.5).abs() < 1e-6);
        assert!((g.strands[0].shape[3] - 1.5).abs() < 1e-6, "length at the root");
        let rank = g.strands[0].root_color[3];
        assert!((0.0..1.0).contains(&rank));
        assert_eq!(g.root_radius, 0.01);
    }

    #[test]
    fn bad_strands_are_refused_by_name() {
        let vertices = [vertex([0.0; 3]), vertex([1.0, 0.0, 0.0]), vertex([0.0, 1.0, 0.0])];
        let span = pelt_core::placement::StrandSpan {
            first: 0,
            count: 2,
            root_color: Vec3::ONE,
            tip_color: Vec3::ONE,
            triangle: 0,
            weights: [1.0, 0.0, 0.0],
        };
        let good = PlacedStrands {
            points: vec![[0.0, 0.0, 0.0, 0.01], [0.0, 0.0, 1.0, 0.01]],
            spans: vec![span],
        };
        type Spoil = fn(&mut PlacedStrands);
        let cases: [(&str, Spoil); 5] = [
            ("guard_hairs.spans[0]", |p| p.spans[0].triangle = 1),
            ("guard_hairs.spans[0]", |p| p.spans[0].count = 3),
            ("guard_hairs.spans[0]", |p| p.spans[0].weights[1] = f32::NAN),
            ("guard_hairs.points[1]", |p| p.points[1][3] = 0.0),
            ("guard_hairs.points[0]", |p| p.points[0][0] = f32::INFINITY),
        ];
        for (name, spoil) in cases {
            let mut bad = good.clone();
            spoil(&mut bad);
            let e = prepare(&bad, &vertices, &[0, 1, 2], &[1.0; 3]).unwrap_err();
            assert!(e.to_string().contains(name), "{e}");
        }
        assert!(prepare(&good, &vertices, &[0, 1, 2], &[1.0; 3]).is_ok());
    }
}
