//! What the progressive loop (`render.rs`) asks of a traceable scene ([`Sampler`]: the strands of
//! `scene.rs` or the density volume of `volume.rs`) and the lights a sample draws from
//! ([`Lights`]). Its own file so that the loop and the scenes both import it and not each other.

use glam::{Vec3, Vec3A};

use super::geometry::SkinPoint;
use super::light::{LightSample, Prepared};
use super::settings::ReferenceSettings;
use super::shade::HairShading;
use crate::rng::Rng;

/// The lights of one render, ready to sample, with what shading needs besides the scene.
pub(crate) struct Lights<'a> {
    pub prepared: &'a [Prepared],
    pub settings: &'a ReferenceSettings,
    /// Offset of shadow rays off their surface, object units.
    pub epsilon: f32,
}

impl Lights<'_> {
    /// A direction toward `light` with its weight (a sun's own; one importance sample of an
    /// environment).
    pub(crate) fn sample(&self, light: &Prepared, rng: &mut Rng) -> LightSample {
        match light {
            Prepared::Sun {
                direction,
                radiance_scale,
            } => LightSample {
                direction: *direction,
                weight: *radiance_scale,
            },
            Prepared::Environment(sampler) => {
                sampler.sample([rng.next_f64(), rng.next_f64(), rng.next_f64()])
            }
        }
    }

    pub(crate) fn shading(&self) -> &HairShading {
        &self.settings.shading
    }

    /// Light reaching a point from every light, × π: `Σ weight · f(ω) · visibility(ω)`, with
    /// `visibility` (drawing from `rng` after the light's own sample) asked only where `f` is
    /// not zero, and taken as 1 with shadows off.
    pub(crate) fn direct(
        &self,
        rng: &mut Rng,
        mut f: impl FnMut(Vec3A) -> Vec3,
        mut visibility: impl FnMut(Vec3A, &mut Rng) -> f32,
    ) -> Vec3 {
        let mut radiance = Vec3::ZERO;
        for light in self.prepared {
            let l = self.sample(light, rng);
            let value = f(l.direction);
            if value == Vec3::ZERO {
                continue;
            }
            let seen = if self.settings.shadows {
                visibility(l.direction, rng)
            } else {
                1.0
            };
            radiance += l.weight * value * seen;
        }
        radiance
    }

    /// A skin point's Lambertian light (none from behind its face), `visibility` seen from
    /// `lifted`, the point moved off the skin.
    pub(crate) fn skin(
        &self,
        skin: &SkinPoint,
        rng: &mut Rng,
        visibility: impl FnMut(Vec3A, &mut Rng) -> f32,
    ) -> Vec3 {
        let shading = self.shading();
        self.direct(
            rng,
            |l| {
                if skin.face.dot(l) <= 0.0 {
                    Vec3::ZERO
                } else {
                    shading.skin(skin.normal, l, skin.albedo)
                }
            },
            visibility,
        )
    }
}

/// What the progressive loop needs of a traceable scene (the strands, or their density volume).
pub(crate) trait Sampler: Sync {
    /// Lowest and highest corner.
    fn bounds(&self) -> ([f32; 3], [f32; 3]);
    /// Whether `eye` lies inside the skin.
    fn encloses(&self, eye: Vec3A) -> bool;
    /// One sample along the unit ray `origin + t · direction`: radiance × π (premultiplied by
    /// coverage) and coverage.
    fn sample(&self, origin: Vec3A, direction: Vec3A, lights: &Lights<'_>, rng: &mut Rng) -> (Vec3, f32);
}
