//! What the three fur passes share: target formats, the bind group layout (frame uniforms, shell,
//! tangent and fin textures, samplers), vertex layouts and the pipeline recipe. Each pass file
//! (`skin.rs`, `fins.rs`, `shells.rs`) states only what is its own: shader, culling, depth
//! writes and blending (Lengyel et al. 2001, §2.3).

use std::num::NonZeroU64;

use super::frame_uniforms::FrameUniforms;
use super::{fins, shells, skin};
use crate::error::{PeltError, Result};

/// Color target: 8-bit sRGB, so blending happens in linear light.
pub(super) const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Depth target.
pub(super) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Bytes of one vertex of buffer 0 (both [`super::surface_mesh::SurfaceVertex`] and
/// [`super::fin_mesh::FinVertex`] are five `vec3`s and a `vec2`).
const GEOMETRY_STRIDE: u64 = 68;

/// Attributes of buffer 0 of the skin and shell passes (`SurfaceIn` in `surface.wgsl`).
const SURFACE_ATTRIBUTES: [wgpu::VertexAttribute; 6] = wgpu::vertex_attr_array![
    0 => Float32x3, 1 => Float32x3, 2 => Float32x3, 3 => Float32x3, 4 => Float32x2, 5 => Float32x3
];
/// Attributes of buffer 0 of the fin pass (`FinIn` in `fins.wgsl`).
const FIN_ATTRIBUTES: [wgpu::VertexAttribute; 6] = wgpu::vertex_attr_array![
    0 => Float32x3, 1 => Float32x3, 2 => Float32x3, 3 => Float32x3, 4 => Float32x3, 5 => Float32x2
];
const COLOR_ATTRIBUTE: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![6 => Float32x4];
const LENGTH_ATTRIBUTE: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![7 => Float32];

/// Buffer layouts: 0 geometry, 1 color (`vec4`), 2 length (`f32`).
pub(super) fn vertex_layouts(fins: bool) -> [Option<wgpu::VertexBufferLayout<'static>>; 3] {
    let per_vertex = |array_stride, attributes| {
        Some(wgpu::VertexBufferLayout {
            array_stride,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes,
        })
    };
    [
        per_vertex(
            GEOMETRY_STRIDE,
            if fins {
                &FIN_ATTRIBUTES
            } else {
                &SURFACE_ATTRIBUTES
            },
        ),
        per_vertex(16, &COLOR_ATTRIBUTE),
        per_vertex(4, &LENGTH_ATTRIBUTE),
    ]
}

/// How a pass draws.
pub(super) struct PassState<'a> {
    pub label: &'a str,
    pub source: &'a str,
    pub fins: bool,
    pub cull_mode: Option<wgpu::Face>,
    pub depth_write: bool,
    pub blend: Option<wgpu::BlendState>,
}

/// The pipelines of the fur passes and what they bind; built once per [`super::Renderer`].
pub(super) struct FurPipelines {
    pub bind_group_layout: wgpu::BindGroupLayout,
    pub skin: wgpu::RenderPipeline,
    pub fins: wgpu::RenderPipeline,
    pub shells: wgpu::RenderPipeline,
    /// Repeating trilinear sampler: the shell tile wraps across each patch.
    pub tile_sampler: wgpu::Sampler,
    /// Repeats along the fin (u), clamps across (v: skin to top of the fur).
    pub fin_sampler: wgpu::Sampler,
}

fn texture_entry(binding: u32, view_dimension: wgpu::TextureViewDimension) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension,
            multisampled: false,
        },
        count: None,
    }
}

fn sampler_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
        count: None,
    }
}

fn sampler(device: &wgpu::Device, label: &str, v: wgpu::AddressMode) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some(label),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: v,
        address_mode_w: wgpu::AddressMode::ClampToEdge,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        ..Default::default()
    })
}

impl FurPipelines {
    /// Compiles the shaders and builds the pipelines.
    ///
    /// # Errors
    /// [`PeltError::Render`] when the device rejects a shader or pipeline (a bug, or a device
    /// missing a downlevel capability).
    pub fn new(device: &wgpu::Device) -> Result<Self> {
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("fur"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: NonZeroU64::new(size_of::<FrameUniforms>() as u64),
                    },
                    count: None,
                },
                texture_entry(1, wgpu::TextureViewDimension::D2Array),
                texture_entry(2, wgpu::TextureViewDimension::D2Array),
                texture_entry(3, wgpu::TextureViewDimension::D2),
                sampler_entry(4),
                sampler_entry(5),
            ],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("fur"),
            bind_group_layouts: &[Some(&bind_group_layout)],
            immediate_size: 0,
        });
        let pipelines = FurPipelines {
            skin: pipeline(device, &layout, &skin::STATE),
            fins: pipeline(device, &layout, &fins::STATE),
            shells: pipeline(device, &layout, &shells::STATE),
            bind_group_layout,
            tile_sampler: sampler(device, "tile", wgpu::AddressMode::Repeat),
            fin_sampler: sampler(device, "fin", wgpu::AddressMode::ClampToEdge),
        };
        match pollster::block_on(scope.pop()) {
            None => Ok(pipelines),
            Some(e) => Err(PeltError::Render(format!(
                "building the fur pipelines failed: {e}"
            ))),
        }
    }
}

/// One pass's pipeline from its state.
fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    state: &PassState<'_>,
) -> wgpu::RenderPipeline {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(state.label),
        source: wgpu::ShaderSource::Wgsl(state.source.into()),
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(state.label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &vertex_layouts(state.fins),
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: state.cull_mode,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(state.depth_write),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: COLOR_FORMAT,
                blend: state.blend,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}
