//! Bench cases of the hair volume.

use super::{BenchOptions, CaseResult, time_fallible};
use pelt_core::error::Result;
use pelt_core::hair::{HairParams, grow_strands};
use pelt_core::volume::coverage::{CoverageMode, splat_disk};
use pelt_core::volume::{HairVolume, VolumeParams, bake_strands};

/// `volume.coverage.approx`: the root cross-sections of the default strands splatted into one
/// 128² layer with the paper's chord/wedge approximation, against the exact area in the same run.
pub(super) fn coverage_approx(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    const RES: usize = 128;
    let strands = grow_strands(&HairParams::default())?;
    let splat_all = |mode: CoverageMode| -> Result<Vec<f32>> {
        let mut grid = vec![0.0f32; RES * RES];
        for s in &strands {
            splat_disk(&mut grid, RES, s.root[0], s.root[1], s.radii[0], mode)?;
        }
        Ok(grid)
    };
    let exact = splat_all(CoverageMode::Exact)?;
    let approx = splat_all(CoverageMode::Approx)?;
    let error = exact
        .iter()
        .zip(&approx)
        .map(|(a, b)| f64::from((a - b).abs()))
        .fold(0.0, f64::max);
    let reps = if options.quick { 7 } else { 31 };
    let exact_timing = time_fallible(reps, || splat_all(CoverageMode::Exact))?;
    let approx_timing = time_fallible(reps, || splat_all(CoverageMode::Approx))?;
    let size = format!("{} disks into {RES}x{RES}", strands.len());
    Ok(vec![
        CaseResult::timed("volume.coverage.exact", size.clone(), exact_timing),
        CaseResult {
            error: Some(error),
            error_metric: Some("max absolute texel coverage difference vs exact".into()),
            baseline: Some("volume.coverage.exact".into()),
            speedup: Some(exact_timing.0 / approx_timing.0),
            ..CaseResult::timed("volume.coverage.approx", size, approx_timing)
        },
    ])
}

/// Hair for a bake bench: `density` strands, widths scaled so that hairs stay about one texel
/// wide at `resolution` (the default widths are meant for 128²).
fn bench_hair(density: u32, resolution: usize) -> HairParams {
    let scale = 128.0 / resolution as f64;
    let defaults = HairParams::default();
    let mut hair = HairParams {
        density,
        ..defaults.clone()
    };
    hair.undercoat.width = defaults.undercoat.width.map(|w| w * scale);
    hair.overcoat.width = defaults.overcoat.width.map(|w| w * scale);
    hair
}

fn bake_size(v: &HairVolume, strands: usize) -> String {
    let bytes = v.shells.len()
        + v.tangents.len()
        + 4 * v.coverage.len()
        + v.fin.len()
        + v.lod.iter().map(Vec::len).sum::<usize>()
        + v.mips.iter().map(Vec::len).sum::<usize>();
    format!(
        "{r}x{r}x{l} from {strands} strands, output {:.1} MiB",
        bytes as f64 / (1024.0 * 1024.0),
        r = v.resolution,
        l = v.layers,
    )
}

/// `volume.bake.*`: the whole hair-volume bake (shells, coverage, tangents, fin, LOD chain,
/// mipmaps) by each coverage mode; the approximations report their coverage error and speed
/// against the exact bake of the same strands.
pub(super) fn volume_bake(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let mut results = Vec::new();
    let small = VolumeParams::default();
    let strands = grow_strands(&bench_hair(5000, small.resolution))?;
    let reps = if options.quick { 5 } else { 15 };
    let exact = bake_strands(&strands, &small, None)?;
    let exact_timing = time_fallible(reps, || bake_strands(&strands, &small, None))?;
    let size = bake_size(&exact, strands.len());
    results.push(CaseResult::timed("volume.bake.exact", size.clone(), exact_timing));
    for (name, mode) in [
        ("volume.bake.approx", CoverageMode::Approx),
        ("volume.bake.supersample16", CoverageMode::Supersample(16)),
    ] {
        let params = VolumeParams {
            coverage: mode,
            ..small.clone()
        };
        let other = bake_strands(&strands, &params, None)?;
        let diffs: Vec<f64> = exact
            .coverage
            .iter()
            .zip(&other.coverage)
            .map(|(a, b)| f64::from((a - b).abs()))
            .collect();
        let max = diffs.iter().copied().fold(0.0, f64::max);
        let mean = diffs.iter().sum::<f64>() / diffs.len() as f64;
        let timing = time_fallible(reps, || bake_strands(&strands, &params, None))?;
        results.push(CaseResult {
            error: Some(max),
            error_metric: Some(format!("max abs texel coverage diff vs exact (mean {mean:.1e})")),
            baseline: Some("volume.bake.exact".into()),
            speedup: Some(exact_timing.0 / timing.0),
            ..CaseResult::timed(name, size.clone(), timing)
        });
    }
    let (res, layers, density) = if options.quick {
        (512, 32, 50_000)
    } else {
        (1024, 64, 200_000)
    };
    let large = VolumeParams {
        resolution: res,
        layers,
        ..VolumeParams::default()
    };
    let strands = grow_strands(&bench_hair(density, res))?;
    let volume = bake_strands(&strands, &large, None)?;
    let size = bake_size(&volume, strands.len());
    drop(volume);
    let timing = time_fallible(if options.quick { 1 } else { 3 }, || {
        bake_strands(&strands, &large, None)
    })?;
    results.push(CaseResult::timed("volume.bake.exact", size, timing));
    Ok(results)
}
