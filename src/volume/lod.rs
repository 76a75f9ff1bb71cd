//! Level of detail of the shell stack: fewer, composited shells and mipmaps.
//!
//! Lengyel et al. 2001, §2.4: far from the viewer fewer shells suffice, so a reduced set is made by
//! compositing successive pairs of shells with the "over" operator, repeated down to a single
//! shell; each layer also gets a mipmap chain for minification. Both work on premultiplied linear
//! color and store straight, sRGB-encoded RGBA8 like the full-detail shells.

use rayon::prelude::*;

use crate::color::{Srgb8Encoder, srgb8_encoder, srgb8_to_linear_table, unit_to_u8};

/// Premultiplied linear RGBA of one straight sRGB RGBA8 texel.
fn premultiplied(px: &[u8], table: &[f32; 256]) -> [f32; 4] {
    let a = f32::from(px[3]) / 255.0;
    [
        table[px[0] as usize] * a,
        table[px[1] as usize] * a,
        table[px[2] as usize] * a,
        a,
    ]
}

/// Straight sRGB RGBA8 of a premultiplied linear texel.
fn straight(p: [f32; 4], srgb: &Srgb8Encoder, out: &mut [u8]) {
    let a = p[3];
    let rgb = if a > 0.0 {
        [p[0] / a, p[1] / a, p[2] / a]
    } else {
        [0.0; 3]
    };
    out[..3].copy_from_slice(&rgb.map(|c| srgb.encode(c)));
    out[3] = unit_to_u8(a);
}

/// Composites layers `2j + 1` over `2j` for every pair of the `layers` RGBA8 layers of `texels`
/// texels each; an odd last layer is kept as it is. Returns `ceil(layers / 2)` layers.
pub fn composite_pairs(shells: &[u8], layers: usize, texels: usize) -> Vec<u8> {
    let (table, srgb) = (srgb8_to_linear_table(), srgb8_encoder());
    let size = 4 * texels;
    let mut out = vec![0u8; layers.div_ceil(2) * size];
    out.par_chunks_exact_mut(size).enumerate().for_each(|(j, dst)| {
        let inner = &shells[2 * j * size..(2 * j + 1) * size];
        if 2 * j + 1 >= layers {
            dst.copy_from_slice(inner);
            return;
        }
        let outer = &shells[(2 * j + 1) * size..(2 * j + 2) * size];
        for ((d, i), o) in dst
            .chunks_exact_mut(4)
            .zip(inner.chunks_exact(4))
            .zip(outer.chunks_exact(4))
        {
            if o[3] == 0 {
                d.copy_from_slice(i);
                continue;
            }
            let (pi, po) = (premultiplied(i, &table), premultiplied(o, &table));
            let keep = 1.0 - po[3];
            straight(std::array::from_fn(|c| po[c] + keep * pi[c]), srgb, d);
        }
    });
    out
}

/// The reduced shell sets: level 1 has `ceil(L / 2)` layers, each next level half of that, the
/// last a single layer. Level 0 (the full stack) is not repeated.
pub fn lod_chain(shells: &[u8], layers: usize, texels: usize) -> Vec<Vec<u8>> {
    let mut levels: Vec<Vec<u8>> = Vec::new();
    let mut count = layers;
    while count > 1 {
        let source = levels.last().map_or(shells, Vec::as_slice);
        levels.push(composite_pairs(source, count, texels));
        count = count.div_ceil(2);
    }
    levels
}

/// For each destination texel `0..m` of a row of `n` source texels, the source texels it covers
/// with their area weights (a box filter of width `n / m`; 2×2 averaging when `n = 2m`).
fn box_weights(n: usize, m: usize) -> Vec<Vec<(usize, f32)>> {
    let scale = n as f64 / m as f64;
    (0..m)
        .map(|i| {
            let (lo, hi) = (i as f64 * scale, (i + 1) as f64 * scale);
            (lo.floor() as usize..(hi.ceil() as usize).min(n))
                .map(|s| {
                    let w = (hi.min(s as f64 + 1.0) - lo.max(s as f64)) / scale;
                    (s, w as f32)
                })
                .filter(|&(_, w)| w > 0.0)
                .collect()
        })
        .collect()
}

/// The next mip level of one square RGBA8 layer of side `n`: side `max(1, n / 2)`.
pub fn downsample(layer: &[u8], n: usize) -> Vec<u8> {
    let (table, srgb) = (srgb8_to_linear_table(), srgb8_encoder());
    let m = (n / 2).max(1);
    if n == 2 * m {
        // Even side (every level of a power-of-two chain): the plain 2×2 average.
        let mut out = vec![0u8; 4 * m * m];
        for (y, row) in out.chunks_exact_mut(4 * m).enumerate() {
            for (x, px) in row.chunks_exact_mut(4).enumerate() {
                let corners = [
                    (2 * y, 2 * x),
                    (2 * y, 2 * x + 1),
                    (2 * y + 1, 2 * x),
                    (2 * y + 1, 2 * x + 1),
                ];
                if corners.iter().all(|&(sy, sx)| layer[4 * (sy * n + sx) + 3] == 0) {
                    continue; // transparent: stays zero
                }
                let mut sum = [0.0f32; 4];
                for (sy, sx) in corners {
                    let p = premultiplied(&layer[4 * (sy * n + sx)..4 * (sy * n + sx) + 4], &table);
                    for (s, v) in sum.iter_mut().zip(p) {
                        *s += 0.25 * v;
                    }
                }
                straight(sum, srgb, px);
            }
        }
        return out;
    }
    let weights = box_weights(n, m);
    let mut out = vec![0u8; 4 * m * m];
    for (y, wy) in weights.iter().enumerate() {
        for (x, wx) in weights.iter().enumerate() {
            let mut sum = [0.0f32; 4];
            for &(sy, fy) in wy {
                for &(sx, fx) in wx {
                    let p = premultiplied(&layer[4 * (sy * n + sx)..4 * (sy * n + sx) + 4], &table);
                    for c in 0..4 {
                        sum[c] += fy * fx * p[c];
                    }
                }
            }
            straight(sum, srgb, &mut out[4 * (y * m + x)..4 * (y * m + x) + 4]);
        }
    }
    out
}

/// Number of levels of a full mip chain of side `n` (down to 1×1), the level 0 included.
pub fn mip_count(n: usize) -> usize {
    (usize::BITS - n.max(1).leading_zeros()) as usize
}
