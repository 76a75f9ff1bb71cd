//! [`RgbaImage`], what a render returns: 8-bit sRGB RGBA with straight alpha, rows top to bottom.

use crate::color::{srgb8_encoder, srgb8_to_linear_table};
use crate::error::Result;
use crate::export::ImageRef;

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

    /// The image as the exporters take it (e.g. [`crate::export::save_png`] with `srgb: true`).
    ///
    /// # Errors
    /// Never for an image made by the renderer (its sizes always agree).
    pub fn view(&self) -> Result<ImageRef<'_, u8>> {
        ImageRef::new(self.width as usize, self.height as usize, 4, &self.pixels)
    }
}
