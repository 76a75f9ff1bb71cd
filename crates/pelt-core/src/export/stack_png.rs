//! PNG encodings of the baked stack that both the glTF export and the texture sets carry: single
//! shell layers, atlases (shells, tangents, 8-bit transfer textures) and the fin texture.
//!
//! Lengyel et al. 2001, §2.2: each shell layer is an RGBA image; the atlas ([`super::atlas`])
//! lays them side by side for targets without texture arrays. The PRT shell-fur paper, §2.3,
//! packs 4 transfer coefficients per RGBA texel; glTF images are 8-bit, so the transfer goes into
//! PNG in its 8-bit packing (with the scale and bias the manifest and extras state).
//!
//! Encoding jobs run in parallel in Pelt's pool and are collected in job order, so the bytes do
//! not depend on the thread count.

use rayon::prelude::*;

use super::png::{PngCompression, PngOptions, write_png};
use crate::error::Result;
use crate::prt::pack::PackedU8;
use crate::texture::atlas::{AtlasLayout, pack_atlas};
use crate::texture::image::ImageRef;
use crate::threads::pool;
use crate::volume::HairVolume;

/// One image to encode, borrowed from the bake.
#[derive(Debug, Clone, Copy)]
pub(crate) enum StackImage<'a> {
    /// Shell layer `layer` (sRGB color, straight alpha).
    Layer(&'a HairVolume, usize),
    /// Every shell layer in the atlas (sRGB).
    ShellAtlas(&'a HairVolume),
    /// Every tangent layer in the atlas (packed `0.5·d + 0.5`, linear).
    TangentAtlas(&'a HairVolume),
    /// The fin texture (sRGB).
    Fin(&'a HairVolume),
    /// 8-bit transfer texture `texture`, its layers in the atlas (linear).
    Transfer(&'a PackedU8, usize),
}

impl StackImage<'_> {
    /// Whether the image holds sRGB-encoded color (the PNG gets an `sRGB` chunk) rather than data.
    pub(crate) fn is_color(&self) -> bool {
        matches!(
            self,
            StackImage::Layer(..) | StackImage::ShellAtlas(_) | StackImage::Fin(_)
        )
    }

    /// Texels of the image written (an atlas counts its empty cells too).
    pub(crate) fn texels(&self) -> usize {
        let atlas = |layers, side| AtlasLayout::new(layers, side).map_or(usize::MAX, |a| a.width * a.height);
        match *self {
            StackImage::Layer(volume, _) => volume.resolution * volume.resolution,
            StackImage::ShellAtlas(volume) | StackImage::TangentAtlas(volume) => {
                atlas(volume.layers, volume.resolution)
            }
            StackImage::Fin(volume) => volume.fin_size[0] * volume.fin_size[1],
            StackImage::Transfer(packed, _) => atlas(packed.layers, packed.resolution),
        }
    }

    /// The PNG file.
    pub(crate) fn encode(&self) -> Result<Vec<u8>> {
        let options = PngOptions {
            srgb: self.is_color(),
            compression: PngCompression::Fast,
        };
        let mut out = Vec::new();
        match *self {
            StackImage::Layer(volume, layer) => {
                let r = volume.resolution;
                let size = 4 * r * r;
                let data = &volume.shells[layer * size..(layer + 1) * size];
                write_png(&mut out, &ImageRef::new(r, r, 4, data)?, &options)?;
            }
            StackImage::ShellAtlas(volume) => {
                let layout = AtlasLayout::new(volume.layers, volume.resolution)?;
                let atlas = pack_atlas(&layout, 4, &volume.shells)?;
                write_png(&mut out, &atlas.view(), &options)?;
            }
            StackImage::TangentAtlas(volume) => {
                let layout = AtlasLayout::new(volume.layers, volume.resolution)?;
                let atlas = pack_atlas(&layout, 4, &volume.tangents)?;
                write_png(&mut out, &atlas.view(), &options)?;
            }
            StackImage::Fin(volume) => {
                let [w, h] = volume.fin_size;
                write_png(&mut out, &ImageRef::new(w, h, 4, &volume.fin)?, &options)?;
            }
            StackImage::Transfer(packed, texture) => {
                let layout = AtlasLayout::new(packed.layers, packed.resolution)?;
                let size = 4 * packed.layers * packed.resolution * packed.resolution;
                let data = &packed.texels[texture * size..(texture + 1) * size];
                let atlas = pack_atlas(&layout, 4, data)?;
                write_png(&mut out, &atlas.view(), &options)?;
            }
        }
        Ok(out)
    }
}

/// Encodes every image in parallel; the result is in `images` order.
///
/// # Errors
/// Whatever the atlas or PNG writers report (sizes were checked by
/// [`super::ExportInput::validate`], so none is expected).
pub(crate) fn encode_all(images: &[StackImage<'_>]) -> Result<Vec<Vec<u8>>> {
    pool().install(|| images.par_iter().map(StackImage::encode).collect())
}
