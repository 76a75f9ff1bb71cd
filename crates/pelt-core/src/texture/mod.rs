//! Images in memory and what is computed over them, shared by the hair volume (its LOD chain) and
//! the export (its files): [`image`] (validated views of 8-bit, 16-bit-float and f32 pixels),
//! [`mip`] (mip chains that average coverage-weighted color in linear light, Lengyel et al. 2001
//! §2.4), [`atlas`] (the shell layers side by side in one image, for materials without texture
//! arrays), [`color`] (the sRGB transfer functions) and [`read`] (light probes read through the
//! `image` crate).
//!
//! Kept by hand rather than taken from the `image` crate: the mips weight color by coverage in
//! linear light and must give the same bytes for any thread count, which a generic resize does not.

pub mod atlas;
pub mod color;
pub mod image;
pub mod mip;
pub mod read;

#[cfg(test)]
mod tests;

pub use atlas::{AtlasLayout, pack_atlas};
pub use image::{Image, ImageRef, layer_views};
pub use mip::{MipAlpha, MipLevels, MipOptions, full_mip_count, mip_chain_rgba8, mip_chain_rgba16f};
pub use read::{LinearRgb, read_light_probe};
