//! The peak memory of a GLB export ([`crate::memory`]), checked per object once its vertices are
//! split at the patch seams (a copy the size of the mesh) and before the allocations that the
//! shell count, the fins, the resolution and the layers multiply: the lifted shells, the images
//! and the binary buffer that collects them.
//!
//! With `S` split vertices, `T` triangles, `E` edges, `N` shells and `P` workers: the buffer holds
//! the attributes (`48` bytes per vertex, `24` more when skinned, `48` more of engine attributes),
//! the index lists, `12·S` per shell (geometry) or per fallback shell (engine), four vertices and
//! six indices per fin, the guard hairs (lines, or four ribbon vertices a point), and the PNGs;
//! the PNGs are held twice (the buffer and the table that stores each content once) and a
//! growing buffer briefly three times (its old and new allocation, and the file `finish`
//! assembles). Working copies: the lifted shells, the guard hairs' arrays and the encoders'
//! images (`P` at a time).

use super::super::input::ExportInput;
use super::{GltfMode, GltfOptions};
use crate::error::Result;
use crate::memory;
use crate::mesh::split_at_uv_seams;
use crate::texture::AtlasLayout;

/// An RGBA8 PNG of `texels` texels, at most: the raw bytes, a filter byte per row and zlib's
/// stored-block headers, rounded up.
fn png_bytes(texels: f64) -> f64 {
    4.2 * texels + 4096.0
}

/// The sizes an object's GLB buffers are made from.
pub(super) struct ObjectSizes {
    /// Vertices after the split at patch seams.
    pub split_vertices: usize,
    /// Skinned (joints and weights per vertex).
    pub skinned: bool,
    /// Fins drawn (geometry mode).
    pub fins: bool,
}

/// Estimated bytes `input` adds to the binary buffer, and the working copies made on the way.
fn object_bytes(input: &ExportInput<'_>, mode: GltfMode, sizes: &ObjectSizes) -> (f64, f64) {
    let s = sizes.split_vertices as f64;
    let t = input.mesh.face_count() as f64;
    let edges = input.mesh.topology().edges().len() as f64;
    let v = input.volume;
    let (l, r) = (v.layers, v.resolution);
    let layer = (r * r) as f64;
    let atlas = AtlasLayout::new(l, r).map_or(f64::INFINITY, |a| (a.width * a.height) as f64);
    let fin = (v.fin_size[0] * v.fin_size[1]) as f64;
    let workers = crate::threads::thread_count().max(1) as f64;
    let skin = if sizes.skinned { 24.0 } else { 0.0 };
    let vertex = 48.0 + skin;
    // The skin's and the own materials' index lists together hold every triangle once.
    let indices = 12.0 * t;
    let (points, strands) = input
        .guard_hairs
        .map_or((0.0, 0.0), |g| (g.points.len() as f64, g.spans.len() as f64));
    match mode {
        GltfMode::Geometry => {
            let shells = input.shell_count() as f64;
            let images = (shells + 1.0).min(l as f64) * png_bytes(layer) + png_bytes(fin);
            let fins = if sizes.fins {
                edges * (4.0 * vertex + 24.0)
            } else {
                0.0
            };
            // Two crossed ribbons: four vertices a point, twelve indices a segment.
            let guard = 4.0 * points * (40.0 + skin) + 48.0 * (points - strands);
            let buffer = s * vertex + 2.0 * indices + 12.0 * s * shells + fins + guard + 2.0 * images;
            let working = 12.0 * s * shells + fins + guard + workers * 3.0 * 4.0 * layer.max(fin);
            (buffer, working)
        }
        GltfMode::Engine => {
            let fallback = super::FALLBACK_SHELLS as f64;
            let transfer = input.transfer.map_or(0, |t| t.u8.textures) as f64;
            let images =
                (1.0 + fallback) * png_bytes(layer) + (2.0 + transfer) * png_bytes(atlas) + png_bytes(fin);
            // Lines: position, color and radius a point, two indices a segment.
            let guard = points * (32.0 + skin) + 8.0 * (points - strands);
            let buffer = s * (vertex + 48.0) + 2.0 * indices + 12.0 * s * fallback + guard + 2.0 * images;
            let working = 12.0 * s * fallback + guard + workers * 3.0 * 4.0 * atlas.max(fin);
            (buffer, working)
        }
    }
}

/// Estimated peak bytes of [`super::encode_glb`] for `objects`: the largest over the objects of
/// the buffer up to and with it, and its working copies. Splits each object's mesh at its seams
/// to count the vertices (the export checks each object as it comes, with the split it makes).
///
/// # Errors
/// As [`split_at_uv_seams`].
pub fn glb_peak_bytes(objects: &[ExportInput<'_>], options: &GltfOptions) -> Result<f64> {
    let (mut buffer, mut peak) = (0.0f64, 0.0f64);
    for input in objects {
        let sizes = ObjectSizes {
            split_vertices: split_at_uv_seams(input.mesh, input.corner_uvs)?.len(),
            skinned: input.skin.is_some(),
            fins: options.fins,
        };
        let (bytes, working) = object_bytes(input, options.mode, &sizes);
        peak = peak.max(3.0 * (buffer + bytes) + working);
        buffer += bytes;
    }
    Ok(peak)
}

/// `Ok` when adding `input` to a buffer of `buffer_bytes` fits the memory limit; otherwise
/// [`crate::PeltError::MemoryLimit`] naming what to lower.
pub(super) fn check_object(
    input: &ExportInput<'_>,
    mode: GltfMode,
    sizes: &ObjectSizes,
    buffer_bytes: usize,
) -> Result<()> {
    let (buffer, working) = object_bytes(input, mode, sizes);
    let peak = 3.0 * (buffer_bytes as f64 + buffer) + working;
    memory::check("export_gltf", peak, || {
        let shells = match mode {
            GltfMode::Geometry => format!("`shells` ({}), ", input.shell_count()),
            GltfMode::Engine => String::new(),
        };
        format!(
            "{shells}the volume's `resolution` ({}) or `layers` ({}), or export fewer objects \
             per file",
            input.volume.resolution, input.volume.layers
        )
    })
}
