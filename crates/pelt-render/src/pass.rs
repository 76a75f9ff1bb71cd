//! What every fur pass shares (Lengyel et al. 2001, §2.3): the lighting [`Model`], the color
//! [`Target`], the depth format, where vertices come from ([`VertexInput`] and its buffer
//! layouts), a pass's [`PassState`] and the recipe that turns it into a pipeline
//! ([`build_pipeline`]). Each pass file (`skin.rs`, `fins.rs`, `shells.rs` with the hulls of
//! `marched.rs` and `planes.rs`, `strands.rs`) owns its shader (composed by `shaders.rs`), its
//! state, its pipelines and its draw call.

/// Depth target.
pub(super) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Bytes of one vertex of buffer 0 of the skin and shells ([`pelt_core::scene::surface_mesh::SurfaceVertex`]:
/// four `vec3`s, a `vec2`, a `vec3` and a `vec2`).
pub(super) const SURFACE_STRIDE: u64 = 76;
/// Bytes of one fin vertex ([`pelt_core::scene::fin_mesh::FinVertex`]: a `vec2`, two `u32` and an `f32`).
const FIN_STRIDE: u64 = 20;

/// Attributes of buffer 0 of the skin and shell passes (`SurfaceIn` in `surface_kk.wgsl`).
static SURFACE_ATTRIBUTES: [wgpu::VertexAttribute; 7] = wgpu::vertex_attr_array![
    0 => Float32x3, 1 => Float32x3, 2 => Float32x3, 3 => Float32x3, 4 => Float32x2, 5 => Float32x3,
    8 => Float32x2
];
/// Attributes of buffer 0 of the fin pass (`FinIn` in `light_model.wgsl`).
static FIN_ATTRIBUTES: [wgpu::VertexAttribute; 3] =
    wgpu::vertex_attr_array![5 => Float32x2, 8 => Uint32x2, 9 => Float32];
static COLOR_ATTRIBUTE: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![6 => Float32x4];
static LENGTH_ATTRIBUTE: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![7 => Float32];

/// The lighting model a pipeline shades with (the shader def `PRT` selects it in the WGSL).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Model {
    KajiyaKay,
    Prt,
}

/// The color target a pipeline writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Target {
    /// 8-bit sRGB: blending happens in linear light, the bytes come back sRGB-encoded.
    Srgb8,
    /// The same in BGRA order, the usual format of a window's surface.
    Bgra8Srgb,
    /// Half floats, linear (for [`super::Renderer::render_linear`]).
    Linear16,
    /// Single floats, linear: a CPU adapter's offscreen target for both
    /// [`super::Renderer::render`] and [`super::Renderer::render_linear`]. Lavapipe's half-float
    /// target loses a little at every blend (31 shells over a pixel came out 0.4% dark) and its
    /// sRGB8 target re-encodes each blend by a polynomial (instanced frames 5–7% bright).
    Linear32,
}

impl Target {
    pub fn format(self) -> wgpu::TextureFormat {
        match self {
            Target::Srgb8 => wgpu::TextureFormat::Rgba8UnormSrgb,
            Target::Bgra8Srgb => wgpu::TextureFormat::Bgra8UnormSrgb,
            Target::Linear16 => wgpu::TextureFormat::Rgba16Float,
            Target::Linear32 => wgpu::TextureFormat::Rgba32Float,
        }
    }

    /// The target that draws into a texture of `format`: 8-bit formats through their sRGB view
    /// (blending in linear light), half floats as they are.
    pub fn for_format(format: wgpu::TextureFormat) -> Option<Target> {
        use wgpu::TextureFormat as F;
        match format {
            F::Rgba8UnormSrgb | F::Rgba8Unorm => Some(Target::Srgb8),
            F::Bgra8UnormSrgb | F::Bgra8Unorm => Some(Target::Bgra8Srgb),
            F::Rgba16Float => Some(Target::Linear16),
            _ => None,
        }
    }

    /// Bytes of one texel.
    pub fn texel_bytes(self) -> u32 {
        match self {
            Target::Srgb8 | Target::Bgra8Srgb => 4,
            Target::Linear16 => 8,
            Target::Linear32 => 16,
        }
    }
}

/// Where a pass's vertices come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum VertexInput {
    /// Surface vertex buffers, indexed draw.
    Surface,
    /// Fin vertex buffers, indexed draw.
    Fins,
    /// No buffers: the shader pulls triangle corners from storage (PRT skin and shells).
    Pulled,
}

/// Buffer layouts: 0 geometry, 1 color (`vec4`), 2 length (`f32`).
fn vertex_layouts(input: VertexInput) -> Vec<Option<wgpu::VertexBufferLayout<'static>>> {
    let per_vertex = |array_stride, attributes| wgpu::VertexBufferLayout {
        array_stride,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes,
    };
    let geometry = match input {
        VertexInput::Pulled => return Vec::new(),
        VertexInput::Surface => per_vertex(SURFACE_STRIDE, &SURFACE_ATTRIBUTES),
        VertexInput::Fins => per_vertex(FIN_STRIDE, &FIN_ATTRIBUTES),
    };
    vec![
        Some(geometry),
        Some(per_vertex(16, &COLOR_ATTRIBUTE)),
        Some(per_vertex(4, &LENGTH_ATTRIBUTE)),
    ]
}

/// How a pass draws.
pub(super) struct PassState<'a> {
    pub label: &'a str,
    /// The composed shader ([`super::shaders::PassShader::module`]).
    pub module: &'static wgpu::naga::Module,
    pub input: VertexInput,
    pub topology: wgpu::PrimitiveTopology,
    pub cull_mode: Option<wgpu::Face>,
    pub depth_write: bool,
    pub blend: Option<wgpu::BlendState>,
}

/// A plain 2D texture of one mip level: the shape of every target and depth buffer.
pub(super) fn texture_2d(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// One pass's pipeline from its state: the recipe every fur pass shares.
pub(super) fn build_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    state: &PassState<'_>,
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(state.label),
        source: wgpu::ShaderSource::Naga(std::borrow::Cow::Borrowed(state.module)),
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(state.label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &vertex_layouts(state.input),
        },
        primitive: wgpu::PrimitiveState {
            topology: state.topology,
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
                format,
                blend: state.blend,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}
