//! The fin texture: the hair of a thin slab of the tile seen from the side.
//!
//! Shells seen edge-on at the silhouette show gaps between layers; Lengyel et al. 2001, §2.2 cover
//! them with "fins", quads standing on mesh edges, textured with an image of the same hair
//! geometry rendered sideways: the strands whose roots lie in a slab of the tile along one surface
//! tangent, composited along that tangent. Here the view runs along +y: each image row is one
//! height, each strand crossing that height inside the slab `y ∈ [0, slab)` (toroidally) covers
//! the interval `[x − r, x + r]` of the row, and the pieces are composited front to back
//! ("over", nearest first) with their exact interval coverage per texel.
//!
//! Image rows run top to bottom: row 0 is the top of the fur (height 1), the last row the skin.
//! The x axis is the tile's and wraps, so the texture repeats along the fin.

use rayon::prelude::*;

use super::grid::{floor_i64, fract_wrap, wrap_near};
use super::strand_table::StrandTable;
use crate::texture::color::{srgb8_encoder, unit_to_u8};

/// One strand's cut through a row.
pub(super) struct Piece {
    /// Distance behind the slab's front, as [`depth_key`].
    pub depth: i64,
    /// Center and radius, texels.
    pub x: f64,
    pub radius: f64,
    /// Linear color.
    pub color: [f32; 3],
}

/// An integer that orders depths as [`f64::total_cmp`] does (the sign-magnitude bits of an f64
/// turned into two's complement), so that sorting compares integers.
pub(super) fn depth_key(depth: f64) -> i64 {
    let bits = depth.to_bits() as i64;
    bits ^ (((bits >> 63) as u64) >> 1) as i64
}

/// Renders row `row` of a `width × height` fin texture into `rgba` (straight RGBA8, color
/// sRGB-encoded).
///
/// `candidates` are the table indices (ascending) of the strands that can enter the slab at all
/// (see [`slab_candidates`]).
pub fn fin_row(
    strands: &StrandTable,
    candidates: &[usize],
    slab: f64,
    [width, height]: [usize; 2],
    row: usize,
    rgba: &mut [u8],
) {
    let z = 1.0 - (row as f64 + 0.5) / height as f64;
    let pieces: Vec<Piece> = candidates
        .iter()
        .filter(|&&k| strands.reaches(k, z))
        .filter_map(|&k| {
            let cut = strands.cut(k, z);
            let depth = fract_wrap(cut.y);
            (depth < slab).then(|| {
                let [root, tip] = strands.colors(k);
                Piece {
                    depth: depth_key(depth),
                    x: fract_wrap(cut.x) * width as f64,
                    radius: cut.radius * width as f64,
                    color: std::array::from_fn(|c| root[c] + (tip[c] - root[c]) * cut.along),
                }
            })
        })
        .collect();
    composite_row(&pieces, width, rgba);
}

/// Composites `pieces` (one row's strand cuts, in strand order) front to back into `rgba`, a row
/// of `width` texels (straight RGBA8, color sRGB-encoded), with each piece's exact interval
/// coverage per texel; the row wraps.
pub(super) fn composite_row(pieces: &[Piece], width: usize, rgba: &mut [u8]) {
    // Nearest first; the strand index breaks ties, so the order is total and never depends on
    // the sort. Pieces are in strand order, so their position stands for the index, and the
    // sort moves pairs of integers instead of whole pieces.
    let mut order: Vec<(i64, usize)> = pieces.iter().enumerate().map(|(i, p)| (p.depth, i)).collect();
    order.sort_unstable();

    let mut transmit = vec![1.0f32; width];
    let mut premul = vec![[0.0f32; 3]; width];
    for p in order.iter().map(|&(_, i)| &pieces[i]) {
        let (lo, hi) = (p.x - p.radius, p.x + p.radius);
        for ix in floor_i64(lo)..=floor_i64(hi) {
            let cover = (hi.min(ix as f64 + 1.0) - lo.max(ix as f64)).clamp(0.0, 1.0) as f32;
            if cover <= 0.0 {
                continue;
            }
            let t = wrap_near(ix, width as i64);
            let visible = transmit[t] * cover;
            for (sum, &c) in premul[t].iter_mut().zip(&p.color) {
                *sum += visible * c;
            }
            transmit[t] *= 1.0 - cover;
        }
    }
    // Empty texels get the row's mean hair color so filtering does not pull in black.
    let covered: f32 = transmit.iter().map(|t| 1.0 - t).sum();
    let fill: [f32; 3] = if covered > 0.0 {
        std::array::from_fn(|c| premul.iter().map(|p| p[c]).sum::<f32>() / covered)
    } else {
        [0.0; 3]
    };
    let srgb = srgb8_encoder();
    for (t, px) in rgba.chunks_exact_mut(4).enumerate() {
        let alpha = 1.0 - transmit[t];
        let rgb = if alpha > 0.0 {
            premul[t].map(|c| c / alpha)
        } else {
            fill
        };
        px[..3].copy_from_slice(&rgb.map(|c| srgb.encode(c)));
        px[3] = unit_to_u8(alpha);
    }
}

/// Table indices of the strands whose lateral extent meets the slab `y ∈ [0, slab)` (mod 1).
pub fn slab_candidates(strands: &StrandTable, slab: f64) -> Vec<usize> {
    // In parallel when called from Pelt's pool (as the bake does); the order stays ascending.
    (0..strands.len())
        .into_par_iter()
        .filter(|&k| {
            let [lo, hi] = strands.y_range(k);
            // Shift the range so it starts in [0, 1); it meets the slab there or one tile on.
            let shift = lo.floor();
            let (lo, hi) = (lo - shift, hi - shift);
            hi - lo >= 1.0 || lo < slab || hi >= 1.0
        })
        .collect()
}
