//! Pass (c), the shells (Lengyel et al. 2001, §2.3): one instanced draw of the mesh, instance `i`
//! being shell `i + 1`, so the GPU composites them inner to outer; the offset along
//! `length × (normal + comb shear)` is computed in the vertex shader (§2.4). Depth is tested and
//! written behind an alpha test, so empty texels write no depth.

use super::pipelines::{FurPipelines, PassState};
use super::scene::FurScene;

/// Back faces culled, depth written, premultiplied "over".
pub(super) const STATE: PassState<'static> = PassState {
    label: "shells",
    source: concat!(
        include_str!("common.wgsl"),
        include_str!("lighting.wgsl"),
        include_str!("surface.wgsl"),
        include_str!("shells.wgsl")
    ),
    fins: false,
    cull_mode: Some(wgpu::Face::Back),
    depth_write: true,
    blend: Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
};

/// Draws `count` shells.
pub(super) fn draw(pass: &mut wgpu::RenderPass<'_>, pipelines: &FurPipelines, scene: &FurScene, count: u32) {
    if count == 0 {
        return;
    }
    pass.set_pipeline(&pipelines.shells);
    scene.surface.bind(pass);
    pass.draw_indexed(0..scene.surface.index_count, 0, 0..count);
}
