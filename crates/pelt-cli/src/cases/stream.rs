//! Frames drawn back to back into a texture, as a viewport or a game draws them: no readback,
//! one wait after a run of frames, so the CPU's encoding of one frame overlaps the GPU's drawing
//! of the last. The seconds per frame are what a window's frame rate is made of; the
//! `render.frame*` cases also count reading the picture back and converting it.

use std::time::Instant;

use super::time_fallible;
use pelt_core::error::Result;
use pelt_render::{Camera, FurScene, Lighting, RenderSettings, Renderer};

/// Seconds a timed run lasts at least, so that its one wait at the end and its first frame's
/// start are small against it; a slow frame (a CPU adapter's) still runs twice.
const RUN_SECONDS: f64 = 0.25;

/// The most frames one timed run draws (a GPU's fast frames).
const MAX_FRAMES: u32 = 64;

/// Frames drawn back to back: their median seconds each (what sets a window's frame rate), the
/// CPU's share of that (encoding and submitting, which the GPU's drawing overlaps) and the peak
/// heap of the warm-up.
pub(super) struct Streamed {
    pub seconds: f64,
    pub cpu_seconds: f64,
    pub peak: Option<usize>,
}

impl Streamed {
    /// The timing for [`super::CaseResult::timed`].
    pub fn timing(&self) -> (f64, Option<usize>) {
        (self.seconds, self.peak)
    }

    /// How the frame's time splits, for a case's description.
    pub fn split(&self) -> String {
        format!(
            "frames drawn into a texture back to back (no readback), CPU {:.2} ms a frame",
            self.cpu_seconds * 1e3
        )
    }
}

/// Times frames drawn into one 8-bit sRGB texture of the camera's size: `reps` runs (as many
/// frames each as fill [`RUN_SECONDS`], 2 to [`MAX_FRAMES`], sized by a first frame) after a
/// warm-up run; the CPU's share from one more run that times only the submissions.
///
/// # Errors
/// Whatever [`Renderer::render_to_texture`] or [`Renderer::wait`] returns.
pub(super) fn streamed(
    renderer: &Renderer,
    scene: &FurScene,
    camera: &Camera,
    lighting: &Lighting,
    settings: &RenderSettings,
    reps: usize,
) -> Result<Streamed> {
    let texture = renderer.device().create_texture(&wgpu::TextureDescriptor {
        label: Some("streamed frames"),
        size: wgpu::Extent3d {
            width: camera.width,
            height: camera.height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    let draw = || renderer.render_to_texture(scene, camera, lighting, settings, &texture);
    let start = Instant::now();
    draw()?;
    renderer.wait()?;
    let first = start.elapsed().as_secs_f64();
    let frames = ((RUN_SECONDS / first).ceil() as u32).clamp(2, MAX_FRAMES);
    let (seconds, peak) = time_fallible(reps, || {
        for _ in 0..frames {
            draw()?;
        }
        renderer.wait()
    })?;
    let mut cpu_seconds = 0.0;
    for _ in 0..frames {
        let start = Instant::now();
        draw()?;
        cpu_seconds += start.elapsed().as_secs_f64();
    }
    renderer.wait()?;
    Ok(Streamed {
        seconds: seconds / f64::from(frames),
        cpu_seconds: cpu_seconds / f64::from(frames),
        peak,
    })
}
