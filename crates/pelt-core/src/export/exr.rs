//! OpenEXR writer for float images (single-part scanline files, `HALF` or `FLOAT` channels),
//! written by hand from the OpenEXR file layout.
//!
//! Float data of the bake (per-layer coverage, density, PRT transfer coefficients; Lengyel et al.
//! 2001 §2.2 and the PRT shell-fur paper §2.2) must keep its range and precision, which 8- or
//! 16-bit PNG cannot. The file is: magic number, version field, one header (the eight required
//! attributes, in alphabetical order), the line offset table, then the scanline blocks. Inside a
//! block each scanline stores its channels one after the other in alphabetical order of their
//! names, little-endian. `ZIP` compression packs 16 scanlines per block: bytes split into two
//! halves (even then odd positions), a delta predictor, then zlib; a block that would not shrink
//! is stored raw, which readers recognise by its size. Blocks are compressed in parallel and
//! concatenated in order, so the bytes do not depend on the thread count.

use std::io::Write;
use std::path::Path;

use flate2::Compression;
use flate2::write::ZlibEncoder;
use half::f16;
use rayon::prelude::*;

use super::{save_to_path, writer_error};
use crate::error::{PeltError, Result};
use crate::texture::image::ImageRef;
use crate::threads::pool;

/// First four bytes of every OpenEXR file (20000630 little-endian).
const MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
/// Format version 2 in the low byte; flag bits above it.
const VERSION: u32 = 2;
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
    /// The channel's pixel type code in the channel list.
    #[doc(hidden)]
    const PIXEL_TYPE: i32;
    /// Bytes per sample in the file.
    #[doc(hidden)]
    const BYTES: usize;
    /// Appends the sample little-endian.
    #[doc(hidden)]
    fn append_le(self, out: &mut Vec<u8>);
    /// The value, for finiteness checks and messages.
    #[doc(hidden)]
    fn to_f64(self) -> f64;
}

impl ExrSample for f32 {
    const PIXEL_TYPE: i32 = 2;
    const BYTES: usize = 4;
    fn append_le(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
}

impl ExrSample for f16 {
    const PIXEL_TYPE: i32 = 1;
    const BYTES: usize = 2;
    fn append_le(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
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
    /// Code of the `compression` attribute.
    fn code(self) -> u8 {
        match self {
            ExrCompression::None => 0,
            ExrCompression::Zip => 3,
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

/// The whole file in memory, compressing blocks in the current rayon pool.
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
    // Channels are stored in alphabetical (byte-wise) order of their names.
    let mut order: Vec<usize> = (0..names.len()).collect();
    order.sort_by(|&a, &b| names[a].as_bytes().cmp(names[b].as_bytes()));

    let header = header::<T>(image, &names, &order, options.compression);
    let blocks = image.height().div_ceil(lines);
    let packed: Vec<Vec<u8>> = (0..blocks)
        .into_par_iter()
        .map(|b| {
            let rows = b * lines..((b + 1) * lines).min(image.height());
            let raw = raw_block(image, &order, rows);
            match options.compression {
                ExrCompression::None => Ok(raw),
                ExrCompression::Zip => zip_block(raw),
            }
        })
        .collect::<Result<_>>()?;

    let table_bytes = 8 * blocks;
    let data_bytes: usize = packed.iter().map(|p| 8 + p.len()).sum();
    let mut out = Vec::with_capacity(header.len() + table_bytes + data_bytes);
    out.extend_from_slice(&header);
    let mut offset = (header.len() + table_bytes) as u64;
    for p in &packed {
        out.extend_from_slice(&offset.to_le_bytes());
        offset += (8 + p.len()) as u64;
    }
    for (b, p) in packed.iter().enumerate() {
        // Both fit in i32: the first row is below the height (≤ i32::MAX) and blocks are capped.
        out.extend_from_slice(&((b * lines) as i32).to_le_bytes());
        out.extend_from_slice(&(p.len() as i32).to_le_bytes());
        out.extend_from_slice(p);
    }
    Ok(out)
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

/// Magic number, version field and header attributes, ended by a NUL byte.
fn header<T: ExrSample>(
    image: &ImageRef<'_, T>,
    names: &[String],
    order: &[usize],
    compression: ExrCompression,
) -> Vec<u8> {
    let long = names.iter().any(|n| n.len() > SHORT_NAME_MAX);
    let mut out = Vec::with_capacity(512);
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&(VERSION | if long { LONG_NAMES } else { 0 }).to_le_bytes());

    let mut chlist = Vec::new();
    for &c in order {
        chlist.extend_from_slice(names[c].as_bytes());
        chlist.push(0);
        chlist.extend_from_slice(&T::PIXEL_TYPE.to_le_bytes());
        // pLinear and three reserved bytes, then x and y sampling of 1 (no subsampling).
        chlist.extend_from_slice(&[0; 4]);
        chlist.extend_from_slice(&1i32.to_le_bytes());
        chlist.extend_from_slice(&1i32.to_le_bytes());
    }
    chlist.push(0);
    // The validated sides are at most i32::MAX, so the largest coordinate fits in i32.
    let window: Vec<u8> = [0, 0, image.width() as i32 - 1, image.height() as i32 - 1]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let floats = |values: &[f32]| -> Vec<u8> { values.iter().flat_map(|v| v.to_le_bytes()).collect() };

    attribute(&mut out, "channels", "chlist", &chlist);
    attribute(&mut out, "compression", "compression", &[compression.code()]);
    attribute(&mut out, "dataWindow", "box2i", &window);
    attribute(&mut out, "displayWindow", "box2i", &window);
    // INCREASING_Y: blocks from the top row down, matching the image's row order.
    attribute(&mut out, "lineOrder", "lineOrder", &[0]);
    attribute(&mut out, "pixelAspectRatio", "float", &floats(&[1.0]));
    attribute(&mut out, "screenWindowCenter", "v2f", &floats(&[0.0, 0.0]));
    attribute(&mut out, "screenWindowWidth", "float", &floats(&[1.0]));
    out.push(0);
    out
}

/// One attribute: name, type name (both NUL-terminated), value size and value.
fn attribute(out: &mut Vec<u8>, name: &str, type_name: &str, value: &[u8]) {
    out.extend_from_slice(name.as_bytes());
    out.push(0);
    out.extend_from_slice(type_name.as_bytes());
    out.push(0);
    // Header values are a few hundred bytes at most (255-byte names, four channels).
    out.extend_from_slice(&(value.len() as i32).to_le_bytes());
    out.extend_from_slice(value);
}

/// Uncompressed block: per scanline, each channel's samples in `order`, little-endian.
fn raw_block<T: ExrSample>(
    image: &ImageRef<'_, T>,
    order: &[usize],
    rows: std::ops::Range<usize>,
) -> Vec<u8> {
    let channels = image.channels();
    let mut out = Vec::with_capacity(rows.len() * image.width() * channels * T::BYTES);
    for y in rows {
        let Some(row) = image.row(y) else { break };
        for &c in order {
            for pixel in row.chunks_exact(channels) {
                pixel[c].append_le(&mut out);
            }
        }
    }
    out
}

/// ZIP compression of one block; the raw bytes when compression would not shrink them.
fn zip_block(raw: Vec<u8>) -> Result<Vec<u8>> {
    if raw.is_empty() {
        return Ok(raw);
    }
    // Bytes at even positions first, odd positions second: the low and high bytes of the
    // samples end up in separate runs, each smoother than the mix.
    let half = raw.len().div_ceil(2);
    let mut split = vec![0u8; raw.len()];
    for (i, &byte) in raw.iter().enumerate() {
        split[if i % 2 == 0 { i / 2 } else { half + i / 2 }] = byte;
    }
    // Delta predictor: each byte becomes its difference from the previous one, biased by 128.
    let mut previous = split[0];
    for byte in &mut split[1..] {
        let current = *byte;
        *byte = current.wrapping_sub(previous).wrapping_add(128);
        previous = current;
    }
    let mut encoder = ZlibEncoder::new(Vec::with_capacity(raw.len() / 2), Compression::default());
    let compressed = encoder
        .write_all(&split)
        .and_then(|()| encoder.finish())
        .map_err(|e| PeltError::Internal(format!("zlib on an in-memory buffer failed: {e}")))?;
    Ok(if compressed.len() < raw.len() {
        compressed
    } else {
        raw
    })
}
