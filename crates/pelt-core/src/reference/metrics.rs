//! How far a preview image is from the reference, over the fur's pixels (those either image
//! covers): relative MSE in linear light (the figure the fur level-of-detail literature
//! reports), ꟻLIP (Andersson et al. 2020, through the `nv-flip` crate) on the display-encoded
//! images at full resolution and 4× downsampled (strand instances differ between the two, so the
//! downsampled figure is the fair one), the ratio of mean luminance, and the silhouette's alpha
//! profile: mean coverage against distance from the skin's outline, in fur depths.

use crate::error::{Num, PeltError, Result};
use crate::texture::color;

/// Width of one bin of the alpha profile, fur depths.
pub const PROFILE_BIN: f64 = 0.1;
/// Bins of the alpha profile: out to 1.5 fur depths from the skin.
pub const PROFILE_BINS: usize = 15;
/// Fewest pixels for a profile bin to count in [`ImageErrors::alpha_profile_error`].
const PROFILE_MIN_PIXELS: usize = 8;
/// Background the images are composited over before display encoding: middle grey.
const BACKGROUND: f32 = 0.214;

/// The error figures of one preview image.
#[derive(Debug, Clone, PartialEq)]
pub struct ImageErrors {
    /// `Σ |preview − reference|² / Σ |reference|²` over the fur's pixels, premultiplied linear
    /// RGB.
    pub relative_mse: f64,
    /// Mean ꟻLIP error over the fur's pixels, `[0, 1]`.
    pub flip: f64,
    /// The same with both images box-filtered to a quarter of the side first.
    pub flip_down4: f64,
    /// Mean luminance of the preview over the reference's, over the fur's pixels.
    pub luminance_ratio: f64,
    /// Largest difference of mean coverage between the two profiles, over bins with pixels.
    pub alpha_profile_error: f64,
    /// Mean coverage per bin of distance from the skin (bin `k` holds distances in
    /// `(k, k + 1] · PROFILE_BIN` fur depths): the preview's, then the reference's; NaN where a
    /// bin has no pixel.
    pub alpha_profile: [Vec<f64>; 2],
    /// The preview's fine detail over the reference's: the energy of luminance above about a
    /// tenth of a cycle per pixel (what a 5 × 5 box blur removes), over the fur's pixels. The
    /// hybrid paper's complaint about shells, a velvety look, is a ratio below 1. With the
    /// reference's pixel variances ([`compare_noisy`]) its Monte Carlo noise is taken out of its
    /// detail first; NaN where nothing is left.
    pub detail_ratio: f64,
    /// The share of the reference's measured detail that is its Monte Carlo noise (0 without
    /// its variances).
    pub detail_noise_share: f64,
}

/// An image to compare: premultiplied linear RGBA, rows top to bottom.
#[derive(Debug, Clone, Copy)]
pub struct LinearRgba<'a> {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// `width × height` pixels.
    pub pixels: &'a [[f32; 4]],
}

/// Compares `preview` with `reference` (same size); `skin_distance` is each pixel's distance
/// from the skin's outline in pixels (0 on the skin, see [`distance_from_mask`]) and
/// `fur_depth_pixels` the fur depth's length on screen.
///
/// # Errors
/// [`PeltError::InvalidParameter`] when the sizes differ or `fur_depth_pixels` is not positive.
pub fn compare(
    preview: LinearRgba<'_>,
    reference: LinearRgba<'_>,
    skin_distance: &[f32],
    fur_depth_pixels: f64,
) -> Result<ImageErrors> {
    compare_noisy(preview, reference, None, skin_distance, fur_depth_pixels)
}

/// [`compare`], with the variance of each reference pixel's luminance
/// ([`super::ReferenceImage::pixel_variance`]), whose noise is taken out of the reference's
/// detail.
///
/// # Errors
/// As [`compare`], and when `reference_variance` has another length.
pub fn compare_noisy(
    preview: LinearRgba<'_>,
    reference: LinearRgba<'_>,
    reference_variance: Option<&[f32]>,
    skin_distance: &[f32],
    fur_depth_pixels: f64,
) -> Result<ImageErrors> {
    let n = preview.width * preview.height;
    if (preview.width, preview.height) != (reference.width, reference.height)
        || preview.pixels.len() != n
        || reference.pixels.len() != n
        || skin_distance.len() != n
        || reference_variance.is_some_and(|v| v.len() != n)
    {
        return Err(PeltError::parameter(
            "preview",
            format!(
                "must match the reference's {} × {} pixels (and the skin distances), got {} × {}",
                reference.width, reference.height, preview.width, preview.height
            ),
        ));
    }
    if !(fur_depth_pixels.is_finite() && fur_depth_pixels > 0.0) {
        return Err(PeltError::parameter(
            "fur_depth_pixels",
            format!("must be positive, got {}", Num(fur_depth_pixels)),
        ));
    }
    let fur = |i: usize| preview.pixels[i][3] > 0.0 || reference.pixels[i][3] > 0.0;
    let (mut diff, mut norm, mut lum_p, mut lum_r) = (0.0, 0.0, 0.0, 0.0);
    for i in (0..n).filter(|&i| fur(i)) {
        let (p, r) = (preview.pixels[i], reference.pixels[i]);
        for c in 0..3 {
            diff += f64::from(p[c] - r[c]).powi(2);
            norm += f64::from(r[c]).powi(2);
        }
        lum_p += luminance(p);
        lum_r += luminance(r);
    }
    let profiles = [
        alpha_profile(preview, skin_distance, fur_depth_pixels),
        alpha_profile(reference, skin_distance, fur_depth_pixels),
    ];
    let alpha_profile_error = profiles[0]
        .iter()
        .zip(&profiles[1])
        .filter(|(p, r)| p.1 >= PROFILE_MIN_PIXELS && r.1 >= PROFILE_MIN_PIXELS)
        .map(|(p, r)| (p.0 - r.0).abs())
        .fold(0.0, f64::max);
    let (small_p, small_r) = (downsample4(preview), downsample4(reference));
    let fur_mask: Vec<bool> = (0..n).map(fur).collect();
    let measured = detail_energy(reference, &fur_mask);
    let noise = reference_variance.map_or(0.0, |v| {
        noise_detail(v, reference.width, reference.height, &fur_mask)
    });
    let detail_r = measured - noise;
    Ok(ImageErrors {
        relative_mse: if norm > 0.0 { diff / norm } else { 0.0 },
        flip: flip_mean(preview, reference),
        flip_down4: flip_mean(small_p.view(), small_r.view()),
        luminance_ratio: if lum_r > 0.0 { lum_p / lum_r } else { f64::NAN },
        alpha_profile_error,
        alpha_profile: profiles.map(|p| p.iter().map(|b| b.0).collect()),
        detail_ratio: if detail_r > 0.0 {
            detail_energy(preview, &fur_mask) / detail_r
        } else {
            f64::NAN
        },
        detail_noise_share: if measured > 0.0 { noise / measured } else { 0.0 },
    })
}

/// Side of the box blur whose residual [`detail_energy`] measures.
const DETAIL_BOX: usize = 5;

/// Mean over the `mask`ed pixels of (luminance − its `DETAIL_BOX`² box mean)², premultiplied
/// (a box cut at the image's edge averages what it has).
fn detail_energy(image: LinearRgba<'_>, mask: &[bool]) -> f64 {
    let lum: Vec<f64> = image.pixels.iter().map(|&p| luminance(p)).collect();
    over_boxes(&lum, image.width, image.height, mask, |v, sum, n| {
        (v - sum / n).powi(2)
    })
}

/// What independent noise of per-pixel variance `variance` adds to [`detail_energy`] on average:
/// the residual n_p − (1/N) Σ_box n_q has variance v_p (1 − 2/N) + Σ_box v_q / N².
fn noise_detail(variance: &[f32], w: usize, h: usize, mask: &[bool]) -> f64 {
    let variance: Vec<f64> = variance.iter().map(|&v| f64::from(v)).collect();
    over_boxes(&variance, w, h, mask, |v, sum, n| {
        v * (1.0 - 2.0 / n) + sum / (n * n)
    })
}

/// Mean over the `mask`ed pixels of `term(value, Σ over its DETAIL_BOX² box, pixels in the box)`.
fn over_boxes(values: &[f64], w: usize, h: usize, mask: &[bool], term: impl Fn(f64, f64, f64) -> f64) -> f64 {
    let r = DETAIL_BOX / 2;
    let (mut sum, mut count) = (0.0, 0usize);
    for y in 0..h {
        for x in (0..w).filter(|&x| mask[y * w + x]) {
            let (mut s, mut n) = (0.0, 0.0);
            for yy in y.saturating_sub(r)..(y + r + 1).min(h) {
                for xx in x.saturating_sub(r)..(x + r + 1).min(w) {
                    s += values[yy * w + xx];
                    n += 1.0;
                }
            }
            sum += term(values[y * w + x], s, n);
            count += 1;
        }
    }
    if count == 0 { 0.0 } else { sum / count as f64 }
}

/// Rec. 709 luminance of a linear RGBA pixel ([`color::luminance`]).
pub fn luminance(p: [f32; 4]) -> f64 {
    color::luminance([p[0], p[1], p[2]].map(f64::from))
}

/// Per bin, the mean coverage and the pixel count (NaN mean for none).
fn alpha_profile(image: LinearRgba<'_>, distance: &[f32], fur_depth_pixels: f64) -> Vec<(f64, usize)> {
    let mut sums = vec![(0.0, 0usize); PROFILE_BINS];
    for (p, &d) in image.pixels.iter().zip(distance) {
        if d <= 0.0 {
            continue;
        }
        let bin = (f64::from(d) / fur_depth_pixels / PROFILE_BIN).ceil() as usize;
        if (1..=PROFILE_BINS).contains(&bin) {
            sums[bin - 1].0 += f64::from(p[3]);
            sums[bin - 1].1 += 1;
        }
    }
    sums.into_iter()
        .map(|(s, c)| (if c > 0 { s / c as f64 } else { f64::NAN }, c))
        .collect()
}

/// An owned image, for the downsampled copies.
struct Owned {
    width: usize,
    height: usize,
    pixels: Vec<[f32; 4]>,
}

impl Owned {
    fn view(&self) -> LinearRgba<'_> {
        LinearRgba {
            width: self.width,
            height: self.height,
            pixels: &self.pixels,
        }
    }
}

/// 4 × 4 box filter of premultiplied pixels (a partial block at the edge averages what it has).
fn downsample4(image: LinearRgba<'_>) -> Owned {
    let (w, h) = (image.width.div_ceil(4), image.height.div_ceil(4));
    let mut pixels = vec![[0.0f32; 4]; w * h];
    for (j, row) in pixels.chunks_mut(w).enumerate() {
        for (i, out) in row.iter_mut().enumerate() {
            let mut sum = [0.0f32; 4];
            let mut count = 0.0;
            for y in 4 * j..(4 * j + 4).min(image.height) {
                for x in 4 * i..(4 * i + 4).min(image.width) {
                    let p = image.pixels[y * image.width + x];
                    for c in 0..4 {
                        sum[c] += p[c];
                    }
                    count += 1.0;
                }
            }
            *out = sum.map(|s| s / count);
        }
    }
    Owned {
        width: w,
        height: h,
        pixels,
    }
}

/// The image over the grey background, sRGB-encoded 8-bit RGB.
pub fn display_rgb8(image: LinearRgba<'_>) -> Vec<u8> {
    let encoder = crate::texture::color::srgb8_encoder();
    image
        .pixels
        .iter()
        .flat_map(|p| {
            let under = BACKGROUND * (1.0 - p[3]);
            [0, 1, 2].map(|c| encoder.encode(p[c] + under))
        })
        .collect()
}

/// The ꟻLIP error map of `preview` against `reference`, `[0, 1]` per pixel.
pub fn flip_map(preview: LinearRgba<'_>, reference: LinearRgba<'_>) -> Vec<f32> {
    let (w, h) = (reference.width as u32, reference.height as u32);
    let r = nv_flip::FlipImageRgb8::with_data(w, h, &display_rgb8(reference));
    let p = nv_flip::FlipImageRgb8::with_data(w, h, &display_rgb8(preview));
    nv_flip::flip(r, p, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec()
}

/// The ꟻLIP error map in the magma color map, 8-bit RGB, for pictures.
pub fn flip_picture(map: &[f32], width: usize, height: usize) -> Vec<u8> {
    let image = nv_flip::FlipImageFloat::with_data(width as u32, height as u32, map);
    image.apply_color_lut(&nv_flip::magma_lut()).to_vec()
}

fn flip_mean(preview: LinearRgba<'_>, reference: LinearRgba<'_>) -> f64 {
    let map = flip_map(preview, reference);
    let (sum, count) = map
        .iter()
        .zip(preview.pixels.iter().zip(reference.pixels))
        .filter(|(_, (p, r))| p[3] > 0.0 || r[3] > 0.0)
        .fold((0.0, 0usize), |(s, c), (e, _)| (s + f64::from(*e), c + 1));
    if count > 0 { sum / count as f64 } else { 0.0 }
}

/// Euclidean distance in pixels from each pixel to the nearest pixel of `mask` (0 on the mask;
/// infinity when the mask is empty): Felzenszwalb and Huttenlocher's exact transform, one
/// dimension at a time.
pub fn distance_from_mask(mask: &[bool], width: usize, height: usize) -> Vec<f32> {
    const FAR: f64 = 1e20;
    let mut squared: Vec<f64> = mask.iter().map(|&m| if m { 0.0 } else { FAR }).collect();
    let mut line = Vec::new();
    for x in 0..width {
        line.clear();
        line.extend((0..height).map(|y| squared[y * width + x]));
        for (y, v) in transform_1d(&line).into_iter().enumerate() {
            squared[y * width + x] = v;
        }
    }
    for row in squared.chunks_mut(width) {
        let out = transform_1d(row);
        row.copy_from_slice(&out);
    }
    squared
        .iter()
        .map(|&d| if d >= FAR { f32::INFINITY } else { d.sqrt() as f32 })
        .collect()
}

/// The 1D squared-distance transform of sampled function `f`: `min_q (p − q)² + f(q)`.
fn transform_1d(f: &[f64]) -> Vec<f64> {
    let n = f.len();
    if n == 0 {
        return Vec::new();
    }
    let mut out = vec![0.0; n];
    let mut hull = vec![0usize; n];
    let mut bounds = vec![0.0f64; n + 1];
    let mut k = 0;
    bounds[0] = f64::NEG_INFINITY;
    bounds[1] = f64::INFINITY;
    let meet = |q: usize, p: usize| {
        ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * q as f64 - 2.0 * p as f64)
    };
    for q in 1..n {
        let mut s = meet(q, hull[k]);
        while s <= bounds[k] {
            k -= 1;
            s = meet(q, hull[k]);
        }
        k += 1;
        hull[k] = q;
        bounds[k] = s;
        bounds[k + 1] = f64::INFINITY;
    }
    k = 0;
    for (p, o) in out.iter_mut().enumerate() {
        while bounds[k + 1] < p as f64 {
            k += 1;
        }
        let q = hull[k];
        *o = (p as f64 - q as f64).powi(2) + f[q];
    }
    out
}
