//! Level of detail of the shell stack: fewer, composited shells.
//!
//! Lengyel et al. 2001, §2.4: far from the viewer fewer shells suffice, so a reduced set is made by
//! compositing successive pairs of shells with the "over" operator, repeated down to a single
//! shell. Compositing works on premultiplied linear color and stores straight, sRGB-encoded RGBA8
//! like the full-detail shells. (The mipmaps of every layer come from [`crate::texture::mip`].)

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

/// Composites layers `2j + 1` over `2j` for every pair of the `layers` RGBA8 layers of `texels`
/// texels each; an odd last layer is kept as it is. Returns `ceil(layers / 2)` layers.
pub fn composite_pairs(shells: &[u8], layers: usize, texels: usize) -> Vec<u8> {
    let size = 4 * texels;
    let mut out = vec![0u8; layers.div_ceil(2) * size];
    out.par_chunks_exact_mut(size).enumerate().for_each(|(j, dst)| {
        let inner = &shells[2 * j * size..(2 * j + 1) * size];
        if 2 * j + 1 >= layers {
            dst.copy_from_slice(inner);
            return;
        }
        let outer = &shells[(2 * j + 1) * size..(2 * j + 2) * size];
        composite_pair(inner, outer, dst);
    });
    out
}

/// The reduced shell sets: level 1 has `ceil(L / 2)` layers, each next level half of that, the
/// last a single layer. Level 0 (the full stack) is not repeated.
pub fn lod_chain(shells: &[u8], layers: usize, texels: usize) -> Vec<Vec<u8>> {
    if layers <= 1 {
        return Vec::new();
    }
    lod_chain_from(
        composite_pairs(shells, layers, texels),
        layers.div_ceil(2),
        texels,
    )
}

/// [`lod_chain`] given its level 1 (`layers` layers), which the bake composites while sampling.
pub fn lod_chain_from(first: Vec<u8>, layers: usize, texels: usize) -> Vec<Vec<u8>> {
    let mut levels = vec![first];
    let mut count = layers;
    while count > 1 {
        let source = levels.last().map_or(&[][..], Vec::as_slice);
        let next = composite_pairs(source, count, texels);
        levels.push(next);
        count = count.div_ceil(2);
    }
    levels
}
