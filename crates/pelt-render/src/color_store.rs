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
    let srgb = srgb8_encoder();
    premultiplied_texels(straight, 4, |[r, g, b], alpha, out| {
        out.copy_from_slice(&[srgb.encode(r), srgb.encode(g), srgb.encode(b), alpha]);
    })
}

/// Straight sRGB RGBA8 to premultiplied linear RGBA16F, little-endian bytes.
pub(super) fn premultiply_half(straight: &[u8]) -> Vec<u8> {
    premultiplied_texels(straight, 8, |[r, g, b], alpha, out| {
        let a = f32::from(alpha) / 255.0;
        for (pair, v) in out.chunks_exact_mut(2).zip([r, g, b, a]) {
            pair.copy_from_slice(&f16::from_f32(v).to_le_bytes());
        }
    })
}

/// Each straight sRGB RGBA8 texel's linear color premultiplied by its alpha, handed with the
/// alpha byte to `store`, which writes the texel's `texel_bytes` bytes; in parallel chunks of the
/// current rayon pool, each texel on its own.
fn premultiplied_texels(
    straight: &[u8],
    texel_bytes: usize,
    store: impl Fn([f32; 3], u8, &mut [u8]) + Sync,
) -> Vec<u8> {
    const CHUNK: usize = 4096;
    let table = srgb8_to_linear_table();
    let mut out = vec![0u8; straight.len() / 4 * texel_bytes];
    out.par_chunks_mut(texel_bytes * CHUNK)
        .zip(straight.par_chunks(4 * CHUNK))
        .for_each(|(dst, src)| {
            for (d, s) in dst.chunks_exact_mut(texel_bytes).zip(src.chunks_exact(4)) {
                let a = f32::from(s[3]) / 255.0;
                let rgb = [0, 1, 2].map(|c| table[usize::from(s[c])] * a);
                store(rgb, s[3], d);
            }
        });
    out
}
