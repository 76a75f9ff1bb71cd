//! Golden images of the default hair volume: the shell atlas and the fin texture.
//!
//! The bake is deterministic, so these images only change when the hair model or the sampling
//! changes on purpose; then regenerate them with `PELT_UPDATE_GOLDEN=1 cargo test --test
//! golden_volume`, look at them, and commit them with the change. A few units of difference on a
//! handful of texels are tolerated, for floating-point library differences between platforms.

use std::path::{Path, PathBuf};

use pelt::export::{AtlasLayout, ImageRef, PngOptions, pack_atlas, save_png};
use pelt::hair::HairParams;
use pelt::volume::{VolumeParams, bake_volume};

fn golden_dir() -> PathBuf {
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

/// Compares `pixels` with the golden file `name` (or writes it when updating).
fn check(name: &str, width: usize, height: usize, pixels: &[u8]) {
    let path = golden_dir().join(name);
    let image = ImageRef::new(width, height, 4, pixels).unwrap();
    let options = PngOptions {
        srgb: true,
        ..PngOptions::default()
    };
    if std::env::var_os("PELT_UPDATE_GOLDEN").is_some() {
        save_png(&path, &image, &options).unwrap();
        return;
    }
    let (w, h, golden) = read_png(&path);
    assert_eq!((w, h), (width, height), "{name}: size");
    let differing: Vec<u8> = golden
        .iter()
        .zip(pixels)
        .map(|(a, b)| a.abs_diff(*b))
        .filter(|&d| d > 0)
        .collect();
    let worst = differing.iter().copied().max().unwrap_or(0);
    let ok = worst <= 2 && differing.len() * 1000 <= pixels.len();
    if !ok {
        let actual = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
        save_png(&actual, &image, &options).unwrap();
        panic!(
            "{name}: {} channel values differ (worst by {worst}); actual image in {}",
            differing.len(),
            actual.display()
        );
    }
}

#[test]
fn default_shell_atlas_and_fin_match_the_golden_images() {
    let volume = bake_volume(&HairParams::default(), &VolumeParams::default(), None).unwrap();
    let layout = AtlasLayout::new(volume.layers, volume.resolution).unwrap();
    let atlas = pack_atlas(&layout, 4, &volume.shells).unwrap();
    check(
        "shell_atlas.png",
        layout.width,
        layout.height,
        atlas.view().data(),
    );
    let [fw, fh] = volume.fin_size;
    check("fin.png", fw, fh, &volume.fin);
}
