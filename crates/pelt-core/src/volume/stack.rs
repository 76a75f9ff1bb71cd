//! The full-detail shell stack, sampled two layers at a time, with the first LOD level and the
//! mipmaps of each pair made while its layers are still in cache.
//!
//! Lengyel et al. 2001, §2.2 sample one RGBA image per shell layer; §2.4 composites successive
//! pairs of shells for level of detail and relies on mipmaps of every layer. Both read the layers
//! just sampled, so after a task for the skin alone each parallel task samples a pair of layers
//! (`2j − 1`, `2j`), composites the pair into layer `j` of LOD level 1 (whose layer 0 is the
//! skin, [`super::lod`]) and builds the pair's mip chain, instead of reading the whole stack back
//! from memory in separate passes. Every output is computed from the same inputs by the same
//! functions as in separate passes, so the bytes do not change.

use rayon::prelude::*;

use super::coverage::CoverageMode;
use super::lod::composite_pair;
use super::shells::{LayerOut, ScratchPool, sample_layer, sample_layer_pair};
use super::strand_table::StrandTable;
use crate::error::{PeltError, Result};
use crate::progress::Progress;
use crate::texture::MipAlpha;
use crate::texture::full_mip_count;
use crate::texture::mip::{chain_rgba8, level_side};

/// What the stack is made of and what comes with it.
pub(super) struct StackParams<'a> {
    pub strands: &'a StrandTable,
    pub resolution: usize,
    /// Layers to sample (after the trim).
    pub layers: usize,
    pub coverage: CoverageMode,
    /// The `(z, weight)` samples of layer `i`.
    pub heights: &'a (dyn Fn(usize) -> Vec<(f64, f64)> + Sync),
    pub lod: bool,
    pub mipmaps: bool,
}

/// The sampled stack: see [`super::HairVolume`] for the layouts.
pub(super) struct Stack {
    pub shells: Vec<u8>,
    pub coverage: Vec<f32>,
    pub tangents: Vec<u8>,
    pub mean_coverage: Vec<f64>,
    /// LOD level 1 (the skin and `ceil((layers − 1) / 2)` pairs), empty without LOD or with
    /// fewer than three layers.
    pub lod_first: Vec<u8>,
    /// Mip levels 1.. of every layer, empty without mipmaps.
    pub mips: Vec<Vec<u8>>,
}

/// One task: the skin, a pair of layers or the last, single one, and where its results go.
struct Pair<'a> {
    first: usize,
    rgba: &'a mut [u8],
    coverage: &'a mut [f32],
    tangent: &'a mut [u8],
    mean: &'a mut [f64],
    lod: Option<&'a mut [u8]>,
    /// The pair's part of each mip level.
    mips: Vec<&'a mut [u8]>,
}

/// `buffer` (`per_layer` items a layer) cut as the tasks take it: the skin alone, then pairs.
fn task_parts<T>(buffer: &mut [T], per_layer: usize) -> impl Iterator<Item = &mut [T]> {
    let (skin, rest) = buffer.split_at_mut(per_layer.min(buffer.len()));
    std::iter::once(skin).chain(rest.chunks_mut(2 * per_layer))
}

/// Samples every layer (in Pelt's pool), advancing `progress` by one per layer.
///
/// # Errors
/// [`crate::error::PeltError::Cancelled`] when `progress` asks to stop.
pub(super) fn sample_stack(params: &StackParams<'_>, progress: &Progress<'_>) -> Result<Stack> {
    let (res, layers) = (params.resolution, params.layers);
    let texels = res * res;
    let tasks = 1 + layers.saturating_sub(1).div_ceil(2);
    let mut shells = vec![0u8; layers * texels * 4];
    let mut coverage = vec![0.0f32; layers * texels];
    let mut tangents = vec![0u8; layers * texels * 4];
    let mut mean_coverage = vec![0.0f64; layers];
    let mut lod_first = if params.lod && layers > 2 {
        vec![0u8; tasks * texels * 4]
    } else {
        Vec::new()
    };
    let mip_count = if params.mipmaps {
        full_mip_count(res, res)
    } else {
        0
    };
    let mut mips: Vec<Vec<u8>> = (1..mip_count)
        .map(|k| vec![0u8; layers * level_side(res, k).pow(2) * 4])
        .collect();

    let mut pair_mips: Vec<Vec<&mut [u8]>> = (0..tasks).map(|_| Vec::new()).collect();
    for (k, level) in (1..).zip(mips.iter_mut()) {
        let size = level_side(res, k).pow(2) * 4;
        for (slot, part) in pair_mips.iter_mut().zip(task_parts(level, size)) {
            slot.push(part);
        }
    }
    let mut lod_parts = lod_first.chunks_mut(texels * 4);
    let tasks: Vec<Pair<'_>> = task_parts(&mut shells, texels * 4)
        .zip(task_parts(&mut coverage, texels))
        .zip(task_parts(&mut tangents, texels * 4))
        .zip(task_parts(&mut mean_coverage, 1))
        .zip(pair_mips)
        .enumerate()
        .map(|(j, ((((rgba, coverage), tangent), mean), mips))| Pair {
            first: (2 * j).saturating_sub(1),
            rgba,
            coverage,
            tangent,
            mean,
            lod: lod_parts.next(),
            mips,
        })
        .collect();

    // Rayon starts a fresh scratch for every piece of the task list it hands out; sharing them
    // keeps the large per-texel sums to about one per thread.
    let scratches = ScratchPool::default();
    tasks.into_par_iter().try_for_each_init(
        || [scratches.take(), scratches.take()],
        |[scratch, other], pair| {
            let count = pair.mean.len();
            let heights = [pair.first, pair.first + 1].map(params.heights);
            if let ([a], [b]) = (&heights[0][..], &heights[1][..])
                && count == 2
            {
                // One height each (no vertical filter): both layers in one walk over the strands.
                progress.check()?;
                let (rgba_a, rgba_b) = pair.rgba.split_at_mut(texels * 4);
                let (cov_a, cov_b) = pair.coverage.split_at_mut(texels);
                let (tan_a, tan_b) = pair.tangent.split_at_mut(texels * 4);
                let outs = [
                    LayerOut {
                        coverage: cov_a,
                        rgba: rgba_a,
                        tangent: tan_a,
                    },
                    LayerOut {
                        coverage: cov_b,
                        rgba: rgba_b,
                        tangent: tan_b,
                    },
                ];
                let skin = [pair.first == 0, false];
                let means = sample_layer_pair(
                    params.strands,
                    [*a, *b],
                    res,
                    params.coverage,
                    skin,
                    [scratch, other],
                    outs,
                );
                pair.mean.copy_from_slice(&means);
                progress.advance(2)?;
            } else {
                let layer_parts = pair
                    .rgba
                    .chunks_mut(texels * 4)
                    .zip(pair.coverage.chunks_mut(texels))
                    .zip(pair.tangent.chunks_mut(texels * 4))
                    .zip(pair.mean.iter_mut())
                    .zip(&heights);
                for (layer, ((((rgba, cov), tan), mean), heights)) in (pair.first..).zip(layer_parts) {
                    progress.check()?;
                    let out = LayerOut {
                        coverage: cov,
                        rgba,
                        tangent: tan,
                    };
                    *mean = sample_layer(
                        params.strands,
                        heights,
                        res,
                        params.coverage,
                        layer == 0,
                        scratch,
                        out,
                    );
                    progress.advance(1)?;
                }
            }
            if let Some(dst) = pair.lod {
                let (inner, outer) = pair.rgba.split_at(texels * 4);
                if count == 2 {
                    composite_pair(inner, outer, dst);
                } else {
                    dst.copy_from_slice(inner);
                }
            }
            if !pair.mips.is_empty() {
                // Alpha-weighted box filter in linear light, as the exported KTX2 chains.
                let chain = chain_rgba8(res, res, count, pair.rgba, true, MipAlpha::Straight, mip_count);
                for (dst, level) in pair.mips.into_iter().zip(&chain) {
                    dst.copy_from_slice(level);
                }
            }
            Ok::<(), PeltError>(())
        },
    )?;
    Ok(Stack {
        shells,
        coverage,
        tangents,
        mean_coverage,
        lod_first,
        mips,
    })
}
