//! PNG writer, 8 and 16 bits per sample, gray / gray + alpha / RGB / RGBA, through the `png`
//! crate.
//!
//! Lengyel et al. 2001, §2.2 keep each shell layer as an RGBA image; PNG is the lossless form
//! every engine and Blender read. Samples are written as given (straight alpha); the optional
//! `sRGB` chunk only declares how the color values are encoded, it changes no value. The encoder
//! is deterministic: the same image and options always give the same bytes.

use std::borrow::Cow;
use std::io::Write;
use std::path::Path;

use ::png::{BitDepth, ColorType, Encoder, EncodingError, SrgbRenderingIntent};

use super::{save_to_path, writer_error};
use crate::error::{PeltError, Result};
use crate::texture::image::ImageRef;

/// A sample type PNG can store: `u8` (8-bit) or `u16` (16-bit).
pub trait PngSample: Copy + Send + Sync + private::Sealed {
    /// Bit depth written to the header.
    #[doc(hidden)]
    const DEPTH: BitDepth;
    /// The samples as PNG stores them (big-endian for 16 bits).
    #[doc(hidden)]
    fn png_bytes(samples: &[Self]) -> Cow<'_, [u8]>;
}

impl PngSample for u8 {
    const DEPTH: BitDepth = BitDepth::Eight;
    fn png_bytes(samples: &[Self]) -> Cow<'_, [u8]> {
        Cow::Borrowed(samples)
    }
}

impl PngSample for u16 {
    const DEPTH: BitDepth = BitDepth::Sixteen;
    fn png_bytes(samples: &[Self]) -> Cow<'_, [u8]> {
        Cow::Owned(samples.iter().flat_map(|s| s.to_be_bytes()).collect())
    }
}

mod private {
    pub trait Sealed {}
    impl Sealed for u8 {}
    impl Sealed for u16 {}
}

/// Effort spent on deflate; every level is lossless and deterministic.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PngCompression {
    /// Fast, larger files.
    Fast,
    /// The `png` crate's balance of speed and size.
    #[default]
    Balanced,
    /// Slowest, smallest files.
    High,
}

/// Options of [`write_png`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PngOptions {
    /// Add an `sRGB` chunk (perceptual intent), declaring that the color values are sRGB
    /// encoded. Off by default: data such as coverage or tangents is not color.
    pub srgb: bool,
    /// Deflate effort.
    pub compression: PngCompression,
}

/// Writes `image` as a PNG: 1 channel is gray, 2 gray + alpha, 3 RGB, 4 RGBA; `u8` samples give
/// an 8-bit file, `u16` a 16-bit one.
///
/// # Errors
/// [`PeltError::Io`] (path [`super::WRITER_NAME`]) when `writer` fails.
pub fn write_png<T: PngSample, W: Write>(
    writer: W,
    image: &ImageRef<'_, T>,
    options: &PngOptions,
) -> Result<()> {
    // ImageRef caps both sides at 2^31 - 1, which is also PNG's own limit, so they fit in u32.
    let mut encoder = Encoder::new(writer, image.width() as u32, image.height() as u32);
    encoder.set_color(match image.channels() {
        1 => ColorType::Grayscale,
        2 => ColorType::GrayscaleAlpha,
        3 => ColorType::Rgb,
        _ => ColorType::Rgba,
    });
    encoder.set_depth(T::DEPTH);
    encoder.set_compression(match options.compression {
        PngCompression::Fast => ::png::Compression::Fast,
        PngCompression::Balanced => ::png::Compression::Balanced,
        PngCompression::High => ::png::Compression::High,
    });
    if options.srgb {
        encoder.set_source_srgb(SrgbRenderingIntent::Perceptual);
    }
    let mut png = encoder.write_header().map_err(encoding_error)?;
    png.write_image_data(&T::png_bytes(image.data()))
        .map_err(encoding_error)?;
    png.finish().map_err(encoding_error)
}

/// [`write_png`] into a new file at `path`.
///
/// # Errors
/// As [`write_png`]; I/O failures name `path`.
pub fn save_png<T: PngSample>(
    path: impl AsRef<Path>,
    image: &ImageRef<'_, T>,
    options: &PngOptions,
) -> Result<()> {
    save_to_path(path.as_ref(), |out| write_png(out, image, options))
}

/// The image was validated before encoding, so anything but an I/O failure is a bug here.
fn encoding_error(e: EncodingError) -> PeltError {
    match e {
        EncodingError::IoError(source) => writer_error(source),
        other => PeltError::Internal(format!("PNG encoder: {other}")),
    }
}
