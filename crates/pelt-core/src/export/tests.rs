//! Tests of the export module: every writer's output is read back by an independent decoder
//! (the `png` crate's decoder, the `exr` crate, the `ktx2` crate), and the mipmaps and atlas are
//! checked against references computed here from their definitions.

mod atlas;
mod exr;
mod fixture;
mod glb_reader;
mod gltf;
mod image;
mod ktx2;
mod mip;
mod png;
mod rig;
mod texture_set;

use crate::error::PeltError;
use crate::rng::Rng;

/// Runs `work` in a fresh pool of `threads` threads, so results can be compared across counts.
fn with_threads<T: Send>(threads: usize, work: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(work)
}

/// `n` pseudo-random bytes from `seed`.
fn random_bytes(seed: u64, n: usize) -> Vec<u8> {
    let mut rng = Rng::new(seed);
    (0..n).map(|_| rng.next_u64() as u8).collect()
}

/// `n` pseudo-random floats in `[lo, hi)`.
fn random_floats(seed: u64, n: usize, lo: f64, hi: f64) -> Vec<f64> {
    let mut rng = Rng::new(seed);
    (0..n).map(|_| lo + (hi - lo) * rng.next_f64()).collect()
}

/// The parameter name of an `InvalidParameter` error; panics (failing the test) otherwise.
fn parameter_name<T: std::fmt::Debug>(result: crate::error::Result<T>) -> String {
    match result {
        Err(PeltError::InvalidParameter { name, .. }) => name,
        other => panic!("expected InvalidParameter, got {other:?}"),
    }
}

/// A fresh, empty folder under the system temporary folder for one test.
fn temp_dir(test: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("pelt-export-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
