//! KTX2 writer for uncompressed 2D and 2D-array textures with mipmaps, written by hand (the `ktx2`
//! crate only reads) from the KTX 2.0 specification and the Khronos Data Format specification.
//!
//! Engines sample the shell layers of Lengyel et al. 2001 (§2.2) as one 2D-array texture, with the
//! mipmaps their level of detail relies on (§2.4); KTX2 carries exactly that to Vulkan, WebGPU,
//! three.js, Godot and Unity. The file is: identifier, header, index, level index (base level
//! first), a data format descriptor with one basic block, key/value data (`KTXorientation` = `rd`,
//! rows top to bottom, and `KTXwriter`), then the levels from the smallest to the base, each
//! aligned to `lcm(texel size, 4)` bytes. Inside a level the layers follow each other, rows are
//! tightly packed, data is little-endian. No supercompression.

use std::io::Write;
use std::path::Path;

use half::f16;

use super::{save_to_path, writer_error};
use crate::error::{PeltError, Result};
use crate::texture::mip::{self, MAX_MIP_DIMENSION, MipOptions, full_mip_count, level_side};

/// The 12-byte file identifier, «KTX 20»\r\n\x1A\n.
const IDENTIFIER: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];
/// Identifier, nine header words and the index (four u32, two u64).
const HEADER_BYTES: usize = 12 + 9 * 4 + 4 * 4 + 2 * 8;
/// One level index entry: byte offset, byte length, uncompressed byte length.
const LEVEL_INDEX_BYTES: usize = 24;

/// Data format descriptor constants (Khronos Data Format specification 1.3, basic block).
mod dfd {
    /// Basic block version.
    pub const VERSION: u32 = 2;
    /// Block header words, model words and 4 samples of 4 words each.
    pub const BLOCK_BYTES: u32 = 24 + 4 * 16;
    /// `KHR_DF_MODEL_RGBSDA`.
    pub const MODEL_RGBSDA: u32 = 1;
    /// `KHR_DF_PRIMARIES_BT709` (the sRGB primaries).
    pub const PRIMARIES_BT709: u32 = 1;
    /// `KHR_DF_TRANSFER_LINEAR`.
    pub const TRANSFER_LINEAR: u32 = 1;
    /// `KHR_DF_TRANSFER_SRGB`.
    pub const TRANSFER_SRGB: u32 = 2;
    /// Channel id of alpha in RGBSDA.
    pub const ALPHA: u32 = 15;
    /// Channel ids of RGBSDA: red, green, blue, alpha.
    pub const CHANNELS: [u32; 4] = [0, 1, 2, ALPHA];
    /// Sample qualifier: this sample is linear even if the transfer function is not.
    pub const QUALIFIER_LINEAR: u32 = 0x10;
    /// Sample qualifier: signed values.
    pub const QUALIFIER_SIGNED: u32 = 0x40;
    /// Sample qualifier: floating-point values.
    pub const QUALIFIER_FLOAT: u32 = 0x80;
}

/// Texel formats the writer supports (Vulkan `VkFormat` names).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ktx2Format {
    /// `VK_FORMAT_R8G8B8A8_UNORM`: linear bytes (data such as coverage or tangents).
    Rgba8Unorm,
    /// `VK_FORMAT_R8G8B8A8_SRGB`: sRGB-encoded color bytes, linear alpha.
    Rgba8Srgb,
    /// `VK_FORMAT_R16G16B16A16_SFLOAT`: half floats, linear.
    Rgba16Float,
}

impl Ktx2Format {
    /// The `VkFormat` enum value stored in the header.
    pub const fn vk_format(self) -> u32 {
        match self {
            Ktx2Format::Rgba8Unorm => 37,
            Ktx2Format::Rgba8Srgb => 43,
            Ktx2Format::Rgba16Float => 97,
        }
    }

    /// Bytes per texel.
    pub const fn texel_bytes(self) -> usize {
        match self {
            Ktx2Format::Rgba8Unorm | Ktx2Format::Rgba8Srgb => 4,
            Ktx2Format::Rgba16Float => 8,
        }
    }

    /// Bytes of one component (the header's `typeSize`).
    const fn type_size(self) -> u32 {
        match self {
            Ktx2Format::Rgba8Unorm | Ktx2Format::Rgba8Srgb => 1,
            Ktx2Format::Rgba16Float => 2,
        }
    }

    /// Level data is aligned to the least common multiple of the texel size and 4.
    const fn level_alignment(self) -> usize {
        match self {
            Ktx2Format::Rgba8Unorm | Ktx2Format::Rgba8Srgb => 4,
            Ktx2Format::Rgba16Float => 8,
        }
    }
}

/// A validated texture ready to write: base size, format, plain 2D or array, and every level's
/// bytes (all layers, layer-major, rows top to bottom, tightly packed, little-endian).
#[derive(Debug, Clone, PartialEq)]
pub struct Ktx2Texture {
    format: Ktx2Format,
    width: usize,
    height: usize,
    array_layers: Option<usize>,
    levels: Vec<Vec<u8>>,
}

impl Ktx2Texture {
    /// A texture from given level bytes; `levels[0]` is the base. `array_layers: None` makes a
    /// plain 2D texture, `Some(n)` a 2D array of `n` layers (even `n = 1`).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `width` or `height` (outside
    /// `1..=MAX_MIP_DIMENSION`), `array_layers` (0 or over `u32::MAX`), `levels` (none, or more
    /// than [`full_mip_count`]), `levels[i]` (length not `max(1, width >> i) · max(1, height >> i)
    /// · layers · texel bytes`), or, for [`Ktx2Format::Rgba16Float`], a NaN or infinite half.
    pub fn new(
        format: Ktx2Format,
        width: usize,
        height: usize,
        array_layers: Option<usize>,
        levels: Vec<Vec<u8>>,
    ) -> Result<Self> {
        let layers = check_shape(width, height, array_layers)?;
        let full = full_mip_count(width, height);
        if !(1..=full).contains(&levels.len()) {
            return Err(PeltError::parameter(
                "levels",
                format!(
                    "has {} levels, must have 1..={full} for a {width} × {height} base",
                    levels.len()
                ),
            ));
        }
        for (i, level) in levels.iter().enumerate() {
            let (w, h) = (level_side(width, i), level_side(height, i));
            // Sides are at most 2^16 and texels 8 bytes, so only the layer count can overflow.
            let Some(expected) = layers.checked_mul(w * h * format.texel_bytes()) else {
                return Err(PeltError::parameter(
                    "array_layers",
                    format!("{layers} layers of {w} × {h} texels do not fit in memory"),
                ));
            };
            if level.len() != expected {
                return Err(PeltError::parameter(
                    format!("levels[{i}]"),
                    format!(
                        "must hold {w} × {h} texels × {layers} layers × {} bytes = {expected} \
                         bytes, got {}",
                        format.texel_bytes(),
                        level.len()
                    ),
                ));
            }
            if format == Ktx2Format::Rgba16Float {
                let halves: Vec<f16> = level
                    .chunks_exact(2)
                    .map(|b| f16::from_le_bytes([b[0], b[1]]))
                    .collect();
                mip::check_finite_f16(&format!("levels[{i}]"), w, h, &halves)?;
            }
        }
        Ok(Ktx2Texture {
            format,
            width,
            height,
            array_layers,
            levels,
        })
    }

    /// A texture whose levels are generated from RGBA8 `base` (layer-major, rows top to bottom)
    /// by [`mip::mip_chain_rgba8`], in sRGB when `format` is [`Ktx2Format::Rgba8Srgb`].
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `format` when it is not an RGBA8 format, and as
    /// [`mip::mip_chain_rgba8`] and [`Ktx2Texture::new`].
    pub fn from_rgba8(
        format: Ktx2Format,
        width: usize,
        height: usize,
        array_layers: Option<usize>,
        base: &[u8],
        options: &MipOptions,
    ) -> Result<Self> {
        if format == Ktx2Format::Rgba16Float {
            return Err(PeltError::parameter(
                "format",
                "must be Rgba8Unorm or Rgba8Srgb for u8 data",
            ));
        }
        let layers = check_shape(width, height, array_layers)?;
        let srgb = format == Ktx2Format::Rgba8Srgb;
        let levels = mip::mip_chain_rgba8(width, height, layers, base, srgb, options)?;
        Self::new(format, width, height, array_layers, levels)
    }

    /// A [`Ktx2Format::Rgba16Float`] texture whose levels are generated from `base` (layer-major,
    /// rows top to bottom) by [`mip::mip_chain_rgba16f`].
    ///
    /// # Errors
    /// As [`mip::mip_chain_rgba16f`] and [`Ktx2Texture::new`].
    pub fn from_rgba16f(
        width: usize,
        height: usize,
        array_layers: Option<usize>,
        base: &[f16],
        options: &MipOptions,
    ) -> Result<Self> {
        let layers = check_shape(width, height, array_layers)?;
        let chain = mip::mip_chain_rgba16f(width, height, layers, base, options)?;
        let levels = chain
            .iter()
            .map(|level| level.iter().flat_map(|v| v.to_le_bytes()).collect())
            .collect();
        Self::new(Ktx2Format::Rgba16Float, width, height, array_layers, levels)
    }

    /// Texel format.
    pub fn format(&self) -> Ktx2Format {
        self.format
    }

    /// Base width in texels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Base height in texels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// `Some(layers)` for an array texture, `None` for a plain 2D texture.
    pub fn array_layers(&self) -> Option<usize> {
        self.array_layers
    }

    /// The levels' bytes, base first.
    pub fn levels(&self) -> &[Vec<u8>] {
        &self.levels
    }
}

/// Writes `texture` as a KTX2 file.
///
/// # Errors
/// [`PeltError::Io`] (path [`super::WRITER_NAME`]) when `writer` fails.
pub fn write_ktx2<W: Write>(mut writer: W, texture: &Ktx2Texture) -> Result<()> {
    writer.write_all(&encode_ktx2(texture)).map_err(writer_error)
}

/// [`write_ktx2`] into a new file at `path`.
///
/// # Errors
/// As [`write_ktx2`]; I/O failures name `path`.
pub fn save_ktx2(path: impl AsRef<Path>, texture: &Ktx2Texture) -> Result<()> {
    save_to_path(path.as_ref(), |out| write_ktx2(out, texture))
}

/// Layer count after checking the base size and the layer count.
fn check_shape(width: usize, height: usize, array_layers: Option<usize>) -> Result<usize> {
    for (name, side) in [("width", width), ("height", height)] {
        if !(1..=MAX_MIP_DIMENSION).contains(&side) {
            return Err(PeltError::parameter(
                name,
                format!("is {side}, must be in 1..={MAX_MIP_DIMENSION}"),
            ));
        }
    }
    match array_layers {
        None => Ok(1),
        Some(n) if n >= 1 && u32::try_from(n).is_ok() => Ok(n),
        Some(n) => Err(PeltError::parameter(
            "array_layers",
            format!("is {n}, must be in 1..={}", u32::MAX),
        )),
    }
}

/// The whole file. Sizes were validated by [`Ktx2Texture::new`], so every header field fits.
pub(crate) fn encode_ktx2(texture: &Ktx2Texture) -> Vec<u8> {
    let format = texture.format;
    let level_count = texture.levels.len();
    let dfd = data_format_descriptor(format);
    let kvd = key_value_data();
    let dfd_offset = HEADER_BYTES + LEVEL_INDEX_BYTES * level_count;
    let kvd_offset = dfd_offset + dfd.len();

    // Levels are stored smallest first; each starts on the format's alignment.
    let align = format.level_alignment();
    let mut offsets = vec![0usize; level_count];
    let mut end = kvd_offset + kvd.len();
    for level in (0..level_count).rev() {
        offsets[level] = end.next_multiple_of(align);
        end = offsets[level] + texture.levels[level].len();
    }

    let mut out = Vec::with_capacity(end);
    out.extend_from_slice(&IDENTIFIER);
    let words = [
        format.vk_format(),
        format.type_size(),
        texture.width as u32,
        texture.height as u32,
        0, // pixelDepth: 2D
        texture.array_layers.map_or(0, |n| n as u32),
        1, // faceCount: not a cubemap
        level_count as u32,
        0, // supercompressionScheme: none
        dfd_offset as u32,
        dfd.len() as u32,
        kvd_offset as u32,
        kvd.len() as u32,
    ];
    for word in words {
        out.extend_from_slice(&word.to_le_bytes());
    }
    // No supercompression global data: offset and length 0.
    out.extend_from_slice(&[0; 16]);
    for (level, data) in texture.levels.iter().enumerate() {
        let length = data.len() as u64;
        out.extend_from_slice(&(offsets[level] as u64).to_le_bytes());
        out.extend_from_slice(&length.to_le_bytes());
        out.extend_from_slice(&length.to_le_bytes());
    }
    out.extend_from_slice(&dfd);
    out.extend_from_slice(&kvd);
    for level in (0..level_count).rev() {
        out.resize(offsets[level], 0);
        out.extend_from_slice(&texture.levels[level]);
    }
    out
}

/// `dfdTotalSize` followed by one basic descriptor block with four samples (R, G, B, A).
fn data_format_descriptor(format: Ktx2Format) -> Vec<u8> {
    let (transfer, bits, qualifiers, lower, upper) = match format {
        Ktx2Format::Rgba8Unorm => (dfd::TRANSFER_LINEAR, 8, 0, 0, 255),
        Ktx2Format::Rgba8Srgb => (dfd::TRANSFER_SRGB, 8, 0, 0, 255),
        // Float samples span [-1, 1] by convention, stored as f32 bit patterns.
        Ktx2Format::Rgba16Float => (
            dfd::TRANSFER_LINEAR,
            16,
            dfd::QUALIFIER_FLOAT | dfd::QUALIFIER_SIGNED,
            (-1.0f32).to_bits(),
            1.0f32.to_bits(),
        ),
    };
    let mut words = vec![
        4 + dfd::BLOCK_BYTES,
        // Vendor Khronos (0) and descriptor type basic (0).
        0,
        dfd::VERSION | (dfd::BLOCK_BYTES << 16),
        // Flags 0: straight alpha.
        dfd::MODEL_RGBSDA | (dfd::PRIMARIES_BT709 << 8) | (transfer << 16),
        // Texel block 1 × 1 × 1 × 1, stored as dimension - 1.
        0,
        // bytesPlane0 is the texel size; the other planes are empty.
        format.texel_bytes() as u32,
        0,
    ];
    for (i, channel) in dfd::CHANNELS.into_iter().enumerate() {
        let mut channel_type = channel | qualifiers;
        // With a non-linear transfer function the alpha sample must be flagged linear.
        if transfer == dfd::TRANSFER_SRGB && channel == dfd::ALPHA {
            channel_type |= dfd::QUALIFIER_LINEAR;
        }
        let bit_offset = i as u32 * bits;
        words.push(bit_offset | ((bits - 1) << 16) | (channel_type << 24));
        words.push(0); // sample position 0, 0, 0, 0
        words.push(lower);
        words.push(upper);
    }
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// The key/value pairs, sorted by key, each padded to 4 bytes.
fn key_value_data() -> Vec<u8> {
    let writer = format!("pelt {}", crate::VERSION);
    let pairs = [("KTXorientation", "rd"), ("KTXwriter", writer.as_str())];
    let mut out = Vec::new();
    for (key, value) in pairs {
        // Key and value are NUL-terminated strings.
        let length = key.len() + value.len() + 2;
        out.extend_from_slice(&(length as u32).to_le_bytes());
        out.extend_from_slice(key.as_bytes());
        out.push(0);
        out.extend_from_slice(value.as_bytes());
        out.push(0);
        out.resize(out.len().next_multiple_of(4), 0);
    }
    out
}
