//! Tests of the SH basis against independent computations: exact quadrature, closed-form
//! polynomials, analytic rotations about +Z, and direct integration over caps.

use std::f64::consts::PI;

use glam::{DMat3, DQuat, DVec3};

use super::sh::*;
use super::sphere::{fibonacci_directions, gauss_legendre, gauss_product_rule};
use crate::error::PeltError;

/// Deterministic pseudo-random numbers in [-1, 1) for test data.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// A random rotation matrix from a random unit quaternion.
fn random_rotation(rng: &mut Rng) -> DMat3 {
    let [w, x, y, z] = [rng.next(), rng.next(), rng.next(), rng.next()];
    DMat3::from_quat(DQuat::from_xyzw(x, y, z, w).normalize())
}

/// `m` as the rows the SH rotation takes.
fn rows(m: DMat3) -> [[f64; 3]; 3] {
    m.transpose().to_cols_array_2d()
}

/// `m · d` for a direction as the SH functions take it.
fn mul(m: DMat3, d: [f64; 3]) -> [f64; 3] {
    (m * DVec3::from(d)).to_array()
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max)
}

fn unit(d: [f64; 3]) -> [f64; 3] {
    DVec3::from(d).normalize().to_array()
}

fn is_parameter_error(e: PeltError, name: &str) -> bool {
    matches!(e, PeltError::InvalidParameter { name: n, .. } if n == name)
}

#[test]
fn index_and_band_of_are_inverse() {
    let mut i = 0;
    for l in 0..MAX_ORDER {
        for m in -(l as isize)..=l as isize {
            assert_eq!(index(l, m), i);
            assert_eq!(band_of(i), (l, m));
            i += 1;
        }
    }
    assert_eq!(i, MAX_COEFFS);
    assert_eq!(coeff_count(PAPER_ORDER), 25);
}

#[test]
fn bad_input_is_rejected_with_the_parameter_name() {
    assert!(is_parameter_error(
        eval_vec(0, [0.0, 0.0, 1.0]).unwrap_err(),
        "order"
    ));
    assert!(is_parameter_error(
        eval_vec(9, [0.0, 0.0, 1.0]).unwrap_err(),
        "order"
    ));
    assert!(is_parameter_error(
        eval_vec(3, [f64::NAN, 0.0, 1.0]).unwrap_err(),
        "direction"
    ));
    assert!(is_parameter_error(
        eval_vec(3, [0.0, 0.0, 1.1]).unwrap_err(),
        "direction"
    ));
    let mut short = [0.0; 8];
    assert!(is_parameter_error(
        eval(3, [0.0, 0.0, 1.0], &mut short).unwrap_err(),
        "out"
    ));
    assert!(is_parameter_error(
        project_equirect(3, 4, 2, &[0.0; 23]).unwrap_err(),
        "image"
    ));
    assert!(is_parameter_error(
        project_equirect(3, 0, 2, &[]).unwrap_err(),
        "image"
    ));
    let mut nan_image = vec![0.0f32; 4 * 2 * 3];
    nan_image[7] = f32::NAN;
    assert!(is_parameter_error(
        project_equirect(3, 4, 2, &nan_image).unwrap_err(),
        "image"
    ));
    assert!(is_parameter_error(cap_zonal(3, -0.1).unwrap_err(), "half_angle"));
    assert!(is_parameter_error(
        cap_zonal(3, f64::NAN).unwrap_err(),
        "half_angle"
    ));
    assert!(is_parameter_error(
        rotate(&[0.0; 5], rows(DMat3::IDENTITY)).unwrap_err(),
        "coefficients"
    ));
    let mirror = [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    assert!(is_parameter_error(
        ShRotation::new(3, mirror).unwrap_err(),
        "rotation"
    ));
    let sheared = [[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    assert!(is_parameter_error(
        ShRotation::new(3, sheared).unwrap_err(),
        "rotation"
    ));
    let e = project_samples(2, &[[0.0, 0.0, 1.0]], &[1.0, 2.0], &[1.0]).unwrap_err();
    assert!(is_parameter_error(e, "weights"));
}

/// Gram matrix by a product Gauss–Legendre × uniform-azimuth rule exact for degree 14 and beyond.
#[test]
fn basis_is_orthonormal_up_to_order_8() {
    // 80 × 128 = 10240 directions; exactness needs only 8 × 15.
    let (dirs, weights) = gauss_product_rule(80, 128);
    assert!(dirs.len() >= 10_000);
    let mut gram = vec![0.0; MAX_COEFFS * MAX_COEFFS];
    for (d, w) in dirs.iter().zip(&weights) {
        let y = eval_vec(MAX_ORDER, *d).unwrap();
        for i in 0..MAX_COEFFS {
            for j in 0..MAX_COEFFS {
                gram[i * MAX_COEFFS + j] += w * y[i] * y[j];
            }
        }
    }
    let mut worst: f64 = 0.0;
    for i in 0..MAX_COEFFS {
        for j in 0..MAX_COEFFS {
            let expected = if i == j { 1.0 } else { 0.0 };
            worst = worst.max((gram[i * MAX_COEFFS + j] - expected).abs());
        }
    }
    eprintln!("orthonormality: max |G − I| = {worst:e}");
    assert!(worst < 1e-12, "max |G − I| = {worst:e}");
}

/// Sloan's closed-form polynomials in (x, y, z), without Condon–Shortley phase.
fn closed_form(d: [f64; 3]) -> [f64; 16] {
    let [x, y, z] = d;
    let k = |num: f64| (num / PI).sqrt();
    [
        k(1.0 / 4.0),
        k(3.0 / 4.0) * y,
        k(3.0 / 4.0) * z,
        k(3.0 / 4.0) * x,
        k(15.0 / 4.0) * x * y,
        k(15.0 / 4.0) * y * z,
        k(5.0 / 16.0) * (3.0 * z * z - 1.0),
        k(15.0 / 4.0) * x * z,
        k(15.0 / 16.0) * (x * x - y * y),
        k(35.0 / 32.0) * y * (3.0 * x * x - y * y),
        k(105.0 / 4.0) * x * y * z,
        k(21.0 / 32.0) * y * (5.0 * z * z - 1.0),
        k(7.0 / 16.0) * z * (5.0 * z * z - 3.0),
        k(21.0 / 32.0) * x * (5.0 * z * z - 1.0),
        k(105.0 / 16.0) * z * (x * x - y * y),
        k(35.0 / 32.0) * x * (x * x - 3.0 * y * y),
    ]
}

#[test]
fn low_bands_match_closed_form_polynomials() {
    let mut rng = Rng(1);
    let mut dirs = vec![
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        unit([1.0, 2.0, 3.0]),
        unit([-0.3, 0.5, -0.8]),
    ];
    dirs.extend((0..20).map(|_| unit([rng.next(), rng.next(), rng.next()])));
    let mut worst: f64 = 0.0;
    for d in dirs {
        let y = eval_vec(4, d).unwrap();
        worst = worst.max(max_abs_diff(&y, &closed_form(d)));
        // The f32 variant is the same values rounded once.
        let mut y32 = [0.0f32; 16];
        eval_f32(4, d.map(|v| v as f32), &mut y32).unwrap();
        for (a, b) in y32.iter().zip(&y) {
            assert!((f64::from(*a) - b).abs() < 1e-6);
        }
    }
    eprintln!("closed form l ≤ 3: max error {worst:e}");
    assert!(worst < 1e-12, "max error {worst:e}");
}

fn random_coeffs(rng: &mut Rng, order: usize) -> Vec<f64> {
    (0..coeff_count(order)).map(|_| rng.next()).collect()
}

#[test]
fn rotation_matches_reprojection_of_the_rotated_function() {
    let mut rng = Rng(42);
    let (dirs, weights) = gauss_product_rule(16, 32);
    let check_dirs = fibonacci_directions(500);
    let mut worst_proj: f64 = 0.0;
    let mut worst_eval: f64 = 0.0;
    for _ in 0..5 {
        let coeffs = random_coeffs(&mut rng, MAX_ORDER);
        let r = random_rotation(&mut rng);
        let rotated = rotate(&coeffs, rows(r)).unwrap();
        // g(ω) = f(Rᵀω), projected by a rule exact for the band-limited product.
        let values: Vec<f64> = dirs
            .iter()
            .map(|&d| reconstruct(&coeffs, mul(r.transpose(), d)).unwrap())
            .collect();
        let reprojected = project_samples(MAX_ORDER, &dirs, &weights, &values).unwrap();
        worst_proj = worst_proj.max(max_abs_diff(&rotated, &reprojected));
        for &d in &check_dirs {
            let g = reconstruct(&coeffs, mul(r.transpose(), d)).unwrap();
            worst_eval = worst_eval.max((reconstruct(&rotated, d).unwrap() - g).abs());
        }
    }
    eprintln!("rotation vs reprojection {worst_proj:e}, vs evaluation {worst_eval:e}");
    assert!(
        worst_proj < 1e-10 && worst_eval < 1e-10,
        "{worst_proj:e} {worst_eval:e}"
    );
}

#[test]
fn rotation_moves_a_lobe_to_the_rotated_direction_and_composes() {
    let mut rng = Rng(7);
    let d = unit([0.2, -0.5, 0.7]);
    let a = random_rotation(&mut rng);
    let b = random_rotation(&mut rng);
    let lobe = project_cap(6, d, 0.3).unwrap();
    let moved = rotate(&lobe, rows(a)).unwrap();
    assert!(max_abs_diff(&moved, &project_cap(6, mul(a, d), 0.3).unwrap()) < 1e-12);
    let coeffs = random_coeffs(&mut rng, MAX_ORDER);
    let composed = rotate(&coeffs, rows(a * b)).unwrap();
    let stepwise = rotate(&rotate(&coeffs, rows(b)).unwrap(), rows(a)).unwrap();
    assert!(max_abs_diff(&composed, &stepwise) < 1e-12);
}

#[test]
fn rotation_then_inverse_returns_the_input() {
    let mut rng = Rng(3);
    let mut worst: f64 = 0.0;
    for order in 1..=MAX_ORDER {
        let coeffs = random_coeffs(&mut rng, order);
        let r = random_rotation(&mut rng);
        let back = rotate(&rotate(&coeffs, rows(r)).unwrap(), rows(r.transpose())).unwrap();
        worst = worst.max(max_abs_diff(&back, &coeffs));
    }
    eprintln!("R then R⁻¹: max error {worst:e}");
    assert!(worst < 1e-12, "{worst:e}");
}

#[test]
fn rotation_about_z_mixes_each_m_pair_analytically() {
    let mut rng = Rng(5);
    let coeffs = random_coeffs(&mut rng, MAX_ORDER);
    for beta in [0.3, 1.0, -2.5, PI] {
        let (s, c) = f64::sin_cos(beta);
        let rz = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
        let rotated = rotate(&coeffs, rz).unwrap();
        // g(φ) = f(φ − β): a·cos(mφ) + b·sin(mφ) becomes
        // (a cos mβ − b sin mβ) cos(mφ) + (a sin mβ + b cos mβ) sin(mφ).
        let mut expected = coeffs.clone();
        for l in 0..MAX_ORDER {
            for m in 1..=l as isize {
                let (sm, cm) = (m as f64 * beta).sin_cos();
                let (a, b) = (coeffs[index(l, m)], coeffs[index(l, -m)]);
                expected[index(l, m)] = a * cm - b * sm;
                expected[index(l, -m)] = a * sm + b * cm;
            }
        }
        let err = max_abs_diff(&rotated, &expected);
        assert!(err < 1e-12, "β = {beta}: {err:e}");
    }
}

#[test]
fn equirect_projection_of_a_constant_image_is_pure_dc() {
    for (w, h) in [(512, 256), (7, 3), (1, 1)] {
        let color = [0.25f32, 1.0, 3.5];
        let image: Vec<f32> = (0..w * h).flat_map(|_| color).collect();
        let coeffs = project_equirect(MAX_ORDER, w, h, &image).unwrap();
        for ch in 0..3 {
            // ∫ c·Y_0^0 dω = c·4π/√(4π) = c·√(4π).
            let dc = f64::from(color[ch]) * (4.0 * PI).sqrt();
            assert!(
                (coeffs[0][ch] - dc).abs() < 1e-12 * dc,
                "{w}×{h}: DC {}",
                coeffs[0][ch]
            );
            let leak = coeffs[1..].iter().map(|c| c[ch].abs()).fold(0.0, f64::max);
            assert!(leak < 1e-12 * dc, "{w}×{h}: leakage {leak:e}");
        }
    }
}

/// Fraction of an equirect pixel's solid angle inside the cap, by 32 × 32 equal-area sub-cells
/// for pixels near the cap's edge (pixels far from it are wholly in or out).
fn cap_coverage(w: usize, h: usize, row: usize, col: usize, d: [f64; 3], alpha: f64) -> f64 {
    const SUB: usize = 32;
    let (t0, t1) = (row as f64 * PI / h as f64, (row + 1) as f64 * PI / h as f64);
    let (z0, z1) = (t0.cos(), t1.cos());
    let centre = |zf: f64, pf: f64| {
        let z = z0 + (z1 - z0) * zf;
        let s = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI * (col as f64 + pf) / w as f64;
        (s * phi.cos() * d[0] + s * phi.sin() * d[1] + z * d[2])
            .clamp(-1.0, 1.0)
            .acos()
    };
    // Every point of the pixel lies within its half-diagonal (< one row height + one column
    // width in angle) of its centre.
    let reach = (t1 - t0) + 2.0 * PI / w as f64;
    let distance = centre(0.5, 0.5);
    if distance + reach < alpha {
        return 1.0;
    }
    if distance - reach > alpha {
        return 0.0;
    }
    let mut inside = 0;
    for i in 0..SUB {
        for j in 0..SUB {
            if centre((i as f64 + 0.5) / SUB as f64, (j as f64 + 0.5) / SUB as f64) <= alpha {
                inside += 1;
            }
        }
    }
    inside as f64 / (SUB * SUB) as f64
}

/// Draws a unit-power cap into a `w × h` image (red at full, green at half strength) and projects it.
fn drawn_cap(w: usize, h: usize, order: usize, d: [f64; 3], alpha: f64) -> Vec<[f64; 3]> {
    let power = 1.0 / (2.0 * PI * (1.0 - alpha.cos()));
    let mut image = vec![0.0f32; w * h * 3];
    for row in 0..h {
        for col in 0..w {
            let v = (cap_coverage(w, h, row, col, d, alpha) * power) as f32;
            image[(row * w + col) * 3..][..3].copy_from_slice(&[v, 0.5 * v, 0.0]);
        }
    }
    project_equirect(order, w, h, &image).unwrap()
}

#[test]
fn equirect_projection_of_a_drawn_cap_matches_the_analytic_cap() {
    // The image holds each pixel's mean over its cell, so the projection differs from the cap's by
    // the variation of Y inside the cells the edge crosses: O(pixel²), growing with the band
    // (at 512 × 256: ~2e-6 in band 0, ~3e-4 in band 7 for a 0.15 rad cap).
    let (w, h) = (512, 256);
    let d = unit([0.4, -0.6, 0.5]);
    for (order, alpha) in [(MAX_ORDER, 0.3), (PAPER_ORDER, 0.15)] {
        let coeffs = drawn_cap(w, h, order, d, alpha);
        let analytic = project_cap(order, d, alpha).unwrap();
        let red: Vec<f64> = coeffs.iter().map(|c| c[0]).collect();
        let green: Vec<f64> = coeffs.iter().map(|c| c[1] * 2.0).collect();
        let err = max_abs_diff(&red, &analytic).max(max_abs_diff(&green, &analytic));
        let rel = err / analytic[0];
        eprintln!(
            "equirect cap (order {order}, α {alpha}) vs analytic: max abs {err:e}, relative to DC {rel:e}"
        );
        assert!(rel < 1e-3, "order {order}, α {alpha}: relative error {rel:e}");
        assert!(coeffs.iter().all(|c| c[2] == 0.0));
    }
}

/// Integrates the basis over a cap directly, in the cap's own frame: Gauss–Legendre in
/// `t = ω·d` on `[cos α, 1]` times uniform azimuth about `d`, exact for band-limited integrands.
fn cap_by_quadrature(order: usize, d: [f64; 3], alpha: f64) -> Vec<f64> {
    let a = alpha.cos();
    let d = DVec3::from(d);
    let helper = if d.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let u = d.cross(helper).normalize();
    let v = d.cross(u);
    let (xs, ws) = gauss_legendre(16);
    let n_psi = 32;
    let power = 1.0 / (2.0 * PI * (1.0 - a));
    let mut dirs = Vec::new();
    let mut weights = Vec::new();
    for (x, w) in xs.iter().zip(&ws) {
        let t = 0.5 * (1.0 + a) + 0.5 * (1.0 - a) * x;
        let s = (1.0 - t * t).max(0.0).sqrt();
        for k in 0..n_psi {
            let psi = 2.0 * PI * k as f64 / n_psi as f64;
            let (sp, cp) = psi.sin_cos();
            dirs.push((s * (cp * u + sp * v) + t * d).normalize().to_array());
            weights.push(0.5 * (1.0 - a) * w * 2.0 * PI / n_psi as f64);
        }
    }
    let values = vec![power; dirs.len()];
    project_samples(order, &dirs, &weights, &values).unwrap()
}

#[test]
fn cap_projection_matches_quadrature_over_the_cap() {
    let mut worst: f64 = 0.0;
    for (d, alpha) in [
        (unit([0.0, 0.0, 1.0]), 0.5),
        (unit([1.0, -2.0, 0.5]), 0.05),
        (unit([-0.3, 0.1, -0.9]), 1.2),
        (unit([0.6, 0.6, 0.0]), 2.5),
        (unit([0.2, 0.3, 0.9]), PI),
        (unit([0.9, -0.1, 0.2]), 1e-3),
    ] {
        let analytic = project_cap(MAX_ORDER, d, alpha).unwrap();
        let numeric = cap_by_quadrature(MAX_ORDER, d, alpha);
        worst = worst.max(max_abs_diff(&analytic, &numeric));
    }
    eprintln!("cap analytic vs quadrature: max error {worst:e}");
    assert!(worst < 1e-6, "{worst:e}");
}

#[test]
fn cap_zonal_matches_legendre_differences_and_the_delta_limit() {
    // Independent closed form: mean of P_l over the cap = (P_{l−1}(a) − P_{l+1}(a))/((2l+1)(1−a)).
    let legendre = |n: usize, x: f64| {
        let (mut p0, mut p1) = (1.0, x);
        if n == 0 {
            return 1.0;
        }
        for k in 2..=n {
            let kf = k as f64;
            (p0, p1) = (p1, ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf);
        }
        p1
    };
    for alpha in [0.3, 1.0, 2.0, 3.0] {
        let a = f64::cos(alpha);
        let z = cap_zonal(MAX_ORDER, alpha).unwrap();
        for (l, zl) in z.iter().enumerate().skip(1) {
            let mean = (legendre(l - 1, a) - legendre(l + 1, a)) / ((2 * l + 1) as f64 * (1.0 - a));
            let expected = ((2 * l + 1) as f64 / (4.0 * PI)).sqrt() * mean;
            assert!(
                (zl - expected).abs() < 1e-12,
                "α={alpha} l={l}: {zl} vs {expected}"
            );
        }
    }
    // α = 0 is a delta light: its coefficients are the basis evaluated at d.
    let d = unit([0.3, -0.4, 0.8]);
    let delta = project_cap(MAX_ORDER, d, 0.0).unwrap();
    assert!(max_abs_diff(&delta, &eval_vec(MAX_ORDER, d).unwrap()) < 1e-14);
    // A tiny cap converges to it smoothly (error O(α²)), not through cancellation noise.
    let tiny = project_cap(MAX_ORDER, d, 1e-6).unwrap();
    assert!(max_abs_diff(&tiny, &delta) < 1e-10);
}

#[test]
fn rotation_band_matrices_are_orthogonal() {
    let mut rng = Rng(11);
    let rot = ShRotation::new(MAX_ORDER, rows(random_rotation(&mut rng))).unwrap();
    assert_eq!(rot.order(), MAX_ORDER);
    assert!(rot.band(MAX_ORDER).is_none());
    for l in 0..MAX_ORDER {
        let band = rot.band(l).unwrap();
        let n = 2 * l + 1;
        for i in 0..n {
            for j in 0..n {
                let dot: f64 = (0..n).map(|k| band[i * n + k] * band[j * n + k]).sum();
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!((dot - expected).abs() < 1e-12, "band {l} ({i},{j}): {dot}");
            }
        }
    }
}
