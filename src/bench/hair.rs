//! Bench cases of strand growth.

use super::{BenchOptions, CaseResult, time_fallible};
use crate::error::Result;
use crate::hair::{HairParams, grow_strands};

/// `hair.grow`: one tile of strands with clumping and a helix.
pub(super) fn hair_grow(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let params = HairParams {
        density: if options.quick { 65_536 } else { 262_144 },
        clump_count: 64,
        clump_strength: 0.4,
        helix_radius: 0.002,
        helix_frequency: 2.0,
        ..HairParams::default()
    };
    let timing = time_fallible(if options.quick { 5 } else { 15 }, || grow_strands(&params))?;
    let size = format!(
        "{} strands x {} segments, {} clumps",
        params.density, params.segments, params.clump_count
    );
    Ok(vec![CaseResult::timed("hair.grow", size, timing)])
}
