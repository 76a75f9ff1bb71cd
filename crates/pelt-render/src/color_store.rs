//! How the color textures (shells, fins, virtual-plane slices) are stored on the device. The
//! renderer blends premultiplied color, so the bake's straight sRGB RGBA8 texels are multiplied
//! by alpha in linear light on upload; filtering and "over" are only right on such values.
//!
//! A GPU stores them sRGB-encoded in `Rgba8UnormSrgb` and decodes each texel exactly (by table)
//! before filtering. A CPU rasterizer (lavapipe) decodes sRGB8 by a polynomial that strays by up
//! to 2.5%: bytes 1–10 read 2.5% bright, 15 and 24–32 about 2% dark, 80–100 0.7% bright. Faint
//! shell texels (low bytes once premultiplied) then read darker than the composites of the LOD
//! levels made from them, and the image drifted with the level. There the colors are stored as
//! premultiplied linear half floats instead, which every device reads exactly, at twice the
//! bytes.

use half::f16;
use rayon::prelude::*;

use pelt_core::texture::color::{srgb8_encoder, srgb8_to_linear_table};

/// The storage of the color textures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum ColorStore {
    /// Premultiplied, sRGB-encoded RGBA8 (a GPU's).
    Srgb8,
    /// Premultiplied linear RGBA16F (a CPU adapter's).
    Half,
}

impl ColorStore {
    /// The storage for an adapter that is (`cpu`) a CPU rasterizer or not.
    pub fn for_adapter(cpu: bool) -> Self {
        if cpu { ColorStore::Half } else { ColorStore::Srgb8 }
    }

    pub fn format(self) -> wgpu::TextureFormat {
        match self {
            ColorStore::Srgb8 => wgpu::TextureFormat::Rgba8UnormSrgb,
            ColorStore::Half => wgpu::TextureFormat::Rgba16Float,
        }
    }

    /// Bytes of one stored texel.
    pub fn texel_bytes(self) -> usize {
        match self {
            ColorStore::Srgb8 => 4,
            ColorStore::Half => 8,
        }
    }

    /// Straight sRGB RGBA8 texels as stored: premultiplied, in the current rayon pool (each texel
    /// on its own, so the result does not depend on the thread count).
    pub fn premultiplied(self, straight: &[u8]) -> Vec<u8> {
        match self {
            ColorStore::Srgb8 => premultiply(straight),
            ColorStore::Half => premultiply_half(straight),
        }
    }
}

/// Straight sRGB RGBA8 to premultiplied (sRGB-encoded) RGBA8.
pub(super) fn premultiply(straight: &[u8]) -> Vec<u8> {
    let (table, srgb) = (srgb8_to_linear_table(), srgb8_encoder());
    let mut out = vec![0u8; straight.len()];
    out.par_chunks_mut(4 * 4096)
        .zip(straight.par_chunks(4 * 4096))
        .for_each(|(dst, src)| {
            for (d, s) in dst.chunks_exact_mut(4).zip(src.chunks_exact(4)) {
                let a = f32::from(s[3]) / 255.0;
                for c in 0..3 {
                    d[c] = srgb.encode(table[usize::from(s[c])] * a);
                }
                d[3] = s[3];
            }
        });
    out
}

/// Straight sRGB RGBA8 to premultiplied linear RGBA16F, little-endian bytes.
pub(super) fn premultiply_half(straight: &[u8]) -> Vec<u8> {
    let table = srgb8_to_linear_table();
    let mut out = vec![0u8; 2 * straight.len()];
    out.par_chunks_mut(8 * 4096)
        .zip(straight.par_chunks(4 * 4096))
        .for_each(|(dst, src)| {
            for (d, s) in dst.chunks_exact_mut(8).zip(src.chunks_exact(4)) {
                let a = f32::from(s[3]) / 255.0;
                let texel = [
                    table[usize::from(s[0])] * a,
                    table[usize::from(s[1])] * a,
                    table[usize::from(s[2])] * a,
                    a,
                ];
                for (pair, v) in d.chunks_exact_mut(2).zip(texel) {
                    pair.copy_from_slice(&f16::from_f32(v).to_le_bytes());
                }
            }
        });
    out
}
