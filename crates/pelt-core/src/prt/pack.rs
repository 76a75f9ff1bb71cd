//! Coefficient textures: the transfer packed 4 coefficients per RGBA texel.
//!
//! §2.3 of the PRT shell-fur paper stores the 25 coefficients of each shell in 7 four-channel
//! textures ("we pack 4 SH function lighting results into a four-channel texture"); the fragment
//! shader then takes a 25-term dot product with the light's coefficients (§2.4). Texture `t`,
//! channel `c` (R, G, B, A = 0..3) holds coefficient `k = 4t + c` (SH index `l² + l + m`); the
//! channels past the last coefficient are 0. Two encodings:
//!
//! - float16 ([`pack_f16`]): the coefficients as IEEE half floats (≈ 3 significant digits;
//!   coefficients of a transfer are bounded by `4π·max|Y|`, far inside the half range);
//! - 8-bit ([`pack_u8`]): each coefficient quantized over its own range across the volume, with a
//!   scale and bias per coefficient recorded in a JSON sidecar ([`QuantizationSidecar`]) so an
//!   engine decodes `value = byte / 255 · scale + bias`.
//!
//! Nothing here writes files; the image writers take these arrays.

use half::f16;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::transfer::Transfer;
use crate::error::Result;
use crate::threads::pool;

/// Coefficients per RGBA texel.
pub const CHANNELS: usize = 4;

/// The decode formula stated in every sidecar.
pub const DECODE: &str = "value = byte / 255 * scale + bias";

/// RGBA textures needed for `coefficients` coefficients (25 → 7).
pub fn texture_count(coefficients: usize) -> usize {
    coefficients.div_ceil(CHANNELS)
}

/// Float16 coefficient textures.
#[derive(Debug, Clone, PartialEq)]
pub struct PackedF16 {
    /// Number of textures per layer, `⌈n²/4⌉`.
    pub textures: usize,
    /// Layers L.
    pub layers: usize,
    /// Resolution R.
    pub resolution: usize,
    /// `[texture][layer][y][x][RGBA]` texels.
    pub texels: Vec<f16>,
}

/// 8-bit coefficient textures and their decode table.
#[derive(Debug, Clone, PartialEq)]
pub struct PackedU8 {
    /// Number of textures per layer, `⌈n²/4⌉`.
    pub textures: usize,
    /// Layers L.
    pub layers: usize,
    /// Resolution R.
    pub resolution: usize,
    /// `[texture][layer][y][x][RGBA]` bytes.
    pub texels: Vec<u8>,
    /// Scale and bias per coefficient, for the JSON sidecar.
    pub sidecar: QuantizationSidecar,
}

/// How to decode 8-bit coefficient textures; serialized as the JSON sidecar next to the images.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct QuantizationSidecar {
    /// Always `"pelt-prt-u8"`.
    pub format: String,
    /// Version of this layout, 1.
    pub version: u32,
    /// SH order n.
    pub order: usize,
    /// Coefficients n².
    pub coefficients: usize,
    /// RGBA textures per layer.
    pub textures: usize,
    /// Layers L.
    pub layers: usize,
    /// Resolution R.
    pub resolution: usize,
    /// Where coefficient `k` lives: texture `k / 4`, channel `k % 4` (RGBA).
    pub layout: String,
    /// The SH convention the coefficients are in.
    pub basis: String,
    /// [`DECODE`].
    pub decode: String,
    /// Scale per coefficient (`max − min` over the volume; 0 for a constant coefficient).
    pub scale: Vec<f32>,
    /// Bias per coefficient (its minimum over the volume).
    pub bias: Vec<f32>,
}

/// Where coefficient `k` of voxel `v` (flat `(l·R + y)·R + x`, of `voxels = L·R²`) lies in
/// [`PackedF16::texels`] and [`PackedU8::texels`].
pub fn texel_index(k: usize, v: usize, voxels: usize) -> usize {
    ((k / CHANNELS) * voxels + v) * CHANNELS + k % CHANNELS
}

/// The texels `[texture][voxel][RGBA]` of `transfer`: coefficient `k` of voxel `v` encoded by
/// `encode(k, value)` in texture `k / 4`, channel `k % 4`; channels past the last coefficient
/// stay `T::default()` (zero).
fn pack_texels<T: Copy + Default + Send>(
    transfer: &Transfer,
    encode: impl Fn(usize, f32) -> T + Sync,
) -> Vec<T> {
    let n = transfer.coeff_count();
    let voxels = transfer.layers * transfer.resolution * transfer.resolution;
    let mut texels = vec![T::default(); texture_count(n) * voxels * CHANNELS];
    pool().install(|| {
        texels
            .par_chunks_mut(voxels * CHANNELS)
            .enumerate()
            .for_each(|(t, tex)| {
                for (v, rgba) in tex.chunks_exact_mut(CHANNELS).enumerate() {
                    for (c, out) in rgba.iter_mut().enumerate() {
                        let k = t * CHANNELS + c;
                        if k < n {
                            *out = encode(k, transfer.coefficients[v * n + k]);
                        }
                    }
                }
            });
    });
    texels
}

/// Packs `transfer` into float16 RGBA textures. Values beyond the half range (impossible for a
/// baked transfer) are clamped to ±65504 so no texel is infinite.
///
/// # Errors
/// [`InvalidParameter`](crate::PeltError::InvalidParameter) when `transfer` is inconsistent (see [`Transfer::check`]).
pub fn pack_f16(transfer: &Transfer) -> Result<PackedF16> {
    transfer.check()?;
    let n = transfer.coeff_count();
    let textures = texture_count(n);
    let texels = pack_texels(transfer, |_, value| f16::from_f32(value.clamp(-65504.0, 65504.0)));
    Ok(PackedF16 {
        textures,
        layers: transfer.layers,
        resolution: transfer.resolution,
        texels,
    })
}

/// Packs `transfer` into 8-bit RGBA textures with a per-coefficient scale and bias:
/// `byte = round((value − bias) / scale · 255)`, so decoding is within `scale / 510` of the value.
/// Non-finite coefficients (impossible for a baked transfer) encode as byte 0.
///
/// # Errors
/// [`InvalidParameter`](crate::PeltError::InvalidParameter) when `transfer` is inconsistent (see [`Transfer::check`]).
pub fn pack_u8(transfer: &Transfer) -> Result<PackedU8> {
    transfer.check()?;
    let n = transfer.coeff_count();
    let textures = texture_count(n);
    let (bias, scale): (Vec<f32>, Vec<f32>) = (0..n)
        .map(|k| {
            let (lo, hi) = transfer
                .coefficients
                .iter()
                .skip(k)
                .step_by(n)
                .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                });
            if lo.is_finite() { (lo, hi - lo) } else { (0.0, 0.0) }
        })
        .unzip();
    let texels = pack_texels(transfer, |k, value| {
        if scale[k] > 0.0 {
            ((value - bias[k]) / scale[k] * 255.0).round().clamp(0.0, 255.0) as u8
        } else {
            0
        }
    });
    Ok(PackedU8 {
        textures,
        layers: transfer.layers,
        resolution: transfer.resolution,
        texels,
        sidecar: QuantizationSidecar {
            format: "pelt-prt-u8".into(),
            version: 1,
            order: transfer.order,
            coefficients: n,
            textures,
            layers: transfer.layers,
            resolution: transfer.resolution,
            layout: "[texture][layer][y][x][RGBA]; coefficient k is texture k / 4, channel k % 4".into(),
            basis: "real SH, index l*l + l + m, orthonormal, no Condon-Shortley phase, theta from +Z, phi from +X toward +Y (tile frame: x, y along the skin, z up)".into(),
            decode: DECODE.into(),
            scale,
            bias,
        },
    })
}
