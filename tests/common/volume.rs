//! The hair volume the render tests bake: small (64², a few layers) so a debug build bakes it
//! quickly, with hairs twice the default width so they stay about a texel wide at 64².

use pelt::hair::HairParams;
use pelt::prt::pack::{PackedF16, pack_f16};
use pelt::prt::volume_input::VolumeInput;
use pelt::prt::{TransferParams, bake_transfer};
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

/// Rewrites every texel of `volume`'s layer 0 (the skin) and of its mips with `paint`.
pub fn paint_skin(volume: &mut HairVolume, paint: impl Fn(&mut [u8])) {
    let plane = volume.resolution * volume.resolution;
    volume.shells[..4 * plane].chunks_exact_mut(4).for_each(&paint);
    for (k, mip) in volume.mips.iter_mut().enumerate() {
        let side = (volume.resolution >> (k + 1)).max(1);
        mip[..4 * side * side].chunks_exact_mut(4).for_each(&paint);
    }
}

/// A small order-3 PRT transfer of `volume` (64 directions), its fur `depth_in_tiles` tiles deep,
/// packed as a scene takes it.
pub fn small_transfer(volume: &HairVolume, depth_in_tiles: f64) -> PackedF16 {
    let transfer = bake_transfer(
        &VolumeInput::new(volume, depth_in_tiles).transfer_volume(volume),
        &TransferParams {
            order: 3,
            directions: 64,
            ..TransferParams::default()
        },
        None,
    )
    .expect("the small test transfer bakes");
    pack_f16(&transfer).expect("the small test transfer packs")
}
