//! The reference's lights, in Blender's units: a sun of strength `E` (irradiance on a surface
//! facing it) gives a white Lambertian surface facing it the radiance `E / π`; an environment
//! gives radiance per direction. Colors are linear RGB.

use std::f64::consts::PI;

use glam::{DVec3, Vec3, Vec3A};

use crate::error::{Num, PeltError, Result, check_range};
use crate::prt::sh;
use crate::texture::color::luminance;

/// Largest light strength or environment coefficient accepted.
pub const MAX_STRENGTH: f32 = 1e6;

/// A light of the reference scene.
#[derive(Debug, Clone, PartialEq)]
pub enum ReferenceLight {
    /// A directional light at infinity.
    Sun {
        /// Toward the light, object space; any non-zero length.
        direction: [f32; 3],
        /// Irradiance on a surface facing it, `[0, MAX_STRENGTH]`.
        strength: f32,
        /// Linear RGB tint, each `[0, MAX_STRENGTH]`.
        color: [f32; 3],
    },
    /// Radiance arriving from every direction as real SH coefficients (Pelt's basis,
    /// `prt::sh`), object space, linear RGB: `n²` rows for an order `n` in `[1, 8]`; negative
    /// radiance (ringing) counts as none. Sampled in proportion to its luminance.
    Environment {
        /// The coefficients.
        sh: Vec<[f32; 3]>,
    },
}

/// A light ready to sample.
pub(crate) enum Prepared {
    Sun { direction: Vec3A, radiance_scale: Vec3 },
    Environment(EnvironmentSampler),
}

/// A direction toward a light with what it brings: `weight` is the radiance over the sample's
/// density, so a shading point adds `weight · f(ω) · V / π` (with `f` the phase or BRDF × π).
pub(crate) struct LightSample {
    pub direction: Vec3A,
    pub weight: Vec3,
}

fn check(name: &str, v: f32) -> Result<()> {
    check_range(name, f64::from(v), 0.0, f64::from(MAX_STRENGTH))
}

impl ReferenceLight {
    /// Checks the light (named `lights[i]`) and prepares its sampling.
    pub(crate) fn prepare(&self, i: usize) -> Result<Prepared> {
        match self {
            ReferenceLight::Sun {
                direction,
                strength,
                color,
            } => {
                check(&format!("lights[{i}].strength"), *strength)?;
                for (c, &v) in color.iter().enumerate() {
                    check(&format!("lights[{i}].color[{c}]"), v)?;
                }
                // In f64, so any finite non-zero f32 direction has a length.
                let wide = glam::DVec3::from(direction.map(f64::from));
                let len = wide.length();
                if !(len.is_finite() && len > 0.0) {
                    return Err(PeltError::parameter(
                        format!("lights[{i}].direction"),
                        format!("must be finite and non-zero, got {direction:?}"),
                    ));
                }
                Ok(Prepared::Sun {
                    direction: Vec3A::from((wide / len).as_vec3()),
                    radiance_scale: Vec3::from(*color) * *strength,
                })
            }
            ReferenceLight::Environment { sh } => {
                let name = format!("lights[{i}].sh");
                let order = sh::order_of_len(sh.len()).map_err(|_| {
                    PeltError::parameter(
                        &name,
                        format!("needs n² rows for an order n in [1, 8], got {}", sh.len()),
                    )
                })?;
                if let Some(v) = sh
                    .iter()
                    .flatten()
                    .find(|v| !(v.is_finite() && v.abs() <= MAX_STRENGTH))
                {
                    return Err(PeltError::parameter(
                        name,
                        format!(
                            "coefficients must be finite with magnitude at most {MAX_STRENGTH}, got {}",
                            Num(f64::from(*v))
                        ),
                    ));
                }
                Ok(Prepared::Environment(EnvironmentSampler::new(order, sh)))
            }
        }
    }
}

/// Cells of the environment's sampling table: equal solid angle (uniform in azimuth and in
/// `z = cos θ`).
const AZIMUTHS: usize = 64;
const HEIGHTS: usize = 32;

/// Importance sampling of an SH environment: its luminance tabulated on equal-area cells, a cell
/// drawn in proportion to it, a direction uniform within the cell; the radiance is evaluated
/// exactly at that direction.
pub(crate) struct EnvironmentSampler {
    order: usize,
    coefficients: Vec<[f64; 3]>,
    /// Cumulative cell probabilities, the last 1.
    cdf: Vec<f64>,
    /// Each cell's probability.
    probability: Vec<f64>,
}

impl EnvironmentSampler {
    fn new(order: usize, coefficients: &[[f32; 3]]) -> Self {
        let coefficients: Vec<[f64; 3]> = coefficients.iter().map(|c| c.map(f64::from)).collect();
        let mut sampler = EnvironmentSampler {
            order,
            coefficients,
            cdf: Vec::new(),
            probability: Vec::new(),
        };
        let cells = AZIMUTHS * HEIGHTS;
        // Every cell keeps a floor of the mean, so no direction with light has zero density.
        let luminance: Vec<f64> = (0..cells)
            .map(|c| {
                let d = cell_direction(c, 0.5, 0.5);
                luminance(sampler.radiance(d).to_array())
            })
            .collect();
        let mean = luminance.iter().sum::<f64>() / cells as f64;
        let weights: Vec<f64> = luminance.iter().map(|l| l + 0.05 * mean + 1e-12).collect();
        let total: f64 = weights.iter().sum();
        let mut acc = 0.0;
        for w in &weights {
            acc += w / total;
            sampler.probability.push(w / total);
            sampler.cdf.push(acc);
        }
        *sampler.cdf.last_mut().expect("cells") = 1.0;
        sampler
    }

    /// Radiance from direction `d` (unit), negative parts clipped.
    pub(crate) fn radiance(&self, d: DVec3) -> DVec3 {
        let mut y = [0.0; 64];
        let y = &mut y[..self.order * self.order];
        sh::eval(self.order, d.to_array(), y).expect("order checked when prepared");
        let mut rgb = DVec3::ZERO;
        for (c, yk) in self.coefficients.iter().zip(y.iter()) {
            rgb += DVec3::from(*c) * *yk;
        }
        rgb.max(DVec3::ZERO)
    }

    /// A direction drawn from the table with `u` uniform in `[0, 1)³`.
    pub(crate) fn sample(&self, u: [f64; 3]) -> LightSample {
        let cell = self.cdf.partition_point(|&c| c <= u[0]).min(self.cdf.len() - 1);
        let d = cell_direction(cell, u[1], u[2]);
        let density = self.probability[cell] * (AZIMUTHS * HEIGHTS) as f64 / (4.0 * PI);
        LightSample {
            direction: d.as_vec3a(),
            weight: (self.radiance(d) / density).as_vec3(),
        }
    }
}

/// A direction in cell `c` at fractions `(fu, fv)` of its azimuth and height.
fn cell_direction(c: usize, fu: f64, fv: f64) -> DVec3 {
    let (i, j) = (c % AZIMUTHS, c / AZIMUTHS);
    let phi = (i as f64 + fu) / AZIMUTHS as f64 * 2.0 * PI;
    let z = -1.0 + (j as f64 + fv) / HEIGHTS as f64 * 2.0;
    let r = (1.0 - z * z).max(0.0).sqrt();
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}
