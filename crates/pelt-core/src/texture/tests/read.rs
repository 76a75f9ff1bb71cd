//! Light probes read back: written by Pelt's EXR writer and by the `image` crate's HDR and PNG
//! encoders, then projected onto SH and compared with the analytic projection of the same sky.

use std::path::PathBuf;

use crate::error::PeltError;
use crate::export::{ExrOptions, PngOptions, save_exr, save_png};
use crate::prt::sh;
use crate::prt::sphere::fibonacci_directions;
use crate::texture::{ImageRef, read_light_probe};

fn temp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("pelt-probe-{}-{name}", std::process::id()))
}

/// The sky `0.6 + 0.4 z` in Pelt's latitude–longitude layout (row 0 at +Z), cell centres.
fn sky(width: usize, height: usize) -> Vec<f32> {
    (0..height)
        .flat_map(|r| {
            let z = (std::f64::consts::PI * (r as f64 + 0.5) / height as f64).cos();
            std::iter::repeat_n((0.6 + 0.4 * z) as f32, 3 * width)
        })
        .collect()
}

/// Order-2 SH of `0.6 + 0.4 z`, by quadrature over many directions.
fn analytic() -> Vec<f64> {
    let dirs = fibonacci_directions(1 << 14);
    let weights = vec![4.0 * std::f64::consts::PI / dirs.len() as f64; dirs.len()];
    let values: Vec<f64> = dirs.iter().map(|d| 0.6 + 0.4 * d[2]).collect();
    sh::project_samples(2, &dirs, &weights, &values).unwrap()
}

#[test]
fn an_exr_and_an_hdr_sky_project_to_the_analytic_coefficients() {
    let (w, h) = (64, 32);
    let rgb = sky(w, h);
    let exr = temp("sky.exr");
    save_exr(
        &exr,
        &ImageRef::new(w, h, 3, &rgb).unwrap(),
        &ExrOptions::default(),
    )
    .unwrap();
    let hdr = temp("sky.hdr");
    let pixels: Vec<image::Rgb<f32>> = rgb
        .chunks_exact(3)
        .map(|p| image::Rgb([p[0], p[1], p[2]]))
        .collect();
    image::codecs::hdr::HdrEncoder::new(std::fs::File::create(&hdr).unwrap())
        .encode(&pixels, w, h)
        .unwrap();
    let want = analytic();
    for (path, tolerance) in [(&exr, 1e-3), (&hdr, 1e-2)] {
        let probe = read_light_probe(path).unwrap();
        assert_eq!((probe.width, probe.height), (w, h));
        let got = sh::project_equirect(2, w, h, &probe.rgb).unwrap();
        for (k, (g, a)) in got.iter().zip(&want).enumerate() {
            for c in g {
                assert!(
                    (c - a).abs() < tolerance,
                    "{}: coefficient {k}: {c} vs {a}",
                    path.display()
                );
            }
        }
        std::fs::remove_file(path).unwrap();
    }
}

#[test]
fn a_png_probe_is_decoded_from_srgb_and_bad_probes_are_named() {
    let png = temp("grey.png");
    let bytes = [128u8; 4 * 3 * 2];
    let options = PngOptions {
        srgb: true,
        ..PngOptions::default()
    };
    save_png(&png, &ImageRef::new(4, 2, 3, &bytes).unwrap(), &options).unwrap();
    let probe = read_light_probe(&png).unwrap();
    // sRGB 128/255 is 0.2158 linear (IEC 61966-2-1).
    assert!(
        probe.rgb.iter().all(|v| (v - 0.215_861).abs() < 1e-5),
        "{:?}",
        &probe.rgb[..3]
    );

    let nan = temp("nan.exr");
    let mut rgb = [1.0f32; 4 * 2 * 3];
    rgb[3 * 5 + 1] = f32::NAN;
    // Pelt's writer refuses NaN, so this one is written by the exr crate itself.
    let samples = |x: usize, y: usize| {
        let p = 3 * (y * 4 + x);
        (rgb[p], rgb[p + 1], rgb[p + 2])
    };
    exr::prelude::write_rgb_file(&nan, 4, 2, samples).unwrap();
    match read_light_probe(&nan) {
        Err(PeltError::InvalidParameter { name, reason }) => {
            assert_eq!(name, "environment");
            assert!(reason.contains("pixel (1, 1) channel 1"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    let text = temp("probe.txt");
    std::fs::write(&text, "not an image").unwrap();
    assert!(matches!(
        read_light_probe(&text),
        Err(PeltError::InvalidParameter { name, .. }) if name == "environment"
    ));
    assert!(matches!(
        read_light_probe(&temp("missing.hdr")),
        Err(PeltError::Io { .. })
    ));
    for path in [png, nan, text] {
        std::fs::remove_file(path).unwrap();
    }
}
