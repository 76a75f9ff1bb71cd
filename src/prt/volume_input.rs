//! A baked hair volume as the input of the transfer bake.
//!
//! The volume's coverage is the density ρ of prt-shell-fur §2.2 (the share of each texel the hair
//! cross-sections cover at the layer's height). The transfer measures lengths in texel widths, so
//! the layer spacing follows from the fur depth: layer `i` of the volume sits at `i / L` of the
//! depth, and the depth in tile widths times the resolution gives it in texels. The packed hair
//! tangents are decoded, squashed with the same height scale, and zeroed where no hair is (the
//! bake gives such voxels the isotropic mean of the Kajiya–Kay phase).

use crate::volume::HairVolume;

use super::transfer::TransferVolume;

/// The decoded tangents and the spacing of a volume, kept so [`TransferVolume`] can borrow them.
#[derive(Debug, Clone)]
pub struct VolumeInput {
    /// Hair direction per voxel in texel units (x, y lateral, z up); zero where no hair is.
    pub tangents: Vec<[f32; 3]>,
    /// Distance between layers, texel widths.
    pub layer_spacing: f32,
}

impl VolumeInput {
    /// Reads `volume` with the fur `depth` tile widths deep (the strands are grown in a unit cube,
    /// so 1 keeps their shape; a smaller depth flattens them).
    pub fn new(volume: &HairVolume, depth: f64) -> Self {
        let tangents = volume
            .tangents
            .chunks_exact(4)
            .zip(&volume.coverage)
            .map(|(px, &coverage)| {
                if coverage > 0.0 {
                    let d = |b: u8| f32::from(b) / 255.0 * 2.0 - 1.0;
                    [d(px[0]), d(px[1]), d(px[2]) * depth as f32]
                } else {
                    [0.0; 3]
                }
            })
            .collect();
        let layer_spacing = (volume.layer_spacing * depth * volume.resolution as f64) as f32;
        VolumeInput {
            tangents,
            layer_spacing,
        }
    }

    /// The transfer input over `volume` (the one this was made from).
    pub fn transfer_volume<'a>(&'a self, volume: &'a HairVolume) -> TransferVolume<'a> {
        TransferVolume {
            layers: volume.layers,
            resolution: volume.resolution,
            layer_spacing: self.layer_spacing,
            density: &volume.coverage,
            tangents: Some(&self.tangents),
        }
    }
}
