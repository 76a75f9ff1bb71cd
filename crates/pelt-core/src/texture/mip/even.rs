//! The common case of the mip filter for RGBA8: both sides even, so every output texel is the
//! plain 2 × 2 box of four source texels (Lengyel et al. 2001, §2.4 rely on such mipmaps of every
//! shell layer).
//!
//! The general filter of [`super`] walks up to 3 × 3 taps with per-axis weights through generic
//! decode and encode closures; for even sides every texel has the same four taps of the same
//! weight, so this path unrolls them and reads the sRGB table directly. It performs those of the
//! general filter's floating-point operations that reach the result, in the same order with the
//! same weights, and the alpha average (exact in the general filter) in integers, so its bytes
//! are those of the general filter (the tests compare the two on every texel). Hair shells are mostly
//! runs of identical texels (the empty texels of a layer all hold its fill color); a block of four
//! identical texels is copied, which is exact as well: see [`halve_even_rgba8`].

use rayon::prelude::*;

use super::{MipAlpha, decode_rgba8, encode_rgba8};
use crate::texture::color::{srgb8_encoder, srgb8_to_linear_table};

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
            // One test (and one branch) for four equal texels.
            let word = |p: &[u8]| u32::from_ne_bytes([p[0], p[1], p[2], p[3]]);
            let first = word(t0);
            if (first ^ word(t1)) | (first ^ word(b0)) | (first ^ word(b1)) == 0 {
                dst.copy_from_slice(t0);
                continue;
            }
            let taps = [t0, t1, b0, b1];
            // Alpha: the general filter sums w·a exactly (integers below 2^40) and divides by
            // norm = 4w, which is exact too, so it rounds a quarter of the byte sum.
            let alpha_sum: u32 = taps.iter().map(|p| u32::from(p[3])).sum();
            let alpha_byte = ((alpha_sum + 2) >> 2) as u8;
            let color = if alpha == MipAlpha::Straight && alpha_sum > 0 {
                // The general filter's alpha-weighted sums in its order (rows, then columns).
                let mut weighted = [0.0f64; 3];
                let mut alpha_weight = 0.0f64;
                for p in taps {
                    let v = decode_rgba8(p, srgb, table);
                    let wa = w * v[3];
                    alpha_weight += wa;
                    for k in 0..3 {
                        weighted[k] += wa * v[k];
                    }
                }
                weighted.map(|s| s / alpha_weight)
            } else {
                let mut plain = [0.0f64; 3];
                for p in taps {
                    let v = decode_rgba8(p, srgb, table);
                    for k in 0..3 {
                        plain[k] += w * v[k];
                    }
                }
                plain.map(|s| s / norm)
            };
            let value = [color[0], color[1], color[2], 0.0];
            let mut bytes = encode_rgba8(value, srgb, encoder);
            bytes[3] = alpha_byte;
            dst.copy_from_slice(&bytes);
        }
    });
    out
}

#[cfg(test)]
mod tests;
