//! [`FurScene`]: a furred mesh uploaded once — split vertex buffers, fin quads, the hair volume's
//! textures — and updated in place when only colors or lengths change (Lengyel et al. 2001, §3:
//! per-vertex color and length are interactive controls, so they must not re-upload the rest).

use wgpu::util::DeviceExt;

use std::ops::Range;

use super::frame_uniforms::FrameUniforms;
use super::layouts::FurLayouts;
use super::lod::{Extent, Levels};
use super::pass::Model;
use super::planes::ScenePlanes;
use super::prt_rotate::{RotateOutputs, RotationUniforms};
use super::shadow_map::ShadowMap;
use super::shown_heights::shown_heights;
use super::stand_heights::{composite_groups, stand_heights};
use super::tangent_spread::tangent_moments;
use super::textures::VolumeTextures;
use super::{Renderer, scoped, textures, transfer};
use pelt_core::FurMesh;
use pelt_core::error::{PeltError, Result};
use pelt_core::mesh::{MAX_LENGTH, bounding_sphere};
use pelt_core::prt::pack::PackedF16;
use pelt_core::scene::curvature::vertex_curvature;
use pelt_core::scene::deform::Deformer;
use pelt_core::scene::fin_cull::FinPlanes;
use pelt_core::scene::fin_mesh::FinMesh;
use pelt_core::scene::fin_pose::PosedFinPlanes;
use pelt_core::scene::level_hosts::LevelHosts;
use pelt_core::scene::scene_levels::{self, MeshLevel, SceneLevels};
use pelt_core::scene::surface_mesh::expand;
use pelt_core::scene::surface_mesh::{self, SurfaceMesh};
use pelt_core::threads::pool;
use pelt_core::volume::slices::check_slices;
use pelt_core::volume::{HairVolume, PlaneSlices};

/// Hair color where the mesh has none: white, so the texture's own color shows.
const DEFAULT_COLOR: [f32; 4] = [1.0; 4];
/// Length multiplier where the mesh has none.
const DEFAULT_LENGTH: f32 = 1.0;

/// Bytes sent to the GPU by a scene, by kind (what [`FurScene::update_attributes`] saves).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct UploadStats {
    /// Shell, tangent and fin textures with their mip levels.
    pub texture_bytes: u64,
    /// PRT transfer textures with their mip levels and the fins' layer means, summed over every
    /// [`FurScene::set_transfer`].
    pub transfer_bytes: u64,
    /// Positions, frames, UVs, comb vectors and indices of the skin, shells and fins.
    pub geometry_bytes: u64,
    /// Colors and lengths, summed over the initial upload and every update.
    pub attribute_bytes: u64,
    /// Skin vertices (which the shells and fins are drawn from) rewritten by
    /// [`FurScene::deform`] and [`FurScene::update_comb`], summed over every pose and comb.
    pub pose_bytes: u64,
}

/// The vertex and index buffers of one kind of geometry (surface or fins). They are storage
/// buffers too, which PRT's vertex pulling and rotation pass read.
pub(super) struct GpuMesh {
    pub geometry: wgpu::Buffer,
    pub color: wgpu::Buffer,
    pub length: wgpu::Buffer,
    pub index: wgpu::Buffer,
}

impl GpuMesh {
    fn new(
        device: &wgpu::Device,
        label: &str,
        geometry: &[u8],
        indices: &[u32],
        colors: &[[f32; 4]],
        lengths: &[f32],
    ) -> Self {
        let buffer = |what: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(&format!("{label} {what}")),
                contents,
                usage,
            })
        };
        // Every vertex buffer is rewritten in place: colors and lengths by a repaint, the
        // geometry by a pose (`FurScene::deform`).
        let dynamic = wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
        // The fin pass rewrites its index buffer every frame (`fin_cull`).
        let index = wgpu::BufferUsages::INDEX | wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
        GpuMesh {
            geometry: buffer("geometry", geometry, dynamic),
            color: buffer("color", bytemuck::cast_slice(colors), dynamic),
            length: buffer("length", bytemuck::cast_slice(lengths), dynamic),
            index: buffer("index", bytemuck::cast_slice(indices), index),
        }
    }

    /// The fins of every level, under `attributes` (colors and lengths per mesh vertex).
    pub(super) fn fins(device: &wgpu::Device, fins: &FinMesh, attributes: (&[[f32; 4]], &[f32])) -> Self {
        GpuMesh::new(
            device,
            "fins",
            bytemuck::cast_slice(&fins.vertices),
            &fins.indices,
            &expand(attributes.0, &fins.source),
            &expand(attributes.1, &fins.source),
        )
    }

    /// Sets vertex buffers 0–2 and the index buffer.
    pub fn bind(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_vertex_buffer(0, self.geometry.slice(..));
        pass.set_vertex_buffer(1, self.color.slice(..));
        pass.set_vertex_buffer(2, self.length.slice(..));
        pass.set_index_buffer(self.index.slice(..), wgpu::IndexFormat::Uint32);
    }

    /// Draws the triangles of `indices` (a range of the index buffer: one geometric level)
    /// `instances` times: indexed from the vertex buffers, or for PRT one vertex per corner that
    /// the shader pulls from the storage buffers (bind group 1; the vertex index counts from the
    /// range's start).
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        model: Model,
        indices: Range<u32>,
        instances: Range<u32>,
    ) {
        match model {
            Model::KajiyaKay => {
                self.bind(pass);
                pass.draw_indexed(indices, 0, instances);
            }
            Model::Prt => pass.draw(indices, instances),
        }
    }
}

/// A furred mesh on the GPU of one [`Renderer`].
pub struct FurScene {
    renderer_id: u64,
    pub(super) queue: wgpu::Queue,
    pub(super) surface: GpuMesh,
    pub(super) fins: GpuMesh,
    /// The fins' planes, from which each frame collects the fins it draws.
    pub(super) fin_planes: std::sync::Mutex<PosedFinPlanes>,
    /// The full mesh and its simplified versions, finest first.
    pub(super) mesh_levels: Vec<MeshLevel>,
    /// Where each coarser level stands: after a repaint, those that would smear it are not
    /// drawn (until [`FurScene::remake_levels`]).
    pub(super) level_hosts: Vec<LevelHosts>,
    /// The current colors and lengths, per mesh vertex.
    pub(super) attributes: (Vec<[f32; 4]>, Vec<f32>),
    /// Levels, finest first, that a frame may draw under them.
    pub(super) drawable: usize,
    pub(super) uniforms: wgpu::Buffer,
    pub(super) bind_group: wgpu::BindGroup,
    /// The body's shadow map (redrawn when the light or the skin moves); the bind groups hold it.
    pub(super) shadow: ShadowMap,
    /// The volume's textures, which the bind group holds (kept to make it anew).
    volume_textures: VolumeTextures,
    /// The virtual planes' slices, when set.
    pub(super) planes: Option<ScenePlanes>,
    /// The mesh vertex each fin vertex came from.
    pub(super) fin_source: Vec<u32>,
    mesh_vertices: usize,
    pub(super) layers: u32,
    pub(super) layer_spacing: f32,
    /// Fur depth in object units: the height of the volume's top at length multiplier 1.
    pub(super) fur_depth: f32,
    resolution: usize,
    /// The shell array's LOD levels.
    pub(super) levels: Levels,
    /// Level 0's opacity `[L][R²]`, which weighs the transfer of the LOD composites.
    alpha: Vec<u8>,
    /// Level 0's color luminance `[L][R²]` (sRGB-encoded), which weighs the light each member of
    /// an LOD composite shows (`transfer::composite_members`).
    shade: Vec<u8>,
    /// Per array layer of every level, the level-0 height it stands at (`stand_heights.rs`).
    pub(super) stand_heights: Vec<f32>,
    /// The hair directions' second moment, for the fins' lighting (`tangent_spread.rs`).
    pub(super) fin_tangents: [[f32; 4]; 2],
    /// Bounding sphere and longest painted length, for the LOD schedule.
    pub(super) extent: Extent,
    pub(super) transfer: Option<SceneTransfer>,
    pub(super) uploads: UploadStats,
    /// The rest shape (the mesh as uploaded), to pose the scene and make its levels anew.
    pub(super) deformer: Deformer,
    /// The skin's rest vertices (which the guard strands' points are placed over), from which
    /// the geometric levels are made anew.
    pub(super) rest_surface: SurfaceMesh,
    /// The guard strands, when set.
    pub(super) strands: Option<SceneStrands>,
}

/// A scene's guard strands on the GPU.
pub(super) struct SceneStrands {
    /// Group 2 of the strand pass.
    pub bind_group: wgpu::BindGroup,
    /// Segments of the longest strand.
    pub segments: u32,
    /// The thickest root's radius.
    pub root_radius: f32,
    /// The strands as uploaded, in ascending LOD rank (their root triangles pose their frames,
    /// their ranks tell which the LOD may keep), and the frames.
    pub records: Vec<super::guard_strands::GpuStrand>,
    frames: wgpu::Buffer,
}

/// A scene's PRT state: the transfer textures and what the rotation pass and the PRT passes
/// bind.
pub(super) struct SceneTransfer {
    pub order: usize,
    pub textures: u32,
    /// Array layers per transfer texture.
    pub stride: u32,
    /// Rotation uniforms, rewritten every frame.
    pub uniforms: wgpu::Buffer,
    pub rotate_group: wgpu::BindGroup,
    /// Bind group 1 of the PRT passes.
    pub render_group: wgpu::BindGroup,
}

fn check_colors(colors: &[[f32; 4]], vertices: usize) -> Result<()> {
    if colors.len() != vertices {
        return Err(PeltError::parameter(
            "color",
            format!("must have one row per vertex ({vertices}), got {}", colors.len()),
        ));
    }
    if let Some(i) = colors.iter().position(|c| !c.iter().all(|v| v.is_finite())) {
        return Err(PeltError::parameter(
            format!("color[{i}]"),
            format!("must be finite, got {:?}", colors[i]),
        ));
    }
    Ok(())
}

fn check_lengths(lengths: &[f32], vertices: usize) -> Result<()> {
    if lengths.len() != vertices {
        return Err(PeltError::parameter(
            "length",
            format!(
                "must have one value per vertex ({vertices}), got {}",
                lengths.len()
            ),
        ));
    }
    if let Some(i) = lengths.iter().position(|l| !(0.0..=MAX_LENGTH).contains(l)) {
        return Err(PeltError::parameter(
            format!("length[{i}]"),
            format!("must be in [0, {MAX_LENGTH}], got {}", lengths[i]),
        ));
    }
    Ok(())
}

fn check_fur_depth(fur_depth: f32) -> Result<()> {
    pelt_core::mesh::FUR_DEPTH.check(f64::from(fur_depth))
}

/// The longest length multiplier (0 for none).
fn longest(lengths: &[f32]) -> f64 {
    lengths.iter().fold(0.0, |m, &l| m.max(f64::from(l)))
}

/// The skin's bounding sphere and the longest length multiplier (the fur stays out of the
/// radius: the LOD schedule measures it apart).
fn extent(positions: &[[f32; 3]], lengths: &[f32]) -> Extent {
    let (center, radius) = bounding_sphere(positions);
    Extent {
        center,
        radius,
        max_length: longest(lengths),
    }
}

impl FurScene {
    /// Uploads `mesh` (its colors, comb vectors and lengths, or white, none and 1 where absent)
    /// with per-triangle corner UVs in tile units (`corner_uvs[f][k]` for corner `k` of triangle
    /// `f`, as the lapped patches produce them; vertices are split where they differ) and the
    /// baked hair `volume`, whose fur is `fur_depth` object units deep (the bake's: the height of
    /// the volume's top at length multiplier 1, [`FurScene::fur_depth`]).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `fur_depth` (outside [`FUR_DEPTH`](pelt_core::mesh::FUR_DEPTH)),
    /// `corner_uvs` or the `volume` array whose size does not match (or exceeds the device),
    /// [`PeltError::Render`] when the device fails.
    pub fn new(
        renderer: &Renderer,
        mesh: &FurMesh,
        corner_uvs: &[[[f32; 2]; 3]],
        volume: &HairVolume,
        fur_depth: f32,
    ) -> Result<Self> {
        check_fur_depth(fur_depth)?;
        let device = &renderer.device;
        pelt_core::memory::check(
            "preview upload",
            super::scene_upload_peak_bytes(volume, renderer),
            || {
                format!(
                    "the volume's `resolution` ({}) or `layers` ({})",
                    volume.resolution, volume.layers
                )
            },
        )?;
        textures::validate(volume, &device.limits())?;
        let levels = Levels::new(volume.layers as u32);
        let alpha: Vec<u8> = volume.shells.chunks_exact(4).map(|px| px[3]).collect();
        let shade = pool().install(|| transfer::texel_shades(&volume.shells));
        let surface = surface_mesh::build(mesh, corner_uvs)?;
        let layouts = renderer.fur_layouts()?;
        let colors = mesh
            .color()
            .map_or_else(|| vec![DEFAULT_COLOR; mesh.vertex_count()], <[_]>::to_vec);
        let lengths = mesh
            .length()
            .map_or_else(|| vec![DEFAULT_LENGTH; mesh.vertex_count()], <[_]>::to_vec);
        let (surface_colors, surface_lengths) = (
            expand(&colors, &surface.source),
            expand(&lengths, &surface.source),
        );
        let SceneLevels {
            levels: mesh_levels,
            surface_indices,
            fins,
            hosts: level_hosts,
        } = SceneLevels::new(
            mesh,
            &surface,
            (&colors, &lengths),
            (&surface_colors, &surface_lengths),
        );

        let surface_indices = with_room_for_levels(&surface_indices, surface.indices.len());
        let (surface_gpu, fins_gpu, volume_gpu, uniforms, bind_group, shadow) =
            scoped(device, "uploading the scene", || {
                let surface_gpu = GpuMesh::new(
                    device,
                    "surface",
                    bytemuck::cast_slice(&surface.vertices),
                    &surface_indices,
                    &surface_colors,
                    &surface_lengths,
                );
                let fins_gpu = GpuMesh::fins(device, &fins, (&colors, &lengths));
                let volume_gpu = textures::upload_volume(
                    device,
                    &renderer.queue,
                    volume,
                    &levels,
                    renderer.color_store(),
                )?;
                let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("frame uniforms"),
                    size: size_of::<FrameUniforms>() as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                let shadow = ShadowMap::new(device);
                let bind_group = fur_bind_group(
                    device,
                    layouts,
                    &uniforms,
                    &volume_gpu,
                    &layouts.no_planes,
                    &surface_gpu.geometry,
                    &shadow,
                );
                Ok::<_, PeltError>((surface_gpu, fins_gpu, volume_gpu, uniforms, bind_group, shadow))
            })??;

        let attribute_rows = (surface.source.len() + fins.source.len()) as u64;
        let uploads = UploadStats {
            texture_bytes: volume_gpu.bytes,
            geometry_bytes: (size_of_val(surface.vertices.as_slice())
                + size_of_val(fins.vertices.as_slice())
                + 4 * (surface_indices.len() + fins.indices.len())) as u64,
            attribute_bytes: attribute_rows * (16 + 4),
            transfer_bytes: 0,
            pose_bytes: 0,
        };
        let deformer = Deformer::new(mesh, &surface);
        let fin_ends = fins.ends();
        let extent = extent(mesh.positions(), &lengths);
        Ok(FurScene {
            renderer_id: renderer.id,
            queue: renderer.queue.clone(),
            surface: surface_gpu,
            fins: fins_gpu,
            fin_planes: std::sync::Mutex::new(PosedFinPlanes::new(
                FinPlanes::new(fins.centers, fins.normals),
                fin_ends,
            )),
            drawable: mesh_levels.len(),
            mesh_levels,
            level_hosts,
            attributes: (colors, lengths),
            uniforms,
            bind_group,
            shadow,
            volume_textures: volume_gpu,
            planes: None,
            fin_source: fins.source,
            mesh_vertices: mesh.vertex_count(),
            layers: volume.layers as u32,
            layer_spacing: volume.layer_spacing as f32,
            fur_depth,
            resolution: volume.resolution,
            levels,
            stand_heights: stand_heights(&alpha, volume.layers, volume.resolution * volume.resolution),
            fin_tangents: tangent_moments(volume),
            alpha,
            shade,
            extent,
            transfer: None,
            uploads,
            deformer,
            rest_surface: surface,
            strands: None,
        })
    }

    /// Uploads a baked asset: its mesh with the patches' UVs, its volume and fur depth, and its
    /// transfer and guard hairs when it has them.
    ///
    /// # Errors
    /// As [`FurScene::new`], [`FurScene::set_transfer`] and [`FurScene::set_guard_hairs`].
    pub fn from_asset(renderer: &Renderer, asset: &pelt_core::pipeline::FurAsset) -> Result<Self> {
        let mut scene = FurScene::new(
            renderer,
            &asset.mesh,
            &asset.patches.uv,
            &asset.volume,
            asset.params.fur_depth() as f32,
        )?;
        if let Some(transfer) = &asset.transfer {
            scene.set_transfer(renderer, &transfer.packed_f16)?;
        }
        if let Some(guard_hairs) = &asset.guard_hairs {
            scene.set_guard_hairs(renderer, guard_hairs)?;
        }
        if let Some(planes) = &asset.planes {
            scene.set_planes(renderer, Some(planes))?;
        }
        Ok(scene)
    }

    /// Uploads PRT transfer textures ([`pelt_core::prt::pack::pack_f16`] of a transfer baked from
    /// this scene's hair volume), replacing any earlier ones; [`super::LightModel::Prt`] needs
    /// them.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `renderer` (not the one that uploaded the scene),
    /// `transfer.layers` or `transfer.resolution` (a texture set from another bake),
    /// `transfer.textures`, `transfer.texels` (length, or the first non-finite value) or
    /// `transfer` (beyond the device's limits); [`PeltError::Render`] when the device fails or
    /// lacks what PRT needs. The scene is unchanged then.
    pub fn set_transfer(&mut self, renderer: &Renderer, transfer: &PackedF16) -> Result<()> {
        if renderer.id != self.renderer_id {
            return Err(PeltError::parameter(
                "renderer",
                "is not the Renderer that uploaded this scene",
            ));
        }
        let device = &renderer.device;
        let limits = device.limits();
        let stride = self.levels.total() as usize;
        let order = transfer::check(
            transfer,
            self.layers as usize,
            self.resolution,
            stride,
            limits.max_texture_array_layers,
        )?;
        pelt_core::memory::check(
            "preview upload",
            super::transfer_upload_peak_bytes(self.layers as usize, self.resolution, order),
            || {
                format!(
                    "the transfer's `order` ({order}) or the volume's `resolution` ({})",
                    self.resolution
                )
            },
        )?;
        let vertices = self.rest_surface.source.len();
        // Per surface vertex: the rotated lighting (n² RGBA rows) and the hot spot's gain per
        // LOD composite (`prt_rotate.wgsl`, 8 bytes each).
        let composites = stride - self.layers as usize;
        let (rotated_bytes, gains_bytes) = (
            (vertices * order * order * 16) as u64,
            (vertices * composites * 8) as u64,
        );
        for (bytes, what) in [
            (rotated_bytes, format!("order {order}")),
            (gains_bytes, format!("{composites} LOD layers")),
        ] {
            if bytes > limits.max_storage_buffer_binding_size {
                return Err(PeltError::parameter(
                    "transfer",
                    format!(
                        "{what} on {vertices} surface vertices needs a {bytes}-byte buffer, the device allows {}",
                        limits.max_storage_buffer_binding_size
                    ),
                ));
            }
        }
        let (means, composite_ranges, chains, curvature) = pool().install(|| {
            let texels = self.resolution * self.resolution;
            let alphas = transfer::level_alphas(&self.alpha, &self.levels, texels);
            let per_texture = transfer::premultiplied_levels(transfer, &alphas, &self.levels);
            let chains = transfer::mip_chains(&per_texture, &alphas, &self.levels, self.resolution);
            let mut means = transfer::layer_means(transfer, &self.alpha, order);
            // After level 0's rows, the composites' heights per mip level (two values each,
            // padded to whole rows), then their members' rows.
            let n = order * order;
            let groups = composite_groups(self.layers as usize);
            let heights = shown_heights(&alphas[0], self.resolution, &groups);
            let height_rows = (2 * heights.len()).div_ceil(n);
            let members = transfer::composite_members(
                transfer,
                &alphas,
                &self.shade,
                &self.levels,
                order,
                self.layers as usize + height_rows,
            );
            let mut heights = heights.as_flattened().to_vec();
            heights.resize(height_rows * n, 0.0);
            means.extend_from_slice(&heights);
            means.extend_from_slice(&members.rows);
            (
                means,
                members.ranges,
                chains,
                vertex_curvature(&self.rest_surface),
            )
        });
        let chains = chains?;
        let layouts = renderer.fur_layouts()?;
        let prt = layouts.prt(device)?;
        let (scene_transfer, bytes) = scoped(device, "uploading the transfer", || {
            let textures = transfer::upload(device, &renderer.queue, &chains, self.resolution, stride)?;
            let storage = |label: &str, contents: &[u8]| {
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage: wgpu::BufferUsages::STORAGE,
                })
            };
            let means_buffer = storage("prt layer means", bytemuck::cast_slice(&means));
            let rotated = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("prt rotated lighting"),
                size: rotated_bytes.max(16),
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            });
            let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("prt rotation uniforms"),
                size: size_of::<RotationUniforms>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            // A binding is never empty (a scene may have no surface vertices).
            let curvature = storage(
                "prt surface curvature",
                bytemuck::cast_slice(if curvature.is_empty() {
                    &[0.0f32][..]
                } else {
                    &curvature
                }),
            );
            // Never empty: a scene may have no surface vertices, a volume no composite.
            let ranges = storage(
                "prt composite members",
                bytemuck::cast_slice(if composite_ranges.is_empty() {
                    &[[0u32; 4]][..]
                } else {
                    &composite_ranges
                }),
            );
            let gains = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("prt hot-spot gains"),
                size: gains_bytes.max(16),
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            });
            let rotate_group = prt.rotate.bind_group(
                device,
                &uniforms,
                &self.surface.geometry,
                &RotateOutputs {
                    rotated: &rotated,
                    curvature: &curvature,
                    means: &means_buffer,
                    composites: &ranges,
                    gains: &gains,
                },
                (&self.shadow.view, &layouts.shadow_sampler),
            );
            fn buffer(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
                wgpu::BindGroupEntry {
                    binding,
                    resource: buffer.as_entire_binding(),
                }
            }
            let render_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("prt"),
                layout: &prt.group_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&textures.view),
                    },
                    buffer(1, &rotated),
                    buffer(2, &means_buffer),
                    buffer(3, &self.surface.index),
                    buffer(4, &gains),
                    buffer(5, &self.surface.color),
                    buffer(6, &self.surface.length),
                ],
            });
            let scene_transfer = SceneTransfer {
                order,
                textures: transfer.textures as u32,
                stride: stride as u32,
                uniforms,
                rotate_group,
                render_group,
            };
            Ok::<_, PeltError>((
                scene_transfer,
                textures.bytes + size_of_val(means.as_slice()) as u64 + curvature.size() + ranges.size(),
            ))
        })??;
        self.transfer = Some(scene_transfer);
        self.uploads.transfer_bytes += bytes;
        Ok(())
    }

    /// Sets the virtual planes' slices ([`pelt_core::volume::bake_slices`] of this scene's hair),
    /// which [`super::ShellMethod::VirtualPlanes`] draws, replacing any earlier ones; `None`
    /// removes them.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `renderer` (not the one that uploaded the scene),
    /// `planes`, `plane_size[i]`, `planes.rgba` or `planes.tilt` (slices that do not match their
    /// sizes), or `plane_size` beyond the device; [`PeltError::MemoryLimit`] above the memory
    /// limit; [`PeltError::Render`] when the device fails. The scene is unchanged then.
    pub fn set_planes(&mut self, renderer: &Renderer, slices: Option<&PlaneSlices>) -> Result<()> {
        if renderer.id != self.renderer_id {
            return Err(PeltError::parameter(
                "renderer",
                "is not the Renderer that uploaded this scene",
            ));
        }
        let layouts = renderer.fur_layouts()?;
        let Some(slices) = slices else {
            self.planes = None;
            self.rebind(renderer, layouts);
            return Ok(());
        };
        check_slices(slices)?;
        let limits = renderer.device.limits();
        let (side, layers) = (
            limits.max_texture_dimension_2d as usize,
            limits.max_texture_array_layers as usize,
        );
        if slices.size.iter().any(|&s| s > side) || 2 * slices.planes > layers {
            return Err(PeltError::parameter(
                "plane_size",
                format!(
                    "must fit this device's textures ({side} texels a side, {layers} layers for 2 × planes), got {:?} with {} planes",
                    slices.size, slices.planes
                ),
            ));
        }
        // The slices, their mips (a third more) and their premultiplied copy.
        pelt_core::memory::check("preview upload", 3.0 * slices.rgba.len() as f64, || {
            format!("`planes` ({}) or `plane_size` ({:?})", slices.planes, slices.size)
        })?;
        let device = &renderer.device;
        let planes = scoped(device, "uploading the plane slices", || {
            super::planes::upload_planes(device, &renderer.queue, slices, renderer.color_store())
        })??;
        self.uploads.texture_bytes += planes.bytes;
        self.planes = Some(planes);
        self.rebind(renderer, layouts);
        Ok(())
    }

    /// Makes group 0 anew with the current textures.
    fn rebind(&mut self, renderer: &Renderer, layouts: &FurLayouts) {
        let planes = self.planes.as_ref().map_or(&layouts.no_planes, |p| &p.view);
        self.bind_group = fur_bind_group(
            &renderer.device,
            layouts,
            &self.uniforms,
            &self.volume_textures,
            planes,
            &self.surface.geometry,
            &self.shadow,
        );
    }

    /// Sets the guard hairs drawn as strands over the shells ([`pelt_core::guard::guard_hairs`] of
    /// this scene's mesh), replacing any earlier ones; an empty set removes them, so the frame
    /// is the shells alone. Each strand is tied to its root triangle and follows
    /// [`FurScene::deform`]; its points are taken as placed over the rest shape, its colors as
    /// baked (a repaint does not reach them).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `renderer` (not the one that uploaded the scene),
    /// `guard_hairs` (too many strands or points for the device or [`pelt_core::guard::MAX_GUARD_STRANDS`]),
    /// `guard_hairs.spans[i]` or `guard_hairs.points[i]` (see `guard_strands::prepare`);
    /// [`PeltError::MemoryLimit`] above the memory limit; [`PeltError::Render`] when the device
    /// fails. The scene is unchanged then.
    pub fn set_guard_hairs(
        &mut self,
        renderer: &Renderer,
        guard_hairs: &pelt_core::placement::PlacedStrands,
    ) -> Result<()> {
        if renderer.id != self.renderer_id {
            return Err(PeltError::parameter(
                "renderer",
                "is not the Renderer that uploaded this scene",
            ));
        }
        if guard_hairs.spans.is_empty() {
            self.strands = None;
            return Ok(());
        }
        // The strand records (kept), their frames and points, twice over while they are made
        // and sent.
        let bytes = 2.0 * (160.0 * guard_hairs.spans.len() as f64 + 16.0 * guard_hairs.points.len() as f64);
        pelt_core::memory::check("guard strand upload", bytes, || "`guard_share`".into())?;
        let lengths = expand(&self.attributes.1, &self.rest_surface.source);
        let prepared = super::guard_strands::prepare(
            guard_hairs,
            &self.rest_surface.vertices,
            self.deformer.triangles(),
            &lengths,
        )?;
        let device = &renderer.device;
        let limit = device.limits().max_storage_buffer_binding_size;
        // A draw's vertices, `strands · (2 · segments + 4)`, fit in a u32 below
        // MAX_GUARD_STRANDS strands of MAX_SEGMENTS segments; the buffers must fit the device.
        let biggest =
            size_of_val(prepared.points.as_slice()).max(size_of_val(prepared.strands.as_slice())) as u64;
        if biggest > limit {
            return Err(PeltError::parameter(
                "guard_hairs",
                format!(
                    "{} strands of {} points need a {biggest}-byte buffer, the device allows {limit} bytes",
                    prepared.strands.len(),
                    prepared.segments + 1
                ),
            ));
        }
        let layout = &renderer.fur_layouts()?.strand_group_layout;
        let scene_strands = scoped(device, "uploading the guard strands", || {
            let storage = |label: &str, contents: &[u8]| {
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage: wgpu::BufferUsages::STORAGE,
                })
            };
            let strands = storage("guard strands", bytemuck::cast_slice(&prepared.strands));
            let points = storage("guard strand points", bytemuck::cast_slice(&prepared.points));
            let frames = super::guard_strands::root_frames(self.deformer.current(), &prepared.strands);
            let frames = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("guard strand frames"),
                contents: bytemuck::cast_slice(&frames),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            });
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("guard strands"),
                layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: strands.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: points.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: frames.as_entire_binding(),
                    },
                ],
            });
            SceneStrands {
                bind_group,
                segments: prepared.segments,
                root_radius: prepared.root_radius,
                records: prepared.strands.clone(),
                frames,
            }
        })?;
        self.uploads.geometry_bytes +=
            (size_of_val(prepared.strands.as_slice()) + size_of_val(prepared.points.as_slice())) as u64;
        self.strands = Some(scene_strands);
        Ok(())
    }

    /// Guard strands the scene draws ([`FurScene::set_guard_hairs`]).
    pub fn guard_strand_count(&self) -> usize {
        self.strands.as_ref().map_or(0, |s| s.records.len())
    }

    /// The SH order of the scene's transfer, if it has one.
    pub fn transfer_order(&self) -> Option<usize> {
        self.transfer.as_ref().map(|t| t.order)
    }

    /// Rewrites the per-vertex colors and/or lengths (one row per mesh vertex, like
    /// [`pelt_core::MeshInput`]'s) in place; nothing else is sent to the GPU. Geometric levels of
    /// detail that cannot hold the new values (`pelt_core::scene::level_hosts`) are not drawn until they
    /// can again, or until [`FurScene::remake_levels`] makes them anew under these.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `color` / `length` (wrong row count) or the first
    /// bad row (`color[i]` not finite, `length[i]` outside `[0, MAX_LENGTH]`); nothing is written
    /// then.
    pub fn update_attributes(&mut self, color: Option<&[[f32; 4]]>, length: Option<&[f32]>) -> Result<()> {
        if let Some(c) = color {
            check_colors(c, self.mesh_vertices)?;
        }
        if let Some(l) = length {
            check_lengths(l, self.mesh_vertices)?;
            self.extent.max_length = longest(l);
        }
        let mut bytes = 0u64;
        if let Some(c) = color {
            for (mesh, source) in [
                (&self.surface, &self.rest_surface.source),
                (&self.fins, &self.fin_source),
            ] {
                let rows = expand(c, source);
                if rows.is_empty() {
                    continue;
                }
                self.queue
                    .write_buffer(&mesh.color, 0, bytemuck::cast_slice(&rows));
                bytes += size_of_val(rows.as_slice()) as u64;
            }
        }
        if let Some(l) = length {
            for (mesh, source) in [
                (&self.surface, &self.rest_surface.source),
                (&self.fins, &self.fin_source),
            ] {
                let rows = expand(l, source);
                if rows.is_empty() {
                    continue;
                }
                self.queue
                    .write_buffer(&mesh.length, 0, bytemuck::cast_slice(&rows));
                bytes += size_of_val(rows.as_slice()) as u64;
            }
        }
        // Sent now, as a pose is (`FurScene::deform`): repaints without a frame between them
        // would otherwise pile up their staging copies.
        self.queue.submit(std::iter::empty());
        self.uploads.attribute_bytes += bytes;
        if let Some(c) = color {
            self.attributes.0.copy_from_slice(c);
        }
        if let Some(l) = length {
            self.attributes.1.copy_from_slice(l);
        }
        self.drawable = scene_levels::drawable(&self.level_hosts, &self.attributes.0, &self.attributes.1);
        Ok(())
    }

    /// Checks comb vectors for [`FurScene::update_comb`] without changing anything.
    ///
    /// # Errors
    /// As [`FurScene::update_comb`].
    pub fn check_comb(&self, comb: &[[f32; 3]]) -> Result<()> {
        if comb.len() != self.mesh_vertices {
            return Err(PeltError::parameter(
                "comb",
                format!(
                    "must have one row per vertex ({}), got {}",
                    self.mesh_vertices,
                    comb.len()
                ),
            ));
        }
        match comb.iter().position(|c| !c.iter().all(|v| v.is_finite())) {
            Some(i) => Err(PeltError::parameter(
                format!("comb[{i}]"),
                format!("must be finite, got {:?}", comb[i]),
            )),
            None => Ok(()),
        }
    }

    /// Rewrites the comb vectors (one row per mesh vertex, object space at rest) in place: the
    /// shells and fins lean with the new comb (Lengyel et al. 2001, §3: the shear), in the
    /// current pose; the patches keep the orientation of the comb they were baked with.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `comb` (wrong row count) or `comb[i]` (not
    /// finite); nothing changes then.
    pub fn update_comb(&mut self, comb: &[[f32; 3]]) -> Result<()> {
        self.check_comb(comb)?;
        let deformer = &mut self.deformer;
        let surface = pool().install(|| deformer.set_comb(comb));
        let vertices = bytemuck::cast_slice::<_, u8>(surface);
        self.queue.write_buffer(&self.surface.geometry, 0, vertices);
        self.shadow.set_drawn(None);
        // Sent now, as a pose is.
        self.queue.submit(std::iter::empty());
        self.uploads.pose_bytes += vertices.len() as u64;
        Ok(())
    }

    /// Poses the scene: the mesh's vertices at `positions` (one row per mesh vertex, object
    /// space, the triangles of the bake) with `normals` (scaled to unit length), or normals
    /// computed from the posed triangles when `None`. Only the skin's vertex buffer is
    /// rewritten (the shells are drawn from it, the fins read their ends from it; see
    /// `deform.rs`), and the planes the CPU sorts the fins by follow at the next frame that
    /// draws them (`fin_pose.rs`); the textures, the transfer and the painted attributes stay, so a skinned
    /// character follows its armature every frame without a bake. Poses do not accumulate:
    /// each is taken from the rest shape.
    ///
    /// # Errors
    /// [`PeltError::InvalidMesh`] naming `positions` or `normals` (a row count other than the
    /// mesh's, a NaN or infinity, a zero normal); the scene is unchanged then.
    pub fn deform(&mut self, positions: &[[f32; 3]], normals: Option<&[[f32; 3]]>) -> Result<()> {
        let deformer = &mut self.deformer;
        let (surface, normals) = pool().install(|| deformer.pose(positions, normals))?;
        let vertices = bytemuck::cast_slice::<_, u8>(surface);
        self.queue.write_buffer(&self.surface.geometry, 0, vertices);
        self.shadow.set_drawn(None);
        if let Some(strands) = &self.strands {
            let frames = super::guard_strands::root_frames(surface, &strands.records);
            self.queue
                .write_buffer(&strands.frames, 0, bytemuck::cast_slice(&frames));
            self.uploads.pose_bytes += size_of_val(frames.as_slice()) as u64;
        }
        // Sent now: poses without a frame between them would otherwise pile up their staging
        // copies until the next frame's submit.
        self.queue.submit(std::iter::empty());
        self.uploads.pose_bytes += vertices.len() as u64;
        let levels = self.mesh_levels.iter().map(|l| l.fins.clone());
        self.fin_planes
            .get_mut()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .pose(positions, normals, levels);
        self.extent = extent(positions, &self.attributes.1);
        Ok(())
    }

    /// Bytes sent to the GPU so far, by kind.
    pub fn uploads(&self) -> UploadStats {
        self.uploads
    }

    /// GPU vertices of the skin and shells (mesh vertices plus the copies made at UV seams).
    pub fn surface_vertex_count(&self) -> usize {
        self.rest_surface.source.len()
    }

    /// Whether the virtual planes' slices are set ([`FurScene::set_planes`]).
    pub fn has_planes(&self) -> bool {
        self.planes.is_some()
    }

    /// Fin quads of the full mesh (one per mesh edge that has a fin plane).
    pub fn fin_count(&self) -> usize {
        self.mesh_levels.first().map_or(0, |l| l.fins.len())
    }

    /// Fin quads of every geometric level together (what the fin buffers hold).
    pub fn uploaded_fin_count(&self) -> usize {
        self.fin_source.len() / 4
    }

    /// Triangles of each geometric level of detail, the full mesh first
    /// ([`super::RenderSettings::mesh_error`]).
    pub fn level_triangles(&self) -> Vec<usize> {
        self.mesh_levels.iter().map(|l| l.indices.len() / 3).collect()
    }

    /// Geometric levels, the full mesh first, that frames may draw under the current colors and
    /// lengths (all of them as uploaded; see [`FurScene::update_attributes`]).
    pub fn drawable_level_count(&self) -> usize {
        self.drawable_levels().len()
    }

    /// The object-space error bound of each geometric level (0 for the full mesh).
    pub fn level_errors(&self) -> Vec<f64> {
        self.mesh_levels.iter().map(|l| l.error).collect()
    }

    /// The geometric levels a frame may draw, finest first: those that stand for the full
    /// mesh under the current colors and lengths ([`pelt_core::scene::level_hosts`]).
    pub(super) fn drawable_levels(&self) -> &[MeshLevel] {
        &self.mesh_levels[..self.drawable.min(self.mesh_levels.len())]
    }

    /// Layers of the shell texture, the skin included.
    pub fn layers(&self) -> u32 {
        self.layers
    }

    /// Fur depth in object units: the height of the volume's top at length multiplier 1
    /// (`pelt_length`), the shells standing at the volume's layer spacing of it.
    pub fn fur_depth(&self) -> f32 {
        self.fur_depth
    }

    /// Sets the fur depth (object units, [`FUR_DEPTH`](pelt_core::mesh::FUR_DEPTH)) that frames draw with from now on,
    /// without a re-upload (each frame's uniforms carry it): the shells and fins stretch to it at
    /// the next frame, so under Kajiya–Kay a new depth needs no bake. The guard hairs and a PRT
    /// transfer keep the depth they were baked for.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `fur_depth` (NaN, not above 0 or above
    /// [`MAX_FUR_DEPTH`](pelt_core::mesh::MAX_FUR_DEPTH)); the scene is unchanged then.
    pub fn set_fur_depth(&mut self, fur_depth: f32) -> Result<()> {
        check_fur_depth(fur_depth)?;
        self.fur_depth = fur_depth;
        Ok(())
    }

    pub(super) fn renderer_id(&self) -> u64 {
        self.renderer_id
    }
}

/// `indices` (every level's) followed by zeros up to twice the full mesh's `full` indices: each
/// coarser level has at most half the triangles of the one above (`geometry_lod`), so levels made
/// anew under other colors always fit, written in place (the PRT bind group keeps the buffer).
fn with_room_for_levels(indices: &[u32], full: usize) -> Vec<u32> {
    let mut padded = Vec::with_capacity(2 * full);
    padded.extend_from_slice(indices);
    padded.resize((2 * full).max(indices.len()), 0);
    padded
}

/// Group 0 of every fur pass: the frame's uniforms, the volume's textures and samplers, the
/// skin's vertices, the virtual planes' slices and the body's shadow map.
fn fur_bind_group(
    device: &wgpu::Device,
    layouts: &FurLayouts,
    uniforms: &wgpu::Buffer,
    volume: &VolumeTextures,
    planes: &wgpu::TextureView,
    skin: &wgpu::Buffer,
    shadow: &ShadowMap,
) -> wgpu::BindGroup {
    let view = wgpu::BindingResource::TextureView;
    let sampler = wgpu::BindingResource::Sampler;
    let resources = [
        uniforms.as_entire_binding(),
        view(&volume.shells),
        view(&volume.tangents),
        view(&volume.fin),
        sampler(&layouts.tile_sampler),
        sampler(&layouts.fin_sampler),
        skin.as_entire_binding(),
        view(planes),
        view(&shadow.view),
        sampler(&layouts.shadow_sampler),
    ];
    let entries: Vec<wgpu::BindGroupEntry<'_>> = resources
        .into_iter()
        .enumerate()
        .map(|(binding, resource)| wgpu::BindGroupEntry {
            binding: binding as u32,
            resource,
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("fur"),
        layout: &layouts.bind_group_layout,
        entries: &entries,
    })
}
