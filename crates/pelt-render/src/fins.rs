//! Pass (b), the fins (Lengyel et al. 2001, §2.3): the quads of [`pelt_core::scene::fin_mesh`] that
//! [`pelt_core::scene::fin_cull`] collects, faded toward the silhouette in the vertex shader, blended
//! premultiplied, depth tested but not written (the shells drawn next must still land on the
//! skin behind a fin).

use super::pass::{Model, PassState, VertexInput, build_pipeline};
use super::scene::FurScene;
use super::shaders::PassShader;
use pelt_core::error::Result;

/// The pass's shader, one source for both lighting models.
pub(super) static SHADER: PassShader = PassShader::new("fins.wgsl", include_str!("fins.wgsl"));

/// Both sides drawn (a fin is seen from either side), depth not written, premultiplied "over".
fn state(model: Model) -> Result<PassState<'static>> {
    Ok(PassState {
        label: "fins",
        module: SHADER.module(model)?,
        input: VertexInput::Fins,
        topology: wgpu::PrimitiveTopology::TriangleList,
        cull_mode: None,
        depth_write: false,
        blend: Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
    })
}

/// The fins' pipeline for one lighting model and target.
pub(super) struct FinsPass(wgpu::RenderPipeline);

impl FinsPass {
    pub(super) fn new(
        device: &wgpu::Device,
        layout: &wgpu::PipelineLayout,
        model: Model,
        format: wgpu::TextureFormat,
    ) -> Result<Self> {
        Ok(FinsPass(build_pipeline(device, layout, &state(model)?, format)))
    }

    /// Draws the first `indices` of the fin index buffer, where the frame has collected the fins
    /// the fade leaves visible (`fin_cull`); the vertex shader drops any faded out after all.
    pub(super) fn draw(&self, pass: &mut wgpu::RenderPass<'_>, scene: &FurScene, indices: u32) {
        if indices == 0 {
            return;
        }
        pass.set_pipeline(&self.0);
        scene.fins.bind(pass);
        pass.draw_indexed(0..indices, 0, 0..1);
    }
}
