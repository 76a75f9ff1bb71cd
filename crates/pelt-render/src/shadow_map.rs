//! The body's shadow on its own fur: a depth map of the skin seen from the directional light,
//! drawn before the fur whenever the light, the pose or the mesh level drawn changed since it was
//! last drawn (a camera moving about a still object under still lights, the viewport's usual
//! case, redraws nothing: the light is in object space). Every Kajiya–Kay pass
//! reads it at the point it lights (`body_shadow.wgsl`); under PRT the rotation pass reads it per
//! vertex, over the fur's height, and dims the directional light's share of the rotated lighting
//! by it (`prt_rotate.wgsl`), the environment's untouched. The fur's own volume shadows itself
//! (Banks darkening and the wrapped N·L, or the transfer); what neither can cast is one part of
//! the body on another (the torus's near side on its inner wall under a side light), which the
//! reference renderer's rays do. The skin alone casts: the hair on it is partly clear, and its
//! own shadow is already the fur's model's.

use std::num::NonZeroU64;

use glam::dcamera::rh::proj::directx::orthographic;
use glam::dcamera::rh::view::look_at_mat4;
use glam::{DVec3, Mat4};

use super::lod::Extent;
use super::pass::{SURFACE_STRIDE, texture_2d};

/// Texels along each side of the map: fur shadows are soft, and on the canonical scenes the
/// fur's depth spans 30 texels or more. A CPU adapter pays for every texel each time the map
/// is drawn (1024² took 4–8 ms a frame on lavapipe).
pub(super) const SHADOW_SIZE: u32 = 512;
/// Depth of the map, compared in the shaders with a linear comparison sampler (2 × 2 PCF).
pub(super) const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// How far a receiving point is lifted along its normal before it is looked up, in texels of
/// the map: against the skin's own depth at a slant (shadow acne).
const NORMAL_OFFSET_TEXELS: f64 = 1.5;
/// How much nearer the light a receiving point is taken, in texels of the map.
const DEPTH_BIAS_TEXELS: f64 = 1.0;

/// The layout entries of a map and its comparison sampler at bindings `first` and `first + 1`,
/// seen by `visibility`.
pub(super) fn layout_entries(first: u32, visibility: wgpu::ShaderStages) -> [wgpu::BindGroupLayoutEntry; 2] {
    [
        wgpu::BindGroupLayoutEntry {
            binding: first,
            visibility,
            ty: wgpu::BindingType::Texture {
                sample_type: wgpu::TextureSampleType::Depth,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        },
        wgpu::BindGroupLayoutEntry {
            binding: first + 1,
            visibility,
            ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
            count: None,
        },
    ]
}

/// What a map was drawn for: the light's view and the skin triangles drawn.
type ShadowKey = ([f32; 16], std::ops::Range<u32>);

/// A scene's map, the uniform of its pass and what it holds now.
pub(super) struct ShadowMap {
    pub view: wgpu::TextureView,
    uniforms: wgpu::Buffer,
    drawn: std::sync::Mutex<Option<ShadowKey>>,
}

impl ShadowMap {
    pub fn new(device: &wgpu::Device) -> ShadowMap {
        let texture = texture_2d(
            device,
            "body shadow",
            (SHADOW_SIZE, SHADOW_SIZE),
            SHADOW_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("body shadow"),
            size: size_of::<[f32; 16]>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        ShadowMap {
            view: texture.create_view(&wgpu::TextureViewDescriptor::default()),
            uniforms,
            drawn: std::sync::Mutex::new(None),
        }
    }

    /// Whether the map must be drawn for `frame` with the skin triangles `indices`.
    pub fn stale(&self, frame: &ShadowFrame, indices: &std::ops::Range<u32>) -> bool {
        let drawn = self
            .drawn
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        drawn.as_ref() != Some(&(frame.light_view_proj.to_cols_array(), indices.clone()))
    }

    /// Records that the map holds `frame`'s view of the triangles `indices` (once the frame
    /// that drew it was submitted), or with `None` that it holds nothing usable (the skin moved).
    pub fn set_drawn(&self, drawn: Option<(&ShadowFrame, std::ops::Range<u32>)>) {
        *self
            .drawn
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner) =
            drawn.map(|(frame, indices)| (frame.light_view_proj.to_cols_array(), indices));
    }
}

/// Where a frame looks its shadow up: the light's orthographic view of the furred mesh and the
/// biases (`light_view_proj` and `shadow` of `Frame` in `common.wgsl`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct ShadowFrame {
    pub light_view_proj: Mat4,
    /// x: 1 when the map is drawn, y: the normal offset (object units), z: the depth bias
    /// (map depth units).
    pub params: [f32; 4],
}

impl ShadowFrame {
    /// No map: every point lit.
    pub const NONE: ShadowFrame = ShadowFrame {
        light_view_proj: Mat4::IDENTITY,
        params: [0.0; 4],
    };

    /// The light's view of the sphere that holds the skin and `fur` object units of hair over
    /// it, looking along `-direction` (unit, toward the light).
    pub fn new(direction: [f32; 3], extent: &Extent, fur: f64) -> ShadowFrame {
        let toward = DVec3::from(direction.map(f64::from)).normalize_or(DVec3::Z);
        // Twice the fur's height: the hair may stand over the bounding sphere's widest point.
        let radius = (extent.radius + 2.0 * fur).max(1e-6);
        let up = if toward.z.abs() < 0.9 { DVec3::Z } else { DVec3::X };
        let eye = extent.center + toward * (2.0 * radius);
        let view = look_at_mat4(eye, extent.center, up);
        // wgpu's clip depth runs 0 (near) to 1 (far), y up: the sphere spans 1 to 3 radii from
        // the eye.
        let projection = orthographic(-radius, radius, -radius, radius, radius, 3.0 * radius);
        let texel = 2.0 * radius / f64::from(SHADOW_SIZE);
        ShadowFrame {
            light_view_proj: (projection * view).as_mat4(),
            params: [
                1.0,
                (NORMAL_OFFSET_TEXELS * texel) as f32,
                (DEPTH_BIAS_TEXELS * texel / (2.0 * radius)) as f32,
                0.0,
            ],
        }
    }
}

/// The depth-only pipeline that draws the skin into a [`ShadowMap`].
pub(super) struct ShadowPass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl ShadowPass {
    pub fn new(device: &wgpu::Device) -> ShadowPass {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("body shadow"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: NonZeroU64::new(size_of::<[f32; 16]>() as u64),
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("body shadow"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("body shadow"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shadow_map.wgsl").into()),
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("body shadow"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    // The skin's vertex buffer, its position first.
                    array_stride: SURFACE_STRIDE,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3],
                })],
            },
            // Both faces: an open mesh (the flat patch) casts from either side.
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: SHADOW_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
        ShadowPass { layout, pipeline }
    }

    /// Draws the skin triangles `indices` of `skin` (geometry and index buffers) into `map`
    /// as the light of `frame` sees them.
    pub fn draw(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        map: &ShadowMap,
        frame: &ShadowFrame,
        skin: (&wgpu::Buffer, &wgpu::Buffer, std::ops::Range<u32>),
    ) {
        queue.write_buffer(
            &map.uniforms,
            0,
            bytemuck::cast_slice(&frame.light_view_proj.to_cols_array()),
        );
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("body shadow"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: map.uniforms.as_entire_binding(),
            }],
        });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("body shadow"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &map.view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.set_vertex_buffer(0, skin.0.slice(..));
        pass.set_index_buffer(skin.1.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(skin.2, 0, 0..1);
    }
}
