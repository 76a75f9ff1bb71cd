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

pub use super::accumulate::Phase;
use super::accumulate::{PhaseField, Projector};
pub use super::params::{
    DEFAULT_BRUTE_STEP, DEFAULT_SIGMA, DEFAULT_SWEEP_MAX_SAMPLES, DEFAULT_SWEEP_STEP, MAX_DIRECTIONS,
    MAX_SIGMA, Method, TransferParams,
};
use super::sh::{self};
use super::sphere::mirrored_fibonacci_directions;
use super::volume::{ExtraRows, RayGeometry, Volume};
pub use super::volume::{MAX_LAYER_SPACING, MAX_LAYERS, MAX_RESOLUTION, MAX_VOXELS, TAU_CUT, TransferVolume};
use super::{march, sweep};
use crate::error::{PeltError, Result};
use crate::progress::{Progress, ProgressCallback};
use crate::threads::pool;

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
