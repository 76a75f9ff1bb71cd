//! A window's surface for an interactive viewer: [`Renderer::for_window`] opens the device on an
//! adapter that can present to the window, and [`WindowSurface::draw`] renders a frame into the
//! surface's next texture with [`Renderer::render_to_texture`] (the same passes as offscreen,
//! Lengyel et al. 2001, §2.3) and presents it.
//!
//! The window itself comes from the caller (any windowing library with `raw-window-handle` 0.6
//! handles), so the library does not depend on one.

use std::time::Instant;

use super::camera::Camera;
use super::image::RgbaImage;
use super::lighting::Lighting;
use super::lod::FrameInfo;
use super::pass::Target;
use super::scene::FurScene;
use super::settings::RenderSettings;
use super::{AdapterChoice, Renderer, scoped};
use pelt_core::error::{PeltError, Result};

/// The window's display connection (e.g. winit's `OwnedDisplayHandle`).
pub type DisplayHandle = Box<dyn wgpu::wgt::WgpuHasDisplayHandle>;

/// A window's swap chain, drawn by the [`Renderer`] that [`Renderer::for_window`] returned with
/// it.
pub struct WindowSurface {
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
}

/// A frame [`WindowSurface::draw`] presented.
#[derive(Debug, Clone)]
pub struct PresentedFrame {
    /// What was drawn (shells, LOD level).
    pub info: FrameInfo,
    /// Seconds from the start of the render call until the GPU had finished it (not counting
    /// the wait for presentation).
    pub seconds: f64,
    /// The frame as presented, when asked for.
    pub image: Option<RgbaImage>,
}

impl Renderer {
    /// Opens a device on an adapter that can present to `window` (chosen as [`Renderer::new`]
    /// does) and returns it with the window's surface, configured to `width × height` pixels.
    ///
    /// `display` is the window system connection the window belongs to; `window` anything wgpu
    /// makes a surface from (e.g. an `Arc` of a winit window), kept alive by the surface.
    ///
    /// # Errors
    /// [`PeltError::Render`] when the surface cannot be created, no adapter of the requested kind
    /// can present to it, the device cannot be opened, or the surface offers no usable format;
    /// [`PeltError::InvalidParameter`] for a zero or oversized `width` / `height`.
    pub fn for_window(
        choice: AdapterChoice,
        display: DisplayHandle,
        window: impl Into<wgpu::SurfaceTarget<'static>>,
        width: u32,
        height: u32,
    ) -> Result<(Renderer, WindowSurface)> {
        let (renderer, surface) = pollster::block_on(Self::open(choice, Some((display, window.into()))))?;
        let surface = surface.ok_or_else(|| PeltError::Render("no surface was created".into()))?;
        let config = renderer.surface_config(&surface, width, height)?;
        let mut window = WindowSurface { surface, config };
        window.configure(&renderer)?;
        Ok((renderer, window))
    }

    /// The configuration of `surface` at `width × height`: an 8-bit sRGB-capable format (drawn
    /// through its sRGB view), vsync, opaque alpha where offered, `COPY_SRC` where offered (for
    /// screenshots).
    fn surface_config(
        &self,
        surface: &wgpu::Surface<'_>,
        width: u32,
        height: u32,
    ) -> Result<wgpu::SurfaceConfiguration> {
        let caps = surface.get_capabilities(&self.adapter_handle);
        let rank = |format: &wgpu::TextureFormat| match (Target::for_format(*format), format.is_srgb()) {
            (Some(Target::Bgra8Srgb | Target::Srgb8), true) => Some(0),
            (Some(Target::Bgra8Srgb | Target::Srgb8), false) => Some(1),
            _ => None,
        };
        let format = caps
            .formats
            .iter()
            .filter_map(|f| rank(f).map(|r| (r, *f)))
            .min_by_key(|(r, _)| *r)
            .map(|(_, f)| f)
            .ok_or_else(|| {
                PeltError::Render(format!(
                    "the window offers no 8-bit RGBA or BGRA format (it offers {:?})",
                    caps.formats
                ))
            })?;
        let alpha_mode = preferred(
            &caps.alpha_modes,
            wgpu::CompositeAlphaMode::Opaque,
            wgpu::CompositeAlphaMode::Auto,
        );
        let present_mode = preferred(
            &caps.present_modes,
            wgpu::PresentMode::Fifo,
            wgpu::PresentMode::AutoVsync,
        );
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | (caps.usages & wgpu::TextureUsages::COPY_SRC);
        let config = wgpu::SurfaceConfiguration {
            usage,
            format,
            color_space: wgpu::SurfaceColorSpace::Auto,
            width,
            height,
            desired_maximum_frame_latency: 2,
            present_mode,
            alpha_mode,
            // A non-sRGB format is drawn through its sRGB view (blending in linear light).
            view_formats: if format.is_srgb() {
                Vec::new()
            } else {
                vec![format.add_srgb_suffix()]
            },
        };
        check_size(&config, self.device.limits().max_texture_dimension_2d)?;
        Ok(config)
    }
}

/// wgpu panics on a zero-sized or oversized surface, so sizes are checked first.
fn check_size(config: &wgpu::SurfaceConfiguration, max_side: u32) -> Result<()> {
    for (name, side) in [("width", config.width), ("height", config.height)] {
        if !(1..=max_side).contains(&side) {
            return Err(PeltError::parameter(
                name,
                format!("must be in [1, {max_side}], got {side}"),
            ));
        }
    }
    Ok(())
}

impl WindowSurface {
    fn configure(&mut self, renderer: &Renderer) -> Result<()> {
        scoped(&renderer.device, "configuring the window surface", || {
            self.surface.configure(&renderer.device, &self.config);
        })
    }

    /// The surface's size in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    /// The surface's texture format.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.config.format
    }

    /// Follows the window to a new size.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] for a zero or oversized side (skip drawing while a window
    /// is minimized); [`PeltError::Render`] when the device rejects the configuration.
    pub fn resize(&mut self, renderer: &Renderer, width: u32, height: u32) -> Result<()> {
        let mut config = self.config.clone();
        config.width = width;
        config.height = height;
        check_size(&config, renderer.device.limits().max_texture_dimension_2d)?;
        self.config = config;
        self.configure(renderer)
    }

    /// Draws a frame into the surface's next texture and presents it. `camera` must have the
    /// surface's size. With `capture`, the frame is read back before it is presented (or, where
    /// the surface cannot be read, the same inputs are rendered offscreen).
    ///
    /// Returns `None` when the window had no texture to draw into this time (occluded, timed
    /// out, or outdated and now reconfigured): draw again on the next redraw.
    ///
    /// # Errors
    /// As [`Renderer::render_to_texture`]; [`PeltError::Render`] when the surface is lost.
    pub fn draw(
        &mut self,
        renderer: &Renderer,
        scene: &FurScene,
        camera: &Camera,
        lighting: &Lighting,
        settings: &RenderSettings,
        capture: bool,
    ) -> Result<Option<PresentedFrame>> {
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(frame) => frame,
            // Drawn as it is; configured again for the next frame.
            wgpu::CurrentSurfaceTexture::Suboptimal(frame) => {
                self.configure(renderer)?;
                frame
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => return Ok(None),
            wgpu::CurrentSurfaceTexture::Outdated => {
                self.configure(renderer)?;
                return Ok(None);
            }
            wgpu::CurrentSurfaceTexture::Lost => {
                return Err(PeltError::Render("the window's surface was lost".into()));
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                return Err(PeltError::Render(
                    "acquiring the window's next texture failed validation".into(),
                ));
            }
        };
        let start = Instant::now();
        let info = renderer.render_to_texture(scene, camera, lighting, settings, &frame.texture)?;
        renderer.wait()?;
        let seconds = start.elapsed().as_secs_f64();
        let image = match capture {
            false => None,
            true if frame.texture.usage().contains(wgpu::TextureUsages::COPY_SRC) => {
                Some(renderer.read_texture(&frame.texture)?)
            }
            true => Some(renderer.render(scene, camera, lighting, settings)?),
        };
        scoped(&renderer.device, "presenting a frame", || {
            renderer.queue.present(frame)
        })?;
        Ok(Some(PresentedFrame { info, seconds, image }))
    }
}

/// `wanted` when the surface offers it, else the first mode it offers, else `fallback`.
fn preferred<T: Copy + PartialEq>(offered: &[T], wanted: T, fallback: T) -> T {
    if offered.contains(&wanted) {
        wanted
    } else {
        offered.first().copied().unwrap_or(fallback)
    }
}
