//! Adding hairs' covered shares into the per-texel sums of one shell layer.
//!
//! Lengyel et al. 2001, §2.2 sample each shell layer from the hair geometry; per texel the bake
//! sums every crossing hair's coverage (`prt-shell-fur` §2.1) with its color and direction (see
//! [`super::shells`]). The sums of a big layer (32 bytes per texel, 32 MiB at 1024²) do not fit
//! in a core's cache, and consecutive hairs (in the order of their roots) land rows apart once
//! curl has moved them, so adding each share where it falls waits on memory for most of them.
//! [`Banded`] instead queues the shares per band of rows, each band's sums the size of a cache,
//! and adds them band after band into one band-sized buffer that stays in cache, finishing each
//! band before the next: the whole layer's sums never exist, which spares the bake reading and
//! writing them back (64 bytes of memory traffic per texel and layer, most of a big bake's). Only
//! a layer whose queue outgrows its limit spills its shares into whole-layer sums. Every texel
//! lies in one band and each band keeps its queue in order, so every texel receives its shares
//! in the same order as when they are added at once ([`Direct`]), and the f32 sums come out bit
//! for bit the same.

use std::ops::Range;

/// Per-texel sums of one layer, one 32-byte record per texel so a hair's visit touches one cache
/// line: `[Σ w, Π (1 − w), Σ w·color (3), Σ w·direction (3)]` with `w = share · weight`.
pub(super) type Sums = [f32; 8];

/// The sums of a texel no hair touched.
pub(super) const EMPTY: Sums = [0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];

/// Texels per band: 512 KiB of sums, a quarter of a typical L2 cache.
const BAND_TEXELS: usize = 1 << 14;
/// Shares queued before a layer spills them into whole-layer sums (48 MiB of queue; a 1024²
/// layer of 200,000 hairs about a texel wide queues some 2 million).
pub(super) const QUEUE_LIMIT: usize = 1 << 22;
/// Hairs queued before the layer spills (24 MiB of colors and directions).
pub(super) const HAIR_LIMIT: usize = 1 << 20;

/// What a hair adds to each texel it covers, besides its share: color and unit direction.
#[derive(Debug, Clone, Copy)]
pub(super) struct Hair {
    pub color: [f32; 3],
    pub direction: [f32; 3],
}

/// Adds share `w` of `hair` to the sums of one texel.
#[inline(always)]
fn add(t: &mut Sums, w: f32, hair: &Hair) {
    t[0] += w;
    t[1] *= 1.0 - w;
    t[2] += w * hair.color[0];
    t[3] += w * hair.color[1];
    t[4] += w * hair.color[2];
    t[5] += w * hair.direction[0];
    t[6] += w * hair.direction[1];
    t[7] += w * hair.direction[2];
}

/// Where the shares of the hairs go, one hair after the other.
pub(super) trait Sink {
    /// The next hair's shares follow.
    fn start(&mut self, hair: Hair);
    /// Share `w` of the current hair in `texel`, which lies in row `row`.
    fn add(&mut self, texel: usize, row: usize, w: f32);
    /// The current hair is done.
    fn finish(&mut self);
    /// Adds every share still queued and hands the sums to `rows` in bands of whole rows, each
    /// band complete and still in cache, in order.
    /// `rows` gets the sums of those rows only: its first record is the first texel of the
    /// range's first row.
    fn drain(&mut self, rows: &mut dyn FnMut(&mut [Sums], Range<usize>));
}

/// Adds every share at once: for layers whose sums fit in cache.
pub(super) struct Direct<'a> {
    pub sums: &'a mut [Sums],
    pub hair: Hair,
    pub resolution: usize,
}

impl Sink for Direct<'_> {
    #[inline(always)]
    fn start(&mut self, hair: Hair) {
        self.hair = hair;
    }

    #[inline(always)]
    fn add(&mut self, texel: usize, _row: usize, w: f32) {
        add(&mut self.sums[texel], w, &self.hair);
    }

    fn finish(&mut self) {}

    fn drain(&mut self, rows: &mut dyn FnMut(&mut [Sums], Range<usize>)) {
        rows(self.sums, 0..self.resolution);
    }
}

/// One queued share.
#[derive(Debug, Clone, Copy)]
struct Share {
    texel: u32,
    w: f32,
    hair: u32,
}

/// Queues of [`Banded`], kept by a worker across layers.
#[derive(Debug, Default)]
pub(super) struct BandQueues {
    bands: Vec<Vec<Share>>,
    hairs: Vec<Hair>,
    queued: usize,
    /// One band's sums, all [`EMPTY`] between bands (the finisher resets every record it reads
    /// a share from, and a record no share reached is still `EMPTY`).
    band_sums: Vec<Sums>,
    /// Whether this layer's queue overflowed into the whole-layer sums.
    spilled: bool,
}

/// Queues the shares per band of rows and adds them band by band.
pub(super) struct Banded<'a> {
    /// The whole layer's sums, made on the first spill (and kept, all `EMPTY`, for later ones).
    sums: &'a mut Vec<Sums>,
    queues: &'a mut BandQueues,
    /// Rows per band, as a power of two.
    shift: u32,
    resolution: usize,
    /// Queued shares and hairs at which the layer spills ([`QUEUE_LIMIT`], [`HAIR_LIMIT`]).
    limits: (usize, usize),
}

impl<'a> Banded<'a> {
    /// Whether a `resolution`² layer is worth banding: not when its sums fit in cache anyway.
    pub fn wanted(resolution: usize) -> bool {
        resolution * resolution > 4 * BAND_TEXELS
    }

    /// A banded sink for a `resolution`² layer, or `None` when it is not [`Banded::wanted`].
    pub fn new(sums: &'a mut Vec<Sums>, queues: &'a mut BandQueues, resolution: usize) -> Option<Self> {
        Self::wanted(resolution).then(|| Self::build(sums, queues, resolution))
    }

    /// A banded sink for a `resolution`² layer, wanted or not.
    pub fn build(sums: &'a mut Vec<Sums>, queues: &'a mut BandQueues, resolution: usize) -> Self {
        let rows = (BAND_TEXELS / resolution).max(1);
        // The largest power of two not above `rows`.
        let shift = usize::BITS - 1 - rows.leading_zeros();
        let bands = resolution.div_ceil(1 << shift);
        queues.bands.resize_with(bands, Vec::new);
        queues.bands.truncate(bands);
        queues.band_sums.clear();
        queues.band_sums.resize((1 << shift) * resolution, EMPTY);
        queues.spilled = false;
        Banded {
            sums,
            queues,
            shift,
            resolution,
            limits: (QUEUE_LIMIT, HAIR_LIMIT),
        }
    }
}

impl Sink for Banded<'_> {
    #[inline(always)]
    fn start(&mut self, hair: Hair) {
        self.queues.hairs.push(hair);
    }

    #[inline(always)]
    fn add(&mut self, texel: usize, row: usize, w: f32) {
        // Texels below 2^32 (at most MAX_RESOLUTION², 2^24) and fewer than 2^32 queued hairs.
        let hair = (self.queues.hairs.len() - 1) as u32;
        self.queues.bands[row >> self.shift].push(Share {
            texel: texel as u32,
            w,
            hair,
        });
        self.queues.queued += 1;
    }

    fn finish(&mut self) {
        if self.queues.queued >= self.limits.0 || self.queues.hairs.len() >= self.limits.1 {
            self.spill();
        }
    }

    fn drain(&mut self, rows: &mut dyn FnMut(&mut [Sums], Range<usize>)) {
        self.add_queued(rows);
    }
}

impl Banded<'_> {
    /// Adds the queued shares band by band into the band buffer, handing each band's rows to
    /// `rows` as soon as they are complete; or, after a spill, into the whole layer's sums.
    fn add_queued(&mut self, rows: &mut dyn FnMut(&mut [Sums], Range<usize>)) {
        let res = self.resolution;
        if self.queues.spilled {
            self.spill();
            self.queues.spilled = false;
            for b in 0..self.queues.bands.len() {
                let band = band_rows(b, self.shift, res);
                rows(&mut self.sums[band.start * res..band.end * res], band);
            }
            return;
        }
        let BandQueues {
            bands,
            hairs,
            queued,
            band_sums,
            ..
        } = &mut *self.queues;
        for (b, queue) in bands.iter_mut().enumerate() {
            let band = band_rows(b, self.shift, res);
            add_shares(queue, hairs, band_sums, band.start * res);
            let texels = band.len() * res;
            rows(&mut band_sums[..texels], band);
        }
        hairs.clear();
        *queued = 0;
    }

    /// Adds the queued shares into the whole layer's sums (made on first need) and empties the
    /// queues: for a layer with more shares than a queue holds.
    fn spill(&mut self) {
        let texels = self.resolution * self.resolution;
        if self.sums.len() != texels {
            *self.sums = vec![EMPTY; texels];
        }
        let BandQueues {
            bands,
            hairs,
            queued,
            spilled,
            ..
        } = &mut *self.queues;
        for queue in bands.iter_mut() {
            add_shares(queue, hairs, self.sums, 0);
        }
        hairs.clear();
        *queued = 0;
        *spilled = true;
    }
}

/// Adds the shares of `queue` (of `hairs`) into `sums`, whose first record is texel `offset`,
/// and empties the queue.
fn add_shares(queue: &mut Vec<Share>, hairs: &[Hair], sums: &mut [Sums], offset: usize) {
    for share in queue.iter() {
        add(
            &mut sums[share.texel as usize - offset],
            share.w,
            &hairs[share.hair as usize],
        );
    }
    queue.clear();
}

/// The rows of band `b` of a `resolution`² layer with `1 << shift` rows per band.
fn band_rows(b: usize, shift: u32, resolution: usize) -> Range<usize> {
    let first = b << shift;
    first..(first + (1 << shift)).min(resolution)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// Many overlapping hairs, each a few shares in neighbouring rows, two layers in a row (the
    /// second reuses the queues and band sums), with the default limits (no spill) and with
    /// small ones that spill many times per layer.
    #[test]
    fn banded_sums_are_the_direct_sums_bit_for_bit() {
        // (texel, row, share)
        type Share = (usize, usize, f32);
        let resolution = 512;
        let texels = resolution * resolution;
        let mut rng = Rng::new(7);
        let hairs: Vec<(Hair, Vec<Share>)> = (0..20_000)
            .map(|_| {
                let mut unit = || rng.next_f64() as f32;
                let hair = Hair {
                    color: [unit(), unit(), unit()],
                    direction: [unit() - 0.5, unit() - 0.5, unit()],
                };
                // Hairs clustered on a few texels so that shares pile up, over band borders.
                let row = (rng.next_u64() % 40) as usize * 13 % resolution;
                let column = (rng.next_u64() % 64) as usize;
                let shares = (0..(1 + rng.next_u64() % 6) as usize)
                    .map(|i| {
                        let r = (row + i / 2) % resolution;
                        (r * resolution + column + i % 2, r, rng.next_f64() as f32)
                    })
                    .collect();
                (hair, shares)
            })
            .collect();
        let run = |sink: &mut dyn FnMut(&Hair, &[Share])| {
            for (hair, shares) in &hairs {
                sink(hair, shares);
            }
        };
        let mut direct_sums = vec![EMPTY; texels];
        let mut direct = Direct {
            sums: &mut direct_sums,
            hair: hairs[0].0,
            resolution,
        };
        run(&mut |hair, shares| {
            direct.start(*hair);
            for &(texel, row, w) in shares {
                direct.add(texel, row, w);
            }
            direct.finish();
        });
        direct.drain(&mut |_, _| {});
        let bits = |sums: &[Sums]| -> Vec<u32> { sums.iter().flatten().map(|v| v.to_bits()).collect() };
        // Limits that never spill here, and small ones that spill many times per layer.
        for limits in [(QUEUE_LIMIT, HAIR_LIMIT), (1000, 300)] {
            let mut queues = BandQueues::default();
            let mut whole = Vec::new();
            for _layer in 0..2 {
                let Some(mut banded) = Banded::new(&mut whole, &mut queues, resolution) else {
                    panic!("a 512² layer is banded");
                };
                banded.limits = limits;
                run(&mut |hair, shares| {
                    banded.start(*hair);
                    for &(texel, row, w) in shares {
                        banded.add(texel, row, w);
                    }
                    banded.finish();
                });
                // The bands come complete and in order; each is reset as the finisher does.
                let mut seen = vec![EMPTY; texels];
                let mut next = 0;
                banded.drain(&mut |sums, rows| {
                    assert_eq!(rows.start, next);
                    assert_eq!(sums.len(), rows.len() * resolution);
                    seen[rows.start * resolution..rows.end * resolution].copy_from_slice(sums);
                    sums.iter_mut().filter(|t| t[0] > 0.0).for_each(|t| *t = EMPTY);
                    next = rows.end;
                });
                assert_eq!(next, resolution);
                assert!(bits(&seen) == bits(&direct_sums), "limits {limits:?}");
                // What the next layer starts from is empty again.
                assert!(queues.band_sums.iter().all(|t| bits(&[*t]) == bits(&[EMPTY])));
                assert!(whole.iter().all(|t| bits(&[*t]) == bits(&[EMPTY])));
                assert_eq!(
                    whole.is_empty(),
                    limits.0 == QUEUE_LIMIT,
                    "only a spill makes whole sums"
                );
            }
        }
    }
}
