//! A CPU adapter's frame for a caller's texture ([`super::Renderer::render_to_texture`], the
//! window): drawn into the single-float offscreen target (`Target::Linear32`, where lavapipe
//! blends exactly), then copied into the caller's texture once by one full-frame triangle
//! (`full_frame.rs`, `resolve.wgsl`), which the texture's format encodes. Blended in an 8-bit target instead,
//! lavapipe re-encodes every shell's blend and the frame came out 5–7% bright.

use super::full_frame::{full_frame_pipeline, texel_entry};
use super::pass::Target;

/// The copying pipeline into one target format.
pub(super) struct ResolvePass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl ResolvePass {
    pub fn new(device: &wgpu::Device, target: Target) -> ResolvePass {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("resolve"),
            entries: &[texel_entry(0)],
        });
        let pipeline = full_frame_pipeline(
            device,
            "resolve",
            include_str!("resolve.wgsl"),
            &layout,
            None,
            wgpu::ColorTargetState {
                format: target.format(),
                // Every pixel replaced: the frame already holds the background.
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            },
        );
        ResolvePass { layout, pipeline }
    }

    /// Records the copy of `frame` (a single-float view of the frame's size) into `target`.
    pub fn draw(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::TextureView,
        target: &wgpu::TextureView,
    ) {
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("resolve"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(frame),
            }],
        });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("resolve"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}
