//! The hair-volume bake: strands to shell stack, fin texture, LOD chain, tangents and density.
//!
//! Follows Lengyel et al. 2001, §2.2 (shell and fin textures from one tile of geometric hair) and
//! §2.4 (level of detail), with the coverage of the PRT shell-fur paper, §2.1. The tile is the unit
//! cube: unit square laterally (toroidal), height 1 = the fur depth; layer `i` of `L` samples the
//! height `i / L`, so a renderer places it at `i / L` of the hair length (the shell offset of §2.3).
//! Layer 0 is the opaque skin. Layers above the tallest strand hold no hair and are trimmed.

use rayon::prelude::*;
use serde::Serialize;

use crate::error::{Num, PeltError, Result};
use crate::guard::drawn_as_strands;
use crate::hair::{HairParams, Strand, grow_strands};
use crate::progress::{Progress, ProgressCallback};
use crate::threads::pool;

use super::fin::{fin_row, slab_candidates};
use super::lod::{lod_chain, lod_chain_from, next_count};
pub use super::params::{MAX_FIN_SIZE, MAX_LAYERS, MAX_RESOLUTION, MAX_VERTICAL_FILTER, VolumeParams};
use super::stack::{StackParams, sample_stack};
use super::strand_table::StrandTable;

/// Height samples per layer spacing taken by the tall Gaussian filter.
const FILTER_SAMPLES_PER_LAYER: f64 = 4.0;

/// What the trim and the sampling found, for the bake report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VolumeStats {
    /// Strands sampled.
    pub strands: usize,
    /// Height of the tallest tip, fur depths.
    pub tallest: f64,
    /// Layers asked for.
    pub layers_requested: usize,
    /// Layers kept after the trim.
    pub layers: usize,
    /// Layers dropped because no hair reaches them.
    pub trimmed: usize,
    /// Mean coverage of each kept layer (the share of the tile covered by hair cross-sections).
    pub mean_coverage: Vec<f64>,
}

/// The baked hair volume. Arrays are layer-major, rows top to bottom of the tile's `y`, straight
/// (not premultiplied) RGBA8 with sRGB-encoded color.
#[derive(Debug, Clone)]
pub struct HairVolume {
    /// Texture side `R`.
    pub resolution: usize,
    /// Kept layers `L'` (after the trim).
    pub layers: usize,
    /// Height between layers, fur depths (`1 / layers_requested`).
    pub layer_spacing: f64,
    /// `[L'][R][R][4]` shell colors and alpha; layer 0 opaque.
    pub shells: Vec<u8>,
    /// `[L'][R][R]` covered share per texel (summed over hairs, can exceed 1): the density volume.
    pub coverage: Vec<f32>,
    /// `[L'][R][R][4]` hair tangent packed `0.5·d + 0.5` in RGB (x, y in the tile, z up), alpha
    /// as the shells'.
    pub tangents: Vec<u8>,
    /// Fin texture `[width, height]`.
    pub fin_size: [usize; 2],
    /// `[height][width][4]` fin colors and alpha; row 0 is the top of the fur.
    pub fin: Vec<u8>,
    /// LOD levels 1.. of the shells ([`super::lod::level_counts`]): level `k` has the skin and
    /// `ceil((L' − 1) / 2^k)` composited groups of `[R][R][4]`, the last level one layer.
    pub lod: Vec<Vec<u8>>,
    /// Mip levels 1.. of every layer: level `k` is `[L'][max(1, R >> k)]²[4]`.
    pub mips: Vec<Vec<u8>>,
    /// Trim and coverage figures.
    pub stats: VolumeStats,
}

/// Grows the strands of `hair` and bakes them (see [`bake_strands`]).
///
/// # Errors
/// [`PeltError::InvalidParameter`] for a bad `hair` or `volume` field, [`PeltError::Cancelled`]
/// when `progress` asks to stop.
pub fn bake_volume(
    hair: &HairParams,
    volume: &VolumeParams,
    progress: Option<ProgressCallback<'_>>,
) -> Result<HairVolume> {
    volume.validate()?;
    hair.validate()?;
    let bytes = super::peak::grown_volume_peak_bytes(volume, hair);
    super::peak::check_volume_memory(volume, bytes, Some(hair.density))?;
    let strands = grow_strands(hair)?;
    bake_strands(&strands, volume, progress)
}

/// Bakes given strands (radii below half a tile) into a hair volume, in Pelt's thread pool.
/// The output is bit-identical for any thread count.
///
/// # Errors
/// [`PeltError::InvalidParameter`] for a bad `volume` field or a strand radius of half a tile or
/// more, [`PeltError::Cancelled`] when `progress` asks to stop.
pub fn bake_strands(
    strands: &[Strand],
    volume: &VolumeParams,
    progress: Option<ProgressCallback<'_>>,
) -> Result<HairVolume> {
    volume.validate()?;
    validate_strands(strands)?;
    let sizes = super::peak::StrandSizes {
        count: strands.len() as f64,
        max_width: strands
            .iter()
            .flat_map(|s| &s.radii)
            .fold(0.0, |w, r| w.max(2.0 * r)),
    };
    super::peak::check_volume_memory(volume, super::peak::volume_peak_bytes(volume, sizes), None)?;
    pool().install(|| bake_validated(strands, volume, progress))
}

/// Checks what the sampling relies on: one point count for all strands (at least 2), a radius per
/// point in `[0, 0.5)`, finite coordinates.
fn validate_strands(strands: &[Strand]) -> Result<()> {
    let points = strands.first().map_or(2, |s| s.points.len());
    for (i, s) in strands.iter().enumerate() {
        let bad = |reason: String| Err(PeltError::parameter(format!("strands[{i}]"), reason));
        if s.points.len() != points || points < 2 || s.radii.len() != points {
            return bad(format!(
                "must have {points} points and radii like strands[0] (at least 2), got {} and {}",
                s.points.len(),
                s.radii.len()
            ));
        }
        if !s.points.iter().flatten().all(|c| c.is_finite()) {
            return bad("has a coordinate that is not finite".into());
        }
        if let Some(r) = s.radii.iter().find(|r| !(0.0..0.5).contains(*r)) {
            return bad(format!("radius must be in [0, 0.5) tile units, got {}", Num(*r)));
        }
    }
    Ok(())
}

/// `(z, weight)` samples of layer `layer` of `layers`: its own height, or the tall Gaussian.
fn layer_heights(layer: usize, layers: usize, filter: f64) -> Vec<(f64, f64)> {
    let spacing = 1.0 / layers as f64;
    let z = layer as f64 * spacing;
    if layer == 0 || filter == 0.0 {
        return vec![(z, 1.0)];
    }
    let n = (3.0 * filter * FILTER_SAMPLES_PER_LAYER).ceil() as i64;
    let step = 3.0 * filter / n as f64; // in layer spacings
    let samples: Vec<(f64, f64)> = (-n..=n)
        .map(|k| {
            let d = k as f64 * step;
            (z + d * spacing, (-0.5 * (d / filter).powi(2)).exp())
        })
        .filter(|&(h, _)| h >= 0.0)
        .collect();
    let total: f64 = samples.iter().map(|s| s.1).sum();
    samples.into_iter().map(|(h, w)| (h, w / total)).collect()
}

pub(crate) fn bake_validated(
    strands: &[Strand],
    volume: &VolumeParams,
    callback: Option<ProgressCallback<'_>>,
) -> Result<HairVolume> {
    let (res, requested) = (volume.resolution, volume.layers);
    // With guard hairs drawn as strands of their own, the shells hold the rest of the coat.
    let drawn = if volume.guard_hairs {
        drawn_as_strands(strands, volume.guard_share)
    } else {
        Vec::new()
    };
    let table = StrandTable::new(strands, |i, _| !drawn.get(i).copied().unwrap_or(false));
    let tallest = table.tallest();
    let layers = if volume.trim {
        // Highest layer any sample of the filter can still find hair at.
        let reach = 3.0 * volume.vertical_filter / requested as f64;
        // Two layers at least (the skin and one above it), which the transfer needs even when no
        // hair stands (zero density or length).
        (((tallest + reach) * requested as f64).floor() as usize + 1)
            .max(2)
            .min(requested)
    } else {
        requested
    };
    let texels = res * res;
    let [fin_w, fin_h] = volume.fin_size;
    let progress = Progress::new(layers + fin_h, callback);

    let heights = |layer: usize| layer_heights(layer, requested, volume.vertical_filter);
    let stack = sample_stack(
        &StackParams {
            strands: &table,
            resolution: res,
            layers,
            coverage: volume.coverage,
            heights: &heights,
            lod: volume.lod,
            mipmaps: volume.mipmaps,
        },
        &progress,
    )?;

    let mut fin = vec![0u8; fin_w * fin_h * 4];
    let candidates = slab_candidates(&table, volume.fin_slab);
    fin.par_chunks_mut(fin_w * 4)
        .enumerate()
        .try_for_each(|(row, rgba)| {
            progress.check()?;
            fin_row(&table, &candidates, volume.fin_slab, volume.fin_size, row, rgba);
            progress.advance(1)
        })?;

    // Levels 2.. from level 1, which the stack made pair by pair (of two layers, made here).
    let lod = if !stack.lod_first.is_empty() {
        lod_chain_from(stack.lod_first, next_count(layers), texels)
    } else if volume.lod {
        lod_chain(&stack.shells, layers, texels)
    } else {
        Vec::new()
    };
    Ok(HairVolume {
        resolution: res,
        layers,
        layer_spacing: 1.0 / requested as f64,
        shells: stack.shells,
        coverage: stack.coverage,
        tangents: stack.tangents,
        fin_size: volume.fin_size,
        fin,
        lod,
        mips: stack.mips,
        stats: VolumeStats {
            strands: table.len(),
            tallest,
            layers_requested: requested,
            layers,
            trimmed: requested - layers,
            mean_coverage: stack.mean_coverage,
        },
    })
}
