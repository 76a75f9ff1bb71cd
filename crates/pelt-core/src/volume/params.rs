//! The hair volume's sampling parameters (Lengyel et al. 2001, §2.2): layers, resolution, the
//! coverage model, the fin texture, trimming, LOD and the guard hairs' share, with their ranges.
//! Its own file so that the bake (`bake.rs`) and its memory estimate (`peak.rs`) both read it and
//! not each other.

use serde::{Deserialize, Serialize};

use super::coverage::CoverageMode;
use crate::error::Result;
use crate::params::Range;

/// Most shell layers.
pub const MAX_LAYERS: usize = 256;
/// Largest shell texture side.
pub const MAX_RESOLUTION: usize = 4096;
/// Largest fin texture side.
pub const MAX_FIN_SIZE: usize = 4096;
/// Widest tall-Gaussian filter, standard deviation in layer spacings.
pub const MAX_VERTICAL_FILTER: f64 = 8.0;

/// How the hair volume is sampled.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct VolumeParams {
    /// Shell layers including the skin, `[1, MAX_LAYERS]`; default 16.
    pub layers: usize,
    /// Shell texture side in texels, `[1, MAX_RESOLUTION]`; default 128.
    pub resolution: usize,
    /// How a cross-section's share of a texel is computed; default exact.
    pub coverage: CoverageMode,
    /// Tall Gaussian filter along the height (Lengyel §2.2), standard deviation in layer spacings,
    /// `[0, MAX_VERTICAL_FILTER]`; 0 (default) samples each layer at its own height only.
    pub vertical_filter: f64,
    /// Fin texture `[width, height]`, each `[1, MAX_FIN_SIZE]`; default 512 × 128.
    pub fin_size: [usize; 2],
    /// Depth of the slab of hair seen in the fin texture, tile units, `(0, 1]`; default 0.1.
    pub fin_slab: f64,
    /// Drop layers above the tallest strand (and report it); default true.
    pub trim: bool,
    /// Build the LOD chain of composited shells; default true.
    pub lod: bool,
    /// Build the mipmaps of every layer; default true.
    pub mipmaps: bool,
    /// Guard hairs (a `guard_share` of the overcoat) are drawn as explicit strands
    /// ([`crate::guard`]): leave them out, so that no hair is drawn twice; default false.
    pub guard_hairs: bool,
    /// With `guard_hairs`, the share of the overcoat drawn as strands, `(0, 1]`; the rest stays
    /// in the shells ([`crate::guard::drawn_as_strands`] picks which); default 1.
    pub guard_share: f64,
}

impl Default for VolumeParams {
    fn default() -> Self {
        VolumeParams {
            layers: 16,
            resolution: 128,
            coverage: CoverageMode::Exact,
            vertical_filter: 0.0,
            fin_size: [512, 128],
            fin_slab: 0.1,
            trim: true,
            lod: true,
            mipmaps: true,
            guard_hairs: false,
            guard_share: 1.0,
        }
    }
}

impl VolumeParams {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming the first field out of range.
    pub fn validate(&self) -> Result<()> {
        use ranges::*;
        LAYERS.check(self.layers as f64)?;
        RESOLUTION.check(self.resolution as f64)?;
        VERTICAL_FILTER.check(self.vertical_filter)?;
        FIN_WIDTH.check(self.fin_size[0] as f64)?;
        FIN_HEIGHT.check(self.fin_size[1] as f64)?;
        GUARD_SHARE.check(self.guard_share)?;
        FIN_SLAB.check(self.fin_slab)
    }

    /// Every number's range, as [`VolumeParams::validate`] checks it.
    pub const RANGES: &'static [Range] = {
        use ranges::*;
        &[
            LAYERS,
            RESOLUTION,
            VERTICAL_FILTER,
            FIN_WIDTH,
            FIN_HEIGHT,
            GUARD_SHARE,
            FIN_SLAB,
        ]
    };
}

/// The ranges of [`VolumeParams`]' numbers (`crate::params`).
mod ranges {
    use super::*;

    pub const LAYERS: Range = Range::closed("layers", 1.0, MAX_LAYERS as f64, "layers, the skin included");
    pub const RESOLUTION: Range = Range::closed("resolution", 1.0, MAX_RESOLUTION as f64, "texels per side");
    pub const VERTICAL_FILTER: Range =
        Range::closed("vertical_filter", 0.0, MAX_VERTICAL_FILTER, "layer spacings");
    pub const FIN_WIDTH: Range = Range::closed("fin_size[0]", 1.0, MAX_FIN_SIZE as f64, "texels");
    pub const FIN_HEIGHT: Range = Range::closed("fin_size[1]", 1.0, MAX_FIN_SIZE as f64, "texels");
    pub const GUARD_SHARE: Range = crate::guard::SHARE;
    pub const FIN_SLAB: Range = Range::open_below("fin_slab", 0.0, 1.0, "tile widths");
}
