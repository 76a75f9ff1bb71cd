//! The transfer bake: how much of the light arriving from each direction reaches each voxel of
//! the hair volume, projected onto spherical harmonics.
//!
//! Follows §2.2 ("Off-line Rendering") and §2.3 ("PRT Basis Functions") of the PRT shell-fur
//! paper: the transmittance toward a light at infinity `T = exp(−σ Σ ρ Δs)` (its eq. 4; its `r` is
//! our `σ`), gathered for uniformly spread sample directions and projected onto the SH basis,
//!
//! ```text
//! t_lm(x) = Σ_i w_i · Y_lm(ω_i) · T(x, ω_i) · phase(x, ω_i),
//! ```
//!
//! so that at render time the light reaching a voxel under any lighting `L` is the dot product
//! `Σ L_lm t_lm(x)` (§2.4).
//!
//! # The volume
//!
//! [`TransferVolume`]: `layers` (L ≥ 2) square layers of `resolution` (R) texels, density stored at
//! `(l·R + y)·R + x`. The tile is 1 × 1 laterally and toroidal (x and y wrap); lengths are measured
//! in *texel widths*. Layer 0 is the skin (height 0); layer `l` sits at height `l·s`, where
//! `s = layer_spacing`. Between texel centres the density is bilinear (toroidal), between layers
//! linear in height, above the top layer zero; the skin is opaque, so a path that would pass below
//! height 0 is blocked. Density ρ ≥ 0 is the share of the texel covered by hair cross-section.
//!
//! # Transmittance
//!
//! Light arrives from infinity along `ω`; the path from a voxel centre toward `ω` accumulates
//! optical depth `τ = σ ∫ ρ dt` until it leaves the top layer, and `T = e^{−τ}`. Directions with
//! `ω_z ≤ 0` see the skin, which is infinite laterally, so `T = 0` there for every voxel. The
//! extinction σ is the optical depth per texel width of path through ρ = 1; the default
//! [`DEFAULT_SIGMA`] = ½ is explained there. Two methods compute `T` ([`Method`]): `Brute`, the
//! paper's march from every voxel (`march.rs`), and `Sweep`, which carries the optical depth
//! layer by layer for all voxels of a direction at once (`sweep.rs`). Depths above
//! [`TAU_CUT`] count as opaque (`T < 4·10⁻¹¹` is stored as 0).
//!
//! # Phase
//!
//! [`Phase::Isotropic`] (the paper's) weighs every direction by 1. [`Phase::KajiyaKay`] weighs it by
//! the diffuse term of Kajiya and Kay (1989), `sin(t, ω) = √(1 − (t·ω)²)`, with the voxel's hair
//! tangent `t`. Voxels without a tangent (zero vector: no hair) get the sphere mean of that term,
//! π/4, isotropically: their density is zero, so they only matter where texture filtering blends
//! them with neighbours, and the mean keeps that blend from brightening or darkening.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::accumulate::{PhaseField, Projector};
use super::sh::{self, PAPER_ORDER};
use super::sphere::{DEFAULT_DIRECTIONS, mirrored_fibonacci_directions};
use super::{march, sweep};
use crate::error::{PeltError, Result, check_range};
use crate::progress::{Progress, ProgressCallback};
use crate::threads::pool;

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

/// Most layers of a volume.
pub const MAX_LAYERS: usize = 4096;

/// Largest layer resolution.
pub const MAX_RESOLUTION: usize = 1 << 14;

/// Most voxels of a volume (`L·R²`), so coefficient buffers stay addressable.
pub const MAX_VOXELS: usize = 1 << 30;

/// Largest extinction σ.
pub const MAX_SIGMA: f32 = 1.0e6;

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
    /// there is no hair), `L·R²` rows. Needed by [`Phase::KajiyaKay`], ignored otherwise.
    pub tangents: Option<&'a [[f32; 3]]>,
}

/// The phase term of the transfer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Phase {
    /// Every direction weighs 1 (the paper's "light reaching each voxel").
    #[default]
    Isotropic,
    /// Kajiya–Kay diffuse `sin(t, ω)` with the voxel's hair tangent `t`.
    KajiyaKay,
}

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
        sh::check_order(self.order)?;
        check_range("directions", self.directions as f64, 16.0, MAX_DIRECTIONS as f64)?;
        check_range("sigma", f64::from(self.sigma), 0.0, f64::from(MAX_SIGMA))?;
        check_range("brute_step", f64::from(self.brute_step), 1e-3, 16.0)?;
        check_range("sweep_step", f64::from(self.sweep_step), 0.05, 16.0)?;
        check_range("sweep_max_samples", f64::from(self.sweep_max_samples), 1.0, 256.0)
    }
}

/// Baked transfer coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct Transfer {
    /// SH order n.
    pub order: usize,
    /// Layers L.
    pub layers: usize,
    /// Resolution R.
    pub resolution: usize,
    /// `[L][R][R][n²]` coefficients, f32.
    pub coefficients: Vec<f32>,
}

impl Transfer {
    /// Coefficients per voxel (`order²`).
    pub fn coeff_count(&self) -> usize {
        sh::coeff_count(self.order)
    }

    /// Checks that the fields agree: `order` in `1..=8` and `L·R²·order²` coefficients.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `order` or `coefficients`.
    pub fn check(&self) -> Result<()> {
        sh::check_order(self.order)?;
        let expected = self
            .layers
            .checked_mul(self.resolution)
            .and_then(|v| v.checked_mul(self.resolution))
            .and_then(|v| v.checked_mul(self.coeff_count()));
        if expected != Some(self.coefficients.len()) {
            return Err(PeltError::parameter(
                "coefficients",
                format!(
                    "must hold layers·resolution²·order² = {}·{}²·{} values, got {}",
                    self.layers,
                    self.resolution,
                    self.coeff_count(),
                    self.coefficients.len()
                ),
            ));
        }
        Ok(())
    }

    /// The coefficients of voxel `(layer, y, x)`, if it exists.
    pub fn voxel(&self, layer: usize, y: usize, x: usize) -> Option<&[f32]> {
        let (r, n) = (self.resolution, self.coeff_count());
        if layer >= self.layers || y >= r || x >= r {
            return None;
        }
        let v = (layer * r + y) * r + x;
        self.coefficients.get(v * n..(v + 1) * n)
    }

    /// The same transfer cut to the first `order` bands (lower bands do not depend on how many
    /// higher ones were baked).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] (`order`) when `order` is 0 or above [`Transfer::order`].
    pub fn truncated(&self, order: usize) -> Result<Transfer> {
        if !(1..=self.order).contains(&order) {
            return Err(PeltError::parameter(
                "order",
                format!(
                    "must be between 1 and the baked order {}, got {order}",
                    self.order
                ),
            ));
        }
        let (from, to) = (self.coeff_count(), sh::coeff_count(order));
        let coefficients = self
            .coefficients
            .chunks_exact(from)
            .flat_map(|c| c[..to].iter().copied())
            .collect();
        Ok(Transfer {
            order,
            coefficients,
            ..*self
        })
    }
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

/// The bake directions of `params` ([`mirrored_fibonacci_directions`]) with their (equal)
/// weight.
pub fn bake_directions(params: &TransferParams) -> (Vec<[f64; 3]>, f64) {
    let dirs = mirrored_fibonacci_directions(params.directions);
    let weight = 4.0 * std::f64::consts::PI / dirs.len().max(1) as f64;
    (dirs, weight)
}

/// Checks that the phase has what it needs.
fn check_phase(volume: &TransferVolume<'_>, params: &TransferParams) -> Result<()> {
    if params.phase == Phase::KajiyaKay && volume.tangents.is_none() {
        return Err(PeltError::parameter(
            "tangents",
            "are required by the Kajiya-Kay phase (pass a tangent per voxel)",
        ));
    }
    Ok(())
}

/// The bake of `projector`'s channels for a validated volume, in the current pool.
pub(super) fn bake_channels(
    vol: &Volume<'_>,
    params: &TransferParams,
    projector: &Projector,
    phase: &PhaseField,
    progress: Option<ProgressCallback<'_>>,
    extra: &mut ExtraRows,
) -> Result<Vec<f32>> {
    let mut out = vec![0.0f32; vol.voxel_count() * projector.sh_channels];
    let sigma = f64::from(params.sigma);
    match params.method {
        Method::Brute => {
            let progress = Progress::new(vol.layers * vol.resolution, progress);
            let step = f64::from(params.brute_step);
            march::bake(vol, sigma, step, projector, phase, &progress, &mut out, extra)?;
        }
        Method::Sweep => {
            let progress = Progress::new(vol.layers * projector.dirs.len(), progress);
            let step = f64::from(params.sweep_step);
            let max_samples = params.sweep_max_samples as usize;
            sweep::bake(
                vol,
                sigma,
                step,
                max_samples,
                projector,
                phase,
                &progress,
                &mut out,
                extra,
            )?;
        }
    }
    Ok(out)
}

/// Bakes the transfer coefficients of `volume` (layout `[L][R][R][order²]`).
///
/// `progress` receives the finished fraction and may return `false` to cancel. Runs in Pelt's
/// thread pool; the result is bit-identical for any number of threads.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming the field of `params` or `volume` that is out of range
/// (wrong array length, negative or non-finite density, non-finite tangent, missing tangents for
/// [`Phase::KajiyaKay`]); [`PeltError::Cancelled`] when `progress` returned `false`.
pub fn bake_transfer(
    volume: &TransferVolume<'_>,
    params: &TransferParams,
    progress: Option<ProgressCallback<'_>>,
) -> Result<Transfer> {
    params.validate()?;
    check_phase(volume, params)?;
    super::peak::check_transfer_memory(volume.layers, volume.resolution, params, false, false)?;
    pool().install(|| bake_validated(volume, params, progress))
}

/// The body of [`bake_transfer`], run in whatever pool is current (tests pin the thread count).
pub(super) fn bake_validated(
    volume: &TransferVolume<'_>,
    params: &TransferParams,
    progress: Option<ProgressCallback<'_>>,
) -> Result<Transfer> {
    let vol = Volume::new(volume)?;
    let (dirs, weight) = bake_directions(params);
    let projector = Projector::new(params.order, &dirs, weight, 0, |_, _| {})?;
    let phase = PhaseField::new(params.phase, volume.tangents);
    let mut extra = ExtraRows::none(vol.layers * vol.resolution);
    let coefficients = bake_channels(&vol, params, &projector, &phase, progress, &mut extra)?;
    Ok(Transfer {
        order: params.order,
        layers: vol.layers,
        resolution: vol.resolution,
        coefficients,
    })
}

/// The transmittance `T(x, ω)` of every voxel toward one direction (`[L][R][R]`), by
/// `params.method` with `params.sigma` and the method's step settings (order, directions and
/// phase are not used). `direction` points toward the light and need not be normalized.
///
/// # Errors
/// [`PeltError::InvalidParameter`] for a bad volume or parameter, or a `direction` that is not
/// finite or has zero length.
pub fn transmittance(
    volume: &TransferVolume<'_>,
    params: &TransferParams,
    direction: [f64; 3],
) -> Result<Vec<f32>> {
    params.validate()?;
    let len = direction.iter().map(|v| v * v).sum::<f64>().sqrt();
    if !(len.is_finite() && len > 0.0) {
        return Err(PeltError::parameter(
            "direction",
            format!("must be finite and non-zero, got {direction:?}"),
        ));
    }
    let dir = direction.map(|v| v / len);
    pool().install(|| {
        let vol = Volume::new(volume)?;
        if dir[2] <= 0.0 {
            return Ok(vec![0.0; vol.voxel_count()]);
        }
        let sigma = f64::from(params.sigma);
        Ok(match params.method {
            Method::Brute => {
                let ray = RayGeometry::new(dir, vol.spacing);
                march::transmittance(&vol, sigma, f64::from(params.brute_step), &ray)
            }
            Method::Sweep => sweep::transmittance(
                &vol,
                sigma,
                f64::from(params.sweep_step),
                params.sweep_max_samples as usize,
                dir,
            ),
        })
    })
}
