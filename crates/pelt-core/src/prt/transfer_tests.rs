//! Tests of the transfer bake, band selection and packing against independent computations:
//! closed-form slab transmittance, direct quadrature sums, mirror symmetry, brute-force marching.

use std::f64::consts::PI;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::bands::{BandParams, auto_validated, bake_transfer_auto, band_energy};
use super::pack::{pack_f16, pack_u8, texel_index, texture_count};
use super::sh;
use super::sphere::{fibonacci_directions, mirrored_fibonacci_directions};
use super::transfer::*;
use crate::error::PeltError;
use crate::volume::coverage::{CoverageMode, splat_disk};

/// Deterministic pseudo-random numbers in [0, 1) for test data.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Slanted cylinders of hair ("strands") of random position, slant, radius and height, splatted
/// per layer with exact disk coverage.
fn cylinders(res: usize, layers: usize, spacing: f64, count: usize, seed: u64) -> Vec<f32> {
    let mut rng = Rng(seed);
    let mut density = vec![0.0f32; layers * res * res];
    let r2 = res * res;
    for _ in 0..count {
        let (x, y) = (rng.next(), rng.next());
        let (sx, sy) = (0.3 * (rng.next() - 0.5), 0.3 * (rng.next() - 0.5));
        let radius = (0.25 + 0.35 * rng.next()) / res as f64;
        let top = 0.4 + 0.6 * rng.next();
        for l in 0..layers {
            let h = l as f64 / (layers - 1) as f64;
            if h > top {
                break;
            }
            // Slant in texel widths per texel of height, converted to tile units.
            let z = l as f64 * spacing / res as f64;
            let grid = &mut density[l * r2..(l + 1) * r2];
            splat_disk(grid, res, x + sx * z, y + sy * z, radius, CoverageMode::Exact).unwrap();
        }
    }
    density
}

/// The default pelt with 16 times fewer, 4 times wider hairs: at 32² texels the strands are as
/// wide in texels as the default pelt's at 128², where the sweep has the most to resolve.
fn coarse_pelt() -> crate::hair::HairParams {
    let d = crate::hair::HairParams::default();
    let widen = |c: crate::hair::CoatParams| crate::hair::CoatParams {
        width: c.width.map(|w| 4.0 * w),
        ..c
    };
    crate::hair::HairParams {
        density: d.density / 16,
        undercoat: widen(d.undercoat),
        overcoat: widen(d.overcoat),
        ..d
    }
}

fn volume<'a>(res: usize, layers: usize, spacing: f32, density: &'a [f32]) -> TransferVolume<'a> {
    TransferVolume {
        layers,
        resolution: res,
        layer_spacing: spacing,
        density,
        tangents: None,
    }
}

/// The bake's direction set for `n` and its weight, as input data for sums done here.
fn bake_set(n: usize) -> (Vec<[f64; 3]>, f64) {
    let dirs = mirrored_fibonacci_directions(n);
    let w = 4.0 * PI / dirs.len() as f64;
    (dirs, w)
}

fn rel_rms(a: &[f32], b: &[f32]) -> f64 {
    assert_eq!(a.len(), b.len());
    let num: f64 = a.iter().zip(b).map(|(x, y)| f64::from(x - y).powi(2)).sum();
    let den: f64 = b.iter().map(|y| f64::from(*y).powi(2)).sum();
    (num / den).sqrt()
}

fn is_parameter_error(e: PeltError, name: &str) -> bool {
    matches!(&e, PeltError::InvalidParameter { name: n, .. } if n == name)
}

fn params(method: Method, directions: usize, order: usize) -> TransferParams {
    TransferParams {
        method,
        directions,
        order,
        ..TransferParams::default()
    }
}

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn sweep_matches_brute_force_on_hair_strands() {
    // Hairs as wide in texels as the default pelt's at 128² (the benchmark), half a tile deep.
    let baked = crate::volume::bake_volume(
        &coarse_pelt(),
        &crate::volume::VolumeParams {
            layers: 8,
            resolution: 32,
            trim: false,
            ..Default::default()
        },
        None,
    )
    .unwrap();
    let input = crate::prt::volume_input::VolumeInput::new(&baked, 0.5);
    let (res, layers, spacing) = (32, 8, input.layer_spacing);
    let density = baked.coverage.clone();
    let mean = density.iter().map(|&d| f64::from(d)).sum::<f64>() / density.len() as f64;
    assert!(
        mean > 0.02,
        "the volume must shadow noticeably (mean density {mean})"
    );
    let vol = volume(res, layers, spacing, &density);
    let sweep = bake_transfer(&vol, &params(Method::Sweep, 96, 5), None).unwrap();
    let brute = bake_transfer(&vol, &params(Method::Brute, 96, 5), None).unwrap();
    let error = rel_rms(&sweep.coefficients, &brute.coefficients);
    eprintln!("sweep vs brute: relative RMS {error:.2e}");
    assert!(error <= 1e-2, "relative RMS {error}");
    assert!(sweep.coefficients.iter().all(|c| c.is_finite()));
}

#[test]
fn both_methods_match_the_closed_form_slab() {
    // Constant ρ: T = exp(−σ ρ (H − z) / ω_z) exactly, for any lateral structure of the method.
    let (res, layers, spacing, rho) = (8, 6, 1.7f32, 0.3f32);
    let density = vec![rho; layers * res * res];
    let vol = volume(res, layers, spacing, &density);
    let height = f64::from(spacing) * (layers - 1) as f64;
    for method in [Method::Brute, Method::Sweep] {
        let p = TransferParams {
            method,
            sigma: 0.7,
            ..TransferParams::default()
        };
        for dir in [
            [0.0, 0.0, 1.0],
            [0.5, 0.2, 0.8],
            [-0.9, 0.3, 0.3],
            [0.2, -0.97, 0.1],
        ] {
            let t = transmittance(&vol, &p, dir).unwrap();
            let len: f64 = dir.iter().map(|v: &f64| v * v).sum::<f64>().sqrt();
            let cz = dir[2] / len;
            for (v, &tv) in t.iter().enumerate() {
                let z = (v / (res * res)) as f64 * f64::from(spacing);
                let exact = (-0.7 * f64::from(rho) * (height - z) / cz).exp();
                assert!(
                    (f64::from(tv) - exact).abs() <= 1e-5 * exact.max(1e-3),
                    "{method:?} {dir:?} voxel {v}: {tv} vs {exact}"
                );
            }
        }
        // The coefficients are the quadrature of the closed form.
        let order = 4;
        let n = sh::coeff_count(order);
        let baked = bake_transfer(&vol, &TransferParams { order, ..p.clone() }, None).unwrap();
        let (dirs, w) = bake_set(p.directions);
        for layer in [0, 2, layers - 1] {
            let z = layer as f64 * f64::from(spacing);
            let mut expected = vec![0.0; n];
            for d in dirs.iter().filter(|d| d[2] > 0.0) {
                let t = (-0.7 * f64::from(rho) * (height - z) / d[2]).exp();
                let y = sh::eval_vec(order, *d).unwrap();
                for (e, y) in expected.iter_mut().zip(&y) {
                    *e += w * y * t;
                }
            }
            let got = baked.voxel(layer, 3, 5).unwrap();
            for (g, e) in got.iter().zip(&expected) {
                assert!(
                    (f64::from(*g) - e).abs() < 2e-5,
                    "{method:?} layer {layer}: {g} vs {e}"
                );
            }
        }
    }
}

#[test]
fn empty_volume_transfers_the_upper_hemisphere() {
    let (res, layers) = (4, 3);
    let density = vec![0.0; layers * res * res];
    let vol = volume(res, layers, 2.0, &density);
    let order = 6;
    let n = sh::coeff_count(order);
    for method in [Method::Brute, Method::Sweep] {
        let p = params(method, 200, order);
        for dir in [[0.3, 0.1, 0.9], [1.0, 0.0, 1e-5]] {
            let t = transmittance(&vol, &p, dir).unwrap();
            assert!(t.iter().all(|&v| v == 1.0), "{method:?}: T = 1 above the skin");
        }
        assert!(
            transmittance(&vol, &p, [0.3, 0.1, -0.2])
                .unwrap()
                .iter()
                .all(|&v| v == 0.0)
        );
        let baked = bake_transfer(&vol, &p, None).unwrap();
        // The projection of the indicator of ω_z > 0 by the same quadrature, summed here.
        let (dirs, w) = bake_set(200);
        let mut expected = vec![0.0; n];
        for d in dirs.iter().filter(|d| d[2] > 0.0) {
            for (e, y) in expected.iter_mut().zip(sh::eval_vec(order, *d).unwrap()) {
                *e += w * y;
            }
        }
        // And its exact value: zonal, Y_l^0 integrated over μ ∈ [0, 1] (P_l of odd l ≥ 3 and
        // even l ≥ 2 per the closed forms below).
        let exact_dc = 2.0 * PI / (4.0 * PI).sqrt();
        let exact_z = 2.0 * PI * (3.0 / (4.0 * PI)).sqrt() / 2.0;
        for c in baked.coefficients.chunks_exact(n) {
            for (g, e) in c.iter().zip(&expected) {
                assert!((f64::from(*g) - e).abs() < 1e-5, "{method:?}: {g} vs {e}");
            }
            assert!((f64::from(c[0]) - exact_dc).abs() < 1e-5);
            assert!((f64::from(c[sh::index(1, 0)]) - exact_z).abs() < 1e-3);
            assert!(
                f64::from(c[sh::index(2, 0)]).abs() < 1e-3,
                "band 2 of a hemisphere is 0"
            );
        }
    }
}

#[test]
fn huge_density_is_opaque_without_nan() {
    let (res, layers) = (6, 4);
    let density = vec![1e30f32; layers * res * res];
    let vol = volume(res, layers, 1.0, &density);
    for method in [Method::Brute, Method::Sweep] {
        let p = TransferParams {
            method,
            sigma: MAX_SIGMA,
            ..TransferParams::default()
        };
        for dir in [[0.0, 0.0, 1.0], [0.7, 0.1, 0.2], [1.0, 0.0, 5e-5]] {
            let t = transmittance(&vol, &p, dir).unwrap();
            let r2 = res * res;
            assert!(t[..(layers - 1) * r2].iter().all(|&v| v == 0.0), "{method:?}");
            assert!(
                t[(layers - 1) * r2..].iter().all(|&v| v == 1.0),
                "nothing above the top"
            );
        }
        let baked = bake_transfer(&vol, &params(method, 64, 5), None).unwrap();
        assert!(baked.coefficients.iter().all(|c| c.is_finite()));
        assert!(baked.voxel(0, 0, 0).unwrap().iter().all(|&c| c == 0.0));
    }
}

#[test]
fn largest_density_without_extinction_is_unshadowed() {
    // Found by the long Python fuzz (seed 102): the sweep's density pyramid summed two values
    // near f32::MAX to inf, and σ = 0 made that NaN.
    let (res, layers) = (5, 2);
    let density = vec![f32::MAX; layers * res * res];
    let vol = volume(res, layers, 3.0, &density);
    for method in [Method::Brute, Method::Sweep] {
        let p = TransferParams {
            sigma: 0.0,
            ..params(method, 45, 3)
        };
        for dir in [[0.0, 0.0, 1.0], [0.7, 0.1, 0.2], [1.0, 0.0, 5e-5]] {
            let t = transmittance(&vol, &p, dir).unwrap();
            assert!(t.iter().all(|&v| v == 1.0), "{method:?} {dir:?}");
        }
        let baked = bake_transfer(&vol, &p, None).unwrap();
        assert!(baked.coefficients.iter().all(|c| c.is_finite()), "{method:?}");
    }
}

#[test]
fn grazing_directions_stay_finite_and_match_the_slab() {
    let (res, layers, rho) = (5, 4, 1e-6f32);
    let mut density = cylinders(res, layers, 1.0, 6, 9);
    for d in &mut density {
        *d += rho;
    }
    let vol = volume(res, layers, 1.0, &density);
    for method in [Method::Brute, Method::Sweep] {
        let p = TransferParams {
            method,
            ..TransferParams::default()
        };
        for dir in [
            [1.0, 0.0, 9e-5],
            [0.6, -0.8, 1e-6],
            [0.0, 1.0, 1e-12],
            [1.0, 1.0, 0.0],
        ] {
            let t = transmittance(&vol, &p, dir).unwrap();
            assert!(
                t.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)),
                "{method:?} {dir:?}"
            );
        }
    }
    // A thin homogeneous slab seen at ω_z = 5e-5: T = exp(−σρ(H − z)/ω_z), tile-independent.
    let sigma = f64::from(TransferParams::default().sigma);
    let slab = vec![1e-5f32; layers * res * res];
    let vol = volume(res, layers, 1.0, &slab);
    for method in [Method::Brute, Method::Sweep] {
        let p = TransferParams {
            method,
            brute_step: 2.0,
            ..TransferParams::default()
        };
        let cz = 5e-5;
        let dir = [(1.0f64 - cz * cz).sqrt(), 0.0, cz];
        let t = transmittance(&vol, &p, dir).unwrap();
        for (v, &tv) in t.iter().enumerate() {
            let z = (v / (res * res)) as f64;
            let exact = (-sigma * 1e-5 * (3.0 - z) / cz).exp();
            assert!(
                (f64::from(tv) - exact).abs() < 1e-5,
                "{method:?} voxel {v}: {tv} vs {exact}"
            );
        }
    }
}

/// Mirrors a `[L][R][R]` field in x (texel x ↔ R − 1 − x).
fn mirror_x<T: Copy>(field: &[T], res: usize) -> Vec<T> {
    field
        .chunks_exact(res)
        .flat_map(|row| row.iter().rev().copied().collect::<Vec<_>>())
        .collect()
}

#[test]
fn lighting_from_plus_x_and_minus_x_is_mirror_equal() {
    let (res, layers, spacing) = (20, 6, 1.5);
    let raw = cylinders(res, layers, f64::from(spacing), 30, 17);
    let mirrored = mirror_x(&raw, res);
    let density: Vec<f32> = raw.iter().zip(&mirrored).map(|(a, b)| 0.5 * (a + b)).collect();
    let vol = volume(res, layers, spacing, &density);
    for method in [Method::Sweep, Method::Brute] {
        // Transmittance: exactly the mirror image for mirrored directions.
        let p = params(method, 256, 5);
        for dir in [[0.8, 0.3, 0.5], [0.95, -0.1, 0.05]] {
            let plus = transmittance(&vol, &p, dir).unwrap();
            let minus = transmittance(&vol, &p, [-dir[0], dir[1], dir[2]]).unwrap();
            let worst = plus
                .iter()
                .zip(mirror_x(&minus, res))
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f32::max);
            assert!(
                worst < 1e-5,
                "{method:?} {dir:?}: transmittance asymmetry {worst}"
            );
        }
        // Lighting through the SH transfer with a soft light from +x and from −x.
        let baked = bake_transfer(&vol, &p, None).unwrap();
        let n = baked.coeff_count();
        let light = |sx: f64| sh::project_cap(5, [sx * 0.8, 0.0, 0.6], 0.3).unwrap();
        let lit = |l: &[f64]| -> Vec<f32> {
            baked
                .coefficients
                .chunks_exact(n)
                .map(|t| t.iter().zip(l).map(|(t, l)| f64::from(*t) * l).sum::<f64>() as f32)
                .collect()
        };
        let plus = lit(&light(1.0));
        let minus = mirror_x(&lit(&light(-1.0)), res);
        let scale = plus.iter().copied().fold(0.0, f32::max);
        let worst = plus
            .iter()
            .zip(&minus)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f32::max);
        eprintln!(
            "{method:?}: mirror asymmetry {:.2e} of the brightest voxel",
            worst / scale
        );
        assert!(
            worst <= 1e-3 * scale,
            "{method:?}: asymmetry {worst} vs max {scale}"
        );
    }
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let (res, layers) = (12, 5);
    let density = cylinders(res, layers, 1.0, 20, 5);
    let tangents: Vec<[f32; 3]> = (0..density.len())
        .map(|i| [(i % 7) as f32 * 0.1, 0.2, 1.0])
        .collect();
    let vol = TransferVolume {
        tangents: Some(&tangents),
        ..volume(res, layers, 1.0, &density)
    };
    for method in [Method::Brute, Method::Sweep] {
        for phase in [Phase::Isotropic, Phase::KajiyaKay] {
            let p = TransferParams {
                phase,
                ..params(method, 48, 4)
            };
            let one = in_pool(1, || bake_validated(&vol, &p, None).unwrap());
            let two = in_pool(2, || bake_validated(&vol, &p, None).unwrap());
            assert_eq!(
                bits(&one.coefficients),
                bits(&two.coefficients),
                "{method:?} {phase:?}"
            );
        }
    }
    let p = params(Method::Sweep, 48, 4);
    let bands = BandParams::default();
    let (t1, r1) = in_pool(1, || auto_validated(&vol, &p, &bands, None).unwrap());
    let (t2, r2) = in_pool(2, || auto_validated(&vol, &p, &bands, None).unwrap());
    assert_eq!(bits(&t1.coefficients), bits(&t2.coefficients));
    assert_eq!(r1, r2);
}

#[test]
fn kajiya_kay_weighs_directions_by_the_sine_to_the_tangent() {
    let (res, layers) = (3, 2);
    let density = vec![0.0; layers * res * res];
    // Voxel 0 has no tangent; the others lean along x (any length).
    let mut tangents = vec![[2.0f32, 0.0, 0.0]; layers * res * res];
    tangents[0] = [0.0; 3];
    let vol = TransferVolume {
        tangents: Some(&tangents),
        ..volume(res, layers, 1.0, &density)
    };
    let order = 3;
    let p = TransferParams {
        phase: Phase::KajiyaKay,
        ..params(Method::Sweep, 100, order)
    };
    let baked = bake_transfer(&vol, &p, None).unwrap();
    let (dirs, w) = bake_set(100);
    let (mut along_x, mut mean) = (vec![0.0; 9], vec![0.0; 9]);
    for d in dirs.iter().filter(|d| d[2] > 0.0) {
        let y = sh::eval_vec(order, *d).unwrap();
        for k in 0..9 {
            along_x[k] += w * y[k] * (1.0 - d[0] * d[0]).sqrt();
            mean[k] += w * y[k] * PI / 4.0;
        }
    }
    let close = |a: &[f32], b: &[f64]| a.iter().zip(b).all(|(a, b)| (f64::from(*a) - b).abs() < 1e-5);
    assert!(close(baked.voxel(0, 0, 0).unwrap(), &mean));
    assert!(close(baked.voxel(1, 2, 1).unwrap(), &along_x));
    let missing = bake_transfer(&volume(res, layers, 1.0, &density), &p, None).unwrap_err();
    assert!(is_parameter_error(missing, "tangents"));
}

#[test]
fn bad_parameters_are_named() {
    let density = vec![0.0f32; 2 * 4 * 4];
    let vol = volume(4, 2, 1.0, &density);
    type Breaker = fn(&mut TransferParams);
    let cases: &[(&str, Breaker)] = &[
        ("order", |p| p.order = 0),
        ("order", |p| p.order = 9),
        ("directions", |p| p.directions = 15),
        ("directions", |p| p.directions = MAX_DIRECTIONS + 1),
        ("sigma", |p| p.sigma = -1.0),
        ("sigma", |p| p.sigma = f32::NAN),
        ("brute_step", |p| p.brute_step = 0.0),
        ("sweep_step", |p| p.sweep_step = f32::INFINITY),
        ("sweep_max_samples", |p| p.sweep_max_samples = 0),
    ];
    for (name, breaker) in cases {
        let mut p = TransferParams::default();
        breaker(&mut p);
        assert!(is_parameter_error(p.validate().unwrap_err(), name), "{name}");
        assert!(
            is_parameter_error(bake_transfer(&vol, &p, None).unwrap_err(), name),
            "{name}"
        );
    }
    let p = TransferParams::default();
    let bake = |v: TransferVolume<'_>| bake_transfer(&v, &p, None).unwrap_err();
    assert!(is_parameter_error(
        bake(volume(4, 1, 1.0, &density[..16])),
        "layers"
    ));
    assert!(is_parameter_error(bake(volume(0, 2, 1.0, &[])), "resolution"));
    assert!(is_parameter_error(
        bake(volume(4, 2, 0.0, &density)),
        "layer_spacing"
    ));
    assert!(is_parameter_error(
        bake(volume(4, 2, f32::NAN, &density)),
        "layer_spacing"
    ));
    assert!(is_parameter_error(
        bake(volume(4, 2, 1.0, &density[1..])),
        "density"
    ));
    let mut negative = density.clone();
    negative[5] = -0.1;
    let e = bake(volume(4, 2, 1.0, &negative));
    assert!(e.to_string().contains("[layer 0, y 1, x 1]"), "{e}");
    assert!(is_parameter_error(e, "density"));
    let mut nan = density.clone();
    nan[20] = f32::NAN;
    assert!(is_parameter_error(bake(volume(4, 2, 1.0, &nan)), "density"));
    let short = vec![[0.0f32, 0.0, 1.0]; 31];
    let with_tangents = |t| TransferVolume {
        tangents: Some(t),
        ..volume(4, 2, 1.0, &density)
    };
    assert!(is_parameter_error(bake(with_tangents(&short)), "tangents"));
    let mut bad = vec![[0.0f32, 0.0, 1.0]; 32];
    bad[3][1] = f32::INFINITY;
    assert!(is_parameter_error(bake(with_tangents(&bad)), "tangents"));
    let e = transmittance(&vol, &p, [0.0, 0.0, 0.0]).unwrap_err();
    assert!(is_parameter_error(e, "direction"));
    for (name, bands) in [
        (
            "tolerance",
            BandParams {
                tolerance: 0.0,
                ..BandParams::default()
            },
        ),
        (
            "light_sharpness",
            BandParams {
                light_sharpness: -1.0,
                ..BandParams::default()
            },
        ),
    ] {
        assert!(is_parameter_error(
            bake_transfer_auto(&vol, &p, &bands, None).unwrap_err(),
            name
        ));
    }
}

#[test]
fn cancellation_stops_both_methods_and_progress_reaches_one() {
    let (res, layers) = (8, 4);
    let density = cylinders(res, layers, 1.0, 10, 2);
    let vol = volume(res, layers, 1.0, &density);
    for method in [Method::Brute, Method::Sweep] {
        let p = params(method, 32, 3);
        let calls = AtomicUsize::new(0);
        let cancel = |_: f64| calls.fetch_add(1, Ordering::Relaxed) < 2;
        let e = bake_transfer(&vol, &p, Some(&cancel)).unwrap_err();
        assert!(matches!(e, PeltError::Cancelled), "{method:?}: {e}");
        let seen = Mutex::new(Vec::new());
        let record = |f: f64| {
            seen.lock().unwrap().push(f);
            true
        };
        bake_transfer(&vol, &p, Some(&record)).unwrap();
        let seen = seen.into_inner().unwrap();
        assert_eq!(seen.last().copied(), Some(1.0), "{method:?}");
    }
}

#[test]
fn truncation_keeps_the_lower_bands() {
    let (res, layers) = (6, 3);
    let density = cylinders(res, layers, 1.0, 8, 4);
    let vol = volume(res, layers, 1.0, &density);
    let full = bake_transfer(&vol, &params(Method::Sweep, 64, 6), None).unwrap();
    let low = bake_transfer(&vol, &params(Method::Sweep, 64, 3), None).unwrap();
    assert_eq!(
        bits(&full.truncated(3).unwrap().coefficients),
        bits(&low.coefficients)
    );
    assert!(is_parameter_error(full.truncated(7).unwrap_err(), "order"));
    assert!(full.voxel(3, 0, 0).is_none());
}

#[test]
fn von_mises_fisher_lights_have_the_closed_form_mean_cosine() {
    // A unit-power lobe has z_0 = Y_0^0 = 1/√(4π) and z_1 = √(3/4π)·(coth κ − 1/κ).
    for kappa in [0.5, 8.0, 60.0] {
        let lights = super::bands::TestLights::new(kappa).unwrap();
        let c = &lights.coefficients[0];
        let d = fibonacci_directions(super::bands::TEST_LIGHTS)[0];
        let z1 = (3.0 / (4.0 * PI)).sqrt() * (1.0 / kappa.tanh() - 1.0 / kappa);
        assert!((c[0] - 1.0 / (4.0 * PI).sqrt()).abs() < 1e-12, "κ {kappa}");
        // Band 1 of a zonal lobe about d is √(4π/3)·z_1·Y_1(d) = z_1·(y, z, x)·√(3/4π)·√(4π/3).
        let expected = [d[1], d[2], d[0]].map(|v| z1 * v);
        for (got, e) in c[1..4].iter().zip(expected) {
            assert!((got - e).abs() < 1e-12, "κ {kappa}: {got} vs {e}");
        }
    }
}

#[test]
fn band_selection_picks_the_smallest_order_within_tolerance() {
    let (res, layers) = (16, 6);
    let density = cylinders(res, layers, 1.0, 30, 8);
    let vol = volume(res, layers, 1.0, &density);
    let p = params(Method::Sweep, 128, 5);
    let (transfer, report) = bake_transfer_auto(&vol, &p, &BandParams::default(), None).unwrap();
    assert_eq!(report.rows.len(), 8);
    assert_eq!(transfer.order, report.order);
    let first = report.rows.iter().find(|r| r.error <= report.tolerance);
    assert_eq!(report.order, first.map_or(8, |r| r.order));
    assert_eq!(report.met, first.is_some());
    let energy: f64 = report.rows.iter().map(|r| r.band_energy).sum();
    assert!((energy - 1.0).abs() < 1e-9);
    assert!(
        report.rows[0].error > report.rows[7].error,
        "more bands, less error"
    );
    for r in &report.rows {
        assert_eq!(r.coefficients, r.order * r.order);
        assert_eq!(r.bytes_u8, texture_count(r.coefficients) * layers * res * res * 4);
        assert_eq!(r.bytes_f16, 2 * r.bytes_u8);
        assert!(r.error.is_finite() && r.error == r.error_directional.max(r.error_environment));
    }
    // The auto result is the plain bake at the chosen order, bit for bit.
    let plain = bake_transfer(&vol, &params(Method::Sweep, 128, report.order), None).unwrap();
    assert_eq!(bits(&transfer.coefficients), bits(&plain.coefficients));
    // A tolerance of 100 % is met by the DC term alone.
    let loose = BandParams {
        tolerance: 1.0,
        ..BandParams::default()
    };
    assert_eq!(bake_transfer_auto(&vol, &p, &loose, None).unwrap().1.order, 1);
    // Band energies sum Σ t² per band, here checked on the baked coefficients directly.
    let e = band_energy(&transfer);
    let total: f64 = transfer.coefficients.iter().map(|&c| f64::from(c).powi(2)).sum();
    assert!((e.iter().sum::<f64>() - total).abs() < 1e-9 * total);
}

#[test]
fn packing_puts_four_coefficients_per_texel() {
    let (res, layers, order) = (3, 2, 5);
    let n = sh::coeff_count(order);
    let mut rng = Rng(11);
    let transfer = Transfer {
        order,
        layers,
        resolution: res,
        coefficients: (0..layers * res * res * n)
            .map(|_| (rng.next() * 4.0 - 2.0) as f32)
            .collect(),
    };
    let voxels = layers * res * res;
    let f16 = pack_f16(&transfer).unwrap();
    assert_eq!(f16.textures, 7, "25 coefficients → 7 RGBA textures");
    assert_eq!(f16.texels.len(), 7 * voxels * 4);
    let u8 = pack_u8(&transfer).unwrap();
    assert_eq!(u8.texels.len(), f16.texels.len());
    let side = &u8.sidecar;
    for v in 0..voxels {
        for k in 0..n {
            let value = transfer.coefficients[v * n + k];
            let i = texel_index(k, v, voxels);
            assert_eq!(i, ((k / 4) * voxels + v) * 4 + k % 4);
            let half = f16.texels[i].to_f32();
            assert!(
                (half - value).abs() <= value.abs() * 2.0f32.powi(-11),
                "{half} vs {value}"
            );
            let decoded = f32::from(u8.texels[i]) / 255.0 * side.scale[k] + side.bias[k];
            assert!(
                (decoded - value).abs() <= side.scale[k] / 510.0 + 1e-6,
                "{decoded} vs {value}"
            );
        }
        // The 3 channels past coefficient 24 are zero.
        for k in n..28 {
            assert_eq!(f16.texels[texel_index(k, v, voxels)].to_f32(), 0.0);
            assert_eq!(u8.texels[texel_index(k, v, voxels)], 0);
        }
    }
    let json = serde_json::to_string(side).unwrap();
    assert!(json.contains("value = byte / 255 * scale + bias"));
    let back: super::pack::QuantizationSidecar = serde_json::from_str(&json).unwrap();
    assert_eq!(&back, side);
    // A constant coefficient decodes exactly with scale 0.
    let constant = Transfer {
        coefficients: vec![0.75; voxels * n],
        ..transfer
    };
    let packed = pack_u8(&constant).unwrap();
    assert!(packed.sidecar.scale.iter().all(|&s| s == 0.0));
    assert!(packed.sidecar.bias.iter().all(|&b| b == 0.75));
    // An inconsistent transfer is an error, not a panic.
    let short = Transfer {
        coefficients: vec![0.0; 10],
        ..constant
    };
    assert!(is_parameter_error(pack_f16(&short).unwrap_err(), "coefficients"));
    assert!(is_parameter_error(pack_u8(&short).unwrap_err(), "coefficients"));
}
