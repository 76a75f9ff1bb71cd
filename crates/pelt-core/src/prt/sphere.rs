//! Direction sets and quadrature rules on the unit sphere.
//!
//! The PRT bake of §2.3 of the PRT shell-fur paper projects transfer functions onto the SH basis by
//! summing over sample rays; this module supplies those rays with their quadrature weights:
//! spherical Fibonacci points (near-uniform, equal weights), a jittered equal-area stratified set,
//! and a product Gauss–Legendre × uniform-azimuth rule that integrates polynomials exactly (used to
//! check the SH code and wherever an exact projection of a band-limited function is needed).

use std::f64::consts::PI;

use crate::rng::Rng;

/// Number of bake directions used when the caller does not choose one.
pub const DEFAULT_DIRECTIONS: usize = 256;

/// Golden angle π(3 − √5): successive Fibonacci points turn by it, which spreads them evenly in
/// azimuth without any two rows lining up.
const GOLDEN_ANGLE: f64 = 2.399_963_229_728_653;

/// `n` spherical Fibonacci directions, near-uniform over the sphere, each standing for the solid
/// angle [`fibonacci_weight`]`(n)`.
///
/// Point `i` sits at `z = 1 − (2i + 1)/n` (equal-area bands in `z`) and azimuth `i·` golden angle.
/// The set is deterministic; `n = 0` gives an empty set.
pub fn fibonacci_directions(n: usize) -> Vec<[f64; 3]> {
    (0..n)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let r = (1.0 - z * z).max(0.0).sqrt();
            // Reduce the angle before taking sin/cos so large `i` keeps full precision.
            let phi = (i as f64 * GOLDEN_ANGLE) % (2.0 * PI);
            [r * phi.cos(), r * phi.sin(), z]
        })
        .collect()
}

/// The quadrature weight of each of `n` equal-weight directions: `4π / n` (0 for `n = 0`).
pub fn fibonacci_weight(n: usize) -> f64 {
    if n == 0 { 0.0 } else { 4.0 * PI / n as f64 }
}

/// `4·⌈n/4⌉` directions with the mirror symmetries of a square tile: the spherical Fibonacci
/// points of [`fibonacci_directions`]`(⌈n/4⌉)`, each followed by its mirror images `(−x, y, z)`,
/// `(x, −y, z)` and `(−x, −y, z)`. Each stands for `4π / count`; every height band of the base set
/// holds four points, so the set keeps Fibonacci's equal-area stratification in `z` (exactly half
/// the points lie above the horizon).
///
/// A bake over this set commutes with mirroring the tile in x or y: a pelt symmetric under
/// `x → −x` lit from `+x` and from `−x` gives mirrored results to rounding, where the plain
/// Fibonacci set (not symmetric) leaves a few percent of quadrature difference between the two
/// sides — the one-sided brightness the PRT shell-fur paper reports in §2.4. The price is a less
/// even spread in azimuth: on sharp lobes about 1.2× the quadrature error of
/// [`fibonacci_directions`]`(n)` at 256 directions, 1.6× at 1024.
pub fn mirrored_fibonacci_directions(n: usize) -> Vec<[f64; 3]> {
    fibonacci_directions(n.div_ceil(4))
        .into_iter()
        .flat_map(|[x, y, z]| [[x, y, z], [-x, y, z], [x, -y, z], [-x, -y, z]])
        .collect()
}

/// `rows × cols` directions, one drawn uniformly inside each cell of an equal-area grid (uniform in
/// `z = cos θ` and in azimuth), so each stands for `4π / (rows·cols)` of solid angle.
///
/// Stratification keeps the variance of Monte Carlo bakes low while avoiding the aliasing of a
/// regular grid. The jitter comes from a fixed hash of `seed` and the cell, so the set is
/// deterministic. Rows run from +Z downwards, cells within a row by increasing azimuth.
pub fn stratified_directions(rows: usize, cols: usize, seed: u64) -> Vec<[f64; 3]> {
    let mut rng = Rng::new(seed);
    let mut out = Vec::with_capacity(rows * cols);
    for r in 0..rows {
        for c in 0..cols {
            let u = rng.next_f64();
            let v = rng.next_f64();
            let z = 1.0 - 2.0 * (r as f64 + u) / rows as f64;
            let phi = 2.0 * PI * (c as f64 + v) / cols as f64;
            let s = (1.0 - z * z).max(0.0).sqrt();
            out.push([s * phi.cos(), s * phi.sin(), z]);
        }
    }
    out
}

/// Gauss–Legendre nodes and weights on `[-1, 1]` with `n` points, exact for polynomials of degree
/// `2n − 1`. Nodes are in increasing order; `n = 0` gives empty vectors.
///
/// Nodes are found by Newton's method on `P_n` from the Tricomi initial guess, which converges to
/// machine precision in a few steps for every `n`.
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = vec![0.0; n];
    let mut weights = vec![0.0; n];
    let nf = n as f64;
    for i in 0..n.div_ceil(2) {
        // Tricomi's approximation of the i-th largest root.
        let mut x = (PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
        for _ in 0..100 {
            let (p, dp) = legendre_and_derivative(n, x);
            let step = p / dp;
            x -= step;
            if step.abs() <= 1e-16 * x.abs().max(1.0) {
                break;
            }
        }
        let (_, derivative) = legendre_and_derivative(n, x);
        let w = 2.0 / ((1.0 - x * x) * derivative * derivative);
        nodes[n - 1 - i] = x;
        nodes[i] = -x;
        weights[n - 1 - i] = w;
        weights[i] = w;
    }
    (nodes, weights)
}

/// `P_n(x)` and `P_n'(x)` by the three-term recurrence.
fn legendre_and_derivative(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, dp)
}

/// Product quadrature on the sphere: Gauss–Legendre in `z = cos θ` (`n_z` nodes) times `n_phi`
/// uniform azimuths. Returns directions and their solid-angle weights (summing to 4π).
///
/// It integrates every polynomial in `(x, y, z)` of degree `d` exactly when `n_z ≥ (d + 1)/2` and
/// `n_phi ≥ d + 1`, so SH products up to order 8 (degree 14) need `n_z ≥ 8`, `n_phi ≥ 15`.
pub fn gauss_product_rule(n_z: usize, n_phi: usize) -> (Vec<[f64; 3]>, Vec<f64>) {
    let (zs, wz) = gauss_legendre(n_z);
    let dphi = 2.0 * PI / n_phi.max(1) as f64;
    let mut dirs = Vec::with_capacity(n_z * n_phi);
    let mut weights = Vec::with_capacity(n_z * n_phi);
    for (&z, &w) in zs.iter().zip(&wz) {
        let s = (1.0 - z * z).max(0.0).sqrt();
        for j in 0..n_phi {
            let phi = (j as f64 + 0.5) * dphi;
            dirs.push([s * phi.cos(), s * phi.sin(), z]);
            weights.push(w * dphi);
        }
    }
    (dirs, weights)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;

    #[test]
    fn gauss_legendre_integrates_monomials_exactly() {
        for n in [1, 2, 5, 8, 16, 40] {
            let (x, w) = gauss_legendre(n);
            for k in 0..2 * n {
                let numeric: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(k as i32)).sum();
                // ∫_{-1}^{1} x^k dx = 2/(k+1) for even k, 0 for odd k.
                let exact = if k % 2 == 0 { 2.0 / (k as f64 + 1.0) } else { 0.0 };
                assert!(
                    (numeric - exact).abs() < 1e-13,
                    "n={n} k={k}: {numeric} vs {exact}"
                );
            }
            assert!(
                x.windows(2).all(|p| p[0] < p[1]),
                "nodes not increasing for n={n}"
            );
        }
    }

    #[test]
    fn fibonacci_points_are_unit_and_balanced() {
        let n = DEFAULT_DIRECTIONS;
        let dirs = fibonacci_directions(n);
        assert_eq!(dirs.len(), n);
        assert!(
            dirs.iter()
                .all(|&d| (DVec3::from(d).length() - 1.0).abs() < 1e-14)
        );
        // Equal weights integrate z² over the sphere (4π/3) to within the rule's O(1/n²) error.
        let w = fibonacci_weight(n);
        let mean: [f64; 3] = [0, 1, 2].map(|k| dirs.iter().map(|d| d[k]).sum::<f64>() / n as f64);
        assert!(mean.iter().all(|m| m.abs() < 0.01), "centroid {mean:?}");
        let z2: f64 = dirs.iter().map(|d| w * d[2] * d[2]).sum();
        assert!((z2 - 4.0 * PI / 3.0).abs() < 1e-3, "{z2}");
        assert!(fibonacci_directions(0).is_empty());
    }

    #[test]
    fn mirrored_points_are_closed_under_the_tile_mirrors() {
        let dirs = mirrored_fibonacci_directions(DEFAULT_DIRECTIONS);
        assert_eq!(dirs.len(), DEFAULT_DIRECTIONS);
        assert_eq!(mirrored_fibonacci_directions(13).len(), 16);
        assert_eq!(dirs.iter().filter(|d| d[2] > 0.0).count(), DEFAULT_DIRECTIONS / 2);
        for d in &dirs {
            assert!((DVec3::from(*d).length() - 1.0).abs() < 1e-14);
            for m in [[-d[0], d[1], d[2]], [d[0], -d[1], d[2]]] {
                assert!(dirs.contains(&m), "{d:?} has no mirror image");
            }
        }
        // Equal weights still integrate z² over the sphere (4π/3) closely.
        let w = 4.0 * PI / dirs.len() as f64;
        let z2: f64 = dirs.iter().map(|d| w * d[2] * d[2]).sum();
        assert!((z2 - 4.0 * PI / 3.0).abs() < 2e-3, "{z2}");
    }

    #[test]
    fn stratified_points_fill_their_cells_deterministically() {
        let (rows, cols) = (8, 16);
        let dirs = stratified_directions(rows, cols, 7);
        assert_eq!(dirs, stratified_directions(rows, cols, 7));
        assert_ne!(dirs, stratified_directions(rows, cols, 8));
        for (i, d) in dirs.iter().enumerate() {
            assert!((DVec3::from(*d).length() - 1.0).abs() < 1e-14);
            let (r, c) = (i / cols, i % cols);
            let z_top = 1.0 - 2.0 * r as f64 / rows as f64;
            let z_bottom = 1.0 - 2.0 * (r + 1) as f64 / rows as f64;
            assert!(d[2] <= z_top && d[2] >= z_bottom, "point {i} outside its row");
            let phi = d[1].atan2(d[0]).rem_euclid(2.0 * PI);
            let cell = (phi / (2.0 * PI) * cols as f64).floor() as usize;
            assert_eq!(cell.min(cols - 1), c, "point {i} outside its column");
        }
    }

    #[test]
    fn product_rule_integrates_polynomials_exactly() {
        let (dirs, w) = gauss_product_rule(8, 15);
        // ∫ x^2 y^4 z^8 dω = 2 Γ(3/2)Γ(5/2)Γ(9/2) / Γ(17/2) (closed form of monomial integrals).
        let gamma_half = |k: u32| -> f64 {
            // Γ(k + 1/2) = (2k−1)!! √π / 2^k
            let mut v = PI.sqrt();
            for j in 1..=k {
                v *= (2 * j - 1) as f64 / 2.0;
            }
            v
        };
        let exact = 2.0 * gamma_half(1) * gamma_half(2) * gamma_half(4) / gamma_half(8);
        let numeric: f64 = dirs
            .iter()
            .zip(&w)
            .map(|(d, w)| w * d[0].powi(2) * d[1].powi(4) * d[2].powi(8))
            .sum();
        assert!((numeric - exact).abs() < 1e-15, "{numeric} vs {exact}");
        assert!((w.iter().sum::<f64>() - 4.0 * PI).abs() < 1e-13);
    }
}
