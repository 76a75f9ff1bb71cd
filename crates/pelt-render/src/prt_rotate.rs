//! The compute pass that rotates the world lighting into every surface vertex's tile frame
//! (prt-shell-fur §2.4), once per frame before the render pass (`prt_rotate.wgsl`).
//!
//! Why the GPU: the rotated lighting is `vertices × n²` RGB values (≈ 16 MB at order 5 for a
//! 40k-vertex mesh), which the fragments read from a storage buffer. Computing it on the CPU
//! would cost a rotation per vertex in f64 plus that upload every frame; the compute pass costs
//! one small uniform write. `pelt bench` measures both (`render.prt.rotate`).
//!
//! While the light may come from the eye the pass also weighs the hot-spot gain of each LOD
//! composite the frame draws, per vertex (`transfer::composite_members`): two products of `n²`
//! per member, far fewer than the fragments' loop over every member that the same factor would
//! cost (computed for every level, it had tripled a 44k-vertex frame on the CPU adapter).

use std::num::NonZeroU64;
use std::ops::Range;

use bytemuck::{Pod, Zeroable};

use super::pass::Model;
use super::prt_light::WorldLighting;
use super::shaders::PassShader;
use super::shadow_map::{self, ShadowFrame};
use pelt_core::error::{PeltError, Result};
use pelt_core::prt::sh::{MAX_COEFFS, MAX_ORDER, ShRotation};

/// The pass's shader, composed with the hot spot's ratio it shares with the fragments.
static SHADER: PassShader = PassShader::new("prt_rotate.wgsl", include_str!("prt_rotate.wgsl"));

/// Threads per workgroup (`WORKGROUP` in the shader).
const WORKGROUP: u32 = 64;

/// Mirrors `Rotation` in `prt_rotate.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(super) struct RotationUniforms {
    counts: [u32; 4],
    sun_direction: [f32; 4],
    layers: [u32; 4],
    light_view_proj: [f32; 16],
    shadow: [f32; 4],
    light: [[f32; 4]; MAX_COEFFS],
    sun: [[f32; 4]; MAX_COEFFS],
}

impl RotationUniforms {
    /// The uniforms for `vertices` surface vertices and the world lighting `light` (`n²` rows
    /// each for the environment and the directional light), hair `fur_depth` deep, with
    /// `layers` level-0 layers and `composites` LOD layers past them, of which `gains` (counted
    /// from the first) get the hot spot's gain: those the frame draws where the light may come
    /// from the eye (its share, `LightingFrame::hot_spot_share`, is not 0), else none; the
    /// directional light shadowed by the body through `shadow`'s map.
    pub fn new(
        vertices: u32,
        order: usize,
        light: &WorldLighting,
        fur_depth: f32,
        (layers, composites): (u32, u32),
        gains: Range<u32>,
        shadow: &ShadowFrame,
    ) -> Self {
        let rows = |c: &[[f32; 4]]| {
            let mut rows = [[0.0; 4]; MAX_COEFFS];
            rows[..c.len()].copy_from_slice(c);
            rows
        };
        let [x, y, z] = light.sun_direction;
        RotationUniforms {
            counts: [vertices, order as u32, (order * order) as u32, 0],
            sun_direction: [x, y, z, fur_depth],
            layers: [layers, composites, gains.start, gains.end.min(composites)],
            light_view_proj: shadow.light_view_proj.to_cols_array(),
            shadow: shadow.params,
            light: rows(&light.environment),
            sun: rows(&light.sun),
        }
    }
}

/// What the rotation pass writes and reads per scene besides its uniforms and the geometry.
pub(super) struct RotateOutputs<'a> {
    /// The rotated lighting, per surface vertex `n²` RGBA rows.
    pub rotated: &'a wgpu::Buffer,
    /// Per surface vertex, the surface's curvature.
    pub curvature: &'a wgpu::Buffer,
    /// Level 0's layer means, then the composites' member rows (`transfer::composite_members`).
    pub means: &'a wgpu::Buffer,
    /// Per composite, its members (`CompositeMembers::ranges`).
    pub composites: &'a wgpu::Buffer,
    /// Per surface vertex and composite, the hot spot's gain.
    pub gains: &'a wgpu::Buffer,
}

/// The band matrices of a rotation by 90° about +x, bands `0..MAX_ORDER` one after the other,
/// row-major (the shader's `x90`).
pub(super) fn x90_bands() -> Result<Vec<f32>> {
    let rx90 = [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]];
    let rotation = ShRotation::new(MAX_ORDER, rx90)?;
    Ok((0..MAX_ORDER)
        .filter_map(|l| rotation.band(l))
        .flatten()
        .map(|&v| v as f32)
        .collect())
}

/// The compute pipeline, its bind group layout and the constant band matrices.
pub(super) struct RotatePipeline {
    pipeline: wgpu::ComputePipeline,
    pub layout: wgpu::BindGroupLayout,
    x90: wgpu::Buffer,
}

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl RotatePipeline {
    /// Compiles the shader and uploads the band matrices; call inside an error scope.
    pub fn new(device: &wgpu::Device) -> Result<Self> {
        use wgpu::util::DeviceExt;
        let shadow = shadow_map::layout_entries(8, wgpu::ShaderStages::COMPUTE);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("prt rotation"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: NonZeroU64::new(size_of::<RotationUniforms>() as u64),
                    },
                    count: None,
                },
                storage_entry(1, true),
                storage_entry(2, true),
                storage_entry(3, false),
                storage_entry(4, true),
                storage_entry(5, true),
                storage_entry(6, true),
                storage_entry(7, false),
                // The body's shadow map and its comparison sampler (`shadow_map.rs`).
                shadow[0],
                shadow[1],
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("prt rotation"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("prt rotation"),
            source: wgpu::ShaderSource::Naga(std::borrow::Cow::Borrowed(SHADER.module(Model::Prt)?)),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("prt rotation"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let x90 = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("prt x90 bands"),
            contents: bytemuck::cast_slice(&x90_bands()?),
            usage: wgpu::BufferUsages::STORAGE,
        });
        Ok(RotatePipeline {
            pipeline,
            layout,
            x90,
        })
    }

    /// The bind group of one scene: its uniforms, surface geometry, `outputs` and its body
    /// shadow map with the comparison sampler.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        uniforms: &wgpu::Buffer,
        geometry: &wgpu::Buffer,
        outputs: &RotateOutputs<'_>,
        shadow: (&wgpu::TextureView, &wgpu::Sampler),
    ) -> wgpu::BindGroup {
        fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry {
                binding,
                resource: buffer.as_entire_binding(),
            }
        }
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("prt rotation"),
            layout: &self.layout,
            entries: &[
                entry(0, uniforms),
                entry(1, geometry),
                entry(2, &self.x90),
                entry(3, outputs.rotated),
                entry(4, outputs.curvature),
                entry(5, outputs.means),
                entry(6, outputs.composites),
                entry(7, outputs.gains),
                wgpu::BindGroupEntry {
                    binding: 8,
                    resource: wgpu::BindingResource::TextureView(shadow.0),
                },
                wgpu::BindGroupEntry {
                    binding: 9,
                    resource: wgpu::BindingResource::Sampler(shadow.1),
                },
            ],
        })
    }

    /// Records the rotation of `vertices` vertices.
    ///
    /// # Errors
    /// [`PeltError::Render`] when the vertices need more workgroups than the device dispatches.
    pub fn dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        group: &wgpu::BindGroup,
        vertices: u32,
        max_per_dimension: u32,
    ) -> Result<()> {
        let groups = vertices.div_ceil(WORKGROUP);
        // Wide dispatches fold into rows; the shader unfolds `x + y · width`.
        let width = groups.min(max_per_dimension).max(1);
        let rows = groups.div_ceil(width);
        if rows > max_per_dimension {
            return Err(PeltError::Render(format!(
                "{vertices} surface vertices need more compute workgroups than the device allows"
            )));
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("prt rotation"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(width, rows, 1);
        Ok(())
    }
}
