//! The bind group and pipeline layouts every fur pass binds, and the samplers: group 0 (frame
//! uniforms, shell, tangent and fin textures, samplers, the skin's vertices, which the fins and
//! PRT's vertex pulling read, the virtual planes' slices), group 1 for PRT (transfer textures,
//! rotated lighting, layer means, the surface indices, colors and lengths for vertex pulling) and
//! group 2 for the strands (the guard strands, their points and root frames). Scenes build their
//! bind groups against these; the passes build their pipelines with them (`pipelines.rs`).

use std::num::NonZeroU64;
use std::sync::OnceLock;

use super::frame_uniforms::FrameUniforms;
use super::prt_rotate::RotatePipeline;
use super::shadow_map;
use pelt_core::error::{PeltError, Result};

/// What PRT adds: its bind group layout (group 1), the pipeline layout with it, and the
/// rotation compute pass.
pub(super) struct PrtShared {
    pub group_layout: wgpu::BindGroupLayout,
    pub pipeline_layout: wgpu::PipelineLayout,
    /// With the guard strands' group 2.
    pub strand_layout: wgpu::PipelineLayout,
    pub rotate: RotatePipeline,
}

/// Layouts and samplers; one per [`super::Renderer`].
pub(super) struct FurLayouts {
    pub bind_group_layout: wgpu::BindGroupLayout,
    pub pipeline_layout: wgpu::PipelineLayout,
    /// Group 2 of the strand pass: the guard strands, their points and their root frames.
    pub strand_group_layout: wgpu::BindGroupLayout,
    /// Groups 0 and 2 (group 1 is PRT's).
    pub strand_layout: wgpu::PipelineLayout,
    /// Repeating trilinear sampler: the shell tile wraps across each patch.
    pub tile_sampler: wgpu::Sampler,
    /// Repeats along the fin (u), clamps across (v: skin to top of the fur).
    pub fin_sampler: wgpu::Sampler,
    /// What a scene without the virtual planes' slices binds in their place.
    pub no_planes: wgpu::TextureView,
    /// The body's shadow map's comparison sampler: 2 × 2 texels filtered, clamped at the edges
    /// (the map holds the whole fur).
    pub shadow_sampler: wgpu::Sampler,
    prt: OnceLock<PrtShared>,
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
pub(super) fn validated<T>(
    device: &wgpu::Device,
    what: &str,
    build: impl FnOnce() -> Result<T>,
) -> Result<T> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let built = build();
    match (pollster::block_on(scope.pop()), built) {
        (None, built) => built,
        (Some(e), _) => Err(PeltError::Render(format!("building {what} failed: {e}"))),
    }
}

impl FurLayouts {
    /// Creates the layouts and samplers.
    ///
    /// # Errors
    /// [`PeltError::Render`] when the device rejects them.
    pub fn new(device: &wgpu::Device) -> Result<Self> {
        validated(device, "the fur layouts", || {
            let shadow = shadow_map::layout_entries(8, wgpu::ShaderStages::VERTEX_FRAGMENT);
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
                    // The body's shadow map and its comparison sampler: the fins light their
                    // corners in the vertex stage.
                    shadow[0],
                    shadow[1],
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
            Ok(FurLayouts {
                bind_group_layout,
                pipeline_layout,
                strand_group_layout,
                strand_layout,
                tile_sampler: sampler(device, "tile", wgpu::AddressMode::Repeat),
                fin_sampler: sampler(device, "fin", wgpu::AddressMode::ClampToEdge),
                no_planes: empty_planes(device),
                shadow_sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                    label: Some("body shadow"),
                    mag_filter: wgpu::FilterMode::Linear,
                    min_filter: wgpu::FilterMode::Linear,
                    compare: Some(wgpu::CompareFunction::LessEqual),
                    ..Default::default()
                }),
                prt: OnceLock::new(),
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
                    storage_entry(4, fragment),
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
}

/// A scene without slices binds this: one empty slice per family (wgpu zero-fills a new
/// texture), never read, since the planes pass refuses such a scene.
fn empty_planes(device: &wgpu::Device) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("no plane slices"),
            size: wgpu::Extent3d {
                width: 1,
                height: 1,
                depth_or_array_layers: 2,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&wgpu::TextureViewDescriptor {
            label: Some("no plane slices"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        })
}
