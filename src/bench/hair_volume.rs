//! A plausible hair density for the transfer benchmarks (prt-shell-fur §2.1: each hair adds the
//! share of a texel its cross-section covers where it crosses a layer): the strands sliced at each
//! layer height, each crossing splatted as a disk with its exact texel coverage (the same sum as
//! `splat_disk`), and the coverage-weighted strand direction as the tangent.
//!
//! This is only a stand-in until the volume bake exists; it skips filtering across heights.

use crate::error::Result;
use crate::hair::{HairParams, grow_strands};
use crate::volume::coverage::{CoverageMode, disk_texel_coverage};

/// Density (`[L][R][R]`) and unit hair tangents (texel units, z up; zero where no hair) of the
/// strands of `params`, with the fur depth `depth` texels tall.
pub(crate) fn hair_volume(
    params: &HairParams,
    resolution: usize,
    layers: usize,
    depth: f64,
) -> Result<(Vec<f32>, Vec<[f32; 3]>)> {
    let strands = grow_strands(params)?;
    let r2 = resolution * resolution;
    let mut density = vec![0.0f32; layers * r2];
    let mut tangents = vec![[0.0f32; 3]; layers * r2];
    for (l, (grid, tan)) in density
        .chunks_exact_mut(r2)
        .zip(tangents.chunks_exact_mut(r2))
        .enumerate()
    {
        let h = l as f64 / (layers - 1) as f64;
        for s in &strands {
            // The segment of the polyline that spans height h, if the strand reaches it.
            let Some(k) = s
                .points
                .windows(2)
                .position(|w| w[0][2] <= h && h <= w[1][2] && w[0][2] < w[1][2])
            else {
                continue;
            };
            let (a, b) = (s.points[k], s.points[k + 1]);
            let f = (h - a[2]) / (b[2] - a[2]);
            let (x, y) = (a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]));
            let r = s.radii[k] + f * (s.radii[k + 1] - s.radii[k]);
            let t = [
                (b[0] - a[0]) * resolution as f64,
                (b[1] - a[1]) * resolution as f64,
                (b[2] - a[2]) * depth,
            ];
            let len = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
            disk_texel_coverage(resolution, x, y, r, CoverageMode::Exact, |i, share| {
                grid[i] += share as f32;
                for c in 0..3 {
                    tan[i][c] += (share * t[c] / len) as f32;
                }
            })?;
        }
        for t in tan.iter_mut() {
            let len = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
            if len > 0.0 {
                *t = t.map(|c| c / len);
            }
        }
    }
    Ok((density, tangents))
}
