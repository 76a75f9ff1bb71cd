//! The slice textures of the virtual-planes renderer (raycast-fur-virtual-planes §3.1–§3.2): the
//! tile cut by `N` planes across `u` and `N` across `v`, each plane textured with the hair of the
//! slab behind it (up to the next plane) seen from the side, as the fin texture sees its slab
//! ([`super::fin`]). Every plane has its own slice, so no pattern repeats within the tile (§3.2).
//!
//! The planes lean with the hair (§3.6): the slabs are cut in the tile sheared by the strands'
//! mean slant (`x − tilt.x · z`, `y − tilt.y · z`), so a slab holds whole strands rather than a
//! slanted strand's few heights, and the renderer traces the ray in the same shear.
//!
//! Layout: `2N` layers of `[height][width][4]`, straight RGBA8 with sRGB-encoded color, row 0
//! the top of the fur (height 1) as in the fin texture. Layer `i < N` is the slab
//! `x' ∈ [i/N, (i+1)/N)` seen along +x (its texture's x axis is the tile's y'); layer `N + j` the
//! slab `y' ∈ [j/N, (j+1)/N)` seen along +y (its x axis is x'). Both axes wrap with the tile.

use rayon::prelude::*;

use super::fin::{Piece, composite_row, depth_key};
use super::grid::fract_wrap;
use super::strand_table::StrandTable;
use crate::error::{PeltError, Result, check_range};
use crate::hair::Strand;
use crate::progress::{Progress, ProgressCallback};
use crate::threads::pool;

/// Most planes per family.
pub const MAX_PLANES: usize = 256;
/// Largest slice side, texels.
pub const MAX_SLICE_SIDE: usize = 1024;

/// How the slices are baked.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaneParams {
    /// Planes per family (across u and across v), `[1, MAX_PLANES]`; default 32 (the paper's
    /// tests use 32 to 128).
    pub planes: usize,
    /// Slice `[width, height]` in texels, each `[1, MAX_SLICE_SIDE]`: the width spans one tile
    /// along the plane, the height the fur depth; default 128 × 64.
    pub size: [usize; 2],
}

impl Default for PlaneParams {
    fn default() -> Self {
        PlaneParams {
            planes: 32,
            size: [128, 64],
        }
    }
}

impl PlaneParams {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming the first field out of range.
    pub fn validate(&self) -> Result<()> {
        check_range("planes", self.planes as f64, 1.0, MAX_PLANES as f64)?;
        check_range("plane_size[0]", self.size[0] as f64, 1.0, MAX_SLICE_SIDE as f64)?;
        check_range("plane_size[1]", self.size[1] as f64, 1.0, MAX_SLICE_SIDE as f64)
    }

    /// Bytes of the slices.
    pub fn bytes(&self) -> f64 {
        2.0 * self.planes as f64 * self.size[0] as f64 * self.size[1] as f64 * 4.0
    }

    /// Bytes the bake holds at its peak: the rows as made, then the slices they are gathered
    /// into (besides one row of pieces per thread).
    pub fn peak_bytes(&self) -> f64 {
        2.0 * self.bytes()
    }
}

/// The baked slices.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaneSlices {
    /// Planes per family `N`.
    pub planes: usize,
    /// Slice `[width, height]`.
    pub size: [usize; 2],
    /// The strands' mean slant, tile units across per fur depth up: the planes' lean.
    pub tilt: [f32; 2],
    /// `[2N][height][width][4]` straight RGBA8, sRGB color (see the module doc).
    pub rgba: Vec<u8>,
}

/// Bakes the slices of the strands that `keep(index)` keeps (the shells' strands: guard hairs
/// drawn as strands of their own are left out), in Pelt's thread pool; bit-identical for any
/// thread count.
///
/// # Errors
/// [`PeltError::InvalidParameter`] for a bad field, [`PeltError::MemoryLimit`] above the memory
/// limit, [`PeltError::Cancelled`] when `progress` asks to stop.
pub fn bake_slices(
    strands: &[Strand],
    keep: impl Fn(usize) -> bool + Sync,
    params: &PlaneParams,
    progress: Option<ProgressCallback<'_>>,
) -> Result<PlaneSlices> {
    params.validate()?;
    crate::memory::check("planes", params.peak_bytes(), || {
        format!("`planes` ({}) or `plane_size` ({:?})", params.planes, params.size)
    })?;
    pool().install(|| {
        let table = StrandTable::new(strands, |i, _| keep(i));
        let tilt = mean_slant(strands, &keep);
        let progress = Progress::new(params.size[1], progress);
        let rows = (0..params.size[1])
            .into_par_iter()
            .map(|row| {
                progress.check()?;
                let rgba = slice_row(&table, params, tilt, row);
                progress.advance(1)?;
                Ok(rgba)
            })
            .collect::<Result<Vec<Vec<u8>>>>()?;
        // Rows hold every layer's row `row`; the slices are layer-major.
        let [width, height] = params.size;
        let row_bytes = width * 4;
        let mut rgba = vec![0u8; 2 * params.planes * height * row_bytes];
        for (row, all) in rows.iter().enumerate() {
            for (layer, src) in all.chunks_exact(row_bytes).enumerate() {
                let at = (layer * height + row) * row_bytes;
                rgba[at..at + row_bytes].copy_from_slice(src);
            }
        }
        Ok(PlaneSlices {
            planes: params.planes,
            size: params.size,
            tilt: tilt.map(|t| t as f32),
            rgba,
        })
    })
}

/// The kept strands' mean slant (tip over root, laterally, per unit of height); zero without
/// any standing strand. Summed in strand order, so the result does not depend on threads.
fn mean_slant(strands: &[Strand], keep: &(impl Fn(usize) -> bool + Sync)) -> [f64; 2] {
    let mut sum = [0.0f64; 2];
    let mut count = 0usize;
    for (i, s) in strands.iter().enumerate() {
        let (Some(root), Some(tip)) = (s.points.first(), s.points.last()) else {
            continue;
        };
        let rise = tip[2] - root[2];
        if !(keep(i) && rise > 1e-6 && rise.is_finite()) {
            continue;
        }
        let slant = [(tip[0] - root[0]) / rise, (tip[1] - root[1]) / rise];
        if slant.iter().all(|v| v.is_finite()) {
            sum[0] += slant[0];
            sum[1] += slant[1];
            count += 1;
        }
    }
    if count == 0 {
        return [0.0; 2];
    }
    sum.map(|v| v / count as f64)
}

/// Row `row` of every slice, layer after layer (`2N` rows of `width` texels).
fn slice_row(table: &StrandTable, params: &PlaneParams, tilt: [f64; 2], row: usize) -> Vec<u8> {
    let [width, height] = params.size;
    let n = params.planes;
    let z = 1.0 - (row as f64 + 0.5) / height as f64;
    let mut slabs: Vec<Vec<Piece>> = (0..2 * n).map(|_| Vec::new()).collect();
    for k in (0..table.len()).filter(|&k| table.reaches(k, z)) {
        let cut = table.cut(k, z);
        let sheared = [fract_wrap(cut.x - tilt[0] * z), fract_wrap(cut.y - tilt[1] * z)];
        let [root, tip] = table.colors(k);
        let color: [f32; 3] = std::array::from_fn(|c| root[c] + (tip[c] - root[c]) * cut.along);
        // Across u the slab is picked by x' and the texture runs along y'; across v the reverse.
        for (family, (across, along)) in [(sheared[0], sheared[1]), (sheared[1], sheared[0])]
            .into_iter()
            .enumerate()
        {
            let slab = ((across * n as f64) as usize).min(n - 1);
            slabs[family * n + slab].push(Piece {
                depth: depth_key(across - slab as f64 / n as f64),
                x: along * width as f64,
                radius: cut.radius * width as f64,
                color,
            });
        }
    }
    let mut rgba = vec![0u8; 2 * n * width * 4];
    for (pieces, out) in slabs.iter().zip(rgba.chunks_exact_mut(width * 4)) {
        composite_row(pieces, width, out);
    }
    rgba
}

/// A named error for slices that do not match their sizes (a hand-made [`PlaneSlices`]).
pub fn check_slices(slices: &PlaneSlices) -> Result<()> {
    PlaneParams {
        planes: slices.planes,
        size: slices.size,
    }
    .validate()?;
    let expected = 2 * slices.planes * slices.size[0] * slices.size[1] * 4;
    if slices.rgba.len() != expected {
        return Err(PeltError::parameter(
            "planes.rgba",
            format!(
                "must hold {expected} bytes for the slices' sizes, got {}",
                slices.rgba.len()
            ),
        ));
    }
    if !slices.tilt.iter().all(|t| t.is_finite()) {
        return Err(PeltError::parameter(
            "planes.tilt",
            format!("must be finite, got {:?}", slices.tilt),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hair::Coat;

    /// A straight strand from `root` leaning `lean` per unit of height, 1 high, radius `radius`.
    fn strand(root: [f64; 2], lean: [f64; 2], radius: f64) -> Strand {
        let points = (0..=8)
            .map(|k| {
                let z = k as f64 / 8.0;
                [root[0] + lean[0] * z, root[1] + lean[1] * z, z]
            })
            .collect();
        Strand {
            root,
            points,
            radii: vec![radius; 9],
            root_color: [1.0; 3],
            tip_color: [1.0; 3],
            coat: Coat::Undercoat,
        }
    }

    fn alpha(slices: &PlaneSlices, layer: usize, row: usize, texel: usize) -> f64 {
        let [w, h] = slices.size;
        f64::from(slices.rgba[((layer * h + row) * w + texel) * 4 + 3]) / 255.0
    }

    #[test]
    fn an_upright_strand_shows_in_its_two_slabs_only_with_its_exact_width() {
        let params = PlaneParams {
            planes: 4,
            size: [32, 8],
        };
        // Root at x = 0.3 (slab 1 of 4 across u), y = 0.6 (slab 2 across v), 2 texels wide.
        let r = 1.0 / 32.0;
        let s = bake_slices(&[strand([0.3, 0.6], [0.0; 2], r)], |_| true, &params, None).unwrap();
        assert_eq!(s.tilt, [0.0, 0.0]);
        for layer in 0..8 {
            for row in 0..8 {
                // Across u the texture runs along y: the strand spans 0.6·32 ± 1 = 19.2 ± 1.
                // Across v it runs along x: 9.6 ± 1.
                let (shown, center): (bool, f64) = match layer {
                    1 => (true, 0.6 * 32.0),
                    6 => (true, 0.3 * 32.0),
                    _ => (false, 0.0),
                };
                for texel in 0..32 {
                    let exact = if shown {
                        let (lo, hi) = (center - 1.0, center + 1.0);
                        (hi.min(texel as f64 + 1.0) - lo.max(texel as f64)).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    let got = alpha(&s, layer, row, texel);
                    assert!(
                        (got - exact).abs() <= 0.5 / 255.0 + 1e-9,
                        "{layer} {row} {texel}: {got} vs {exact}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_planes_lean_with_the_hair() {
        let params = PlaneParams {
            planes: 8,
            size: [32, 16],
        };
        // Leaning half a tile across u over its height: sheared upright, in one slab at all heights.
        let s = bake_slices(&[strand([0.1, 0.5], [0.5, 0.0], 0.01)], |_| true, &params, None).unwrap();
        assert_eq!(s.tilt, [0.5, 0.0]);
        let slab = (0.1 * 8.0) as usize;
        for row in 0..16 {
            let covered: Vec<usize> = (0..8)
                .filter(|&l| (0..32).any(|t| alpha(&s, l, row, t) > 0.0))
                .collect();
            assert_eq!(covered, vec![slab], "row {row}");
        }
    }

    #[test]
    fn left_out_strands_and_bad_sizes() {
        let params = PlaneParams {
            planes: 2,
            size: [8, 4],
        };
        let s = bake_slices(&[strand([0.3, 0.6], [0.0; 2], 0.1)], |_| false, &params, None).unwrap();
        assert!(s.rgba.chunks_exact(4).all(|px| px[3] == 0));
        for (planes, size, name) in [
            (0, [8, 4], "planes"),
            (257, [8, 4], "planes"),
            (2, [0, 4], "plane_size[0]"),
        ] {
            let bad = PlaneParams { planes, size };
            let err = bake_slices(&[], |_| true, &bad, None).unwrap_err().to_string();
            assert!(err.contains(name), "{err}");
        }
    }

    #[test]
    fn same_bytes_for_any_thread_count() {
        let hair = crate::hair::HairParams {
            density: 400,
            ..Default::default()
        };
        let strands = crate::hair::grow_strands(&hair).unwrap();
        let params = PlaneParams {
            planes: 8,
            size: [32, 16],
        };
        let bake = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| bake_slices(&strands, |_| true, &params, None).unwrap())
        };
        assert_eq!(bake(1), bake(3));
    }
}
