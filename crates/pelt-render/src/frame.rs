//! One frame: the fur passes in Lengyel et al. 2001's order (§2.3) — skin, fins, shells, with the
//! guard strands among the shells (hybrid paper §3) and, when compositing, the occluders' depth
//! first — in a single render pass into an offscreen target (8-bit sRGB or linear half floats), then read
//! back, or into a caller's texture (`texture_target.rs`). Under PRT a compute pass first rotates
//! the lighting into every vertex's tile frame; before either, when the light or the skin moved,
//! a depth pass draws the body's shadow map (`shadow_map.rs`).

use super::camera::{Camera, CameraFrame};
use super::frame_uniforms::{FrameUniforms, SceneFrame};
use super::image::{LinearImage, RgbaImage, straight_srgb8_row};
use super::lighting::{Lighting, LightingFrame};
use super::lod::{self, FrameInfo};
use super::occluders::Occluders;
use super::pass::{DEPTH_FORMAT, Model, Target, texture_2d};
use super::prt_light::world_coefficients;
use super::prt_rotate::RotationUniforms;
use super::readback::{read_texels, read_texels_with};
use super::scene::FurScene;
use super::settings::{RenderSettings, ShellMethod};
use super::shadow_map::ShadowFrame;
use super::strands::{self, Bands};
use super::{Renderer, scoped};
use pelt_core::error::{PeltError, Result};
use pelt_core::scene::fin_pose::PosedFinPlanes;
use pelt_core::scene::geometry_lod;

/// The depth target of one size and, for frames drawn offscreen, a color target of that size,
/// kept between frames.
pub(super) struct Targets {
    size: (u32, u32),
    depth_view: wgpu::TextureView,
    color: Option<ColorTarget>,
}

/// The offscreen color target.
struct ColorTarget {
    target: Target,
    texture: wgpu::Texture,
    view: wgpu::TextureView,
}

impl Targets {
    /// `cached` if it fits `size` (and holds a color target of `color`, when one is asked for),
    /// else the parts that do not fit made anew.
    fn fit(
        device: &wgpu::Device,
        cached: Option<Targets>,
        size: (u32, u32),
        color: Option<Target>,
    ) -> Targets {
        let mut targets = match cached {
            Some(t) if t.size == size => t,
            _ => {
                let depth = texture_2d(
                    device,
                    "fur depth",
                    size,
                    DEPTH_FORMAT,
                    wgpu::TextureUsages::RENDER_ATTACHMENT,
                );
                Targets {
                    size,
                    depth_view: depth.create_view(&wgpu::TextureViewDescriptor::default()),
                    color: None,
                }
            }
        };
        if let Some(target) = color
            && targets.color.as_ref().is_none_or(|c| c.target != target)
        {
            let texture = texture_2d(
                device,
                "fur color",
                size,
                target.format(),
                // Read back, or copied into a caller's texture (`resolve.rs`).
                wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::COPY_SRC
                    | wgpu::TextureUsages::TEXTURE_BINDING,
            );
            targets.color = Some(ColorTarget {
                target,
                view: texture.create_view(&wgpu::TextureViewDescriptor::default()),
                texture,
            });
        }
        targets
    }
}

/// Where a frame goes: a caller's texture (of the target's format and the camera's size), or
/// the cached offscreen target, read back as `Readback` says.
#[derive(Clone, Copy)]
pub(super) enum Output<'a> {
    Texture(&'a wgpu::TextureView),
    /// A caller's texture of the given format, the frame drawn offscreen in the draw's target
    /// and copied into it once (`resolve.rs`).
    Resolved(&'a wgpu::TextureView, Target),
    Read(Readback),
}

/// How an offscreen frame's texels come back.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Readback {
    /// The target's own bytes, premultiplied.
    Stored,
    /// A [`Target::Linear32`] frame as straight-alpha sRGB8, encoded once while it is read.
    StraightSrgb8,
}

/// Everything a frame needs, checked.
struct Checked {
    camera: CameraFrame,
    light: LightingFrame,
    model: Model,
    info: FrameInfo,
}

impl Renderer {
    /// Renders `scene` offscreen: the opaque skin (writing depth), the fins near the silhouette
    /// (if `settings.fins`), then the shells inner to outer in one instanced draw. Returns 8-bit
    /// sRGB with straight alpha, blended in an sRGB8 target (on a CPU adapter, in single floats
    /// and encoded once: see `Target::Linear32`).
    ///
    /// Renders are serialized per renderer; the result depends only on the inputs (and the
    /// adapter).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming the bad camera, lighting or settings field,
    /// `lighting.model` for PRT on a scene without transfer textures, or `scene` when it was
    /// uploaded by another renderer; [`PeltError::Render`] when the device fails. The renderer
    /// stays usable after an error.
    pub fn render(
        &self,
        scene: &FurScene,
        camera: &Camera,
        lighting: &Lighting,
        settings: &RenderSettings,
    ) -> Result<RgbaImage> {
        self.render_over(scene, camera, lighting, settings, None)
    }

    /// [`Renderer::render`] for compositing into another renderer's picture of the same view:
    /// the fur behind `occluders` (that picture's depth, pushed back by their bias) is hidden;
    /// `None` draws it over everything, as [`Renderer::render`].
    ///
    /// # Errors
    /// As [`Renderer::render`]; [`PeltError::InvalidParameter`] naming `occluders.depth` or
    /// `occluders.bias` when they do not fit the camera or their ranges.
    pub fn render_over(
        &self,
        scene: &FurScene,
        camera: &Camera,
        lighting: &Lighting,
        settings: &RenderSettings,
        occluders: Option<&Occluders>,
    ) -> Result<RgbaImage> {
        let (w, h) = (camera.width, camera.height);
        let (target, read) = if self.exact_targets {
            (Target::Linear32, Readback::StraightSrgb8)
        } else {
            (Target::Srgb8, Readback::Stored)
        };
        let bytes = self.render_to(scene, camera, lighting, settings, target, read, occluders)?;
        Ok(match read {
            Readback::StraightSrgb8 => RgbaImage::from_straight(w, h, bytes),
            Readback::Stored => RgbaImage::from_premultiplied(w, h, bytes),
        })
    }

    /// [`Renderer::render`] into a half-float target (single floats on a CPU adapter), returned
    /// as linear `f32` RGBA with straight alpha (no 8-bit rounding; HDR values above 1 are kept).
    ///
    /// # Errors
    /// As [`Renderer::render`].
    pub fn render_linear(
        &self,
        scene: &FurScene,
        camera: &Camera,
        lighting: &Lighting,
        settings: &RenderSettings,
    ) -> Result<LinearImage> {
        self.render_linear_over(scene, camera, lighting, settings, None)
    }

    /// [`Renderer::render_linear`] behind `occluders`, as [`Renderer::render_over`].
    ///
    /// # Errors
    /// As [`Renderer::render_over`].
    pub fn render_linear_over(
        &self,
        scene: &FurScene,
        camera: &Camera,
        lighting: &Lighting,
        settings: &RenderSettings,
        occluders: Option<&Occluders>,
    ) -> Result<LinearImage> {
        let (w, h) = (camera.width, camera.height);
        let target = if self.exact_targets {
            Target::Linear32
        } else {
            Target::Linear16
        };
        let read = Readback::Stored;
        let bytes = self.render_to(scene, camera, lighting, settings, target, read, occluders)?;
        Ok(match target {
            Target::Linear32 => LinearImage::from_premultiplied_f32(w, h, &bytes),
            _ => LinearImage::from_premultiplied_f16(w, h, &bytes),
        })
    }

    /// What [`Renderer::render`] would draw with these inputs: the shell count, and with LOD
    /// the level, blend and the projected sizes it followed.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming the bad camera or settings field, or `scene` when
    /// it was uploaded by another renderer.
    pub fn frame_info(
        &self,
        scene: &FurScene,
        camera: &Camera,
        settings: &RenderSettings,
    ) -> Result<FrameInfo> {
        if scene.renderer_id() != self.id {
            return Err(PeltError::parameter("scene", "was uploaded by another Renderer"));
        }
        CameraFrame::of(camera, self.device.limits().max_texture_dimension_2d)?;
        settings.shells_to_draw(scene.layers)?;
        let settings = &settings.as_drawn(self.shell_method(settings.shell_method));
        let fixed = settings.shells_to_draw(scene.layers)?;
        let mut info = lod::choose(
            &scene.levels,
            settings,
            camera,
            &scene.extent,
            scene.fur_depth,
            fixed,
        );
        let levels = scene.drawable_levels();
        let errors: Vec<f64> = levels.iter().map(|l| l.error).collect();
        let ppu = lod::nearest_pixels_per_unit(camera, scene.extent.center, scene.extent.radius);
        let level = geometry_lod::choose(&errors, ppu, settings.mesh_error);
        info.mesh_level = level as u32;
        info.triangles = levels.get(level).map_or(0, |l| l.indices.len() as u32 / 3);
        Ok(info)
    }

    fn check(
        &self,
        scene: &FurScene,
        camera: &Camera,
        lighting: &Lighting,
        settings: &RenderSettings,
    ) -> Result<Checked> {
        let info = self.frame_info(scene, camera, settings)?;
        // Host memory of a frame: the readback (up to 8 bytes a pixel; 16 on a CPU adapter,
        // whose single-float target is host memory too), the converted image (up to 16) and a
        // caller's copy (16).
        let pixels = f64::from(camera.width) * f64::from(camera.height);
        let per_pixel = if self.exact_targets { 64.0 } else { 40.0 };
        pelt_core::memory::check("render", per_pixel * pixels, || {
            format!("`width` ({}) or `height` ({})", camera.width, camera.height)
        })?;
        let camera = CameraFrame::of(camera, self.device.limits().max_texture_dimension_2d)?;
        let light = lighting.frame()?;
        let model = if light.prt.is_some() {
            if scene.transfer.is_none() {
                return Err(PeltError::parameter(
                    "lighting.model",
                    "\"prt\" needs a baked transfer: bake with the transfer on (Python: \
                     Pipeline.bake(transfer=True)), or use \"kajiya-kay\"",
                ));
            }
            Model::Prt
        } else {
            Model::KajiyaKay
        };
        if self.shell_method(settings.shell_method) == ShellMethod::VirtualPlanes && scene.planes.is_none() {
            return Err(PeltError::parameter(
                "shell_method",
                "\"planes\" needs the virtual planes' slices: bake them (Python: \
                 Pipeline.bake(planes=32)) or set them with FurScene::set_planes, or draw the shells",
            ));
        }
        Ok(Checked {
            camera,
            light,
            model,
            info,
        })
    }

    /// Renders into `target` offscreen and returns its texels as `read` says.
    #[allow(clippy::too_many_arguments)]
    fn render_to(
        &self,
        scene: &FurScene,
        camera: &Camera,
        lighting: &Lighting,
        settings: &RenderSettings,
        target: Target,
        read: Readback,
        occluders: Option<&Occluders>,
    ) -> Result<Vec<u8>> {
        let output = Output::Read(read);
        let (_, texels) = self.draw(scene, camera, lighting, settings, target, output, occluders)?;
        texels.ok_or_else(|| PeltError::Render("an offscreen frame was not read back".into()))
    }

    /// Draws a frame into `output`: a caller's texture, or the cached offscreen target, whose
    /// texels it then reads back; behind `occluders` when given.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn draw(
        &self,
        scene: &FurScene,
        camera: &Camera,
        lighting: &Lighting,
        settings: &RenderSettings,
        target: Target,
        output: Output<'_>,
        occluders: Option<&Occluders>,
    ) -> Result<(FrameInfo, Option<Vec<u8>>)> {
        let checked = self.check(scene, camera, lighting, settings)?;
        if let Some(o) = occluders {
            o.check(camera.width, camera.height)?;
        }
        let resolve_pass = match output {
            Output::Resolved(_, format) => Some(self.fur_pipelines()?.resolve(&self.device, format)?),
            _ => None,
        };
        let occluder_pass = match occluders {
            Some(_) => Some(self.fur_pipelines()?.occluders(&self.device, target)?),
            None => None,
        };
        let pipelines = self
            .fur_pipelines()?
            .passes(&self.device, checked.model, target)?;
        // The directional light is shadowed by the body: per fragment under Kajiya–Kay, per
        // vertex in PRT's rotation pass (its transfer is the fur's alone).
        let shadow_pass = if settings.body_shadow && checked.light.color != [0.0; 3] {
            Some(self.fur_pipelines()?.shadow(&self.device)?)
        } else {
            None
        };
        let transfer = scene.transfer.as_ref().filter(|_| checked.model == Model::Prt);
        let rotate = match transfer {
            Some(_) => Some(&self.fur_layouts()?.prt(&self.device)?.rotate),
            None => None,
        };
        let level = scene
            .mesh_levels
            .get(checked.info.mesh_level as usize)
            .ok_or_else(|| PeltError::Render("the geometric level drawn is missing".into()))?;
        let method = self.shell_method(settings.shell_method);
        let settings = &settings.as_drawn(method);
        let shadow_frame = match shadow_pass {
            // At least the fur of length 1: painting the fur shorter leaves the map as it was
            // (a bald mesh draws exactly its skin).
            Some(_) => ShadowFrame::new(
                checked.light.direction,
                &scene.extent,
                f64::from(scene.fur_depth) * scene.extent.max_length.max(1.0),
            ),
            None => ShadowFrame::NONE,
        };
        // Drawn again only when what it shows changed (the skin's moves clear it).
        let shadow_redraw = shadow_pass.filter(|_| scene.shadow.stale(&shadow_frame, &level.indices));
        let rotation = match transfer {
            Some(t) => Some(RotationUniforms::new(
                scene.surface_vertex_count() as u32,
                t.order,
                &world_coefficients(&checked.light, t.order)?,
                scene.fur_depth,
                (scene.layers, t.stride - scene.layers),
                // Only the instanced shells read the composites' gains.
                if checked.light.hot_spot_share() > 0.0 && method == ShellMethod::Instanced {
                    scene.levels.composites_drawn(&checked.info)
                } else {
                    0..0
                },
                &shadow_frame,
            )),
            None => None,
        };
        let strand_scene = scene.strands.as_ref().filter(|_| settings.guard_hairs);
        let bands = Bands::new(settings, checked.info.shells, method, strand_scene.is_some());
        let ppu = lod::nearest_pixels_per_unit(camera, scene.extent.center, scene.extent.radius);
        let strand_draw = strand_scene.map_or((0, 0), |s| {
            let fur_pixels = ppu.map_or(f64::INFINITY, |ppu| {
                f64::from(scene.fur_depth) * scene.extent.max_length * ppu
            });
            (
                strands::kept_strands(&s.records, s.root_radius, ppu, settings.strand_pixels),
                strands::segments_drawn(s.segments, fur_pixels),
            )
        });
        let uniforms = FrameUniforms::new(
            &checked.camera,
            &checked.light,
            settings,
            &SceneFrame {
                info: &checked.info,
                levels: &scene.levels,
                stand_heights: &scene.stand_heights,
                layers: scene.layers,
                fur_depth: scene.fur_depth,
                layer_spacing: scene.layer_spacing,
                prt: transfer.map_or([0; 3], |t| [(t.order * t.order) as u32, t.textures, t.stride]),
                fin_spacing: level.fin_spacing,
                fin_tangents: scene.fin_tangents,
                strand: (
                    [
                        camera.width as f32,
                        camera.height as f32,
                        settings.strand_pixels,
                        strands::MIN_KEPT,
                    ],
                    [
                        bands.count,
                        strand_draw.1,
                        u32::from(bands.whole) | (u32::from(bands.stochastic) << 1),
                        0,
                    ],
                ),
                planes: scene.planes.as_ref().map_or((0, [0.0; 2]), |p| (p.count, p.tilt)),
                shadow: shadow_frame,
            },
        );
        // A panic elsewhere cannot leave the cached targets half-made, so a poisoned lock is fine.
        let mut cached = self
            .targets
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let size = (camera.width, camera.height);
        let (view, read, resolved) = match output {
            Output::Texture(view) => (Some(view), None, None),
            Output::Resolved(view, _) => (None, None, Some(view)),
            Output::Read(read) => (None, Some(read), None),
        };
        let offscreen = view.is_none().then_some(target);
        let targets = scoped(&self.device, "creating the render targets", || {
            Targets::fit(&self.device, cached.take(), size, offscreen)
        })?;
        let targets = cached.insert(targets);
        let (color_view, readback) = match (view, &targets.color) {
            (Some(view), _) => (view, None),
            (None, Some(color)) => (&color.view, Some(&color.texture)),
            (None, None) => {
                return Err(PeltError::Render("the offscreen color target is missing".into()));
            }
        };
        let [r, g, b, a] = settings.background.map(f64::from);
        let max_groups = self.device.limits().max_compute_workgroups_per_dimension;
        let fin_indices = if settings.fins && settings.fin_opacity > 0.0 {
            // On Pelt's own threads, not the global pool of the process it shares (Blender's).
            let mut planes = scene
                .fin_planes
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            let planes: &mut PosedFinPlanes = &mut planes;
            let eye = checked.camera.eye.to_array();
            pelt_core::threads::pool().install(|| planes.visible_indices(eye, level.fins.clone()))
        } else {
            Vec::new()
        };
        scoped(&self.device, "rendering a frame", || {
            self.queue
                .write_buffer(&scene.uniforms, 0, bytemuck::bytes_of(&uniforms));
            if !fin_indices.is_empty() {
                self.queue
                    .write_buffer(&scene.fins.index, 0, bytemuck::cast_slice(&fin_indices));
            }
            let occluder_group = occluder_pass.zip(occluders).map(|(pass, o)| {
                (
                    pass,
                    pass.bind(&self.device, &self.queue, &checked.camera, size, o),
                )
            });
            let mut encoder = self
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("fur") });
            if let Some(shadow) = shadow_redraw {
                let skin = (
                    &scene.surface.geometry,
                    &scene.surface.index,
                    level.indices.clone(),
                );
                shadow.draw(
                    &self.device,
                    &self.queue,
                    &mut encoder,
                    &scene.shadow,
                    &shadow_frame,
                    skin,
                );
            }
            if let (Some(t), Some(rotation), Some(rotate)) = (transfer, &rotation, rotate) {
                self.queue
                    .write_buffer(&t.uniforms, 0, bytemuck::bytes_of(rotation));
                rotate.dispatch(
                    &mut encoder,
                    &t.rotate_group,
                    scene.surface_vertex_count() as u32,
                    max_groups,
                )?;
            }
            {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("fur"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: color_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            // The target holds premultiplied color.
                            load: wgpu::LoadOp::Clear(wgpu::Color {
                                r: r * a,
                                g: g * a,
                                b: b * a,
                                a,
                            }),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &targets.depth_view,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(1.0),
                            store: wgpu::StoreOp::Discard,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                if let Some((occluders, group)) = &occluder_group {
                    occluders.draw(&mut pass, group);
                }
                pass.set_bind_group(0, &scene.bind_group, &[]);
                if let Some(t) = transfer {
                    pass.set_bind_group(1, &t.render_group, &[]);
                }
                pipelines.skin.draw(&mut pass, scene, level, checked.model);
                pipelines.fins.draw(&mut pass, scene, fin_indices.len() as u32);
                // Without strands, one band: the shells in one draw.
                for k in 0..bands.draws() {
                    pipelines.strands.draw(&mut pass, scene, &bands, k, strand_draw);
                    let shells = bands.shell_start(k)..bands.shell_start(k + 1).min(checked.info.shells);
                    pipelines
                        .shells
                        .draw(&mut pass, scene, level, checked.model, (shells, method));
                }
            }
            if let (Some(pass), Some(into)) = (resolve_pass, resolved) {
                pass.draw(&self.device, &mut encoder, color_view, into);
            }
            self.queue.submit([encoder.finish()]);
            Ok::<_, PeltError>(())
        })??;
        if shadow_redraw.is_some() {
            scene
                .shadow
                .set_drawn(Some((&shadow_frame, level.indices.clone())));
        }
        let (device, queue, bytes) = (&self.device, &self.queue, target.texel_bytes());
        let texels = match (readback, read) {
            (Some(texture), Some(Readback::StraightSrgb8)) => {
                // The row conversion reads single floats.
                debug_assert_eq!(target, Target::Linear32);
                Some(read_texels_with(
                    device,
                    queue,
                    texture,
                    bytes,
                    4,
                    straight_srgb8_row,
                )?)
            }
            (Some(texture), Some(Readback::Stored)) => Some(read_texels(device, queue, texture, bytes)?),
            _ => None,
        };
        Ok((checked.info, texels))
    }
}
