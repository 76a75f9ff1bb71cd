//! Pass (c), the shells (Lengyel et al. 2001, §2.3). `Instanced`: one instanced draw of the mesh,
//! instance `i` being shell `i + 1`, so the GPU composites them inner to outer; `Marched` and
//! `VirtualPlanes` draw one hull instead (`marched.rs`, `planes.rs`). the offset along
//! `length × (normal + comb shear)` is computed in the vertex shader (§2.4). Depth is tested and
//! written behind an alpha test, so empty texels write no depth.

use std::ops::Range;

use super::pass::{Model, PassState, VertexInput, build_pipeline};
use super::scene::FurScene;
use super::settings::ShellMethod;
use super::shaders::PassShader;
use super::{marched, planes};
use pelt_core::error::Result;
use pelt_core::scene::scene_levels::MeshLevel;

/// The pass's shader, one source for both lighting models.
pub(super) static SHADER: PassShader = PassShader::new("shells.wgsl", include_str!("shells.wgsl"));

/// Back faces culled, depth written, premultiplied "over" (the marched and virtual-plane hulls
/// too, with their own shaders).
fn state(model: Model) -> Result<PassState<'static>> {
    Ok(PassState {
        label: "shells",
        module: SHADER.module(model)?,
        input: match model {
            Model::KajiyaKay => VertexInput::Surface,
            Model::Prt => VertexInput::Pulled,
        },
        topology: wgpu::PrimitiveTopology::TriangleList,
        cull_mode: Some(wgpu::Face::Back),
        depth_write: true,
        blend: Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
    })
}

/// The shells' pipelines for one lighting model and target: instanced, and the one-hull methods
/// (marched, virtual planes), which share the instanced state.
pub(super) struct ShellsPass {
    instanced: wgpu::RenderPipeline,
    marched: wgpu::RenderPipeline,
    planes: wgpu::RenderPipeline,
}

impl ShellsPass {
    pub(super) fn new(
        device: &wgpu::Device,
        layout: &wgpu::PipelineLayout,
        model: Model,
        format: wgpu::TextureFormat,
    ) -> Result<Self> {
        let instanced = state(model)?;
        let hull = |label, shader: &'static PassShader| -> Result<PassState<'static>> {
            Ok(PassState {
                label,
                module: shader.module(model)?,
                ..state(model)?
            })
        };
        Ok(ShellsPass {
            instanced: build_pipeline(device, layout, &instanced, format),
            marched: build_pipeline(device, layout, &hull("marched shells", &marched::SHADER)?, format),
            planes: build_pipeline(device, layout, &hull("virtual planes", &planes::SHADER)?, format),
        })
    }

    /// Draws shell instances `shells` (0 the innermost) of geometric level `level`: instanced, a
    /// copy of the mesh per shell, or marched ([`super::marched`]) or traced through the virtual
    /// planes ([`super::planes`]), their hull once with the range that starts at 0; `method` is
    /// resolved ([`ShellMethod::resolve`]), an `Auto` left over draws instanced.
    pub(super) fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        scene: &FurScene,
        level: &MeshLevel,
        model: Model,
        (shells, method): (Range<u32>, ShellMethod),
    ) {
        if shells.is_empty() {
            return;
        }
        let (pipeline, instances) = match method {
            ShellMethod::Instanced | ShellMethod::Auto => (&self.instanced, shells),
            ShellMethod::Marched if shells.start == 0 => (&self.marched, 0..1),
            ShellMethod::VirtualPlanes if shells.start == 0 => (&self.planes, 0..1),
            ShellMethod::Marched | ShellMethod::VirtualPlanes => return,
        };
        pass.set_pipeline(pipeline);
        scene.surface.draw(pass, model, level.indices.clone(), instances);
    }
}
