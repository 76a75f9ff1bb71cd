//! The transfer bake's parameters (the PRT shell-fur paper, §2.2–§2.3): order, directions,
//! extinction, phase and method, with their defaults and ranges. Its own file so that the bake
//! (`transfer.rs`) and its memory estimate (`peak.rs`) both read it and not each other.

use serde::{Deserialize, Serialize};

use super::accumulate::Phase;
use super::sh::{self, PAPER_ORDER};
use super::sphere::DEFAULT_DIRECTIONS;
use crate::error::Result;
use crate::params::Range;

/// Default extinction σ: optical depth ½ per texel width of path through density 1.
///
/// A hair of radius `r` texels whose slice coverage is `c` blocks a path along `ω` with
/// extinction `2c |ω × t| / (π r |t_z|)` per texel (`reference::density`); the baked volume's
/// density already holds `c / |t_z|` (`volume_input`), and σ stands for the rest, averaged over
/// directions. A density counts every hair as fog, so it shadows the hair that an eye ray meets
/// first, which solid hairs lit from behind that eye do not: the value is chosen against the
/// reference's strands, not against their radius. Of the values tried (1, 0.76, 0.5 and 0.36 per
/// texel, with and without the `1 / |t_z|`), ½ with it brought the PRT preview's mean
/// luminance on both canonical spheres under a sun from the side and from above, and under the
/// sky, within [0.91, 1.06] of the reference's (σ = 1 without it: 0.72–0.99).
pub const DEFAULT_SIGMA: f32 = 0.5;

/// Default brute-force step along the path, texel widths.
pub const DEFAULT_BRUTE_STEP: f32 = 0.25;

/// Default lateral spacing of the sweep's samples on the finest prefiltered level, texel widths.
pub const DEFAULT_SWEEP_STEP: f32 = 1.0;

/// Default most samples per layer gap: with the default step, gaps whose path shifts at most 16
/// texels sideways are integrated exactly.
pub const DEFAULT_SWEEP_MAX_SAMPLES: u32 = 16;

/// Most bake directions.
pub const MAX_DIRECTIONS: usize = 1 << 16;

/// Largest extinction σ.
pub const MAX_SIGMA: f32 = 1.0e6;

/// How the transmittance is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// March from every voxel toward every direction (the paper's method; the reference).
    Brute,
    /// Carry the optical depth layer by layer, all voxels of a direction at once.
    #[default]
    Sweep,
}

/// Parameters of the transfer bake.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct TransferParams {
    /// SH order n (n bands, n² coefficients), `1..=8`; the paper uses 5.
    pub order: usize,
    /// Number of sample directions over the whole sphere, `16..=MAX_DIRECTIONS`, rounded up to a
    /// multiple of 4: spherical Fibonacci points made mirror-symmetric in x and y
    /// ([`mirrored_fibonacci_directions`]). Only the half above the horizon does any work.
    pub directions: usize,
    /// Extinction σ: optical depth per texel width of path through ρ = 1, `[0, MAX_SIGMA]`.
    pub sigma: f32,
    /// Phase term.
    pub phase: Phase,
    /// Transmittance method.
    pub method: Method,
    /// Brute force: longest step along the path, texel widths, `[0.001, 16]`.
    pub brute_step: f32,
    /// Sweep: gaps whose path shifts sideways by at most `sweep_step · sweep_max_samples` texels
    /// are integrated exactly; longer (near-horizontal) ones take at most `sweep_max_samples`
    /// samples spaced `sweep_step · 2^m` apart from a level prefiltered to that spacing. Texel
    /// widths, `[0.05, 16]`.
    pub sweep_step: f32,
    /// Sweep: see `sweep_step`; `1..=256`.
    pub sweep_max_samples: u32,
}

impl Default for TransferParams {
    fn default() -> Self {
        TransferParams {
            order: PAPER_ORDER,
            directions: DEFAULT_DIRECTIONS,
            sigma: DEFAULT_SIGMA,
            phase: Phase::Isotropic,
            method: Method::Sweep,
            brute_step: DEFAULT_BRUTE_STEP,
            sweep_step: DEFAULT_SWEEP_STEP,
            sweep_max_samples: DEFAULT_SWEEP_MAX_SAMPLES,
        }
    }
}

impl TransferParams {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming the first field out of range (NaN is out of every
    /// range).
    pub fn validate(&self) -> Result<()> {
        use ranges::*;
        // The order's own message counts bands; its range is ORDER's.
        sh::check_order(self.order)?;
        DIRECTIONS.check(self.directions as f64)?;
        SIGMA.check(f64::from(self.sigma))?;
        BRUTE_STEP.check(f64::from(self.brute_step))?;
        SWEEP_STEP.check(f64::from(self.sweep_step))?;
        SWEEP_MAX_SAMPLES.check(f64::from(self.sweep_max_samples))
    }

    /// Every number's range, as [`TransferParams::validate`] checks it.
    pub const RANGES: &'static [Range] = {
        use ranges::*;
        &[
            ORDER,
            DIRECTIONS,
            SIGMA,
            BRUTE_STEP,
            SWEEP_STEP,
            SWEEP_MAX_SAMPLES,
        ]
    };
}

/// The ranges of [`TransferParams`]' numbers (`crate::params`).
mod ranges {
    use super::*;

    pub const ORDER: Range = Range::closed("order", 1.0, sh::MAX_ORDER as f64, "bands");
    pub const DIRECTIONS: Range = Range::closed("directions", 16.0, MAX_DIRECTIONS as f64, "directions");
    pub const SIGMA: Range = Range::closed("sigma", 0.0, MAX_SIGMA as f64, "optical depth per texel");
    pub const BRUTE_STEP: Range = Range::closed("brute_step", 1e-3, 16.0, "texel widths");
    pub const SWEEP_STEP: Range = Range::closed("sweep_step", 0.05, 16.0, "texel widths");
    pub const SWEEP_MAX_SAMPLES: Range = Range::closed("sweep_max_samples", 1.0, 256.0, "samples");
}
