//! Pelt's own thread pool.
//!
//! Pelt runs inside Blender's process, so it never takes over rayon's global pool: heavy work runs
//! in [`pool`], whose size is `PELT_THREADS` when set (a positive integer) and the number of cores
//! otherwise, until [`set_thread_count`] (the add-on's preference) replaces it. Results never
//! depend on the thread count (see [`deterministic_sum`]).

use std::sync::{Arc, RwLock};

use rayon::prelude::*;

use crate::error::{PeltError, Result};

/// Environment variable that sets the number of worker threads.
pub const THREADS_ENV: &str = "PELT_THREADS";

/// Most worker threads: more only costs memory and start-up time (a pool of 100,000 threads
/// takes minutes to build), and no machine Pelt runs on has that many cores.
pub const MAX_THREADS: usize = 1024;

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
        // Inside Blender there is no one to return the error to: say it and use every core.
        let threads = threads_from_env().unwrap_or_else(|e| {
            eprintln!("pelt: {e}; using one thread per core");
            0
        });
        // A process that cannot start even one thread, after `build`'s retries, cannot run Pelt.
        let pool = build(threads).or_else(|_| build(1));
        Arc::new(pool.expect("a one-thread pool can be built"))
    })
    .clone()
}

/// The thread count `PELT_THREADS` asks for (0, one per core, when it is unset or empty).
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `PELT_THREADS` when it is not an integer in
/// `[1, MAX_THREADS]`.
pub fn threads_from_env() -> Result<usize> {
    let Some(value) = std::env::var_os(THREADS_ENV) else {
        return Ok(0);
    };
    let text = value.to_string_lossy();
    if text.trim().is_empty() {
        return Ok(0);
    }
    text.trim()
        .parse::<usize>()
        .ok()
        .filter(|n| (1..=MAX_THREADS).contains(n))
        .ok_or_else(|| {
            PeltError::parameter(
                THREADS_ENV,
                format!("must be an integer in [1, {MAX_THREADS}], got {text:?}"),
            )
        })
}

/// Replaces the pool by one of `threads` workers (0: one per core); later stages use it.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `threads` above [`MAX_THREADS`], or when the system
/// will not start that many threads (the pool in use stays).
pub fn set_thread_count(threads: usize) -> Result<()> {
    if threads > MAX_THREADS {
        return Err(thread_count_out_of_range(threads));
    }
    replace_pool(threads, build)
}

type Built = std::result::Result<rayon::ThreadPool, rayon::ThreadPoolBuildError>;

/// Puts `build(threads)` in place of the pool, or names the system's refusal and keeps it.
fn replace_pool(threads: usize, build: impl Fn(usize) -> Built) -> Result<()> {
    let pool = build(threads).map_err(|e| {
        PeltError::parameter(
            "threads",
            format!("the system would not start {threads} threads ({e}); the pool in use stays"),
        )
    })?;
    *POOL.write().unwrap_or_else(|e| e.into_inner()) = Some(Arc::new(pool));
    Ok(())
}

/// The error for a `threads` argument of `got` (any integer type the caller took it as).
pub fn thread_count_out_of_range(got: impl std::fmt::Display) -> PeltError {
    PeltError::parameter(
        "threads",
        format!("must be in [0, {MAX_THREADS}] (0: one per core), got {got}"),
    )
}

/// Tries to start a pool this many times: a refused thread (`EAGAIN`) is often one that the pool
/// just replaced still holds while it winds down.
const BUILD_ATTEMPTS: u32 = 5;

fn build(threads: usize) -> Built {
    let mut attempt = 0;
    loop {
        let built = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("pelt-{i}"))
            .build();
        attempt += 1;
        if built.is_ok() || attempt == BUILD_ATTEMPTS {
            return built;
        }
        std::thread::sleep(std::time::Duration::from_millis(10 << attempt));
    }
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
    fn threads_the_system_refuses_are_a_named_error_and_the_pool_stays() {
        // As when a replaced pool's threads still wind down (the Python fuzz met `EAGAIN` so).
        let refused = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .spawn_handler(|_| Err(std::io::Error::from(std::io::ErrorKind::WouldBlock)))
                .build()
        };
        let kept = pool();
        let error = replace_pool(3, refused).unwrap_err().to_string();
        assert!(
            error.contains("`threads`")
                && error.contains("3 threads")
                && error.contains("the pool in use stays"),
            "{error}"
        );
        assert!(kept.install(|| (0..100).into_par_iter().sum::<i32>()) == 4950);
        assert!(thread_count() >= 1);
    }

    #[test]
    fn thread_counts_are_capped_with_a_named_error() {
        let error = set_thread_count(100_000).unwrap_err().to_string();
        assert!(
            error.contains("`threads`") && error.contains("[0, 1024]") && error.contains("100000"),
            "{error}"
        );
    }

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
