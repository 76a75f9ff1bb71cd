//! One shell layer sampled from the strands: coverage, color and hair tangent per texel.
//!
//! Lengyel et al. 2001, §2.2 sample the hair geometry into a stack of semi-transparent layers,
//! the innermost one opaque (the skin), optionally through a "tall Gaussian" filter along the
//! height; the PRT shell-fur paper (§2.1) gives each hair's contribution as the share of the texel
//! its disk-shaped cross-section covers at the layer's height. Here a layer takes one or more
//! weighted sample heights (one without the filter), finds where each strand crosses each height,
//! and splats the cross-section with the chosen coverage mode. Color and tangent are averages
//! weighted by coverage; the hair tangent is what per-pixel Kajiya–Kay lighting needs (Lengyel
//! lists it as future work in §2.4).

use std::ops::Range;
use std::sync::Mutex;

use crate::texture::color::{Srgb8Encoder, srgb8_encoder, unit_to_u8};

use super::coverage::{CoverageMode, visit_disk_texels};
use super::footprint::FootprintScratch;
use super::splat::{BandQueues, Banded, Direct, EMPTY, Hair, Sink, Sums};
use super::strand_table::StrandTable;

/// Buffers of one worker, reused across the layers it samples.
///
/// The upper layers of a pelt hold few hairs, so the sums are not cleared and read whole for
/// every layer: `dirty` marks the rows that hairs touched, only those are finished from the sums
/// and reset afterwards, and every other row is written as empty directly.
#[derive(Debug, Default)]
pub struct LayerScratch {
    /// The whole layer's sums: for layers small enough to add shares directly, or a banded
    /// layer whose queue overflowed (see [`Banded`]).
    sums: Vec<Sums>,
    dirty: Vec<bool>,
    footprint: FootprintScratch,
    queues: BandQueues,
}

impl LayerScratch {
    /// Sizes the buffers for a `resolution`² layer. The whole layer's sums are made here only
    /// for layers small enough to add their shares directly; a banded layer keeps one band's
    /// sums, and makes the whole layer's only if its queue overflows ([`Banded`]).
    fn prepare(&mut self, resolution: usize) {
        if self.dirty.len() != resolution {
            self.dirty = vec![false; resolution];
        }
        let texels = resolution * resolution;
        if !Banded::wanted(resolution) && self.sums.len() != texels {
            self.sums = vec![EMPTY; texels];
        }
    }
}

/// Scratch buffers handed to the workers of one bake and taken back when they finish a share of
/// the layers, so the next share reuses them instead of allocating and filling new sums.
#[derive(Debug, Default)]
pub struct ScratchPool {
    free: Mutex<Vec<LayerScratch>>,
}

impl ScratchPool {
    /// A scratch from the pool, or a new one; it returns to the pool when dropped.
    pub fn take(&self) -> PooledScratch<'_> {
        // A poisoned lock only means another worker panicked; its buffers are still sound (they
        // are reset before use), but starting afresh is as good.
        let scratch = self.free.lock().ok().and_then(|mut free| free.pop());
        PooledScratch {
            scratch: scratch.unwrap_or_default(),
            pool: self,
        }
    }
}

/// A [`LayerScratch`] borrowed from a [`ScratchPool`].
#[derive(Debug)]
pub struct PooledScratch<'a> {
    scratch: LayerScratch,
    pool: &'a ScratchPool,
}

impl std::ops::Deref for PooledScratch<'_> {
    type Target = LayerScratch;
    fn deref(&self) -> &LayerScratch {
        &self.scratch
    }
}

impl std::ops::DerefMut for PooledScratch<'_> {
    fn deref_mut(&mut self) -> &mut LayerScratch {
        &mut self.scratch
    }
}

impl Drop for PooledScratch<'_> {
    fn drop(&mut self) {
        if let Ok(mut free) = self.pool.free.lock() {
            free.push(std::mem::take(&mut self.scratch));
        }
    }
}

/// Where one layer's results go: slices of the volume's arrays for this layer.
pub struct LayerOut<'a> {
    /// Coverage per texel (summed shares, may exceed 1 where hairs overlap): the density.
    pub coverage: &'a mut [f32],
    /// Straight RGBA8, color sRGB-encoded; alpha is the hairs composited over each other,
    /// `1 − Π (1 − share)` (1 on the skin).
    pub rgba: &'a mut [u8],
    /// Hair tangent packed `0.5 · d + 0.5` in RGB, alpha as in `rgba`.
    pub tangent: &'a mut [u8],
}

/// Samples one layer.
///
/// `heights` are `(z, weight)` pairs (weights summing to 1); `skin` makes the layer opaque.
/// Texels no hair reaches keep alpha 0 but get the layer's mean color and tangent, so that
/// filtering (mipmaps, bilinear lookups at hair borders) does not pull in black. The strands
/// must have passed the bake's checks (finite, radius below half a tile). Returns the layer's
/// mean coverage (its coverage summed texel by texel in f64, over the texel count).
pub fn sample_layer(
    strands: &StrandTable,
    heights: &[(f64, f64)],
    resolution: usize,
    mode: CoverageMode,
    skin: bool,
    scratch: &mut LayerScratch,
    out: LayerOut<'_>,
) -> f64 {
    let texels = resolution * resolution;
    scratch.prepare(resolution);
    let LayerScratch {
        sums,
        dirty,
        footprint,
        queues,
    } = scratch;
    let hairs = Hairs {
        strands,
        heights,
        resolution,
        mode,
    };
    let mut out = out;
    let coverage = match Banded::new(sums, queues, resolution) {
        Some(mut banded) => hairs.sample(footprint, dirty, &mut banded, skin, &mut out),
        None => {
            let mut direct = Direct {
                sums,
                hair: Hair {
                    color: [0.0; 3],
                    direction: [0.0; 3],
                },
                resolution,
            };
            hairs.sample(footprint, dirty, &mut direct, skin, &mut out)
        }
    };
    coverage / texels as f64
}

/// The hairs crossing one layer's sample heights.
struct Hairs<'a> {
    strands: &'a StrandTable,
    heights: &'a [(f64, f64)],
    resolution: usize,
    mode: CoverageMode,
}

impl Hairs<'_> {
    /// Splats the hairs through `sink` and finishes the layer into `out`, band by band; returns
    /// the layer's summed coverage.
    fn sample(
        &self,
        footprint: &mut FootprintScratch,
        dirty: &mut [bool],
        sink: &mut impl Sink,
        skin: bool,
        out: &mut LayerOut<'_>,
    ) -> f64 {
        let totals = self.splat(footprint, dirty, sink);
        finish(&totals, skin, self.resolution, sink, dirty, out)
    }

    /// Adds every hair's shares to `sink`, marks the rows they touch in `dirty`, and returns the
    /// layer totals for the fill values: Σ w, Σ w·color, Σ w·direction, per hair in f64 and in
    /// strand order (thread-count independent).
    fn splat(&self, footprint: &mut FootprintScratch, dirty: &mut [bool], sink: &mut impl Sink) -> [f64; 7] {
        let mut totals = [0.0f64; 7];
        for &(z, weight) in self.heights {
            for k in (0..self.strands.len()).filter(|&k| self.strands.reaches(k, z)) {
                self.splat_hair(k, (z, weight), footprint, dirty, sink, &mut totals);
            }
        }
        totals
    }

    /// Adds the shares of table strand `k` at height `z` (which it reaches) with `weight`.
    #[inline(always)]
    fn splat_hair(
        &self,
        k: usize,
        (z, weight): (f64, f64),
        footprint: &mut FootprintScratch,
        dirty: &mut [bool],
        sink: &mut impl Sink,
        totals: &mut [f64; 7],
    ) {
        let cut = self.strands.cut(k, z);
        let [root, tip] = self.strands.colors(k);
        let color: [f32; 3] = std::array::from_fn(|c| root[c] + (tip[c] - root[c]) * cut.along);
        let d = cut.direction;
        let mut hair_total = 0.0f64;
        sink.start(Hair { color, direction: d });
        visit_disk_texels(
            self.resolution,
            cut.x,
            cut.y,
            cut.radius,
            self.mode,
            footprint,
            |texel, row, share| {
                let w = (share * weight) as f32;
                hair_total += f64::from(w);
                dirty[row] = true;
                sink.add(texel, row, w);
            },
        );
        sink.finish();
        totals[0] += hair_total;
        for c in 0..3 {
            totals[1 + c] += hair_total * f64::from(color[c]);
            totals[4 + c] += hair_total * f64::from(d[c]);
        }
    }
}

/// Samples two layers of one sample height each (`(z, weight)`) in a single walk over the
/// strands, so that each strand's data is read once for both; otherwise as two calls of
/// [`sample_layer`], with the same results. Returns both layers' mean coverage.
#[allow(clippy::too_many_arguments)]
pub(super) fn sample_layer_pair(
    strands: &StrandTable,
    heights: [(f64, f64); 2],
    resolution: usize,
    mode: CoverageMode,
    skin: [bool; 2],
    scratch: [&mut LayerScratch; 2],
    out: [LayerOut<'_>; 2],
) -> [f64; 2] {
    let texels = resolution * resolution;
    let [first, second] = scratch;
    first.prepare(resolution);
    second.prepare(resolution);
    let footprint = &mut first.footprint;
    let dirty = [&mut first.dirty[..], &mut second.dirty[..]];
    let mut outs = out;
    let pair = Pair {
        strands,
        heights,
        resolution,
        mode,
        skin,
    };
    let coverage = if Banded::wanted(resolution) {
        let mut a = Banded::build(&mut first.sums, &mut first.queues, resolution);
        let mut b = Banded::build(&mut second.sums, &mut second.queues, resolution);
        pair.sample(footprint, dirty, [&mut a, &mut b], &mut outs)
    } else {
        let hair = Hair {
            color: [0.0; 3],
            direction: [0.0; 3],
        };
        let mut a = Direct {
            sums: &mut first.sums,
            hair,
            resolution,
        };
        let mut b = Direct {
            sums: &mut second.sums,
            hair,
            resolution,
        };
        pair.sample(footprint, dirty, [&mut a, &mut b], &mut outs)
    };
    coverage.map(|c| c / texels as f64)
}

/// The two layers of [`sample_layer_pair`].
struct Pair<'a> {
    strands: &'a StrandTable,
    heights: [(f64, f64); 2],
    resolution: usize,
    mode: CoverageMode,
    skin: [bool; 2],
}

impl Pair<'_> {
    fn sample<S: Sink>(
        &self,
        footprint: &mut FootprintScratch,
        dirty: [&mut [bool]; 2],
        sinks: [&mut S; 2],
        outs: &mut [LayerOut<'_>; 2],
    ) -> [f64; 2] {
        let [dirty_a, dirty_b] = dirty;
        let [sink_a, sink_b] = sinks;
        let layer = |i: usize| Hairs {
            strands: self.strands,
            heights: &self.heights[i..i + 1],
            resolution: self.resolution,
            mode: self.mode,
        };
        let (a, b) = (layer(0), layer(1));
        let (za, zb) = (self.heights[0].0, self.heights[1].0);
        let mut totals = [[0.0f64; 7]; 2];
        for k in 0..self.strands.len() {
            self.strands.prefetch(k + PREFETCH_AHEAD, za);
            if self.strands.reaches(k, za) {
                a.splat_hair(k, self.heights[0], footprint, dirty_a, sink_a, &mut totals[0]);
            }
            if self.strands.reaches(k, zb) {
                b.splat_hair(k, self.heights[1], footprint, dirty_b, sink_b, &mut totals[1]);
            }
        }
        let [out_a, out_b] = outs;
        [
            finish(&totals[0], self.skin[0], self.resolution, sink_a, dirty_a, out_a),
            finish(&totals[1], self.skin[1], self.resolution, sink_b, dirty_b, out_b),
        ]
    }
}

/// How many strands ahead of the one being splatted the walk fetches the next cut's points: about
/// the number of hairs splatted in the time a read from memory takes.
const PREFETCH_AHEAD: usize = 8;

/// Finishes a layer whose hairs are all in `sink`; returns its summed coverage.
fn finish(
    totals: &[f64; 7],
    skin: bool,
    resolution: usize,
    sink: &mut impl Sink,
    dirty: &mut [bool],
    out: &mut LayerOut<'_>,
) -> f64 {
    let finisher = Finisher::new(totals, skin, resolution);
    let mut coverage = 0.0f64;
    sink.drain(&mut |sums, rows| finisher.rows(rows, sums, dirty, out, &mut coverage));
    coverage
}

/// Turns the sums into straight color and unit tangents; empty texels get the layer's mean color
/// and tangent.
struct Finisher {
    resolution: usize,
    skin: bool,
    fill_tangent: [f32; 3],
    /// The bytes of a texel no hair reached.
    empty_px: [u8; 4],
    empty_tx: [u8; 4],
    srgb: &'static Srgb8Encoder,
}

/// A unit direction packed `0.5 · d + 0.5` in RGB, with `alpha`.
fn pack(dir: [f32; 3], alpha: u8) -> [u8; 4] {
    [
        unit_to_u8(0.5 * dir[0] + 0.5),
        unit_to_u8(0.5 * dir[1] + 0.5),
        unit_to_u8(0.5 * dir[2] + 0.5),
        alpha,
    ]
}

impl Finisher {
    /// The fill values from the layer totals Σ w, Σ w·color, Σ w·direction.
    fn new(totals: &[f64; 7], skin: bool, resolution: usize) -> Self {
        let fill_color: [f32; 3] = if totals[0] > 0.0 {
            std::array::from_fn(|c| (totals[1 + c] / totals[0]) as f32)
        } else {
            [0.0; 3]
        };
        let fill_tangent = unit_or(
            [totals[4] as f32, totals[5] as f32, totals[6] as f32],
            [0.0, 0.0, 1.0],
        );
        let srgb = srgb8_encoder();
        let empty_alpha = if skin { 255 } else { 0 };
        let empty_px = [
            srgb.encode(fill_color[0]),
            srgb.encode(fill_color[1]),
            srgb.encode(fill_color[2]),
            empty_alpha,
        ];
        Finisher {
            resolution,
            skin,
            fill_tangent,
            empty_px,
            empty_tx: pack(fill_tangent, empty_alpha),
            srgb,
        }
    }

    /// Finishes the rows `rows` of the layer from its `sums` into `out`, and resets their sums
    /// and `dirty` flags for the next layer while they are in cache. Adds their coverage to
    /// `total` texel by texel (in f64, in order: the same sum for any banding).
    fn rows(
        &self,
        rows: Range<usize>,
        sums: &mut [Sums],
        dirty: &mut [bool],
        out: &mut LayerOut<'_>,
        total: &mut f64,
    ) {
        let (res, srgb) = (self.resolution, self.srgb);
        let (empty_px, empty_tx) = (self.empty_px, self.empty_tx);
        let first = rows.start;
        for row in rows {
            let coverage = &mut out.coverage[row * res..(row + 1) * res];
            let rgba = &mut out.rgba[4 * row * res..4 * (row + 1) * res];
            let tangent = &mut out.tangent[4 * row * res..4 * (row + 1) * res];
            if !std::mem::take(&mut dirty[row]) {
                coverage.fill(0.0);
                rgba.chunks_exact_mut(4)
                    .for_each(|px| px.copy_from_slice(&empty_px));
                tangent
                    .chunks_exact_mut(4)
                    .for_each(|tx| tx.copy_from_slice(&empty_tx));
                continue;
            }
            let row_sums = &mut sums[(row - first) * res..(row - first + 1) * res];
            let pixels = rgba.chunks_exact_mut(4).zip(tangent.chunks_exact_mut(4));
            for ((sum, cov), (px, tx)) in row_sums.iter_mut().zip(coverage.iter_mut()).zip(pixels) {
                let t = *sum;
                *cov = t[0];
                if t[0] <= 0.0 {
                    // Most texels of the upper layers: no hair, constant bytes. A texel whose
                    // Σ w is 0 got no share above 0, so its sums are still exactly EMPTY: not
                    // rewriting them keeps their cache line clean.
                    px.copy_from_slice(&empty_px);
                    tx.copy_from_slice(&empty_tx);
                    continue;
                }
                *sum = EMPTY;
                *total += f64::from(t[0]);
                let inv = 1.0 / t[0];
                let dir = unit_or([t[5], t[6], t[7]], self.fill_tangent);
                let alpha = if self.skin { 255 } else { unit_to_u8(1.0 - t[1]) };
                px.copy_from_slice(&[
                    srgb.encode(t[2] * inv),
                    srgb.encode(t[3] * inv),
                    srgb.encode(t[4] * inv),
                    alpha,
                ]);
                tx.copy_from_slice(&pack(dir, alpha));
            }
        }
    }
}

/// `v` normalized, or `fallback` when `v` is (nearly) zero, e.g. hairs crossing in opposite
/// directions inside one texel.
fn unit_or(v: [f32; 3], fallback: [f32; 3]) -> [f32; 3] {
    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if len > 1e-12 && len.is_finite() {
        v.map(|c| c / len)
    } else {
        fallback
    }
}
