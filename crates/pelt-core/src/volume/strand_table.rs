//! The strands in one flat table, in raster order of their roots, for sampling many heights quickly.
//!
//! Each layer asks every strand where it crosses the layer's height. With one heap allocation per
//! strand that walk is bound by scattered memory reads; here the polylines sit in one array
//! (single precision is ample: a thousandth of a texel at 4096²), ordered by where their roots
//! stand (rows of the tile, then x), so that consecutive strands splat into neighbouring texels
//! and a layer's sums stay in cache.

use rayon::prelude::*;

use crate::hair::Strand;

/// A strand's cut through a horizontal plane.
#[derive(Debug, Clone, Copy)]
pub struct Cut {
    /// Unwrapped position in the tile.
    pub x: f64,
    /// Unwrapped position in the tile.
    pub y: f64,
    /// Radius, tile units.
    pub radius: f64,
    /// Height along the strand as a share of its own height.
    pub along: f32,
    /// Unit direction of the strand there.
    pub direction: [f32; 3],
}

/// Strands as flat arrays in raster order of their roots (ties keep their input order).
pub struct StrandTable {
    /// Points per strand (segments + 1), the same for all strands of the table.
    stride: usize,
    /// Per strand: `(height, input index)`.
    heights: Vec<(f64, usize)>,
    /// `stride` points per strand: `(x, y, radius)`; heights rise evenly from 0 to the strand's.
    points: Vec<[f32; 3]>,
    /// Per strand: root and tip color.
    colors: Vec<[[f32; 3]; 2]>,
}

impl StrandTable {
    /// Builds the table of the strands that `keep(index, strand)` keeps; strands with a different
    /// point count from the first one, fewer than two points or a height that is not positive
    /// and finite are left out (they cross no layer).
    pub fn new(strands: &[Strand], keep: impl Fn(usize, &Strand) -> bool + Sync) -> Self {
        let stride = strands.first().map_or(2, |s| s.points.len().max(2));
        // Rows of 1/256 of the tile: finer than any shell texture's cache-relevant span. The key
        // is computed once per strand, not per comparison (two `fmod`s each).
        // Built in parallel (the bake runs in Pelt's pool): on a big pelt this walk over every
        // strand's separate allocations was a serial tenth of a second.
        let mut keyed: Vec<(u32, f64, usize, f64)> = strands
            .par_iter()
            .enumerate()
            .filter(|(_, s)| s.points.len() == stride && s.radii.len() == stride)
            .filter(|(i, s)| keep(*i, s))
            .map(|(i, s)| {
                let r = s.root;
                let row = (r[1].rem_euclid(1.0) * 256.0) as u32;
                (row, r[0].rem_euclid(1.0), i, s.height())
            })
            .filter(|&(.., h)| h > 0.0 && h.is_finite())
            .collect();
        // The input index breaks ties, so the order is total and an unstable sort is exact.
        keyed.par_sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
        let order: Vec<(f64, usize)> = keyed.iter().map(|&(_, _, i, h)| (h, i)).collect();
        let mut points = vec![[0.0f32; 3]; order.len() * stride];
        let mut colors = vec![[[0.0f32; 3]; 2]; order.len()];
        points
            .par_chunks_mut(stride)
            .zip(colors.par_iter_mut())
            .zip(&order)
            .for_each(|((dst, color), &(_, i))| {
                let s = &strands[i];
                for ((d, p), &r) in dst.iter_mut().zip(&s.points).zip(&s.radii) {
                    *d = [p[0] as f32, p[1] as f32, r as f32];
                }
                *color = [s.root_color, s.tip_color];
            });
        StrandTable {
            stride,
            heights: order,
            points,
            colors,
        }
    }

    /// Number of strands in the table.
    pub fn len(&self) -> usize {
        self.heights.len()
    }

    /// Whether the table holds no strand.
    pub fn is_empty(&self) -> bool {
        self.heights.is_empty()
    }

    /// Height of the tallest strand (0 without strands).
    pub fn tallest(&self) -> f64 {
        self.heights.iter().map(|h| h.0).fold(0.0, f64::max)
    }

    /// Whether table strand `k` reaches height `z` (`z` within `[0, height]`).
    #[inline]
    pub fn reaches(&self, k: usize, z: f64) -> bool {
        z >= 0.0 && self.heights[k].0 >= z
    }

    /// Root and tip color of table strand `k`.
    pub fn colors(&self, k: usize) -> [[f32; 3]; 2] {
        self.colors[k]
    }

    /// Where table strand `k` crosses height `z`, which must lie in `[0, height]` (see
    /// [`StrandTable::reaches`]). Position and radius are linear along the segment holding `z`.
    pub fn cut(&self, k: usize, z: f64) -> Cut {
        let height = self.heights[k].0;
        let segments = self.stride - 1;
        let (s, t) = self.segment(height, z);
        let f = t - s as f64;
        let a = self.points[k * self.stride + s];
        let b = self.points[k * self.stride + s + 1];
        let (dx, dy) = (f64::from(b[0] - a[0]), f64::from(b[1] - a[1]));
        let dz = height / segments as f64;
        let inv = 1.0 / (dx * dx + dy * dy + dz * dz).sqrt();
        Cut {
            x: f64::from(a[0]) + f * dx,
            y: f64::from(a[1]) + f * dy,
            radius: f64::from(a[2]) + f * f64::from(b[2] - a[2]),
            along: (z / height) as f32,
            direction: [(dx * inv) as f32, (dy * inv) as f32, (dz * inv) as f32],
        }
    }

    /// The segment of a strand `height` tall that holds height `z`, and `z`'s place along the
    /// strand in segments (`t`, the segment index plus the fraction within it).
    #[inline(always)]
    fn segment(&self, height: f64, z: f64) -> (usize, f64) {
        let segments = self.stride - 1;
        let t = (z / height * segments as f64).max(0.0);
        ((t as usize).min(segments - 1), t)
    }

    /// Asks the processor to start loading the points [`StrandTable::cut`] reads for table
    /// strand `k` at height `z`. The table is far larger than the caches and a layer's walk reads
    /// two points per strand, so without this every cut waits on memory; walking the strands in
    /// order, a cut a few strands ahead is fetched while the current hair is splatted. A hint
    /// only: results are the same without it (and on processors without one, it does nothing).
    #[inline(always)]
    pub fn prefetch(&self, k: usize, z: f64) {
        #[cfg(target_arch = "x86_64")]
        if let Some(&(height, _)) = self.heights.get(k) {
            let (s, _) = self.segment(height, z);
            if let Some(point) = self.points.get(k * self.stride + s) {
                use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
                // SAFETY: a prefetch reads nothing the program sees and cannot fault; the address
                // is that of a live element of `points`.
                #[allow(unused_unsafe)]
                unsafe {
                    _mm_prefetch::<_MM_HINT_T0>(std::ptr::from_ref(point).cast());
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = (k, z);
    }

    /// The lateral extent `[min y, max y]` of table strand `k`, unwrapped.
    pub fn y_range(&self, k: usize) -> [f64; 2] {
        let pts = &self.points[k * self.stride..(k + 1) * self.stride];
        pts.iter()
            .fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], p| {
                [lo.min(f64::from(p[1])), hi.max(f64::from(p[1]))]
            })
    }
}
