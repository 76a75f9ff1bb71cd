//! The continuous density model both transfer methods integrate, and the toroidal image operations
//! the sweep is built from.
//!
//! §2.2 of the PRT shell-fur paper marches through "voxels hit"; to make the brute-force march and
//! the layer sweep converge to the *same* integral, Pelt defines the density between samples:
//! texel `(x, y)` of layer `l` holds its value at its centre, laterally the field is the bilinear
//! interpolant of the texel centres on the torus, vertically it is linear between layers, zero
//! above the top layer and opaque below the skin (see [`super::transfer`]).
//!
//! Inside this module positions are *grid coordinates*: texel `i` has its centre at `i` (texel
//! units shifted by one half), so a bilinear sample needs no half-texel offsets.

/// Splits a grid coordinate into a wrapped integer part in `[0, res)` and a fraction in `[0, 1]`.
///
/// `rem_euclid` can round a tiny negative value up to exactly `res`; taking the integer part as
/// `res − 1` with fraction 1 then reads the same point without indexing out of range.
#[inline]
pub(super) fn wrap(coord: f64, res: usize) -> (usize, f64) {
    let r = coord.rem_euclid(res as f64);
    let i = (r.floor() as usize).min(res - 1);
    (i, r - i as f64)
}

/// Bilinear value of the toroidal `res × res` image `img` (row-major) at grid position `(gx, gy)`.
#[inline]
pub(super) fn bilinear(img: &[f32], res: usize, gx: f64, gy: f64) -> f64 {
    let (ix, fx) = wrap(gx, res);
    let (iy, fy) = wrap(gy, res);
    let ix1 = if ix + 1 == res { 0 } else { ix + 1 };
    let iy1 = if iy + 1 == res { 0 } else { iy + 1 };
    let (r0, r1) = (iy * res, iy1 * res);
    let top = f64::from(img[r0 + ix]) * (1.0 - fx) + f64::from(img[r0 + ix1]) * fx;
    let bottom = f64::from(img[r1 + ix]) * (1.0 - fx) + f64::from(img[r1 + ix1]) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// One term of [`add_shifted`]: the image and the factor its samples are scaled by.
pub(super) struct Term<'a> {
    pub img: &'a [f32],
    pub scale: f32,
}

/// For every grid point `(x, y)`: `out[y·res + x] += Σ scale · bilinear(img, x + ox, y + oy)` over
/// `terms`, all images toroidal `res × res`.
///
/// The shift is the same for every point, so the four bilinear weights are constants and each
/// output row reads two source rows at a fixed column offset: the loop runs over contiguous
/// slices (two segments on either side of the wrap), which the compiler vectorizes.
pub(super) fn add_shifted(out: &mut [f32], res: usize, ox: f64, oy: f64, terms: &[Term<'_>]) {
    let (ix, fx) = wrap(ox, res);
    let (iy, fy) = wrap(oy, res);
    let (fx, fy) = (fx as f32, fy as f32);
    for term in terms {
        let w = [
            term.scale * (1.0 - fx) * (1.0 - fy),
            term.scale * fx * (1.0 - fy),
            term.scale * (1.0 - fx) * fy,
            term.scale * fx * fy,
        ];
        add_taps(out, res, ix, iy, term.img, w);
    }
}

/// `out[y][x] += w·(img[y'][x'], img[y'][x'+1], img[y'+1][x'], img[y'+1][x'+1])` with
/// `x' = x + ix`, `y' = y + iy`, all wrapped.
fn add_taps(out: &mut [f32], res: usize, ix: usize, iy: usize, img: &[f32], w: [f32; 4]) {
    for (y, row) in out.chunks_exact_mut(res).enumerate() {
        let r0 = (y + iy) % res;
        let r1 = if r0 + 1 == res { 0 } else { r0 + 1 };
        let a = &img[r0 * res..(r0 + 1) * res];
        let b = &img[r1 * res..(r1 + 1) * res];
        add_row(row, a, b, ix, w);
    }
}

/// `row[x] += w·(a[c], a[c+1], b[c], b[c+1])` with `c = (x + shift) mod n`, `c + 1` wrapped.
#[inline]
fn add_row(row: &mut [f32], a: &[f32], b: &[f32], shift: usize, w: [f32; 4]) {
    let n = row.len();
    // x in [0, n − shift − 1): both columns in range without wrapping.
    let first = n - shift - 1;
    segment(&mut row[..first], &a[shift..], &b[shift..], w);
    // x = n − shift − 1: column n − 1 and its neighbour 0.
    row[first] += w[0] * a[n - 1] + w[1] * a[0] + w[2] * b[n - 1] + w[3] * b[0];
    // x in [n − shift, n): columns x + shift − n, already past the wrap.
    segment(&mut row[first + 1..], a, b, w);
}

#[inline]
fn segment(out: &mut [f32], a: &[f32], b: &[f32], w: [f32; 4]) {
    let len = out.len();
    if len == 0 {
        return;
    }
    let (a0, a1) = (&a[..len], &a[1..=len]);
    let (b0, b1) = (&b[..len], &b[1..=len]);
    for x in 0..len {
        out[x] += w[0] * a0[x] + w[1] * a1[x] + w[2] * b0[x] + w[3] * b1[x];
    }
}

/// Box-prefiltered copies of one layer, level `m` averaging the continuous field over a
/// `2^m × 2^m` square, so the sweep can sample a long path sparsely without aliasing.
///
/// For an even width the square's edges fall on texel centres, where the trapezoid rule is exact
/// for the piecewise-linear field: level 1 is the `[¼, ½, ¼]` filter per axis, and level `m + 1`
/// averages two level-`m` values `2^(m−1)` texels either side. The top level (`2^m ≥ res`) is
/// the layer mean, the exact average over the whole torus.
pub(super) struct Pyramid {
    levels: Vec<Vec<f32>>,
}

impl Pyramid {
    /// The top level for resolution `res`: the smallest `m` with `2^m ≥ res`.
    pub(super) fn top_level(res: usize) -> usize {
        res.next_power_of_two().trailing_zeros() as usize
    }

    /// Levels `0..=max_level` of `layer` (`res × res`); `max_level` is capped at the top level.
    pub(super) fn build(layer: &[f32], res: usize, max_level: usize) -> Self {
        let top = Self::top_level(res);
        let max_level = max_level.min(top);
        let mut levels = vec![layer.to_vec()];
        for m in 1..=max_level {
            let next = if m == top {
                let mean = layer.iter().map(|&v| f64::from(v)).sum::<f64>() / layer.len() as f64;
                vec![mean as f32; layer.len()]
            } else if m == 1 {
                separable(&levels[0], res, |line, i, n| {
                    0.25 * line[(i + n - 1) % n] + 0.5 * line[i] + 0.25 * line[(i + 1) % n]
                })
            } else {
                let h = 1usize << (m - 2);
                // Halves added, not the sum halved: the sum of two densities near f32::MAX is
                // inf, which a zero σ then turned into NaN.
                separable(&levels[m - 1], res, |line, i, n| {
                    0.5 * line[(i + n - h % n) % n] + 0.5 * line[(i + h) % n]
                })
            };
            levels.push(next);
        }
        Pyramid { levels }
    }

    /// Level `m` (must have been built).
    pub(super) fn level(&self, m: usize) -> &[f32] {
        &self.levels[m.min(self.levels.len() - 1)]
    }
}

/// Applies the 1D filter `f(line, i, n)` along x, then along y, on a toroidal `res × res` image.
fn separable(img: &[f32], res: usize, f: impl Fn(&[f32], usize, usize) -> f32) -> Vec<f32> {
    let mut rows = vec![0.0; img.len()];
    for (src, dst) in img.chunks_exact(res).zip(rows.chunks_exact_mut(res)) {
        for (i, d) in dst.iter_mut().enumerate() {
            *d = f(src, i, res);
        }
    }
    let mut out = vec![0.0; img.len()];
    let mut column = vec![0.0; res];
    for x in 0..res {
        for (y, c) in column.iter_mut().enumerate() {
            *c = rows[y * res + x];
        }
        for y in 0..res {
            out[y * res + x] = f(&column, y, res);
        }
    }
    out
}

/// The exact weights of a layer gap's density integral on the texel grid.
///
/// For the bilinear field `ρ(x) = Σ_t ρ[t]·Λ(x − t)` (Λ the tent), the gap integral from grid point
/// `p` is `∫₀¹ (1−f)·ρ_lo(p + o + f·d) + f·ρ_hi(p + o + f·d) df = Σ_e ρ_lo[p+e]·W_lo(e) +
/// ρ_hi[p+e]·W_hi(e)`, with `W_lo(e) = ∫₀¹ (1−f)·Λ(e − o − f·d) df` (and `f` for `W_hi`): the
/// same small kernel for every `p`, since all rays of a direction are parallel. The kernel covers
/// the tent footprint of the segment, a band about three texels wide, so applying it costs about
/// as much as a few bilinear samples while integrating the model exactly instead of by the
/// midpoint rule. The weights are integrated numerically once per use, 64 samples per texel of
/// segment (error below 10⁻⁴ of a weight, far under the sweep's other errors).
pub(super) struct SegmentKernel {
    /// Per source row offset `ey`: the first column offset and the weights `(W_lo, W_hi)` of
    /// consecutive columns.
    rows: Vec<(usize, usize, Vec<[f32; 2]>)>,
}

impl SegmentKernel {
    /// The kernel of the segment from `o` to `o + d` (grid units) scaled by `scale`, for a
    /// `res × res` torus.
    pub(super) fn new(o: [f64; 2], d: [f64; 2], scale: f64, res: usize) -> Self {
        if res == 1 {
            // One texel: every sample lands in it, with the mean weights ∫(1−f) = ∫f = 1/2.
            return SegmentKernel {
                rows: vec![(0, 0, vec![[(0.5 * scale) as f32; 2]])],
            };
        }
        let x0 = o[0].min(o[0] + d[0]).floor() as i64;
        let y0 = o[1].min(o[1] + d[1]).floor() as i64;
        let x1 = o[0].max(o[0] + d[0]).floor() as i64 + 1;
        let y1 = o[1].max(o[1] + d[1]).floor() as i64 + 1;
        // A segment longer than the torus wraps onto it: the grid never exceeds `res × res`.
        let side = |extent: i64| (extent.saturating_add(1) as usize).min(res);
        let (w, h) = (side(x1 - x0), side(y1 - y0));
        let mut grid = vec![[0.0f64; 2]; w * h];
        let n = 8 + (64.0 * d[0].hypot(d[1])).ceil() as usize;
        for k in 0..n {
            let f = (k as f64 + 0.5) / n as f64;
            let (px, py) = (o[0] + f * d[0], o[1] + f * d[1]);
            let (ix, iy) = (px.floor(), py.floor());
            let (fx, fy) = (px - ix, py - iy);
            let (cx, cy) = (ix as i64 - x0, iy as i64 - y0);
            for (dx, dy, t) in [
                (0, 0, (1.0 - fx) * (1.0 - fy)),
                (1, 0, fx * (1.0 - fy)),
                (0, 1, (1.0 - fx) * fy),
                (1, 1, fx * fy),
            ] {
                let (gx, gy) = ((cx + dx).rem_euclid(res as i64), (cy + dy).rem_euclid(res as i64));
                let cell = &mut grid[gy as usize * w + gx as usize];
                cell[0] += t * (1.0 - f) / n as f64;
                cell[1] += t * f / n as f64;
            }
        }
        let wrap = |v: i64| v.rem_euclid(res as i64) as usize;
        let rows = grid
            .chunks_exact(w)
            .enumerate()
            .filter_map(|(ry, cells)| {
                let first = cells.iter().position(|c| c[0] + c[1] > 0.0)?;
                let last = cells.iter().rposition(|c| c[0] + c[1] > 0.0)?;
                let weights = cells[first..=last]
                    .iter()
                    .map(|c| [(c[0] * scale) as f32, (c[1] * scale) as f32])
                    .collect();
                Some((wrap(y0 + ry as i64), wrap(x0 + first as i64), weights))
            })
            .collect();
        SegmentKernel { rows }
    }

    /// `out[p] += Σ_e lo[p+e]·W_lo(e) + hi[p+e]·W_hi(e)` over the toroidal `res × res` grid.
    pub(super) fn apply(&self, out: &mut [f32], res: usize, lo: &[f32], hi: &[f32]) {
        for (y, row) in out.chunks_exact_mut(res).enumerate() {
            for (ey, ex, weights) in &self.rows {
                let r = (y + ey) % res;
                let (a, b) = (&lo[r * res..(r + 1) * res], &hi[r * res..(r + 1) * res]);
                for (k, w) in weights.iter().enumerate() {
                    add_column_shift(row, a, b, (ex + k) % res, *w);
                }
            }
        }
    }
}

/// `row[x] += w[0]·a[(x + shift) mod n] + w[1]·b[(x + shift) mod n]`, in two contiguous pieces.
#[inline]
fn add_column_shift(row: &mut [f32], a: &[f32], b: &[f32], shift: usize, w: [f32; 2]) {
    let n = row.len();
    let (head, tail) = row.split_at_mut(n - shift);
    for ((o, &x), &y) in head.iter_mut().zip(&a[shift..]).zip(&b[shift..]) {
        *o += w[0] * x + w[1] * y;
    }
    for ((o, &x), &y) in tail.iter_mut().zip(a).zip(b) {
        *o += w[0] * x + w[1] * y;
    }
}
