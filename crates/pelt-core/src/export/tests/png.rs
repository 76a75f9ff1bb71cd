use std::io::Cursor;

use ::png::{BitDepth, ColorType, Decoder};

use super::{random_bytes, temp_dir};
use crate::error::PeltError;
use crate::export::png::{PngCompression, PngOptions, save_png, write_png};
use crate::texture::atlas::{AtlasLayout, pack_atlas};
use crate::texture::image::ImageRef;

/// Decodes with the `png` crate's decoder (no transformations): header fields and raw bytes.
fn decode(bytes: &[u8]) -> (u32, u32, ColorType, BitDepth, Vec<u8>, bool) {
    let mut reader = Decoder::new(Cursor::new(bytes)).read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    let srgb = reader.info().srgb.is_some();
    (
        info.width,
        info.height,
        info.color_type,
        info.bit_depth,
        buf,
        srgb,
    )
}

fn encode<T: crate::export::PngSample>(image: &ImageRef<'_, T>, options: &PngOptions) -> Vec<u8> {
    let mut out = Vec::new();
    write_png(&mut out, image, options).unwrap();
    out
}

const COLOR_TYPES: [ColorType; 4] = [
    ColorType::Grayscale,
    ColorType::GrayscaleAlpha,
    ColorType::Rgb,
    ColorType::Rgba,
];

#[test]
fn eight_bit_png_decodes_to_the_input_for_every_channel_count() {
    let (w, h) = (7, 5);
    for channels in 1..=4 {
        let data = random_bytes(channels as u64, w * h * channels);
        let image = ImageRef::new(w, h, channels, &data).unwrap();
        let (dw, dh, color, depth, pixels, srgb) = decode(&encode(&image, &PngOptions::default()));
        assert_eq!((dw, dh), (w as u32, h as u32));
        assert_eq!(color, COLOR_TYPES[channels - 1]);
        assert_eq!(depth, BitDepth::Eight);
        assert_eq!(pixels, data);
        assert!(!srgb);
    }
}

#[test]
fn sixteen_bit_png_decodes_to_the_input_for_every_channel_count() {
    let (w, h) = (5, 6);
    for channels in 1..=4 {
        let data: Vec<u16> = random_bytes(10 + channels as u64, 2 * w * h * channels)
            .chunks_exact(2)
            .map(|b| u16::from_le_bytes([b[0], b[1]]))
            .collect();
        let image = ImageRef::new(w, h, channels, &data).unwrap();
        let (_, _, color, depth, pixels, _) = decode(&encode(&image, &PngOptions::default()));
        assert_eq!(color, COLOR_TYPES[channels - 1]);
        assert_eq!(depth, BitDepth::Sixteen);
        // PNG stores 16-bit samples big-endian.
        let decoded: Vec<u16> = pixels
            .chunks_exact(2)
            .map(|b| u16::from_be_bytes([b[0], b[1]]))
            .collect();
        assert_eq!(decoded, data);
    }
}

#[test]
fn png_bytes_are_deterministic_and_every_compression_is_lossless() {
    let data = random_bytes(3, 16 * 9 * 4);
    let image = ImageRef::new(16, 9, 4, &data).unwrap();
    for compression in [
        PngCompression::Fast,
        PngCompression::Balanced,
        PngCompression::High,
    ] {
        let options = PngOptions {
            compression,
            ..PngOptions::default()
        };
        let first = encode(&image, &options);
        assert_eq!(first, encode(&image, &options));
        assert_eq!(decode(&first).4, data);
    }
}

#[test]
fn srgb_option_adds_the_chunk_and_keeps_the_values() {
    let data = random_bytes(4, 4 * 4 * 3);
    let image = ImageRef::new(4, 4, 3, &data).unwrap();
    let options = PngOptions {
        srgb: true,
        ..PngOptions::default()
    };
    let (_, _, _, _, pixels, srgb) = decode(&encode(&image, &options));
    assert!(srgb);
    assert_eq!(pixels, data);
}

#[test]
fn atlas_png_of_sixteen_128_layers_round_trips() {
    let (layers, tile) = (16, 128);
    let data = random_bytes(5, layers * tile * tile * 4);
    let layout = AtlasLayout::new(layers, tile).unwrap();
    let atlas = pack_atlas(&layout, 4, &data).unwrap();
    let (w, h, _, _, pixels, _) = decode(&encode(&atlas.view(), &PngOptions::default()));
    assert_eq!((w, h), (512, 512));
    assert_eq!(pixels, atlas.data());
}

#[test]
fn save_png_writes_the_file_and_names_the_path_on_failure() {
    let dir = temp_dir("png");
    let data = random_bytes(6, 3 * 2 * 2);
    let image = ImageRef::new(3, 2, 2, &data).unwrap();
    let path = dir.join("layer.png");
    save_png(&path, &image, &PngOptions::default()).unwrap();
    assert_eq!(decode(&std::fs::read(&path).unwrap()).4, data);

    let missing = dir.join("no-such-folder").join("layer.png");
    match save_png(&missing, &image, &PngOptions::default()) {
        Err(PeltError::Io { path, .. }) => assert!(path.contains("no-such-folder")),
        other => panic!("expected an I/O error, got {other:?}"),
    }
    std::fs::remove_dir_all(dir).unwrap();
}
