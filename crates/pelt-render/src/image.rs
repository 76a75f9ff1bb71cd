//! What a render returns, rows top to bottom, straight alpha: [`RgbaImage`] (8-bit sRGB) and
//! [`LinearImage`] (linear floats).

use half::f16;
use rayon::prelude::*;

use pelt_core::error::Result;
use pelt_core::texture::ImageRef;
use pelt_core::texture::color::{srgb8_encoder, srgb8_to_linear_table, unit_to_u8};
use pelt_core::threads::pool;

/// Pixels per parallel task of a per-pixel pass: small enough to spread a 540p frame over 16
/// threads, large enough that scheduling costs nothing.
const PIXELS_PER_TASK: usize = 16 * 1024;

/// An RGBA8 image: sRGB-encoded color, straight (not premultiplied) alpha, `height` rows of
/// `width` pixels from the top.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbaImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `height × width × 4` bytes.
    pub pixels: Vec<u8>,
}

impl RgbaImage {
    /// Turns the render target's premultiplied pixels into straight alpha: color is divided by
    /// alpha in linear light (where it was blended) and encoded again.
    /// Pixels are independent, so they are split over Pelt's threads: on a GPU this pass is a
    /// large share of a read-back frame.
    pub(super) fn from_premultiplied(width: u32, height: u32, mut pixels: Vec<u8>) -> Self {
        let (table, srgb) = (srgb8_to_linear_table(), srgb8_encoder());
        pool().install(|| {
            pixels.par_chunks_mut(4 * PIXELS_PER_TASK).for_each(|chunk| {
                for px in chunk.chunks_exact_mut(4) {
                    match px[3] {
                        255 => {}
                        0 => px[..3].fill(0),
                        a => {
                            let scale = 255.0 / f32::from(a);
                            for c in &mut px[..3] {
                                *c = srgb.encode(table[usize::from(*c)] * scale);
                            }
                        }
                    }
                }
            });
        });
        RgbaImage {
            width,
            height,
            pixels,
        }
    }

    /// Straight sRGB8 pixels as they are.
    pub(super) fn from_straight(width: u32, height: u32, pixels: Vec<u8>) -> Self {
        RgbaImage {
            width,
            height,
            pixels,
        }
    }

    /// The pixel at column `x`, row `y` (row 0 at the top), or `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 4 * (y as usize * self.width as usize + x as usize);
        self.pixels.get(i..i + 4)?.try_into().ok()
    }

    /// The image as an OpenGL-style texture takes it (Blender's `gpu.types.GPUTexture` among
    /// them): `f32` in `[0, 1]` (the bytes over 255), rows from the bottom. Made on Pelt's
    /// threads: in Python the same conversion took half of a 1080p frame on a GPU.
    pub fn texture_floats(&self) -> Vec<f32> {
        let row = 4 * self.width as usize;
        let mut floats = vec![0.0f32; self.pixels.len()];
        if row == 0 {
            return floats;
        }
        pool().install(|| {
            floats
                .par_chunks_mut(row)
                .zip(self.pixels.par_chunks(row).rev())
                .for_each(|(out, bytes)| {
                    for (f, &b) in out.iter_mut().zip(bytes) {
                        *f = f32::from(b) * (1.0 / 255.0);
                    }
                });
        });
        floats
    }

    /// The image as the exporters take it (e.g. [`pelt_core::export::save_png`] with `srgb: true`).
    ///
    /// # Errors
    /// Never for an image made by the renderer (its sizes always agree).
    pub fn view(&self) -> Result<ImageRef<'_, u8>> {
        ImageRef::new(self.width as usize, self.height as usize, 4, &self.pixels)
    }
}

/// A linear-light RGBA image in `f32`: straight (not premultiplied) alpha, `height` rows of
/// `width` pixels from the top, from a half-float target (about three significant digits) or,
/// on a CPU adapter, a single-float one.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `height × width × 4` values.
    pub pixels: Vec<f32>,
}

impl LinearImage {
    /// Turns the half-float target's premultiplied bytes into straight alpha; fully transparent
    /// pixels are all zero.
    pub(super) fn from_premultiplied_f16(width: u32, height: u32, bytes: &[u8]) -> Self {
        let values = bytes
            .chunks_exact(8)
            .map(|px| std::array::from_fn(|c| f16::from_le_bytes([px[2 * c], px[2 * c + 1]]).to_f32()));
        Self::from_premultiplied(width, height, values)
    }

    /// [`LinearImage::from_premultiplied_f16`] of a single-float target.
    pub(super) fn from_premultiplied_f32(width: u32, height: u32, bytes: &[u8]) -> Self {
        Self::from_premultiplied(width, height, bytes.chunks_exact(16).map(premultiplied_f32))
    }

    /// Straight alpha from premultiplied values.
    fn from_premultiplied(width: u32, height: u32, values: impl Iterator<Item = [f32; 4]>) -> Self {
        let pixels = values
            .flat_map(|v| {
                let a = v[3];
                if a > 0.0 {
                    // An HDR value past the half range comes back infinite: keep it finite.
                    [v[0] / a, v[1] / a, v[2] / a, a].map(|c| c.min(f32::from(f16::MAX)))
                } else {
                    [0.0; 4]
                }
            })
            .collect();
        LinearImage {
            width,
            height,
            pixels,
        }
    }

    /// The pixel at column `x`, row `y` (row 0 at the top), or `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[f32; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 4 * (y as usize * self.width as usize + x as usize);
        self.pixels.get(i..i + 4)?.try_into().ok()
    }
}

/// A row of single-float premultiplied texels (little-endian) as straight sRGB8: color divided by
/// the alpha as stored (as an 8-bit target's is) and encoded once.
pub(super) fn straight_srgb8_row(row: &[u8], out: &mut [u8]) {
    let srgb = srgb8_encoder();
    for (px, texel) in out.chunks_exact_mut(4).zip(row.chunks_exact(16)) {
        let [r, g, b, a] = premultiplied_f32(texel);
        let alpha = unit_to_u8(a);
        if alpha == 0 {
            px.fill(0);
            continue;
        }
        let scale = 255.0 / f32::from(alpha);
        for (c, v) in px.iter_mut().zip([r, g, b]) {
            *c = srgb.encode(v * scale);
        }
        px[3] = alpha;
    }
}

/// One single-float texel's four values (little-endian bytes).
fn premultiplied_f32(texel: &[u8]) -> [f32; 4] {
    std::array::from_fn(|c| {
        f32::from_le_bytes([texel[4 * c], texel[4 * c + 1], texel[4 * c + 2], texel[4 * c + 3]])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_floats_are_the_bytes_over_255_bottom_row_first() {
        let pixels: Vec<u8> = (0..24).map(|i| (i * 11) as u8).collect();
        let image = RgbaImage {
            width: 2,
            height: 3,
            pixels: pixels.clone(),
        };
        let floats = image.texture_floats();
        for y in 0..3 {
            for i in 0..8 {
                let byte = pixels[8 * (2 - y) + i];
                let exact = f64::from(byte) / 255.0;
                assert!(
                    (f64::from(floats[8 * y + i]) - exact).abs() < 1e-7,
                    "row {y}, value {i}"
                );
            }
        }
        let empty = RgbaImage {
            width: 0,
            height: 0,
            pixels: Vec::new(),
        };
        assert!(empty.texture_floats().is_empty());
    }
}
