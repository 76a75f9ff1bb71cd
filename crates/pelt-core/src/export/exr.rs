//! OpenEXR writer for float images (single-part scanline files, `HALF` or `FLOAT` channels),
//! through the `exr` crate.
//!
//! Float data of the bake (per-layer coverage, density, PRT transfer coefficients; Lengyel et al.
//! 2001 §2.2 and the PRT shell-fur paper §2.2) must keep its range and precision, which 8- or
//! 16-bit PNG cannot. Pelt checks what the crate would accept silently (non-finite samples, which
//! Pelt promises never to write) and gives named errors; the crate lays out the file. Blocks are
//! compressed in Pelt's pool and written in increasing line order, so the bytes do not depend on
//! the thread count.

use std::io::{Cursor, Write};
use std::path::Path;

use ::exr::block::UncompressedBlock;
use ::exr::block::writer::ChunksWriter;
use ::exr::image::write::layers::{LayersWriter, WritableLayers};
use ::exr::prelude::{
    AnyChannel, AnyChannels, Blocks, Encoding, FlatSamples, Image, Layer, LayerAttributes, LineOrder,
    SmallVec,
};
use half::f16;
use rayon::prelude::*;

use super::{save_to_path, writer_error};
use crate::error::{PeltError, Result};
use crate::texture::image::ImageRef;
use crate::threads::pool;

/// Version flag: attribute or channel names longer than 31 bytes occur.
const LONG_NAMES: u32 = 0x400;
/// Names up to this length need no [`LONG_NAMES`] flag.
const SHORT_NAME_MAX: usize = 31;
/// Longest name any OpenEXR file allows.
const LONG_NAME_MAX: usize = 255;
/// Largest chunk payload: the chunk's size field is an `i32`.
const MAX_CHUNK_BYTES: usize = i32::MAX as usize;

/// A sample type OpenEXR can store: `f32` (`FLOAT`) or [`half::f16`] (`HALF`).
pub trait ExrSample: Copy + Send + Sync + private::Sealed {
    /// Bytes per sample in the file.
    #[doc(hidden)]
    const BYTES: usize;
    /// One channel's samples as the `exr` crate holds them.
    #[doc(hidden)]
    fn flat_samples(samples: impl Iterator<Item = Self>) -> FlatSamples;
    /// The value, for finiteness checks and messages.
    #[doc(hidden)]
    fn to_f64(self) -> f64;
}

impl ExrSample for f32 {
    const BYTES: usize = 4;
    fn flat_samples(samples: impl Iterator<Item = Self>) -> FlatSamples {
        FlatSamples::F32(samples.collect())
    }
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
}

impl ExrSample for f16 {
    const BYTES: usize = 2;
    fn flat_samples(samples: impl Iterator<Item = Self>) -> FlatSamples {
        FlatSamples::F16(samples.collect())
    }
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
}

mod private {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for half::f16 {}
}

/// How the scanline blocks are compressed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ExrCompression {
    /// `NO_COMPRESSION`: one scanline per block, stored raw.
    None,
    /// `ZIP_COMPRESSION`: 16 scanlines per block, predictor + zlib. Lossless.
    #[default]
    Zip,
}

impl ExrCompression {
    /// The `exr` crate's name for it.
    fn exr(self) -> ::exr::compression::Compression {
        match self {
            ExrCompression::None => ::exr::compression::Compression::Uncompressed,
            ExrCompression::Zip => ::exr::compression::Compression::ZIP16,
        }
    }

    /// Scanlines per block, fixed by the compression method.
    fn lines_per_block(self) -> usize {
        match self {
            ExrCompression::None => 1,
            ExrCompression::Zip => 16,
        }
    }
}

/// Options of [`write_exr`].
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ExrOptions {
    /// Block compression; ZIP by default.
    pub compression: ExrCompression,
    /// One name per channel, in the image's channel order; `None` gives the usual names for the
    /// channel count (see [`default_channel_names`]). Names are 1 to 255 bytes, without NUL,
    /// distinct.
    pub channel_names: Option<Vec<String>>,
}

/// The names OpenEXR readers expect for 1 to 4 channels: `Y`, `Y A`, `R G B`, `R G B A`.
pub fn default_channel_names(channels: usize) -> &'static [&'static str] {
    match channels {
        1 => &["Y"],
        2 => &["Y", "A"],
        3 => &["R", "G", "B"],
        _ => &["R", "G", "B", "A"],
    }
}

/// Writes `image` as a single-part scanline OpenEXR file with one `FLOAT` (`f32` samples) or
/// `HALF` (`f16` samples) channel per image channel.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `channel_names` (wrong count, empty, too long, NUL,
/// duplicate), `data` (a NaN or infinite sample, with its pixel and channel) or `width` (a block of
/// scanlines over OpenEXR's 2 GiB chunk limit); [`PeltError::Io`] (path
/// [`super::WRITER_NAME`]) when `writer` fails.
pub fn write_exr<T: ExrSample, W: Write>(
    mut writer: W,
    image: &ImageRef<'_, T>,
    options: &ExrOptions,
) -> Result<()> {
    let bytes = pool().install(|| encode_exr(image, options))?;
    writer.write_all(&bytes).map_err(writer_error)
}

/// [`write_exr`] into a new file at `path`.
///
/// # Errors
/// As [`write_exr`]; I/O failures name `path`.
pub fn save_exr<T: ExrSample>(
    path: impl AsRef<Path>,
    image: &ImageRef<'_, T>,
    options: &ExrOptions,
) -> Result<()> {
    // Encode first, so an invalid image leaves no empty file behind.
    let bytes = pool().install(|| encode_exr(image, options))?;
    save_to_path(path.as_ref(), |out| out.write_all(&bytes).map_err(writer_error))
}

/// The whole file in memory, its blocks compressed in the current rayon pool and written in
/// increasing line order, so the bytes do not depend on the thread count.
pub(crate) fn encode_exr<T: ExrSample>(image: &ImageRef<'_, T>, options: &ExrOptions) -> Result<Vec<u8>> {
    let names = channel_names(image.channels(), options)?;
    check_finite(image, &names)?;
    let lines = options.compression.lines_per_block();
    let line_bytes = image.width() * image.channels() * T::BYTES;
    if line_bytes.checked_mul(lines).is_none_or(|b| b > MAX_CHUNK_BYTES) {
        return Err(PeltError::parameter(
            "width",
            format!(
                "is {}: a block of {lines} scanlines would exceed OpenEXR's {MAX_CHUNK_BYTES}-byte \
                 chunk limit",
                image.width()
            ),
        ));
    }
    let channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = names
        .iter()
        .enumerate()
        .map(|(c, name)| {
            let samples = image.data().iter().skip(c).step_by(image.channels()).copied();
            AnyChannel::new(name.as_str(), T::flat_samples(samples))
        })
        .collect();
    let encoding = Encoding {
        compression: options.compression.exr(),
        blocks: Blocks::ScanLines,
        // INCREASING_Y: blocks from the top row down, matching the image's row order.
        line_order: LineOrder::Increasing,
    };
    let layer = Layer::new(
        (image.width(), image.height()),
        LayerAttributes::default(),
        encoding,
        AnyChannels::sort(channels),
    );
    let file = Image::from_layer(layer);
    let headers = file.layer_data.infer_headers(&file.attributes);
    let layers = file.layer_data.create_writer(&headers);
    let mut out = Cursor::new(Vec::new());
    ::exr::block::write(&mut out, headers, true, |meta, chunks| {
        // Blocks are extracted and compressed in the current pool (Pelt's, or the caller's when
        // the texture set encodes files in parallel), then written in file order.
        let indices: Vec<_> = meta.enumerate_ordered_header_block_indices().collect();
        let compressed: Vec<_> = indices
            .into_par_iter()
            .map(|(in_header, index)| {
                let data = layers.extract_uncompressed_block(&meta.headers, index);
                let block = UncompressedBlock { index, data };
                block
                    .compress_to_chunk(&meta.headers)
                    .map(|chunk| (in_header, chunk))
            })
            .collect::<std::result::Result<_, _>>()?;
        for (in_header, chunk) in compressed {
            chunks.write_chunk(in_header, chunk)?;
        }
        Ok(())
    })
    .map_err(|e| PeltError::Internal(format!("OpenEXR encoder: {e}")))?;
    let mut bytes = out.into_inner();
    // The spec's "long names" bit (version field, bit 10) covers channel names over 31 bytes too;
    // the crate sets it for attribute names only.
    if names.iter().any(|n| n.len() > SHORT_NAME_MAX) {
        bytes[5] |= (LONG_NAMES >> 8) as u8;
    }
    Ok(bytes)
}

/// The validated channel names, in the image's channel order.
fn channel_names(channels: usize, options: &ExrOptions) -> Result<Vec<String>> {
    let Some(names) = &options.channel_names else {
        return Ok(default_channel_names(channels)
            .iter()
            .map(|n| n.to_string())
            .collect());
    };
    if names.len() != channels {
        return Err(PeltError::parameter(
            "channel_names",
            format!("has {} names, the image has {channels} channels", names.len()),
        ));
    }
    for (i, name) in names.iter().enumerate() {
        if name.is_empty() || name.len() > LONG_NAME_MAX || name.contains('\0') {
            return Err(PeltError::parameter(
                "channel_names",
                format!("name {i} ({name:?}) must be 1 to {LONG_NAME_MAX} bytes without NUL"),
            ));
        }
        if names[..i].contains(name) {
            return Err(PeltError::parameter(
                "channel_names",
                format!("name {i} ({name:?}) appears twice"),
            ));
        }
    }
    Ok(names.clone())
}

/// OpenEXR can hold NaN and infinity, but Pelt promises finite outputs, so a non-finite sample
/// is a bug upstream that should surface here rather than in a renderer.
fn check_finite<T: ExrSample>(image: &ImageRef<'_, T>, names: &[String]) -> Result<()> {
    let Some(i) = image.data().iter().position(|s| !s.to_f64().is_finite()) else {
        return Ok(());
    };
    let pixel = i / image.channels();
    Err(PeltError::parameter(
        "data",
        format!(
            "pixel ({}, {}) channel {} is {} (not finite)",
            pixel % image.width(),
            pixel / image.width(),
            names[i % image.channels()],
            image.data()[i].to_f64()
        ),
    ))
}
