use super::halve_even_rgba8;
use crate::rng::Rng;
use crate::texture::mip::{MipAlpha, halve, rgba8_decoder, rgba8_encoder};

/// Random RGBA8 layers with what shells hold: blocks of four identical texels, fully
/// transparent and fully opaque texels, and arbitrary ones.
fn shell_like(seed: u64, width: usize, height: usize, layers: usize) -> Vec<u8> {
    let mut rng = Rng::new(seed);
    let mut data: Vec<u8> = (0..width * height * layers * 4)
        .map(|_| rng.next_u64() as u8)
        .collect();
    for texel in data.chunks_exact_mut(4) {
        match rng.next_u64() % 4 {
            0 => texel[3] = 0,
            1 => texel[3] = 255,
            _ => {}
        }
    }
    // Every third 2 × 2 block: one texel repeated.
    for layer in 0..layers {
        for y in (0..height).step_by(2) {
            for x in (0..width).step_by(2) {
                if !rng.next_u64().is_multiple_of(3) {
                    continue;
                }
                let at = |dx: usize, dy: usize| ((layer * height + y + dy) * width + x + dx) * 4;
                let texel: [u8; 4] = std::array::from_fn(|c| data[at(0, 0) + c]);
                for (dx, dy) in [(1, 0), (0, 1), (1, 1)] {
                    data[at(dx, dy)..at(dx, dy) + 4].copy_from_slice(&texel);
                }
            }
        }
    }
    data
}

#[test]
fn even_sides_give_the_bytes_of_the_general_filter() {
    let sizes = [(2, 2), (4, 6), (12, 10), (30, 2), (2, 18), (126, 4)];
    for (i, &(w, h)) in sizes.iter().enumerate() {
        let layers = 3;
        let src = shell_like(i as u64, w, h, layers);
        for srgb in [false, true] {
            for alpha in [MipAlpha::Straight, MipAlpha::Independent] {
                let general = halve(
                    &src,
                    w,
                    h,
                    layers,
                    alpha,
                    &rgba8_decoder(srgb),
                    &rgba8_encoder(srgb),
                );
                let fast = halve_even_rgba8(&src, w, h, layers, srgb, alpha);
                assert_eq!(fast, general, "{w}x{h} srgb {srgb} {alpha:?}");
            }
        }
    }
}

#[test]
fn every_uniform_block_of_every_texel_value_is_kept() {
    // A block of four equal texels must come back unchanged; check all byte values per channel
    // against the general filter, in both encodings, with alpha 0, partial and 255.
    let mut src = Vec::new();
    for v in 0..=255u8 {
        for a in [0u8, 1, 77, 254, 255] {
            let texel = [v, 255 - v, v / 3, a];
            src.extend(texel.iter().chain(&texel));
        }
    }
    // One row of blocks: duplicate the row below itself.
    let row = src.clone();
    src.extend_from_slice(&row);
    let w = row.len() / 4;
    for srgb in [false, true] {
        let general = halve(
            &src,
            w,
            2,
            1,
            MipAlpha::Straight,
            &rgba8_decoder(srgb),
            &rgba8_encoder(srgb),
        );
        let expected: Vec<u8> = row.chunks_exact(8).flat_map(|b| b[..4].to_vec()).collect();
        assert_eq!(general, expected, "general filter, srgb {srgb}");
        assert_eq!(
            halve_even_rgba8(&src, w, 2, 1, srgb, MipAlpha::Straight),
            expected
        );
    }
}

#[test]
fn byte_rounding_matches_the_library_round() {
    use crate::texture::mip::round_u8;
    let mut values = vec![
        0.0,
        -0.0,
        0.5,
        0.499_999_999_999_999_94,
        1.5,
        2.5,
        254.5,
        254.499_999_999_999_97,
        255.5,
        300.0,
        -0.5,
        -0.7,
        -3.0,
        1e300,
        -1e300,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
    ];
    values.extend((0..=4 * 256).map(|i| f64::from(i) / 4.0));
    values.extend((0..10_000).map(|i| f64::from(i) * 0.025_63));
    for v in values {
        assert_eq!(round_u8(v), v.round().clamp(0.0, 255.0) as u8, "{v}");
    }
}
