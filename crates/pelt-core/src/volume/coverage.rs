//! Anti-aliased coverage of a hair's cross-section in the texels of one shell layer.
//!
//! Where a hair pierces the horizontal plane of a shell layer its cross-section is a disk; each
//! texel it touches receives the share of the texel that the disk covers (`prt-shell-fur`, §2.1,
//! "the percent of each hair that crosses a horizontal plane at the center of each texel"). The
//! paper limits hairs to one texel of width, splits the disk into four cases (Figure 2) and
//! approximates the circular segments ("chords") after Harris and Stocker and the corner pieces
//! ("wedges") by a quarter disk, because the exact area needs an inverse trigonometric function and
//! a square root. Here [`disk_square_area`] is exact in closed form for any disk and rectangle, and
//! the paper's approximation ([`approx_area`], built from [`chord_approx_area`] and
//! [`wedge_approx_area`]) and a supersampled estimate ([`supersampled_area`]) are kept for
//! comparison. [`splat_disk`] adds a disk's coverage to a toroidal grid (Lengyel et al. 2001, §2.2:
//! the tile repeats, so a hair near an edge also covers texels on the opposite side).

use std::f64::consts::PI;
use std::str::FromStr;

use super::footprint::{FootprintScratch, visit_exact};
use super::grid::{floor_i64, fract_wrap, wrap_near};
use crate::error::{Num, PeltError, Result};

thread_local! {
    /// Buffers of the exact footprint, reused by every disk splatted on this thread.
    static SCRATCH: std::cell::RefCell<FootprintScratch> = std::cell::RefCell::default();
}

/// Most sub-samples per axis in [`CoverageMode::Supersample`].
pub const MAX_SUPERSAMPLE: u32 = 64;
/// Largest grid side [`splat_disk`] accepts.
pub const MAX_RESOLUTION: usize = 1 << 16;

/// How the covered share of a texel is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CoverageMode {
    /// Closed-form area ([`disk_square_area`]).
    Exact,
    /// The paper's chord and wedge approximation ([`approx_area`]).
    Approx,
    /// `n × n` point samples per texel ([`supersampled_area`]).
    Supersample(u32),
}

impl FromStr for CoverageMode {
    type Err = PeltError;

    /// Parses `exact`, `approx` or `supersample:N` with `N` in `[1, MAX_SUPERSAMPLE]`.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] named `coverage` for any other string.
    fn from_str(s: &str) -> Result<Self> {
        let bad = || {
            PeltError::parameter(
                "coverage",
                format!(
                    "must be `exact`, `approx` or `supersample:N` with N in [1, {MAX_SUPERSAMPLE}], got `{s}`"
                ),
            )
        };
        match s {
            "exact" => Ok(CoverageMode::Exact),
            "approx" => Ok(CoverageMode::Approx),
            _ => {
                let n: u32 = s
                    .strip_prefix("supersample:")
                    .and_then(|n| n.parse().ok())
                    .ok_or_else(bad)?;
                if (1..=MAX_SUPERSAMPLE).contains(&n) {
                    Ok(CoverageMode::Supersample(n))
                } else {
                    Err(bad())
                }
            }
        }
    }
}

impl CoverageMode {
    /// Area of the disk `(cx, cy, r)` inside the rectangle `[x0, x1] × [y0, y1]` by this mode.
    #[allow(clippy::too_many_arguments)]
    pub fn area(self, cx: f64, cy: f64, r: f64, x0: f64, y0: f64, x1: f64, y1: f64) -> f64 {
        match self {
            CoverageMode::Exact => disk_square_area(cx, cy, r, x0, y0, x1, y1),
            CoverageMode::Approx => approx_area(cx, cy, r, x0, y0, x1, y1),
            CoverageMode::Supersample(n) => supersampled_area(cx, cy, r, x0, y0, x1, y1, n),
        }
    }
}

/// Exact area of the intersection of the disk of centre `(cx, cy)` and radius `r` with the
/// rectangle `[x0, x1] × [y0, y1]`.
///
/// Closed form by inclusion–exclusion over the four corners of the rectangle of
/// `Q(x, y)`, the area of the disk below and left of `(x, y)`, which integrates the disk's vertical
/// chord with the antiderivative of `sqrt(r² − x²)`. A radius `r <= 0` (or NaN) or an empty
/// rectangle gives 0. The absolute error is a few ulps of `r²` where the circle crosses the
/// rectangle (below 1e-9 for radii up to a thousand times the rectangle's side, measured in
/// the rectangle's units of one texel); rectangles wholly inside or outside the disk are exact.
#[allow(clippy::too_many_arguments)]
pub fn disk_square_area(cx: f64, cy: f64, r: f64, x0: f64, y0: f64, x1: f64, y1: f64) -> f64 {
    if !(r > 0.0 && x1 > x0 && y1 > y0) {
        return 0.0;
    }
    // A texel wholly inside a large disk is the common case deep inside a clump; it is also where
    // the inclusion–exclusion below would lose the most digits (terms of order r²).
    let (dx, dy) = (
        (x0 - cx).abs().max((x1 - cx).abs()),
        (y0 - cy).abs().max((y1 - cy).abs()),
    );
    if dx * dx + dy * dy <= r * r {
        return (x1 - x0) * (y1 - y0);
    }
    // Work relative to the centre, clamped to the disk's bounding box: outside it Q is constant
    // along that axis, and clamping keeps huge rectangles from costing precision.
    let a0 = (x0 - cx).clamp(-r, r);
    let a1 = (x1 - cx).clamp(-r, r);
    let b0 = (y0 - cy).clamp(-r, r);
    let b1 = (y1 - cy).clamp(-r, r);
    if a0 >= a1 || b0 >= b1 {
        return 0.0;
    }
    if a0 == -r && a1 == r && b0 == -r && b1 == r {
        return PI * r * r;
    }
    let area = quadrant(a1, b1, r) - quadrant(a0, b1, r) - quadrant(a1, b0, r) + quadrant(a0, b0, r);
    area.clamp(0.0, ((a1 - a0) * (b1 - b0)).min(PI * r * r))
}

/// `∫₀ˣ sqrt(r² − t²) dt` for `x` in `[−r, r]`.
fn half_chord_integral(x: f64, r: f64) -> f64 {
    let h = (r * r - x * x).max(0.0).sqrt();
    0.5 * (x * h + r * r * (x / r).clamp(-1.0, 1.0).asin())
}

/// Area of the disk of radius `r` at the origin within `X <= x, Y <= y`, for `x, y` in `[−r, r]`.
///
/// The vertical chord at `X` spans `[−h, h]`, `h = sqrt(r² − X²)`; its part below `y` is `2h`
/// where `h <= y`, `y + h` where `h > |y|` (that is `|X| < s = sqrt(r² − y²)`), and 0 where
/// `h <= −y`.
fn quadrant(x: f64, y: f64, r: f64) -> f64 {
    let s = (r * r - y * y).max(0.0).sqrt();
    let integral = |from: f64, to: f64| half_chord_integral(to, r) - half_chord_integral(from, r);
    let mid = x.clamp(-s, s);
    let middle = y * (mid + s) + integral(-s, mid);
    if y < 0.0 {
        return middle;
    }
    2.0 * integral(-r, x.min(-s)) + middle + 2.0 * integral(s, x.max(s))
}

/// Harris and Stocker's approximation of the circular segment of depth `d` (its sagitta) of a
/// circle of radius `r`: `A = 4/3·d·m + d³/(4m)` with half-chord `m = sqrt(d(2r − d))`, within
/// 0.8 % of the true area for `d <= r` (`prt-shell-fur`, §2.1, equation 1).
///
/// Depths beyond `r` use the complement of the opposite segment, where the formula itself would
/// diverge; `d <= 0` gives 0 and `d >= 2r` the whole disk.
pub fn chord_approx_area(r: f64, d: f64) -> f64 {
    if !(d > 0.0 && r > 0.0) {
        return 0.0;
    }
    if d >= 2.0 * r {
        return PI * r * r;
    }
    if d > r {
        return PI * r * r - chord_approx_area(r, 2.0 * r - d);
    }
    let m = (d * (2.0 * r - d)).sqrt();
    4.0 / 3.0 * d * m + d * d * d / (4.0 * m)
}

/// The paper's wedge approximation: the piece of a disk beyond a texel corner, bounded by straight
/// sides of lengths `s1` and `s2` along the texel edges, as a quarter disk of radius
/// `(s1 + s2) / 2` (`prt-shell-fur`, §2.1, equation 2; the paper gives no error bound).
pub fn wedge_approx_area(s1: f64, s2: f64) -> f64 {
    let radius = 0.5 * (s1 + s2);
    0.25 * PI * radius * radius
}

/// The paper's approximate area of a disk inside a rectangle: the disk minus the chords cut off
/// by the four sides plus the wedges beyond the corners, which the chords count twice (the
/// general form of the four cases of Figure 2, `prt-shell-fur` §2.1).
///
/// Chords and wedges come from [`chord_approx_area`] and [`wedge_approx_area`]; which pieces
/// exist is decided exactly, so a disk wholly inside or wholly outside is exact and any size of
/// disk is handled, although the paper only meant it for hairs at most one texel wide. The result
/// is clamped to `[0, min(disk, rectangle)]`.
#[allow(clippy::too_many_arguments)]
pub fn approx_area(cx: f64, cy: f64, r: f64, x0: f64, y0: f64, x1: f64, y1: f64) -> f64 {
    if !(r > 0.0 && x1 > x0 && y1 > y0) {
        return 0.0;
    }
    // How far the disk reaches beyond each side: left, right, bottom, top.
    let cap = |beyond: f64| chord_approx_area(r, beyond);
    let caps = cap(x0 - cx + r) + cap(cx + r - x1) + cap(y0 - cy + r) + cap(cy + r - y1);
    // Centre relative to each corner, measured outwards along both of its sides.
    let corners = corner_approx(x0 - cx, y0 - cy, r)
        + corner_approx(cx - x1, y0 - cy, r)
        + corner_approx(x0 - cx, cy - y1, r)
        + corner_approx(cx - x1, cy - y1, r);
    let disk = PI * r * r;
    (disk - caps + corners).clamp(0.0, ((x1 - x0) * (y1 - y0)).min(disk))
}

/// Approximate area of the disk of radius `r` in the quadrant `u > 0, v > 0` when its centre is
/// at `(u, v)` in the quadrant's frame.
fn corner_approx(u: f64, v: f64, r: f64) -> f64 {
    let cap = |beyond: f64| chord_approx_area(r, beyond);
    if u <= -r || v <= -r {
        return 0.0;
    }
    // The disk lies wholly on the outer side of one line: the quadrant cuts a single chord.
    if v >= r {
        return cap(r + u);
    }
    if u >= r {
        return cap(r + v);
    }
    if u * u + v * v < r * r {
        // The corner is inside the disk: the paper's wedge, with sides from the corner to the
        // circle along each line.
        let s1 = u + (r * r - v * v).sqrt();
        let s2 = v + (r * r - u * u).sqrt();
        return wedge_approx_area(s1, s2);
    }
    // Both lines cut the disk but the corner is outside it, so the two chords do not meet: the
    // quadrant holds nothing, one whole chord, or the disk less the two inner chords.
    match (u > 0.0, v > 0.0) {
        (false, false) => 0.0,
        (false, true) => cap(r + u),
        (true, false) => cap(r + v),
        (true, true) => PI * r * r - cap(r - u) - cap(r - v),
    }
}

/// Area of the disk inside the rectangle estimated from `n × n` samples at the centres of a
/// regular grid of sub-rectangles (`n = 0` counts as 1); the error falls like `1/n` along the rim.
#[allow(clippy::too_many_arguments)]
pub fn supersampled_area(cx: f64, cy: f64, r: f64, x0: f64, y0: f64, x1: f64, y1: f64, n: u32) -> f64 {
    if !(r > 0.0 && x1 > x0 && y1 > y0) {
        return 0.0;
    }
    let n = n.max(1);
    let (dx, dy) = ((x1 - x0) / f64::from(n), (y1 - y0) / f64::from(n));
    let mut inside = 0u64;
    for j in 0..n {
        let y = y0 + (f64::from(j) + 0.5) * dy - cy;
        for i in 0..n {
            let x = x0 + (f64::from(i) + 0.5) * dx - cx;
            inside += u64::from(x * x + y * y < r * r);
        }
    }
    inside as f64 * dx * dy
}

/// Calls `visit(texel, share)` for each texel of a toroidal `resolution × resolution` grid over
/// the unit tile that the disk `(cx, cy, r)` touches, with the covered share of the texel (its
/// covered area over the texel's area). Texels are indexed `row * resolution + column`, row 0 at
/// `y = 0`; the centre is wrapped modulo 1, and pieces of the disk past a tile edge land on the
/// opposite side, so the shares add up to `πr²·resolution²` (exactly, up to rounding, for
/// [`CoverageMode::Exact`]). A texel can be visited twice when the disk is nearly a tile wide.
///
/// # Errors
/// [`PeltError::InvalidParameter`] when `resolution` is 0 or above [`MAX_RESOLUTION`], `cx` or
/// `cy` is not finite, or `r` is outside `[0, 0.5)` (a wider disk would overlap itself on the
/// torus and cover a texel more than once).
pub fn disk_texel_coverage(
    resolution: usize,
    cx: f64,
    cy: f64,
    r: f64,
    mode: CoverageMode,
    mut visit: impl FnMut(usize, f64),
) -> Result<()> {
    if !(1..=MAX_RESOLUTION).contains(&resolution) {
        return Err(PeltError::parameter(
            "resolution",
            format!("must be in [1, {MAX_RESOLUTION}], got {resolution}"),
        ));
    }
    for (name, value) in [("cx", cx), ("cy", cy)] {
        if !value.is_finite() {
            return Err(PeltError::parameter(
                name,
                format!("must be finite, got {}", Num(value)),
            ));
        }
    }
    if !(0.0..0.5).contains(&r) {
        return Err(PeltError::parameter(
            "r",
            format!("must be in [0, 0.5), got {}", Num(r)),
        ));
    }
    SCRATCH.with_borrow_mut(|scratch| {
        visit_disk_texels(resolution, cx, cy, r, mode, scratch, |texel, _, share| {
            visit(texel, share);
        });
    });
    Ok(())
}

/// The body of [`disk_texel_coverage`] for arguments already known to be valid (the volume bake
/// checks its strands once instead of once per disk), with the caller's buffers; `visit` also gets
/// the texel's row.
pub(crate) fn visit_disk_texels(
    resolution: usize,
    cx: f64,
    cy: f64,
    r: f64,
    mode: CoverageMode,
    scratch: &mut FootprintScratch,
    mut visit: impl FnMut(usize, usize, f64),
) {
    // In texel units the texel area is 1, so areas are already shares of a texel.
    let res = resolution as f64;
    let (px, py, pr) = (fract_wrap(cx) * res, fract_wrap(cy) * res, r * res);
    // Within [-res/2, 3·res/2] since the centre is in [0, res] and pr < res / 2: fits an i64,
    // and every index of the span is within one tile of [0, res).
    let span = |c: f64| (floor_i64(c - pr), floor_i64(c + pr));
    let ((ix0, ix1), (iy0, iy1)) = (span(px), span(py));
    let n = resolution as i64;
    let wrap = |i: i64| wrap_near(i, n);
    if mode == CoverageMode::Exact {
        if ix0 >= 0 && ix1 < n && iy0 >= 0 && iy1 < n {
            // Most disks lie inside the tile: plain offsets from the footprint's first texel.
            let origin = iy0 as usize * resolution + ix0 as usize;
            visit_exact(
                px,
                py,
                pr,
                (ix0, ix1),
                (iy0, iy1),
                scratch,
                |column, row, share| {
                    visit(origin + row * resolution + column, iy0 as usize + row, share);
                },
            );
            return;
        }
        visit_exact(
            px,
            py,
            pr,
            (ix0, ix1),
            (iy0, iy1),
            scratch,
            |column, row, share| {
                let row = wrap(iy0 + row as i64);
                visit(row * resolution + wrap(ix0 + column as i64), row, share);
            },
        );
        return;
    }
    for iy in iy0..=iy1 {
        let y0 = iy as f64;
        for ix in ix0..=ix1 {
            let x0 = ix as f64;
            let share = mode.area(px, py, pr, x0, y0, x0 + 1.0, y0 + 1.0);
            if share > 0.0 {
                visit(wrap(iy) * resolution + wrap(ix), wrap(iy), share);
            }
        }
    }
}

/// Adds the covered share of each texel of the disk `(cx, cy, r)` (tile units) to the toroidal
/// `resolution × resolution` grid `grid` (row-major, row 0 at `y = 0`); see
/// [`disk_texel_coverage`].
///
/// # Errors
/// [`PeltError::InvalidParameter`] when `grid` does not hold `resolution²` values, or for the
/// reasons of [`disk_texel_coverage`].
pub fn splat_disk(
    grid: &mut [f32],
    resolution: usize,
    cx: f64,
    cy: f64,
    r: f64,
    mode: CoverageMode,
) -> Result<()> {
    if resolution.checked_mul(resolution) != Some(grid.len()) {
        return Err(PeltError::parameter(
            "grid",
            format!("must hold resolution² = {resolution}² values, got {}", grid.len()),
        ));
    }
    disk_texel_coverage(resolution, cx, cy, r, mode, |texel, share| {
        grid[texel] += share as f32;
    })
}

#[cfg(test)]
mod tests;
