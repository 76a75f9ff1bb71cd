//! `pelt view` run as a subprocess: on a small baked folder under a virtual X server
//! (`xvfb-run`) on the CPU adapter, it draws a few frames, exits with status 0 and saves a
//! screenshot that shows the furred mesh over the background; bad folders end with a one-line
//! error and status 1. Skipped, with the reason printed, only when `xvfb-run` is not installed;
//! when it is but no X server starts, the test fails.
#![cfg(feature = "viewer")]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use bake::{SMALL_BAKE, suzanne};

/// The small bake the root package's integration tests share.
#[path = "../../../tests/common/bake.rs"]
mod bake;

const PELT: &str = env!("CARGO_BIN_EXE_pelt");
/// Window side of the test.
const SIDE: u32 = 64;

fn out_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("viewer-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// `xvfb-run` on the PATH, if any.
fn xvfb_run() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join("xvfb-run"))
        .find(|p| p.is_file())
}

/// A small bake of Suzanne: few small layers, order-2 transfer, PNG textures only.
fn bake(dir: &Path) {
    let mesh = suzanne();
    let output = Command::new(PELT)
        .args(["bake", mesh.to_str().unwrap(), "--out", dir.to_str().unwrap()])
        .args(SMALL_BAKE)
        .args(["--formats", "png", "--mode", "geometry"])
        .output()
        .unwrap();
    assert!(output.status.success(), "pelt bake failed: {}", stderr(&output));
}

/// Decodes an 8-bit RGBA PNG.
fn read_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let decoded = image::open(path).unwrap();
    let image::DynamicImage::ImageRgba8(rgba) = decoded else {
        panic!("expected 8-bit RGBA, got {:?}", decoded.color());
    };
    let (width, height) = rgba.dimensions();
    (width, height, rgba.into_raw())
}

#[test]
fn the_viewer_draws_frames_under_xvfb_and_saves_the_fur() {
    let Some(xvfb) = xvfb_run() else {
        eprintln!("skipped: xvfb-run is not installed (Debian package xvfb), so no window can open");
        return;
    };
    let dir = out_dir("suzanne");
    let asset = dir.join("asset");
    bake(&asset);
    let shot = dir.join("shot.png");
    let size = format!("{SIDE}x{SIDE}");
    // `timeout` ends a viewer that never gets a frame; `-a` picks a free display number.
    let output = Command::new("timeout")
        .arg("300")
        .arg(&xvfb)
        .args(["-a", "-s", "-screen 0 320x240x24", PELT, "view"])
        .arg(&asset)
        .args([
            "--adapter",
            "cpu",
            "--frames",
            "3",
            "--size",
            &size,
            "--screenshot",
        ])
        .arg(&shot)
        .output()
        .unwrap();
    let err = stderr(&output);
    assert!(
        !err.contains("Xvfb failed to start"),
        "no X server could start under xvfb-run, so the viewer was not tested: {err}"
    );
    assert!(
        output.status.code() != Some(124),
        "pelt view did not finish 3 frames within 300 s: {err}"
    );
    assert!(
        output.status.success(),
        "pelt view failed ({}): {err}",
        output.status
    );
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("controls:"), "the controls are printed: {stdout}");

    let (width, height, pixels) = read_png(&shot);
    assert_eq!((width, height), (SIDE, SIDE));
    let pixel = |x: u32, y: u32| -> &[u8] {
        let i = 4 * (y * SIDE + x) as usize;
        &pixels[i..i + 4]
    };
    // The corners are background, the same opaque colour; the mesh fills the middle.
    let background = pixel(0, 0);
    assert_eq!(background[3], 255, "an opaque background");
    for (x, y) in [(SIDE - 1, 0), (0, SIDE - 1), (SIDE - 1, SIDE - 1)] {
        assert_eq!(pixel(x, y), background, "corner ({x}, {y})");
    }
    assert_ne!(pixel(SIDE / 2, SIDE / 2), background, "the centre shows the mesh");
    let covered = pixels.chunks_exact(4).filter(|p| *p != background).count();
    let share = covered as f64 / f64::from(SIDE * SIDE);
    assert!(
        (0.1..0.9).contains(&share),
        "the mesh covers {share:.2} of the image"
    );
    // Shaded fur, not a flat silhouette.
    let colours: std::collections::HashSet<&[u8]> = pixels.chunks_exact(4).collect();
    assert!(colours.len() > 50, "only {} colours", colours.len());
}

/// Runs `pelt view` on `dir` (no window is opened: the folder is read first).
fn view(dir: &Path, extra: &[&str]) -> Output {
    Command::new(PELT)
        .arg("view")
        .arg(dir)
        .args(extra)
        .output()
        .unwrap()
}

fn assert_one_line_error(output: &Output, needle: &str) {
    let err = stderr(output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    assert!(err.contains(needle), "{needle:?} missing from {err:?}");
}

#[test]
fn bad_folders_end_with_one_line_and_status_1() {
    let empty = out_dir("empty");
    assert_one_line_error(&view(&empty, &[]), "bake.json");
    assert_one_line_error(&view(&empty.join("missing"), &[]), "bake.json");
    let corrupt = out_dir("corrupt");
    std::fs::write(corrupt.join("bake.json"), "{ not json").unwrap();
    assert_one_line_error(&view(&corrupt, &[]), "not a Pelt bake record");
    // A record whose mesh is gone.
    let moved = out_dir("moved");
    let record = r#"{"mesh": "/nonexistent/pelt-mesh.obj", "out": "x", "comb": null, "preset": "mink",
        "mode": "both", "formats": "png", "layers": null, "resolution": null, "fur_depth": null,
        "tile_size": null, "no_transfer": false, "order": null, "no_fins": false}"#;
    std::fs::write(moved.join("bake.json"), record).unwrap();
    assert_one_line_error(&view(&moved, &[]), "pelt-mesh.obj");
}

#[test]
fn an_unknown_object_is_named_with_the_ones_there_are() {
    let dir = out_dir("object");
    let mesh = suzanne();
    let record = format!(
        r#"{{"mesh": {mesh:?}, "out": "x", "comb": null, "preset": "mink", "mode": "both",
        "formats": "png", "layers": 4, "resolution": 16, "fur_depth": null, "tile_size": null,
        "no_transfer": true, "order": null, "no_fins": false}}"#
    );
    std::fs::write(dir.join("bake.json"), record).unwrap();
    let output = view(&dir, &["--object", "Cube"]);
    assert_one_line_error(&output, "no object \"Cube\"");
    assert!(stderr(&output).contains("suzanne"));
}
