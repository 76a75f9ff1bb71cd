//! Pelt's wgpu preview renderer (the crate `pelt-render`, over `pelt-core`; `pelt::render` in the
//! `pelt` package with its feature `render`).
//!
//! [`Renderer`] owns the device. It picks an adapter headless: a hardware GPU first, a CPU adapter
//! (Mesa's lavapipe or llvmpipe) when asked for or when no GPU exists, and reports which one it got.
//! Passes live one per file with their WGSL beside them.
//!
//! The fur renderer follows Lengyel et al. 2001, §2.3–§2.4 and §3: a [`FurScene`] (the skin split
//! at patch seams, fin quads and mesh levels that `pelt_core::scene` prepares, the hair volume's
//! textures, optionally PRT transfer textures) is uploaded once; [`Renderer::render`] draws the
//! opaque skin, the fins near the silhouette and the shells (instanced, or one marched or
//! virtual-plane hull) offscreen and returns an [`RgbaImage`] ([`Renderer::render_linear`] a
//! [`LinearImage`]); [`Renderer::render_to_texture`] draws the same passes into a caller's
//! texture, and [`WindowSurface`] into a window (`pelt view`). Guard hairs
//! ([`FurScene::set_guard_hairs`]) are drawn as strands among the shells (hybrid paper §3;
//! `guard_strands.rs`, `strands.rs`, [`StrandOrder`]). Lighting is Kajiya–Kay or precomputed
//! radiance transfer (prt-shell-fur §2.4). The smoke pass proves the device works end to end.
//!
//! Files: `camera.rs`, `lighting.rs`, `settings.rs` (the per-frame inputs, validated); `lod.rs`
//! (the shell count and cross-fade per frame); `textures.rs` (volume upload, premultiplied),
//! `upload_peak.rs` (the memory an upload needs), `transfer.rs` (PRT textures); `scene.rs`;
//! `layouts.rs` (the bind group and pipeline layouts scenes and passes share), `pass.rs` (what a
//! pass declares and the pipeline recipe) and one file per pass owning its shader, pipelines and
//! draw call: `skin.rs`, `fins.rs`, `shells.rs` (with the one-hull methods' shaders of
//! `marched.rs` and `planes.rs`, which share `march.wgsl`), `strands.rs`; `shaders.rs` composes
//! each pass's WGSL, one source for both lighting models, with the modules it imports:
//! `common.wgsl`, `surface.wgsl` and the model's, which the shader def `PRT` picks
//! (`light_model.wgsl` states what each provides: `lighting.wgsl`, `surface_kk.wgsl`,
//! `fin_kk.wgsl`, `strand_kk.wgsl` for Kajiya–Kay; `prt.wgsl`, `surface_prt.wgsl`,
//! `fin_prt.wgsl`, `strand_prt.wgsl` for PRT); `pipelines.rs` (the passes' pipelines per lighting
//! model and target, built on first use);
//! `prt_light.rs` (world SH) and `prt_rotate.rs` (the rotation compute pass); `frame.rs` (one
//! frame) with `frame_uniforms.rs`, `image.rs` (the images returned), `occluders.rs` (another
//! picture's depth starting a frame's, for compositing into it: [`Renderer::render_over`]),
//! `shadow_map.rs` (the body's shadow on its own fur),
//! `readback.rs`, `texture_target.rs` (a caller's texture) and `window.rs` (a window's surface).

mod camera;
mod color_store;
mod fins;
mod frame;
mod frame_uniforms;
mod full_frame;
mod guard_strands;
mod image;
mod layouts;
mod lighting;
mod lod;
mod marched;
mod occluders;
mod over_mips;
mod pass;
mod pipelines;
mod planes;
mod prt_light;
mod prt_rotate;
mod readback;
mod remade_levels;
mod resolve;
mod scene;
mod settings;
mod shaders;
mod shadow_map;
mod shells;
mod shown_heights;
mod skin;
mod smoke;
mod stand_heights;
mod strands;
mod tangent_spread;
mod texture_target;
mod textures;
mod transfer;
mod upload_peak;
mod window;

#[cfg(test)]
mod prt_tests;
#[cfg(test)]
mod tests;

pub use camera::{Camera, MAX_IMAGE_SIDE};
pub use image::{LinearImage, RgbaImage};
pub use lighting::{
    KajiyaKay, LightModel, Lighting, MAX_LIGHT_RADIUS, MAX_POWER, MAX_RADIANCE, Prt, check_environment,
};
pub use lod::FrameInfo;
pub use occluders::Occluders;
pub use scene::{FurScene, UploadStats};
pub use settings::{
    DEFAULT_STRAND_BANDS, MAX_PLANE_LOOP_LIMIT, MAX_SHELLS_PER_PIXEL, MAX_STRAND_BANDS, MAX_STRAND_PIXELS,
    RenderDefaults, RenderSettings, ShellMethod, StrandOrder,
};
pub use smoke::SMOKE_COLOR;
pub use upload_peak::{scene_upload_peak_bytes, transfer_upload_peak_bytes};
pub use window::{DisplayHandle, PresentedFrame, WindowSurface};

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, OnceLock};

use pelt_core::error::{PeltError, Result};
use pipelines::FurPipelines;

/// How to choose the adapter.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum AdapterChoice {
    /// A hardware GPU when there is one, otherwise a CPU adapter.
    #[default]
    PreferHardware,
    /// Only a CPU adapter (deterministic results for golden-image tests).
    Cpu,
    /// Only a hardware GPU; an error when there is none.
    Gpu,
}

/// What adapter the renderer runs on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AdapterReport {
    /// Driver's name for the device, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub name: String,
    /// Backend, e.g. `Vulkan`.
    pub backend: String,
    /// Device type, e.g. `Cpu` or `DiscreteGpu`.
    pub device_type: String,
}

/// A wgpu device and queue for offscreen rendering.
pub struct Renderer {
    /// Kept to ask a window's surface what it supports.
    adapter_handle: wgpu::Adapter,
    device: wgpu::Device,
    queue: wgpu::Queue,
    adapter: AdapterReport,
    /// Whether the adapter is a CPU rasterizer.
    cpu: bool,
    /// Whether offscreen frames are drawn into single floats ([`pass::Target::Linear32`]): on a
    /// CPU adapter that blends them.
    exact_targets: bool,
    /// Tells scenes of this renderer from others' (wgpu objects of two devices must not meet).
    id: u64,
    /// The fur pipelines, built on first use.
    fur: OnceLock<FurPipelines>,
    /// Render targets of the last frame's size; the lock also serializes frames, which share
    /// each scene's uniform buffer.
    targets: Mutex<Option<frame::Targets>>,
}

/// Source of [`Renderer`] ids.
static NEXT_RENDERER_ID: AtomicU64 = AtomicU64::new(0);

/// Runs `work` inside validation and out-of-memory error scopes, so a device error becomes a
/// [`PeltError::Render`] naming `what` instead of wgpu's default panic, and the device survives.
fn scoped<T>(device: &wgpu::Device, what: &str, work: impl FnOnce() -> T) -> Result<T> {
    let memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let value = work();
    let invalid = pollster::block_on(validation.pop());
    let out_of_memory = pollster::block_on(memory.pop());
    match invalid.or(out_of_memory) {
        None => Ok(value),
        Some(e) => Err(PeltError::Render(format!("{what} failed: {e}"))),
    }
}

/// The downlevel defaults, raised to the adapter's own limits where Pelt's data can grow: image
/// and texture sides, texture array layers (PRT keeps every transfer texture in one array),
/// storage buffer sizes (the rotated PRT lighting).
fn required_limits(adapter: &wgpu::Limits) -> wgpu::Limits {
    wgpu::Limits {
        max_texture_array_layers: adapter.max_texture_array_layers,
        max_storage_buffer_binding_size: adapter.max_storage_buffer_binding_size,
        max_buffer_size: adapter.max_buffer_size,
        // PRT's strand pass reads seven storage buffers in its vertex stage (the downlevel
        // default is four; WebGPU and every desktop API allow eight).
        max_storage_buffers_per_shader_stage: adapter.max_storage_buffers_per_shader_stage.min(8),
        ..wgpu::Limits::downlevel_defaults().using_resolution(adapter.clone())
    }
}

impl Renderer {
    /// Opens a device headless.
    ///
    /// # Errors
    /// [`PeltError::Render`] when no adapter (of the requested kind) exists or the device cannot be
    /// created; the message lists what was tried.
    pub fn new(choice: AdapterChoice) -> Result<Self> {
        pollster::block_on(Self::open(choice, None)).map(|(renderer, _)| renderer)
    }

    /// Opens the device, and with `window` (its display connection and itself) the window's
    /// surface on the same instance, choosing only adapters that can present to it.
    async fn open(
        choice: AdapterChoice,
        window: Option<(window::DisplayHandle, wgpu::SurfaceTarget<'static>)>,
    ) -> Result<(Self, Option<wgpu::Surface<'static>>)> {
        let (descriptor, target) = match window {
            None => (wgpu::InstanceDescriptor::new_without_display_handle(), None),
            Some((display, target)) => (
                wgpu::InstanceDescriptor::new_with_display_handle(display),
                Some(target),
            ),
        };
        let instance = wgpu::Instance::new(descriptor.with_env());
        let surface = match target {
            Some(target) => Some(
                instance
                    .create_surface(target)
                    .map_err(|e| PeltError::Render(format!("cannot draw into the window: {e}")))?,
            ),
            None => None,
        };
        let request = |force_fallback_adapter| {
            instance.request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter,
                compatible_surface: surface.as_ref(),
                apply_limit_buckets: false,
            })
        };
        let adapter = match choice {
            AdapterChoice::Cpu => request(true).await,
            AdapterChoice::Gpu => request(false).await,
            AdapterChoice::PreferHardware => match request(false).await {
                Ok(adapter) => Ok(adapter),
                Err(_) => request(true).await,
            },
        }
        .map_err(|e| {
            let presenting = if surface.is_some() {
                " that can draw into the window"
            } else {
                ""
            };
            PeltError::Render(match choice {
                AdapterChoice::Cpu => format!(
                    "no CPU adapter{presenting} found ({e}); install Mesa's Vulkan drivers (lavapipe)"
                ),
                AdapterChoice::Gpu => format!("no GPU adapter{presenting} found ({e})"),
                AdapterChoice::PreferHardware => format!(
                    "no GPU or CPU adapter{presenting} found ({e}); install Mesa's Vulkan drivers (lavapipe) for a CPU adapter"
                ),
            })
        })?;
        let info = adapter.get_info();
        if choice == AdapterChoice::Gpu && info.device_type == wgpu::DeviceType::Cpu {
            return Err(PeltError::Render(format!(
                "no GPU adapter found (only the CPU adapter {})",
                info.name
            )));
        }
        let cpu = info.device_type == wgpu::DeviceType::Cpu;
        let exact_targets = cpu && adapter.features().contains(wgpu::Features::FLOAT32_BLENDABLE);
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("pelt"),
                required_features: if exact_targets {
                    wgpu::Features::FLOAT32_BLENDABLE
                } else {
                    wgpu::Features::empty()
                },
                required_limits: required_limits(&adapter.limits()),
                experimental_features: wgpu::ExperimentalFeatures::disabled(),
                memory_hints: wgpu::MemoryHints::Performance,
                trace: wgpu::Trace::Off,
            })
            .await
            .map_err(|e| PeltError::Render(format!("cannot open a device on {}: {e}", info.name)))?;
        let renderer = Renderer {
            adapter_handle: adapter,
            device,
            queue,
            adapter: AdapterReport {
                name: info.name,
                backend: format!("{:?}", info.backend),
                device_type: format!("{:?}", info.device_type),
            },
            cpu,
            exact_targets,
            id: NEXT_RENDERER_ID.fetch_add(1, Ordering::Relaxed),
            fur: OnceLock::new(),
            targets: Mutex::new(None),
        };
        Ok((renderer, surface))
    }

    /// The adapter in use.
    pub fn adapter(&self) -> &AdapterReport {
        &self.adapter
    }

    /// Whether the adapter is a CPU (software) rasterizer.
    pub fn is_cpu(&self) -> bool {
        self.cpu
    }

    /// How this renderer's device stores color textures.
    pub(crate) fn color_store(&self) -> color_store::ColorStore {
        color_store::ColorStore::for_adapter(self.cpu)
    }

    /// How this renderer draws shells asked for with `method` ([`ShellMethod::Auto`] resolved).
    pub fn shell_method(&self, method: ShellMethod) -> ShellMethod {
        method.resolve()
    }

    /// The device, to make textures for [`Renderer::render_to_texture`].
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The fur pipelines, built on first use (a race builds them twice and keeps one).
    fn fur_pipelines(&self) -> Result<&FurPipelines> {
        if let Some(p) = self.fur.get() {
            return Ok(p);
        }
        let built = FurPipelines::new(&self.device)?;
        Ok(self.fur.get_or_init(|| built))
    }

    /// The fur layouts and samplers that scenes bind against.
    fn fur_layouts(&self) -> Result<&layouts::FurLayouts> {
        Ok(&self.fur_pipelines()?.layouts)
    }
}
