//! The smoke pass: clears an offscreen target and draws one flat-colored triangle, proving that
//! the device compiles WGSL, rasterizes and reads back.

use super::Renderer;
use super::pass::texture_2d;
use super::readback::read_rgba8;
use pelt_core::error::Result;

/// RGBA8 value the smoke triangle writes.
pub const SMOKE_COLOR: [u8; 4] = [204, 102, 51, 255];

impl Renderer {
    /// Renders the smoke frame: a black background with a triangle of [`SMOKE_COLOR`] whose
    /// corners are at NDC (-0.8, -0.8), (0.8, -0.8), (0, 0.8). Returns `height × width` RGBA8 rows.
    ///
    /// # Errors
    /// [`pelt_core::PeltError::Render`] when the GPU work or the readback fails.
    pub fn render_smoke(&self, width: u32, height: u32) -> Result<Vec<u8>> {
        let device = &self.device;
        let format = wgpu::TextureFormat::Rgba8Unorm;
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let target = texture_2d(device, "smoke target", (width, height), format, usage);
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("smoke.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("smoke.wgsl").into()),
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("smoke"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(format.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let view = target.create_view(&wgpu::TextureViewDescriptor::default());
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("smoke") });
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("smoke"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&pipeline);
            pass.draw(0..3, 0..1);
        }
        self.queue.submit([encoder.finish()]);
        read_rgba8(device, &self.queue, &target)
    }
}
