//! Which fins a frame draws (Lengyel et al. 2001, §2.3: "We collect the fins with nonzero alpha
//! and render them"). A fin's fade `max(0, 2|p| − 1)` depends only on its plane and the eye, so
//! the CPU collects the fins it leaves visible into the fin index buffer before the draw: the
//! vertex shader then never runs for the (many) faded-out ones. The shader keeps its own fade
//! test, so this list only has to hold every fin the shader would draw; it errs on the side of
//! keeping a fin, and the image is the same as drawing all of them. The list runs back to
//! front, which the fins' "over" blending needs where they overlap.

use std::ops::Range;

use rayon::prelude::*;

use crate::mesh::quad_triangles;

/// A fin `p` this far under the fade's zero (|p| = 1/2) is still kept, so that rounding in this
/// f32 evaluation, which need not match the shader's bit for bit, never drops a fin the shader
/// draws.
const MARGIN: f32 = 1e-4;

/// Fins per parallel work item: big enough that splitting costs nothing next to the work.
const CHUNK: usize = 4096;

/// Each fin's plane: the point its fade is evaluated at and its unit normal.
#[derive(Debug, Clone, Default)]
pub struct FinPlanes {
    centers: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
}

impl FinPlanes {
    pub fn new(centers: Vec<[f32; 3]>, normals: Vec<[f32; 3]>) -> Self {
        debug_assert_eq!(centers.len(), normals.len());
        FinPlanes { centers, normals }
    }

    /// Moves the planes of the fins in `range` to `plane(ends[fin])` (center, unit normal), in
    /// place.
    pub fn update(
        &mut self,
        range: Range<u32>,
        ends: &[[u32; 2]],
        plane: impl Fn([u32; 2]) -> ([f32; 3], [f32; 3]) + Sync,
    ) {
        let range = range.start as usize..range.end as usize;
        self.centers[range.clone()]
            .par_iter_mut()
            .zip(self.normals[range.clone()].par_iter_mut())
            .zip(ends[range].par_iter())
            .for_each(|((center, normal), &ends)| (*center, *normal) = plane(ends));
    }

    /// The index list (two triangles per fin) of the fins among `fins` (one geometric level's)
    /// visible from `eye` (object space, homogeneous: `w = 1` a position, `w = 0` a direction
    /// toward the viewer), farthest first: fins are blended "over" without writing depth, so
    /// drawn in any other order a farther fin would cover a nearer one where they overlap
    /// (light patches where neighbouring fins cross at the silhouette). Ties go to the lower
    /// fin, so the order, and thus the image, does not depend on the thread count.
    pub fn visible_indices(&self, eye: [f32; 4], fins: Range<u32>) -> Vec<u32> {
        let range = fins.start as usize..fins.end as usize;
        let chunks: Vec<Vec<u64>> = self.centers[range.clone()]
            .par_chunks(CHUNK)
            .zip(self.normals[range].par_chunks(CHUNK))
            .enumerate()
            .map(|(chunk, (centers, normals))| {
                let first = fins.start + (chunk * CHUNK) as u32;
                centers
                    .iter()
                    .zip(normals)
                    .enumerate()
                    .filter(|(_, (c, n))| faded_in(**c, **n, eye))
                    .map(|(k, (c, _))| order_key(distance(*c, eye), first + k as u32))
                    .collect()
            })
            .collect();
        let mut visible = chunks.concat();
        // Keys are distinct (each holds its fin), so the parallel sort is deterministic.
        visible.par_sort_unstable();
        visible
            .par_iter()
            .flat_map_iter(|&key| quad_triangles(key as u32))
            .collect()
    }
}

/// A key whose ascending order is farthest `distance` first, then the lower `fin`: one integer
/// comparison per step of the sort (the distance's f32 bits mapped to an order-preserving u32,
/// inverted, above the fin).
fn order_key(distance: f32, fin: u32) -> u64 {
    let bits = distance.to_bits();
    // Negative floats order reversed by their bits, positive ones as their bits.
    let ascending = if bits >> 31 == 1 { !bits } else { bits | 1 << 31 };
    (u64::from(!ascending) << 32) | u64::from(fin)
}

/// How far `center` lies from `eye` (homogeneous, as in [`FinPlanes::visible_indices`]), for
/// ordering: the squared distance from a position, the depth along a direction.
fn distance(center: [f32; 3], eye: [f32; 4]) -> f32 {
    if eye[3] == 0.0 {
        -center.iter().zip(&eye).map(|(c, e)| c * e).sum::<f32>()
    } else {
        center.iter().zip(&eye).map(|(c, e)| (e - c) * (e - c)).sum()
    }
}

/// `2|p| − 1 > 0` (within [`MARGIN`]) for `p` = fin normal · unit vector toward the eye, as
/// `fins.wgsl` computes it.
fn faded_in(center: [f32; 3], normal: [f32; 3], eye: [f32; 4]) -> bool {
    let to_eye: [f32; 3] = std::array::from_fn(|i| eye[i] - center[i] * eye[3]);
    let len2: f32 = to_eye.iter().map(|x| x * x).sum();
    let p: f32 = normal.iter().zip(&to_eye).map(|(n, v)| n * v).sum();
    // |p| / |v| > 1/2 − MARGIN without the square root; a zero vector (the eye on the fin) keeps it.
    let bound = (0.5 - MARGIN) * (0.5 - MARGIN) * len2;
    p * p > bound || len2 == 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_exactly_the_fins_facing_the_eye_more_than_sixty_degrees() {
        // Fins at the origin whose normal makes angle θ with the direction toward the eye.
        let angles: Vec<f32> = (0..=180).map(|d| (d as f32).to_radians()).collect();
        let normals: Vec<[f32; 3]> = angles.iter().map(|a| [a.sin(), 0.0, a.cos()]).collect();
        let planes = FinPlanes::new(vec![[0.0; 3]; normals.len()], normals);
        for eye in [[0.0, 0.0, 5.0, 1.0], [0.0, 0.0, 1.0, 0.0]] {
            let kept: Vec<u32> = planes
                .visible_indices(eye, 0..angles.len() as u32)
                .chunks(6)
                .map(|t| t[0] / 4)
                .collect();
            // |cos θ| > 1/2: θ < 60° or θ > 120°; the 60° and 120° fins sit on the fade's zero.
            let expected: Vec<u32> = (0..=180u32).filter(|&d| d <= 60 || d >= 120).collect();
            assert_eq!(kept, expected);
        }
    }

    #[test]
    fn fins_come_farthest_first_for_an_eye_point_and_an_eye_direction() {
        // Four fins facing +z at heights 0, 3, 1, 2 below an eye on the z axis.
        let heights = [0.0, 3.0, 1.0, 2.0];
        let planes = FinPlanes::new(
            heights.iter().map(|&z| [0.0, 0.0, z]).collect(),
            vec![[0.0, 0.0, 1.0]; 4],
        );
        for eye in [[0.0, 0.0, 10.0, 1.0], [0.0, 0.0, 1.0, 0.0]] {
            let order: Vec<u32> = planes
                .visible_indices(eye, 0..4)
                .chunks(6)
                .map(|t| t[0] / 4)
                .collect();
            assert_eq!(order, [0, 2, 3, 1], "eye {eye:?}");
        }
    }

    #[test]
    fn order_keys_sort_farthest_first_then_by_fin() {
        let items = [
            (-2.0f32, 0u32),
            (3.0, 1),
            (-0.5, 2),
            (0.0, 3),
            (3.0, 0),
            (1e30, 9),
        ];
        let mut keys: Vec<u64> = items.iter().map(|&(d, f)| order_key(d, f)).collect();
        keys.sort_unstable();
        let order: Vec<(f32, u32)> = keys
            .iter()
            .map(|&k| *items.iter().find(|&&(d, f)| order_key(d, f) == k).unwrap())
            .collect();
        assert_eq!(
            order,
            [(1e30, 9), (3.0, 0), (3.0, 1), (0.0, 3), (-0.5, 2), (-2.0, 0)]
        );
    }

    #[test]
    fn order_and_triangles_follow_the_fins_across_chunks() {
        let n = 3 * CHUNK + 17;
        let normals: Vec<[f32; 3]> = (0..n)
            .map(|k| {
                if k % 3 == 0 {
                    [1.0, 0.0, 0.0]
                } else {
                    [0.0, 0.0, 1.0]
                }
            })
            .collect();
        let planes = FinPlanes::new(vec![[0.0; 3]; n], normals);
        // All at one distance: fin order.
        let indices = planes.visible_indices([0.0, 0.0, 2.0, 1.0], 0..n as u32);
        let expected: Vec<u32> = (0..n as u32)
            .filter(|k| k % 3 != 0)
            .flat_map(quad_triangles)
            .collect();
        assert_eq!(indices, expected);
        // A level's range: the same fins, numbered as uploaded.
        let level = (CHUNK as u32 + 5)..n as u32;
        let indices = planes.visible_indices([0.0, 0.0, 2.0, 1.0], level.clone());
        let expected: Vec<u32> = level.filter(|k| k % 3 != 0).flat_map(quad_triangles).collect();
        assert_eq!(indices, expected);
    }
}
