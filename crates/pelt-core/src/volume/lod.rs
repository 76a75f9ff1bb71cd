//! Level of detail of the shell stack: fewer, composited shells.
//!
//! Lengyel et al. 2001, §2.4: far from the viewer fewer shells suffice, so a reduced set is made by
//! compositing successive pairs of shells with the "over" operator, repeated down to a single
//! shell. Compositing works on premultiplied linear color and stores straight, sRGB-encoded RGBA8
//! like the full-detail shells. (The mipmaps of every layer come from [`crate::texture::mip`].)
//!
//! Layer 0 (the opaque skin) stays apart at every level but the last: level `k` is the skin and
//! `⌈(L − 1) / 2^k⌉` groups of hair, group `j` holding level-0 layers `(j − 1) 2^k + 1 ..= j 2^k`
//! (the last cut at `L − 1`), so a group is shown above the skin and lit as hair, not as skin.
//! The level with the skin and one group is followed by a last level of one layer, everything
//! composited into the skin.

use rayon::prelude::*;

use crate::texture::color::{Srgb8Encoder, srgb8_encoder, srgb8_to_linear_table, unit_to_u8};

/// Premultiplied linear RGBA of one straight sRGB RGBA8 texel (`alphas[b]` is `b / 255`).
#[inline(always)]
fn premultiplied(px: &[u8], table: &[f32; 256], alphas: &[f32; 256]) -> [f32; 4] {
    let a = alphas[px[3] as usize];
    [
        table[px[0] as usize] * a,
        table[px[1] as usize] * a,
        table[px[2] as usize] * a,
        a,
    ]
}

/// Straight sRGB RGBA8 of a premultiplied linear texel.
#[inline(always)]
fn straight(p: [f32; 4], srgb: &Srgb8Encoder, out: &mut [u8]) {
    let a = p[3];
    let rgb = if a > 0.0 {
        [p[0] / a, p[1] / a, p[2] / a]
    } else {
        [0.0; 3]
    };
    out[0] = srgb.encode(rgb[0]);
    out[1] = srgb.encode(rgb[1]);
    out[2] = srgb.encode(rgb[2]);
    out[3] = unit_to_u8(a);
}

/// Byte alpha to `[0, 1]` by table: the quotients `b / 255` without a division per texel.
fn alpha_table() -> [f32; 256] {
    std::array::from_fn(|b| f32::from(b as u8) / 255.0)
}

/// Composites the RGBA8 layer `outer` over `inner` into `dst` (all of one size).
pub fn composite_pair(inner: &[u8], outer: &[u8], dst: &mut [u8]) {
    let (table, srgb, alphas) = (srgb8_to_linear_table(), srgb8_encoder(), alpha_table());
    for ((d, i), o) in dst
        .chunks_exact_mut(4)
        .zip(inner.chunks_exact(4))
        .zip(outer.chunks_exact(4))
    {
        // Trivial cases first: most texels of a sparse pelt are empty in one of the two.
        if o[3] == 0 {
            d.copy_from_slice(i);
            continue;
        }
        if i[3] == 0 || o[3] == 255 {
            d.copy_from_slice(o);
            continue;
        }
        let (pi, po) = (premultiplied(i, table, &alphas), premultiplied(o, table, &alphas));
        let keep = 1.0 - po[3];
        straight(std::array::from_fn(|c| po[c] + keep * pi[c]), srgb, d);
    }
}

/// Layers of every level, level 0 (`layers`) first: then `1 + ⌈(L − 1) / 2^k⌉` down to two (the
/// skin and one group), then one. A single layer has no coarser level.
pub fn level_counts(layers: usize) -> Vec<usize> {
    let mut counts = vec![layers];
    while let Some(&last) = counts.last().filter(|&&c| c > 1) {
        counts.push(next_count(last));
    }
    counts
}

/// Layers of the level after one of `count > 1` layers.
pub fn next_count(count: usize) -> usize {
    if count > 2 { 1 + (count - 1).div_ceil(2) } else { 1 }
}

/// The layers of a level of `count` layers that the next level's layer `i` composites: the inner
/// one and the outer one over it, if any. The skin is kept; group `i` joins groups `2i − 1` and
/// `2i`; the last level joins the only group and the skin.
pub fn sources(count: usize, i: usize) -> (usize, Option<usize>) {
    if count <= 2 {
        return (0, (count == 2).then_some(1));
    }
    if i == 0 {
        return (0, None);
    }
    (2 * i - 1, Some(2 * i).filter(|&outer| outer < count))
}

/// The level after `previous` (`count > 1` RGBA8 layers of `texels` texels each).
pub fn composite_level(previous: &[u8], count: usize, texels: usize) -> Vec<u8> {
    let size = 4 * texels;
    let layer = |l: usize| &previous[l * size..(l + 1) * size];
    let mut out = vec![0u8; next_count(count) * size];
    out.par_chunks_exact_mut(size)
        .enumerate()
        .for_each(|(i, dst)| match sources(count, i) {
            (inner, Some(outer)) => composite_pair(layer(inner), layer(outer), dst),
            (inner, None) => dst.copy_from_slice(layer(inner)),
        });
    out
}

/// The reduced shell sets, levels 1 to the last (see [`level_counts`]); level 0 (the full stack)
/// is not repeated.
pub fn lod_chain(shells: &[u8], layers: usize, texels: usize) -> Vec<Vec<u8>> {
    if layers <= 1 {
        return Vec::new();
    }
    lod_chain_from(
        composite_level(shells, layers, texels),
        next_count(layers),
        texels,
    )
}

/// [`lod_chain`] given its level 1 (`layers` layers), which the bake composites while sampling.
pub fn lod_chain_from(first: Vec<u8>, layers: usize, texels: usize) -> Vec<Vec<u8>> {
    let mut levels = vec![first];
    let mut count = layers;
    while count > 1 {
        let source = levels.last().map_or(&[][..], Vec::as_slice);
        let next = composite_level(source, count, texels);
        levels.push(next);
        count = next_count(count);
    }
    levels
}
