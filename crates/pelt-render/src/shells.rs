//! Pass (c), the shells (Lengyel et al. 2001, §2.3). `Instanced`: one instanced draw of the mesh,
//! instance `i` being shell `i + 1`, so the GPU composites them inner to outer; `Marched` and
//! `VirtualPlanes` draw one hull instead (`marched.rs`, `planes.rs`). the offset along
//! `length × (normal + comb shear)` is computed in the vertex shader (§2.4). Depth is tested and
//! written behind an alpha test, so empty texels write no depth.

use std::ops::Range;

use super::pass::{Model, PassPipelines, PassState, VertexInput};
use super::scene::FurScene;
use super::settings::ShellMethod;
use pelt_core::scene::scene_levels::MeshLevel;

const KAJIYA_KAY: &str = concat!(
    include_str!("common.wgsl"),
    include_str!("lighting.wgsl"),
    include_str!("surface.wgsl"),
    include_str!("surface_kk.wgsl"),
    include_str!("shells.wgsl")
);
const PRT: &str = concat!(
    include_str!("common.wgsl"),
    include_str!("prt.wgsl"),
    include_str!("surface.wgsl"),
    include_str!("surface_prt.wgsl"),
    include_str!("shells.wgsl")
);

/// Back faces culled, depth written, premultiplied "over".
pub(super) fn state(model: Model) -> PassState<'static> {
    PassState {
        label: "shells",
        source: match model {
            Model::KajiyaKay => KAJIYA_KAY,
            Model::Prt => PRT,
        },
        input: match model {
            Model::KajiyaKay => VertexInput::Surface,
            Model::Prt => VertexInput::Pulled,
        },
        topology: wgpu::PrimitiveTopology::TriangleList,
        cull_mode: Some(wgpu::Face::Back),
        depth_write: true,
        blend: Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
    }
}

/// Draws shell instances `shells` (0 the innermost) of geometric level `level`: instanced, a
/// copy of the mesh per shell, or marched ([`super::marched`]) or traced through the virtual
/// planes ([`super::planes`]), their hull once with the range that starts at 0; `method` is resolved ([`ShellMethod::resolve`]), an `Auto` left over draws
/// instanced.
pub(super) fn draw(
    pass: &mut wgpu::RenderPass<'_>,
    pipelines: &PassPipelines,
    scene: &FurScene,
    level: &MeshLevel,
    model: Model,
    shells: Range<u32>,
    method: ShellMethod,
) {
    if shells.is_empty() {
        return;
    }
    let (pipeline, instances) = match method {
        ShellMethod::Instanced | ShellMethod::Auto => (&pipelines.shells, shells),
        ShellMethod::Marched if shells.start == 0 => (&pipelines.marched, 0..1),
        ShellMethod::VirtualPlanes if shells.start == 0 => (&pipelines.planes, 0..1),
        ShellMethod::Marched | ShellMethod::VirtualPlanes => return,
    };
    pass.set_pipeline(pipeline);
    scene.surface.draw(pass, model, level.indices.clone(), instances);
}
