//! Bench cases of the mesh stage.

use super::{BenchOptions, CaseResult, time_fallible};
use pelt_core::error::Result;
use pelt_core::mesh::{FurMesh, MeshInput, shapes};

/// `mesh.build`: validation, edge map, normals, frames and statistics of a 100k-triangle torus.
pub(super) fn mesh_build(options: &BenchOptions) -> Result<Vec<CaseResult>> {
    let (positions, triangles) = shapes::torus(224, 224);
    let reps = if options.quick { 7 } else { 31 };
    let timing = time_fallible(reps, || FurMesh::new(MeshInput::new(&positions, &triangles)))?;
    let size = format!("{} triangles, {} vertices", triangles.len(), positions.len());
    Ok(vec![CaseResult::timed("mesh.build", size, timing)])
}
