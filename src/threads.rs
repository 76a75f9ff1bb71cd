//! Pelt's own thread pool.
//!
//! Pelt runs inside Blender's process, so it never takes over rayon's global pool: heavy work runs
//! in [`pool`], whose size is `PELT_THREADS` when set (a positive integer) and the number of cores
//! otherwise, until [`set_thread_count`] (the add-on's preference) replaces it. Results never
//! depend on the thread count (see [`deterministic_sum`]).

use std::sync::{Arc, RwLock};

use rayon::prelude::*;

/// Environment variable that sets the number of worker threads.
pub const THREADS_ENV: &str = "PELT_THREADS";

/// Rows per chunk in [`deterministic_sum`]; fixed so that the summation tree never changes.
const SUM_CHUNK: usize = 4096;

static POOL: RwLock<Option<Arc<rayon::ThreadPool>>> = RwLock::new(None);

/// The pool all parallel stages run in (built on first use). A stage holds its own handle, so
/// [`set_thread_count`] never disturbs work in flight.
pub fn pool() -> Arc<rayon::ThreadPool> {
    if let Some(pool) = POOL.read().unwrap_or_else(|e| e.into_inner()).as_ref() {
        return pool.clone();
    }
    let mut slot = POOL.write().unwrap_or_else(|e| e.into_inner());
    slot.get_or_insert_with(|| {
        let threads = std::env::var(THREADS_ENV)
            .ok()
            .and_then(|v| v.trim().parse::<usize>().ok())
            .filter(|&n| n > 0)
            .unwrap_or(0);
        Arc::new(build(threads))
    })
    .clone()
}

/// Replaces the pool by one of `threads` workers (0: one per core); later stages use it.
pub fn set_thread_count(threads: usize) {
    let pool = Arc::new(build(threads));
    *POOL.write().unwrap_or_else(|e| e.into_inner()) = Some(pool);
}

fn build(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|i| format!("pelt-{i}"))
        .build()
        .or_else(|_| rayon::ThreadPoolBuilder::new().num_threads(1).build())
        .expect("a one-thread pool can always be built")
}

/// Number of threads in [`pool`].
pub fn thread_count() -> usize {
    pool().current_num_threads()
}

/// Sums `f(i)` for `i in 0..n` in f64 over fixed-size chunks, so the result is bit-identical
/// whatever the number of threads (rayon's own `sum` splits work adaptively).
pub fn deterministic_sum(n: usize, f: impl Fn(usize) -> f64 + Sync) -> f64 {
    let chunks = n.div_ceil(SUM_CHUNK);
    let partial: Vec<f64> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let end = ((c + 1) * SUM_CHUNK).min(n);
            (c * SUM_CHUNK..end).map(&f).sum()
        })
        .collect();
    partial.iter().sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deterministic_sum_matches_sequential_order_of_chunks() {
        let f = |i: usize| 1.0 / (i as f64 + 1.0);
        let n: usize = 10_000;
        let expected: f64 = (0..n.div_ceil(SUM_CHUNK))
            .map(|c| (c * SUM_CHUNK..((c + 1) * SUM_CHUNK).min(n)).map(f).sum::<f64>())
            .sum();
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let three = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
        let a = one.install(|| deterministic_sum(n, f));
        let b = three.install(|| deterministic_sum(n, f));
        assert_eq!(a.to_bits(), expected.to_bits());
        assert_eq!(b.to_bits(), expected.to_bits());
    }
}
