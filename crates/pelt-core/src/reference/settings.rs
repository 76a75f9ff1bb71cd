//! How long the reference renders and how it lights ([`ReferenceSettings`]), with the limits of
//! an image.

use super::shade::HairShading;
use crate::error::{PeltError, Result, check_range};

/// Most samples per pixel.
pub const MAX_SAMPLES: u32 = 1 << 16;
/// Most pixels in one image (the accumulators hold 56 bytes a pixel).
pub const MAX_PIXELS: u64 = 1 << 26;

/// How long the reference renders and how it lights.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceSettings {
    /// Seed of every random choice.
    pub seed: u64,
    /// Samples per pixel in each pass, `[1, 1024]`.
    pub samples_per_pass: u32,
    /// Fewest samples per pixel, `[1, MAX_SAMPLES]`.
    pub min_samples: u32,
    /// Most samples per pixel, `[min_samples, MAX_SAMPLES]`: the render stops there even when
    /// the target is not met (the achieved error is reported).
    pub max_samples: u32,
    /// Relative standard error of the image's mean radiance to reach, `(0, 1]`.
    pub target_error: f64,
    /// Shadow rays toward the lights; off, every light reaches every point (for checking the
    /// composite against closed forms).
    pub shadows: bool,
    /// The hair and skin's Kajiya–Kay coefficients.
    pub shading: HairShading,
}

impl Default for ReferenceSettings {
    fn default() -> Self {
        ReferenceSettings {
            seed: 0,
            samples_per_pass: 4,
            min_samples: 16,
            max_samples: 1024,
            target_error: 0.01,
            shadows: true,
            shading: HairShading::default(),
        }
    }
}

impl ReferenceSettings {
    /// Checks every field, so a caller can refuse bad settings before the slow scene build.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming the first field out of range.
    pub fn validate(&self) -> Result<()> {
        let range = |name: &str, v: u32, lo: u32, hi: u32| {
            check_range(name, f64::from(v), f64::from(lo), f64::from(hi))
        };
        range("samples_per_pass", self.samples_per_pass, 1, 1024)?;
        range("min_samples", self.min_samples, 1, MAX_SAMPLES)?;
        range("max_samples", self.max_samples, self.min_samples, MAX_SAMPLES)?;
        if !(self.target_error > 0.0 && self.target_error <= 1.0) {
            return Err(PeltError::parameter(
                "target_error",
                format!("must be in (0, 1], got {}", self.target_error),
            ));
        }
        self.shading.validate()
    }
}
