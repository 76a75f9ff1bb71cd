use std::collections::HashMap;
use std::io::Cursor;

use ::exr::prelude::traits::*;
use ::exr::prelude::{FlatSamples, read};
use half::f16;

use super::{parameter_name, random_floats, temp_dir, with_threads};
use crate::export::exr::{ExrCompression, ExrOptions, ExrSample, encode_exr, save_exr, write_exr};
use crate::texture::image::ImageRef;

/// What the `exr` crate reads back: size, compression, and each channel's samples by name.
struct Decoded {
    width: usize,
    height: usize,
    compression: ::exr::compression::Compression,
    channels: HashMap<String, FlatSamples>,
    /// Channel names in file order.
    names: Vec<String>,
}

fn decode(bytes: &[u8]) -> Decoded {
    // Pedantic header parse first: it rejects attributes the lenient image reader would skip.
    ::exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), true).unwrap();
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .non_parallel()
        .pedantic()
        .from_buffered(Cursor::new(bytes))
        .unwrap();
    assert_eq!(image.layer_data.len(), 1);
    let layer = &image.layer_data[0];
    let names = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    Decoded {
        width: layer.size.0,
        height: layer.size.1,
        compression: layer.encoding.compression,
        channels: layer
            .channel_data
            .list
            .iter()
            .map(|c| (c.name.to_string(), c.sample_data.clone()))
            .collect(),
        names,
    }
}

fn encode<T: ExrSample>(image: &ImageRef<'_, T>, options: &ExrOptions) -> Vec<u8> {
    let mut out = Vec::new();
    write_exr(&mut out, image, options).unwrap();
    out
}

/// Samples of channel `c` of an interleaved image, row by row.
fn channel<T: Copy>(data: &[T], channels: usize, c: usize) -> Vec<T> {
    data.iter().skip(c).step_by(channels).copied().collect()
}

fn f32_bits(samples: &FlatSamples) -> Vec<u32> {
    match samples {
        FlatSamples::F32(v) => v.iter().map(|s| s.to_bits()).collect(),
        other => panic!("expected FLOAT samples, got {other:?}"),
    }
}

fn f16_bits(samples: &FlatSamples) -> Vec<u16> {
    match samples {
        FlatSamples::F16(v) => v.iter().map(|s| s.to_bits()).collect(),
        other => panic!("expected HALF samples, got {other:?}"),
    }
}

/// Values spanning signs, magnitudes and subnormals, which the byte predictor must not disturb.
fn awkward_f32(seed: u64, n: usize) -> Vec<f32> {
    random_floats(seed, n, -1.0, 1.0)
        .into_iter()
        .enumerate()
        .map(|(i, v)| match i % 5 {
            0 => v as f32 * 1e30,
            1 => v as f32 * 1e-40,
            2 => 0.0,
            _ => v as f32,
        })
        .collect()
}

#[test]
fn f32_rgba_round_trips_bit_exact_with_zip_and_none() {
    // 37 × 23: blocks of 16 lines leave a partial last block.
    let (w, h) = (37, 23);
    let data = awkward_f32(1, w * h * 4);
    let image = ImageRef::new(w, h, 4, &data).unwrap();
    for (compression, expected) in [
        (ExrCompression::Zip, ::exr::compression::Compression::ZIP16),
        (
            ExrCompression::None,
            ::exr::compression::Compression::Uncompressed,
        ),
    ] {
        let options = ExrOptions {
            compression,
            ..ExrOptions::default()
        };
        let decoded = decode(&encode(&image, &options));
        assert_eq!((decoded.width, decoded.height), (w, h));
        assert_eq!(decoded.compression, expected);
        // The file lists channels alphabetically.
        assert_eq!(decoded.names, ["A", "B", "G", "R"]);
        for (c, name) in ["R", "G", "B", "A"].iter().enumerate() {
            let expected: Vec<u32> = channel(&data, 4, c).iter().map(|v| v.to_bits()).collect();
            assert_eq!(f32_bits(&decoded.channels[*name]), expected, "channel {name}");
        }
    }
}

#[test]
fn f16_round_trips_bit_exact_with_default_names_for_each_channel_count() {
    let (w, h) = (19, 40);
    let default_names: [&[&str]; 4] = [&["Y"], &["Y", "A"], &["R", "G", "B"], &["R", "G", "B", "A"]];
    for channels in 1..=4 {
        let data: Vec<f16> = random_floats(channels as u64, w * h * channels, -4.0, 4.0)
            .into_iter()
            .map(f16::from_f64)
            .collect();
        let image = ImageRef::new(w, h, channels, &data).unwrap();
        let decoded = decode(&encode(&image, &ExrOptions::default()));
        assert_eq!((decoded.width, decoded.height), (w, h));
        assert_eq!(decoded.channels.len(), channels);
        for (c, name) in default_names[channels - 1].iter().enumerate() {
            let expected: Vec<u16> = channel(&data, channels, c).iter().map(|v| v.to_bits()).collect();
            assert_eq!(f16_bits(&decoded.channels[*name]), expected, "channel {name}");
        }
    }
}

#[test]
fn custom_names_are_sorted_in_the_file_and_long_names_are_flagged() {
    let (w, h) = (8, 3);
    let data: Vec<f32> = random_floats(7, w * h * 3, 0.0, 1.0)
        .into_iter()
        .map(|v| v as f32)
        .collect();
    let long = "coverage_of_the_hair_disk_inside_the_texel".to_string();
    assert!(long.len() > 31);
    let names = vec!["zeta".to_string(), long.clone(), "middle".to_string()];
    let image = ImageRef::new(w, h, 3, &data).unwrap();
    let bytes = encode(
        &image,
        &ExrOptions {
            channel_names: Some(names.clone()),
            ..ExrOptions::default()
        },
    );
    // Version field: format 2 with the long-name bit (0x400).
    assert_eq!(u32::from_le_bytes(bytes[4..8].try_into().unwrap()), 0x402);
    let decoded = decode(&bytes);
    assert_eq!(decoded.names, [long.as_str(), "middle", "zeta"]);
    for (c, name) in names.iter().enumerate() {
        let expected: Vec<u32> = channel(&data, 3, c).iter().map(|v| v.to_bits()).collect();
        assert_eq!(f32_bits(&decoded.channels[name]), expected, "channel {name}");
    }
    // Short names keep the plain version 2.
    let plain = encode(&image, &ExrOptions::default());
    assert_eq!(u32::from_le_bytes(plain[4..8].try_into().unwrap()), 2);
}

#[test]
fn zip_shrinks_smooth_data_and_stores_incompressible_blocks_raw() {
    let (w, h) = (64, 64);
    let smooth: Vec<f16> = (0..w * h * 4)
        .map(|i| f16::from_f64(((i / 4) % w) as f64 / w as f64))
        .collect();
    let image = ImageRef::new(w, h, 4, &smooth).unwrap();
    let none = encode(
        &image,
        &ExrOptions {
            compression: ExrCompression::None,
            ..ExrOptions::default()
        },
    );
    let zip = encode(&image, &ExrOptions::default());
    assert!(
        zip.len() * 4 < none.len(),
        "zip {} vs none {}",
        zip.len(),
        none.len()
    );

    // One half-float pixel: 2 raw bytes, far below any zlib stream, so the block is stored raw
    // and the chunk's size field (the last 4 bytes before the data) reads 2.
    let one = [f16::from_f64(0.75)];
    let bytes = encode(&ImageRef::new(1, 1, 1, &one).unwrap(), &ExrOptions::default());
    let n = bytes.len();
    assert_eq!(i32::from_le_bytes(bytes[n - 6..n - 2].try_into().unwrap()), 2);
    assert_eq!(&bytes[n - 2..], &one[0].to_le_bytes());
    assert_eq!(f16_bits(&decode(&bytes).channels["Y"]), [one[0].to_bits()]);
}

#[test]
fn exr_bytes_do_not_depend_on_the_thread_count() {
    let (w, h) = (50, 130);
    let data = awkward_f32(9, w * h * 4);
    let image = ImageRef::new(w, h, 4, &data).unwrap();
    let options = ExrOptions::default();
    let one = with_threads(1, || encode_exr(&image, &options).unwrap());
    let two = with_threads(2, || encode_exr(&image, &options).unwrap());
    assert_eq!(one, two);
    assert_eq!(one, encode(&image, &options));
}

#[test]
fn non_finite_samples_and_bad_names_are_rejected() {
    let mut data = vec![0.5f32; 4 * 3 * 2];
    data[(2 * 4 + 1) * 2 + 1] = f32::NAN; // pixel (1, 2), channel 1 (A)
    let image = ImageRef::new(4, 3, 2, &data).unwrap();
    match write_exr(Vec::new(), &image, &ExrOptions::default()) {
        Err(crate::error::PeltError::InvalidParameter { name, reason }) => {
            assert_eq!(name, "data");
            assert!(reason.contains("pixel (1, 2) channel A"), "{reason}");
        }
        other => panic!("expected InvalidParameter, got {other:?}"),
    }
    let inf = [f16::INFINITY];
    let image = ImageRef::new(1, 1, 1, &inf).unwrap();
    assert_eq!(
        parameter_name(write_exr(Vec::new(), &image, &ExrOptions::default())),
        "data"
    );

    let data = [0.0f32; 2];
    let image = ImageRef::new(1, 1, 2, &data).unwrap();
    for names in [
        vec!["R"],
        vec!["R", "R"],
        vec!["R", ""],
        vec!["R", "a\0b"],
        vec!["R", &"x".repeat(256)],
    ] {
        let options = ExrOptions {
            channel_names: Some(names.iter().map(|n| n.to_string()).collect()),
            ..ExrOptions::default()
        };
        assert_eq!(
            parameter_name(write_exr(Vec::new(), &image, &options)),
            "channel_names"
        );
    }
}

#[test]
fn save_exr_writes_a_readable_file() {
    let dir = temp_dir("exr");
    let data: Vec<f32> = random_floats(11, 6 * 5, 0.0, 2.0)
        .into_iter()
        .map(|v| v as f32)
        .collect();
    let image = ImageRef::new(6, 5, 1, &data).unwrap();
    let path = dir.join("density.exr");
    save_exr(&path, &image, &ExrOptions::default()).unwrap();
    let decoded = decode(&std::fs::read(&path).unwrap());
    let expected: Vec<u32> = data.iter().map(|v| v.to_bits()).collect();
    assert_eq!(f32_bits(&decoded.channels["Y"]), expected);

    // An invalid image is rejected before the file is created.
    let nan = [f32::NAN];
    let bad = dir.join("bad.exr");
    let image = ImageRef::new(1, 1, 1, &nan).unwrap();
    assert_eq!(
        parameter_name(save_exr(&bad, &image, &ExrOptions::default())),
        "data"
    );
    assert!(!bad.exists());
    std::fs::remove_dir_all(dir).unwrap();
}
