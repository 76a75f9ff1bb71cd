//! The `pelt` command line, run as a subprocess: `bake` writes what `pelt.json` lists, the same
//! bytes for 1 and 2 threads and across runs; `export` writes a folder again; bad input ends
//! with a message and exit status 1, never a panic.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use bake::{SMALL_BAKE, suzanne};
use pelt::export::Manifest;

/// The small bake the root package's integration tests share.
#[path = "../../../tests/common/bake.rs"]
mod bake;

const PELT: &str = env!("CARGO_BIN_EXE_pelt");

fn out_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("cli-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Runs `pelt` with `args` and `PELT_THREADS=threads`.
fn pelt(args: &[&str], threads: usize) -> Output {
    Command::new(PELT)
        .args(args)
        .env("PELT_THREADS", threads.to_string())
        .output()
        .unwrap()
}

/// A small bake of Suzanne (few small layers, order-2 transfer) into `dir`.
fn bake(dir: &Path, threads: usize, extra: &[&str]) -> Output {
    let mesh = suzanne();
    let mut args = vec!["bake", mesh.to_str().unwrap(), "--out", dir.to_str().unwrap()];
    args.extend_from_slice(&SMALL_BAKE);
    args.extend_from_slice(extra);
    pelt(&args, threads)
}

/// Every file of a folder by name.
fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect()
}

/// Every entry of a folder (a file's bytes, or nothing for a folder) by name.
fn files_or_folders(dir: &Path) -> BTreeMap<String, Option<Vec<u8>>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let path = e.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            (name, path.is_file().then(|| std::fs::read(&path).unwrap()))
        })
        .collect()
}

fn assert_ok(output: &Output) {
    assert!(
        output.status.success(),
        "pelt failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
}

#[test]
fn bake_writes_what_the_manifest_lists_identically_for_any_thread_count() {
    let (one, two) = (out_dir("bake-1"), out_dir("bake-2"));
    assert_ok(&bake(&one, 1, &[]));
    assert_ok(&bake(&two, 2, &[]));
    let manifest = Manifest::load(&one).unwrap();
    assert_eq!(manifest.objects.len(), 1);
    assert_eq!(manifest.objects[0].name, "suzanne");
    let mut listed: Vec<&str> = manifest
        .objects
        .iter()
        .flat_map(|o| &o.files)
        .chain(&manifest.files)
        .map(|f| f.path.as_str())
        .chain(["pelt.json", "bake.json"])
        .collect();
    listed.sort_unstable();
    let (a, b) = (files(&one), files(&two));
    assert_eq!(listed, a.keys().map(String::as_str).collect::<Vec<_>>());
    assert!(a.contains_key("suzanne_engine.glb") && a.contains_key("suzanne_geometry.glb"));
    assert!(a.contains_key("suzanne_shells.ktx2") && a.contains_key("suzanne_density.exr"));
    // Everything but the record of where the output went is byte-identical.
    for (name, bytes) in &a {
        if name != "bake.json" {
            assert!(bytes == &b[name], "{name} differs between 1 and 2 threads");
        }
    }

    // `export` writes the folder again from bake.json: another folder, PNG and geometry only.
    let again = out_dir("export");
    let output = pelt(
        &[
            "export",
            one.to_str().unwrap(),
            "--out",
            again.to_str().unwrap(),
            "--formats",
            "png",
            "--mode",
            "geometry",
        ],
        2,
    );
    assert_ok(&output);
    let c = files(&again);
    assert!(!c.contains_key("suzanne_engine.glb") && !c.contains_key("suzanne_shells.ktx2"));
    for name in [
        "suzanne_geometry.glb",
        "suzanne_layer_003.png",
        "suzanne_shells_atlas.png",
    ] {
        assert!(c[name] == a[name], "{name} differs after export");
    }

    // A folder where the last file should go: the export fails and the previous output stays as
    // it was, with no half-written files beside it.
    std::fs::remove_file(again.join("bake.json")).unwrap();
    std::fs::create_dir(again.join("bake.json")).unwrap();
    let before = files_or_folders(&again);
    let output = pelt(
        &["export", one.to_str().unwrap(), "--out", again.to_str().unwrap()],
        2,
    );
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("bake.json"));
    assert_eq!(files_or_folders(&again), before);
    let parent = again.parent().unwrap();
    let strays: Vec<_> = std::fs::read_dir(parent)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp"))
        .collect();
    assert!(strays.is_empty(), "{strays:?}");
    for dir in [one, two, again] {
        std::fs::remove_dir_all(dir).unwrap();
    }
}

#[test]
fn guard_hairs_bake_into_the_engine_file_and_export_again() {
    // In a folder of its own: the staging folders beside these outputs must not show up beside
    // those of the test that checks for strays, which runs at the same time.
    let dir = out_dir("guard/baked");
    assert_ok(&bake(
        &dir,
        2,
        &[
            "--guard-hairs",
            "--tile-size",
            "1.0",
            "--formats",
            "png",
            "--mode",
            "engine",
        ],
    ));
    let read = |dir: &Path| {
        let bytes = std::fs::read(dir.join("suzanne_engine.glb")).unwrap();
        let length = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        serde_json::from_slice::<serde_json::Value>(&bytes[20..20 + length]).unwrap()
    };
    let json = read(&dir);
    let fur = &json["meshes"][0]["primitives"][0]["extensions"]["PELT_shell_fur"];
    assert!(fur["guardHairs"]["strands"].as_u64().unwrap() > 10, "{fur}");
    // bake.json keeps the choice: `export` writes the same file again.
    let again = out_dir("guard/exported");
    assert_ok(&pelt(
        &[
            "export",
            dir.to_str().unwrap(),
            "--out",
            again.to_str().unwrap(),
            "--formats",
            "png",
        ],
        2,
    ));
    assert_eq!(read(&again)["meshes"], json["meshes"]);
    for dir in [dir, again] {
        std::fs::remove_dir_all(dir).unwrap();
    }
}

#[test]
fn planes_bake_their_slices_and_bake_json_keeps_the_count() {
    let dir = out_dir("planes");
    let output = bake(&dir, 2, &["--planes", "4", "--formats", "png"]);
    assert_ok(&output);
    // The stage's report line, on stderr with the others.
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("planes") && stderr.contains("4 planes per axis"),
        "{stderr}"
    );
    let record: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("bake.json")).unwrap()).unwrap();
    assert_eq!(record["planes"], 4, "{record}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn bad_input_exits_with_a_message_and_no_panic() {
    let dir = out_dir("bad");
    std::fs::create_dir_all(&dir).unwrap();
    let broken = dir.join("broken.glb");
    std::fs::write(&broken, b"glTF\x02\0\0\0\x10\0\0\0").unwrap();
    let nan = dir.join("nan.obj");
    std::fs::write(&nan, "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n").unwrap();
    // POSITION names an accessor that does not exist (the validator indexed it and panicked).
    let dangling = dir.join("dangling.gltf");
    std::fs::write(
        &dangling,
        r#"{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {"POSITION": 3}}]}]}"#,
    )
    .unwrap();
    // A buffer outside the file's folder: its bytes would end up in the baked output.
    let passwd = dir.join("passwd.gltf");
    std::fs::write(
        &passwd,
        r#"{"asset": {"version": "2.0"}, "buffers": [{"uri": "/etc/passwd", "byteLength": 36}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}],
            "accessors": [{"bufferView": 0, "count": 3, "componentType": 5126, "type": "VEC3",
                           "min": [0, 0, 0], "max": [1, 1, 1]}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}]}"#,
    )
    .unwrap();
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    for (args, needle) in [
        (vec!["bake", broken.to_str().unwrap(), "--out", out], "broken.glb"),
        (vec!["bake", nan.to_str().unwrap(), "--out", out], "nan"),
        (vec!["bake", "missing.obj", "--out", out], "missing.obj"),
        (vec!["bake", "mesh.stl", "--out", out], "unknown mesh format"),
        (
            vec!["bake", nan.to_str().unwrap(), "--out", out, "--preset", "fluffy"],
            "preset",
        ),
        (
            vec!["bake", nan.to_str().unwrap(), "--out", out, "--formats", "tga"],
            "formats",
        ),
        (
            vec!["bake", nan.to_str().unwrap(), "--out", out, "--mode", "both-ways"],
            "--mode",
        ),
        (vec!["export", dir.to_str().unwrap()], "bake.json"),
        (
            vec!["bake", dangling.to_str().unwrap(), "--out", out],
            "accessor 3",
        ),
        (
            vec!["bake", passwd.to_str().unwrap(), "--out", out],
            "inside the file's folder",
        ),
        (
            vec!["bake", "missing.obj", "--out", out, "--planes", "257"],
            "`planes`: must be in [0, 256], got 257",
        ),
    ] {
        let output = pelt(&args, 2);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.starts_with("pelt: ") && stderr.contains(needle),
            "{args:?}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    // A bake larger than the memory limit stops before any stage, naming what to lower.
    let mesh = suzanne();
    let huge = [
        "bake",
        mesh.to_str().unwrap(),
        "--out",
        out,
        "--resolution",
        "4096",
    ];
    for (extra, needle) in [
        (
            vec!["--layers", "256"],
            "layers·resolution² must be at most 1073741824",
        ),
        (
            vec!["--layers", "64", "--memory-limit", "1G"],
            "above the memory limit of 1.0 GiB",
        ),
        (vec!["--layers", "64", "--memory-limit", "lots"], "--memory-limit"),
    ] {
        let args: Vec<&str> = huge.iter().copied().chain(extra).collect();
        let output = pelt(&args, 2);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains(needle), "{stderr}");
        assert!(
            stderr.contains("`resolution` (4096)") || !needle.contains("memory limit"),
            "{stderr}"
        );
    }
    // A thread count that would take minutes to start is refused at once, by name.
    let output = pelt(&["bake", "missing.obj", "--out", out], 100_000);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("PELT_THREADS") && stderr.contains("[1, 1024]"),
        "{stderr}"
    );
    assert!(!Path::new(out).exists(), "nothing is written on bad input");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn reference_renders_a_baked_folder_and_writes_nothing_on_bad_input() {
    let dir = out_dir("reference");
    // A tile as wide as Suzanne's ears keeps the strands few.
    assert_ok(&bake(&dir, 2, &["--tile-size", "1.0", "--formats", "png"]));
    let exr = dir.join("reference.exr");
    let exr_arg = exr.to_str().unwrap();
    let zero = pelt(
        &[
            "reference",
            dir.to_str().unwrap(),
            "--out",
            exr_arg,
            "--samples",
            "0",
        ],
        2,
    );
    assert!(!zero.status.success());
    let message = String::from_utf8_lossy(&zero.stderr);
    assert!(message.contains("min_samples"), "{message}");
    let unknown = pelt(&["reference", "sphere.furry.side", "--out", exr_arg], 2);
    assert!(!unknown.status.success());
    assert!(String::from_utf8_lossy(&unknown.stderr).contains("canonical scene"));
    assert!(!exr.exists());

    let output = pelt(
        &[
            "reference",
            dir.to_str().unwrap(),
            "--out",
            exr_arg,
            "--size",
            "24",
            "--samples",
            "2",
        ],
        2,
    );
    assert_ok(&output);
    let written = files(&dir);
    assert!(written.contains_key("reference.exr") && written.contains_key("reference.png"));
    assert!(!written.keys().any(|name| name.ends_with(".part")));
    let png = image::load_from_memory(&written["reference.png"]).unwrap();
    assert_eq!((png.width(), png.height()), (24, 24));

    // The volume mode renders the same folder's baked volume.
    let volume = dir.join("volume.exr");
    let output = pelt(
        &[
            "reference",
            dir.to_str().unwrap(),
            "--out",
            volume.to_str().unwrap(),
            "--size",
            "16",
            "--samples",
            "2",
            "--mode",
            "volume",
        ],
        2,
    );
    assert_ok(&output);
    assert!(String::from_utf8_lossy(&output.stderr).contains("prisms"));
    assert!(volume.exists() && dir.join("volume.png").exists());
}

#[test]
fn reference_lit_by_a_light_probe_matches_the_same_sky_given_analytically() {
    let dir = out_dir("reference-probe");
    std::fs::create_dir_all(&dir).unwrap();
    // The canonical scenes' environment, `0.6 + 0.4 z`, as a latitude–longitude EXR (row 0 at +Z).
    let (w, h) = (64usize, 32usize);
    let rgb: Vec<f32> = (0..h)
        .flat_map(|r| {
            let z = (std::f64::consts::PI * (r as f64 + 0.5) / h as f64).cos();
            std::iter::repeat_n((0.6 + 0.4 * z) as f32, 3 * w)
        })
        .collect();
    let sky = dir.join("sky.exr");
    let image = pelt::texture::ImageRef::new(w, h, 3, &rgb).unwrap();
    pelt::export::save_exr(&sky, &image, &pelt::export::ExrOptions::default()).unwrap();
    let render = |source: &str, out: &str, extra: &[&str]| {
        let out = dir.join(out);
        let mut args = vec!["reference", source, "--out", out.to_str().unwrap()];
        args.extend_from_slice(&["--size", "24", "--samples", "8", "--target-error", "0.05"]);
        args.extend_from_slice(extra);
        assert_ok(&pelt(&args, 2));
        let png = image::open(out.with_extension("png")).unwrap().to_rgba8();
        png.pixels().map(|p| f64::from(p[0])).sum::<f64>() / f64::from(png.width() * png.height())
    };
    let analytic = render("patch.short.environment", "analytic.exr", &[]);
    // The side scene's sun would light it quite differently: the probe replaces it.
    let probe = render(
        "patch.short.side",
        "probe.exr",
        &["--environment", sky.to_str().unwrap(), "--environment-order", "2"],
    );
    assert!(analytic > 10.0, "the patch is lit: {analytic}");
    assert!(
        (probe / analytic - 1.0).abs() < 0.02,
        "probe {probe} vs analytic {analytic}"
    );

    let bad = dir.join("bad.hdr");
    std::fs::write(&bad, "#?RADIANCE\nnot really").unwrap();
    let out = dir.join("bad.exr");
    let output = pelt(
        &[
            "reference",
            "patch.short.eye",
            "--out",
            out.to_str().unwrap(),
            "--environment",
            bad.to_str().unwrap(),
        ],
        2,
    );
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("bad.hdr"));
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
