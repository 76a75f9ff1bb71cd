//! The peak memory of a volume bake from its parameters alone, checked against the budget
//! ([`crate::memory`]) before the strands are grown.
//!
//! With `L` layers (the trim can only lower it) of `R²` texels: shells, coverage and tangents
//! (`12LR²`), the LOD chain (`4R²` per layer of levels 1.., about `4LR²`), the mip levels (about
//! `4LR²/3`), the fin (`4·width·height`); while the stack is sampled, a scratch per busy worker
//! (`32R²` of sums, and band queues of 12 bytes per share of a hair in a texel, at most one per
//! texel of each hair's footprint, and 24 bytes per hair, both capped where the queue spills);
//! and the strands with their table (about `44(S + 1) + 200` bytes per strand of `S` segments).

use super::params::VolumeParams;
use crate::error::Result;
use crate::hair::HairParams;
use crate::memory;

/// What the sampling's band queues hold at most: shares (12 bytes, doubled while a vector grows)
/// and hairs (24 bytes) before a layer spills (`splat.rs`).
const QUEUE_CAP: f64 = 2.0 * 12.0 * super::splat::QUEUE_LIMIT as f64;
const HAIR_CAP: f64 = 24.0 * super::splat::HAIR_LIMIT as f64;

/// The strands a bake samples, as the memory estimate needs them.
#[derive(Debug, Clone, Copy)]
pub struct StrandSizes {
    /// Number of strands.
    pub count: f64,
    /// Widest strand (diameter), tile units.
    pub max_width: f64,
}

impl StrandSizes {
    /// The strands `hair` grows.
    pub fn of(hair: &HairParams) -> Self {
        StrandSizes {
            count: f64::from(hair.density),
            max_width: hair.undercoat.width[1].max(hair.overcoat.width[1]),
        }
    }
}

/// Estimated bytes of the strands of `hair` and their lookup table.
pub fn strand_bytes(hair: &HairParams) -> f64 {
    f64::from(hair.density) * (44.0 * f64::from(hair.segments + 1) + 200.0)
}

/// Estimated bytes of the baked volume that stays (shells, coverage, tangents, LOD, mips, fin).
pub fn volume_bytes(volume: &VolumeParams) -> f64 {
    let (l, r) = (volume.layers as f64, volume.resolution as f64);
    let layer = r * r;
    let lod = if volume.lod {
        // Level k holds the skin and ⌈(L − 1) / 2^k⌉ groups, and the last level one layer.
        4.0 * layer * (l + 2.0 * l.log2().ceil() + 2.0)
    } else {
        0.0
    };
    let mips = if volume.mipmaps {
        4.0 * l * (layer / 3.0 + r.log2().ceil() + 1.0)
    } else {
        0.0
    };
    let fin = 4.0 * (volume.fin_size[0] * volume.fin_size[1]) as f64;
    12.0 * l * layer + lod + mips + fin
}

/// Estimated peak bytes of a volume bake of `strands` without the strands themselves: the
/// volume, and the workers' scratch while the stack is sampled.
pub fn volume_peak_bytes(volume: &VolumeParams, strands: StrandSizes) -> f64 {
    let r = volume.resolution as f64;
    let workers = crate::threads::thread_count().min(volume.layers) as f64;
    let footprint = (strands.max_width * r + 2.0).powi(2).min(r * r);
    let queues =
        (12.0 * 2.0 * strands.count * footprint).min(QUEUE_CAP) + (24.0 * strands.count).min(HAIR_CAP);
    volume_bytes(volume) + workers * (32.0 * r * r + queues)
}

/// Estimated peak bytes of [`super::bake_volume`]: the strands `hair` grows, and the bake of them.
pub fn grown_volume_peak_bytes(volume: &VolumeParams, hair: &HairParams) -> f64 {
    strand_bytes(hair) + volume_peak_bytes(volume, StrandSizes::of(hair))
}

/// `Ok` when a volume bake's estimated peak `bytes` fits the memory limit; otherwise
/// [`crate::PeltError::MemoryLimit`] naming the sizes to lower (the hair `density` too when the
/// bake grows its strands).
pub fn check_volume_memory(volume: &VolumeParams, bytes: f64, density: Option<u32>) -> Result<()> {
    memory::check("bake_volume", bytes, || {
        let sizes = format!(
            "`resolution` ({}), `layers` ({})",
            volume.resolution, volume.layers
        );
        match density {
            Some(d) => format!("{sizes} or the hair `density` ({d})"),
            None => sizes,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_estimate_covers_what_a_bake_keeps_and_refuses_256_layers_of_4096() {
        // The default bake: the arrays it returns, counted here exactly, are within the estimate.
        let (hair, volume) = (HairParams::default(), VolumeParams::default());
        let baked = super::super::bake_volume(&hair, &volume, None).unwrap();
        let kept = baked.shells.len()
            + 4 * baked.coverage.len()
            + baked.tangents.len()
            + baked.fin.len()
            + baked.lod.iter().map(Vec::len).sum::<usize>()
            + baked.mips.iter().map(Vec::len).sum::<usize>();
        assert!(
            volume_bytes(&volume) >= kept as f64,
            "{} < {kept}",
            volume_bytes(&volume)
        );
        assert!(volume_bytes(&volume) < 1.2 * kept as f64 + 1e6);
        let big = VolumeParams {
            layers: 256,
            resolution: 4096,
            ..VolumeParams::default()
        };
        // 12 bytes per voxel alone is 48 GiB.
        assert!(grown_volume_peak_bytes(&big, &hair) > 70e9);
        if memory::limit() < 64 << 30 {
            let error = check_volume_memory(&big, grown_volume_peak_bytes(&big, &hair), Some(hair.density))
                .unwrap_err()
                .to_string();
            assert!(error.contains("`resolution` (4096), `layers` (256)"), "{error}");
        }
    }
}
