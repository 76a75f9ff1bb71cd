//! Bench cases of strand growth and placement.

use super::{BenchOptions, CaseResult, time_fallible};
use pelt_core::error::Result;
use pelt_core::hair::{HairParams, grow_strands};

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

/// `guard.place`: the guard hairs (the overcoat's strands) placed over a 65,536-triangle sphere
/// through its lapped patches, about 130,000 of them (the hybrid issue's 100k on 60k triangles);
/// the patches are built outside the timing.
pub(super) fn guard_place(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let (segments, rings) = if options.quick { (64, 32) } else { (256, 128) };
    let (positions, triangles) = pelt_core::mesh::shapes::uv_sphere(segments, rings);
    let mesh = pelt_core::FurMesh::new(pelt_core::MeshInput::new(&positions, &triangles))?;
    let patches = pelt_core::lapped::build_patches(
        &mesh,
        &pelt_core::lapped::PatchParams {
            tile_size: 0.2,
            ..Default::default()
        },
    )?;
    let hair = HairParams {
        density: 4096,
        guard_fraction: 0.1,
        ..HairParams::default()
    };
    let mut placed = 0;
    let timing = time_fallible(if options.quick { 3 } else { 7 }, || {
        let guard = pelt_core::guard::guard_hairs(&mesh, &patches, &hair, 0.05, 1.0)?;
        placed = guard.spans.len();
        Ok(guard)
    })?;
    let size = format!(
        "{} guard hairs x {} points over {} triangles",
        placed,
        hair.segments + 1,
        mesh.face_count()
    );
    Ok(vec![CaseResult::timed("guard.place", size, timing)])
}
