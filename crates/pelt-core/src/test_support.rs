//! Helpers the unit tests of several modules share (built for tests only).

use crate::error::PeltError;
use crate::rng::Rng;

/// Runs `work` in a fresh pool of `threads` threads, so results can be compared across counts.
pub(crate) fn with_threads<T: Send>(threads: usize, work: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(work)
}

/// `n` pseudo-random bytes from `seed`.
pub(crate) fn random_bytes(seed: u64, n: usize) -> Vec<u8> {
    let mut rng = Rng::new(seed);
    (0..n).map(|_| rng.next_u64() as u8).collect()
}

/// `n` pseudo-random floats in `[lo, hi)`.
pub(crate) fn random_floats(seed: u64, n: usize, lo: f64, hi: f64) -> Vec<f64> {
    let mut rng = Rng::new(seed);
    (0..n).map(|_| lo + (hi - lo) * rng.next_f64()).collect()
}

/// The parameter name of an `InvalidParameter` error; panics (failing the test) otherwise.
pub(crate) fn parameter_name<T: std::fmt::Debug>(result: crate::error::Result<T>) -> String {
    match result {
        Err(PeltError::InvalidParameter { name, .. }) => name,
        other => panic!("expected InvalidParameter, got {other:?}"),
    }
}
