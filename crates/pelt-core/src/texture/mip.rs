//! Mipmap chains for RGBA layers: an area-weighted box filter that halves each side.
//!
//! Lengyel et al. 2001, §2.4 rely on the hardware's mipmapping of the shell textures for level of
//! detail, so the exported texture arrays carry a full chain. Each level halves the previous one
//! (`max(1, ⌊n/2⌋)` per side, the sizes Vulkan and KTX2 expect). An output texel averages the
//! source texels under its footprint weighted by the overlap area: for even sides that is the
//! plain 2 × 2 box; for odd sides the footprint covers 2 + 1/m source texels (m = the new size),
//! so the edge texels count in part and no row or column is dropped or counted twice.
//!
//! Colors are stored with straight alpha, so with [`MipAlpha::Straight`] the color channels are
//! averaged weighted by alpha: transparent texels (whose color is arbitrary, often black) do not
//! darken the fur's edges at coarser levels. sRGB-encoded bytes are decoded to linear light
//! before averaging and encoded again (the KTX 2.0 specification's EOTF → scaling → EOTF⁻¹ path);
//! alpha is always linear. Every texel is computed on its own from fixed inputs in a fixed order,
//! so the result does not depend on the thread count.

use half::f16;
use rayon::prelude::*;

use crate::error::{PeltError, Result};
use crate::texture::color::{Srgb8Encoder, srgb8_encoder, srgb8_to_linear_table};
use crate::threads::pool;

mod even;

/// Largest side of a texture given to the mipmapper: keeps the integer filter weights exactly
/// representable while they are summed in f64, and is beyond what GPUs sample (Vulkan
/// guarantees 4096; common limits are 16384 or 32768).
pub const MAX_MIP_DIMENSION: usize = 65536;

/// How many levels to build.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MipLevels {
    /// Down to 1 × 1: [`full_mip_count`] levels.
    #[default]
    Full,
    /// This many levels, the base included; `1..=full_mip_count(width, height)`.
    Count(usize),
}

/// How alpha enters the average of the color channels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MipAlpha {
    /// Colors are straight (not premultiplied): average them weighted by alpha, so transparent
    /// texels do not bleed their color in. Where all alpha is zero, the plain average is used.
    #[default]
    Straight,
    /// Average every channel on its own (for data that is not color over alpha).
    Independent,
}

/// Options of the mipmap generators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MipOptions {
    /// How many levels.
    pub levels: MipLevels,
    /// How alpha weighs the colors.
    pub alpha: MipAlpha,
}

/// Levels of a full chain for a `width × height` base: `⌊log2(max(width, height))⌋ + 1`, the
/// most KTX2 allows; 0 when a side is 0.
pub fn full_mip_count(width: usize, height: usize) -> usize {
    if width == 0 || height == 0 {
        return 0;
    }
    (usize::BITS - width.max(height).leading_zeros()) as usize
}

/// Side of level `level` for a base side `base`.
pub(crate) fn level_side(base: usize, level: usize) -> usize {
    base.checked_shr(level as u32).unwrap_or(0).max(1)
}

/// The mip chain of `layers` RGBA8 images stored layer-major (`[layers][height][width][4]`):
/// level 0 is `base` itself, each further level halves the previous one, every level stays
/// layer-major. With `srgb` the color bytes are treated as sRGB encoded (see the module docs).
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `width` or `height` (outside
/// `1..=MAX_MIP_DIMENSION`), `layers` (0), `base` (length not `layers · height · width · 4`) or
/// `levels` (outside `1..=full_mip_count(width, height)`).
pub fn mip_chain_rgba8(
    width: usize,
    height: usize,
    layers: usize,
    base: &[u8],
    srgb: bool,
    options: &MipOptions,
) -> Result<Vec<Vec<u8>>> {
    let count = validate(width, height, layers, base.len(), options.levels)?;
    let smaller = pool().install(|| chain_rgba8(width, height, layers, base, srgb, options.alpha, count));
    Ok(std::iter::once(base.to_vec()).chain(smaller).collect())
}

/// [`mip_chain_rgba8`] for half-float RGBA (linear values, e.g. HDR color or coverage).
///
/// # Errors
/// As [`mip_chain_rgba8`], and [`PeltError::InvalidParameter`] naming `base` when a sample is NaN
/// or infinite.
pub fn mip_chain_rgba16f(
    width: usize,
    height: usize,
    layers: usize,
    base: &[f16],
    options: &MipOptions,
) -> Result<Vec<Vec<f16>>> {
    let count = validate(width, height, layers, base.len(), options.levels)?;
    check_finite_f16("base", width, height, base)?;
    let smaller = pool().install(|| chain_rgba16f(width, height, layers, base, options.alpha, count));
    Ok(std::iter::once(base.to_vec()).chain(smaller).collect())
}

/// The number of levels to build, after checking the sizes.
fn validate(width: usize, height: usize, layers: usize, len: usize, levels: MipLevels) -> Result<usize> {
    for (name, side) in [("width", width), ("height", height)] {
        if !(1..=MAX_MIP_DIMENSION).contains(&side) {
            return Err(PeltError::parameter(
                name,
                format!("is {side}, must be in 1..={MAX_MIP_DIMENSION}"),
            ));
        }
    }
    if layers == 0 {
        return Err(PeltError::parameter("layers", "must be at least 1"));
    }
    let expected = width
        .checked_mul(height)
        .and_then(|n| n.checked_mul(layers))
        .and_then(|n| n.checked_mul(4));
    if expected != Some(len) {
        return Err(PeltError::parameter(
            "base",
            format!(
                "must hold layers · height · width · 4 = {layers} · {height} · {width} · 4 samples, \
                 got {len}"
            ),
        ));
    }
    let full = full_mip_count(width, height);
    match levels {
        MipLevels::Full => Ok(full),
        MipLevels::Count(n) if (1..=full).contains(&n) => Ok(n),
        MipLevels::Count(n) => Err(PeltError::parameter(
            "levels",
            format!("is {n}, must be in 1..={full} for a {width} × {height} base"),
        )),
    }
}

/// Names the first NaN or infinite sample of the layer-major RGBA f16 array `name`.
pub(crate) fn check_finite_f16(name: &str, width: usize, height: usize, data: &[f16]) -> Result<()> {
    let Some(i) = data.iter().position(|v| !v.is_finite()) else {
        return Ok(());
    };
    let texel = i / 4;
    let per_layer = width * height;
    Err(PeltError::parameter(
        name,
        format!(
            "layer {} pixel ({}, {}) channel {} is {} (not finite)",
            texel / per_layer,
            texel % per_layer % width,
            texel % per_layer / width,
            i % 4,
            data[i]
        ),
    ))
}

/// Levels `1..count` of the chain of [`mip_chain_rgba8`] (the base not repeated), sizes unchecked.
#[allow(clippy::too_many_arguments)]
pub(crate) fn chain_rgba8(
    width: usize,
    height: usize,
    layers: usize,
    base: &[u8],
    srgb: bool,
    alpha: MipAlpha,
    count: usize,
) -> Vec<Vec<u8>> {
    if width.is_multiple_of(2) && height.is_multiple_of(2) && count > 1 {
        // Both sides even: the fast 2 × 2 path for this level, the general filter below it.
        let first = even::halve_even_rgba8(base, width, height, layers, srgb, alpha);
        let (w, h) = (width / 2, height / 2);
        let rest = chain_rgba8(w, h, layers, &first, srgb, alpha, count - 1);
        return std::iter::once(first).chain(rest).collect();
    }
    let (decode, encode) = (rgba8_decoder(srgb), rgba8_encoder(srgb));
    chain(width, height, layers, base, alpha, count, decode, encode)
}

/// RGBA8 texel to the general filter's values: linear color (decoded from sRGB with `srgb`),
/// alpha in byte units.
fn rgba8_decoder(srgb: bool) -> impl Fn(&[u8]) -> [f64; 4] + Sync {
    let table = srgb8_to_linear_table();
    move |p: &[u8]| decode_rgba8(p, srgb, table)
}

/// The inverse of [`rgba8_decoder`], rounding to the nearest byte.
fn rgba8_encoder(srgb: bool) -> impl Fn([f64; 4]) -> [u8; 4] + Sync {
    let encoder = srgb8_encoder();
    move |v: [f64; 4]| encode_rgba8(v, srgb, encoder)
}

/// The body of [`rgba8_decoder`], inlined into the filters' inner loops.
#[inline(always)]
fn decode_rgba8(p: &[u8], srgb: bool, table: &[f32; 256]) -> [f64; 4] {
    if srgb {
        [
            f64::from(table[p[0] as usize]),
            f64::from(table[p[1] as usize]),
            f64::from(table[p[2] as usize]),
            f64::from(p[3]),
        ]
    } else {
        [p[0], p[1], p[2], p[3]].map(f64::from)
    }
}

/// The body of [`rgba8_encoder`].
#[inline(always)]
fn encode_rgba8(v: [f64; 4], srgb: bool, encoder: &Srgb8Encoder) -> [u8; 4] {
    let color = |c: f64| {
        if srgb {
            encoder.encode(c as f32)
        } else {
            round_u8(c)
        }
    };
    [color(v[0]), color(v[1]), color(v[2]), round_u8(v[3])]
}

pub(crate) fn chain_rgba16f(
    width: usize,
    height: usize,
    layers: usize,
    base: &[f16],
    alpha: MipAlpha,
    count: usize,
) -> Vec<Vec<f16>> {
    let decode = |p: &[f16]| -> [f64; 4] { [p[0], p[1], p[2], p[3]].map(f64::from) };
    let encode = |v: [f64; 4]| v.map(f16::from_f64);
    chain(width, height, layers, base, alpha, count, decode, encode)
}

#[allow(clippy::too_many_arguments)]
fn chain<T: Copy + Default + Send + Sync>(
    width: usize,
    height: usize,
    layers: usize,
    base: &[T],
    alpha: MipAlpha,
    count: usize,
    decode: impl Fn(&[T]) -> [f64; 4] + Sync,
    encode: impl Fn([f64; 4]) -> [T; 4] + Sync,
) -> Vec<Vec<T>> {
    // Levels 1..count only: the callers that want level 0 copy it, the volume bake does not.
    let mut levels: Vec<Vec<T>> = Vec::new();
    let (mut w, mut h) = (width, height);
    for _ in 1..count {
        let previous = levels.last().map_or(base, Vec::as_slice);
        let next = halve(previous, w, h, layers, alpha, &decode, &encode);
        levels.push(next);
        (w, h) = (level_side(w, 1), level_side(h, 1));
    }
    levels
}

/// The source texels under one output texel along one axis, with their integer overlap weights.
#[derive(Clone, Copy)]
struct Taps {
    first: usize,
    weights: [u64; 3],
    count: usize,
}

/// Footprints along an axis of `n` texels halved to `m = max(1, ⌊n/2⌋)`. Measured in units of
/// `1/(n·m)` of the axis, source texel `j` spans `[j·m, (j+1)·m)` and output texel `i` spans
/// `[i·n, (i+1)·n)`; the weight of `j` for `i` is the length of their overlap, and the weights of
/// one output texel sum to `n`. A footprint is `n/m ≤ 3` source texels long, so it touches at
/// most three.
fn axis_taps(n: usize) -> Vec<Taps> {
    let m = level_side(n, 1);
    (0..m)
        .map(|i| {
            let (start, end) = (i * n, (i + 1) * n);
            let first = start / m;
            let last = (end - 1) / m;
            let mut weights = [0u64; 3];
            for (k, j) in (first..=last).enumerate() {
                let overlap = end.min((j + 1) * m) - start.max(j * m);
                weights[k] = overlap as u64;
            }
            Taps {
                first,
                weights,
                count: last - first + 1,
            }
        })
        .collect()
}

/// One level down: every output row (of every layer) in parallel.
fn halve<T: Copy + Default + Send + Sync>(
    src: &[T],
    width: usize,
    height: usize,
    layers: usize,
    alpha: MipAlpha,
    decode: &(impl Fn(&[T]) -> [f64; 4] + Sync),
    encode: &(impl Fn([f64; 4]) -> [T; 4] + Sync),
) -> Vec<T> {
    let (x_taps, y_taps) = (axis_taps(width), axis_taps(height));
    let (w2, h2) = (x_taps.len(), y_taps.len());
    // Sum of all weights of one output texel.
    let norm = (width * height) as f64;
    let mut out = vec![T::default(); layers * h2 * w2 * 4];
    out.par_chunks_mut(w2 * 4).enumerate().for_each(|(r, row)| {
        let layer = &src[(r / h2) * width * height * 4..][..width * height * 4];
        let ty = y_taps[r % h2];
        for (tx, dst) in x_taps.iter().zip(row.chunks_exact_mut(4)) {
            let mut plain = [0.0f64; 4];
            let mut weighted = [0.0f64; 3];
            let mut alpha_weight = 0.0f64;
            for (dy, &wy) in ty.weights[..ty.count].iter().enumerate() {
                for (dx, &wx) in tx.weights[..tx.count].iter().enumerate() {
                    let w = (wy * wx) as f64;
                    let at = ((ty.first + dy) * width + tx.first + dx) * 4;
                    let v = decode(&layer[at..at + 4]);
                    for k in 0..4 {
                        plain[k] += w * v[k];
                    }
                    // Negative alpha (possible in f16 data) must not flip a weight's sign.
                    let wa = w * v[3].max(0.0);
                    alpha_weight += wa;
                    for k in 0..3 {
                        weighted[k] += wa * v[k];
                    }
                }
            }
            let mut value = plain.map(|s| s / norm);
            if alpha == MipAlpha::Straight && alpha_weight > 0.0 {
                for k in 0..3 {
                    value[k] = weighted[k] / alpha_weight;
                }
            }
            dst.copy_from_slice(&encode(value));
        }
    });
    out
}

/// Nearest byte, halves rounding up (the values here are never negative): `v.round()` clamped to
/// `[0, 255]`, without the library call `round` is on baseline x86-64. The truncation's remainder
/// `v − t` is exact, and below 0 both clamp to 0.
#[inline]
fn round_u8(v: f64) -> u8 {
    let t = v as i64;
    let nearest = if v - t as f64 >= 0.5 {
        t.saturating_add(1)
    } else {
        t
    };
    nearest.clamp(0, 255) as u8
}
