//! The PRT transfer textures on the GPU (prt-shell-fur §2.3–§2.4): the packed float16
//! coefficients (coefficient k in texture k / 4, channel k % 4) as one `Rgba16Float` texture
//! array with a mip chain, texture `t` taking layers `t · stride ..` (stride = the shell
//! layers of every LOD level), plus the per-layer means of the hair's transfer that light the fins.
//!
//! The coefficients are stored premultiplied by the shell texel's opacity, like the shell colors:
//! a hair texel and the empty texel beside it have quite different transfer (the hair shadows
//! itself), and the shader, which divides the filtered `t·α` by the filtered `α`, then gets the
//! transfer of the hair under the fragment whatever the sampling phase. Filtered plainly, the
//! product of filtered color and filtered transfer changed with the phase at which the shells
//! sample the texel grid, which showed as rings across the fur (the shells' parallax sweeps that
//! phase with the view angle).
//!
//! An LOD layer composites a run of shells (Lengyel et al. 2001, §2.4), each lit by its own
//! transfer; the composite's transfer is theirs averaged with the weights "over" gives their
//! colors (outer shell `a_o`, inner `a_i (1 − a_o)`), built pairwise like the shells themselves,
//! so that lighting the composite's color with it approximates lighting each shell.
//!
//! A transfer belongs to one bake: its layers and resolution must be the volume's, which is what
//! [`check`] holds it to.

use std::ops::Range;

use half::f16;
use rayon::prelude::*;

use pelt_core::error::{PeltError, Result};
use pelt_core::prt::pack::{CHANNELS, PackedF16, texture_count};
use pelt_core::prt::sh::MAX_ORDER;
use pelt_core::texture::color::{luminance, srgb8_encoder, srgb8_to_linear_table};
use pelt_core::texture::{MipAlpha, MipLevels, MipOptions, mip_chain_rgba16f};
use pelt_core::volume::lod::sources;

use super::lod::Levels;
use super::over_mips::over_levels;

/// The order whose coefficients fill `textures` RGBA textures: the largest `n` with
/// `⌈n²/4⌉ = textures` (one texture reads as order 2: an order-1 bake leaves channels 1–3 zero,
/// which light nothing).
pub(super) fn order_of(textures: usize) -> Option<usize> {
    (1..=MAX_ORDER).rev().find(|&n| texture_count(n * n) == textures)
}

/// Checks `packed` against the scene's volume (`layers`, `resolution`) and the device's array
/// limit for `stride` layers per texture; returns the order.
///
/// # Errors
/// [`PeltError::InvalidParameter`] naming `transfer.textures`, `transfer.layers`,
/// `transfer.resolution` (a texture set from another bake), `transfer.texels` (its length) or
/// the first non-finite `transfer.texels[i]`, or `transfer` when the array needs more layers than
/// the device has.
pub(super) fn check(
    packed: &PackedF16,
    layers: usize,
    resolution: usize,
    stride: usize,
    max_array_layers: u32,
) -> Result<usize> {
    let order = order_of(packed.textures).ok_or_else(|| {
        PeltError::parameter(
            "transfer.textures",
            format!(
                "must be ⌈n²/4⌉ for an SH order n in [1, {MAX_ORDER}] (1, 3, 4, 7, 9, 13 or 16), got {}",
                packed.textures
            ),
        )
    })?;
    for (name, got, want) in [
        ("transfer.layers", packed.layers, layers),
        ("transfer.resolution", packed.resolution, resolution),
    ] {
        if got != want {
            return Err(PeltError::parameter(
                name,
                format!(
                    "is {got} but the scene's hair volume has {want}: the textures come from another bake"
                ),
            ));
        }
    }
    let expected = packed.textures * layers * resolution * resolution * CHANNELS;
    if packed.texels.len() != expected {
        return Err(PeltError::parameter(
            "transfer.texels",
            format!(
                "must hold textures · layers · resolution² · 4 = {expected} values, got {}",
                packed.texels.len()
            ),
        ));
    }
    if let Some(i) = packed.texels.iter().position(|t| !t.is_finite()) {
        return Err(PeltError::parameter(
            format!("transfer.texels[{i}]"),
            format!("must be finite, got {}", packed.texels[i]),
        ));
    }
    let needed = packed.textures * stride;
    if needed > max_array_layers as usize {
        return Err(PeltError::parameter(
            "transfer",
            format!(
                "needs {needed} texture array layers ({} textures × {stride} layers), the device allows {max_array_layers}",
                packed.textures
            ),
        ));
    }
    Ok(order)
}

/// The opacity-weighted tile mean of every coefficient per layer, `[layer][n²]`: the transfer of
/// the hair in the layer, which the fins show (the plain mean where a layer is empty). `alpha` is
/// the shells' `[L][R²]` opacity bytes. Runs in the current rayon pool; each mean is summed in
/// f64 in texel order, so the result does not depend on the thread count.
pub(super) fn layer_means(packed: &PackedF16, alpha: &[u8], order: usize) -> Vec<f32> {
    let n = order * order;
    let texels = packed.resolution * packed.resolution;
    let voxels = packed.layers * texels;
    (0..packed.layers)
        .into_par_iter()
        .flat_map_iter(|layer| {
            let weights = &alpha[layer * texels..(layer + 1) * texels];
            (0..n).map(move |k| {
                let (t, c) = (k / CHANNELS, k % CHANNELS);
                let start = (t * voxels + layer * texels) * CHANNELS + c;
                let values = packed.texels[start..].iter().step_by(CHANNELS).take(texels);
                let (mut sum, mut weight, mut plain) = (0.0f64, 0.0f64, 0.0f64);
                for (v, &a) in values.zip(weights) {
                    let v = f64::from(v.to_f32());
                    sum += f64::from(a) * v;
                    weight += f64::from(a);
                    plain += v;
                }
                let mean = if weight > 0.0 {
                    sum / weight
                } else {
                    plain / texels as f64
                };
                mean as f32
            })
        })
        .collect()
}

/// The uploaded array.
pub(super) struct TransferTextures {
    pub view: wgpu::TextureView,
    /// Bytes written to the GPU.
    pub bytes: u64,
}

/// The full mip chain of every texture of `per_texture` (`levels.total()` layers of
/// `resolution²` RGBA f16 texels each, every LOD level's layers in a row, premultiplied by the
/// opacity `alphas` of each level's layers): weighed as the shells' colors are, by the
/// transmittance above each texel ([`over_levels`]), where the sides halve evenly. Runs in the
/// current rayon pool.
///
/// # Errors
/// [`PeltError::InvalidParameter`] from the mipmapper (not for checked input).
pub(super) fn mip_chains(
    per_texture: &[Vec<f16>],
    alphas: &[Vec<f32>],
    levels: &Levels,
    resolution: usize,
) -> Result<Vec<Vec<Vec<f16>>>> {
    let options = MipOptions {
        levels: MipLevels::Full,
        alpha: MipAlpha::Independent,
    };
    let stride = levels.total() as usize;
    let texels = resolution * resolution;
    per_texture
        .iter()
        .map(|base| {
            let mut chain = mip_chain_rgba16f(resolution, resolution, stride, base, &options)?;
            for ((alpha, &first), &count) in alphas.iter().zip(&levels.bases).zip(&levels.counts) {
                let (first, count) = (first as usize, count as usize);
                let values: Vec<[f32; CHANNELS]> = base
                    [first * texels * CHANNELS..(first + count) * texels * CHANNELS]
                    .chunks_exact(CHANNELS)
                    .map(|v| std::array::from_fn(|c| v[c].to_f32()))
                    .collect();
                let over = over_levels(alpha, &values, count, resolution, chain.len());
                for (m, level) in over.into_iter().enumerate() {
                    let side = resolution >> (m + 1);
                    let start = first * side * side * CHANNELS;
                    let target = &mut chain[m + 1][start..start + level.len() * CHANNELS];
                    for (t, v) in target.iter_mut().zip(level.as_flattened()) {
                        *t = f16::from_f32(*v);
                    }
                }
            }
            Ok(chain)
        })
        .collect()
}

/// Uploads `chains[t]` ([`mip_chains`]: `stride` layers of `resolution²` RGBA f16 texels per
/// level) as one texture array; call inside an error scope.
pub(super) fn upload(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    chains: &[Vec<Vec<f16>>],
    resolution: usize,
    stride: usize,
) -> Result<TransferTextures> {
    let levels = chains.first().map_or(1, Vec::len);
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("prt transfer"),
        size: wgpu::Extent3d {
            width: resolution as u32,
            height: resolution as u32,
            depth_or_array_layers: (chains.len() * stride) as u32,
        },
        mip_level_count: levels as u32,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba16Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let mut bytes = 0u64;
    for (t, chain) in chains.iter().enumerate() {
        for (level, data) in chain.iter().enumerate() {
            let side = (resolution >> level).max(1) as u32;
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: level as u32,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: (t * stride) as u32,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                bytemuck::cast_slice(data),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(8 * side),
                    rows_per_image: Some(side),
                },
                wgpu::Extent3d {
                    width: side,
                    height: side,
                    depth_or_array_layers: stride as u32,
                },
            );
            bytes += size_of_val(data.as_slice()) as u64;
        }
    }
    let view = texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some("prt transfer"),
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    Ok(TransferTextures { view, bytes })
}

/// The opacity of every LOD level's layers, level by level, level 0 being `alpha` (its `[L][R²]`
/// bytes): level `k` layer `j` composites the layers of level `k − 1` that its shells do
/// ([`sources`]: inner, and outer over it). Runs in the current rayon pool.
pub(super) fn level_alphas(alpha: &[u8], levels: &Levels, texels: usize) -> Vec<Vec<f32>> {
    let mut alphas: Vec<Vec<f32>> = vec![alpha.iter().map(|&a| f32::from(a) / 255.0).collect()];
    for k in 1..levels.counts.len() {
        let prev = &alphas[k - 1];
        let next: Vec<f32> = (0..levels.counts[k] as usize * texels)
            .into_par_iter()
            .map(|i| {
                let (j, x) = (i / texels, i % texels);
                let (inner, outer) = sources(levels.counts[k - 1] as usize, j);
                let inner = prev[inner * texels + x];
                match outer {
                    Some(outer) => {
                        let outer = prev[outer * texels + x];
                        outer + inner * (1.0 - outer)
                    }
                    None => inner,
                }
            })
            .collect();
        alphas.push(next);
    }
    alphas
}

/// What each LOD composite shows of the level-0 layers it holds, for the hot spot's factor
/// (`prt_rotate.wgsl`). All shells raise layer `i` by its own factor `f_i` (`prt.wgsl`
/// `hot_spot_factor`); a composite shows `Σ R_i`, `R_i` the light of layer `i`'s hair it shows,
/// and all shells give `Σ R_i f_i` of it. `R_i` is the lighting dotted with layer `i`'s transfer
/// weighted by how much of it the composite shows ("over": its opacity times the clearness of
/// the composite's layers above it) and by its color's luminance, which is linear and baked
/// here; the ratio is taken per vertex. (Raised by one mean for the composite, taking `R_i ∝`
/// the layer's opacity, the dolly had drifted 13%; by the level-0 mean at its middle height, up
/// to twice the all-shells image. Without the color, the dark roots, whose factors are the
/// largest, weighed as much as the light tips: the short-furred sphere's dolly under a light
/// from the eye drifted to 1.11 of all shells, 1.07 with it. Weighing the composite's transfer
/// by the color too made it 1.11 again; `docs/accuracy.md`, twenty-third step.)
pub(super) struct CompositeMembers {
    /// Per composite (every LOD layer past level 0, in the array's order): the level-0 layers
    /// `first..end` it holds and the row of layer `first`'s weighted transfer in `rows`
    /// (row `r` = values `r·n² ..`), `[first, end, row, 0]`.
    pub ranges: Vec<[u32; 4]>,
    /// Per level past 0, per level-0 layer, its `n²` weighted transfer coefficients, meaned
    /// over the tile.
    pub rows: Vec<f32>,
}

/// [`CompositeMembers`] of `packed` (level 0's transfer), `alphas` every level's opacities
/// ([`level_alphas`]) and `shade` level 0's color luminance ([`texel_shades`]), rows numbered
/// from `first_row` (they follow level 0's layer means in one buffer). Runs in the current rayon pool; sums in f64 in texel order, so the result does not
/// depend on the thread count.
pub(super) fn composite_members(
    packed: &PackedF16,
    alphas: &[Vec<f32>],
    shade: &[u8],
    levels: &Levels,
    order: usize,
    first_row: usize,
) -> CompositeMembers {
    let layers = levels.counts[0] as usize;
    let n = order * order;
    let texels = packed.resolution * packed.resolution;
    let voxels = layers * texels;
    // Level-0 layer i's share of its group's color per texel (its opacity × luminance, then
    // × the clearness of what is composited over it); its group's level-0 layers.
    let linear = srgb8_to_linear_table();
    let mut weight: Vec<f32> = alphas[0]
        .iter()
        .zip(shade)
        .map(|(a, &s)| a * linear[usize::from(s)])
        .collect();
    let mut groups: Vec<Range<usize>> = (0..layers).map(|i| i..i + 1).collect();
    let mut members = CompositeMembers {
        ranges: Vec::new(),
        rows: Vec::new(),
    };
    for k in 1..levels.counts.len() {
        let count = levels.counts[k - 1] as usize;
        let mut under: Vec<Option<usize>> = vec![None; layers];
        let next: Vec<Range<usize>> = (0..levels.counts[k] as usize)
            .map(|j| match sources(count, j) {
                (inner, Some(outer)) => {
                    groups[inner].clone().for_each(|i| under[i] = Some(outer));
                    groups[inner].start..groups[outer].end
                }
                (inner, None) => groups[inner].clone(),
            })
            .collect();
        let above = &alphas[k - 1];
        weight
            .par_chunks_exact_mut(texels)
            .zip(&under)
            .for_each(|(w, outer)| {
                if let Some(outer) = outer {
                    let clear = &above[outer * texels..(outer + 1) * texels];
                    w.iter_mut().zip(clear).for_each(|(w, a)| *w *= 1.0 - a);
                }
            });
        let row = first_row + (k - 1) * layers;
        members.ranges.extend(
            next.iter()
                .map(|g| [g.start as u32, g.end as u32, (row + g.start) as u32, 0]),
        );
        let level_rows: Vec<f32> = (0..layers * n)
            .into_par_iter()
            .map(|r| {
                let (i, c) = (r / n, r % n);
                let start = ((c / CHANNELS) * voxels + i * texels) * CHANNELS + c % CHANNELS;
                let values = packed.texels[start..].iter().step_by(CHANNELS).take(texels);
                let shown = &weight[i * texels..(i + 1) * texels];
                let sum: f64 = values
                    .zip(shown)
                    .map(|(v, &w)| f64::from(v.to_f32()) * f64::from(w))
                    .sum();
                (sum / texels as f64) as f32
            })
            .collect();
        members.rows.extend(level_rows);
        groups = next;
    }
    members
}

/// The luminance of each straight sRGB RGBA8 texel of `shells`, sRGB-encoded. Runs in the
/// current rayon pool.
pub(super) fn texel_shades(shells: &[u8]) -> Vec<u8> {
    let (linear, srgb) = (srgb8_to_linear_table(), srgb8_encoder());
    shells
        .par_chunks_exact(4)
        .map(|px| {
            let rgb = [0, 1, 2].map(|c| f64::from(linear[usize::from(px[c])]));
            srgb.encode(luminance(rgb) as f32)
        })
        .collect()
}

/// Every texture's coefficients for all LOD levels (`levels`), premultiplied by the opacity of
/// their shell texel, level 0 being `packed`: level `k` layer `j` composites the layers of level
/// `k − 1` that its shells do ([`sources`]: inner, and outer over it) with weights
/// `a_i (1 − a_o)` and `a_o` from the shells' opacity (`alphas`, every level's, [`level_alphas`]), or the plain
/// mean where both are empty. Runs in the current rayon pool; every value is computed on its
/// own, so the result does not depend on the thread count.
pub(super) fn premultiplied_levels(
    packed: &PackedF16,
    alphas: &[Vec<f32>],
    levels: &Levels,
) -> Vec<Vec<f16>> {
    let texels = packed.resolution * packed.resolution;
    let voxels = packed.layers * texels;
    let premultiply = |values: &[f32], alpha: &[f32]| -> Vec<f16> {
        values
            .par_iter()
            .enumerate()
            .map(|(i, &v)| f16::from_f32(v * alpha[i / CHANNELS]))
            .collect()
    };
    packed
        .texels
        .par_chunks_exact(voxels * CHANNELS)
        .map(|level0| {
            let mut prev: Vec<f32> = level0.iter().map(|v| v.to_f32()).collect();
            let mut out = premultiply(&prev, &alphas[0]);
            for k in 1..levels.counts.len() {
                let alpha = &alphas[k - 1];
                let next: Vec<f32> = (0..levels.counts[k] as usize * texels * CHANNELS)
                    .into_par_iter()
                    .map(|i| {
                        let (j, x, c) = (i / (texels * CHANNELS), i / CHANNELS % texels, i % CHANNELS);
                        let at = |layer: usize| (layer * texels + x) * CHANNELS + c;
                        let (i_inner, outer) = sources(levels.counts[k - 1] as usize, j);
                        let inner = prev[at(i_inner)];
                        let Some(i_outer) = outer else {
                            return inner;
                        };
                        let outer = prev[at(i_outer)];
                        let a_outer = alpha[i_outer * texels + x];
                        let w_inner = alpha[i_inner * texels + x] * (1.0 - a_outer);
                        let sum = a_outer + w_inner;
                        if sum > 0.0 {
                            (a_outer * outer + w_inner * inner) / sum
                        } else {
                            0.5 * (outer + inner)
                        }
                    })
                    .collect();
                out.extend(premultiply(&next, &alphas[k]));
                prev = next;
            }
            out
        })
        .collect()
}
