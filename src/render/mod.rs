//! Offscreen wgpu rendering (feature `render`).
//!
//! [`Renderer`] owns the device. It picks an adapter headless: a hardware GPU first, a CPU adapter
//! (Mesa's lavapipe or llvmpipe) when asked for or when no GPU exists, and reports which one it got.
//! Passes live one per file with their WGSL beside them; today there is the smoke pass that proves
//! the device works end to end.

mod readback;
mod smoke;

pub use smoke::SMOKE_COLOR;

use crate::error::{PeltError, Result};

/// How to choose the adapter.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum AdapterChoice {
    /// A hardware GPU when there is one, otherwise a CPU adapter.
    #[default]
    PreferHardware,
    /// Only a CPU adapter (deterministic results for golden-image tests).
    Cpu,
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
    device: wgpu::Device,
    queue: wgpu::Queue,
    adapter: AdapterReport,
}

impl Renderer {
    /// Opens a device headless.
    ///
    /// # Errors
    /// [`PeltError::Render`] when no adapter (of the requested kind) exists or the device cannot be
    /// created; the message lists what was tried.
    pub fn new(choice: AdapterChoice) -> Result<Self> {
        pollster::block_on(Self::open(choice))
    }

    async fn open(choice: AdapterChoice) -> Result<Self> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle().with_env());
        let request = |force_fallback_adapter| {
            instance.request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter,
                compatible_surface: None,
                apply_limit_buckets: false,
            })
        };
        let adapter = match choice {
            AdapterChoice::Cpu => request(true).await,
            AdapterChoice::PreferHardware => match request(false).await {
                Ok(adapter) => Ok(adapter),
                Err(_) => request(true).await,
            },
        }
        .map_err(|e| {
            PeltError::Render(format!(
                "no {} adapter found ({e}); install Mesa's Vulkan drivers (lavapipe) for a CPU adapter",
                if choice == AdapterChoice::Cpu {
                    "CPU"
                } else {
                    "GPU or CPU"
                }
            ))
        })?;
        let info = adapter.get_info();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("pelt"),
                required_features: wgpu::Features::empty(),
                required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
                experimental_features: wgpu::ExperimentalFeatures::disabled(),
                memory_hints: wgpu::MemoryHints::Performance,
                trace: wgpu::Trace::Off,
            })
            .await
            .map_err(|e| PeltError::Render(format!("cannot open a device on {}: {e}", info.name)))?;
        Ok(Renderer {
            device,
            queue,
            adapter: AdapterReport {
                name: info.name,
                backend: format!("{:?}", info.backend),
                device_type: format!("{:?}", info.device_type),
            },
        })
    }

    /// The adapter in use.
    pub fn adapter(&self) -> &AdapterReport {
        &self.adapter
    }
}
