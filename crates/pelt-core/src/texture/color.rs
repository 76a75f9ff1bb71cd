//! Color encoding shared by the texture producers: linear light inside, sRGB in 8-bit files.
//!
//! Hair colors are given and mixed in linear light; 8-bit textures store them sRGB-encoded (the
//! IEC 61966-2-1 transfer function) so that 256 levels are spent where the eye sees them, and the
//! renderer samples them through an sRGB texture format that decodes back to linear.

use std::sync::OnceLock;

/// Rec. ITU-R BT.709 luminance of linear RGB: the weights of the picture's figures and of the
/// renderer's shade per texel.
pub fn luminance([r, g, b]: [f64; 3]) -> f64 {
    0.2126 * r + 0.7152 * g + 0.0722 * b
}

/// sRGB-encodes a linear value in `[0, 1]` (clamped; NaN gives 0).
pub fn linear_to_srgb(linear: f32) -> f32 {
    let c = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Decodes an sRGB-encoded value in `[0, 1]` to linear.
pub fn srgb_to_linear(encoded: f32) -> f32 {
    let c = if encoded.is_nan() {
        0.0
    } else {
        encoded.clamp(0.0, 1.0)
    };
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// A linear value as an sRGB-encoded byte (the nearest byte in encoded space).
pub fn linear_to_srgb8(linear: f32) -> u8 {
    srgb8_encoder().encode(linear)
}

/// Linear to sRGB-encoded bytes without a `powf` per value: baking encodes every texel of every
/// layer, level and mip. A table over 2¹⁶ linear steps gives a first byte, and the linear value
/// at which the rounded byte changes corrects it: the steps are 20 times finer than the closest
/// two such thresholds (near black), so one correction suffices and the result is exact.
#[derive(Debug)]
pub struct Srgb8Encoder {
    start: Vec<u8>,
    /// `thresholds[b]`: the smallest linear value that rounds to byte `b + 1` (∞ for 255).
    thresholds: [f32; 256],
}

const ENCODER_STEPS: usize = 1 << 16;

/// The shared encoder (built on first use).
pub fn srgb8_encoder() -> &'static Srgb8Encoder {
    static ENCODER: OnceLock<Srgb8Encoder> = OnceLock::new();
    ENCODER.get_or_init(|| {
        let thresholds: [f32; 256] = std::array::from_fn(|b| {
            if b == 255 {
                f32::INFINITY
            } else {
                srgb_to_linear((b as f32 + 0.5) / 255.0)
            }
        });
        let start = (0..=ENCODER_STEPS)
            .map(|i| thresholds.partition_point(|&t| t <= i as f32 / ENCODER_STEPS as f32) as u8)
            .collect();
        Srgb8Encoder { start, thresholds }
    })
}

impl Srgb8Encoder {
    /// The sRGB-encoded byte of a linear value (clamped to `[0, 1]`; NaN gives 0).
    #[inline]
    pub fn encode(&self, linear: f32) -> u8 {
        let v = if linear.is_nan() {
            0.0
        } else {
            linear.clamp(0.0, 1.0)
        };
        let byte = self.start[(v * ENCODER_STEPS as f32) as usize];
        byte + u8::from(v >= self.thresholds[usize::from(byte)])
    }
}

/// A value in `[0, 1]` (clamped) as a byte, rounded to nearest.
pub fn unit_to_u8(value: f32) -> u8 {
    let v = if value.is_nan() {
        0.0
    } else {
        value.clamp(0.0, 1.0)
    };
    (v * 255.0 + 0.5) as u8
}

/// The 256 linear values of the sRGB-encoded bytes, for decoding whole images quickly.
pub fn srgb8_to_linear_table() -> &'static [f32; 256] {
    static TABLE: OnceLock<[f32; 256]> = OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|i| srgb_to_linear(i as f32 / 255.0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips_every_byte_and_matches_reference_points() {
        let table = srgb8_to_linear_table();
        for (byte, &linear) in table.iter().enumerate() {
            assert_eq!(usize::from(linear_to_srgb8(linear)), byte);
        }
        // Reference values of the standard: 0.5 linear is 0.7354 encoded, 0.2140 linear is 0.5.
        assert!((linear_to_srgb(0.5) - 0.735_356_6).abs() < 1e-6);
        assert!((srgb_to_linear(0.5) - 0.214_041_14).abs() < 1e-6);
        assert_eq!(linear_to_srgb8(f32::NAN), 0);
        // The search agrees with rounding the formula, away from the rounding boundaries.
        for i in 0..=10_000 {
            let linear = i as f32 / 10_000.0;
            let direct = linear_to_srgb(linear) * 255.0;
            if (direct - direct.floor() - 0.5).abs() > 1e-3 {
                assert_eq!(
                    linear_to_srgb8(linear),
                    unit_to_u8(linear_to_srgb(linear)),
                    "{linear}"
                );
            }
        }
        assert_eq!((linear_to_srgb8(-1.0), linear_to_srgb8(7.0)), (0, 255));
        assert_eq!(unit_to_u8(2.0), 255);
    }
}
