use std::f64::consts::PI;

use super::bake::bake_validated;
use super::coverage::CoverageMode;
use super::lod::{composite_level, level_counts, lod_chain};
use super::*;
use crate::error::PeltError;
use crate::hair::{Coat, HairParams, Strand, grow_strands};
use crate::texture::color::{linear_to_srgb8, srgb_to_linear};
use crate::texture::full_mip_count;

fn small() -> VolumeParams {
    VolumeParams {
        layers: 8,
        resolution: 32,
        fin_size: [64, 16],
        ..VolumeParams::default()
    }
}

fn bake_with_threads(strands: &[Strand], params: &VolumeParams, threads: usize) -> HairVolume {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| bake_validated(strands, params, None)).unwrap()
}

/// A straight strand from `root` rising with lateral slope `lean`, `segments` segments.
fn straight_strand(root: [f64; 2], lean: [f64; 2], height: f64, radius: [f64; 2], segments: usize) -> Strand {
    let points = (0..=segments)
        .map(|k| {
            let z = height * k as f64 / segments as f64;
            [root[0] + lean[0] * z, root[1] + lean[1] * z, z]
        })
        .collect();
    let radii = (0..=segments)
        .map(|k| radius[0] + (radius[1] - radius[0]) * k as f64 / segments as f64)
        .collect();
    Strand {
        root,
        points,
        radii,
        root_color: [0.2, 0.1, 0.05],
        tip_color: [0.8, 0.6, 0.4],
        coat: Coat::Undercoat,
    }
}

/// The strand's radius at height `z` by walking its polyline (independent of `Strand::crossing`).
fn radius_at(strand: &Strand, z: f64) -> Option<f64> {
    for (seg, pair) in strand.points.windows(2).enumerate() {
        let (z0, z1) = (pair[0][2], pair[1][2]);
        if z >= z0 && z <= z1 {
            let f = (z - z0) / (z1 - z0);
            return Some(strand.radii[seg] + f * (strand.radii[seg + 1] - strand.radii[seg]));
        }
    }
    None
}

#[test]
fn layer_coverage_sums_to_the_cross_sections_including_wrapping_strands() {
    let hair = HairParams {
        slant: 0.6,
        curl: 0.3,
        ..HairParams::default()
    };
    let strands = grow_strands(&hair).unwrap();
    let wrapping = strands
        .iter()
        .filter(|s| {
            s.points
                .iter()
                .any(|p| !(0.0..1.0).contains(&p[0]) || !(0.0..1.0).contains(&p[1]))
        })
        .count();
    assert!(
        wrapping > 100,
        "the test needs strands over the tile edge, got {wrapping}"
    );
    let params = VolumeParams {
        layers: 16,
        resolution: 64,
        trim: false,
        ..small()
    };
    let volume = bake_validated(&strands, &params, None).unwrap();
    let texels = 64 * 64;
    for layer in 0..16 {
        let z = layer as f64 / 16.0;
        let want: f64 = strands
            .iter()
            .filter_map(|s| radius_at(s, z))
            .map(|r| PI * r * r)
            .sum();
        let got: f64 = volume.coverage[layer * texels..(layer + 1) * texels]
            .iter()
            .map(|&c| f64::from(c))
            .sum::<f64>()
            / texels as f64;
        assert!(
            (got - want).abs() <= 1e-4 * want.max(1e-12),
            "layer {layer}: {got} vs {want}"
        );
    }
}

#[test]
fn same_seed_same_bytes_for_one_and_two_threads_and_seeds_differ() {
    let params = VolumeParams {
        vertical_filter: 0.7,
        ..small()
    };
    let strands = grow_strands(&HairParams::default()).unwrap();
    let one = bake_with_threads(&strands, &params, 1);
    let two = bake_with_threads(&strands, &params, 2);
    assert_eq!(one.shells, two.shells);
    assert_eq!(one.tangents, two.tangents);
    assert_eq!(one.fin, two.fin);
    assert_eq!(one.lod, two.lod);
    assert_eq!(one.mips, two.mips);
    let bits = |v: &HairVolume| v.coverage.iter().map(|c| c.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&one), bits(&two));
    let other = grow_strands(&HairParams {
        seed: 2,
        ..HairParams::default()
    })
    .unwrap();
    let three = bake_with_threads(&other, &params, 2);
    assert_ne!(one.shells, three.shells);
    assert_ne!(one.fin, three.fin);
}

#[test]
fn tile_repeats_without_a_seam() {
    // Baking the strands moved by half a tile must give the texture rolled by half a tile: then
    // the tile's edge, now in the middle of the image, is sampled like any other place, and a
    // 2×2 repeat of the texture has no seam.
    let hair = HairParams {
        slant: 0.5,
        curl: 0.4,
        ..HairParams::default()
    };
    let strands = grow_strands(&hair).unwrap();
    let moved: Vec<Strand> = strands
        .iter()
        .map(|s| Strand {
            root: s.root.map(|c| (c + 0.5).rem_euclid(1.0)),
            points: s.points.iter().map(|p| [p[0] + 0.5, p[1] + 0.5, p[2]]).collect(),
            ..s.clone()
        })
        .collect();
    let params = VolumeParams {
        trim: false,
        ..small()
    };
    let a = bake_validated(&strands, &params, None).unwrap();
    let b = bake_validated(&moved, &params, None).unwrap();
    let r = params.resolution;
    let mut worst = 0.0f32;
    for layer in 0..params.layers {
        for y in 0..r {
            for x in 0..r {
                let rolled = layer * r * r + ((y + r / 2) % r) * r + (x + r / 2) % r;
                worst = worst.max((a.coverage[rolled] - b.coverage[layer * r * r + y * r + x]).abs());
            }
        }
    }
    assert!(worst < 1e-5, "rolled coverage differs by {worst}");
    // And the edge columns of a layer continue into each other: hairs cross the edge.
    let layer = 2 * r * r;
    let edge: f32 = (0..r)
        .map(|y| a.coverage[layer + y * r] + a.coverage[layer + y * r + r - 1])
        .sum();
    assert!(edge > 0.0);
}

#[test]
fn zero_density_gives_empty_shells_over_an_opaque_skin() {
    let hair = HairParams {
        density: 0,
        ..HairParams::default()
    };
    let params = VolumeParams {
        trim: false,
        ..small()
    };
    let v = bake_volume(&hair, &params, None).unwrap();
    let texels = params.resolution * params.resolution;
    assert!(v.shells[..4 * texels].chunks_exact(4).all(|p| p[3] == 255));
    assert!(v.shells[4 * texels..].chunks_exact(4).all(|p| p[3] == 0));
    assert!(v.coverage.iter().all(|&c| c == 0.0));
    assert!(v.fin.chunks_exact(4).all(|p| p[3] == 0));
    // With the trim, the skin and one empty layer are left (the transfer needs two).
    let trimmed = bake_volume(&hair, &small(), None).unwrap();
    assert_eq!((trimmed.layers, trimmed.stats.trimmed), (2, params.layers - 2));
}

#[test]
fn trim_drops_the_layers_above_the_tallest_strand() {
    let strands = vec![straight_strand([0.5, 0.5], [0.0, 0.0], 0.7, [0.01, 0.005], 8)];
    let v = bake_validated(
        &strands,
        &VolumeParams {
            layers: 16,
            ..small()
        },
        None,
    )
    .unwrap();
    // Heights i/16 <= 0.7 for i <= 11.
    assert_eq!((v.layers, v.stats.trimmed), (12, 4));
    assert_eq!(v.stats.tallest, 0.7);
    let texels = 32 * 32;
    let top = &v.coverage[11 * texels..12 * texels];
    assert!(
        top.iter().any(|&c| c > 0.0),
        "the last kept layer still holds hair"
    );
    assert_eq!(v.lod.len(), 5, "12 → 7 → 4 → 3 → 2 → 1 layers");
    assert_eq!(v.lod.last().map(|l| l.len()), Some(4 * texels));
}

#[test]
fn tangent_map_and_color_follow_a_slanted_strand() {
    let lean = [0.3, -0.2];
    let strands = vec![straight_strand([0.4, 0.6], lean, 0.9, [0.06, 0.06], 4)];
    let v = bake_validated(
        &strands,
        &VolumeParams {
            trim: false,
            ..small()
        },
        None,
    )
    .unwrap();
    let norm = (lean[0] * lean[0] + lean[1] * lean[1] + 1.0).sqrt();
    let want = [lean[0] / norm, lean[1] / norm, 1.0 / norm];
    let texels = 32 * 32;
    let layer = 4; // height 0.5: halfway up the strand
    let mut seen = 0;
    for t in 0..texels {
        if v.coverage[layer * texels + t] > 0.0 {
            let px = &v.tangents[4 * (layer * texels + t)..4 * (layer * texels + t) + 4];
            for c in 0..3 {
                let d = f64::from(px[c]) / 255.0 * 2.0 - 1.0;
                assert!((d - want[c]).abs() < 0.01, "component {c}: {d} vs {}", want[c]);
            }
            // Color halfway up: the mean of root and tip, sRGB-encoded.
            let rgba = &v.shells[4 * (layer * texels + t)..4 * (layer * texels + t) + 4];
            let along = 0.5 / 0.9;
            let want_r = 0.2 + (0.8 - 0.2) * along;
            assert_eq!(rgba[0], linear_to_srgb8(want_r as f32));
            seen += 1;
        }
    }
    assert!(seen > 10);
}

#[test]
fn fin_row_covers_the_strand_interval_exactly() {
    // One vertical strand at x = 0.5 inside the slab: each fin row below its tip covers
    // [x − r, x + r] (r = 0.01 tile = 0.64 texel of a 64-wide fin): centre texels 31 and 32 get
    // 0.64 each; a strand outside the slab is ignored.
    let strands = vec![
        straight_strand([0.5, 0.05], [0.0, 0.0], 0.6, [0.01, 0.01], 4),
        straight_strand([0.2, 0.5], [0.0, 0.0], 0.9, [0.01, 0.01], 4),
    ];
    let params = VolumeParams {
        fin_slab: 0.1,
        ..small()
    };
    let v = bake_validated(&strands, &params, None).unwrap();
    let [w, h] = params.fin_size;
    for row in 0..h {
        let z = 1.0 - (row as f64 + 0.5) / h as f64;
        let alpha = |x: usize| f64::from(v.fin[4 * (row * w + x) + 3]) / 255.0;
        let (want, other) = if z <= 0.6 { (0.64, 0.0) } else { (0.0, 0.0) };
        assert!(
            (alpha(31) - want).abs() < 0.003 && (alpha(32) - want).abs() < 0.003,
            "row {row}"
        );
        assert_eq!(alpha(12), other, "the strand at x = 0.2 is outside the slab");
        assert_eq!(alpha(40), 0.0);
    }
}

#[test]
fn lod_composites_pairs_with_over_and_mips_average() {
    // Two 1×1 layers: inner opaque red, outer half-transparent green.
    let red = [linear_to_srgb8(1.0), 0, 0, 255];
    let green = [0, linear_to_srgb8(1.0), 0, 128];
    let stack: Vec<u8> = red.iter().chain(green.iter()).copied().collect();
    let out = composite_level(&stack, 2, 1);
    assert_eq!(out.len(), 4);
    let a = 128.0 / 255.0;
    let lin = |b: u8| f64::from(srgb_to_linear(f32::from(b) / 255.0));
    assert!(
        (lin(out[0]) - (1.0 - a)).abs() < 0.01,
        "red shows through: {out:?}"
    );
    assert!((lin(out[1]) - a).abs() < 0.01, "green on top: {out:?}");
    assert_eq!(out[3], 255);
    assert_eq!(
        lod_chain(&[0u8; 4 * 5], 5, 1)
            .iter()
            .map(Vec::len)
            .collect::<Vec<_>>(),
        [12, 8, 4]
    );
    let v = bake_volume(&HairParams::default(), &small(), None).unwrap();
    assert_eq!(v.mips.len(), full_mip_count(32, 32) - 1);
    assert_eq!(v.mips.last().map(Vec::len), Some(4 * v.layers));
}

#[test]
fn lod_keeps_the_skin_apart_and_composites_runs_of_hair_over_it() {
    assert_eq!(level_counts(1), [1]);
    assert_eq!(level_counts(2), [2, 1]);
    assert_eq!(level_counts(6), [6, 4, 3, 2, 1]);
    assert_eq!(level_counts(9), [9, 5, 3, 2, 1]);
    // One texel per layer: an opaque skin, then hair of varied color and opacity.
    for layers in [6usize, 9] {
        let stack: Vec<u8> = (0..layers)
            .flat_map(|l| {
                let alpha = if l == 0 { 255 } else { (40 + 23 * l) as u8 };
                [(30 * l) as u8, (200 - 17 * l) as u8, (90 + 11 * l) as u8, alpha]
            })
            .collect();
        let chain = lod_chain(&stack, layers, 1);
        let counts = level_counts(layers);
        // Straight over of level-0 layers `range` in f64, outermost last, premultiplied linear.
        let over = |range: std::ops::RangeInclusive<usize>| {
            range.fold([0.0f64; 4], |under, l| {
                let px = &stack[4 * l..4 * l + 4];
                let a = f64::from(px[3]) / 255.0;
                let c = |b: u8| f64::from(srgb_to_linear(f32::from(b) / 255.0)) * a;
                let top = [c(px[0]), c(px[1]), c(px[2]), a];
                std::array::from_fn(|i| top[i] + (1.0 - a) * under[i])
            })
        };
        for (k, level) in (1..).zip(&chain) {
            assert_eq!(level.len(), 4 * counts[k], "layers {layers}, level {k}");
            let step = 1usize << k;
            for j in 0..counts[k] {
                let range = match (counts[k], j) {
                    (1, _) => 0..=layers - 1,
                    (_, 0) => 0..=0,
                    _ => (j - 1) * step + 1..=(j * step).min(layers - 1),
                };
                let want = over(range.clone());
                let px = &level[4 * j..4 * j + 4];
                let a = f64::from(px[3]) / 255.0;
                let got = [0, 1, 2].map(|i| f64::from(srgb_to_linear(f32::from(px[i]) / 255.0)) * a);
                assert!(
                    (a - want[3]).abs() < 0.02,
                    "{layers} layers, level {k} layer {j} ({range:?}): alpha {a} vs {}",
                    want[3]
                );
                for i in 0..3 {
                    assert!(
                        (got[i] - want[i]).abs() < 0.02,
                        "{layers} layers, level {k} layer {j} ({range:?}): {got:?} vs {want:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn the_bake_s_lod_is_the_chain_of_its_shells() {
    // The stack composites level 1 while it samples; it must equal compositing afterwards, with
    // an odd and an even layer count (no trim).
    for layers in [7, 8, 2] {
        let params = VolumeParams {
            layers,
            trim: false,
            ..small()
        };
        let v = bake_volume(&HairParams::default(), &params, None).unwrap();
        assert_eq!(v.layers, layers);
        assert_eq!(v.lod, lod_chain(&v.shells, layers, 32 * 32), "{layers} layers");
    }
}

#[test]
fn every_parameter_combination_in_range_is_finite_and_bounded() {
    // A seeded sweep over the ranges of HairParams and VolumeParams, including their ends.
    let mut state = 0x1234_5678_9ABC_DEF0u64;
    let mut next = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for case in 0..24 {
        let mut pick = |lo: f64, hi: f64| match case % 3 {
            0 => lo + (hi - lo) * next(),
            1 => lo,
            _ => hi,
        };
        let w = pick(0.0, 0.1);
        let hair = HairParams {
            seed: case,
            density: pick(0.0, 600.0) as u32,
            guard_fraction: pick(0.0, 1.0),
            undercoat: crate::hair::CoatParams {
                length: [0.0, pick(0.0, 1.0)],
                width: [0.0, w],
            },
            overcoat: crate::hair::CoatParams {
                length: [pick(0.0, 1.0).min(0.5), 1.0],
                width: [w * 0.5, w],
            },
            segments: pick(1.0, 64.0) as u32,
            taper: pick(0.0, 1.0),
            curl: pick(0.0, 1.0),
            helix_radius: pick(0.0, 0.1),
            helix_frequency: pick(0.0, 32.0),
            slant: pick(0.0, crate::hair::MAX_SLANT),
            slant_direction: pick(-std::f64::consts::TAU, std::f64::consts::TAU),
            length_jitter: pick(0.0, 1.0),
            clump_strength: pick(0.0, 1.0),
            clump_count: pick(0.0, 256.0) as u32,
            color_jitter: pick(0.0, 1.0),
            ..HairParams::default()
        };
        let params = VolumeParams {
            layers: pick(1.0, 12.0) as usize,
            resolution: pick(1.0, 24.0) as usize,
            vertical_filter: pick(0.0, 2.0),
            fin_size: [pick(1.0, 32.0) as usize, pick(1.0, 8.0) as usize],
            fin_slab: pick(0.01, 1.0),
            coverage: [
                CoverageMode::Exact,
                CoverageMode::Approx,
                CoverageMode::Supersample(3),
            ][case as usize % 3],
            ..VolumeParams::default()
        };
        let v = bake_volume(&hair, &params, None).unwrap_or_else(|e| panic!("case {case}: {e}"));
        assert!(
            v.coverage.iter().all(|c| c.is_finite() && *c >= 0.0),
            "case {case}"
        );
        assert!(v.stats.mean_coverage.iter().all(|c| c.is_finite()), "case {case}");
        assert!(v.stats.tallest.is_finite());
        let texels = v.resolution * v.resolution;
        assert!(
            v.shells[..4 * texels].chunks_exact(4).all(|p| p[3] == 255),
            "case {case}: skin"
        );
    }
}

#[test]
fn per_hair_shares_stay_within_a_texel() {
    // Alpha is composited from per-hair shares in [0, 1]: a single hair twice a texel wide fills
    // the texels under its middle completely and never more.
    let strands = vec![straight_strand([0.5, 0.5], [0.0, 0.0], 1.0, [0.1, 0.1], 2)];
    let v = bake_validated(
        &strands,
        &VolumeParams {
            trim: false,
            ..small()
        },
        None,
    )
    .unwrap();
    let texels = 32 * 32;
    let layer = &v.coverage[3 * texels..4 * texels];
    assert!(layer.iter().all(|&c| (0.0..=1.0).contains(&c)));
    assert_eq!(layer[16 * 32 + 16], 1.0);
    assert_eq!(v.shells[4 * (3 * texels + 16 * 32 + 16) + 3], 255);
}

#[test]
fn out_of_range_volume_parameters_name_the_field() {
    let cases: Vec<(VolumeParams, &str)> = vec![
        (VolumeParams { layers: 0, ..small() }, "layers"),
        (
            VolumeParams {
                layers: 257,
                ..small()
            },
            "layers",
        ),
        (
            VolumeParams {
                resolution: 0,
                ..small()
            },
            "resolution",
        ),
        (
            VolumeParams {
                resolution: 4097,
                ..small()
            },
            "resolution",
        ),
        (
            VolumeParams {
                vertical_filter: -1.0,
                ..small()
            },
            "vertical_filter",
        ),
        (
            VolumeParams {
                vertical_filter: f64::NAN,
                ..small()
            },
            "vertical_filter",
        ),
        (
            VolumeParams {
                fin_size: [0, 8],
                ..small()
            },
            "fin_size[0]",
        ),
        (
            VolumeParams {
                fin_size: [8, 5000],
                ..small()
            },
            "fin_size[1]",
        ),
        (
            VolumeParams {
                fin_slab: 0.0,
                ..small()
            },
            "fin_slab",
        ),
        (
            VolumeParams {
                fin_slab: f64::INFINITY,
                ..small()
            },
            "fin_slab",
        ),
    ];
    for (params, field) in cases {
        match bake_volume(&HairParams::default(), &params, None) {
            Err(PeltError::InvalidParameter { name, reason }) => {
                assert_eq!(name, field);
                assert!(reason.contains("must be in"), "{reason}");
            }
            other => panic!("{field}: expected InvalidParameter, got {other:?}"),
        }
    }
    let bad_hair = HairParams {
        density: u32::MAX,
        ..HairParams::default()
    };
    assert!(matches!(
        bake_volume(&bad_hair, &small(), None),
        Err(PeltError::InvalidParameter { ref name, .. }) if name == "density"
    ));
}

#[test]
fn cancelling_stops_the_bake() {
    let stop = |fraction: f64| fraction < 0.2;
    let outcome = bake_volume(&HairParams::default(), &small(), Some(&stop));
    assert!(matches!(outcome, Err(PeltError::Cancelled)));
}
