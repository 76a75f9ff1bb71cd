//! Level of detail of the shells (Lengyel et al. 2001, §2.4): far away fewer shells suffice, so
//! the volume's LOD levels composite successive pairs of shells (level `k` keeps the skin and has
//! `⌈(L − 1) / 2^k⌉` groups, group `j` holding level-0 layers `(j − 1) 2^k + 1 ..= j 2^k`,
//! standing where its hair covers the silhouette as those layers would (`stand_heights.rs`,
//! between the group's middle and its top), lit at its middle), and the renderer cross-fades
//! between two neighbouring levels as the object recedes: at blend `τ` shell `j` of level `k`
//! shows `(1 − τ)` of its own texture plus `τ` of level `k + 1`'s group `j / 2` and moves `τ` of
//! the way to where that group stands (nothing for odd `j` but the last, whose twin is itself),
//! so `τ = 1` is exactly level `k + 1` and nothing pops.
//!
//! The schedule follows the projected size: the fur depth in pixels (fur depth × the longest
//! painted length × pixels per object unit at the bounding sphere's centre) times
//! `shells_per_pixel` is the shell count wanted, clamped to `[min_shells, max_shells]`; it falls
//! between two levels' counts `S_{k+1} ≤ s < S_k`, and `τ = (S_k − s) / (S_k − S_{k+1})`.

use glam::{DVec3, Mat4};
use pelt_core::volume::lod::level_counts;

use super::camera::Camera;
use super::settings::RenderSettings;

/// What a frame draws, as [`super::Renderer::frame_info`] reports it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameInfo {
    /// Shells drawn above the skin (instances of the shell pass).
    pub shells: u32,
    /// LOD level drawn: 0 is the full stack, level `k` has `⌈L / 2^k⌉` layers.
    pub level: u32,
    /// Cross-fade toward level `level + 1`, `[0, 1)`; 0 without LOD.
    pub blend: f32,
    /// The continuous shell count the schedule asked for (`shells` without LOD).
    pub target_shells: f32,
    /// Radius of the mesh's bounding sphere in pixels; `None` when the camera is inside it.
    pub radius_pixels: Option<f32>,
    /// Fur depth × the longest painted length in pixels at the sphere's centre; `None` as above.
    pub fur_pixels: Option<f32>,
    /// Geometric level drawn ([`super::RenderSettings::mesh_error`]): 0 is the full mesh.
    pub mesh_level: u32,
    /// Triangles of that level (of the skin, and of each shell).
    pub triangles: u32,
}

/// The shell array's levels: level `k` has `counts[k]` layers from array layer `bases[k]`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct Levels {
    pub counts: Vec<u32>,
    pub bases: Vec<u32>,
}

impl Levels {
    /// Level 0 with `layers` layers, then the volume's LOD levels
    /// ([`pelt_core::volume::lod::level_counts`]: the skin and half as many groups each) down to a
    /// single layer.
    pub fn new(layers: u32) -> Self {
        let counts: Vec<u32> = level_counts(layers as usize)
            .into_iter()
            .map(|c| c as u32)
            .collect();
        let bases = counts
            .iter()
            .scan(0, |base, &c| {
                let here = *base;
                *base += c;
                Some(here)
            })
            .collect();
        Levels { counts, bases }
    }

    /// Layers of all levels together.
    pub fn total(&self) -> u32 {
        self.counts.iter().sum()
    }

    /// The LOD composites (array layers past level 0, counted from the first) that a frame
    /// drawing `info` reads: its level's, and the next coarser one's while it cross-fades.
    pub fn composites_drawn(&self, info: &FrameInfo) -> std::ops::Range<u32> {
        let k = info.level as usize;
        let Some(&start) = self.bases.get(k) else {
            return 0..0;
        };
        let coarser = if info.blend > 0.0 {
            self.counts.get(k + 1).copied().unwrap_or(0)
        } else {
            0
        };
        let end = start + self.counts[k] + coarser;
        let first = self.counts[0];
        start.max(first) - first..end.max(first) - first
    }
}

/// The mesh's bounding sphere and painted lengths, what the schedule reads from the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Extent {
    pub center: DVec3,
    pub radius: f64,
    /// The longest painted length multiplier.
    pub max_length: f64,
}

/// Pixels per object unit at `center` seen by `camera` (validated), or `None` when the camera
/// is inside the sphere of `radius` (or behind its centre).
fn pixels_per_unit(camera: &Camera, center: DVec3, radius: f64) -> Option<f64> {
    projected_scale(camera, center, radius, 0.0)
}

/// The most pixels per object unit anywhere on the sphere of `radius` around `center` (at its
/// point nearest the eye), or `None` as [`pixels_per_unit`].
pub(super) fn nearest_pixels_per_unit(camera: &Camera, center: DVec3, radius: f64) -> Option<f64> {
    projected_scale(camera, center, radius, radius)
}

/// Pixels per object unit at depth `center` moved `toward` object units toward the eye.
fn projected_scale(camera: &Camera, center: DVec3, radius: f64, toward: f64) -> Option<f64> {
    let view = Mat4::from_cols_array(&camera.view).as_dmat4();
    let proj = Mat4::from_cols_array(&camera.projection).as_dmat4();
    let view_point = view * center.extend(1.0);
    // The view matrix may scale: object units to view units along its longest axis.
    let scale = [view.x_axis, view.y_axis, view.z_axis]
        .map(|axis| axis.truncate().length())
        .into_iter()
        .fold(0.0, f64::max);
    let last = proj.row(3);
    let perspective = last.z != 0.0;
    let w = last.dot(view_point) - toward * scale * last.z.abs();
    // The eye looks down −z: a centre closer than the radius has the camera inside the sphere.
    if perspective && -view_point.z <= radius * scale {
        return None;
    }
    if w.is_nan() || w <= 0.0 {
        return None;
    }
    let half_extent = 0.5
        * (proj.x_axis.x.abs() * f64::from(camera.width)).max(proj.y_axis.y.abs() * f64::from(camera.height));
    let ppu = scale * half_extent / w;
    ppu.is_finite().then_some(ppu)
}

/// The level and blend for `settings` (checked) of a scene of `extent` whose fur is `fur_depth`
/// object units deep, with `fixed` the shell count without LOD.
pub(super) fn choose(
    levels: &Levels,
    settings: &RenderSettings,
    camera: &Camera,
    extent: &Extent,
    fur_depth: f32,
    fixed: u32,
) -> FrameInfo {
    let ppu = pixels_per_unit(camera, extent.center, extent.radius);
    let radius_pixels = ppu.map(|p| (p * extent.radius) as f32);
    let fur_pixels = ppu.map(|p| (p * f64::from(fur_depth) * extent.max_length) as f32);
    let fixed_info = FrameInfo {
        shells: fixed,
        level: 0,
        blend: 0.0,
        target_shells: fixed as f32,
        radius_pixels,
        fur_pixels,
        mesh_level: 0,
        triangles: 0,
    };
    if !settings.lod {
        return fixed_info;
    }
    let shells: Vec<f64> = levels.counts.iter().map(|&c| f64::from(c - 1)).collect();
    let most = shells[0];
    let (lo, hi) = (
        f64::from(settings.min_shells).min(most),
        f64::from(settings.max_shells).min(most),
    );
    let wanted = fur_pixels.map_or(hi, |px| f64::from(px) * f64::from(settings.shells_per_pixel));
    let s = wanted.clamp(lo, hi);
    let (mut level, mut blend) = (0, 0.0);
    if s < most {
        for k in 0..shells.len() - 1 {
            if s >= shells[k + 1] {
                let tau = ((shells[k] - s) / (shells[k] - shells[k + 1])) as f32;
                // A blend that rounds to 1 is the next level itself.
                (level, blend) = if tau >= 1.0 { (k + 1, 0.0) } else { (k, tau) };
                break;
            }
        }
    }
    FrameInfo {
        shells: shells[level] as u32,
        level: level as u32,
        blend,
        target_shells: s as f32,
        ..fixed_info
    }
}
