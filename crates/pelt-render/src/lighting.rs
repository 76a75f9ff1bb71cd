//! Hair lighting inputs, two models:
//!
//! - Kajiya–Kay with Banks-style self-shadowing, after Lengyel et al. 2001, §2.4. The shaders
//!   evaluate the model analytically per fragment (`lighting.wgsl`) rather than through the
//!   paper's 32 × 32 lookup table: the same function, without its quantization.
//! - Precomputed radiance transfer (the PRT shell-fur paper, §2.4): the world lighting as SH
//!   coefficients (an environment plus the directional light projected as a small cap), rotated
//!   into each vertex's tile frame and dotted per fragment with the scene's transfer textures
//!   (`prt_light.rs`, `prt_rotate.rs`, `prt.wgsl`).

use glam::Vec3;
use pelt_core::error::{Num, PeltError, Result};
use pelt_core::prt::sh;

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
    /// How the ambient changes with the surface normal `n` (object space): the hair and skin
    /// take `ambient + n.x · g[0] + n.y · g[1] + n.z · g[2]` (clamped at 0), so that fur facing
    /// a bright sky gets more of it than fur facing the ground. Linear RGB per unit of normal,
    /// each of magnitude at most [`MAX_RADIANCE`]; zero (the default) is a uniform ambient.
    /// [`KajiyaKay::under_environment`] sets both from an environment's SH.
    pub ambient_gradient: [[f32; 3]; 3],
    /// `Kd`, `[0, MAX_RADIANCE]`.
    pub diffuse: f32,
    /// `Ks`, `[0, MAX_RADIANCE]`.
    pub specular: f32,
    /// `Pd`, `(0, MAX_POWER]`.
    pub diffuse_power: f32,
    /// `Ps`, `(0, MAX_POWER]`.
    pub specular_power: f32,
    /// Goldman's directional attenuation (Fake fur rendering, 1997; the raycast paper's §3.8):
    /// the direct light is scaled by `(1 + κ)/2 · reflect + (1 − κ)/2 · transmit`, where `κ` is
    /// the cosine between `T × L` and `T × V` (1 where the light is on the viewer's side of the
    /// hair, −1 where it shines through it). `ρ_reflect`, `[0, 1]`; 1 with `transmit` 1 (the
    /// default) attenuates nothing.
    pub reflect: f32,
    /// `ρ_transmit`, `[0, 1]`: how much light the hair passes forward.
    pub transmit: f32,
}

impl Default for KajiyaKay {
    fn default() -> Self {
        KajiyaKay {
            ambient: [0.12; 3],
            ambient_gradient: [[0.0; 3]; 3],
            diffuse: 0.9,
            specular: 0.25,
            diffuse_power: 1.0,
            specular_power: 48.0,
            reflect: 1.0,
            transmit: 1.0,
        }
    }
}

impl KajiyaKay {
    /// This model's ambient under an environment of radiance `sh` (real SH coefficients in
    /// Pelt's basis, object space, at least one band; bands past the first are ignored): for a
    /// normal `n`, the irradiance an open hemisphere about `n` receives over π (Ramamoorthi and
    /// Hanrahan 2001: band 0 kept, band 1 weighed 2/3), the radiance a white diffuse surface
    /// facing `n` would show. Under a sky brighter above than below, fur facing up is lit more;
    /// the mean radiance alone had lit the reference's sky scenes' fur 10–30% too dark.
    pub fn under_environment(self, sh: &[[f32; 3]]) -> Self {
        const Y0: f32 = 0.282_094_8; // √(1 / 4π)
        const Y1: f32 = 0.488_602_5; // √(3 / 4π)
        let band = |k: usize| sh.get(k).copied().unwrap_or([0.0; 3]);
        let slope = |k: usize| band(k).map(|c| 2.0 / 3.0 * Y1 * c);
        KajiyaKay {
            ambient: band(0).map(|c| (Y0 * c).max(0.0)),
            // Y_1^{-1} ∝ y, Y_1^0 ∝ z, Y_1^1 ∝ x (`prt::sh`).
            ambient_gradient: [slope(3), slope(1), slope(2)],
            ..self
        }
    }
}

/// Largest angular radius of the PRT directional light, radians (a hemisphere).
pub const MAX_LIGHT_RADIUS: f32 = std::f32::consts::FRAC_PI_2;

/// Precomputed radiance transfer lighting (PRT shell-fur paper, §2.4); needs a scene with
/// transfer textures ([`super::FurScene::set_transfer`]).
///
/// The hair's color is `albedo / π · ∫ L(ω) T(ω) phase(ω) dω`, evaluated as the dot product of
/// the lighting's SH coefficients (rotated into the tile frame) with the baked transfer. With the
/// `1/π`, a directional light of color `C` that reaches the hair unshadowed gives `albedo · C`
/// (as a Lambertian surface facing it would), and a uniform environment of radiance `E` gives at
/// most `2 · albedo · E` (the open hemisphere, isotropic phase). The result is clamped at 0: a
/// band-limited light rings slightly negative beyond the terminator.
#[derive(Debug, Clone, PartialEq)]
pub struct Prt {
    /// Radiance arriving from each direction as real SH coefficients (Pelt's basis, `prt::sh`),
    /// object space, linear RGB: `n²` rows for an order `n` in `[1, 8]`, or none. Each value
    /// finite with magnitude at most [`MAX_RADIANCE`]. Truncated or padded with zeros to the
    /// order of the scene's transfer.
    pub environment: Vec<[f32; 3]>,
    /// The directional light ([`Lighting::direction`], [`Lighting::color`]) enters as a uniform
    /// cap of this angular radius, radians `[0, MAX_LIGHT_RADIUS]`: 0 is a point light, whose
    /// truncated expansion rings most; a few degrees soften that.
    pub light_radius: f32,
}

impl Default for Prt {
    fn default() -> Self {
        // A dim sky: radiance 0.1 from every direction (only the Y_0^0 coefficient, √(4π) · 0.1).
        let sky = 0.1 * (4.0 * std::f32::consts::PI).sqrt();
        Prt {
            environment: vec![[sky; 3]],
            light_radius: 0.2,
        }
    }
}

/// The lighting model.
#[derive(Debug, Clone, PartialEq)]
pub enum LightModel {
    /// Lengyel §2.4's modified Banks / Kajiya–Kay model with the per-texel tangent map.
    KajiyaKay(KajiyaKay),
    /// Precomputed radiance transfer with the scene's transfer textures.
    Prt(Prt),
}

impl Default for LightModel {
    fn default() -> Self {
        LightModel::KajiyaKay(KajiyaKay::default())
    }
}

/// One directional light and the model that shades the hair.
#[derive(Debug, Clone, PartialEq)]
pub struct Lighting {
    /// Direction toward the light, object space; any non-zero length.
    pub direction: [f32; 3],
    /// The light's irradiance on a surface facing it × its color, linear RGB, each
    /// `[0, MAX_RADIANCE]`: Blender's sun strength, so a white Lambertian surface facing it
    /// shows `color / π` (the light units of DESIGN.md §3, shared with the reference
    /// and Cycles). The default, π, lights such a surface to 1.
    pub color: [f32; 3],
    /// Banks-style self-shadowing (Lengyel §2.4): under the ambient light and a light straight
    /// down the normal, hair at the skin is darkened by this share, fading linearly to none at
    /// the tips; a light `θ` off the normal by `1 − (1 − self_shadow)^(1/cos θ)` (it crosses
    /// more fur), and less as the light nears the view direction (none from the eye: the hot
    /// spot). `[0, 1]`. Kajiya–Kay only: the transfer of PRT holds the fur's own shadowing.
    pub self_shadow: f32,
    /// The model.
    pub model: LightModel,
}

impl Default for Lighting {
    fn default() -> Self {
        Lighting {
            direction: [0.4, -0.5, 0.75],
            color: [std::f32::consts::PI; 3],
            self_shadow: 0.15,
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
            format!("must be in {bracket}{lo}, {hi}], got {}", Num(f64::from(value))),
        ))
    }
}

/// What the shaders get from the lighting (see `Frame` in `common.wgsl`).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct LightingFrame {
    pub direction: [f32; 3],
    /// What a white Lambertian surface facing the light shows: [`Lighting::color`] / π.
    pub color: [f32; 3],
    /// [`KajiyaKay::ambient`]; under PRT the environment's ([`KajiyaKay::under_environment`]),
    /// which lights bald skin as a bare surface (`surface_prt.wgsl` `bare_skin`).
    pub ambient: [f32; 3],
    /// [`KajiyaKay::ambient_gradient`]; under PRT the environment's, as `ambient`.
    pub ambient_gradient: [[f32; 3]; 3],
    /// `Kd, Ks, Pd, Ps`; under PRT the default `Kd` alone, for bald skin.
    pub kajiya_kay: [f32; 4],
    /// Goldman's `ρ_reflect, ρ_transmit` (1, 1 under PRT: no attenuation).
    pub goldman: [f32; 2],
    pub self_shadow: f32,
    /// The PRT inputs, checked; `None` for Kajiya–Kay.
    pub prt: Option<Prt>,
}

impl Lighting {
    /// Checks every field and normalizes the direction.
    pub(super) fn frame(&self) -> Result<LightingFrame> {
        let d = Vec3::from(self.direction).as_dvec3();
        let len = d.length();
        if !(len.is_finite() && len > 0.0) {
            return Err(PeltError::parameter(
                "lighting.direction",
                format!("must be finite and non-zero, got {:?}", self.direction),
            ));
        }
        for (i, &c) in self.color.iter().enumerate() {
            in_range(&format!("lighting.color[{i}]"), c, 0.0, MAX_RADIANCE, false)?;
        }
        in_range("lighting.self_shadow", self.self_shadow, 0.0, 1.0, false)?;
        // A division by the length, not `normalize`'s product with its reciprocal: it rounds otherwise.
        let direction = (d / len).as_vec3().to_array();
        let color = (Vec3::from(self.color) / std::f32::consts::PI).to_array();
        match &self.model {
            LightModel::KajiyaKay(kk) => {
                check_kajiya_kay(kk)?;
                Ok(LightingFrame {
                    direction,
                    color,
                    ambient: kk.ambient,
                    ambient_gradient: kk.ambient_gradient,
                    kajiya_kay: [kk.diffuse, kk.specular, kk.diffuse_power, kk.specular_power],
                    goldman: [kk.reflect, kk.transmit],
                    self_shadow: self.self_shadow,
                    prt: None,
                })
            }
            LightModel::Prt(prt) => {
                check_prt(prt)?;
                let bare = KajiyaKay::default().under_environment(&prt.environment);
                Ok(LightingFrame {
                    direction,
                    color,
                    ambient: bare.ambient,
                    ambient_gradient: bare.ambient_gradient,
                    // The bald skin's Kd, as the reference's default skin has it.
                    kajiya_kay: [bare.diffuse, 0.0, 0.0, 0.0],
                    goldman: [1.0; 2],
                    self_shadow: 0.0,
                    prt: Some(prt.clone()),
                })
            }
        }
    }
}

impl LightingFrame {
    /// Under PRT, the directional light's share of the light a surface facing it gets: its
    /// irradiance over that plus the environment's mean radiance × π (band 0), summed over RGB.
    /// The hot spot (`prt.wgsl` `hot_spot`) clears the transfer's shadow of this share. 0 under
    /// Kajiya–Kay, whose Banks darkening has its own hot spot.
    pub fn hot_spot_share(&self) -> f32 {
        let Some(prt) = &self.prt else {
            return 0.0;
        };
        // Y_0^0: the mean radiance is the band-0 coefficient × this; `color` is already E / π.
        let y00 = 0.5 / std::f32::consts::PI.sqrt();
        let band0 = prt.environment.first().copied().unwrap_or([0.0; 3]);
        let sun: f32 = self.color.iter().sum();
        let sky: f32 = band0.iter().map(|c| (c * y00).max(0.0)).sum();
        if sun > 0.0 { sun / (sun + sky) } else { 0.0 }
    }
}

fn check_kajiya_kay(kk: &KajiyaKay) -> Result<()> {
    for (i, &c) in kk.ambient.iter().enumerate() {
        in_range(&format!("kajiya_kay.ambient[{i}]"), c, 0.0, MAX_RADIANCE, false)?;
    }
    for (axis, row) in kk.ambient_gradient.iter().enumerate() {
        for (i, &c) in row.iter().enumerate() {
            let name = format!("kajiya_kay.ambient_gradient[{axis}][{i}]");
            in_range(&name, c, -MAX_RADIANCE, MAX_RADIANCE, false)?;
        }
    }
    in_range("kajiya_kay.diffuse", kk.diffuse, 0.0, MAX_RADIANCE, false)?;
    in_range("kajiya_kay.specular", kk.specular, 0.0, MAX_RADIANCE, false)?;
    in_range("kajiya_kay.diffuse_power", kk.diffuse_power, 0.0, MAX_POWER, true)?;
    in_range("kajiya_kay.reflect", kk.reflect, 0.0, 1.0, false)?;
    in_range("kajiya_kay.transmit", kk.transmit, 0.0, 1.0, false)?;
    in_range(
        "kajiya_kay.specular_power",
        kk.specular_power,
        0.0,
        MAX_POWER,
        true,
    )
}

/// Checks the rows of an environment's SH radiance (`name[i]`): finite, magnitude at most
/// [`MAX_RADIANCE`].
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `name[i]`, the first bad row.
pub fn check_environment(name: &str, rows: &[[f32; 3]]) -> Result<()> {
    for (i, row) in rows.iter().enumerate() {
        if let Some(c) = row.iter().find(|c| !(c.is_finite() && c.abs() <= MAX_RADIANCE)) {
            return Err(PeltError::parameter(
                format!("{name}[{i}]"),
                format!(
                    "values must be finite with magnitude at most {MAX_RADIANCE}, got {}",
                    Num(f64::from(*c))
                ),
            ));
        }
    }
    Ok(())
}

fn check_prt(prt: &Prt) -> Result<()> {
    let n = prt.environment.len();
    if n > 0 && sh::order_of_len(n).is_err() {
        return Err(PeltError::parameter(
            "prt.environment",
            format!(
                "must hold n² rows for an order n in [1, {}] (1, 4, 9, …, 64) or none, got {n}",
                sh::MAX_ORDER
            ),
        ));
    }
    check_environment("prt.environment", &prt.environment)?;
    in_range("prt.light_radius", prt.light_radius, 0.0, MAX_LIGHT_RADIUS, false)
}

#[cfg(test)]
mod tests {
    use super::*;
    use pelt_core::prt::sphere::fibonacci_directions;

    /// A sky brighter above than below: its ambient about each normal is the irradiance there
    /// over π, summed here over the hemisphere direction by direction.
    #[test]
    fn the_ambient_under_an_environment_is_its_irradiance_about_the_normal_over_pi() {
        let radiance = |d: [f64; 3]| 0.6 + 0.4 * d[2] + 0.1 * d[0];
        let directions = fibonacci_directions(20_000);
        let weight = 4.0 * std::f64::consts::PI / directions.len() as f64;
        let weights = vec![weight; directions.len()];
        let values: Vec<f64> = directions.iter().map(|&d| radiance(d)).collect();
        let coefficients = sh::project_samples(2, &directions, &weights, &values).unwrap();
        let sh: Vec<[f32; 3]> = coefficients.iter().map(|&c| [c as f32; 3]).collect();
        let kk = KajiyaKay::default().under_environment(&sh);
        for n in [
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
            [1.0, 0.0, 0.0],
            [0.0, -0.6, 0.8],
        ] {
            let irradiance: f64 = directions
                .iter()
                .map(|&d| {
                    let cos = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
                    radiance(d) * cos.max(0.0) * weight
                })
                .sum();
            let expected = irradiance / std::f64::consts::PI;
            let g = kk.ambient_gradient;
            let ambient =
                f64::from(kk.ambient[0]) + (0..3).map(|axis| n[axis] * f64::from(g[axis][0])).sum::<f64>();
            assert!(
                (ambient - expected).abs() < 0.005 * expected,
                "normal {n:?}: {ambient} against {expected}"
            );
        }
        // A uniform sky gives its radiance everywhere, without a gradient.
        let uniform = KajiyaKay::default().under_environment(&[[2.0 * (std::f32::consts::PI).sqrt(); 3]]);
        assert!((uniform.ambient[0] - 1.0).abs() < 1e-6 && uniform.ambient_gradient == [[0.0; 3]; 3]);
    }
}
