//! Golden images (DESIGN.md §3): reference PNGs under `tests/golden/`. A missing reference is
//! written on the first run (under `CI=true` it fails instead: a golden must be committed), and
//! every reference is rewritten with `PELT_UPDATE_GOLDEN=1` (look at them, then commit them with
//! the change). A mismatch writes `<name>-actual.png` and `<name>-diff.png` (the per-pixel
//! largest channel difference, amplified ×8, as gray) next to the test binary's temporary folder
//! and fails, naming both. Bakes compare channel values; renders compare by ꟻLIP.

use std::path::{Path, PathBuf};

use pelt::export::{PngOptions, save_png};
use pelt::texture::ImageRef;

/// How far an image may stray from its reference, channel by channel.
#[derive(Debug, Clone, Copy)]
pub struct Tolerance {
    /// Largest difference of any channel value (0–255).
    pub worst: u8,
    /// Largest share of channel values that differ at all.
    pub share: f64,
    /// Largest mean difference over all channel values.
    pub mean: f64,
}

impl Tolerance {
    /// The bake's bound: deterministic CPU output, only floating-point library differences
    /// between platforms (a few units on a few values).
    pub const BAKE: Tolerance = Tolerance {
        worst: 2,
        share: 0.001,
        mean: 0.01,
    };
}

pub fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

/// An 8-bit RGBA PNG: width, height, pixels.
pub fn read_png(path: &Path) -> (usize, usize, Vec<u8>) {
    let rgba = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_rgba8();
    let (width, height) = rgba.dimensions();
    (width as usize, height as usize, rgba.into_raw())
}

fn save(path: &Path, width: usize, height: usize, pixels: &[u8]) {
    let image = ImageRef::new(width, height, 4, pixels).unwrap();
    let options = PngOptions {
        srgb: true,
        ..PngOptions::default()
    };
    save_png(path, &image, &options).unwrap();
}

/// The golden image `name`, or `None` once `pixels` were written as it (missing, or
/// `PELT_UPDATE_GOLDEN` set). Under `CI=true` a missing golden fails.
fn golden_or_write(name: &str, width: usize, height: usize, pixels: &[u8]) -> Option<Vec<u8>> {
    let path = golden_dir().join(name);
    if std::env::var_os("PELT_UPDATE_GOLDEN").is_none() && path.exists() {
        let (w, h, golden) = read_png(&path);
        assert_eq!((w, h), (width, height), "{name}: size");
        return Some(golden);
    }
    assert!(
        path.exists() || std::env::var("CI").as_deref() != Ok("true"),
        "{name}: no golden image under tests/golden (CI=true: run the test locally, look at the \
         image it writes and commit it)"
    );
    save(&path, width, height, pixels);
    None
}

/// Mean ꟻLIP (`nv-flip`, as wgpu's own tests use) between RGBA8 straight-alpha sRGB images, both
/// over middle grey.
#[cfg(feature = "metrics")]
pub fn flip_mean(width: usize, height: usize, a: &[u8], b: &[u8]) -> f64 {
    let over_grey = |rgba: &[u8]| -> Vec<u8> {
        rgba.chunks_exact(4)
            .flat_map(|p| {
                let alpha = f32::from(p[3]) / 255.0;
                [0, 1, 2].map(|c| (f32::from(p[c]) * alpha + 128.0 * (1.0 - alpha)).round() as u8)
            })
            .collect()
    };
    let (w, h) = (width as u32, height as u32);
    let map = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w, h, &over_grey(a)),
        nv_flip::FlipImageRgb8::with_data(w, h, &over_grey(b)),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let values = map.to_vec();
    values.iter().map(|&v| f64::from(v)).sum::<f64>() / values.len().max(1) as f64
}

/// Largest mean ꟻLIP a render on the CPU adapter may stray from its golden. One Mesa build is
/// bit-identical; another may filter or round blends a little differently, moving single hair
/// pixels a lot but the image's mean ꟻLIP little. A light 1% brighter or dimmer moves the
/// frontal Kajiya–Kay golden by 0.0093 (checked by
/// `golden_render::the_bound_catches_a_light_one_percent_brighter`); values 5 units apart on 4%
/// of the silhouette's channels moved it by 0.0039.
#[cfg(feature = "metrics")]
pub const RENDER_FLIP: f64 = 0.003;

/// Compares a render's RGBA8 `pixels` with the golden file `name` by mean ꟻLIP (at most
/// [`RENDER_FLIP`]), or writes the file when it is missing (not under `CI=true`) or
/// `PELT_UPDATE_GOLDEN` is set.
#[cfg(feature = "metrics")]
pub fn check_render(name: &str, width: usize, height: usize, pixels: &[u8]) {
    let Some(golden) = golden_or_write(name, width, height, pixels) else {
        return;
    };
    let flip = flip_mean(width, height, &golden, pixels);
    if flip <= RENDER_FLIP {
        return;
    }
    let (actual, diff) = write_mismatch(name, width, height, &golden, pixels);
    panic!(
        "{name}: mean ꟻLIP {flip:.5} against the golden (allowed {RENDER_FLIP}); actual image {}, \
         difference {}",
        actual.display(),
        diff.display()
    );
}

/// Compares RGBA8 `pixels` with the golden file `name` within `tolerance`, or writes the file
/// when it is missing (not under `CI=true`) or `PELT_UPDATE_GOLDEN` is set.
pub fn check(name: &str, width: usize, height: usize, pixels: &[u8], tolerance: Tolerance) {
    let Some(golden) = golden_or_write(name, width, height, pixels) else {
        return;
    };
    let differing = golden.iter().zip(pixels).filter(|(a, b)| a != b).count();
    let worst = golden
        .iter()
        .zip(pixels)
        .map(|(a, b)| a.abs_diff(*b))
        .max()
        .unwrap_or(0);
    let mean = golden
        .iter()
        .zip(pixels)
        .map(|(a, b)| f64::from(a.abs_diff(*b)))
        .sum::<f64>()
        / pixels.len().max(1) as f64;
    if worst <= tolerance.worst
        && differing as f64 <= tolerance.share * pixels.len() as f64
        && mean <= tolerance.mean
    {
        return;
    }
    let (actual, diff_path) = write_mismatch(name, width, height, &golden, pixels);
    panic!(
        "{name}: {differing} channel values differ (worst by {worst}, mean {mean:.3}; allowed \
         {tolerance:?}); actual image {}, difference {}",
        actual.display(),
        diff_path.display()
    );
}

/// Writes `<name>-actual.png` and `<name>-diff.png` into the test binary's temporary folder.
fn write_mismatch(
    name: &str,
    width: usize,
    height: usize,
    golden: &[u8],
    pixels: &[u8],
) -> (PathBuf, PathBuf) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let stem = name.trim_end_matches(".png");
    let actual = dir.join(format!("{stem}-actual.png"));
    let diff_path = dir.join(format!("{stem}-diff.png"));
    save(&actual, width, height, pixels);
    let diff: Vec<u8> = golden
        .chunks_exact(4)
        .zip(pixels.chunks_exact(4))
        .flat_map(|(a, b)| {
            let d = a.iter().zip(b).map(|(x, y)| x.abs_diff(*y)).max().unwrap_or(0);
            let v = d.saturating_mul(8);
            [v, v, v, 255]
        })
        .collect();
    save(&diff_path, width, height, &diff);
    (actual, diff_path)
}
