//! The pipelines of the fur passes, built from each pass's declared state (`pass.rs`): bind group
//! layouts (group 0: frame uniforms, shell, tangent and fin textures, samplers, the skin's
//! vertices, which the fins and PRT's vertex pulling read; group 1 for PRT: transfer textures,
//! rotated lighting, layer means, the surface indices, colors and lengths for vertex pulling) and
//! the pipeline recipe.
//!
//! Group 0 also holds the virtual planes' slices (binding 7).
//!
//! The strand pass adds group 2 (the guard strands, their points and root frames).
//!
//! The occluders' pass (`occluders.rs`), drawn first when the fur is composited into another
//! picture, has its own layout.
//!
//! Pipelines exist per lighting model and target format and are built on first use.

use std::num::NonZeroU64;
use std::sync::OnceLock;

use super::frame_uniforms::FrameUniforms;
use super::occluders::OccluderPass;
use super::pass::{DEPTH_FORMAT, Model, PassPipelines, PassState, Target, vertex_layouts};
use super::prt_rotate::RotatePipeline;
use super::{fins, marched, planes, shells, skin, strands};
use pelt_core::error::{PeltError, Result};

/// What PRT adds: its bind group layout (group 1), the pipeline layout with it, and the
/// rotation compute pass.
pub(super) struct PrtShared {
    pub group_layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    /// With the guard strands' group 2.
    strand_layout: wgpu::PipelineLayout,
    pub rotate: RotatePipeline,
}

/// Layouts, samplers and the pipelines built so far; one per [`super::Renderer`].
pub(super) struct FurPipelines {
    pub bind_group_layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    /// Group 2 of the strand pass: the guard strands, their points and their root frames.
    pub strand_group_layout: wgpu::BindGroupLayout,
    /// Groups 0 and 2 (group 1 is PRT's).
    strand_layout: wgpu::PipelineLayout,
    /// Repeating trilinear sampler: the shell tile wraps across each patch.
    pub tile_sampler: wgpu::Sampler,
    /// Repeats along the fin (u), clamps across (v: skin to top of the fur).
    pub fin_sampler: wgpu::Sampler,
    /// What a scene without the virtual planes' slices binds in their place.
    pub no_planes: wgpu::TextureView,
    prt: OnceLock<PrtShared>,
    /// Indexed by [`variant`].
    passes: [OnceLock<PassPipelines>; 6],
    /// Indexed by the target ([`variant`] under Kajiya–Kay).
    occluders: [OnceLock<OccluderPass>; 3],
}

fn variant(model: Model, target: Target) -> usize {
    let target = match target {
        Target::Srgb8 => 0,
        Target::Bgra8Srgb => 1,
        Target::Linear16 => 2,
    };
    3 * usize::from(model == Model::Prt) + target
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

fn storage_entry(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
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

/// Runs `build` in a validation scope: a rejected shader or pipeline becomes a
/// [`PeltError::Render`] naming `what`.
fn validated<T>(device: &wgpu::Device, what: &str, build: impl FnOnce() -> Result<T>) -> Result<T> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let built = build();
    match (pollster::block_on(scope.pop()), built) {
        (None, built) => built,
        (Some(e), _) => Err(PeltError::Render(format!("building {what} failed: {e}"))),
    }
}

impl FurPipelines {
    /// Creates the layouts and samplers.
    ///
    /// # Errors
    /// [`PeltError::Render`] when the device rejects them.
    pub fn new(device: &wgpu::Device) -> Result<Self> {
        validated(device, "the fur layouts", || {
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
                    // The skin's vertices: the fins read their ends from them, PRT's passes their
                    // corners (and the marched shells' fragments their frame).
                    storage_entry(6, wgpu::ShaderStages::VERTEX_FRAGMENT),
                    // The virtual planes' slices.
                    texture_entry(7, wgpu::TextureViewDimension::D2Array),
                ],
            });
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("fur"),
                bind_group_layouts: &[Some(&bind_group_layout)],
                immediate_size: 0,
            });
            let strand_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("guard strands"),
                entries: &[
                    storage_entry(0, wgpu::ShaderStages::VERTEX),
                    storage_entry(1, wgpu::ShaderStages::VERTEX),
                    storage_entry(2, wgpu::ShaderStages::VERTEX),
                ],
            });
            let strand_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("guard strands"),
                bind_group_layouts: &[Some(&bind_group_layout), None, Some(&strand_group_layout)],
                immediate_size: 0,
            });
            Ok(FurPipelines {
                bind_group_layout,
                pipeline_layout,
                strand_group_layout,
                strand_layout,
                tile_sampler: sampler(device, "tile", wgpu::AddressMode::Repeat),
                fin_sampler: sampler(device, "fin", wgpu::AddressMode::ClampToEdge),
                no_planes: super::planes::empty_planes(device),
                prt: OnceLock::new(),
                passes: Default::default(),
                occluders: Default::default(),
            })
        })
    }

    /// The PRT layouts and rotation pass, built on first use (a race builds them twice and keeps
    /// one).
    ///
    /// # Errors
    /// [`PeltError::Render`] when the device lacks what PRT needs (storage buffers in vertex
    /// shaders, compute).
    pub fn prt(&self, device: &wgpu::Device) -> Result<&PrtShared> {
        if let Some(p) = self.prt.get() {
            return Ok(p);
        }
        let built = validated(device, "the PRT layouts", || {
            let vertex = wgpu::ShaderStages::VERTEX;
            let fragment = wgpu::ShaderStages::FRAGMENT;
            let group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("prt"),
                entries: &[
                    texture_entry(0, wgpu::TextureViewDimension::D2Array),
                    storage_entry(1, fragment),
                    storage_entry(2, fragment),
                    storage_entry(3, vertex),
                    storage_entry(5, vertex),
                    storage_entry(6, vertex),
                ],
            });
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("prt"),
                bind_group_layouts: &[Some(&self.bind_group_layout), Some(&group_layout)],
                immediate_size: 0,
            });
            let strand_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("prt strands"),
                bind_group_layouts: &[
                    Some(&self.bind_group_layout),
                    Some(&group_layout),
                    Some(&self.strand_group_layout),
                ],
                immediate_size: 0,
            });
            Ok(PrtShared {
                group_layout,
                pipeline_layout,
                strand_layout,
                rotate: RotatePipeline::new(device)?,
            })
        })?;
        Ok(self.prt.get_or_init(|| built))
    }

    /// The pipelines of `model` into `target`, built on first use.
    ///
    /// # Errors
    /// [`PeltError::Render`] when the device rejects a shader or pipeline (a bug, or a device
    /// missing a downlevel capability).
    pub fn passes(&self, device: &wgpu::Device, model: Model, target: Target) -> Result<&PassPipelines> {
        let slot = &self.passes[variant(model, target)];
        if let Some(p) = slot.get() {
            return Ok(p);
        }
        let (layout, strand_layout) = match model {
            Model::KajiyaKay => (&self.pipeline_layout, &self.strand_layout),
            Model::Prt => {
                let prt = self.prt(device)?;
                (&prt.pipeline_layout, &prt.strand_layout)
            }
        };
        let format = target.format();
        let built = validated(device, "the fur pipelines", || {
            Ok(PassPipelines {
                skin: pipeline(device, layout, &skin::state(model), format),
                fins: pipeline(device, layout, &fins::state(model), format),
                shells: pipeline(device, layout, &shells::state(model), format),
                marched: pipeline(device, layout, &marched::state(model), format),
                planes: pipeline(device, layout, &planes::state(model), format),
                strands: pipeline(device, strand_layout, &strands::state(model, false), format),
                strands_sorted: pipeline(device, strand_layout, &strands::state(model, true), format),
            })
        })?;
        Ok(slot.get_or_init(|| built))
    }
}

impl FurPipelines {
    /// The pass writing another renderer's depth into `target`'s frames, built on first use.
    ///
    /// # Errors
    /// [`PeltError::Render`] when the device rejects it.
    pub fn occluders(&self, device: &wgpu::Device, target: Target) -> Result<&OccluderPass> {
        let slot = &self.occluders[variant(Model::KajiyaKay, target)];
        if let Some(p) = slot.get() {
            return Ok(p);
        }
        let built = validated(device, "the occluders' pipeline", || {
            Ok(OccluderPass::new(device, target.format()))
        })?;
        Ok(slot.get_or_init(|| built))
    }
}

/// One pass's pipeline from its state.
fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    state: &PassState<'_>,
    format: wgpu::TextureFormat,
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
