//! Pass (a), the skin (Lengyel et al. 2001, §2.3): the opaque mesh textured with layer 0 of the
//! shell texture times the vertex color, filling the depth buffer that fins and shells test.

use super::pipelines::{FurPipelines, PassState};
use super::scene::FurScene;

/// Back faces culled, depth written, no blending.
pub(super) const STATE: PassState<'static> = PassState {
    label: "skin",
    source: concat!(
        include_str!("common.wgsl"),
        include_str!("lighting.wgsl"),
        include_str!("surface.wgsl"),
        include_str!("skin.wgsl")
    ),
    fins: false,
    cull_mode: Some(wgpu::Face::Back),
    depth_write: true,
    blend: None,
};

/// Draws the skin.
pub(super) fn draw(pass: &mut wgpu::RenderPass<'_>, pipelines: &FurPipelines, scene: &FurScene) {
    pass.set_pipeline(&pipelines.skin);
    scene.surface.bind(pass);
    pass.draw_indexed(0..scene.surface.index_count, 0, 0..1);
}
