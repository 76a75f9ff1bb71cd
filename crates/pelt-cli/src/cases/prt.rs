//! Bench cases of precomputed radiance transfer.

use super::{BenchOptions, CaseResult, time_fallible, time_once};
use pelt_core::error::Result;
use pelt_core::hair::HairParams;
use pelt_core::prt::bands::{BandParams, bake_transfer_auto};
use pelt_core::prt::sh;
use pelt_core::prt::transfer::{Method, TransferParams, TransferVolume, bake_transfer};
use pelt_core::prt::volume_input::VolumeInput;
use pelt_core::volume::{HairVolume, VolumeParams, bake_volume};

/// `prt.sh.project_equirect`: an HDR environment (a sky gradient and a sun disk) to order-8 SH.
pub(super) fn sh_project_equirect(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let (width, height) = if options.quick { (512, 256) } else { (2048, 1024) };
    let rgb: Vec<f32> = (0..width * height)
        .flat_map(|i| {
            let (x, y) = (
                (i % width) as f32 / width as f32,
                (i / width) as f32 / height as f32,
            );
            let sun = if (x - 0.3).hypot(y - 0.25) < 0.01 {
                50.0
            } else {
                0.0
            };
            [
                0.2 + 0.8 * (1.0 - y) + sun,
                0.3 + 0.7 * (1.0 - y) + sun,
                1.0 - 0.5 * y + sun,
            ]
        })
        .collect();
    let timing = time_fallible(if options.quick { 5 } else { 11 }, || {
        sh::project_equirect(sh::MAX_ORDER, width, height, &rgb)
    })?;
    let size = format!("{width}x{height} RGB, order {}", sh::MAX_ORDER);
    Ok(vec![CaseResult::timed("prt.sh.project_equirect", size, timing)])
}

/// The benchmark volume: the default pelt baked at `R × R × L`, read a quarter of the tile deep.
struct BenchVolume {
    baked: HairVolume,
    input: VolumeInput,
}

impl BenchVolume {
    fn new(options: &BenchOptions) -> Result<Self> {
        let (resolution, layers) = if options.quick { (32, 8) } else { (128, 16) };
        let params = VolumeParams {
            resolution,
            layers,
            trim: false,
            lod: false,
            mipmaps: false,
            ..VolumeParams::default()
        };
        let baked = bake_volume(&HairParams::default(), &params, None)?;
        let input = VolumeInput::new(&baked, 0.25);
        Ok(BenchVolume { baked, input })
    }

    fn volume(&self) -> TransferVolume<'_> {
        self.input.transfer_volume(&self.baked)
    }

    fn size(&self, what: &str) -> String {
        format!(
            "{r}x{r}x{l}, {what}, 256 dirs, default pelt 1/4 tile deep",
            r = self.baked.resolution,
            l = self.baked.layers
        )
    }
}

/// `prt.transfer.brute` and `prt.transfer.sweep`: order-5 transfer of the benchmark volume. The
/// brute force runs once (it takes minutes at full size); the sweep reports its speedup over it and
/// the relative RMS difference of all coefficients.
pub(super) fn transfer(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let bench = BenchVolume::new(options)?;
    let volume = bench.volume();
    let params = |method| TransferParams {
        method,
        ..TransferParams::default()
    };
    let (brute, brute_timing) = time_once(|| bake_transfer(&volume, &params(Method::Brute), None))?;
    let mut sweep = None;
    let sweep_timing = time_fallible(if options.quick { 3 } else { 5 }, || {
        sweep = Some(bake_transfer(&volume, &params(Method::Sweep), None)?);
        Ok(())
    })?;
    let error = sweep.map(|s| {
        let (mut num, mut den) = (0.0, 0.0);
        for (a, b) in s.coefficients.iter().zip(&brute.coefficients) {
            num += f64::from(a - b).powi(2);
            den += f64::from(*b).powi(2);
        }
        (num / den).sqrt()
    });
    let size = bench.size("order 5 (25 coeffs)");
    Ok(vec![
        CaseResult::timed("prt.transfer.brute", size.clone(), brute_timing),
        CaseResult {
            error,
            error_metric: Some("relative RMS of all coefficients vs prt.transfer.brute".into()),
            baseline: Some("prt.transfer.brute".into()),
            speedup: Some(brute_timing.0 / sweep_timing.0),
            ..CaseResult::timed("prt.transfer.sweep", size, sweep_timing)
        },
    ])
}

/// `prt.bands.orderN`: the band-selection table of the benchmark volume (one order-8 sweep with
/// the test lights), one row per order; every row carries the time of the whole selection.
pub(super) fn bands(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let bench = BenchVolume::new(options)?;
    let volume = bench.volume();
    let mut report = None;
    let timing = time_fallible(if options.quick { 1 } else { 3 }, || {
        report =
            Some(bake_transfer_auto(&volume, &TransferParams::default(), &BandParams::default(), None)?.1);
        Ok(())
    })?;
    let Some(report) = report else {
        return Ok(Vec::new());
    };
    Ok(report
        .rows
        .iter()
        .map(|row| {
            let chosen = if row.order == report.order { ", chosen" } else { "" };
            let size = bench.size(&format!(
                "order {} ({} coeffs, {:.1} MiB f16, {:.1} MiB u8, band energy {:.2e}{chosen})",
                row.order,
                row.coefficients,
                row.bytes_f16 as f64 / 1048576.0,
                row.bytes_u8 as f64 / 1048576.0,
                row.band_energy
            ));
            CaseResult {
                error: Some(row.error),
                error_metric: Some(format!(
                    "relative RMS lighting error vs direct lighting (max of 64 soft lights {:.2e}, environment {:.2e}); tolerance {}",
                    row.error_directional, row.error_environment, report.tolerance
                )),
                ..CaseResult::timed(&format!("prt.bands.order{}", row.order), size, timing)
            }
        })
        .collect())
}
