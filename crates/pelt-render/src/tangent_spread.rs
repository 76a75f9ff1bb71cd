//! How the hair's directions spread about their mean, for the fins' Kajiya–Kay lighting
//! (`fin_kk.wgsl`). A fin shows the hair of a whole column of the volume side by side; Lengyel
//! et al. 2001 (§2.4) light it by one tangent, the growth direction, but the Kajiya–Kay terms are
//! not linear in the tangent: a light straight along the growth direction lights that tangent not
//! at all, while the hairs leaning about it, which the shells' tangent map and the reference's
//! strands light, catch it. The fins instead take the mean of `(T·L)²` over the hair, which the
//! second moment `E[d dᵀ]` of the tangent map's directions gives in any frame.

use pelt_core::volume::HairVolume;
use rayon::prelude::*;

/// `E[d dᵀ]` of the unit hair directions `d` of the tangent map (tile frame: x along u, y along
/// v, z up), each texel of the hair layers (not the skin) weighed by its coverage; packed for
/// `Frame::fin_tangents`: (xx, yy, zz, xy), (xz, yz, 0, 0). Zero without hair.
pub(super) fn tangent_moments(volume: &HairVolume) -> [[f32; 4]; 2] {
    let texels = volume.resolution * volume.resolution;
    if volume.layers < 2 || texels == 0 {
        return [[0.0; 4]; 2];
    }
    // Summed per layer in parallel, then the layers in order: the same bytes for any thread
    // count.
    let layers: Vec<[f64; 7]> = (1..volume.layers)
        .into_par_iter()
        .map(|layer| {
            let range = layer * texels..(layer + 1) * texels;
            let coverage = volume.coverage.get(range.clone()).unwrap_or(&[]);
            let tangents = volume.tangents.get(4 * range.start..4 * range.end).unwrap_or(&[]);
            let mut sum = [0.0f64; 7];
            for (&w, t) in coverage.iter().zip(tangents.chunks_exact(4)) {
                // Also skips a NaN coverage.
                if w.is_nan() || w <= 0.0 {
                    continue;
                }
                let d = [0, 1, 2].map(|k| f64::from(t[k]) / 127.5 - 1.0);
                let norm = d.iter().map(|c| c * c).sum::<f64>();
                if norm <= 0.0 {
                    continue;
                }
                // The packed direction is unit up to 8-bit rounding: d dᵀ / |d|².
                let (weight, scale) = (f64::from(w), f64::from(w) / norm);
                let products = [
                    d[0] * d[0],
                    d[1] * d[1],
                    d[2] * d[2],
                    d[0] * d[1],
                    d[0] * d[2],
                    d[1] * d[2],
                ];
                for (s, p) in sum.iter_mut().zip(products) {
                    *s += scale * p;
                }
                sum[6] += weight;
            }
            sum
        })
        .collect();
    let mut total = [0.0f64; 7];
    for layer in &layers {
        for (t, s) in total.iter_mut().zip(layer) {
            *t += s;
        }
    }
    if total[6].is_nan() || total[6] <= 0.0 {
        return [[0.0; 4]; 2];
    }
    let m = total.map(|s| (s / total[6]) as f32);
    [[m[0], m[1], m[2], m[3]], [m[4], m[5], 0.0, 0.0]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use pelt_core::hair::HairParams;
    use pelt_core::volume::{VolumeParams, bake_volume};

    fn volume() -> HairVolume {
        let params = VolumeParams {
            resolution: 16,
            layers: 8,
            trim: false,
            ..VolumeParams::default()
        };
        bake_volume(&HairParams::default(), &params, None).unwrap()
    }

    #[test]
    fn hair_straight_up_has_all_its_moment_along_z_and_hair_leaning_both_ways_splits_it() {
        let mut v = volume();
        v.coverage.fill(0.5);
        // Straight up: d = (0, 0, 1), packed 0.5·d + 0.5.
        for t in v.tangents.chunks_exact_mut(4) {
            t[..3].copy_from_slice(&[128, 128, 255]);
        }
        let [a, b] = tangent_moments(&v);
        // Within the packing's half step (1/255) of straight up.
        let small = |x: f32| x.abs() < 0.01;
        assert!(small(a[2] - 1.0) && small(a[0]) && small(a[1]), "{a:?}");
        assert!(small(a[3]) && small(b[0]) && small(b[1]), "{b:?}");
        // Half the texels lean 45° toward +x, half toward −x: E[x²] = E[z²] = ½, E[xz] = 0.
        let lean = (0.5f64.sqrt() * 127.5) as u8;
        for (i, t) in v.tangents.chunks_exact_mut(4).enumerate() {
            let x = if i % 2 == 0 { 128 + lean } else { 127 - lean };
            t[..3].copy_from_slice(&[x, 128, 128 + lean]);
        }
        let [a, b] = tangent_moments(&v);
        assert!((a[0] - 0.5).abs() < 0.01 && (a[2] - 0.5).abs() < 0.01, "{a:?}");
        assert!(b[0].abs() < 0.01, "{b:?}");
        // The skin layer is left out, and a texel without hair weighs nothing.
        v.coverage.fill(0.0);
        assert_eq!(tangent_moments(&v), [[0.0; 4]; 2]);
    }

    #[test]
    fn the_default_hair_stands_mostly_up_and_leans_some() {
        let [a, _] = tangent_moments(&volume());
        let trace = a[0] + a[1] + a[2];
        assert!((trace - 1.0).abs() < 1e-3, "{a:?}");
        assert!(a[2] > 0.5 && a[2] < 0.999, "{a:?}");
    }
}
