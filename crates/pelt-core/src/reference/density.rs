//! The baked hair volume read as a density field, for the reference's volume mode (the hybrid
//! paper, §3.2): the bake's coverage per texel and layer turned into an extinction coefficient,
//! with the shells' color and hair tangent, filtered as the shells are (bilinear over the tile,
//! repeating; linear between layers).
//!
//! A layer's coverage `c` is the share of a horizontal slice that the hairs' circular
//! cross-sections cover (`volume::shells`): `c / (π r²)` hairs cross a unit of slice area, `r`
//! their radius. A hair of unit tangent `t` crossing slices of unit normal `n` lays `1 / |t·n|`
//! of length per unit height and blocks a ray of direction `ω` over the width `2r |ω × t|`, so
//! the extinction is `σ(ω) = 2 c |ω × t| / (π r |t·n|)`, in the units of `r`. The layer's `r`
//! is its strands' `Σ r² / Σ r`, which makes the formula exact for the layer's mean when radii
//! differ (taper, the two coats).

use glam::{Vec2, Vec3};

use crate::error::{PeltError, Result};
use crate::hair::Strand;
use crate::texture::color::srgb8_to_linear_table;
use crate::volume::HairVolume;

/// The volume's fields, `[layer][row][column]`, and each layer's effective hair radius.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DensityField {
    resolution: usize,
    layers: usize,
    /// Height between layers, fur depths; layer `l` stands at `l · spacing`.
    spacing: f32,
    coverage: Vec<f32>,
    /// Straight sRGB color and alpha, as the shells hold it.
    shells: Vec<u8>,
    /// Hair tangent packed `0.5 · d + 0.5` (x along u, y along v, z up).
    tangents: Vec<u8>,
    /// Effective hair radius per layer, tile units.
    radius: Vec<f32>,
}

/// The field at a point: coverage, hair direction in the tile frame (not unit) and radius.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Density {
    pub coverage: f32,
    pub tangent: Vec3,
    pub radius: f32,
}

/// The four texels around a tile point and their bilinear weights.
struct Taps {
    index: [usize; 4],
    weight: [f32; 4],
}

impl DensityField {
    /// The field of a bake: `volume`'s layers, with radii from the `strands` it was sampled from.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] (`volume`) when the volume's arrays do not match its
    /// sizes.
    pub(crate) fn from_volume(volume: &HairVolume, strands: &[Strand]) -> Result<Self> {
        let spacing = volume.layer_spacing as f32;
        let radius = (0..volume.layers)
            .map(|l| effective_radius(strands, f64::from(l as f32 * spacing)))
            .collect();
        Self::new(
            volume.resolution,
            volume.layers,
            spacing,
            volume.coverage.clone(),
            volume.shells.clone(),
            volume.tangents.clone(),
            radius,
        )
    }

    /// A field from its parts (see the fields).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] (`volume`) when a size does not match or the spacing is
    /// not positive.
    pub(crate) fn new(
        resolution: usize,
        layers: usize,
        spacing: f32,
        coverage: Vec<f32>,
        shells: Vec<u8>,
        tangents: Vec<u8>,
        radius: Vec<f32>,
    ) -> Result<Self> {
        let texels = resolution * resolution * layers;
        let fits = resolution > 0
            && layers > 0
            && spacing.is_finite()
            && spacing > 0.0
            && coverage.len() == texels
            && shells.len() == 4 * texels
            && tangents.len() == 4 * texels
            && radius.len() == layers
            && coverage.iter().all(|c| c.is_finite() && *c >= 0.0)
            && radius.iter().all(|r| r.is_finite() && *r >= 0.0);
        if !fits {
            return Err(PeltError::parameter(
                "volume",
                format!(
                    "a {resolution}² × {layers} volume needs {texels} coverages, \
                     {} color and tangent bytes and {layers} radii, all finite and not negative, \
                     and a positive layer spacing (got {spacing})",
                    4 * texels
                ),
            ));
        }
        Ok(DensityField {
            resolution,
            layers,
            spacing,
            coverage,
            shells,
            tangents,
            radius,
        })
    }

    /// Height of the volume's top, fur depths: one spacing above the last layer, where the
    /// coverage has fallen to 0.
    pub(crate) fn top(&self) -> f32 {
        self.layers as f32 * self.spacing
    }

    /// Whether any texel holds hair.
    pub(crate) fn has_hair(&self) -> bool {
        self.coverage.iter().any(|&c| c > 0.0)
    }

    /// Texels per tile side.
    pub(crate) fn resolution(&self) -> usize {
        self.resolution
    }

    /// Height between layers, fur depths.
    pub(crate) fn spacing(&self) -> f32 {
        self.spacing
    }

    fn taps(&self, uv: Vec2) -> Taps {
        let r = self.resolution as f32;
        let x = uv.x * r - 0.5;
        let y = uv.y * r - 0.5;
        let (fx, fy) = (x - x.floor(), y - y.floor());
        let n = self.resolution as i64;
        let wrap = |v: f32| (v.floor() as i64).rem_euclid(n) as usize;
        let (x0, y0) = (wrap(x), wrap(y));
        let (x1, y1) = ((x0 + 1) % self.resolution, (y0 + 1) % self.resolution);
        let row = self.resolution;
        Taps {
            index: [y0 * row + x0, y0 * row + x1, y1 * row + x0, y1 * row + x1],
            weight: [(1.0 - fx) * (1.0 - fy), fx * (1.0 - fy), (1.0 - fx) * fy, fx * fy],
        }
    }

    /// The two layers around height `z` (fur depths) and their weights; a layer past the top
    /// weighs nothing.
    fn layers_at(&self, z: f32) -> [(usize, f32); 2] {
        let lz = (z / self.spacing).max(0.0);
        let l0 = lz.floor() as usize;
        let f = lz - l0 as f32;
        let keep = |l: usize, w: f32| if l < self.layers { (l, w) } else { (0, 0.0) };
        [keep(l0, 1.0 - f), keep(l0 + 1, f)]
    }

    /// The field at tile point `uv`, height `z` fur depths. The tangent is the texels' mean
    /// weighted by their coverage (the hairs present), read only where some hair is.
    pub(crate) fn density(&self, uv: Vec2, z: f32) -> Density {
        let taps = self.taps(uv);
        let plane = self.resolution * self.resolution;
        let mut out = Density {
            coverage: 0.0,
            tangent: Vec3::ZERO,
            radius: 0.0,
        };
        let mut radius_weight = 0.0;
        for (layer, lw) in self.layers_at(z) {
            if lw == 0.0 {
                continue;
            }
            // The radius of the layers present: above the last layer the coverage fades to 0
            // while the hairs there keep their width.
            out.radius += lw * self.radius[layer];
            radius_weight += lw;
            for (&i, &w) in taps.index.iter().zip(&taps.weight) {
                let k = layer * plane + i;
                let c = lw * w * self.coverage[k];
                if c > 0.0 {
                    out.coverage += c;
                    let t = &self.tangents[4 * k..4 * k + 3];
                    let d =
                        Vec3::new(f32::from(t[0]), f32::from(t[1]), f32::from(t[2])) * (2.0 / 255.0) - 1.0;
                    out.tangent += c * d;
                }
            }
        }
        if radius_weight > 0.0 {
            out.radius /= radius_weight;
        }
        out
    }

    /// Linear hair color at tile point `uv`, height `z`.
    pub(crate) fn color(&self, uv: Vec2, z: f32) -> Vec3 {
        let table = srgb8_to_linear_table();
        let taps = self.taps(uv);
        let plane = self.resolution * self.resolution;
        let mut out = Vec3::ZERO;
        let mut total = 0.0;
        for (layer, lw) in self.layers_at(z) {
            total += lw;
            for (&i, &w) in taps.index.iter().zip(&taps.weight) {
                let k = 4 * (layer * plane + i);
                let c = &self.shells[k..k + 3];
                out += (lw * w) * Vec3::new(table[c[0] as usize], table[c[1] as usize], table[c[2] as usize]);
            }
        }
        // Above the last layer the hairs fade out, not their color.
        if total > 0.0 { out / total } else { out }
    }
}

/// `Σ r² / Σ r` over the strands that reach height `z` (fur depths), at that height; 0 where
/// none does.
fn effective_radius(strands: &[Strand], z: f64) -> f32 {
    let (mut squares, mut sum) = (0.0f64, 0.0f64);
    for s in strands {
        let height = s.height();
        let n = s.radii.len();
        if n < 2 || height <= 0.0 || z > height {
            continue;
        }
        let at = z / height * (n - 1) as f64;
        let i = (at.floor() as usize).min(n - 2);
        let f = at - i as f64;
        let r = s.radii[i] * (1.0 - f) + s.radii[i + 1] * f;
        squares += r * r;
        sum += r;
    }
    if sum > 0.0 { (squares / sum) as f32 } else { 0.0 }
}
