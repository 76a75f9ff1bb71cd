//! Exact coverage of one disk over all the texels it touches, at the cost of a few arithmetic
//! operations per texel.
//!
//! [`super::coverage::disk_square_area`] evaluates the closed form of one texel from scratch:
//! four corner areas `Q(x, y)`, each with several square roots and arc sines. Over a disk's whole
//! footprint the texel corners form a grid, and every term of `Q` at a grid corner depends either
//! on the corner's column alone (`I(x)`, the antiderivative of the half chord) or on its row alone
//! (`s = sqrt(r² − y²)` and `I(s)`). Computing those once per column and per row leaves only
//! additions per corner, and each texel's area is the usual inclusion–exclusion of its four
//! corners. This is what lets the exact mode cost no more than the paper's approximation
//! (`prt-shell-fur` §2.1 chose the approximation because the exact area needs `asin` and `sqrt`).

use std::f64::consts::FRAC_PI_4;
use std::hint::black_box;
use std::sync::OnceLock;

/// Reusable buffers for [`visit_exact`], so a loop over many disks allocates once.
#[derive(Debug, Default)]
pub struct FootprintScratch {
    /// Per corner column: `(x, I(x))`.
    columns: Vec<(f64, f64)>,
    /// Per corner row: `(y, s, I(s))`.
    rows: Vec<(f64, f64, f64)>,
    /// Corner areas `Q` of the previous corner row.
    below: Vec<f64>,
    /// Corner areas `Q` of the current corner row.
    above: Vec<f64>,
}

/// `∫₀ˣ sqrt(r² − t²) dt` for `x` in `[−r, r]`.
fn half_chord_integral(x: f64, r: f64) -> f64 {
    let h = (r * r - x * x).max(0.0).sqrt();
    0.5 * (x * h + r * r * (x / r).clamp(-1.0, 1.0).asin())
}

/// `asin(−1)` and `asin(1)` as this platform's `asin` gives them (computed at run time, so that
/// they are the very values the calls they stand for would return).
fn asin_of_unit() -> [f64; 2] {
    static VALUES: OnceLock<[f64; 2]> = OnceLock::new();
    *VALUES.get_or_init(|| [black_box(-1.0f64).asin(), black_box(1.0f64).asin()])
}

/// [`half_chord_integral`] with the same operations and result, skipping the arc sine where its
/// value is known: at `x = ±r` (half the grid corners of a footprint lie on its bounding box,
/// clamped there) the argument is exactly ±1 and the chord `h` exactly 0, and at `x = 0` (the
/// rows on the bounding box, where `s = 0`) the argument and the result are `x` itself.
#[inline]
fn half_chord_integral_fast(x: f64, r: f64, asin_unit: [f64; 2]) -> f64 {
    if x == r || x == -r {
        // h = sqrt(max(r² − x², 0)) = 0, since x² and r² are the same product.
        let a = asin_unit[usize::from(x > 0.0)];
        return 0.5 * (x * 0.0 + r * r * a);
    }
    if x == 0.0 {
        // asin(±0) = ±0, r²·(±0) + x·h = ±0 with the sign of x, halved.
        return 0.5 * x;
    }
    half_chord_integral(x, r)
}

/// Calls `visit(column, row, share)` for every texel `[ix, ix+1] × [iy, iy+1]` with
/// `ix0 <= ix <= ix1`, `iy0 <= iy <= iy1` that the disk of centre `(cx, cy)` and radius `r`
/// (texel units, `r > 0`) covers, with the covered area (a share of the unit texel, in `[0, 1]`).
/// `column` and `row` count from `ix0` and `iy0`.
///
/// The area is exact up to rounding: the inclusion–exclusion of corner values of order `r²`
/// leaves an absolute error of a few ulps of `r²`.
#[allow(clippy::too_many_arguments)]
pub fn visit_exact(
    cx: f64,
    cy: f64,
    r: f64,
    (ix0, ix1): (i64, i64),
    (iy0, iy1): (i64, i64),
    scratch: &mut FootprintScratch,
    visit: impl FnMut(usize, usize, f64),
) {
    if r.is_nan() || r <= 0.0 || ix1 < ix0 || iy1 < iy0 {
        return;
    }
    let (columns, rows) = ((ix1 - ix0 + 2) as usize, (iy1 - iy0 + 2) as usize);
    if columns <= SMALL && rows <= SMALL {
        // Hairs a few texels wide, nearly all of them: buffers on the stack.
        let mut xs = [(0.0, 0.0); SMALL];
        let mut ys = [(0.0, 0.0, 0.0); SMALL];
        let (mut below, mut above) = ([0.0; SMALL], [0.0; SMALL]);
        let buffers = Buffers {
            columns: &mut xs[..columns],
            rows: &mut ys[..rows],
            below: &mut below[..columns],
            above: &mut above[..columns],
        };
        visit_corners(cx, cy, r, (ix0, iy0), buffers, visit);
        return;
    }
    scratch.columns.resize(columns, (0.0, 0.0));
    scratch.rows.resize(rows, (0.0, 0.0, 0.0));
    scratch.below.resize(columns, 0.0);
    scratch.above.resize(columns, 0.0);
    let buffers = Buffers {
        columns: &mut scratch.columns,
        rows: &mut scratch.rows,
        below: &mut scratch.below,
        above: &mut scratch.above,
    };
    visit_corners(cx, cy, r, (ix0, iy0), buffers, visit);
}

/// Corner axes up to this long use buffers on the stack.
const SMALL: usize = 8;

/// The per-footprint buffers of [`visit_corners`], as long as its corner columns and rows.
struct Buffers<'a> {
    /// Per corner column: `(x, I(x))`.
    columns: &'a mut [(f64, f64)],
    /// Per corner row: `(y, s, I(s))`.
    rows: &'a mut [(f64, f64, f64)],
    /// Corner areas `Q` of the previous corner row.
    below: &'a mut [f64],
    /// Corner areas `Q` of the current corner row.
    above: &'a mut [f64],
}

/// The body of [`visit_exact`]: the footprint's first texel is `(ix0, iy0)`, its size that of
/// the buffers (corner columns and rows, one more than texels).
fn visit_corners(
    cx: f64,
    cy: f64,
    r: f64,
    (ix0, iy0): (i64, i64),
    buffers: Buffers<'_>,
    mut visit: impl FnMut(usize, usize, f64),
) {
    let Buffers {
        columns,
        rows,
        mut below,
        mut above,
    } = buffers;
    let i_r = FRAC_PI_4 * r * r; // I(r); I is odd, so I(−r) = −I(r).
    let asin_unit = asin_of_unit();
    for (ix, column) in (ix0..).zip(columns.iter_mut()) {
        let x = (ix as f64 - cx).clamp(-r, r);
        *column = (x, half_chord_integral_fast(x, r, asin_unit));
    }
    for (iy, row) in (iy0..).zip(rows.iter_mut()) {
        let y = (iy as f64 - cy).clamp(-r, r);
        let s = (r * r - y * y).max(0.0).sqrt();
        *row = (y, s, half_chord_integral_fast(s, r, asin_unit));
    }
    // Q(x, y): the disk's area within X <= x, Y <= y (relative to the centre, both in [−r, r]).
    // The vertical chord at X spans [−h, h]; its part below y is 2h where h <= y (|X| >= s, upper
    // half-plane only), y + h where |X| < s, and nothing where h <= −y.
    let corner = |&(x, i_x): &(f64, f64), &(y, s, i_s): &(f64, f64, f64)| -> f64 {
        if x < -s {
            // Left of the chord band (every corner of the footprint's first column): the middle
            // term y·(−s + s) − I(s) + I(s) is an exact +0, which leaves these.
            return if y < 0.0 { 0.0 } else { 2.0 * (i_x + i_r) };
        }
        let (mid, i_mid) = if x > s { (s, i_s) } else { (x, i_x) };
        let middle = y * (mid + s) + i_mid + i_s;
        if y < 0.0 {
            return middle;
        }
        let left = -i_s + i_r;
        let right = if x > s { i_x - i_s } else { 0.0 };
        2.0 * left + middle + 2.0 * right
    };
    // The first corner row usually lies on the bounding box, y = −r, where s = I(s) = 0 and
    // every corner value above is an exact +0 (the terms cancel exactly or vanish); the last
    // usually lies at y = r, where the three cases reduce to the sums written out below, with
    // the same roundings. Rounding can keep either row off the box; then it is done in full.
    if rows[0].0 == -r {
        below.fill(0.0);
    } else {
        for (q, c) in below.iter_mut().zip(columns.iter()) {
            *q = corner(c, &rows[0]);
        }
    }
    for (row, top) in rows[1..].iter().enumerate() {
        if top.0 == r {
            for (q, &(x, i_x)) in above.iter_mut().zip(columns.iter()) {
                *q = if x < 0.0 {
                    2.0 * (i_x + i_r)
                } else if x > 0.0 {
                    2.0 * i_r + 2.0 * i_x
                } else {
                    2.0 * i_r
                };
            }
        } else {
            for (q, c) in above.iter_mut().zip(columns.iter()) {
                *q = corner(c, top);
            }
        }
        for column in 0..columns.len() - 1 {
            let area = above[column + 1] - above[column] - below[column + 1] + below[column];
            // Rounding can leave ±ulp(r²) on texels the disk misses or fills.
            let share = area.clamp(0.0, 1.0);
            if share > 0.0 {
                visit(column, row, share);
            }
        }
        std::mem::swap(&mut below, &mut above);
    }
}
