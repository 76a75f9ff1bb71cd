//! The image metrics against answers worked out by hand.

use crate::reference::metrics::{LinearRgba, PROFILE_BIN, compare, compare_noisy, distance_from_mask};
use crate::rng::Rng;

fn view(pixels: &[[f32; 4]], side: usize) -> LinearRgba<'_> {
    LinearRgba {
        width: side,
        height: side,
        pixels,
    }
}

#[test]
fn the_distance_transform_is_the_brute_force_euclidean_distance() {
    let (w, h) = (23, 17);
    let mask: Vec<bool> = (0..w * h).map(|i| (i * 7919) % 53 == 0).collect();
    let fast = distance_from_mask(&mask, w, h);
    for y in 0..h {
        for x in 0..w {
            let brute = (0..w * h)
                .filter(|&i| mask[i])
                .map(|i| (((i % w) as f64 - x as f64).powi(2) + ((i / w) as f64 - y as f64).powi(2)).sqrt())
                .fold(f64::INFINITY, f64::min);
            assert!((f64::from(fast[y * w + x]) - brute).abs() < 1e-4, "({x}, {y})");
        }
    }
    assert!(
        distance_from_mask(&[false; 4], 2, 2)
            .iter()
            .all(|d| d.is_infinite())
    );
}

/// A disk of radius 10 (the skin) under a fringe whose coverage falls linearly from 1 at the
/// outline to 0 at 10 pixels out, colored `color`.
fn disk(side: usize, color: f32, fringe: f32) -> (Vec<[f32; 4]>, Vec<bool>) {
    let c = side as f32 / 2.0;
    let mut pixels = Vec::new();
    let mut skin = Vec::new();
    for y in 0..side {
        for x in 0..side {
            let r = ((x as f32 + 0.5 - c).powi(2) + (y as f32 + 0.5 - c).powi(2)).sqrt();
            let alpha = if r <= 10.0 {
                1.0
            } else {
                (fringe * (1.0 - (r - 10.0) / 10.0)).max(0.0)
            };
            pixels.push([color * alpha, color * alpha, color * alpha, alpha]);
            skin.push(r <= 10.0);
        }
    }
    (pixels, skin)
}

#[test]
fn identical_images_have_no_error_and_a_brighter_one_its_ratio() {
    let side = 48;
    let (reference, skin) = disk(side, 0.3, 1.0);
    let distance = distance_from_mask(&skin, side, side);
    let same = compare(view(&reference, side), view(&reference, side), &distance, 10.0).unwrap();
    assert_eq!(same.relative_mse, 0.0);
    assert_eq!(same.flip, 0.0);
    assert_eq!(same.alpha_profile_error, 0.0);
    assert!((same.luminance_ratio - 1.0).abs() < 1e-12);

    // 1% more light: MSE 1e-4 exactly, the luminance ratio 1.01, FLIP above zero.
    let brighter: Vec<[f32; 4]> = reference
        .iter()
        .map(|p| [p[0] * 1.01, p[1] * 1.01, p[2] * 1.01, p[3]])
        .collect();
    let e = compare(view(&brighter, side), view(&reference, side), &distance, 10.0).unwrap();
    assert!((e.relative_mse - 1e-4).abs() < 1e-7, "{}", e.relative_mse);
    assert!((e.luminance_ratio - 1.01).abs() < 1e-5);
    assert!(e.flip > 0.0 && e.flip < 0.05, "{}", e.flip);
}

#[test]
fn the_alpha_profile_follows_coverage_out_from_the_skin() {
    let side = 64;
    let (reference, skin) = disk(side, 0.5, 1.0);
    let (hard, _) = disk(side, 0.5, 0.5);
    let distance = distance_from_mask(&skin, side, side);
    // The fur depth is 10 pixels: the fringe falls from 1 to 0 over one fur depth.
    let e = compare(view(&hard, side), view(&reference, side), &distance, 10.0).unwrap();
    let [preview, truth] = &e.alpha_profile;
    // Bin k holds (k, k + 1] tenths of a fur depth: mean coverage about 1 − (k + 0.5) / 10.
    for (k, &a) in truth.iter().take(9).enumerate() {
        let expected = 1.0 - (k as f64 + 0.5) * PROFILE_BIN;
        assert!((a - expected).abs() < 0.08, "bin {k}: {a} against {expected}");
        assert!((preview[k] - 0.5 * a).abs() < 0.05, "bin {k}");
    }
    // The largest gap is in the first bin, where the reference is most opaque.
    assert!((e.alpha_profile_error - 0.5 * truth[0]).abs() < 0.05);
}

#[test]
fn the_detail_ratio_is_the_squared_ratio_of_fine_contrast() {
    // A grey image with a one-pixel checkerboard of amplitude `a` over all of it: the 5 × 5 box
    // mean keeps a twenty-fifth of the pattern, so the residual is proportional to `a` and the
    // energies' ratio is the amplitudes' ratio squared.
    let side = 20;
    let checker = |a: f32| -> Vec<[f32; 4]> {
        (0..side * side)
            .map(|i| {
                let sign = if (i % side + i / side) % 2 == 0 { 1.0 } else { -1.0 };
                let v = 0.3 + a * sign;
                [v, v, v, 1.0]
            })
            .collect()
    };
    let distance = vec![0.0; side * side];
    let (fine, coarse) = (checker(0.1), checker(0.05));
    let e = compare(view(&coarse, side), view(&fine, side), &distance, 10.0).unwrap();
    assert!((e.detail_ratio - 0.25).abs() < 1e-5, "{}", e.detail_ratio);
    let same = compare(view(&fine, side), view(&fine, side), &distance, 10.0).unwrap();
    assert!((same.detail_ratio - 1.0).abs() < 1e-12);
    let flat = compare(view(&checker(0.0), side), view(&fine, side), &distance, 10.0).unwrap();
    assert!(flat.detail_ratio < 1e-20, "{}", flat.detail_ratio);
}

#[test]
fn the_reference_noise_is_taken_out_of_its_detail() {
    // The clean checkerboard against itself with noise of known variance added: measured
    // plainly, the noise inflates the reference's detail and halves the ratio; with the
    // variances it is taken out again.
    let side = 128;
    let amplitude = 0.05f32;
    let clean: Vec<[f32; 4]> = (0..side * side)
        .map(|i| {
            let sign = if (i % side + i / side) % 2 == 0 { 1.0 } else { -1.0 };
            let v = 0.3 + amplitude * sign;
            [v, v, v, 1.0]
        })
        .collect();
    // Uniform noise on [−h, h] (variance h² / 3) of the checker's own energy, varying by pixel.
    let mut rng = Rng::new(7);
    let (mut noisy, mut variance) = (Vec::new(), Vec::new());
    for p in &clean {
        let h = amplitude * (1.0 + rng.next_f64() as f32);
        let n = h * (2.0 * rng.next_f64() as f32 - 1.0);
        noisy.push([p[0] + n, p[1] + n, p[2] + n, 1.0]);
        variance.push(h * h / 3.0);
    }
    let distance = vec![0.0; side * side];
    let plain = compare(view(&clean, side), view(&noisy, side), &distance, 10.0).unwrap();
    assert!(
        plain.detail_ratio < 0.6,
        "the noise inflates the detail: {}",
        plain.detail_ratio
    );
    assert_eq!(plain.detail_noise_share, 0.0);
    let e = compare_noisy(
        view(&clean, side),
        view(&noisy, side),
        Some(&variance),
        &distance,
        10.0,
    )
    .unwrap();
    // Measured: 0.97 (what is left is this draw of the noise against its expectation).
    assert!((e.detail_ratio - 1.0).abs() < 0.05, "{}", e.detail_ratio);
    assert!((e.detail_noise_share - (1.0 - plain.detail_ratio)).abs() < 0.05);
    let short = compare_noisy(
        view(&clean, side),
        view(&noisy, side),
        Some(&variance[1..]),
        &distance,
        10.0,
    );
    assert!(short.is_err(), "a variance per pixel");
}
