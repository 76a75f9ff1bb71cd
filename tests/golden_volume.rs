//! Golden images of the default hair volume: the shell atlas and the fin texture.
//!
//! The bake is deterministic, so these images only change when the hair model or the sampling
//! changes on purpose; then regenerate them with `PELT_UPDATE_GOLDEN=1 cargo test --test
//! golden_volume`, look at them, and commit them with the change. A few units of difference on a
//! handful of texels are tolerated ([`Tolerance::BAKE`]), for floating-point library differences
//! between platforms.

mod common;

use common::golden::{Tolerance, check};
use pelt::hair::HairParams;
use pelt::texture::{AtlasLayout, pack_atlas};
use pelt::volume::{VolumeParams, bake_volume};

#[test]
fn default_shell_atlas_and_fin_match_the_golden_images() {
    let volume = bake_volume(&HairParams::default(), &VolumeParams::default(), None).unwrap();
    let layout = AtlasLayout::new(volume.layers, volume.resolution).unwrap();
    let atlas = pack_atlas(&layout, 4, &volume.shells).unwrap();
    check(
        "shell_atlas.png",
        layout.width,
        layout.height,
        atlas.view().data(),
        Tolerance::BAKE,
    );
    let [fw, fh] = volume.fin_size;
    check("fin.png", fw, fh, &volume.fin, Tolerance::BAKE);
}
