//! How the reference lights a hair and the skin: the preview's Kajiya–Kay terms (Lengyel et al.
//! 2001, §2.4, `Kd (1 − u²)^(Pd/2) + Ks (1 − v²)^(Ps/2)` with `u = T·L`, `v = T·H`) taken as the
//! phase of single scattering (the hybrid paper's model: light reaching the hair, scattered once
//! toward the eye), and a Lambertian skin. The preview's ambient term and its Banks darkening
//! are what the reference computes instead: light from an environment, and real shadows.
//!
//! A light of radiance `L` from direction `ω` (or a sun of strength `E`) reaches the eye as
//! `L · f(ω) · V(ω) / π`, so a white Lambertian skin with `Kd = 1` facing a sun gives `E / π`.

use glam::{Vec3, Vec3A};

use crate::error::{Num, PeltError, Result};

/// Largest coefficient or exponent accepted.
pub const MAX_COEFFICIENT: f32 = 1e4;

/// The Kajiya–Kay coefficients; the defaults are the preview's (`render::KajiyaKay`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HairShading {
    /// `Kd`, scales the hair's and the skin's albedo; `[0, MAX_COEFFICIENT]`.
    pub diffuse: f32,
    /// `Ks`, the light-colored highlight; `[0, MAX_COEFFICIENT]`.
    pub specular: f32,
    /// `Pd`, `(0, MAX_COEFFICIENT]`.
    pub diffuse_power: f32,
    /// `Ps`, `(0, MAX_COEFFICIENT]`.
    pub specular_power: f32,
}

impl Default for HairShading {
    fn default() -> Self {
        HairShading {
            diffuse: 0.9,
            specular: 0.25,
            diffuse_power: 1.0,
            specular_power: 48.0,
        }
    }
}

impl HairShading {
    pub(crate) fn validate(&self) -> Result<()> {
        let fields = [
            ("shading.diffuse", self.diffuse, false),
            ("shading.specular", self.specular, false),
            ("shading.diffuse_power", self.diffuse_power, true),
            ("shading.specular_power", self.specular_power, true),
        ];
        for (name, v, open) in fields {
            let ok = v.is_finite() && v <= MAX_COEFFICIENT && if open { v > 0.0 } else { v >= 0.0 };
            if !ok {
                let bracket = if open { "(" } else { "[" };
                return Err(PeltError::parameter(
                    name,
                    format!(
                        "must be in {bracket}0, {MAX_COEFFICIENT}], got {}",
                        Num(f64::from(v))
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The hair's `f(ω)` for light from `light`, seen from `view` (both unit, away from the hair),
    /// with unit tangent `tangent` and linear `albedo`.
    #[inline]
    pub(crate) fn hair(&self, tangent: Vec3A, light: Vec3A, view: Vec3A, albedo: Vec3) -> Vec3 {
        let half = (light + view).normalize_or(light);
        let u = tangent.dot(light);
        let v = tangent.dot(half);
        let diffuse = (1.0 - u * u).max(0.0).powf(0.5 * self.diffuse_power);
        let specular = (1.0 - v * v).max(0.0).powf(0.5 * self.specular_power);
        albedo * (self.diffuse * diffuse) + Vec3::splat(self.specular * specular)
    }

    /// The skin's `f(ω)`: Lambertian, `Kd · albedo · max(n·ω, 0)`.
    #[inline]
    pub(crate) fn skin(&self, normal: Vec3A, light: Vec3A, albedo: Vec3) -> Vec3 {
        albedo * (self.diffuse * normal.dot(light).max(0.0))
    }
}
