//! Drawing into a caller's texture — a window's surface texture, or a texture of an application
//! that composites Pelt's fur into its own frame — with the same passes as the offscreen
//! frame (Lengyel et al. 2001, §2.3), and reading such a texture back.
//!
//! 8-bit textures are drawn through their sRGB view so blending happens in linear light, as
//! offscreen; the texture must therefore be sRGB itself or list its sRGB variant among its view
//! formats (a surface configured by [`super::WindowSurface`] does).

use super::camera::Camera;
use super::frame::Output;
use super::image::RgbaImage;
use super::lighting::Lighting;
use super::lod::FrameInfo;
use super::pass::Target;
use super::readback::read_texels;
use super::scene::FurScene;
use super::settings::RenderSettings;
use super::{Renderer, scoped};
use pelt_core::error::{PeltError, Result};

/// Checks that `texture` is a single 2D image, `usage` allowed, and returns the target of its
/// format.
fn checked_target(texture: &wgpu::Texture, usage: wgpu::TextureUsages, formats: &str) -> Result<Target> {
    let format = texture.format();
    let target = Target::for_format(format).ok_or_else(|| {
        PeltError::parameter("texture", format!("has format {format:?}; expected {formats}"))
    })?;
    if texture.dimension() != wgpu::TextureDimension::D2
        || texture.depth_or_array_layers() != 1
        || texture.sample_count() != 1
    {
        return Err(PeltError::parameter(
            "texture",
            "must be a single-sampled 2D texture with one layer",
        ));
    }
    if !texture.usage().contains(usage) {
        return Err(PeltError::parameter(
            "texture",
            format!("lacks the usage {usage:?}"),
        ));
    }
    Ok(target)
}

impl Renderer {
    /// Draws `scene` into `texture` like [`Renderer::render`] (skin, fins, shells; the
    /// background cleared first) and returns what it drew. The texture holds premultiplied color
    /// afterwards, blended in its own format (on a CPU adapter, blended in single floats
    /// offscreen and copied into it once, as [`Renderer::render`] encodes its frame once). The
    /// work is submitted, not waited for.
    ///
    /// `texture` must come from this renderer's device (a window's surface configured with
    /// [`super::WindowSurface`], or [`Renderer::device`]), be 2D with one layer and one sample,
    /// have `RENDER_ATTACHMENT` usage and the camera's size, and have format `Rgba8UnormSrgb`,
    /// `Bgra8UnormSrgb`, `Rgba16Float`, or `Rgba8Unorm` / `Bgra8Unorm` with the sRGB variant among
    /// its view formats.
    ///
    /// # Errors
    /// As [`Renderer::render`], and [`PeltError::InvalidParameter`] naming `texture` when its
    /// format, usage, shape or size does not fit.
    pub fn render_to_texture(
        &self,
        scene: &FurScene,
        camera: &Camera,
        lighting: &Lighting,
        settings: &RenderSettings,
        texture: &wgpu::Texture,
    ) -> Result<FrameInfo> {
        let target = checked_target(
            texture,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
            "Rgba8UnormSrgb, Bgra8UnormSrgb, Rgba8Unorm, Bgra8Unorm or Rgba16Float",
        )?;
        let size = (texture.width(), texture.height());
        if size != (camera.width, camera.height) {
            return Err(PeltError::parameter(
                "texture",
                format!(
                    "is {}x{}, the camera {}x{}",
                    size.0, size.1, camera.width, camera.height
                ),
            ));
        }
        let view = scoped(&self.device, "viewing the target texture", || {
            texture.create_view(&wgpu::TextureViewDescriptor {
                label: Some("fur target"),
                format: Some(target.format()),
                ..Default::default()
            })
        })?;
        // A CPU adapter blends exactly only in single floats (see `resolve.rs`).
        let (drawn, output) = match self.exact_targets {
            true => (Target::Linear32, Output::Resolved(&view, target)),
            false => (target, Output::Texture(&view)),
        };
        let (info, _) = self.draw(scene, camera, lighting, settings, drawn, output, None)?;
        Ok(info)
    }

    /// Reads an 8-bit RGBA or BGRA texture of this renderer's device (with `COPY_SRC` usage)
    /// holding premultiplied color, e.g. after [`Renderer::render_to_texture`], as an
    /// [`RgbaImage`] (sRGB, straight alpha). Waits for the GPU.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `texture` when its format, usage or shape does not
    /// fit; [`PeltError::Render`] when the device fails.
    pub fn read_texture(&self, texture: &wgpu::Texture) -> Result<RgbaImage> {
        let target = checked_target(
            texture,
            wgpu::TextureUsages::COPY_SRC,
            "Rgba8UnormSrgb, Bgra8UnormSrgb, Rgba8Unorm or Bgra8Unorm",
        )?;
        if target == Target::Linear16 {
            return Err(PeltError::parameter(
                "texture",
                "is Rgba16Float; only 8-bit textures are read back",
            ));
        }
        let mut texels = scoped(&self.device, "reading a texture back", || {
            read_texels(&self.device, &self.queue, texture, 4)
        })??;
        if target == Target::Bgra8Srgb {
            for texel in texels.chunks_exact_mut(4) {
                texel.swap(0, 2);
            }
        }
        Ok(RgbaImage::from_premultiplied(
            texture.width(),
            texture.height(),
            texels,
        ))
    }

    /// Waits until the GPU has finished everything submitted so far (to time a frame drawn with
    /// [`Renderer::render_to_texture`]).
    ///
    /// # Errors
    /// [`PeltError::Render`] when the device is lost or the wait fails.
    pub fn wait(&self) -> Result<()> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| PeltError::Render(format!("waiting for the GPU failed: {e}")))
    }
}
