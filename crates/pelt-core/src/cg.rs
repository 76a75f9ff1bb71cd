//! Jacobi-preconditioned conjugate gradients for the symmetric positive (semi)definite systems of
//! the comb field and the patch parameterization.
//!
//! The operator is a closure, so each caller keeps its own sparse layout (a complex connection
//! Laplacian, a per-patch stiffness). Vector work runs in fused passes over fixed chunks: long
//! vectors spread the chunks over Pelt's pool, and the partial dot products of the chunks are
//! added in chunk order, so the result is bit-identical for any thread count.

use rayon::prelude::*;

/// Elements per chunk of the vector passes (fixed: it shapes the summation order).
const CHUNK: usize = 4096;
/// Vectors at least this long spread their chunks over the pool.
const PARALLEL_LEN: usize = 4 * CHUNK;

/// How a solve ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CgOutcome {
    /// Iterations run.
    pub iterations: usize,
    /// `|b - A x| / |b|` at the end (0 when `b` is zero).
    pub relative_residual: f64,
}

/// Runs `pass` on matching chunks of `outputs` (mutable) and returns the sums of the two
/// partial results it gives per chunk, added in chunk order.
fn fused<const M: usize>(
    outputs: [&mut [f64]; M],
    pass: impl Fn(usize, [&mut [f64]; M]) -> [f64; 2] + Sync,
) -> [f64; 2] {
    let n = outputs[0].len();
    let mut parts = outputs.map(|s| s.chunks_mut(CHUNK));
    let pieces: Vec<[&mut [f64]; M]> = (0..n.div_ceil(CHUNK))
        .map(|_| parts.each_mut().map(|p| p.next().unwrap_or_default()))
        .collect();
    let run = |(c, piece): (usize, [&mut [f64]; M])| pass(c * CHUNK, piece);
    let partial: Vec<[f64; 2]> = if n >= PARALLEL_LEN {
        pieces.into_par_iter().enumerate().map(run).collect()
    } else {
        pieces.into_iter().enumerate().map(run).collect()
    };
    partial.iter().fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]])
}

/// `a·b` in the same chunked order as [`fused`].
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let sum = |c: usize| -> f64 {
        let end = ((c + 1) * CHUNK).min(a.len());
        a[c * CHUNK..end]
            .iter()
            .zip(&b[c * CHUNK..end])
            .map(|(x, y)| x * y)
            .sum()
    };
    let chunks = a.len().div_ceil(CHUNK);
    let partial: Vec<f64> = if a.len() >= PARALLEL_LEN {
        (0..chunks).into_par_iter().map(sum).collect()
    } else {
        (0..chunks).map(sum).collect()
    };
    partial.iter().sum()
}

/// Solves `A x = b` starting from the `x` given, until `|r| <= tolerance |b|` or `max_iterations`.
///
/// `apply(x, y)` must write `y = A x` for a symmetric positive semidefinite `A`; `inv_diag` is
/// the inverse of its diagonal (0 where the diagonal is 0, which freezes that unknown). A
/// singular but consistent system (the Neumann Laplacian of a patch) converges to a solution;
/// its null-space part stays that of the start value.
pub(crate) fn solve(
    apply: impl Fn(&[f64], &mut [f64]),
    inv_diag: &[f64],
    b: &[f64],
    x: &mut [f64],
    tolerance: f64,
    max_iterations: usize,
) -> CgOutcome {
    let n = b.len();
    let b_norm = dot(b, b).sqrt();
    if b_norm == 0.0 {
        // A x = 0 is solved by any null-space vector; keep the start only where A vanishes.
        for (v, &d) in x.iter_mut().zip(inv_diag) {
            if d != 0.0 {
                *v = 0.0;
            }
        }
        return CgOutcome {
            iterations: 0,
            relative_residual: 0.0,
        };
    }
    let mut r = vec![0.0; n];
    apply(x, &mut r);
    let mut z = vec![0.0; n];
    let [mut rz, rr] = fused([&mut r, &mut z], |start, [r, z]| {
        let mut s = [0.0; 2];
        for i in 0..r.len() {
            r[i] = b[start + i] - r[i];
            z[i] = r[i] * inv_diag[start + i];
            s[0] += r[i] * z[i];
            s[1] += r[i] * r[i];
        }
        s
    });
    let mut residual = rr.sqrt();
    let mut p = z.clone();
    let mut q = vec![0.0; n];
    let mut iterations = 0;
    while iterations < max_iterations && residual > tolerance * b_norm {
        apply(&p, &mut q);
        let pq = dot(&p, &q);
        if pq.is_nan() || pq <= 0.0 || !rz.is_finite() {
            // The remaining residual lies in the null space (or rounding broke conjugacy).
            break;
        }
        let alpha = rz / pq;
        let (p_ref, q_ref) = (&p, &q);
        let [rz_next, rr] = fused([&mut *x, &mut r, &mut z], |start, [x, r, z]| {
            let mut s = [0.0; 2];
            for i in 0..r.len() {
                x[i] += alpha * p_ref[start + i];
                r[i] -= alpha * q_ref[start + i];
                z[i] = r[i] * inv_diag[start + i];
                s[0] += r[i] * z[i];
                s[1] += r[i] * r[i];
            }
            s
        });
        let beta = rz_next / rz;
        rz = rz_next;
        let z_ref = &z;
        fused([&mut p], |start, [p]| {
            for i in 0..p.len() {
                p[i] = z_ref[start + i] + beta * p[i];
            }
            [0.0; 2]
        });
        residual = rr.sqrt();
        iterations += 1;
    }
    CgOutcome {
        iterations,
        relative_residual: residual / b_norm,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 1D Laplacian with a diagonal shift: tridiagonal (-1, 2 + s, -1).
    fn shifted_path(n: usize, shift: f64) -> impl Fn(&[f64], &mut [f64]) {
        move |x: &[f64], y: &mut [f64]| {
            for i in 0..n {
                let left = if i > 0 { x[i - 1] } else { 0.0 };
                let right = if i + 1 < n { x[i + 1] } else { 0.0 };
                y[i] = (2.0 + shift) * x[i] - left - right;
            }
        }
    }

    /// Thomas algorithm: an independent direct solve of the same tridiagonal matrix.
    fn thomas(b: &[f64], shift: f64) -> Vec<f64> {
        let n = b.len();
        let (mut c, mut d) = (vec![0.0; n], vec![0.0; n]);
        for i in 0..n {
            let m = (2.0 + shift) + if i > 0 { c[i - 1] } else { 0.0 };
            c[i] = -1.0 / m;
            d[i] = (b[i] + if i > 0 { d[i - 1] } else { 0.0 }) / m;
        }
        let mut exact = vec![0.0; n];
        for i in (0..n).rev() {
            exact[i] = d[i] - c[i] * if i + 1 < n { exact[i + 1] } else { 0.0 };
        }
        exact
    }

    #[test]
    fn solves_tridiagonal_systems_against_the_thomas_algorithm() {
        // One short system (sequential passes) and one long enough for the parallel ones.
        for (n, shift) in [(50, 0.1), (3 * PARALLEL_LEN / 2, 0.5)] {
            let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
            let exact = thomas(&b, shift);
            let mut x = vec![0.0; n];
            let inv = vec![1.0 / (2.0 + shift); n];
            let outcome = solve(shifted_path(n, shift), &inv, &b, &mut x, 1e-12, 5000);
            assert!(outcome.relative_residual <= 1e-12, "{outcome:?}");
            for i in 0..n {
                assert!((x[i] - exact[i]).abs() < 1e-9, "{i}: {} vs {}", x[i], exact[i]);
            }
        }
    }

    #[test]
    fn the_result_does_not_depend_on_the_thread_count() {
        let n = 2 * PARALLEL_LEN + 123;
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.11).cos()).collect();
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut x = vec![0.0; n];
            let inv = vec![1.0 / 2.01; n];
            pool.install(|| solve(shifted_path(n, 0.01), &inv, &b, &mut x, 1e-10, 300));
            x.iter().map(|v| v.to_bits()).collect::<Vec<u64>>()
        };
        assert_eq!(run(1), run(2));
    }

    #[test]
    fn zero_right_hand_side_gives_zero_and_keeps_frozen_unknowns() {
        let mut x = vec![3.0, 4.0];
        let outcome = solve(
            |x, y| y.copy_from_slice(x),
            &[1.0, 0.0],
            &[0.0, 0.0],
            &mut x,
            1e-9,
            10,
        );
        assert_eq!(outcome.iterations, 0);
        assert_eq!(x, vec![0.0, 4.0]);
    }
}
