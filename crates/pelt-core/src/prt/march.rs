//! The brute-force transfer method: march from every voxel centre toward every light direction,
//! as §2.2 of the PRT shell-fur paper does ("marches a ray from the center of each voxel in the
//! direction of d until it leaves the volume"). It is the reference the sweep is checked against.
//!
//! The ray is cut at the layers it crosses; inside each layer gap the density is linear in height,
//! so the midpoint rule with steps of at most [`TransferParams::brute_step`] integrates it with
//! no sample straddling a layer. Gaps between two empty layers are skipped (their integral is
//! exactly zero), and the march stops once the optical depth passes [`TAU_CUT`].
//!
//! [`TransferParams::brute_step`]: super::transfer::TransferParams::brute_step

use rayon::prelude::*;

use super::accumulate::{PhaseField, Projector, RowAccumulator};
use super::field::bilinear;
use super::volume::{ExtraRows, RayGeometry, TAU_CUT, Volume};
use crate::error::Result;
use crate::progress::Progress;

/// Most midpoint samples per layer gap: bounds the work of near-horizontal rays, whose path
/// through one gap can be millions of texels long; beyond it the step grows past `brute_step`.
pub const MAX_SAMPLES_PER_GAP: usize = 1 << 16;

/// Transmittance from the centre of voxel `(layer, x, y)` toward the ray's direction.
pub(super) fn march(
    vol: &Volume<'_>,
    sigma: f64,
    step: f64,
    layer: usize,
    x: usize,
    y: usize,
    ray: &RayGeometry,
) -> f32 {
    let res = vol.resolution;
    let mut tau = 0.0;
    for j in layer..vol.layers - 1 {
        let (empty0, empty1) = (vol.empty[j], vol.empty[j + 1]);
        if empty0 && empty1 {
            continue;
        }
        let n = ((ray.length / step).ceil() as usize).clamp(1, MAX_SAMPLES_PER_GAP);
        let (lower, upper) = (vol.layer(j), vol.layer(j + 1));
        let mut sum = 0.0;
        for k in 0..n {
            let f = (k as f64 + 0.5) / n as f64;
            let s = (j - layer) as f64 + f;
            let gx = x as f64 + s * ray.shift[0];
            let gy = y as f64 + s * ray.shift[1];
            if !empty0 {
                sum += (1.0 - f) * bilinear(lower, res, gx, gy);
            }
            if !empty1 {
                sum += f * bilinear(upper, res, gx, gy);
            }
        }
        tau += sigma * ray.length * sum / n as f64;
        if tau > TAU_CUT {
            return 0.0;
        }
    }
    (-tau).exp() as f32
}

/// Transmittance of every voxel toward one direction (`[layer][y][x]`), marching each voxel.
pub(super) fn transmittance(vol: &Volume<'_>, sigma: f64, step: f64, ray: &RayGeometry) -> Vec<f32> {
    let res = vol.resolution;
    let mut out = vec![0.0; vol.voxel_count()];
    out.par_chunks_mut(res).enumerate().for_each(|(row, t)| {
        let (layer, y) = (row / res, row % res);
        for (x, t) in t.iter_mut().enumerate() {
            *t = march(vol, sigma, step, layer, x, y, ray);
        }
    });
    out
}

/// Accumulates the projection of every voxel's transmittance into `out` (`[voxel][sh channel]`)
/// and the extra channels of sampled rows, one row of voxels per task.
#[allow(clippy::too_many_arguments)]
pub(super) fn bake(
    vol: &Volume<'_>,
    sigma: f64,
    step: f64,
    projector: &Projector,
    phase: &PhaseField,
    progress: &Progress<'_>,
    out: &mut [f32],
    extra: &mut ExtraRows,
) -> Result<()> {
    let res = vol.resolution;
    let rays: Vec<RayGeometry> = projector
        .dirs
        .iter()
        .map(|&d| RayGeometry::new(d, vol.spacing))
        .collect();
    out.par_chunks_mut(res * projector.sh_channels)
        .zip(extra.rows.par_iter_mut())
        .enumerate()
        .try_for_each_init(
            || (RowAccumulator::new(projector, phase, res), vec![0.0f32; res]),
            |(acc, t), (row, (out_row, extra_row))| {
                progress.check()?;
                let (layer, y) = (row / res, row % res);
                acc.load(row * res, out_row, extra_row.as_deref());
                for (i, ray) in rays.iter().enumerate() {
                    for (x, t) in t.iter_mut().enumerate() {
                        *t = march(vol, sigma, step, layer, x, y, ray);
                    }
                    acc.add(i, t, extra_row.is_some());
                }
                acc.store(out_row, extra_row.as_deref_mut());
                progress.advance(1)
            },
        )
}
