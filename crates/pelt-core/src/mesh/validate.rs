//! Input checks for [`super::FurMesh`]. Each check reports the first offending row (lowest index),
//! found in parallel but independent of the thread count.

use rayon::prelude::*;

use super::{MAX_LENGTH, MeshInput};
use crate::error::MeshError;

/// Checks every array of `input`; the order of checks is the order of the error list in the docs.
pub(super) fn validate(input: &MeshInput<'_>) -> Result<(), MeshError> {
    let n = input.positions.len();
    if n == 0 {
        return Err(MeshError::Empty("vertices"));
    }
    if input.triangles.is_empty() {
        return Err(MeshError::Empty("triangles"));
    }
    if n > u32::MAX as usize {
        return Err(MeshError::TooManyVertices(n));
    }
    one_row_per_vertex(
        [
            ("normals", input.normals.map(<[_]>::len)),
            ("color", input.color.map(<[_]>::len)),
            ("comb", input.comb.map(<[_]>::len)),
            ("length", input.length.map(<[_]>::len)),
        ],
        n,
    )?;
    if let Some(polygons) = input.polygons
        && polygons.len() != input.triangles.len()
    {
        return Err(MeshError::TriangleAttributeLength {
            array: "polygons",
            expected: input.triangles.len(),
            got: polygons.len(),
        });
    }
    finite_rows("positions", input.positions)?;
    indices_in_range(input.triangles, n)?;
    if let Some(normals) = input.normals {
        usable_normals(normals)?;
    }
    if let Some(color) = input.color {
        finite_rows("color", color)?;
    }
    if let Some(comb) = input.comb {
        finite_rows("comb", comb)?;
    }
    if let Some(length) = input.length {
        let rows: &[[f32; 1]] = length.as_chunks::<1>().0;
        finite_rows("length", rows)?;
        if let Some(vertex) = length
            .par_iter()
            .position_first(|&l| !(0.0..=MAX_LENGTH).contains(&l))
        {
            return Err(MeshError::LengthOutOfRange {
                vertex,
                value: length[vertex],
                max: MAX_LENGTH,
            });
        }
    }
    Ok(())
}

/// Checks a pose of a valid mesh of `vertex_count` vertices (its triangles are the mesh's, so
/// only the rows need checking), in the order of [`validate`].
pub(super) fn validate_pose(
    positions: &[[f32; 3]],
    normals: Option<&[[f32; 3]]>,
    vertex_count: usize,
) -> Result<(), MeshError> {
    one_row_per_vertex(
        [
            ("positions", Some(positions.len())),
            ("normals", normals.map(<[_]>::len)),
        ],
        vertex_count,
    )?;
    finite_rows("positions", positions)?;
    normals.map_or(Ok(()), usable_normals)
}

/// Fails on the first array (given ones: `Some(rows)`) whose row count is not `vertex_count`.
fn one_row_per_vertex<const N: usize>(
    arrays: [(&'static str, Option<usize>); N],
    vertex_count: usize,
) -> Result<(), MeshError> {
    match arrays
        .into_iter()
        .find_map(|(array, rows)| rows.filter(|&got| got != vertex_count).map(|got| (array, got)))
    {
        Some((array, got)) => Err(MeshError::AttributeLength {
            array,
            expected: vertex_count,
            got,
        }),
        None => Ok(()),
    }
}

/// Fails on the first normal row that is not finite or is zero.
fn usable_normals(normals: &[[f32; 3]]) -> Result<(), MeshError> {
    finite_rows("normals", normals)?;
    match normals.par_iter().position_first(|v| v.iter().all(|&c| c == 0.0)) {
        Some(row) => Err(MeshError::ZeroNormal { row }),
        None => Ok(()),
    }
}

/// Fails on the first row holding a NaN or infinity.
fn finite_rows<const C: usize>(array: &'static str, rows: &[[f32; C]]) -> Result<(), MeshError> {
    let Some(row) = rows
        .par_iter()
        .position_first(|r| r.iter().any(|c| !c.is_finite()))
    else {
        return Ok(());
    };
    let component = rows[row].iter().position(|c| !c.is_finite()).unwrap_or(0);
    Err(MeshError::NonFinite {
        array,
        row,
        component,
        value: rows[row][component],
    })
}

/// Fails on the first triangle corner that names a vertex `>= vertex_count`.
fn indices_in_range(triangles: &[[u32; 3]], vertex_count: usize) -> Result<(), MeshError> {
    let Some(triangle) = triangles
        .par_iter()
        .position_first(|t| t.iter().any(|&i| i as usize >= vertex_count))
    else {
        return Ok(());
    };
    let corner = triangles[triangle]
        .iter()
        .position(|&i| i as usize >= vertex_count)
        .unwrap_or(0);
    Err(MeshError::IndexOutOfRange {
        triangle,
        corner,
        index: i64::from(triangles[triangle][corner]),
        vertex_count,
    })
}
