//! Pass (a), the skin (Lengyel et al. 2001, §2.3): the opaque mesh textured with layer 0 of the
//! shell texture times the vertex color, filling the depth buffer that fins and shells test.

use super::pass::{Model, PassState, VertexInput, build_pipeline};
use super::scene::FurScene;
use super::shaders::PassShader;
use pelt_core::error::Result;
use pelt_core::scene::scene_levels::MeshLevel;

/// The pass's shader, one source for both lighting models.
pub(super) static SHADER: PassShader = PassShader::new("skin.wgsl", include_str!("skin.wgsl"));

/// Back faces culled, depth written, no blending.
fn state(model: Model) -> Result<PassState<'static>> {
    Ok(PassState {
        label: "skin",
        module: SHADER.module(model)?,
        input: match model {
            Model::KajiyaKay => VertexInput::Surface,
            Model::Prt => VertexInput::Pulled,
        },
        topology: wgpu::PrimitiveTopology::TriangleList,
        cull_mode: Some(wgpu::Face::Back),
        depth_write: true,
        blend: None,
    })
}

/// The skin's pipeline for one lighting model and target.
pub(super) struct SkinPass(wgpu::RenderPipeline);

impl SkinPass {
    pub(super) fn new(
        device: &wgpu::Device,
        layout: &wgpu::PipelineLayout,
        model: Model,
        format: wgpu::TextureFormat,
    ) -> Result<Self> {
        Ok(SkinPass(build_pipeline(device, layout, &state(model)?, format)))
    }

    /// Draws the skin of geometric level `level` (bind group 1 is set for PRT).
    pub(super) fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        scene: &FurScene,
        level: &MeshLevel,
        model: Model,
    ) {
        pass.set_pipeline(&self.0);
        scene.surface.draw(pass, model, level.indices.clone(), 0..1);
    }
}
