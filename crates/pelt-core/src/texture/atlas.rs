//! Shell layers laid out side by side in one grid image, for targets without texture arrays.
//!
//! Lengyel et al. 2001, §2.2 sample the hair volume into a stack of shell textures. Blender
//! materials and many engines have no 2D-array textures, so the stack is also exported as an
//! atlas: `columns = ⌈√L⌉`, `rows = ⌈L / columns⌉`, layer `l` in column `l mod columns` and row
//! `⌊l / columns⌋`, counted from the top-left corner (image rows run top to bottom, as in every
//! writer of this module). Cells past the last layer stay transparent zero. The layout is
//! serializable so a manifest can tell a shader where each layer lies.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::image::{Image, MAX_DIMENSION};
use crate::error::{PeltError, Result};
use crate::threads::pool;

/// Where each layer of a stack of `layers` square tiles of `tile × tile` texels lies in the atlas.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct AtlasLayout {
    /// Number of layers, at least 1.
    pub layers: usize,
    /// Side of one layer's tile in texels, at least 1.
    pub tile: usize,
    /// Tiles per atlas row: `⌈√layers⌉`.
    pub columns: usize,
    /// Tile rows: `⌈layers / columns⌉`.
    pub rows: usize,
    /// Atlas width in texels: `columns · tile`.
    pub width: usize,
    /// Atlas height in texels: `rows · tile`.
    pub height: usize,
}

impl AtlasLayout {
    /// The layout of `layers` tiles of `tile × tile` texels.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `layers` or `tile` when it is 0, or `tile` when the
    /// atlas would be wider or taller than [`MAX_DIMENSION`].
    pub fn new(layers: usize, tile: usize) -> Result<Self> {
        if layers == 0 {
            return Err(PeltError::parameter("layers", "must be at least 1"));
        }
        if tile == 0 {
            return Err(PeltError::parameter("tile", "must be at least 1"));
        }
        let columns = ceil_sqrt(layers);
        let rows = layers.div_ceil(columns);
        let side = |cells: usize| cells.checked_mul(tile).filter(|&s| s <= MAX_DIMENSION);
        let (Some(width), Some(height)) = (side(columns), side(rows)) else {
            return Err(PeltError::parameter(
                "tile",
                format!(
                    "{columns} × {rows} tiles of {tile} texels exceed the largest image side \
                     {MAX_DIMENSION}"
                ),
            ));
        };
        Ok(AtlasLayout {
            layers,
            tile,
            columns,
            rows,
            width,
            height,
        })
    }

    /// Top-left texel `(x, y)` of `layer`'s tile, `y` counted down from the top row.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `layer` when it is not below `layers`.
    pub fn tile_origin(&self, layer: usize) -> Result<(usize, usize)> {
        if layer >= self.layers {
            return Err(PeltError::parameter(
                "layer",
                format!("is {layer}, must be below {}", self.layers),
            ));
        }
        Ok((
            (layer % self.columns) * self.tile,
            (layer / self.columns) * self.tile,
        ))
    }
}

/// Packs layer-major data `[layers][tile][tile][channels]` into the atlas image of `layout`
/// (`height × width × channels`, rows top to bottom); unused cells are `T::default()` (zero,
/// transparent).
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `layout` when it is not what [`AtlasLayout::new`] gives
/// for its `layers` and `tile` (e.g. edited after deserializing), `channels` outside `1..=4`, or
/// `data` when its length is not `layers · tile² · channels`.
pub fn pack_atlas<T: Copy + Default + Send + Sync>(
    layout: &AtlasLayout,
    channels: usize,
    data: &[T],
) -> Result<Image<T>> {
    if AtlasLayout::new(layout.layers, layout.tile)? != *layout {
        return Err(PeltError::parameter(
            "layout",
            format!(
                "is inconsistent; {} layers of {} texels give {:?}",
                layout.layers,
                layout.tile,
                AtlasLayout::new(layout.layers, layout.tile)?
            ),
        ));
    }
    if !(1..=4).contains(&channels) {
        return Err(PeltError::parameter(
            "channels",
            format!("is {channels}, must be in 1..=4"),
        ));
    }
    let expected = layout
        .tile
        .checked_mul(layout.tile)
        .and_then(|n| n.checked_mul(channels))
        .and_then(|n| n.checked_mul(layout.layers));
    if expected != Some(data.len()) {
        return Err(PeltError::parameter(
            "data",
            format!(
                "must hold layers · tile · tile · channels = {} · {} · {} · {channels} samples, got {}",
                layout.layers,
                layout.tile,
                layout.tile,
                data.len()
            ),
        ));
    }
    let pixels = pool().install(|| pack_validated(layout, channels, data));
    Image::new(layout.width, layout.height, channels, pixels)
}

/// Copies every atlas row from the tile rows it crosses; each output row is independent, so
/// rows are filled in parallel.
pub(crate) fn pack_validated<T: Copy + Default + Send + Sync>(
    layout: &AtlasLayout,
    channels: usize,
    data: &[T],
) -> Vec<T> {
    let tile_row = layout.tile * channels;
    let tile_len = tile_row * layout.tile;
    let mut out = vec![T::default(); layout.width * layout.height * channels];
    out.par_chunks_mut(layout.width * channels)
        .enumerate()
        .for_each(|(y, row)| {
            let (cell_row, ty) = (y / layout.tile, y % layout.tile);
            for (column, dst) in row.chunks_exact_mut(tile_row).enumerate() {
                let layer = cell_row * layout.columns + column;
                if layer < layout.layers {
                    let start = layer * tile_len + ty * tile_row;
                    dst.copy_from_slice(&data[start..start + tile_row]);
                }
            }
        });
    out
}

/// `⌈√n⌉` in integers (no floating-point rounding at perfect squares).
fn ceil_sqrt(n: usize) -> usize {
    let mut r = n.isqrt();
    if r * r < n {
        r += 1;
    }
    r
}
