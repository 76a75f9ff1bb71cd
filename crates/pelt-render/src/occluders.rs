//! The fur composited into another renderer's picture of the same view (Blender's viewport): that
//! renderer's depth buffer starts the frame's depth, pushed back along each view ray by a bias,
//! so the fur behind another object fails the skin's and shells' depth test while the fur's own
//! surfaces in that picture (its skin; Blender's shells drawn opaque), within the bias of the
//! hair, do not hide it. One full-frame triangle (`full_frame.rs`) writes the depth
//! (`occluders.wgsl`).

use std::num::NonZeroU64;

use super::camera::CameraFrame;
use super::full_frame::{full_frame_pipeline, texel_entry};
use super::pass::DEPTH_FORMAT;
use super::pass::texture_2d;
use pelt_core::error::{PeltError, Result};

/// Another renderer's depth of the frame's view, for [`super::Renderer::render_over`].
#[derive(Debug, Clone, PartialEq)]
pub struct Occluders {
    /// Window depth per pixel in `[0, 1]` after the same projection (OpenGL's depth buffer, as
    /// Blender's `read_depth` gives it; 1 where nothing is), rows top first, the camera's
    /// `width × height`.
    pub depth: Vec<f32>,
    /// How far behind an occluding surface the fur is still drawn, object units (at least the
    /// fur's height, so the fur's own skin and shells in that picture do not hide it).
    pub bias: f32,
}

/// The uniforms of `occluders.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct OccluderUniforms {
    view_proj: [f32; 16],
    inverse_view_proj: [f32; 16],
    eye: [f32; 4],
    bias_size: [f32; 4],
}

impl Occluders {
    /// Checks the depth against the frame's size and the values' ranges.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `occluders.depth` or `occluders.bias`.
    pub fn check(&self, width: u32, height: u32) -> Result<()> {
        let pixels = width as usize * height as usize;
        if self.depth.len() != pixels {
            return Err(PeltError::parameter(
                "occluders.depth",
                format!(
                    "must hold {width} × {height} = {pixels} values (the frame's), got {}",
                    self.depth.len()
                ),
            ));
        }
        if let Some(i) = self.depth.iter().position(|d| !(0.0..=1.0).contains(d)) {
            return Err(PeltError::parameter(
                "occluders.depth",
                format!(
                    "values must be in [0, 1], got {} at row {}, column {}",
                    self.depth[i],
                    i / width as usize,
                    i % width as usize
                ),
            ));
        }
        if !(self.bias.is_finite() && self.bias >= 0.0) {
            return Err(PeltError::parameter(
                "occluders.bias",
                format!("must be finite and at least 0, got {}", self.bias),
            ));
        }
        Ok(())
    }
}

/// The depth-writing pipeline for one color format (the fur pass's: the triangle writes no color).
pub(super) struct OccluderPass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl OccluderPass {
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> OccluderPass {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("occluders"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: NonZeroU64::new(size_of::<OccluderUniforms>() as u64),
                    },
                    count: None,
                },
                texel_entry(1),
            ],
        });
        let pipeline = full_frame_pipeline(
            device,
            "occluders",
            include_str!("occluders.wgsl"),
            &layout,
            Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            }),
            wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::empty(),
            },
        );
        OccluderPass { layout, pipeline }
    }

    /// Uploads `occluders` (checked) for a frame of `camera` and returns the bind group to draw
    /// with.
    pub fn bind(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        camera: &CameraFrame,
        size: (u32, u32),
        occluders: &Occluders,
    ) -> wgpu::BindGroup {
        let texture = texture_2d(
            device,
            "occluder depth",
            size,
            wgpu::TextureFormat::R32Float,
            wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        );
        queue.write_texture(
            texture.as_image_copy(),
            bytemuck::cast_slice(&occluders.depth),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * size.0),
                rows_per_image: Some(size.1),
            },
            texture.size(),
        );
        let uniforms = OccluderUniforms {
            view_proj: camera.view_proj.to_cols_array(),
            inverse_view_proj: camera.inverse_view_proj.to_cols_array(),
            eye: camera.eye.to_array(),
            bias_size: [occluders.bias, size.0 as f32, size.1 as f32, 0.0],
        };
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("occluders"),
            size: size_of::<OccluderUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        queue.write_buffer(&buffer, 0, bytemuck::bytes_of(&uniforms));
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("occluders"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(
                        &texture.create_view(&wgpu::TextureViewDescriptor::default()),
                    ),
                },
            ],
        })
    }

    /// Writes the starting depth: first in the fur pass, before the skin.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, group: &wgpu::BindGroup) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.draw(0..3, 0..1);
    }
}
