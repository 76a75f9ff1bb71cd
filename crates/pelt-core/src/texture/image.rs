//! The image description every writer takes: width × height pixels of 1 to 4 interleaved
//! channels, rows top to bottom (DESIGN.md §3: colors straight, not premultiplied, in files).
//!
//! Validation happens once, when the description is made, so the writers only check what their
//! format adds (sample type, finiteness, size limits of the container).

use crate::error::{PeltError, Result};

/// Largest width or height of an image: the OpenEXR data window holds `i32` coordinates, and PNG
/// and KTX2 allow at least as much.
pub const MAX_DIMENSION: usize = i32::MAX as usize;

/// Most interleaved channels per pixel (RGBA).
pub const MAX_CHANNELS: usize = 4;

/// A borrowed, validated image: `data` holds `width · height · channels` samples, pixel by pixel,
/// rows top to bottom, channels interleaved.
///
/// `T` is the sample type; the writers accept `u8` and `u16` (PNG) and `f32` and
/// [`half::f16`] (OpenEXR).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImageRef<'a, T> {
    width: usize,
    height: usize,
    channels: usize,
    data: &'a [T],
}

impl<'a, T> ImageRef<'a, T> {
    /// Describes `data` as a `width × height` image of `channels` interleaved channels.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `width`, `height` or `channels` when one is outside
    /// `1..=MAX_DIMENSION` / `1..=4`, or `data` when its length is not `width · height · channels`.
    pub fn new(width: usize, height: usize, channels: usize, data: &'a [T]) -> Result<Self> {
        let len = checked_len(width, height, channels)?;
        if data.len() != len {
            return Err(PeltError::parameter(
                "data",
                format!(
                    "must hold width · height · channels = {width} · {height} · {channels} = {len} \
                     samples, got {}",
                    data.len()
                ),
            ));
        }
        Ok(ImageRef {
            width,
            height,
            channels,
            data,
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Interleaved channels per pixel, 1 to 4.
    pub fn channels(&self) -> usize {
        self.channels
    }

    /// All samples, rows top to bottom.
    pub fn data(&self) -> &'a [T] {
        self.data
    }

    /// Samples of row `y` (0 is the top row), or `None` past the last row.
    pub fn row(&self, y: usize) -> Option<&'a [T]> {
        if y >= self.height {
            return None;
        }
        let stride = self.width * self.channels;
        self.data.get(y * stride..(y + 1) * stride)
    }
}

/// An owned, validated image (what [`crate::texture::pack_atlas`] returns); see [`ImageRef`].
#[derive(Debug, Clone, PartialEq)]
pub struct Image<T> {
    width: usize,
    height: usize,
    channels: usize,
    data: Vec<T>,
}

impl<T> Image<T> {
    /// Takes ownership of `data` as a `width × height` image of `channels` channels.
    ///
    /// # Errors
    /// As [`ImageRef::new`].
    pub fn new(width: usize, height: usize, channels: usize, data: Vec<T>) -> Result<Self> {
        ImageRef::new(width, height, channels, &data)?;
        Ok(Image {
            width,
            height,
            channels,
            data,
        })
    }

    /// The borrowed description the writers take.
    pub fn view(&self) -> ImageRef<'_, T> {
        ImageRef {
            width: self.width,
            height: self.height,
            channels: self.channels,
            data: &self.data,
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Interleaved channels per pixel, 1 to 4.
    pub fn channels(&self) -> usize {
        self.channels
    }

    /// All samples, rows top to bottom.
    pub fn data(&self) -> &[T] {
        &self.data
    }

    /// Gives the samples back.
    pub fn into_data(self) -> Vec<T> {
        self.data
    }
}

/// Splits layer-major data `[layers][height][width][channels]` (the layout of the shell stack)
/// into one [`ImageRef`] per layer, for writing each layer to its own file.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `layers` when it is 0, the size parameters as in
/// [`ImageRef::new`], or `data` when its length is not `layers · width · height · channels`.
pub fn layer_views<T>(
    width: usize,
    height: usize,
    channels: usize,
    layers: usize,
    data: &[T],
) -> Result<Vec<ImageRef<'_, T>>> {
    if layers == 0 {
        return Err(PeltError::parameter("layers", "must be at least 1"));
    }
    let per_layer = checked_len(width, height, channels)?;
    if per_layer.checked_mul(layers) != Some(data.len()) {
        return Err(PeltError::parameter(
            "data",
            format!(
                "must hold layers · width · height · channels = {layers} · {width} · {height} · \
                 {channels} samples, got {}",
                data.len()
            ),
        ));
    }
    data.chunks_exact(per_layer)
        .map(|layer| ImageRef::new(width, height, channels, layer))
        .collect()
}

/// `width · height · channels` after checking each factor's range; the product cannot overflow
/// on 64-bit targets, but the check keeps 32-bit ones honest.
pub(crate) fn checked_len(width: usize, height: usize, channels: usize) -> Result<usize> {
    for (name, value) in [("width", width), ("height", height)] {
        if !(1..=MAX_DIMENSION).contains(&value) {
            return Err(PeltError::parameter(
                name,
                format!("is {value}, must be in 1..={MAX_DIMENSION}"),
            ));
        }
    }
    if !(1..=MAX_CHANNELS).contains(&channels) {
        return Err(PeltError::parameter(
            "channels",
            format!("is {channels}, must be in 1..={MAX_CHANNELS}"),
        ));
    }
    width
        .checked_mul(height)
        .and_then(|n| n.checked_mul(channels))
        .ok_or_else(|| {
            PeltError::parameter(
                "width",
                format!("{width} × {height} × {channels} samples do not fit in memory"),
            )
        })
}
