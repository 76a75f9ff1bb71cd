//! Bench cases of the lapped patches.

use super::{BenchOptions, CaseResult, time_fallible};
use pelt_core::error::Result;
use pelt_core::lapped::{PatchParams, build_patches};
use pelt_core::mesh::{FurMesh, MeshInput, shapes};

/// `lapped.build`: direction field and patches (growth, parameterization, quality figures) of a
/// bumpy torus of about 15k and 100k triangles, tile 0.05 (the torus is 2.7 units across). The
/// quality figures go in `size`; `error` is the area-weighted mean alignment error.
pub(super) fn lapped_build(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let sizes: &[(usize, usize)] = if options.quick {
        &[(88, 88)]
    } else {
        &[(88, 88), (224, 224)]
    };
    let params = PatchParams {
        tile_size: 0.05,
        ..PatchParams::default()
    };
    let mut results = Vec::new();
    for &(around, across) in sizes {
        let (positions, triangles) = shapes::bumpy_torus(around, across);
        let mesh = FurMesh::new(MeshInput::new(&positions, &triangles))?;
        let patches = build_patches(&mesh, &params)?;
        let reps = if options.quick { 3 } else { 5 };
        let timing = time_fallible(reps, || build_patches(&mesh, &params))?;
        let q = &patches.quality;
        let size = format!(
            "{} triangles: {} patches, seams {:.1}%, stretch ok {:.1}%, {} flipped, coverage {:.0}%",
            triangles.len(),
            q.patch_count,
            100.0 * q.seam_length_fraction,
            100.0 * q.stretch_within_fraction,
            q.flipped_faces,
            100.0 * q.coverage,
        );
        results.push(CaseResult {
            error: Some(q.mean_alignment_deg),
            error_metric: Some("area-weighted mean alignment error, degrees".into()),
            ..CaseResult::timed(&format!("lapped.build.{}k", triangles.len() / 1000), size, timing)
        });
    }
    Ok(results)
}
