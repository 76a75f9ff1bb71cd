//! Pass (c), virtual planes ([`super::ShellMethod::VirtualPlanes`], raycast-fur-virtual-planes
//! §3): the hull of the marched shells, whose fragments trace the view ray through the planes'
//! slices (`planes.wgsl`) instead of the shell layers; same state as the marched pass, drawn by
//! [`super::shells::draw`]. Also the slices' upload: one texture array of `2N` layers, the
//! slices premultiplied with their mip chains, as the fin texture is.

use super::marched;
use super::pass::{Model, PassState};
use super::textures::upload_with_mips;
use pelt_core::error::Result;
use pelt_core::volume::PlaneSlices;

const KAJIYA_KAY: &str = concat!(
    include_str!("common.wgsl"),
    include_str!("lighting.wgsl"),
    include_str!("surface.wgsl"),
    include_str!("surface_kk.wgsl"),
    include_str!("march.wgsl"),
    include_str!("planes.wgsl")
);
const PRT: &str = concat!(
    include_str!("common.wgsl"),
    include_str!("prt.wgsl"),
    include_str!("surface.wgsl"),
    include_str!("surface_prt.wgsl"),
    include_str!("march.wgsl"),
    include_str!("planes.wgsl")
);

pub(super) fn state(model: Model) -> PassState<'static> {
    PassState {
        label: "virtual planes",
        source: match model {
            Model::KajiyaKay => KAJIYA_KAY,
            Model::Prt => PRT,
        },
        ..marched::state(model)
    }
}

/// The uploaded slices.
pub(super) struct ScenePlanes {
    pub view: wgpu::TextureView,
    /// Planes per family and their lean, for the frame's uniforms.
    pub count: u32,
    pub tilt: [f32; 2],
    /// Bytes written to the GPU.
    pub bytes: u64,
}

/// Uploads checked slices (`pelt_core::volume::slices::check_slices`).
///
/// # Errors
/// [`pelt_core::PeltError::InvalidParameter`] when a mip chain cannot be built (not for checked
/// slices).
pub(super) fn upload_planes(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    slices: &PlaneSlices,
) -> Result<ScenePlanes> {
    let [width, height] = slices.size;
    let (view, bytes) = upload_with_mips(
        device,
        queue,
        "plane slices",
        [width, height, 2 * slices.planes],
        &slices.rgba,
        wgpu::TextureViewDimension::D2Array,
    )?;
    Ok(ScenePlanes {
        view,
        count: slices.planes as u32,
        tilt: slices.tilt,
        bytes,
    })
}

/// A scene without slices binds this: one empty slice per family (wgpu zero-fills a new
/// texture), never read, since the planes pass refuses such a scene.
pub(super) fn empty_planes(device: &wgpu::Device) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("no plane slices"),
            size: wgpu::Extent3d {
                width: 1,
                height: 1,
                depth_or_array_layers: 2,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&wgpu::TextureViewDescriptor {
            label: Some("no plane slices"),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        })
}
