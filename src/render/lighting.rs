//! Hair lighting inputs: Kajiya–Kay with Banks-style self-shadowing, after Lengyel et al. 2001,
//! §2.4. The shaders evaluate the model analytically per fragment (`lighting.wgsl`) rather than
//! through the paper's 32 × 32 lookup table: the same function, without its quantization.
//!
//! Precomputed radiance transfer (the PRT shell-fur paper, §2.4) will be a second
//! [`LightModel`] variant; the shaders call one `shade` function, which is where it will branch.

use crate::error::{PeltError, Result};

/// Largest Kajiya–Kay exponent accepted.
pub const MAX_POWER: f32 = 1e4;
/// Largest light or ambient value accepted (linear, HDR allowed).
pub const MAX_RADIANCE: f32 = 1e4;

/// Kajiya–Kay coefficients: `Ka + Kd (1 − u²)^(Pd/2) + Ks (1 − v²)^(Ps/2)` with `u = T·L` and
/// `v = T·H` (Lengyel §2.4). Hair color (texture × vertex color) scales the ambient and diffuse
/// terms; the specular highlight keeps the light's color.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KajiyaKay {
    /// `Ka`: ambient, linear RGB, each `[0, MAX_RADIANCE]`.
    pub ambient: [f32; 3],
    /// `Kd`, `[0, MAX_RADIANCE]`.
    pub diffuse: f32,
    /// `Ks`, `[0, MAX_RADIANCE]`.
    pub specular: f32,
    /// `Pd`, `(0, MAX_POWER]`.
    pub diffuse_power: f32,
    /// `Ps`, `(0, MAX_POWER]`.
    pub specular_power: f32,
}

impl Default for KajiyaKay {
    fn default() -> Self {
        KajiyaKay {
            ambient: [0.12; 3],
            diffuse: 0.9,
            specular: 0.25,
            diffuse_power: 1.0,
            specular_power: 48.0,
        }
    }
}

/// The lighting model. Today only Kajiya–Kay; PRT joins here.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightModel {
    /// Lengyel §2.4's modified Banks / Kajiya–Kay model with the per-texel tangent map.
    KajiyaKay(KajiyaKay),
}

impl Default for LightModel {
    fn default() -> Self {
        LightModel::KajiyaKay(KajiyaKay::default())
    }
}

/// One directional light and the model that shades the hair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lighting {
    /// Direction toward the light, object space; any non-zero length.
    pub direction: [f32; 3],
    /// Light color × intensity, linear RGB, each `[0, MAX_RADIANCE]`.
    pub color: [f32; 3],
    /// Banks-style self-shadowing (Lengyel §2.4): hair at the skin is darkened by this share,
    /// fading linearly to none at the tips; `[0, 1]`.
    pub self_shadow: f32,
    /// The model.
    pub model: LightModel,
}

impl Default for Lighting {
    fn default() -> Self {
        Lighting {
            direction: [0.4, -0.5, 0.75],
            color: [1.0; 3],
            self_shadow: 0.6,
            model: LightModel::default(),
        }
    }
}

fn in_range(name: &str, value: f32, lo: f32, hi: f32, open_lo: bool) -> Result<()> {
    let ok = value.is_finite() && value <= hi && if open_lo { value > lo } else { value >= lo };
    if ok {
        Ok(())
    } else {
        let bracket = if open_lo { "(" } else { "[" };
        Err(PeltError::parameter(
            name,
            format!("must be in {bracket}{lo}, {hi}], got {value}"),
        ))
    }
}

/// What the shaders get from the lighting (see `Frame` in `common.wgsl`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct LightingFrame {
    pub direction: [f32; 3],
    pub color: [f32; 3],
    pub ambient: [f32; 3],
    /// `Kd, Ks, Pd, Ps`.
    pub kajiya_kay: [f32; 4],
    pub self_shadow: f32,
}

impl Lighting {
    /// Checks every field and normalizes the direction.
    pub(super) fn frame(&self) -> Result<LightingFrame> {
        let d = self.direction.map(f64::from);
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if !(len.is_finite() && len > 1e-12) {
            return Err(PeltError::parameter(
                "lighting.direction",
                format!("must be finite and non-zero, got {:?}", self.direction),
            ));
        }
        for (i, &c) in self.color.iter().enumerate() {
            in_range(&format!("lighting.color[{i}]"), c, 0.0, MAX_RADIANCE, false)?;
        }
        in_range("lighting.self_shadow", self.self_shadow, 0.0, 1.0, false)?;
        let LightModel::KajiyaKay(kk) = self.model;
        for (i, &c) in kk.ambient.iter().enumerate() {
            in_range(&format!("kajiya_kay.ambient[{i}]"), c, 0.0, MAX_RADIANCE, false)?;
        }
        in_range("kajiya_kay.diffuse", kk.diffuse, 0.0, MAX_RADIANCE, false)?;
        in_range("kajiya_kay.specular", kk.specular, 0.0, MAX_RADIANCE, false)?;
        in_range("kajiya_kay.diffuse_power", kk.diffuse_power, 0.0, MAX_POWER, true)?;
        in_range(
            "kajiya_kay.specular_power",
            kk.specular_power,
            0.0,
            MAX_POWER,
            true,
        )?;
        Ok(LightingFrame {
            direction: d.map(|c| (c / len) as f32),
            color: self.color,
            ambient: kk.ambient,
            kajiya_kay: [kk.diffuse, kk.specular, kk.diffuse_power, kk.specular_power],
            self_shadow: self.self_shadow,
        })
    }
}
