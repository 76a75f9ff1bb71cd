//! What a render returns, rows top to bottom, straight alpha: [`RgbaImage`] (8-bit sRGB) and
//! [`LinearImage`] (linear floats).

use half::f16;

use pelt_core::error::Result;
use pelt_core::texture::ImageRef;
use pelt_core::texture::color::{srgb8_encoder, srgb8_to_linear_table};

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
    pub(super) fn from_premultiplied(width: u32, height: u32, mut pixels: Vec<u8>) -> Self {
        let (table, srgb) = (srgb8_to_linear_table(), srgb8_encoder());
        for px in pixels.chunks_exact_mut(4) {
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

    /// The image as the exporters take it (e.g. [`pelt_core::export::save_png`] with `srgb: true`).
    ///
    /// # Errors
    /// Never for an image made by the renderer (its sizes always agree).
    pub fn view(&self) -> Result<ImageRef<'_, u8>> {
        ImageRef::new(self.width as usize, self.height as usize, 4, &self.pixels)
    }
}

/// A linear-light RGBA image in `f32`: straight (not premultiplied) alpha, `height` rows of
/// `width` pixels from the top, from a half-float target (about three significant digits).
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
        let pixels = bytes
            .chunks_exact(8)
            .flat_map(|px| {
                let v: [f32; 4] =
                    std::array::from_fn(|c| f16::from_le_bytes([px[2 * c], px[2 * c + 1]]).to_f32());
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
