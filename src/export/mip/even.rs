//! The common case of the mip filter for RGBA8: both sides even, so every output texel is the
//! plain 2 × 2 box of four source texels (Lengyel et al. 2001, §2.4 rely on such mipmaps of every
//! shell layer).
//!
//! The general filter of [`super`] walks up to 3 × 3 taps with per-axis weights through generic
//! decode and encode closures; for even sides every texel has the same four taps of the same
//! weight, so this path unrolls them and reads the sRGB table directly. It performs the general
//! filter's floating-point operations in the same order with the same weights, so its bytes are
//! those of the general filter (the tests compare the two on every texel). Hair shells are mostly
//! runs of identical texels (the empty texels of a layer all hold its fill color); a block of four
//! identical texels is copied, which is exact as well: see [`halve_even_rgba8`].

use rayon::prelude::*;

use super::{MipAlpha, decode_rgba8, encode_rgba8};
use crate::color::{srgb8_encoder, srgb8_to_linear_table};

/// One level down for `layers` RGBA8 images of even `width` and `height` (layer-major), rows in
/// parallel; the same bytes as the general filter.
///
/// Four identical source texels give that texel back. The general filter gets it too: it sums
/// four equal terms `w·v` (or `w·a·v`) and divides by their weight, which returns `v` to within a
/// few ulps of f64; a linear byte `v` (an integer) comes back exactly and rounds to itself, an
/// sRGB table value is an f32 and the cast back to f32 restores it exactly (an f64 error of a few
/// ulps is far below half an f32 ulp), and the encoder maps every table value to its byte. Alpha
/// is an integer average, exact.
pub(super) fn halve_even_rgba8(
    src: &[u8],
    width: usize,
    height: usize,
    layers: usize,
    srgb: bool,
    alpha: MipAlpha,
) -> Vec<u8> {
    let (w2, h2) = (width / 2, height / 2);
    // The general filter's tap weight (overlap (height/2)·(width/2)) and their sum.
    let w = (h2 as u64 * w2 as u64) as f64;
    let norm = (width * height) as f64;
    let (table, encoder) = (srgb8_to_linear_table(), srgb8_encoder());
    let mut out = vec![0u8; layers * h2 * w2 * 4];
    out.par_chunks_mut(w2 * 4).enumerate().for_each(|(r, row)| {
        let (layer, y) = (r / h2, r % h2);
        let first = (layer * height + 2 * y) * width * 4;
        let (top, bottom) = src[first..first + 8 * w2 * 2].split_at(width * 4);
        let blocks = top.chunks_exact(8).zip(bottom.chunks_exact(8));
        for (dst, (t, b)) in row.chunks_exact_mut(4).zip(blocks) {
            let (t0, t1, b0, b1) = (&t[..4], &t[4..], &b[..4], &b[4..]);
            if t0 == t1 && t0 == b0 && t0 == b1 {
                dst.copy_from_slice(t0);
                continue;
            }
            // The general filter's operations in its order (rows, then columns); its colors
            // divided by the weight sum are not needed where alpha replaces them.
            let mut plain = [0.0f64; 4];
            let mut weighted = [0.0f64; 3];
            let mut alpha_weight = 0.0f64;
            for p in [t0, t1, b0, b1] {
                let v = decode_rgba8(p, srgb, table);
                for k in 0..4 {
                    plain[k] += w * v[k];
                }
                let wa = w * v[3];
                alpha_weight += wa;
                for k in 0..3 {
                    weighted[k] += wa * v[k];
                }
            }
            let value = if alpha == MipAlpha::Straight && alpha_weight > 0.0 {
                [
                    weighted[0] / alpha_weight,
                    weighted[1] / alpha_weight,
                    weighted[2] / alpha_weight,
                    plain[3] / norm,
                ]
            } else {
                plain.map(|s| s / norm)
            };
            dst.copy_from_slice(&encode_rgba8(value, srgb, encoder));
        }
    });
    out
}

#[cfg(test)]
mod tests;
