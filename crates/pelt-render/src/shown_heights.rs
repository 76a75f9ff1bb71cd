//! The heights of the hair each LOD composite shows, per mip level of the shell textures: where
//! the marched shells light a composite under PRT (`surface_prt.wgsl` `march_heights`; the march
//! lights its composite by the hair's mean transfer at the heights it holds, `prt.wgsl`).
//!
//! All shells, marched, give each level-0 layer the share "over" leaves it of the texels the march
//! reads. A composite texel is the "over" of its group's texels at full resolution; at a coarser
//! mip level it is the mean of those composites, while all shells read each layer's mip texel and
//! composite those. So a composite's heights are taken at each mip level as all shells take theirs
//! there: each member weighed by its opacity in the mip texel times the clearness of the members
//! over it, meaned over the tile. The mip texels' opacities are the ones uploaded: weighed by the
//! transmittance above ([`over_levels`], where the sides halve evenly), else the plain 2 × 2 mean.
//! (Weighed at full resolution only, the marched LOD under a side light was 2–4% darker than all
//! shells once the object was small enough to read coarser mips; at the group's middle, up to 11%.)

use std::borrow::Cow;
use std::ops::Range;

use rayon::prelude::*;

use pelt_core::texture::full_mip_count;

use super::over_mips::over_levels;

/// Per mip level of a `resolution²` tile (the full chain), per group of `groups` (level-0
/// layers), the mean and the mean square of the heights (level-0 layer indices) of the hair the
/// group's "over" shows, from the level-0 layers' opacities `alpha` (`[L][texels]`, 0–1); a
/// group that shows nothing gets its members' plain mean. Sums run in f64 in texel order, so the
/// result does not depend on the thread count. Runs in the current rayon pool.
pub(super) fn shown_heights(alpha: &[f32], resolution: usize, groups: &[Range<usize>]) -> Vec<[f32; 2]> {
    let texels = resolution * resolution;
    let layers = alpha.len() / texels.max(1);
    let count = full_mip_count(resolution, resolution);
    let as_values: Vec<[f32; 1]> = alpha.iter().map(|&a| [a]).collect();
    let mut over = over_levels(alpha, &as_values, layers, resolution, count).into_iter();
    let mut side = resolution;
    let mut plain = Cow::Borrowed(alpha);
    let mut out = Vec::new();
    for mip in 0..count {
        if mip > 0 {
            (plain, side) = (Cow::Owned(halve(&plain, side)), (side / 2).max(1));
        }
        let uploaded = match (mip > 0).then(|| over.next()).flatten() {
            Some(level) => Cow::Owned(level.into_iter().map(|[a]| a).collect()),
            None => Cow::Borrowed(plain.as_ref()),
        };
        let texels = side * side;
        out.extend(groups.iter().map(|g| group_heights(&uploaded, texels, g.clone())));
    }
    out
}

/// The mean and mean square of the heights of `group`'s hair, its layers' opacities `alpha`
/// (`[L][texels]`): the module's weights.
fn group_heights(alpha: &[f32], texels: usize, group: Range<usize>) -> [f32; 2] {
    let sums: Vec<[f64; 3]> = (0..texels)
        .into_par_iter()
        .map(|t| {
            let (mut clear, mut sum) = (1.0f64, [0.0f64; 3]);
            for i in group.clone().rev() {
                let a = f64::from(alpha[i * texels + t]).clamp(0.0, 1.0);
                let (w, h) = (a * clear, i as f64);
                sum = [sum[0] + w, sum[1] + w * h, sum[2] + w * h * h];
                clear *= 1.0 - a;
            }
            sum
        })
        .collect();
    let [shown, heights, squares] = sums.iter().fold([0.0f64; 3], |acc, s| {
        [acc[0] + s[0], acc[1] + s[1], acc[2] + s[2]]
    });
    if shown > 0.0 {
        return [(heights / shown) as f32, (squares / shown) as f32];
    }
    let n = group.len() as f64;
    let mean = group.clone().map(|i| i as f64).sum::<f64>() / n;
    let square = group.map(|i| (i * i) as f64).sum::<f64>() / n;
    [mean as f32, square as f32]
}

/// Every layer of `side²` opacities (`[L][side²]`) halved per side by a 2 × 2 box, as the mip
/// chain averages opacity (`pelt_core::texture::mip`; an odd side's last row or column is left
/// out here, a tile's mean weights barely move).
fn halve(alpha: &[f32], side: usize) -> Vec<f32> {
    let half = (side / 2).max(1);
    let texels = side * side;
    alpha
        .par_chunks_exact(texels)
        .flat_map_iter(|layer| {
            (0..half * half).map(move |t| {
                let (x, y) = (2 * (t % half), 2 * (t / half));
                let at = |dx: usize, dy: usize| layer[(y + dy).min(side - 1) * side + (x + dx).min(side - 1)];
                0.25 * (at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1))
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `layers` layers of a `side²` tile, opacities varied per layer and texel.
    fn opacities(layers: usize, side: usize) -> Vec<f32> {
        (0..layers * side * side)
            .map(|v| ((v * 37 + 11) % 17) as f32 / 20.0)
            .collect()
    }

    /// Brute force: the heights' mean and mean square over every texel of mip `mip` and every
    /// member of `group`, each weighed by its opacity there times the product of (1 − opacity)
    /// of the members above it; a layer's opacity in a mip texel is the mean of its
    /// `2^mip × 2^mip` level-0 texels weighed by the transmittance through every layer above.
    fn brute(alpha: &[f32], side: usize, mip: u32, group: Range<usize>) -> [f64; 2] {
        let step = 1usize << mip;
        let texels = side * side;
        let layers = alpha.len() / texels;
        let (mut weights, mut heights, mut squares) = (0.0f64, 0.0f64, 0.0f64);
        for by in (0..side).step_by(step) {
            for bx in (0..side).step_by(step) {
                let mean = |i: usize| {
                    let (mut sum, mut above) = (0.0f64, 0.0f64);
                    for y in by..by + step {
                        for x in bx..bx + step {
                            let at = |j: usize| f64::from(alpha[j * texels + y * side + x]);
                            let clear: f64 = (i + 1..layers).map(|j| 1.0 - at(j)).product();
                            sum += clear * at(i);
                            above += clear;
                        }
                    }
                    sum / above
                };
                for i in group.clone() {
                    let over: f64 = (i + 1..group.end).map(|j| 1.0 - mean(j)).product();
                    let w = mean(i) * over;
                    weights += w;
                    heights += w * i as f64;
                    squares += w * (i * i) as f64;
                }
            }
        }
        [heights / weights, squares / weights]
    }

    #[test]
    fn a_composite_shows_its_members_heights_as_all_shells_show_them_at_each_mip_level() {
        let (layers, side) = (7, 8);
        let alpha = opacities(layers, side);
        let groups = [1..3, 3..7, 1..7, 0..7, 5..6];
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| shown_heights(&alpha, side, &groups))
        };
        let heights = run(1);
        assert_eq!(heights, run(3), "thread count changed the heights");
        // An 8² tile has mip levels 8², 4², 2² and 1².
        assert_eq!(heights.len(), 4 * groups.len());
        for mip in 0..4u32 {
            for (g, group) in groups.iter().enumerate() {
                let got = heights[mip as usize * groups.len() + g];
                let want = brute(&alpha, side, mip, group.clone());
                for (got, want) in got.iter().zip(want) {
                    assert!(
                        (f64::from(*got) - want).abs() < 1e-4 * want.max(1.0),
                        "mip {mip} group {group:?}: {got} vs {want}"
                    );
                }
            }
        }
        // The upper members show more than their share: the group's mean lies above its middle.
        assert!(heights[1][0] > 4.5 + 0.1, "{:?}", heights[1]);
    }

    #[test]
    fn a_composite_that_shows_nothing_stands_at_its_members_mean() {
        let alpha = vec![0.0f32; 4 * 4];
        let heights = shown_heights(&alpha, 2, &[1..4, 2..4]);
        // Mips 2² and 1².
        let each = [[2.0, 14.0 / 3.0], [2.5, 6.5]];
        assert_eq!(heights, [each, each].concat());
    }
}
