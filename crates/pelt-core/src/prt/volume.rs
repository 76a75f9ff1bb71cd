//! The density volume a transfer bake reads (the PRT shell-fur paper, §2.2): the caller's view
//! ([`TransferVolume`]) and its limits, the validated form both methods walk ([`Volume`]), and
//! where a ray toward a direction goes per layer gap ([`RayGeometry`]). Its own file so that
//! `transfer.rs` (the entry point) and the methods (`march.rs`, `sweep.rs`) both import it and
//! not each other.

use rayon::prelude::*;

use crate::error::{PeltError, Result, check_range};

/// Most layers of a volume.
pub const MAX_LAYERS: usize = 4096;

/// Largest layer resolution.
pub const MAX_RESOLUTION: usize = 1 << 14;

/// Most voxels of a volume (`L·R²`), so coefficient buffers stay addressable.
pub const MAX_VOXELS: usize = 1 << 30;

/// Largest layer spacing, texel widths.
pub const MAX_LAYER_SPACING: f32 = 1.0e6;

/// Optical depth above which a path counts as opaque (`e^{−24} ≈ 3.8·10⁻¹¹`).
pub const TAU_CUT: f64 = 24.0;

/// Smallest `ω_z` used for path lengths: rays closer to the horizon are treated as this grazing,
/// which keeps the length per layer gap finite (`s·10⁹` texels) and changes no result above f32
/// precision.
const MIN_COS: f64 = 1.0e-9;

/// The density volume to bake, borrowed from the caller.
#[derive(Debug, Clone, Copy)]
pub struct TransferVolume<'a> {
    /// Number of layers L, `2..=MAX_LAYERS`; layer 0 is the skin.
    pub layers: usize,
    /// Texels per side R of each layer, `1..=MAX_RESOLUTION`.
    pub resolution: usize,
    /// Vertical distance between layers in texel widths, `(0, MAX_LAYER_SPACING]`.
    pub layer_spacing: f32,
    /// Coverage ρ ≥ 0 per voxel, `L·R²` values at `(l·R + y)·R + x`.
    pub density: &'a [f32],
    /// Hair directions per voxel (x, y lateral, z up; any length, normalized here; all-zero where
    /// there is no hair), `L·R²` rows. Needed by `Phase::KajiyaKay`, ignored otherwise.
    pub tangents: Option<&'a [[f32; 3]]>,
}

/// A validated volume, as the methods read it.
pub(super) struct Volume<'a> {
    pub layers: usize,
    pub resolution: usize,
    pub spacing: f64,
    density: &'a [f32],
    /// Layers whose density is zero everywhere.
    pub empty: Vec<bool>,
}

impl<'a> Volume<'a> {
    pub(super) fn new(v: &TransferVolume<'a>) -> Result<Self> {
        check_range("layers", v.layers as f64, 2.0, MAX_LAYERS as f64)?;
        check_range("resolution", v.resolution as f64, 1.0, MAX_RESOLUTION as f64)?;
        if !(v.layer_spacing > 0.0 && v.layer_spacing <= MAX_LAYER_SPACING) {
            return Err(PeltError::parameter(
                "layer_spacing",
                format!(
                    "must be in (0, {MAX_LAYER_SPACING}] texel widths, got {}",
                    v.layer_spacing
                ),
            ));
        }
        let voxels = v.layers * v.resolution * v.resolution;
        if voxels > MAX_VOXELS {
            return Err(PeltError::parameter(
                "resolution",
                format!("layers·resolution² must be at most {MAX_VOXELS}, got {voxels}"),
            ));
        }
        let at = |i: usize| {
            let r2 = v.resolution * v.resolution;
            format!(
                "[layer {}, y {}, x {}]",
                i / r2,
                i % r2 / v.resolution,
                i % v.resolution
            )
        };
        if v.density.len() != voxels {
            return Err(PeltError::parameter(
                "density",
                format!(
                    "must hold layers·resolution² = {}·{}² = {voxels} values, got {}",
                    v.layers,
                    v.resolution,
                    v.density.len()
                ),
            ));
        }
        if let Some(i) = v
            .density
            .par_iter()
            .position_first(|d| !(d.is_finite() && *d >= 0.0))
        {
            return Err(PeltError::parameter(
                "density",
                format!("must be finite and >= 0, got {} at {}", v.density[i], at(i)),
            ));
        }
        if let Some(tangents) = v.tangents {
            if tangents.len() != voxels {
                return Err(PeltError::parameter(
                    "tangents",
                    format!("must hold one row per voxel ({voxels}), got {}", tangents.len()),
                ));
            }
            if let Some(i) = tangents
                .par_iter()
                .position_first(|t| t.iter().any(|c| !c.is_finite()))
            {
                return Err(PeltError::parameter(
                    "tangents",
                    format!("must be finite, got {:?} at {}", tangents[i], at(i)),
                ));
            }
        }
        let r2 = v.resolution * v.resolution;
        let empty = v
            .density
            .par_chunks(r2)
            .map(|l| l.iter().all(|&d| d == 0.0))
            .collect();
        Ok(Volume {
            layers: v.layers,
            resolution: v.resolution,
            spacing: f64::from(v.layer_spacing),
            density: v.density,
            empty,
        })
    }

    pub(super) fn voxel_count(&self) -> usize {
        self.density.len()
    }

    pub(super) fn layer(&self, l: usize) -> &'a [f32] {
        let r2 = self.resolution * self.resolution;
        &self.density[l * r2..(l + 1) * r2]
    }
}

/// Where a ray toward `ω` goes per layer gap.
#[derive(Debug, Clone, Copy)]
pub(super) struct RayGeometry {
    /// Lateral shift per gap, texel widths: `s·(ω_x, ω_y)/ω_z`.
    pub shift: [f64; 2],
    /// Path length per gap, texel widths: `s/ω_z`.
    pub length: f64,
}

impl RayGeometry {
    /// For a unit `dir` with `dir[2] > 0`.
    pub(super) fn new(dir: [f64; 3], spacing: f64) -> Self {
        let cz = dir[2].max(MIN_COS);
        RayGeometry {
            shift: [spacing * dir[0] / cz, spacing * dir[1] / cz],
            length: spacing / cz,
        }
    }
}

/// Extra per-voxel channels kept for some rows of voxels (band selection's test lights).
pub(super) struct ExtraRows {
    /// One entry per row of voxels (`l·R + y`): `[x][channel]` values for tracked rows.
    pub rows: Vec<Option<Vec<f32>>>,
}

impl ExtraRows {
    /// No rows tracked.
    pub(super) fn none(row_count: usize) -> Self {
        ExtraRows {
            rows: vec![None; row_count],
        }
    }

    /// Rows whose `y` is a multiple of `stride` tracked with `channels` values per voxel.
    pub(super) fn strided(layers: usize, res: usize, stride: usize, channels: usize) -> Self {
        ExtraRows {
            rows: (0..layers * res)
                .map(|row| {
                    (row % res)
                        .is_multiple_of(stride)
                        .then(|| vec![0.0; res * channels])
                })
                .collect(),
        }
    }
}
