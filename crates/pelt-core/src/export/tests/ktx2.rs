use half::f16;

use super::{parameter_name, random_bytes, random_floats, temp_dir, with_threads};
use crate::export::ktx2::{Ktx2Format, Ktx2Texture, encode_ktx2, save_ktx2, write_ktx2};
use crate::texture::mip::{MipAlpha, MipLevels, MipOptions, chain_rgba8, mip_chain_rgba8};

fn encode(texture: &Ktx2Texture) -> Vec<u8> {
    let mut out = Vec::new();
    write_ktx2(&mut out, texture).unwrap();
    out
}

/// Checks what every file must satisfy, with the `ktx2` crate as the reader, and returns the
/// reader's level bytes (base first) with their file offsets.
fn check_structure(
    bytes: &[u8],
    format: ::ktx2::Format,
    width: u32,
    height: u32,
    layer_count: u32,
    texel_bytes: usize,
    level_count: usize,
) -> Vec<(usize, Vec<u8>)> {
    let reader = ::ktx2::Reader::new(bytes).unwrap();
    let header = reader.header();
    assert_eq!(header.format, Some(format));
    assert_eq!(
        (header.pixel_width, header.pixel_height, header.pixel_depth),
        (width, height, 0)
    );
    assert_eq!(header.layer_count, layer_count);
    assert_eq!(header.face_count, 1);
    assert_eq!(header.level_count as usize, level_count);
    assert_eq!(header.supercompression_scheme, None);
    assert_eq!(header.type_size as usize, if texel_bytes == 8 { 2 } else { 1 });

    // The data format descriptor equals the one the ktx2 crate derives from the format's
    // Khronos definition, and dfdTotalSize = kvdByteOffset - dfdByteOffset.
    let (basic, _) = ::ktx2::dfd::Basic::from_format(format).unwrap();
    assert_eq!(reader.dfd_blocks(), [::ktx2::dfd::Block::Basic(basic)]);
    let index = header.index;
    assert_eq!(
        index.kvd_byte_offset - index.dfd_byte_offset,
        index.dfd_byte_length
    );
    let dfd_total = &bytes[index.dfd_byte_offset as usize..][..4];
    assert_eq!(
        u32::from_le_bytes(dfd_total.try_into().unwrap()),
        index.dfd_byte_length
    );
    assert_eq!((index.sgd_byte_offset, index.sgd_byte_length), (0, 0));

    let pairs: Vec<(&str, &[u8])> = reader.key_value_data().collect();
    let writer = format!("pelt {}\0", crate::VERSION);
    assert_eq!(
        pairs,
        [("KTXorientation", &b"rd\0"[..]), ("KTXwriter", writer.as_bytes())]
    );
    assert_eq!(index.kvd_byte_length % 4, 0);

    let layers = layer_count.max(1) as usize;
    let alignment = if texel_bytes == 8 { 8 } else { 4 };
    let levels: Vec<(usize, Vec<u8>)> = reader
        .levels()
        .map(|level| {
            let offset = level.data.as_ptr() as usize - bytes.as_ptr() as usize;
            assert_eq!(level.uncompressed_byte_length as usize, level.data.len());
            (offset, level.data.to_vec())
        })
        .collect();
    assert_eq!(levels.len(), level_count);
    for (i, (offset, data)) in levels.iter().enumerate() {
        let (w, h) = ((width as usize >> i).max(1), (height as usize >> i).max(1));
        assert_eq!(data.len(), w * h * layers * texel_bytes, "level {i}");
        assert_eq!(offset % alignment, 0, "level {i} offset {offset}");
        // Smallest level first in the file: each level lies after the next smaller one.
        if i + 1 < levels.len() {
            assert!(levels[i + 1].0 + levels[i + 1].1.len() <= *offset);
        }
    }
    // The base level ends the file.
    assert_eq!(levels[0].0 + levels[0].1.len(), bytes.len());
    levels
}

#[test]
fn srgb_array_with_full_chain_parses_and_holds_the_mipmaps() {
    let (w, h, layers) = (32, 32, 16);
    let base = random_bytes(1, w * h * 4 * layers);
    let texture = Ktx2Texture::from_rgba8(
        Ktx2Format::Rgba8Srgb,
        w,
        h,
        Some(layers),
        &base,
        &MipOptions::default(),
    )
    .unwrap();
    let bytes = encode(&texture);
    let levels = check_structure(&bytes, ::ktx2::Format::R8G8B8A8_SRGB, 32, 32, 16, 4, 6);
    assert_eq!(levels[0].1, base);
    // Every layer of every level equals that layer's own chain, computed separately.
    for layer in 0..layers {
        let layer_base = &base[layer * w * h * 4..(layer + 1) * w * h * 4];
        let own = mip_chain_rgba8(w, h, 1, layer_base, true, &MipOptions::default()).unwrap();
        for (i, (_, data)) in levels.iter().enumerate() {
            let n = own[i].len();
            assert_eq!(
                &data[layer * n..(layer + 1) * n],
                own[i].as_slice(),
                "layer {layer} level {i}"
            );
        }
    }
}

#[test]
fn half_float_2d_texture_with_odd_sides_parses() {
    let (w, h) = (13, 7);
    let base: Vec<f16> = random_floats(2, w * h * 4, 0.0, 8.0)
        .into_iter()
        .map(f16::from_f64)
        .collect();
    let texture = Ktx2Texture::from_rgba16f(w, h, None, &base, &MipOptions::default()).unwrap();
    let bytes = encode(&texture);
    let levels = check_structure(&bytes, ::ktx2::Format::R16G16B16A16_SFLOAT, 13, 7, 0, 8, 4);
    let base_bytes: Vec<u8> = base.iter().flat_map(|v| v.to_le_bytes()).collect();
    assert_eq!(levels[0].1, base_bytes);
    for (i, (_, data)) in levels.iter().enumerate() {
        assert_eq!(data, &texture.levels()[i]);
    }
}

#[test]
fn unorm_array_with_given_levels_stores_them_verbatim() {
    let (w, h, layers) = (6, 4, 3);
    // Arbitrary level contents: the writer must not touch them.
    let levels = vec![
        random_bytes(3, w * h * 4 * layers),
        random_bytes(4, 3 * 2 * 4 * layers),
    ];
    let texture = Ktx2Texture::new(Ktx2Format::Rgba8Unorm, w, h, Some(layers), levels.clone()).unwrap();
    let bytes = encode(&texture);
    let read = check_structure(&bytes, ::ktx2::Format::R8G8B8A8_UNORM, 6, 4, 3, 4, 2);
    assert_eq!(read[0].1, levels[0]);
    assert_eq!(read[1].1, levels[1]);

    // A one-layer array stays an array (layerCount 1), unlike a plain 2D texture (0).
    let single = Ktx2Texture::new(Ktx2Format::Rgba8Unorm, 1, 1, Some(1), vec![vec![1, 2, 3, 4]]).unwrap();
    check_structure(&encode(&single), ::ktx2::Format::R8G8B8A8_UNORM, 1, 1, 1, 4, 1);
}

#[test]
fn ktx2_bytes_do_not_depend_on_the_thread_count() {
    let (w, h, layers) = (40, 24, 5);
    let base = random_bytes(6, w * h * 4 * layers);
    let build = |threads| {
        with_threads(threads, || {
            let smaller = chain_rgba8(w, h, layers, &base, false, MipAlpha::Straight, 6);
            let levels = std::iter::once(base.clone()).chain(smaller).collect();
            let texture = Ktx2Texture::new(Ktx2Format::Rgba8Unorm, w, h, Some(layers), levels).unwrap();
            encode_ktx2(&texture)
        })
    };
    assert_eq!(build(1), build(2));
}

#[test]
fn bad_textures_are_rejected_naming_the_parameter() {
    let texel = vec![vec![0u8; 4]];
    let new = |format, w, h, layers, levels| Ktx2Texture::new(format, w, h, layers, levels);
    assert_eq!(
        parameter_name(new(Ktx2Format::Rgba8Unorm, 0, 1, None, texel.clone())),
        "width"
    );
    assert_eq!(
        parameter_name(new(Ktx2Format::Rgba8Unorm, 1, 70000, None, texel.clone())),
        "height"
    );
    assert_eq!(
        parameter_name(new(Ktx2Format::Rgba8Unorm, 1, 1, Some(0), texel.clone())),
        "array_layers"
    );
    assert_eq!(
        parameter_name(new(Ktx2Format::Rgba8Unorm, 1, 1, None, vec![])),
        "levels"
    );
    // A 1 × 1 base has one level only.
    let two = vec![vec![0u8; 4], vec![0u8; 4]];
    assert_eq!(
        parameter_name(new(Ktx2Format::Rgba8Unorm, 1, 1, None, two)),
        "levels"
    );
    assert_eq!(
        parameter_name(new(Ktx2Format::Rgba8Srgb, 2, 1, None, texel.clone())),
        "levels[0]"
    );
    assert_eq!(
        parameter_name(new(Ktx2Format::Rgba16Float, 1, 1, None, texel)),
        "levels[0]"
    );
    let nan: Vec<u8> = [f16::ONE, f16::ONE, f16::NAN, f16::ONE]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    assert_eq!(
        parameter_name(new(Ktx2Format::Rgba16Float, 1, 1, None, vec![nan])),
        "levels[0]"
    );

    let options = MipOptions {
        levels: MipLevels::Count(1),
        ..MipOptions::default()
    };
    let float_from_bytes = Ktx2Texture::from_rgba8(Ktx2Format::Rgba16Float, 1, 1, None, &[0; 4], &options);
    assert_eq!(parameter_name(float_from_bytes), "format");
}

#[test]
fn save_ktx2_writes_a_readable_file() {
    let dir = temp_dir("ktx2");
    let base = random_bytes(7, 8 * 8 * 4 * 2);
    let texture = Ktx2Texture::from_rgba8(
        Ktx2Format::Rgba8Unorm,
        8,
        8,
        Some(2),
        &base,
        &MipOptions::default(),
    )
    .unwrap();
    let path = dir.join("shells.ktx2");
    save_ktx2(&path, &texture).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(bytes, encode(&texture));
    check_structure(&bytes, ::ktx2::Format::R8G8B8A8_UNORM, 8, 8, 2, 4, 4);
    std::fs::remove_dir_all(dir).unwrap();
}
