//! Mip levels of a shell stack that keep "over" down each column, for the shell colors and the
//! PRT transfer alike (Lengyel et al. 2001, §2.4, mipmap each shell texture on its own).
//!
//! Hair stands upright through many layers: where a texel of an upper layer holds hair, the
//! layers below it hold the same strand there and are hidden. Averaged each on its own, the
//! layers' coarse texels cover independently, and "over" of the averages lets the deeper, darker
//! layers show through gaps the hair does not have: a PRT sphere's all-shells image was 5% darker
//! at 256² than at 2048² at the same distance, which LOD composites ("over" per texel, then
//! mipmapped) did not follow.
//!
//! Here a coarse texel of layer `i` averages its footprint weighed by the transmittance through
//! the layers over `i` (`T_{i+1}`): a premultiplied value `q` becomes `Σ T_{i+1} q / Σ T_{i+1}`,
//! which for the opacity is `1 − M_i / M_{i+1}` (`M` the footprint's mean transmittance), so
//! "over" of the coarse layers straight down is exactly the footprint's mean composite. Means of
//! means: each level is built from the one before (2 × 2) while the sides are even; an odd side
//! ends the chain here and the plain filter (`pelt_core::texture::mip`) serves the levels below.
//! Every texel is computed on its own, so the result does not depend on the thread count.

use rayon::prelude::*;

/// A footprint this hidden (its summed transmittance) is averaged plainly: nothing shows it.
const HIDDEN: f32 = 1e-6;

/// Levels `1..=n` of a stack of `layers` layers of `res × res` texels (layer-major, inner
/// first): `alpha` their opacity, `values` premultiplied by it. `n` is the number of halvings of
/// even sides, at most `count − 1`. Runs in the current rayon pool.
pub(super) fn over_levels<const C: usize>(
    alpha: &[f32],
    values: &[[f32; C]],
    layers: usize,
    res: usize,
    count: usize,
) -> Vec<Vec<[f32; C]>> {
    let texels = res * res;
    debug_assert_eq!(alpha.len(), layers * texels);
    debug_assert_eq!(values.len(), layers * texels);
    let mut above = transmittance_above(alpha, layers, texels);
    let mut side = res;
    let mut out: Vec<Vec<[f32; C]>> = Vec::new();
    while out.len() + 1 < count && side >= 2 && side.is_multiple_of(2) {
        let half = side / 2;
        let current = out.last().map_or(values, Vec::as_slice);
        let children = |k: usize| {
            let (i, texel) = (k / (half * half), k % (half * half));
            let (x, y) = (2 * (texel % half), 2 * (texel / half));
            [(x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1)].map(|(cx, cy)| i * side * side + cy * side + cx)
        };
        let next: Vec<[f32; C]> = (0..layers * half * half)
            .into_par_iter()
            .map(|k| {
                let under = children(k);
                let weight: f32 = under.iter().map(|&c| above[c]).sum();
                let mut mean = [0.0; C];
                for &c in &under {
                    let w = if weight > HIDDEN { above[c] / weight } else { 0.25 };
                    for (m, v) in mean.iter_mut().zip(current[c]) {
                        *m += w * v;
                    }
                }
                mean
            })
            .collect();
        above = (0..layers * half * half)
            .into_par_iter()
            .map(|k| 0.25 * children(k).iter().map(|&c| above[c]).sum::<f32>())
            .collect();
        out.push(next);
        side = half;
    }
    out
}

/// The transmittance through the layers over each texel of each layer (1 under the top one).
fn transmittance_above(alpha: &[f32], layers: usize, texels: usize) -> Vec<f32> {
    let mut above = vec![1.0f32; layers * texels];
    for i in (0..layers.saturating_sub(1)).rev() {
        let (lower, upper) = above.split_at_mut((i + 1) * texels);
        lower[i * texels..]
            .par_iter_mut()
            .zip(&upper[..texels])
            .zip(&alpha[(i + 1) * texels..(i + 2) * texels])
            .for_each(|((t, &over), &a)| *t = over * (1.0 - a));
    }
    above
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A random stack of 5 layers of 8 × 8 texels, hair in columns: a texel holds hair in a run
    /// of layers from the bottom (an upright strand) with some noise.
    fn stack() -> (Vec<f32>, Vec<[f32; 2]>) {
        let (layers, texels) = (5, 64);
        let mut seed = 7u32;
        let mut random = move || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        let heights: Vec<f32> = (0..texels).map(|_| 5.0 * random()).collect();
        let mut alpha = vec![0.0; layers * texels];
        let mut values = vec![[0.0; 2]; layers * texels];
        for i in 0..layers {
            for x in 0..texels {
                let a = if (i as f32) < heights[x] {
                    0.3 + 0.6 * random()
                } else {
                    0.1 * random()
                };
                alpha[i * texels + x] = a;
                values[i * texels + x] = [a * random(), a];
            }
        }
        (alpha, values)
    }

    /// "Over" straight down one column of a stack, inner layer first.
    fn composite<const C: usize>(column: impl DoubleEndedIterator<Item = (f32, [f32; C])>) -> [f32; C] {
        let (mut sum, mut clear) = ([0.0; C], 1.0);
        for (a, v) in column.rev() {
            for (s, v) in sum.iter_mut().zip(v) {
                *s += clear * v;
            }
            clear *= 1.0 - a;
        }
        sum
    }

    #[test]
    fn over_of_each_coarse_column_is_the_mean_of_its_footprints_columns() {
        let (alpha, values) = stack();
        let (layers, res) = (5, 8);
        let levels = over_levels(&alpha, &values, layers, res, 4);
        assert_eq!(levels.len(), 3);
        for (m, level) in levels.iter().enumerate() {
            let (side, step) = (res >> (m + 1), 1 << (m + 1));
            for texel in 0..side * side {
                let (bx, by) = (texel % side, texel / side);
                let coarse = composite((0..layers).map(|i| {
                    let v = level[i * side * side + texel];
                    (v[1], v)
                }));
                let mut mean = [0.0f32; 2];
                for k in 0..step * step {
                    let x = (by * step + k / step) * res + bx * step + k % step;
                    let fine = composite((0..layers).map(|i| (alpha[i * 64 + x], values[i * 64 + x])));
                    for (m, f) in mean.iter_mut().zip(fine) {
                        *m += f / (step * step) as f32;
                    }
                }
                for c in 0..2 {
                    assert!(
                        (coarse[c] - mean[c]).abs() < 1e-5,
                        "level {}, texel {texel}: {coarse:?} {mean:?}",
                        m + 1
                    );
                }
            }
        }
    }

    #[test]
    fn an_odd_side_ends_the_chain_and_the_thread_count_changes_nothing() {
        let (alpha, values) = stack();
        // 8 → 4 → 2 → 1: three halvings, however many levels are asked beyond.
        assert_eq!(over_levels(&alpha, &values, 5, 8, 9).len(), 3);
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| over_levels(&alpha, &values, 5, 8, 4))
        };
        assert_eq!(run(1), run(3));
        let odd: Vec<f32> = alpha[..5 * 36].to_vec();
        assert!(over_levels(&odd, &values[..5 * 36], 5, 6, 4).len() == 1);
    }
}
