use half::f16;

use crate::test_support::{parameter_name, random_bytes, random_floats, with_threads};
use crate::texture::mip::{
    MipAlpha, MipLevels, MipOptions, chain_rgba8, full_mip_count, mip_chain_rgba8, mip_chain_rgba16f,
};

/// Sums over the fine cells of one output texel (see [`fine_sums`]).
#[derive(Clone, Copy, Default)]
struct Sums {
    plain: [f64; 4],
    weighted: [f64; 3],
    alpha_weight: f64,
    cells: f64,
}

/// Reference reduction of one level by integrating over a fine grid: with `m = max(1, n/2)`,
/// an axis of `n` texels is cut into `n·m` equal cells; cell `u` lies in source texel `u / m`
/// and in output texel `u / n`. Summing the source value over the cells of an output texel
/// gives the area-weighted box filter without computing any overlap.
fn fine_sums(values: &[[f64; 4]], width: usize, height: usize) -> (usize, usize, Vec<Sums>) {
    let (mw, mh) = ((width / 2).max(1), (height / 2).max(1));
    let mut sums = vec![Sums::default(); mw * mh];
    for v in 0..height * mh {
        for u in 0..width * mw {
            let src = values[(v / mh) * width + u / mw];
            let out = &mut sums[(v / height) * mw + u / width];
            let a = src[3].max(0.0);
            for (sum, value) in out.plain.iter_mut().zip(src) {
                *sum += value;
            }
            for (sum, value) in out.weighted.iter_mut().zip(src) {
                *sum += a * value;
            }
            out.alpha_weight += a;
            out.cells += 1.0;
        }
    }
    (mw, mh, sums)
}

/// The averaged value of each output texel per the module's definition of straight alpha.
fn reference_level(
    values: &[[f64; 4]],
    width: usize,
    height: usize,
    alpha: MipAlpha,
) -> (usize, usize, Vec<[f64; 4]>) {
    let (mw, mh, sums) = fine_sums(values, width, height);
    let out = sums
        .into_iter()
        .map(|s| {
            let mut v = s.plain.map(|p| p / s.cells);
            if alpha == MipAlpha::Straight && s.alpha_weight > 0.0 {
                for (value, weighted) in v.iter_mut().zip(s.weighted) {
                    *value = weighted / s.alpha_weight;
                }
            }
            v
        })
        .collect();
    (mw, mh, out)
}

fn srgb_decode(v: u8) -> f64 {
    let s = f64::from(v) / 255.0;
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

fn srgb_encode(l: f64) -> u8 {
    let l = l.clamp(0.0, 1.0);
    let s = if l <= 0.0031308 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// Reference chain of one RGBA8 layer, each level from the previous reference level.
fn reference_chain_rgba8(
    base: &[u8],
    width: usize,
    height: usize,
    srgb: bool,
    alpha: MipAlpha,
) -> Vec<Vec<u8>> {
    let mut levels = vec![base.to_vec()];
    let (mut w, mut h) = (width, height);
    while w > 1 || h > 1 {
        let values: Vec<[f64; 4]> = levels
            .last()
            .unwrap()
            .chunks_exact(4)
            .map(|p| {
                let c = |v: u8| if srgb { srgb_decode(v) } else { f64::from(v) };
                [c(p[0]), c(p[1]), c(p[2]), f64::from(p[3])]
            })
            .collect();
        let (mw, mh, out) = reference_level(&values, w, h, alpha);
        let bytes = out
            .iter()
            .flat_map(|v| {
                let c = |x: f64| if srgb { srgb_encode(x) } else { x.round() as u8 };
                [c(v[0]), c(v[1]), c(v[2]), v[3].round() as u8]
            })
            .collect();
        levels.push(bytes);
        (w, h) = (mw, mh);
    }
    levels
}

const SIZES: [(usize, usize); 7] = [(8, 8), (7, 5), (5, 1), (1, 6), (3, 3), (16, 5), (1, 1)];

#[test]
fn full_mip_count_is_floor_log2_of_the_larger_side_plus_one() {
    assert_eq!(full_mip_count(1, 1), 1);
    assert_eq!(full_mip_count(2, 1), 2);
    assert_eq!(full_mip_count(13, 7), 4);
    assert_eq!(full_mip_count(128, 128), 8);
    assert_eq!(full_mip_count(1, 1024), 11);
    assert_eq!(full_mip_count(1023, 3), 10);
    assert_eq!(full_mip_count(0, 3), 0);
}

#[test]
fn rgba8_chain_matches_the_fine_grid_reference_in_every_mode() {
    let layers = 2;
    for (i, &(w, h)) in SIZES.iter().enumerate() {
        let mut base = random_bytes(i as u64, w * h * 4 * layers);
        // Some fully transparent texels, so straight alpha has something to ignore.
        for p in base.chunks_exact_mut(4).step_by(3) {
            p[3] = 0;
        }
        for srgb in [false, true] {
            for alpha in [MipAlpha::Straight, MipAlpha::Independent] {
                let options = MipOptions {
                    alpha,
                    ..MipOptions::default()
                };
                let chain = mip_chain_rgba8(w, h, layers, &base, srgb, &options).unwrap();
                assert_eq!(chain.len(), full_mip_count(w, h));
                for layer in 0..layers {
                    let layer_base = &base[layer * w * h * 4..(layer + 1) * w * h * 4];
                    let reference = reference_chain_rgba8(layer_base, w, h, srgb, alpha);
                    assert_eq!(reference.len(), chain.len());
                    for (level, expected) in reference.iter().enumerate() {
                        let n = expected.len();
                        assert_eq!(
                            &chain[level][layer * n..(layer + 1) * n],
                            expected.as_slice(),
                            "{w}x{h} layer {layer} level {level} srgb {srgb} {alpha:?}"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn rgba16f_chain_matches_the_fine_grid_reference() {
    for (i, &(w, h)) in SIZES.iter().enumerate() {
        let base: Vec<f16> = random_floats(100 + i as u64, w * h * 4, -0.25, 2.0)
            .into_iter()
            .map(f16::from_f64)
            .collect();
        let chain = mip_chain_rgba16f(w, h, 1, &base, &MipOptions::default()).unwrap();
        let mut previous: Vec<[f64; 4]> = base
            .chunks_exact(4)
            .map(|p| [p[0], p[1], p[2], p[3]].map(f64::from))
            .collect();
        let (mut lw, mut lh) = (w, h);
        for level in chain.iter().skip(1) {
            let (mw, mh, out) = reference_level(&previous, lw, lh, MipAlpha::Straight);
            let expected: Vec<u16> = out
                .iter()
                .flat_map(|v| v.map(|x| f16::from_f64(x).to_bits()))
                .collect();
            let got: Vec<u16> = level.iter().map(|v| v.to_bits()).collect();
            assert_eq!(got, expected, "{w}x{h}");
            previous = level
                .chunks_exact(4)
                .map(|p| [p[0], p[1], p[2], p[3]].map(f64::from))
                .collect();
            (lw, lh) = (mw, mh);
        }
    }
}

#[test]
fn transparent_texels_do_not_darken_straight_alpha_colors() {
    // One opaque red texel among three transparent black ones.
    let base = [255, 0, 0, 255, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0];
    let straight = mip_chain_rgba8(2, 2, 1, &base, false, &MipOptions::default()).unwrap();
    // Alpha averages to 255 / 4 = 63.75; the color is red alone.
    assert_eq!(straight[1], [255, 0, 0, 64]);
    let independent = MipOptions {
        alpha: MipAlpha::Independent,
        ..MipOptions::default()
    };
    let plain = mip_chain_rgba8(2, 2, 1, &base, false, &independent).unwrap();
    assert_eq!(plain[1], [64, 0, 0, 64]);
}

#[test]
fn constant_layers_stay_constant_at_every_level() {
    let (w, h) = (11, 6);
    let texel = [200u8, 31, 7, 90];
    let base: Vec<u8> = texel.iter().copied().cycle().take(w * h * 4).collect();
    for srgb in [false, true] {
        let chain = mip_chain_rgba8(w, h, 1, &base, srgb, &MipOptions::default()).unwrap();
        for level in &chain {
            assert!(level.chunks_exact(4).all(|p| p == texel), "srgb {srgb}");
        }
    }
}

#[test]
fn level_count_option_truncates_the_chain() {
    let base = random_bytes(5, 16 * 16 * 4);
    let options = MipOptions {
        levels: MipLevels::Count(3),
        ..MipOptions::default()
    };
    let chain = mip_chain_rgba8(16, 16, 1, &base, false, &options).unwrap();
    let sizes: Vec<usize> = chain.iter().map(Vec::len).collect();
    assert_eq!(sizes, [16 * 16 * 4, 8 * 8 * 4, 4 * 4 * 4]);
}

#[test]
fn mip_chain_does_not_depend_on_the_thread_count() {
    let (w, h, layers) = (45, 33, 3);
    let base = random_bytes(8, w * h * 4 * layers);
    let chain = |threads| {
        with_threads(threads, || {
            chain_rgba8(
                w,
                h,
                layers,
                &base,
                true,
                MipAlpha::Straight,
                full_mip_count(w, h),
            )
        })
    };
    assert_eq!(chain(1), chain(2));
}

#[test]
fn bad_sizes_levels_and_samples_are_rejected() {
    let base = [0u8; 16];
    let options = MipOptions::default();
    assert_eq!(
        parameter_name(mip_chain_rgba8(0, 2, 1, &base, false, &options)),
        "width"
    );
    assert_eq!(
        parameter_name(mip_chain_rgba8(65537, 1, 1, &base, false, &options)),
        "width"
    );
    assert_eq!(
        parameter_name(mip_chain_rgba8(2, 2, 0, &base, false, &options)),
        "layers"
    );
    assert_eq!(
        parameter_name(mip_chain_rgba8(2, 1, 1, &base, false, &options)),
        "base"
    );
    for n in [0, 3] {
        let options = MipOptions {
            levels: MipLevels::Count(n),
            ..MipOptions::default()
        };
        assert_eq!(
            parameter_name(mip_chain_rgba8(2, 2, 1, &base, false, &options)),
            "levels"
        );
    }
    let mut halves = vec![f16::ZERO; 16];
    halves[13] = f16::NAN;
    assert_eq!(
        parameter_name(mip_chain_rgba16f(2, 2, 1, &halves, &options)),
        "base"
    );
}
