//! Pass (c), virtual planes ([`super::ShellMethod::VirtualPlanes`], raycast-fur-virtual-planes
//! §3): the hull of the marched shells, whose fragments trace the view ray through the planes'
//! slices (`planes.wgsl`) instead of the shell layers; same state as the marched pass, owned and drawn
//! by [`super::shells::ShellsPass`]. Also the slices' upload: one texture array of `2N` layers, the
//! slices premultiplied with their mip chains, as the fin texture is.

use super::color_store::ColorStore;
use super::shaders::PassShader;
use super::textures::upload_with_mips;
use pelt_core::error::Result;
use pelt_core::volume::PlaneSlices;

/// The virtual planes' hull shader, one source for both lighting models.
pub(super) static SHADER: PassShader = PassShader::new("planes.wgsl", include_str!("planes.wgsl"));

/// The uploaded slices.
pub(super) struct ScenePlanes {
    pub view: wgpu::TextureView,
    /// Planes per family and their lean, for the frame's uniforms.
    pub count: u32,
    pub tilt: [f32; 2],
    /// Bytes written to the GPU.
    pub bytes: u64,
}

/// Uploads checked slices (`pelt_core::volume::slices::check_slices`), stored as `store` says.
///
/// # Errors
/// [`pelt_core::PeltError::InvalidParameter`] when a mip chain cannot be built (not for checked
/// slices).
pub(super) fn upload_planes(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    slices: &PlaneSlices,
    store: ColorStore,
) -> Result<ScenePlanes> {
    let [width, height] = slices.size;
    let (view, bytes) = upload_with_mips(
        device,
        queue,
        "plane slices",
        [width, height, 2 * slices.planes],
        &slices.rgba,
        wgpu::TextureViewDimension::D2Array,
        store,
    )?;
    Ok(ScenePlanes {
        view,
        count: slices.planes as u32,
        tilt: slices.tilt,
        bytes,
    })
}
