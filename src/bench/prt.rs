//! Bench cases of precomputed radiance transfer.

use super::{BenchOptions, CaseResult, time_fallible};
use crate::error::Result;
use crate::prt::sh;

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
