//! Host memory a scene's texture uploads take at their peak, checked against the memory budget
//! (`pelt_core::memory`) before anything is built: the textures are made on the CPU first (the LOD
//! levels, their mip chains, premultiplied copies), then copied into the queue's staging memory,
//! and on a CPU adapter the device's own textures are host memory too.

use super::Renderer;
use super::lod::Levels;
use pelt_core::volume::HairVolume;

/// A full mip chain's size over its base level's (1 + 1/4 + 1/16 + …).
const MIP_CHAIN: f64 = 4.0 / 3.0;

/// [`super::FurScene::new`]'s texture upload of `volume` to `renderer`: every LOD level's RGBA8
/// layers with their mips held built, then premultiplied, staged and on the device in the
/// renderer's color storage (4 bytes a texel, 8 on a CPU adapter), the LOD levels built here when
/// the bake has none, the tangents (cloned, staged, on the device), the fin texture's chain (as
/// the shells') and the opacity and color luminance the scene keeps (a byte each per level-0
/// texel).
pub fn scene_upload_peak_bytes(volume: &HairVolume, renderer: &Renderer) -> f64 {
    let texels = (volume.resolution * volume.resolution) as f64;
    let layers = volume.layers as f64;
    let all_levels = f64::from(Levels::new(volume.layers as u32).total());
    // Built (RGBA8), then premultiplied, staged and on the device as stored.
    let chain_texel = 4.0 + 3.0 * renderer.color_store().texel_bytes() as f64;
    let shells = chain_texel * MIP_CHAIN * all_levels * texels;
    let built_lod = if volume.lod.is_empty() {
        4.0 * (all_levels - layers) * texels
    } else {
        0.0
    };
    let tangents = 3.0 * 4.0 * layers * texels;
    let fin = chain_texel * MIP_CHAIN * (volume.fin_size[0] * volume.fin_size[1]) as f64;
    shells + built_lod + tangents + fin + 2.0 * layers * texels + OVER_MIPS * layers * texels
}

/// Bytes per level-0 texel of a layer that [`super::over_mips`] holds while it rebuilds a stack's
/// mips (the largest stack is level 0's): the opacity and transmittance in f32, the linear
/// premultiplied values and their coarser levels (a third as many) in four f32.
const OVER_MIPS: f64 = 4.0 + 4.0 + 16.0 * MIP_CHAIN;

/// [`super::FurScene::set_transfer`] of an order-`order` transfer over `layers` layers of
/// `resolution²` texels: the premultiplied f16 coefficients of every LOD level, their mip
/// chains, staged and on the device, the opacity carried through the levels in f32, and what
/// rebuilding a stack's mips holds.
pub fn transfer_upload_peak_bytes(layers: usize, resolution: usize, order: usize) -> f64 {
    let texels = (resolution * resolution) as f64;
    let stride = f64::from(Levels::new(layers as u32).total());
    let textures = (order * order).div_ceil(4) as f64;
    let coefficients = 8.0 * textures * stride * texels;
    coefficients * (1.0 + 3.0 * MIP_CHAIN) + 2.0 * 4.0 * stride * texels + OVER_MIPS * layers as f64 * texels
}
