//! Progressive rendering of the reference image: passes of a few jittered samples per pixel,
//! each sample a view ray to the nearest hair or skin, lit by every light through a shadow ray;
//! passes continue until the image's mean radiance is known to the target relative standard
//! error (estimated from the spread of the passes' means), at least `min_samples` per pixel.
//!
//! Every sample draws from its own generator, seeded by the pixel and the sample's index, and
//! each pixel sums its samples in order, so the image is bit-identical for any thread count.

use std::f32::consts::PI;
use std::time::Instant;

use glam::{DVec4, Vec3A};
use rayon::prelude::*;

use super::camera::RayGenerator;
use super::light::ReferenceLight;
use super::sampler::{Lights, Sampler};
use super::scene::ReferenceScene;
pub use super::settings::{MAX_PIXELS, MAX_SAMPLES, ReferenceSettings};
use super::volume::VolumeScene;
use crate::camera::Camera;
use crate::error::{PeltError, Result};
use crate::progress::ProgressCallback;
use crate::rng::Rng;
use crate::texture::color::luminance;
use crate::threads::pool;

/// A converged reference image.
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceImage {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// Rows top to bottom: linear RGB radiance premultiplied by coverage, and coverage (the
    /// share of the pixel's samples that hit the fur or the skin). No tone mapping.
    pub pixels: Vec<[f32; 4]>,
    /// Samples per pixel taken.
    pub samples: u32,
    /// Relative standard error of the image's mean radiance (luminance) achieved.
    pub relative_error: f64,
    /// Root mean square of the covered pixels' own standard errors, relative to their mean
    /// luminance: how noisy a single pixel still is.
    pub pixel_error: f64,
    /// Per pixel, the variance of its luminance's Monte Carlo estimate (from the spread of its
    /// passes; 0 where it had one pass or none): the noise left in the image, which the image
    /// metrics take out of the reference's fine detail.
    pub pixel_variance: Vec<f32>,
    /// Seconds spent rendering (the scene's BVH not included).
    pub seconds: f64,
}

impl ReferenceImage {
    /// The image for display: sRGB-encoded 8-bit RGBA with straight alpha (color divided by
    /// coverage), rows top to bottom.
    pub fn display_rgba8(&self) -> Vec<u8> {
        let encoder = crate::texture::color::srgb8_encoder();
        self.pixels
            .iter()
            .flat_map(|p| {
                let a = p[3];
                let straight = |c: f32| if a > 0.0 { c / a } else { 0.0 };
                [
                    encoder.encode(straight(p[0])),
                    encoder.encode(straight(p[1])),
                    encoder.encode(straight(p[2])),
                    crate::texture::color::unit_to_u8(a),
                ]
            })
            .collect()
    }
}

/// Renders the reference image of `scene` seen by `camera` under `lights`.
///
/// `progress` hears the share of `min_samples` done (capped at 1) after each pass and cancels by
/// returning `false`; nothing is returned then.
///
/// # Errors
/// [`PeltError::InvalidParameter`] for a bad setting, camera or light, or an eye enclosed by the
/// mesh (`camera.view`); [`PeltError::Cancelled`] when `progress` cancelled.
pub fn render_reference(
    scene: &ReferenceScene,
    camera: &Camera,
    lights: &[ReferenceLight],
    settings: &ReferenceSettings,
    progress: Option<ProgressCallback<'_>>,
) -> Result<ReferenceImage> {
    render_with(scene, camera, lights, settings, progress)
}

/// Renders `scene`'s density volume (the hybrid paper's mode, [`super::volume`]) as
/// [`render_reference`] renders the strands: same camera, lights, settings and convergence.
///
/// # Errors
/// As [`render_reference`].
pub fn render_volume_reference(
    scene: &VolumeScene,
    camera: &Camera,
    lights: &[ReferenceLight],
    settings: &ReferenceSettings,
    progress: Option<ProgressCallback<'_>>,
) -> Result<ReferenceImage> {
    render_with(scene, camera, lights, settings, progress)
}

/// Host memory per pixel of a reference image, for the memory budget: the f64 sums (56 bytes),
/// the image and its variances (20) and a caller's copy of both (20).
const BYTES_PER_PIXEL: f64 = 96.0;

fn render_with<S: Sampler>(
    scene: &S,
    camera: &Camera,
    lights: &[ReferenceLight],
    settings: &ReferenceSettings,
    progress: Option<ProgressCallback<'_>>,
) -> Result<ReferenceImage> {
    let start = Instant::now();
    settings.validate()?;
    let rays = camera.rays()?;
    let pixels = u64::from(camera.width) * u64::from(camera.height);
    if pixels > MAX_PIXELS {
        return Err(PeltError::parameter(
            "camera.width",
            format!(
                "{} × {} is {pixels} pixels, the reference renders at most {MAX_PIXELS}",
                camera.width, camera.height
            ),
        ));
    }
    crate::memory::check("render_reference", pixels as f64 * BYTES_PER_PIXEL, || {
        format!("`width` ({}) or `height` ({})", camera.width, camera.height)
    })?;
    let prepared = lights
        .iter()
        .enumerate()
        .map(|(i, l)| l.prepare(i))
        .collect::<Result<Vec<_>>>()?;
    if let Some(eye) = rays.eye()
        && scene.encloses(eye)
    {
        return Err(PeltError::parameter(
            "camera.view",
            format!(
                "the eye at {eye} lies inside the mesh: the reference sees nothing but the skin's inside"
            ),
        ));
    }
    let (lo, hi) = scene.bounds();
    let extent = (Vec3A::from(hi) - Vec3A::from(lo))
        .length()
        .max(f32::MIN_POSITIVE);
    let tracer = Tracer {
        scene,
        rays,
        lights: Lights {
            prepared: &prepared,
            settings,
            epsilon: extent * 1e-6,
        },
    };

    let width = camera.width as usize;
    let n = width * camera.height as usize;
    let mut sums = vec![DVec4::ZERO; n];
    let mut lum_sum = vec![0.0f64; n];
    let mut lum_squares = vec![0.0f64; n];
    let mut pass_lum = vec![0.0f64; n];
    let mut pass_means = Vec::new();
    let mut samples = 0u32;
    let mut relative_error = f64::INFINITY;
    while samples < settings.max_samples {
        let count = settings.samples_per_pass.min(settings.max_samples - samples);
        pool().install(|| {
            sums.par_chunks_mut(width)
                .zip(lum_sum.par_chunks_mut(width))
                .zip(lum_squares.par_chunks_mut(width))
                .zip(pass_lum.par_chunks_mut(width))
                .enumerate()
                .for_each(|(y, (((sum, ls), lq), pl))| {
                    for x in 0..width {
                        let pixel = (y * width + x) as u64;
                        let mut pass = DVec4::ZERO;
                        for s in samples..samples + count {
                            pass += tracer.sample(x, y, pixel, s);
                        }
                        sum[x] += pass;
                        let l = luminance(pass.truncate().to_array()) / f64::from(count);
                        ls[x] += l;
                        lq[x] += l * l;
                        pl[x] = l;
                    }
                });
        });
        samples += count;
        pass_means.push(pass_lum.iter().sum::<f64>() / n as f64);
        relative_error = mean_error(&pass_means);
        if let Some(callback) = progress
            && !callback((f64::from(samples) / f64::from(settings.min_samples)).min(1.0))
        {
            return Err(PeltError::Cancelled);
        }
        if samples >= settings.min_samples && pass_means.len() >= 2 && relative_error <= settings.target_error
        {
            break;
        }
    }
    let inv = 1.0 / f64::from(samples);
    let out: Vec<[f32; 4]> = sums.iter().map(|s| (*s * inv).as_vec4().to_array()).collect();
    let variances: Vec<f64> = lum_sum
        .iter()
        .zip(&lum_squares)
        .map(|(&s, &q)| mean_variance(s, q, pass_means.len()))
        .collect();
    let pixel_error = pixel_error(&out, &lum_sum, &variances, pass_means.len());
    let pixel_variance = variances.iter().map(|&v| v as f32).collect();
    Ok(ReferenceImage {
        width: camera.width,
        height: camera.height,
        pixels: out,
        samples,
        relative_error,
        pixel_error,
        pixel_variance,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// Relative standard error of the mean of the passes' means (0 for a black image).
fn mean_error(means: &[f64]) -> f64 {
    let k = means.len() as f64;
    if means.len() < 2 {
        return f64::INFINITY;
    }
    let mean = means.iter().sum::<f64>() / k;
    if mean <= 0.0 {
        return 0.0;
    }
    let var = means.iter().map(|m| (m - mean) * (m - mean)).sum::<f64>() / (k - 1.0);
    (var / k).sqrt() / mean
}

/// The variance of the mean of `passes` pass luminances of sum `sum` and sum of squares
/// `squares` (the unbiased sample variance over the passes, over their count); 0 under two passes.
fn mean_variance(sum: f64, squares: f64, passes: usize) -> f64 {
    if passes < 2 {
        return 0.0;
    }
    let k = passes as f64;
    let mean = sum / k;
    ((squares / k - mean * mean) * k / (k - 1.0)).max(0.0) / k
}

/// `variances`: each pixel's [`mean_variance`].
fn pixel_error(pixels: &[[f32; 4]], sums: &[f64], variances: &[f64], passes: usize) -> f64 {
    if passes < 2 {
        return f64::INFINITY;
    }
    let k = passes as f64;
    let (mut var_total, mut lum_total, mut covered) = (0.0, 0.0, 0usize);
    for ((p, &s), &v) in pixels.iter().zip(sums).zip(variances) {
        if p[3] > 0.0 {
            var_total += v;
            lum_total += s / k;
            covered += 1;
        }
    }
    if covered == 0 || lum_total <= 0.0 {
        return 0.0;
    }
    (var_total / covered as f64).sqrt() / (lum_total / covered as f64)
}

/// What one sample needs.
struct Tracer<'a, S> {
    scene: &'a S,
    rays: RayGenerator,
    lights: Lights<'a>,
}

impl<S: Sampler> Tracer<'_, S> {
    /// Sample `s` of pixel `(x, y)`: premultiplied radiance and coverage.
    fn sample(&self, x: usize, y: usize, pixel: u64, s: u32) -> DVec4 {
        let mut rng = Rng::stream(self.lights.settings.seed, pixel, u64::from(s));
        let (jx, jy) = (rng.next_f64(), rng.next_f64());
        let (origin, direction) = self.rays.ray(x as f64 + jx, y as f64 + jy);
        let (radiance, coverage) = self.scene.sample(origin, direction, &self.lights, &mut rng);
        (radiance.as_dvec3() / f64::from(PI)).extend(f64::from(coverage))
    }
}
