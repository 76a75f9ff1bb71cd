//! What the command-line tests bake: Blender's Suzanne with small settings, so a bake is quick.

use std::path::{Path, PathBuf};

/// Blender's Suzanne as OBJ, in the workspace's `tests/data` (found from whichever package's
/// tests include this file).
pub fn suzanne() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .map(|dir| dir.join("tests/data/suzanne.obj"))
        .find(|path| path.exists())
        .expect("tests/data/suzanne.obj above the package")
}

/// `pelt bake` options of a small bake: hair combed down, few small layers, order-2 transfer.
pub const SMALL_BAKE: [&str; 8] = [
    "--comb",
    "0,0,-1",
    "--layers",
    "6",
    "--resolution",
    "32",
    "--order",
    "2",
];
