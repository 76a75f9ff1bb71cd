//! Where each LOD composite stands (Lengyel et al. 2001, §2.4). A composite shell holds a group
//! of level-0 layers; seen from above it shows their "over", but at the silhouette, seen edge
//! on, a ray grazing the fur at height `d` crosses only the layers above `d`. All shells there
//! cover `C(d) = 1 − Π (1 − ā_k)` over the group's layers `k` above `d` (`ā_k` a layer's mean
//! opacity, the ray crossing the layers at unrelated texels); one shell of the group's opacity
//! `C(bottom)` standing at height `H` covers `C(bottom)` below `H` and nothing above. It stands
//! where both cover the same in all: `H = bottom + ∫ C(d) dd / C(bottom)`. Sparse layers give
//! the group's middle, dense ones its top, where the paper puts a pair's composite (at the top,
//! the long-furred benchmark scenes' coarse levels reached the fur's full depth with all their
//! hair at the silhouette and hid more of the fins drawn over them: 3% darker than all shells;
//! every group at its middle did less well than `H`, `docs/accuracy.md`, fifteenth step).

use std::ops::Range;

use pelt_core::volume::lod::{level_counts, sources};

/// The level-0 height, in layers, at which each array layer of every LOD level stands, level 0
/// first (each at its own layer), from the level-0 layers' opacity bytes `alpha`
/// (`[L][texels]`). Each layer's level-0 layers follow the compositing's own pairing
/// (`pelt_core::volume::lod::sources`); a layer holding the skin stands at 0 (each level's
/// layer 0, and the last level's single layer), and the level of one group stands it at the top.
/// Means are summed in f64 in texel order.
pub(super) fn stand_heights(alpha: &[u8], layers: usize, texels: usize) -> Vec<f32> {
    let opacity: Vec<f64> = alpha
        .chunks_exact(texels)
        .take(layers)
        .map(|layer| layer.iter().map(|&a| f64::from(a)).sum::<f64>() / (255.0 * texels as f64))
        .collect();
    let mut heights: Vec<f32> = (0..layers).map(|l| l as f32).collect();
    heights.extend(composite_groups(layers).iter().map(|g| {
        if g.start == 0 {
            0.0
        } else if g.start == 1 && g.end == layers {
            // One group holds all the hair: it stays at the top (below `min_shells`' default;
            // at `H`, the test torus's single shell was 3% brighter than all shells, at the
            // top 0.6% darker, and fading into it dipped 2% below both levels mid-fade).
            (g.end - 1) as f32
        } else {
            group_stand(&opacity[g.clone()], g.start) as f32
        }
    }));
    heights
}

/// The level-0 layers each array layer past level 0 holds, level by level, following the
/// compositing's own pairing (`pelt_core::volume::lod::sources`).
pub(super) fn composite_groups(layers: usize) -> Vec<Range<usize>> {
    let mut all = Vec::new();
    let mut groups: Vec<Range<usize>> = (0..layers).map(|l| l..l + 1).collect();
    for count in level_counts(layers).into_iter().skip(1) {
        groups = (0..count)
            .map(|j| match sources(groups.len(), j) {
                (inner, Some(outer)) => groups[inner].start..groups[outer].end,
                (inner, None) => groups[inner].clone(),
            })
            .collect();
        all.extend(groups.iter().cloned());
    }
    all
}

/// `H` of the module's doc for the group of level-0 layers `first ..` with mean opacities
/// `opacity`, layer `i` standing for the fur between heights `i − 1` and `i`.
fn group_stand(opacity: &[f64], first: usize) -> f64 {
    let bottom = (first - 1) as f64;
    let (mut clear, mut covered) = (1.0, 0.0);
    // C over each layer's slab, from the top down: 1 − the clearness of the layers above it.
    for &a in opacity.iter().rev() {
        clear *= 1.0 - a.clamp(0.0, 1.0);
        covered += 1.0 - clear;
    }
    let base = 1.0 - clear;
    if base > 0.0 {
        bottom + covered / base
    } else {
        // No hair: the group's middle, as good as any.
        bottom + 0.5 * (opacity.len() as f64 + 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `layers` layers of `texels` opacity bytes, layer `l`'s first `a(l) · texels` opaque.
    fn alpha(layers: usize, texels: usize, a: impl Fn(usize) -> f64) -> Vec<u8> {
        (0..layers * texels)
            .map(|i| {
                if ((i % texels) as f64) < a(i / texels) * texels as f64 {
                    255
                } else {
                    0
                }
            })
            .collect()
    }

    /// `H` by brute force: the covered share of a grazing ray at heights `d` sampled finely
    /// across the group, integrated, over the coverage at its bottom.
    fn brute(opacity: &[f64], first: usize) -> f64 {
        let bottom = (first - 1) as f64;
        let steps = 10_000;
        let span = opacity.len() as f64;
        let coverage = |d: f64| {
            // Layer first + i stands for the slab (first + i − 1, first + i]: the ray at d
            // crosses the layers whose slab reaches above d.
            let clear: f64 = opacity
                .iter()
                .enumerate()
                .filter(|&(i, _)| (first + i) as f64 > d)
                .map(|(_, &a)| 1.0 - a)
                .product();
            1.0 - clear
        };
        let integral: f64 = (0..steps)
            .map(|s| coverage(bottom + span * (s as f64 + 0.5) / steps as f64) * span / steps as f64)
            .sum();
        bottom + integral / coverage(bottom)
    }

    #[test]
    fn a_group_stands_where_its_edge_on_coverage_has_its_all_shells_total() {
        for opacity in [
            vec![0.05; 8],
            vec![0.9; 8],
            vec![0.3, 0.2, 0.1, 0.05],
            vec![0.0, 0.5, 0.0, 0.5, 0.2],
        ] {
            for first in [1, 9] {
                let got = group_stand(&opacity, first);
                let want = brute(&opacity, first);
                assert!(
                    (got - want).abs() < 1e-3,
                    "{opacity:?} from {first}: {got} vs {want}"
                );
            }
        }
        // Sparse layers stand near the middle, dense ones at the top, a single layer at itself.
        let sparse = group_stand(&[0.01; 8], 1);
        assert!((sparse - 4.5).abs() < 0.1, "{sparse}");
        assert!((group_stand(&[1.0; 8], 1) - 8.0).abs() < 1e-9);
        assert!((group_stand(&[0.4], 5) - 5.0).abs() < 1e-9);
    }

    #[test]
    fn every_array_layer_gets_its_height_level_by_level() {
        let (layers, texels) = (9, 64);
        let heights = stand_heights(
            &alpha(layers, texels, |l| if l == 0 { 1.0 } else { 0.25 }),
            layers,
            texels,
        );
        // Levels of 9, 5, 3, 2 and 1 layers.
        let counts = level_counts(layers);
        assert_eq!(counts, vec![9, 5, 3, 2, 1]);
        assert_eq!(heights.len(), counts.iter().sum::<usize>());
        assert_eq!(&heights[..9], &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]);
        // Level 1: the skin, then pairs (1, 2), (3, 4), (5, 6), (7, 8).
        let pair = group_stand(&[0.25, 0.25], 1) as f32;
        assert_eq!(heights[9], 0.0);
        for j in 0..4 {
            assert!((heights[10 + j] - (pair + 2.0 * j as f32)).abs() < 1e-5);
        }
        // Level 2: the skin, groups 1..=4 and 5..=8; level 3, the skin and one group of all 8,
        // at its top; the last level, the skin alone.
        let four = group_stand(&[0.25; 4], 1) as f32;
        assert_eq!(&heights[14..], &[0.0, four, four + 4.0, 0.0, 8.0, 0.0]);
        assert!(four > 2.5 && four < 4.0, "{four}");
    }

    #[test]
    fn the_frame_holds_the_two_levels_it_draws_of_the_most_layers() {
        let counts = level_counts(pelt_core::volume::bake::MAX_LAYERS);
        let most = counts.windows(2).skip(1).map(|w| w[0] + w[1]).max().unwrap();
        assert!(most <= 4 * crate::frame_uniforms::STAND_ROWS, "{most}");
    }
}
