//! Bench cases of the hair volume.

use super::{BenchOptions, CaseResult, time_fallible};
use crate::error::Result;
use crate::hair::{HairParams, grow_strands};
use crate::volume::coverage::{CoverageMode, splat_disk};

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
