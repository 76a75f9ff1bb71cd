//! Tests of the export module: every writer's output is read back by an independent decoder
//! (the `png` crate's decoder, the `exr` crate, the `ktx2` crate).

mod exr;
mod fixture;
mod glb_reader;
mod gltf;
mod ktx2;
mod png;
mod rig;
mod texture_set;

use crate::test_support::{parameter_name, random_bytes, random_floats, with_threads};

/// A fresh, empty folder under the system temporary folder for one test.
fn temp_dir(test: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("pelt-export-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn every_reference_shader_named_in_the_description_exists() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let files: Vec<&str> = super::description::REFERENCE_SHADERS.split(", ").collect();
    assert!(files.contains(&"crates/pelt-render/src/light_model.wgsl"));
    for file in files {
        assert!(root.join(file).is_file(), "{file} is not a file");
    }
}
