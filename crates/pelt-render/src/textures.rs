//! The hair volume on the GPU: the shell layers of every LOD level as one texture array with
//! its mip chain (level `k` from array layer `bases[k]`), the hair-tangent array, and the fin
//! texture with a mip chain of its own (Lengyel et al. 2001, §2.2–§2.4).
//!
//! The bake stores straight alpha with sRGB-encoded color; the renderer blends premultiplied
//! color, stored as [`ColorStore`] says (sRGB-encoded RGBA8 on a GPU, linear half floats on a
//! CPU adapter).

use rayon::prelude::*;

use pelt_core::error::{PeltError, Result};
use pelt_core::texture::color::{srgb8_encoder, srgb8_to_linear_table};
use pelt_core::texture::{MipAlpha, MipLevels, MipOptions, full_mip_count, mip_chain_rgba8};
use pelt_core::threads::pool;
use pelt_core::volume::HairVolume;
use pelt_core::volume::lod::lod_chain;

use super::color_store::ColorStore;
use super::lod::Levels;
use super::over_mips::over_levels;

/// The uploaded textures.
pub(super) struct VolumeTextures {
    pub shells: wgpu::TextureView,
    pub tangents: wgpu::TextureView,
    pub fin: wgpu::TextureView,
    /// Bytes written to the GPU.
    pub bytes: u64,
}

fn mismatch(name: &str, expected: usize, got: usize) -> PeltError {
    PeltError::parameter(
        format!("volume.{name}"),
        format!("must hold {expected} bytes for the volume's sizes, got {got}"),
    )
}

/// Checks that the volume's arrays agree with its sizes and fit the device (with its LOD
/// levels, which take up to as many array layers again).
pub(super) fn validate(volume: &HairVolume, limits: &wgpu::Limits) -> Result<()> {
    let (layers, res) = (volume.layers, volume.resolution);
    let max_side = limits.max_texture_dimension_2d as usize;
    let max_layers = limits.max_texture_array_layers as usize;
    let all_levels = |layers: usize| Levels::new(layers as u32).total() as usize;
    if layers == 0 || all_levels(layers) > max_layers {
        let most = (1..=max_layers)
            .rev()
            .find(|&l| all_levels(l) <= max_layers)
            .unwrap_or(0);
        return Err(PeltError::parameter(
            "volume.layers",
            format!("must be in [1, {most}] on this device (its LOD levels included), got {layers}"),
        ));
    }
    for (name, side) in [
        ("volume.resolution", res),
        ("volume.fin_size[0]", volume.fin_size[0]),
        ("volume.fin_size[1]", volume.fin_size[1]),
    ] {
        if !(1..=max_side).contains(&side) {
            return Err(PeltError::parameter(
                name,
                format!("must be in [1, {max_side}] on this device, got {side}"),
            ));
        }
    }
    if !(volume.layer_spacing.is_finite() && volume.layer_spacing > 0.0 && volume.layer_spacing <= 1.0) {
        return Err(PeltError::parameter(
            "volume.layer_spacing",
            format!("must be in (0, 1], got {}", volume.layer_spacing),
        ));
    }
    let layer_bytes = layers * res * res * 4;
    if volume.shells.len() != layer_bytes {
        return Err(mismatch("shells", layer_bytes, volume.shells.len()));
    }
    if volume.tangents.len() != layer_bytes {
        return Err(mismatch("tangents", layer_bytes, volume.tangents.len()));
    }
    let fin_bytes = volume.fin_size[0] * volume.fin_size[1] * 4;
    if volume.fin.len() != fin_bytes {
        return Err(mismatch("fin", fin_bytes, volume.fin.len()));
    }
    if volume.mips.len() >= full_mip_count(res, res) {
        return Err(PeltError::parameter(
            "volume.mips",
            format!(
                "has {} levels, a {res}² texture has at most {}",
                volume.mips.len(),
                full_mip_count(res, res) - 1
            ),
        ));
    }
    for (k, level) in volume.mips.iter().enumerate() {
        let side = (res >> (k + 1)).max(1);
        if level.len() != layers * side * side * 4 {
            return Err(mismatch(
                &format!("mips[{k}]"),
                layers * side * side * 4,
                level.len(),
            ));
        }
    }
    // An empty chain is built on upload; a given one must be complete.
    if !volume.lod.is_empty() {
        let counts = Levels::new(layers as u32).counts;
        if volume.lod.len() != counts.len() - 1 {
            return Err(PeltError::parameter(
                "volume.lod",
                format!(
                    "must hold {} levels (down to one layer) or none, got {}",
                    counts.len() - 1,
                    volume.lod.len()
                ),
            ));
        }
        for (k, level) in volume.lod.iter().enumerate() {
            let expected = counts[k + 1] as usize * res * res * 4;
            if level.len() != expected {
                return Err(mismatch(&format!("lod[{k}]"), expected, level.len()));
            }
        }
    }
    Ok(())
}

/// Creates a texture and writes its mip levels: `blocks` are `(first layer, levels)` with
/// `levels[m]` mip level `m` of the block's layers (every block has every level).
fn upload(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    format: wgpu::TextureFormat,
    [width, height, layers]: [usize; 3],
    blocks: &[(usize, Vec<Vec<u8>>)],
    dimension: wgpu::TextureViewDimension,
) -> (wgpu::TextureView, u64) {
    let mip_levels = blocks.first().map_or(1, |(_, levels)| levels.len());
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: width as u32,
            height: height as u32,
            depth_or_array_layers: layers as u32,
        },
        mip_level_count: mip_levels as u32,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let texel = format.block_copy_size(None).unwrap_or(4) as usize;
    let mut bytes = 0;
    for (first, levels) in blocks {
        for (level, data) in levels.iter().enumerate() {
            let (w, h) = ((width >> level).max(1), (height >> level).max(1));
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: level as u32,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: *first as u32,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                data,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some((texel * w) as u32),
                    rows_per_image: Some(h as u32),
                },
                wgpu::Extent3d {
                    width: w as u32,
                    height: h as u32,
                    depth_or_array_layers: (data.len() / (texel * w * h)) as u32,
                },
            );
            bytes += data.len() as u64;
        }
    }
    let view = texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some(label),
        // A one-layer array must still be viewed as an array, which the default view would not.
        dimension: Some(dimension),
        ..Default::default()
    });
    (view, bytes)
}

/// Uploads a validated volume with its LOD `levels` (the volume's chain, or one built here when
/// it has none), its colors stored as `store` says.
///
/// # Errors
/// [`PeltError::InvalidParameter`] when a mip chain cannot be built (sizes were checked by
/// [`validate`], so this does not happen for a volume that passed it).
pub(super) fn upload_volume(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    volume: &HairVolume,
    levels: &Levels,
    store: ColorStore,
) -> Result<VolumeTextures> {
    let (layers, res) = (volume.layers, volume.resolution);
    let built;
    let lod: &[Vec<u8>] = if volume.lod.is_empty() {
        built = pool().install(|| lod_chain(&volume.shells, layers, res * res));
        &built
    } else {
        &volume.lod
    };
    // Every level gets as many mip levels as the bake gave level 0, built the same way
    // (alpha-weighted, in linear light).
    let mip_options = MipOptions {
        levels: MipLevels::Count(1 + volume.mips.len()),
        alpha: MipAlpha::Straight,
    };
    let mut chains: Vec<Vec<Vec<u8>>> = vec![
        std::iter::once(&volume.shells)
            .chain(&volume.mips)
            .cloned()
            .collect(),
    ];
    for (k, level) in lod.iter().enumerate() {
        let count = levels.counts[k + 1] as usize;
        chains.push(mip_chain_rgba8(res, res, count, level, true, &mip_options)?);
    }
    pool().install(|| {
        for (chain, &count) in chains.iter_mut().zip(&levels.counts) {
            keep_over(chain, count as usize, res);
        }
    });
    let blocks: Vec<(usize, Vec<Vec<u8>>)> = pool().install(|| {
        chains
            .iter()
            .zip(&levels.bases)
            .map(|(chain, &base)| {
                let stored = chain.iter().map(|l| store.premultiplied(l)).collect();
                (base as usize, stored)
            })
            .collect()
    });
    let array = wgpu::TextureViewDimension::D2Array;
    let (shells, shell_bytes) = upload(
        device,
        queue,
        "shells",
        store.format(),
        [res, res, levels.total() as usize],
        &blocks,
        array,
    );
    // Tangents are data, not color: linear format, one level (lighting tolerates their aliasing
    // far better than color would); level 0 only, every LOD layer takes the tangents of the
    // height it stands at.
    let (tangents, tangent_bytes) = upload(
        device,
        queue,
        "tangents",
        wgpu::TextureFormat::Rgba8Unorm,
        [res, res, layers],
        &[(0, vec![volume.tangents.clone()])],
        array,
    );
    let [fin_w, fin_h] = volume.fin_size;
    // Fins are seen at every scale, from the edge of a close-up to a distant silhouette, so they
    // get the same alpha-weighted, linear-light mip chain as the shells.
    let (fin, fin_bytes) = upload_with_mips(
        device,
        queue,
        "fin",
        [fin_w, fin_h, 1],
        &volume.fin,
        wgpu::TextureViewDimension::D2,
        store,
    )?;
    Ok(VolumeTextures {
        shells,
        tangents,
        fin,
        bytes: shell_bytes + tangent_bytes + fin_bytes,
    })
}

/// Replaces the levels of `chain` (a stack of `layers` straight sRGB RGBA8 layers of `res²`
/// texels, level 0 first) that [`over_levels`] builds by its levels, which keep "over" down each
/// column. Runs in the current rayon pool.
fn keep_over(chain: &mut [Vec<u8>], layers: usize, res: usize) {
    let table = srgb8_to_linear_table();
    let (alpha, values): (Vec<f32>, Vec<[f32; 4]>) = chain[0]
        .par_chunks_exact(4)
        .map(|p| {
            let a = f32::from(p[3]) / 255.0;
            let linear = |c: u8| table[c as usize] * a;
            (a, [linear(p[0]), linear(p[1]), linear(p[2]), a])
        })
        .unzip();
    let encoder = srgb8_encoder();
    let levels = over_levels(&alpha, &values, layers, res, chain.len());
    for (level, values) in chain[1..].iter_mut().zip(levels) {
        *level = values
            .par_iter()
            .flat_map_iter(|&[r, g, b, a]| {
                let straight = |v: f32| {
                    if a > 0.0 {
                        encoder.encode((v / a).min(1.0))
                    } else {
                        0
                    }
                };
                [
                    straight(r),
                    straight(g),
                    straight(b),
                    (a * 255.0).round().clamp(0.0, 255.0) as u8,
                ]
            })
            .collect();
    }
}

/// Uploads `layers` straight sRGB RGBA8 images of `width × height` with their full mip chain
/// (alpha-weighted, in linear light), premultiplied and stored as `store` says.
///
/// # Errors
/// [`PeltError::InvalidParameter`] when the sizes do not match `rgba` (checked by the callers).
pub(super) fn upload_with_mips(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    [width, height, layers]: [usize; 3],
    rgba: &[u8],
    dimension: wgpu::TextureViewDimension,
    store: ColorStore,
) -> Result<(wgpu::TextureView, u64)> {
    let options = MipOptions {
        levels: MipLevels::Full,
        alpha: MipAlpha::Straight,
    };
    let levels = mip_chain_rgba8(width, height, layers, rgba, true, &options)?;
    let levels: Vec<Vec<u8>> = pool().install(|| levels.iter().map(|l| store.premultiplied(l)).collect());
    Ok(upload(
        device,
        queue,
        label,
        store.format(),
        [width, height, layers],
        &[(0, levels)],
        dimension,
    ))
}
