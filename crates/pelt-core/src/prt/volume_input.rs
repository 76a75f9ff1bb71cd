//! A baked hair volume as the input of the transfer bake.
//!
//! The volume's coverage is the share of each texel the hair cross-sections cover at the layer's
//! height (prt-shell-fur §2.2's density ρ, sampled on horizontal slices). A light path meets hair
//! in proportion to the hair's *length* per volume, and a hair of unit tangent `t` lays `1 / |t_z|`
//! of length per unit of height: the reference's density model (`reference::density`,
//! `σ(ω) = 2c |ω × t| / (π r |t_z|)`) has the same factor. So the density handed to the bake is
//! the coverage over `|t_z|` (at least [`MIN_CROSSING_COSINE`]), computed with the tangent
//! squashed to the fur's depth: short fur lies flatter and shadows more per unit of coverage than
//! long fur of the same strands. The direction-dependent `|ω × t|` is left to the extinction σ
//! (the sweep's layer pyramids are then shared by every direction).
//!
//! The transfer measures lengths in texel widths, so the layer spacing follows from the fur
//! depth: layer `i` of the volume sits at `i / L` of the depth, and the depth in tile widths
//! times the resolution gives it in texels. The packed hair tangents are decoded, squashed with
//! the same height scale, and zeroed where no hair is (the bake gives such voxels the isotropic
//! mean of the Kajiya–Kay phase).

use glam::Vec3;

use crate::volume::HairVolume;

use super::transfer::TransferVolume;

/// Smallest `|t_z|` of a unit hair tangent in the density: hairs lying flat would make it
/// unbounded, where the slice coverage no longer describes them (the reference's bound).
pub const MIN_CROSSING_COSINE: f32 = 0.1;

/// The decoded tangents, path density and spacing of a volume, kept so [`TransferVolume`] can
/// borrow them.
#[derive(Debug, Clone)]
pub struct VolumeInput {
    /// Hair direction per voxel in texel units (x, y lateral, z up); zero where no hair is.
    pub tangents: Vec<[f32; 3]>,
    /// Coverage over the hair's `|t_z|` per voxel (see the module's doc).
    pub density: Vec<f32>,
    /// Distance between layers, texel widths.
    pub layer_spacing: f32,
}

impl VolumeInput {
    /// Reads `volume` with the fur `depth_tiles` tile widths deep (the fur depth in object units
    /// over the tile size; the strands are grown in a unit cube, so 1 keeps their shape, a smaller
    /// depth flattens them).
    pub fn new(volume: &HairVolume, depth_tiles: f64) -> Self {
        let tangents: Vec<[f32; 3]> = volume
            .tangents
            .chunks_exact(4)
            .zip(&volume.coverage)
            .map(|(px, &coverage)| {
                if coverage > 0.0 {
                    let d = |b: u8| f32::from(b) / 255.0 * 2.0 - 1.0;
                    [d(px[0]), d(px[1]), d(px[2]) * depth_tiles as f32]
                } else {
                    [0.0; 3]
                }
            })
            .collect();
        let density = tangents
            .iter()
            .zip(&volume.coverage)
            .map(|(t, &coverage)| coverage / crossing_cosine(*t))
            .collect();
        let layer_spacing = (volume.layer_spacing * depth_tiles * volume.resolution as f64) as f32;
        VolumeInput {
            tangents,
            density,
            layer_spacing,
        }
    }

    /// The transfer input over `volume` (the one this was made from).
    pub fn transfer_volume<'a>(&'a self, volume: &'a HairVolume) -> TransferVolume<'a> {
        TransferVolume {
            layers: volume.layers,
            resolution: volume.resolution,
            layer_spacing: self.layer_spacing,
            density: &self.density,
            tangents: Some(&self.tangents),
        }
    }
}

/// `|t_z|` of the unit tangent along `t`, at least [`MIN_CROSSING_COSINE`]; 1 for no hair (a
/// zero tangent, where the coverage is zero anyway).
fn crossing_cosine(t: [f32; 3]) -> f32 {
    Vec3::from(t)
        .try_normalize()
        .map_or(1.0, |unit| unit.z.abs().max(MIN_CROSSING_COSINE))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hair_lays_one_over_its_crossing_cosine_of_length_per_unit_of_height() {
        let (s, c) = (60f32.to_radians().sin(), 60f32.to_radians().cos());
        assert!((crossing_cosine([0.0, 0.0, 2.0]) - 1.0).abs() < 1e-6);
        // 60° from upright: 1 / cos 60° = 2 of length per unit height, whatever the length of t.
        assert!((crossing_cosine([3.0 * s, 0.0, 3.0 * c]) - 0.5).abs() < 1e-6);
        // The same hair squashed to a quarter of the depth leans to atan(4 tan 60°) = 81.8°.
        let squashed = 81.79f32.to_radians().cos();
        assert!((crossing_cosine([s, 0.0, c * 0.25]) - squashed).abs() < 1e-3);
        // Lying flat or hanging down: bounded; no hair: 1 (its coverage is zero anyway).
        assert_eq!(crossing_cosine([1.0, 0.0, 0.0]), MIN_CROSSING_COSINE);
        assert!((crossing_cosine([0.0, 0.0, -1.0]) - 1.0).abs() < 1e-6);
        assert_eq!(crossing_cosine([0.0; 3]), 1.0);
    }
}
