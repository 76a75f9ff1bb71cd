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

use glam::{DVec3, Vec3};

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
    /// layer totals for the fill values.
    fn splat(&self, footprint: &mut FootprintScratch, dirty: &mut [bool], sink: &mut impl Sink) -> Totals {
        let mut totals = Totals::default();
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
        totals: &mut Totals,
    ) {
        let cut = self.strands.cut(k, z);
        let [root, tip] = self.strands.colors(k).map(Vec3::from);
        // Written out rather than `lerp` (`root·(1 − s) + tip·s`), which rounds differently.
        let color = root + (tip - root) * cut.along;
        let d = Vec3::from(cut.direction);
        let mut hair_total = 0.0f64;
        sink.start(Hair {
            color: color.to_array(),
            direction: cut.direction,
        });
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
        totals.weight += hair_total;
        totals.color += hair_total * color.as_dvec3();
        totals.direction += hair_total * d.as_dvec3();
    }
}

/// A layer's totals for its fill values, per hair in f64 and in strand order (thread-count
/// independent).
#[derive(Debug, Clone, Copy, Default)]
struct Totals {
    /// Σ w.
    weight: f64,
    /// Σ w·color.
    color: DVec3,
    /// Σ w·direction.
    direction: DVec3,
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
        let mut totals = [Totals::default(); 2];
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
    totals: &Totals,
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
    fill_tangent: Vec3,
    /// The bytes of a texel no hair reached.
    empty_px: [u8; 4],
    empty_tx: [u8; 4],
    srgb: &'static Srgb8Encoder,
}

/// A unit direction packed `0.5 · d + 0.5` in RGB, with `alpha`.
fn pack(dir: Vec3, alpha: u8) -> [u8; 4] {
    let [r, g, b] = (0.5 * dir + 0.5).to_array().map(unit_to_u8);
    [r, g, b, alpha]
}

impl Finisher {
    /// The fill values from the layer totals.
    fn new(totals: &Totals, skin: bool, resolution: usize) -> Self {
        let fill_color = if totals.weight > 0.0 {
            (totals.color / totals.weight).as_vec3()
        } else {
            Vec3::ZERO
        };
        let fill_tangent = unit_or(totals.direction.as_vec3(), Vec3::Z);
        let srgb = srgb8_encoder();
        let empty_alpha = if skin { 255 } else { 0 };
        let [r, g, b] = fill_color.to_array().map(|c| srgb.encode(c));
        let empty_px = [r, g, b, empty_alpha];
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
                let color = Vec3::new(t[2], t[3], t[4]) * (1.0 / t[0]);
                let dir = unit_or(Vec3::new(t[5], t[6], t[7]), self.fill_tangent);
                let alpha = if self.skin { 255 } else { unit_to_u8(1.0 - t[1]) };
                let [r, g, b] = color.to_array().map(|c| srgb.encode(c));
                px.copy_from_slice(&[r, g, b, alpha]);
                tx.copy_from_slice(&pack(dir, alpha));
            }
        }
    }
}

/// `v` normalized, or `fallback` when `v` is (nearly) zero, e.g. hairs crossing in opposite
/// directions inside one texel.
fn unit_or(v: Vec3, fallback: Vec3) -> Vec3 {
    let len = v.length();
    // A division by the length, not `normalize`'s product with its reciprocal: it rounds otherwise.
    if len > 1e-12 && len.is_finite() {
        v / len
    } else {
        fallback
    }
}
