//! Wavefront OBJ reading, so pipelines without Blender (`pelt bake mesh.obj`) and the benchmarks
//! can load real meshes. Only what a fur bake needs: `v` (with optional per-vertex RGB, the common
//! `v x y z r g b` extension) and `f` (polygons of any size, `i`, `i/t`, `i//n`, `i/t/n`, negative
//! indices counted from the end). Polygons are fanned into triangles and keep their polygon id, as
//! Blender's loop triangles do, so the lapped patches keep each polygon whole. Other statements
//! (normals, texture coordinates, groups, materials) are skipped.

use std::path::Path;

use crate::error::{PeltError, Result};
use crate::mesh::MeshInput;

/// A mesh read from a file, owning its arrays; [`MeshData::input`] borrows them for
/// [`crate::FurMesh::new`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshData {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Triangles, fanned from the polygons in file order.
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle, the index of the polygon (face statement) it came from.
    pub polygons: Vec<u32>,
    /// Linear RGBA per vertex when every vertex gave a color.
    pub color: Option<Vec<[f32; 4]>>,
}

impl MeshData {
    /// The arrays as [`MeshInput`] (positions, triangles, polygons and color when present).
    pub fn input(&self) -> MeshInput<'_> {
        let input = MeshInput::new(&self.positions, &self.triangles).with_polygons(&self.polygons);
        match &self.color {
            Some(color) => input.with_color(color),
            None => input,
        }
    }
}

/// Reads an OBJ file.
///
/// # Errors
/// [`PeltError::Io`] when the file cannot be read; [`PeltError::InvalidParameter`] naming the file
/// and line for a malformed statement or an index outside the vertices read so far.
pub fn read_obj(path: &Path) -> Result<MeshData> {
    let bytes = std::fs::read(path).map_err(|source| PeltError::Io {
        path: path.display().to_string(),
        source,
    })?;
    // Bytes that are not UTF-8 (a Latin-1 comment or group name from an older exporter) stand
    // only in words Pelt does not read; numbers and keywords are ASCII either way.
    parse_obj(&String::from_utf8_lossy(&bytes)).map_err(|e| match e {
        PeltError::InvalidParameter { reason, .. } => {
            PeltError::parameter(path.display().to_string(), reason)
        }
        other => other,
    })
}

/// Parses OBJ text; see [`read_obj`]. Errors name `obj` and the line.
pub fn parse_obj(text: &str) -> Result<MeshData> {
    let mut mesh = MeshData::default();
    let mut colors: Vec<[f32; 4]> = Vec::new();
    let mut corners: Vec<u32> = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let bad = |what: &str| PeltError::parameter("obj", format!("line {}: {what}", number + 1));
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let values = words
                    .map(|w| w.parse::<f32>().ok().filter(|v| v.is_finite()))
                    .collect::<Option<Vec<f32>>>()
                    .ok_or_else(|| bad("vertex coordinates must be finite numbers"))?;
                match values.len() {
                    3 | 4 => mesh.positions.push([values[0], values[1], values[2]]),
                    6 | 7 => {
                        mesh.positions.push([values[0], values[1], values[2]]);
                        colors.push([values[3], values[4], values[5], 1.0]);
                    }
                    n => return Err(bad(&format!("a vertex has 3 or 6 numbers, found {n}"))),
                }
            }
            Some("f") => {
                corners.clear();
                for word in words {
                    let index = word.split('/').next().unwrap_or_default();
                    let index: i64 = index
                        .parse()
                        .map_err(|_| bad(&format!("face index `{word}` is not an integer")))?;
                    let count = mesh.positions.len() as i64;
                    let resolved = if index < 0 { count + index } else { index - 1 };
                    if !(0..count).contains(&resolved) {
                        return Err(bad(&format!(
                            "face index {index} is outside the {count} vertices read so far"
                        )));
                    }
                    corners.push(resolved as u32);
                }
                if corners.len() < 3 {
                    return Err(bad("a face needs at least 3 corners"));
                }
                let polygon = mesh.polygons.last().map_or(Some(0), |p| p.checked_add(1));
                let polygon = polygon.ok_or_else(|| bad("too many faces"))?;
                for k in 1..corners.len() - 1 {
                    mesh.triangles.push([corners[0], corners[k], corners[k + 1]]);
                    mesh.polygons.push(polygon);
                }
            }
            _ => {}
        }
    }
    if !colors.is_empty() && colors.len() == mesh.positions.len() {
        mesh.color = Some(colors);
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fans_polygons_and_keeps_their_ids() {
        let text = "# a quad and a triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n\
                    vn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\nf -4//1 5//1 -3//1\n";
        let mesh = parse_obj(text).unwrap();
        assert_eq!(mesh.positions.len(), 5);
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3], [1, 4, 2]]);
        assert_eq!(mesh.polygons, vec![0, 0, 1]);
        assert_eq!(mesh.color, None);
        assert!(crate::FurMesh::new(mesh.input()).is_ok());
    }

    #[test]
    fn reads_vertex_colors() {
        let mesh = parse_obj("v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n").unwrap();
        let color = mesh.color.unwrap();
        assert_eq!(color[1], [0.0, 1.0, 0.0, 1.0]);
    }

    #[test]
    fn bad_statements_name_the_line() {
        for (text, needle) in [
            ("v 0 0\n", "line 1"),
            ("v 0 0 0\nv 1 0 0\nf 1 2 3\n", "line 3: face index 3"),
            ("v 0 0 nan\n", "finite"),
            ("v 0 0 0\nf 1 x 1\n", "`x`"),
            ("v 0 0 0\nv 0 0 0\nf 1 2\n", "at least 3"),
        ] {
            let message = parse_obj(text).unwrap_err().to_string();
            assert!(message.contains(needle), "{text:?}: {message}");
        }
    }

    #[test]
    fn suzanne_and_its_subdivision_are_watertight_where_blender_says() {
        let suzanne = crate::mesh::shapes::suzanne();
        assert_eq!((suzanne.positions.len(), suzanne.triangles.len()), (507, 968));
        assert_eq!(*suzanne.polygons.last().unwrap(), 499);
        let fine = crate::mesh::shapes::subdivide(&suzanne, 2);
        assert_eq!(fine.triangles.len(), 968 * 16);
        let before = crate::FurMesh::new(suzanne.input()).unwrap();
        let after = crate::FurMesh::new(fine.input()).unwrap();
        // Midpoint splits keep the surface: same area, same boundary-edge count times 4.
        let (a, b) = (before.stats().surface_area, after.stats().surface_area);
        assert!((a - b).abs() < 1e-4 * a, "{a} vs {b}");
        assert_eq!(after.stats().boundary_edges, 4 * before.stats().boundary_edges);
    }

    #[test]
    fn missing_file_is_an_io_error() {
        let error = read_obj(Path::new("/nonexistent/pelt.obj")).unwrap_err();
        assert!(matches!(error, PeltError::Io { .. }), "{error}");
    }

    #[test]
    fn latin1_comments_and_names_do_not_stop_the_read() {
        let path = std::env::temp_dir().join(format!("pelt-latin1-{}.obj", std::process::id()));
        // "Créé" and "Fläche" in Latin-1: bytes that are not UTF-8.
        let text = b"# Cr\xe9\xe9 par un vieil export\ng Fl\xe4che\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        std::fs::write(&path, text).unwrap();
        let mesh = read_obj(&path);
        std::fs::remove_file(&path).unwrap();
        let mesh = mesh.unwrap();
        assert_eq!((mesh.positions.len(), mesh.triangles.len()), (3, 1));
    }
}
