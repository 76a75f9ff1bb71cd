//! One frame: the three fur passes in Lengyel et al. 2001's order (§2.3) — skin, fins, shells —
//! in a single render pass into an offscreen sRGB target, then read back.

use super::camera::Camera;
use super::frame_uniforms::{FrameUniforms, SceneFrame};
use super::image::RgbaImage;
use super::lighting::Lighting;
use super::pipelines::{COLOR_FORMAT, DEPTH_FORMAT};
use super::readback::read_rgba8;
use super::scene::FurScene;
use super::settings::RenderSettings;
use super::{Renderer, fins, scoped, shells, skin};
use crate::error::{PeltError, Result};

/// Color and depth targets of one size, kept between frames.
pub(super) struct Targets {
    size: (u32, u32),
    color: wgpu::Texture,
    color_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
}

impl Targets {
    fn new(device: &wgpu::Device, (width, height): (u32, u32)) -> Self {
        let target = |label, format, usage| {
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
        };
        let color = target(
            "fur color",
            COLOR_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let depth = target("fur depth", DEPTH_FORMAT, wgpu::TextureUsages::RENDER_ATTACHMENT);
        Targets {
            size: (width, height),
            color_view: color.create_view(&wgpu::TextureViewDescriptor::default()),
            depth_view: depth.create_view(&wgpu::TextureViewDescriptor::default()),
            color,
        }
    }
}

impl Renderer {
    /// Renders `scene` offscreen: the opaque skin (writing depth), the fins near the silhouette
    /// (if `settings.fins`), then the shells inner to outer in one instanced draw.
    ///
    /// Renders are serialized per renderer; the result depends only on the inputs (and the
    /// adapter).
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming the bad camera, lighting or settings field, or
    /// `scene` when it was uploaded by another renderer; [`PeltError::Render`] when the device
    /// fails. The renderer stays usable after an error.
    pub fn render(
        &self,
        scene: &FurScene,
        camera: &Camera,
        lighting: &Lighting,
        settings: &RenderSettings,
    ) -> Result<RgbaImage> {
        if scene.renderer_id() != self.id {
            return Err(PeltError::parameter("scene", "was uploaded by another Renderer"));
        }
        let camera_frame = camera.frame(self.device.limits().max_texture_dimension_2d)?;
        let light = lighting.frame()?;
        let shell_count = settings.shells_to_draw(scene.layers)?;
        let pipelines = self.fur_pipelines()?;
        let uniforms = FrameUniforms::new(
            &camera_frame,
            &light,
            settings,
            &SceneFrame {
                shells: shell_count,
                layers: scene.layers,
                layer_spacing: scene.layer_spacing,
            },
        );
        // A panic elsewhere cannot leave the cached targets half-made, so a poisoned lock is fine.
        let mut cached = self
            .targets
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let size = (camera.width, camera.height);
        let targets = scoped(&self.device, "creating the render targets", || {
            match cached.take() {
                Some(t) if t.size == size => t,
                _ => Targets::new(&self.device, size),
            }
        })?;
        let targets = cached.insert(targets);
        let [r, g, b, a] = settings.background.map(f64::from);
        scoped(&self.device, "rendering a frame", || {
            self.queue
                .write_buffer(&scene.uniforms, 0, bytemuck::bytes_of(&uniforms));
            let mut encoder = self
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("fur") });
            {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("fur"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &targets.color_view,
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
                pass.set_bind_group(0, &scene.bind_group, &[]);
                skin::draw(&mut pass, pipelines, scene);
                if settings.fins {
                    fins::draw(&mut pass, pipelines, scene);
                }
                shells::draw(&mut pass, pipelines, scene, shell_count);
            }
            self.queue.submit([encoder.finish()]);
        })?;
        let pixels = read_rgba8(&self.device, &self.queue, &targets.color)?;
        Ok(RgbaImage::from_premultiplied(camera.width, camera.height, pixels))
    }
}
