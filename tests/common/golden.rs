//! Golden images (DESIGN.md §3): reference PNGs under `tests/golden/`. A missing reference is
//! written on the first run, and every reference is rewritten with `PELT_UPDATE_GOLDEN=1` (look
//! at them, then commit them with the change). A mismatch writes `<name>-actual.png` and
//! `<name>-diff.png` (the per-pixel largest channel difference, amplified ×8, as gray) next to
//! the test binary's temporary folder and fails, naming both.

use std::path::{Path, PathBuf};

use pelt::export::{ImageRef, PngOptions, save_png};

/// How far an image may stray from its reference.
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

    /// A render on the CPU adapter: bit-identical on one Mesa build, but another version may
    /// filter textures or round blends a little differently, and a hair texel landing one pixel
    /// over changes that pixel a lot. So single values may move freely, while the mean over the
    /// image may move by half a unit: a real change of shading or geometry (a light 1 % brighter,
    /// a silhouette a pixel wider) moves it by more.
    pub const RENDER: Tolerance = Tolerance {
        worst: 255,
        share: 1.0,
        mean: 0.5,
    };
}

pub fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

fn read_png(path: &Path) -> (usize, usize, Vec<u8>) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let mut data = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut data).unwrap();
    data.truncate(info.buffer_size());
    (info.width as usize, info.height as usize, data)
}

fn save(path: &Path, width: usize, height: usize, pixels: &[u8]) {
    let image = ImageRef::new(width, height, 4, pixels).unwrap();
    let options = PngOptions {
        srgb: true,
        ..PngOptions::default()
    };
    save_png(path, &image, &options).unwrap();
}

/// Compares RGBA8 `pixels` with the golden file `name` within `tolerance`, or writes the file
/// when it is missing or `PELT_UPDATE_GOLDEN` is set.
pub fn check(name: &str, width: usize, height: usize, pixels: &[u8], tolerance: Tolerance) {
    let path = golden_dir().join(name);
    if std::env::var_os("PELT_UPDATE_GOLDEN").is_some() || !path.exists() {
        save(&path, width, height, pixels);
        return;
    }
    let (w, h, golden) = read_png(&path);
    assert_eq!((w, h), (width, height), "{name}: size");
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
    panic!(
        "{name}: {differing} channel values differ (worst by {worst}, mean {mean:.3}; allowed \
         {tolerance:?}); actual image {}, difference {}",
        actual.display(),
        diff_path.display()
    );
}
