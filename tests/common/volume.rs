//! The hair volume the render tests bake: small (64², a few layers) so a debug build bakes it
//! quickly, with hairs twice the default width so they stay about a texel wide at 64².

use pelt::hair::HairParams;
use pelt::volume::{HairVolume, VolumeParams, bake_volume};

/// The dense, doubly wide hair of [`small_volume`].
pub fn small_hair() -> HairParams {
    let defaults = HairParams::default();
    let mut hair = HairParams {
        density: 3000,
        ..defaults.clone()
    };
    hair.undercoat.width = defaults.undercoat.width.map(|w| w * 2.0);
    hair.overcoat.width = defaults.overcoat.width.map(|w| w * 2.0);
    hair
}

/// A 64² volume of `layers` layers (a 128 × 32 fin texture, untrimmed) of [`small_hair`].
pub fn small_volume(layers: usize) -> HairVolume {
    let hair = small_hair();
    let params = VolumeParams {
        layers,
        resolution: 64,
        fin_size: [128, 32],
        trim: false,
        ..VolumeParams::default()
    };
    bake_volume(&hair, &params, None).expect("the small test volume bakes")
}
