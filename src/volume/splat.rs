//! Adding hairs' covered shares into the per-texel sums of one shell layer.
//!
//! Lengyel et al. 2001, §2.2 sample each shell layer from the hair geometry; per texel the bake
//! sums every crossing hair's coverage (`prt-shell-fur` §2.1) with its color and direction (see
//! [`super::shells`]). The sums of a big layer (32 bytes per texel, 32 MiB at 1024²) do not fit
//! in a core's cache, and consecutive hairs (in the order of their roots) land rows apart once
//! curl has moved them, so adding each share where it falls waits on memory for most of them.
//! [`Banded`] instead queues the shares per band of rows, each band's sums the size of a cache,
//! and adds them band after band. Every texel lies in one band and each band keeps its queue in
//! order, so every texel receives its shares in the same order as when they are added at once
//! ([`Direct`]), and the f32 sums come out bit for bit the same.

use std::ops::Range;

/// Per-texel sums of one layer, one 32-byte record per texel so a hair's visit touches one cache
/// line: `[Σ w, Π (1 − w), Σ w·color (3), Σ w·direction (3)]` with `w = share · weight`.
pub(super) type Sums = [f32; 8];

/// The sums of a texel no hair touched.
pub(super) const EMPTY: Sums = [0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];

/// Texels per band: 512 KiB of sums, a quarter of a typical L2 cache.
const BAND_TEXELS: usize = 1 << 14;
/// Shares queued before they are added (12 MiB of queue).
const QUEUE_LIMIT: usize = 1 << 20;
/// Hairs queued before their shares are added (6 MiB of colors and directions).
const HAIR_LIMIT: usize = 1 << 18;

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
}

/// Queues the shares per band of rows and adds them band by band.
pub(super) struct Banded<'a> {
    sums: &'a mut [Sums],
    queues: &'a mut BandQueues,
    /// Rows per band, as a power of two.
    shift: u32,
    resolution: usize,
}

impl<'a> Banded<'a> {
    /// Whether a `resolution`² layer is worth banding: not when its sums fit in cache anyway.
    pub fn wanted(resolution: usize) -> bool {
        resolution * resolution > 4 * BAND_TEXELS
    }

    /// A banded sink for a `resolution`² layer, or `None` when it is not [`Banded::wanted`].
    pub fn new(sums: &'a mut [Sums], queues: &'a mut BandQueues, resolution: usize) -> Option<Self> {
        Self::wanted(resolution).then(|| Self::build(sums, queues, resolution))
    }

    /// A banded sink for a `resolution`² layer, wanted or not.
    pub fn build(sums: &'a mut [Sums], queues: &'a mut BandQueues, resolution: usize) -> Self {
        let rows = (BAND_TEXELS / resolution).max(1);
        // The largest power of two not above `rows`.
        let shift = usize::BITS - 1 - rows.leading_zeros();
        let bands = resolution.div_ceil(1 << shift);
        queues.bands.resize_with(bands, Vec::new);
        queues.bands.truncate(bands);
        Banded {
            sums,
            queues,
            shift,
            resolution,
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
        if self.queues.queued >= QUEUE_LIMIT || self.queues.hairs.len() >= HAIR_LIMIT {
            self.add_queued(&mut |_, _| {});
        }
    }

    fn drain(&mut self, rows: &mut dyn FnMut(&mut [Sums], Range<usize>)) {
        self.add_queued(rows);
    }
}

impl Banded<'_> {
    /// Adds the queued shares band by band, handing each band's rows to `rows` once added.
    fn add_queued(&mut self, rows: &mut dyn FnMut(&mut [Sums], Range<usize>)) {
        let BandQueues { bands, hairs, queued } = &mut *self.queues;
        for (b, band) in bands.iter_mut().enumerate() {
            for share in band.iter() {
                add(
                    &mut self.sums[share.texel as usize],
                    share.w,
                    &hairs[share.hair as usize],
                );
            }
            band.clear();
            let first = b << self.shift;
            rows(self.sums, first..(first + (1 << self.shift)).min(self.resolution));
        }
        hairs.clear();
        *queued = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// Many overlapping hairs, each a few shares in neighbouring rows, with the queue flushed
    /// part way (small limits are not needed: a second layer reuses the queues).
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
        let mut queues = BandQueues::default();
        for _layer in 0..2 {
            let mut banded_sums = vec![EMPTY; texels];
            let Some(mut banded) = Banded::new(&mut banded_sums, &mut queues, resolution) else {
                panic!("a 512² layer is banded");
            };
            run(&mut |hair, shares| {
                banded.start(*hair);
                for &(texel, row, w) in shares {
                    banded.add(texel, row, w);
                }
                banded.finish();
            });
            // The bands come complete and in order.
            let mut next = 0;
            banded.drain(&mut |_, rows| {
                assert_eq!(rows.start, next);
                next = rows.end;
            });
            assert_eq!(next, resolution);
            let bits = |sums: &[Sums]| -> Vec<u32> { sums.iter().flatten().map(|v| v.to_bits()).collect() };
            assert!(bits(&banded_sums) == bits(&direct_sums));
        }
    }
}
