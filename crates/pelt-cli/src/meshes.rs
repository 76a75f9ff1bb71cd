//! Mesh files for `pelt bake`: an OBJ is one object named after the file, a glTF file one object
//! per node with a mesh.

use std::path::Path;

use pelt_core::mesh::gltf_read::read_gltf;
use pelt_core::mesh::obj::{MeshData, read_obj};

/// The objects of the mesh file at `path`, by its extension.
pub fn read_objects(path: &Path) -> Result<Vec<(String, MeshData)>, String> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    match extension.as_str() {
        "obj" => {
            let name = path
                .file_stem()
                .map_or_else(|| "mesh".into(), |s| s.to_string_lossy().into_owned());
            let mesh = read_obj(path).map_err(|e| e.to_string())?;
            Ok(vec![(name, mesh)])
        }
        "glb" | "gltf" => Ok(read_gltf(path)
            .map_err(|e| e.to_string())?
            .into_iter()
            .map(|object| (object.name, object.mesh))
            .collect()),
        _ => Err(format!(
            "{}: unknown mesh format; expected .obj, .glb or .gltf",
            path.display()
        )),
    }
}
