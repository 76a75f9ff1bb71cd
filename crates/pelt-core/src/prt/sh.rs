//! Real spherical harmonics: the basis in which Pelt stores precomputed radiance transfer.
//!
//! Follows §2.3 ("PRT Basis Functions") of the PRT shell-fur paper: the real SH `Y_l^m` built from
//! the associated Legendre functions `P_l^m`, with `cos(mφ)` for `m > 0` and `sin(|m|φ)` for
//! `m < 0` (the paper's eq. 6). The paper keeps 5 bands (25 functions, [`PAPER_ORDER`]); Pelt
//! supports up to [`MAX_ORDER`] = 8 bands (64 functions).
//!
//! # Conventions
//!
//! - *Order* `n` means `n` bands `l = 0..n`, hence `n²` coefficients, stored at
//!   [`index`]`(l, m) = l² + l + m`.
//! - Directions are unit vectors `(x, y, z) = (sin θ cos φ, sin θ sin φ, cos θ)`; θ is measured
//!   from +Z, φ from +X towards +Y.
//! - Orthonormal: `∫ Y_i Y_j dω = δ_ij` over the sphere (4π).
//! - No Condon–Shortley phase: `Y_1^{-1} = c·y`, `Y_1^0 = c·z`, `Y_1^1 = c·x` with `c = √(3/4π)`,
//!   the usual graphics convention (Sloan, "Stupid Spherical Harmonics Tricks", 2008).
//! - Projection of `f` gives `c_i = ∫ f Y_i dω`, so `f ≈ Σ c_i Y_i`; a light of unit total power
//!   has `c_0 = Y_0^0 = 1/√(4π)`.
//!
//! Everything is computed in f64; [`eval_f32`] converts at the end for GPU-bound data.

use std::f64::consts::{PI, SQRT_2};

use glam::DVec3;
use rayon::prelude::*;

use super::sphere::gauss_legendre;
use crate::error::{Num, PeltError, Result};
use crate::threads::pool;

/// Highest supported order (bands `l = 0..8`).
pub const MAX_ORDER: usize = 8;

/// Number of coefficients at [`MAX_ORDER`].
pub const MAX_COEFFS: usize = MAX_ORDER * MAX_ORDER;

/// The order used by the paper (§2.3: "the 5 lowest order SH functions … 25 distinct functions").
pub const PAPER_ORDER: usize = 5;

/// How far a direction's length may stray from 1 (f32 normals arrive with errors near 1e-7).
const UNIT_TOLERANCE: f64 = 1e-5;

/// How far `R Rᵀ` may stray from the identity for a matrix to count as a rotation.
const ROTATION_TOLERANCE: f64 = 1e-6;

/// Number of coefficients of an order-`order` expansion (`order²`).
pub const fn coeff_count(order: usize) -> usize {
    order * order
}

/// Position of `Y_l^m` in a coefficient vector: `l² + l + m`. Requires `|m| ≤ l`.
pub fn index(l: usize, m: isize) -> usize {
    debug_assert!(m.unsigned_abs() <= l, "|m| must not exceed l");
    (l * l + l).wrapping_add_signed(m)
}

/// The band and degree `(l, m)` stored at position `i`: the inverse of [`index`].
pub fn band_of(i: usize) -> (usize, isize) {
    let l = i.isqrt();
    (l, i as isize - (l * l + l) as isize)
}

/// Checks that `order` is in `1..=MAX_ORDER`.
pub fn check_order(order: usize) -> Result<()> {
    if (1..=MAX_ORDER).contains(&order) {
        Ok(())
    } else {
        Err(PeltError::parameter(
            "order",
            format!("must be between 1 and {MAX_ORDER} bands, got {order}"),
        ))
    }
}

/// The order of a coefficient vector of length `len` (which must be `n²` with `1 ≤ n ≤ 8`).
pub fn order_of_len(len: usize) -> Result<usize> {
    let order = len.isqrt();
    if order * order != len || check_order(order).is_err() {
        return Err(PeltError::parameter(
            "coefficients",
            format!("length must be n² for 1 ≤ n ≤ {MAX_ORDER} (1, 4, 9, …, 64), got {len}"),
        ));
    }
    Ok(order)
}

/// `d` scaled to length 1 if it is finite and of length 1 within [`UNIT_TOLERANCE`]; the
/// renormalization keeps the basis exactly orthonormal for slightly-off inputs.
fn normalized(d: [f64; 3]) -> Option<[f64; 3]> {
    let d = DVec3::from(d);
    let len = d.length();
    (len.is_finite() && (len - 1.0).abs() <= UNIT_TOLERANCE).then(|| (d / len).to_array())
}

/// [`normalized`], or an error naming the parameter.
fn unit_direction(name: &str, d: [f64; 3]) -> Result<[f64; 3]> {
    normalized(d).ok_or_else(|| direction_error(name, d))
}

fn direction_error(name: &str, d: [f64; 3]) -> PeltError {
    PeltError::parameter(name, format!("must be a finite unit vector, got {d:?}"))
}

/// Checks that an output buffer holds exactly the coefficients of `order`.
fn check_len(name: &str, len: usize, order: usize) -> Result<()> {
    if len == coeff_count(order) {
        Ok(())
    } else {
        Err(PeltError::parameter(
            name,
            format!(
                "must hold {} coefficients for order {order}, got {len}",
                coeff_count(order)
            ),
        ))
    }
}

/// Evaluates all `order²` basis functions at the unit direction `d` into `out`; no checks.
///
/// Writes `Y_l^m = √2 Q_l^m(z) Re((x + iy)^m)` (and `Im` for `m < 0`), where
/// `Q_l^m = K_l^m P_l^m(z) / sin^m θ` is a polynomial in `z`. Folding `sin^m θ` into
/// `(x + iy)^m` makes `cos(mφ) sin^m θ` and `sin(mφ) sin^m θ` a complex-multiplication recurrence,
/// with no division by `sin θ` at the poles and no factorials. `Q` follows the standard stable
/// three-term recurrence in `l` for normalized Legendre functions.
fn eval_unit(order: usize, d: [f64; 3], out: &mut [f64]) {
    let [x, y, z] = d;
    // Q_m^m; starts at Q_0^0 = 1/√(4π).
    let mut q_mm = 0.5 / PI.sqrt();
    // Re and Im of (x + iy)^m.
    let (mut c, mut s) = (1.0, 0.0);
    for m in 0..order {
        if m > 0 {
            let mf = m as f64;
            q_mm *= ((2.0 * mf + 1.0) / (2.0 * mf)).sqrt();
            (c, s) = (x * c - y * s, x * s + y * c);
        }
        let (mut q_prev, mut q) = (0.0, q_mm);
        for l in m..order {
            if l > m {
                let (lf, mf) = (l as f64, m as f64);
                let a = ((4.0 * lf * lf - 1.0) / (lf * lf - mf * mf)).sqrt();
                let b = (((lf - 1.0) * (lf - 1.0) - mf * mf) / (4.0 * (lf - 1.0) * (lf - 1.0) - 1.0)).sqrt();
                (q_prev, q) = (q, a * (z * q - b * q_prev));
            }
            if m == 0 {
                out[index(l, 0)] = q;
            } else {
                let mi = m as isize;
                out[index(l, mi)] = SQRT_2 * q * c;
                out[index(l, -mi)] = SQRT_2 * q * s;
            }
        }
    }
}

/// Evaluates all `order²` basis functions at the unit direction `d` into `out`
/// (`out.len()` must be `order²`).
pub fn eval(order: usize, d: [f64; 3], out: &mut [f64]) -> Result<()> {
    check_order(order)?;
    check_len("out", out.len(), order)?;
    let d = unit_direction("direction", d)?;
    eval_unit(order, d, out);
    Ok(())
}

/// [`eval`] into a new vector.
pub fn eval_vec(order: usize, d: [f64; 3]) -> Result<Vec<f64>> {
    let mut out = vec![0.0; coeff_count(order.min(MAX_ORDER))];
    eval(order, d, &mut out)?;
    Ok(out)
}

/// [`eval`] for f32 data: computed in f64, rounded once at the end.
pub fn eval_f32(order: usize, d: [f32; 3], out: &mut [f32]) -> Result<()> {
    check_order(order)?;
    check_len("out", out.len(), order)?;
    let d = unit_direction("direction", d.map(f64::from))?;
    let mut tmp = [0.0; MAX_COEFFS];
    eval_unit(order, d, &mut tmp);
    for (o, t) in out.iter_mut().zip(&tmp) {
        *o = *t as f32;
    }
    Ok(())
}

/// The value `Σ c_i Y_i(d)` of an expansion at the unit direction `d`.
pub fn reconstruct(coeffs: &[f64], d: [f64; 3]) -> Result<f64> {
    let order = order_of_len(coeffs.len())?;
    let d = unit_direction("direction", d)?;
    let mut y = [0.0; MAX_COEFFS];
    eval_unit(order, d, &mut y);
    Ok(coeffs.iter().zip(&y).map(|(c, y)| c * y).sum())
}

/// Projects a function known at sample directions: `c_i = Σ_k weights[k]·values[k]·Y_i(d_k)`.
///
/// `weights` are the solid angles the samples stand for (e.g. `4π/n` for
/// [`fibonacci_directions`](super::sphere::fibonacci_directions)); all three slices must have the
/// same length.
pub fn project_samples(
    order: usize,
    directions: &[[f64; 3]],
    weights: &[f64],
    values: &[f64],
) -> Result<Vec<f64>> {
    check_order(order)?;
    let n = directions.len();
    for (name, len) in [("weights", weights.len()), ("values", values.len())] {
        if len != n {
            return Err(PeltError::parameter(
                name,
                format!("must have one entry per direction ({n}), got {len}"),
            ));
        }
    }
    let mut out = vec![0.0; coeff_count(order)];
    let mut y = [0.0; MAX_COEFFS];
    for (k, ((&d, &w), &v)) in directions.iter().zip(weights).zip(values).enumerate() {
        let d = normalized(d).ok_or_else(|| direction_error(&format!("directions[{k}]"), d))?;
        if !(w * v).is_finite() {
            return Err(PeltError::parameter(
                format!("weights[{k}] / values[{k}]"),
                format!("must be finite, got {} and {}", Num(w), Num(v)),
            ));
        }
        eval_unit(order, d, &mut y);
        for (o, y) in out.iter_mut().zip(&y) {
            *o += w * v * y;
        }
    }
    Ok(out)
}

/// Gauss–Legendre nodes in θ per image row: enough that even a one-row image integrates the
/// basis (trigonometric polynomials of degree ≤ 8 in θ) to machine precision.
fn row_nodes(height: usize) -> usize {
    64usize.div_ceil(height).clamp(4, 64)
}

/// Projects an equirectangular RGB float image (`width × height`, rows of `width` pixels of 3
/// floats, `rgb.len() == width·height·3`) onto the basis; returns one `[r, g, b]` per coefficient.
///
/// Row `r` covers polar angles `θ ∈ [rπ/h, (r+1)π/h]` (row 0 touches +Z), column `c` covers
/// azimuths `φ ∈ [2πc/w, 2π(c+1)/w]` from +X towards +Y. (Blender stores image rows bottom-up
/// and has its own azimuth origin, so the add-on reorders a world image to this layout first.)
///
/// Each pixel is taken as constant over its cell and the basis is integrated over the cell
/// exactly rather than sampled at its centre: the solid angle of a cell is `(cos θ0 − cos θ1)·Δφ`,
/// and the azimuthal integral of `cos(mφ)` / `sin(mφ)` is closed-form, while the polar part uses
/// Gauss–Legendre in θ. The projection of a constant image therefore has no non-DC leakage, and
/// the per-row work is separable (O(w·h·order) instead of O(w·h·order²)). Rows run in parallel in
/// Pelt's pool and are summed in row order, so the result does not depend on the thread count.
pub fn project_equirect(order: usize, width: usize, height: usize, rgb: &[f32]) -> Result<Vec<[f64; 3]>> {
    check_order(order)?;
    if width == 0 || height == 0 {
        return Err(PeltError::parameter(
            "image",
            format!("must have at least one pixel, got {width}×{height}"),
        ));
    }
    let expected = width.checked_mul(height).and_then(|p| p.checked_mul(3));
    if expected != Some(rgb.len()) {
        return Err(PeltError::parameter(
            "image",
            format!(
                "a {width}×{height} RGB image needs {} floats, got {}",
                width as u128 * height as u128 * 3,
                rgb.len()
            ),
        ));
    }
    if let Some(bad) = rgb.iter().position(|v| !v.is_finite()) {
        return Err(PeltError::parameter(
            "image",
            format!(
                "pixel {} (row {}, column {}) is not finite",
                bad / 3,
                bad / 3 / width,
                bad / 3 % width
            ),
        ));
    }

    // Azimuthal integrals per column and m: cos_int[m][c] = ∫ cos(mφ) dφ, sin_int likewise.
    let dphi = 2.0 * PI / width as f64;
    let mut cos_int = vec![vec![0.0; width]; order];
    let mut sin_int = vec![vec![0.0; width]; order];
    for c in 0..width {
        let (p0, p1) = (c as f64 * dphi, (c + 1) as f64 * dphi);
        cos_int[0][c] = dphi;
        for m in 1..order {
            let mf = m as f64;
            cos_int[m][c] = ((mf * p1).sin() - (mf * p0).sin()) / mf;
            sin_int[m][c] = ((mf * p0).cos() - (mf * p1).cos()) / mf;
        }
    }

    let (gx, gw) = gauss_legendre(row_nodes(height));
    let dtheta = PI / height as f64;
    let n = coeff_count(order);
    let rows: Vec<Vec<[f64; 3]>> = pool().install(|| {
        (0..height)
            .into_par_iter()
            .map(|r| {
                // Polar integral of the basis over the row: evaluating at azimuth 0 gives
                // √2·Q_l^m·sin^m θ for m > 0, which is the polar factor of both Y_l^{±m}.
                let (t0, t1) = (r as f64 * dtheta, (r + 1) as f64 * dtheta);
                let mut polar = [0.0; MAX_COEFFS];
                let mut y = [0.0; MAX_COEFFS];
                for (&x, &w) in gx.iter().zip(&gw) {
                    let theta = 0.5 * (t0 + t1) + 0.5 * (t1 - t0) * x;
                    let (st, ct) = theta.sin_cos();
                    eval_unit(order, [st, 0.0, ct], &mut y);
                    let weight = 0.5 * (t1 - t0) * w * st;
                    for (p, y) in polar.iter_mut().zip(&y) {
                        *p += weight * y;
                    }
                }
                // Azimuthal sums of the row's pixels against cos(mφ) and sin(mφ).
                let row = &rgb[r * width * 3..(r + 1) * width * 3];
                let mut a = [[0.0f64; 3]; MAX_ORDER];
                let mut b = [[0.0f64; 3]; MAX_ORDER];
                for (c, px) in row.chunks_exact(3).enumerate() {
                    for m in 0..order {
                        for ch in 0..3 {
                            a[m][ch] += f64::from(px[ch]) * cos_int[m][c];
                            b[m][ch] += f64::from(px[ch]) * sin_int[m][c];
                        }
                    }
                }
                (0..n)
                    .map(|i| {
                        let (l, m) = band_of(i);
                        let p = polar[index(l, m.abs())];
                        let az = if m >= 0 {
                            a[m as usize]
                        } else {
                            b[m.unsigned_abs()]
                        };
                        az.map(|v| p * v)
                    })
                    .collect()
            })
            .collect()
    });
    let mut out = vec![[0.0; 3]; n];
    for row in &rows {
        for (o, v) in out.iter_mut().zip(row) {
            for ch in 0..3 {
                o[ch] += v[ch];
            }
        }
    }
    Ok(out)
}

/// Zonal coefficients `z_l` (one per band, about +Z) of a uniform spherical cap of half-angle
/// `half_angle` (radians, `0 ≤ α ≤ π`) normalized to unit total power: `f = 1/(2π(1 − cos α))`
/// inside the cap, 0 outside.
///
/// `z_l = √((2l+1)/4π) · mean of P_l over the cap`. The mean is `(P_{l−1}(a) − P_{l+1}(a)) /
/// ((2l+1)(1 − a))` with `a = cos α`, which cancels catastrophically for narrow caps; expanding
/// `P_l` about 1 instead, `P_l(1 − s) = Σ_k C(l,k) C(l+k,k) (−s/2)^k`, gives the mean as the
/// polynomial `Σ_k C(l,k) C(l+k,k) (−s/2)^k / (k+1)` in `s = 1 − cos α = 2 sin²(α/2)`, accurate
/// down to `α = 0`, where it is the delta-function limit `z_l = √((2l+1)/4π)`.
pub fn cap_zonal(order: usize, half_angle: f64) -> Result<Vec<f64>> {
    check_order(order)?;
    if !(0.0..=PI).contains(&half_angle) {
        return Err(PeltError::parameter(
            "half_angle",
            format!("must be between 0 and π radians, got {}", Num(half_angle)),
        ));
    }
    let s = 2.0 * (0.5 * half_angle).sin().powi(2);
    Ok((0..order)
        .map(|l| {
            // term_k = C(l,k)·C(l+k,k)·(−s/2)^k, built by its ratio to term_{k−1}.
            let mut term = 1.0;
            let mut mean = 1.0;
            for k in 1..=l {
                let kf = k as f64;
                term *= (l as f64 - kf + 1.0) * (l as f64 + kf) / (kf * kf) * (-0.5 * s);
                mean += term / (kf + 1.0);
            }
            ((2 * l + 1) as f64 / (4.0 * PI)).sqrt() * mean
        })
        .collect())
}

/// Turns per-band zonal coefficients `z_l` (a function symmetric about +Z) into the coefficients
/// of the same function symmetric about the unit direction `d`:
/// `c_l^m = √(4π/(2l+1)) · z_l · Y_l^m(d)`. The order is `zonal.len()`.
pub fn zonal_to_direction(zonal: &[f64], d: [f64; 3]) -> Result<Vec<f64>> {
    let order = zonal.len();
    check_order(order)?;
    let d = unit_direction("direction", d)?;
    let mut out = vec![0.0; coeff_count(order)];
    eval_unit(order, d, &mut out);
    for (i, c) in out.iter_mut().enumerate() {
        let l = band_of(i).0;
        *c *= (4.0 * PI / (2 * l + 1) as f64).sqrt() * zonal[l];
    }
    Ok(out)
}

/// Coefficients of a directional light of angular radius `half_angle` around the unit direction
/// `d` (towards the light), as a uniform cap of unit total power; `half_angle = 0` is a delta light.
pub fn project_cap(order: usize, d: [f64; 3], half_angle: f64) -> Result<Vec<f64>> {
    zonal_to_direction(&cap_zonal(order, half_angle)?, d)
}

/// The per-band matrices that rotate SH coefficient vectors by one 3×3 rotation.
///
/// Built once per rotation by the recurrence of Ivanic & Ruedenberg (J. Phys. Chem. 100, 1996,
/// with the 1998 erratum), which derives band `l` from band `l − 1` and band 1 (the rotation
/// matrix itself, permuted to the `(y, z, x)` order of `Y_1^{-1}, Y_1^0, Y_1^1`). It is exact up to
/// rounding, unlike fitting from samples, and costs O(order³).
#[derive(Debug, Clone, PartialEq)]
pub struct ShRotation {
    order: usize,
    /// Band `l` as a row-major `(2l+1)×(2l+1)` matrix indexed by `(m + l, m' + l)`.
    bands: Vec<Vec<f64>>,
}

impl ShRotation {
    /// Prepares the rotation `r` (row-major; maps a direction `d` to `r·d`) for coefficient vectors
    /// of `order` bands. Applying it to the coefficients of `f` gives those of `g(ω) = f(rᵀω)`: a
    /// lobe pointing along `d` ends up pointing along `r·d`.
    ///
    /// `r` must be finite, orthonormal (within 1e-6) and proper (determinant +1).
    pub fn new(order: usize, r: [[f64; 3]; 3]) -> Result<Self> {
        check_order(order)?;
        check_rotation(&r)?;
        // Band 1 in the (y, z, x) order of m = −1, 0, 1.
        const AXIS: [usize; 3] = [1, 2, 0];
        let band1: Vec<f64> = (0..9).map(|k| r[AXIS[k / 3]][AXIS[k % 3]]).collect();
        let mut bands = vec![vec![1.0]];
        for l in 1..order {
            let next = if l == 1 {
                band1.clone()
            } else {
                ivanic_ruedenberg_band(l, &band1, &bands[l - 1])
            };
            bands.push(next);
        }
        Ok(ShRotation { order, bands })
    }

    /// The number of bands this rotation acts on.
    pub fn order(&self) -> usize {
        self.order
    }

    /// Band `l`'s `(2l+1)×(2l+1)` row-major matrix (`l < order`), indexed by `(m + l, m' + l)`.
    pub fn band(&self, l: usize) -> Option<&[f64]> {
        self.bands.get(l).map(Vec::as_slice)
    }

    /// Rotates `coeffs` (length `order²`) into `out` (same length).
    pub fn apply_into(&self, coeffs: &[f64], out: &mut [f64]) -> Result<()> {
        check_len("coefficients", coeffs.len(), self.order)?;
        check_len("out", out.len(), self.order)?;
        for (l, band) in self.bands.iter().enumerate() {
            let size = 2 * l + 1;
            let start = l * l;
            let input = &coeffs[start..start + size];
            for (row, o) in band.chunks_exact(size).zip(&mut out[start..start + size]) {
                *o = row.iter().zip(input).map(|(a, b)| a * b).sum();
            }
        }
        Ok(())
    }

    /// Rotates `coeffs` (length `order²`) into a new vector.
    pub fn apply(&self, coeffs: &[f64]) -> Result<Vec<f64>> {
        let mut out = vec![0.0; coeffs.len()];
        self.apply_into(coeffs, &mut out)?;
        Ok(out)
    }
}

/// Rotates a coefficient vector (length `n²`, `1 ≤ n ≤ 8`) by `r`; see [`ShRotation::new`].
pub fn rotate(coeffs: &[f64], r: [[f64; 3]; 3]) -> Result<Vec<f64>> {
    ShRotation::new(order_of_len(coeffs.len())?, r)?.apply(coeffs)
}

fn check_rotation(r: &[[f64; 3]; 3]) -> Result<()> {
    let bad = |why: &str| Err(PeltError::parameter("rotation", format!("{why}, got {r:?}")));
    if r.iter().flatten().any(|v| !v.is_finite()) {
        return bad("must be finite");
    }
    for i in 0..3 {
        for j in 0..3 {
            let dot: f64 = (0..3).map(|k| r[i][k] * r[j][k]).sum();
            let expected = if i == j { 1.0 } else { 0.0 };
            if (dot - expected).abs() > ROTATION_TOLERANCE {
                return bad("must be orthonormal");
            }
        }
    }
    let det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1])
        - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0])
        + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    if det < 0.0 {
        return bad("must be a rotation, not a reflection (determinant −1)");
    }
    Ok(())
}

/// Band `l ≥ 2` of the rotation from band 1 (`r1`) and band `l − 1` (`prev`), after Ivanic &
/// Ruedenberg's Table 2 with the published corrections.
fn ivanic_ruedenberg_band(l: usize, r1: &[f64], prev: &[f64]) -> Vec<f64> {
    let li = l as isize;
    let size = 2 * l + 1;
    let mut out = vec![0.0; size * size];
    for m in -li..=li {
        for n in -li..=li {
            let d = if m == 0 { 1.0 } else { 0.0 };
            let denom = if n.abs() == li {
                (2 * li * (2 * li - 1)) as f64
            } else {
                ((li + n) * (li - n)) as f64
            };
            let ma = m.abs();
            let u = (((li + m) * (li - m)) as f64 / denom).sqrt();
            let v = 0.5 * ((1.0 + d) * ((li + ma - 1) * (li + ma)) as f64 / denom).sqrt() * (1.0 - 2.0 * d);
            let w = -0.5 * (((li - ma - 1) * (li - ma)) as f64 / denom).sqrt() * (1.0 - d);
            let mut value = 0.0;
            // Skip zero coefficients: their U/V/W terms would index outside band l − 1.
            if u != 0.0 {
                value += u * term_p(0, m, n, li, r1, prev);
            }
            if v != 0.0 {
                value += v * term_v(m, n, li, r1, prev);
            }
            if w != 0.0 {
                value += w * term_w(m, n, li, r1, prev);
            }
            out[((m + li) as usize) * size + (n + li) as usize] = value;
        }
    }
    out
}

/// Entry `(i, j)` of band 1, `i, j ∈ {−1, 0, 1}`.
fn r1_at(r1: &[f64], i: isize, j: isize) -> f64 {
    r1[((i + 1) * 3 + (j + 1)) as usize]
}

/// Entry `(a, b)` of band `l − 1` (size `2l − 1`), `|a|, |b| ≤ l − 1`.
fn prev_at(prev: &[f64], l: isize, a: isize, b: isize) -> f64 {
    let size = 2 * l - 1;
    prev[((a + l - 1) * size + (b + l - 1)) as usize]
}

/// Ivanic & Ruedenberg's helper `P`.
fn term_p(i: isize, a: isize, b: isize, l: isize, r1: &[f64], prev: &[f64]) -> f64 {
    if b == l {
        r1_at(r1, i, 1) * prev_at(prev, l, a, l - 1) - r1_at(r1, i, -1) * prev_at(prev, l, a, -l + 1)
    } else if b == -l {
        r1_at(r1, i, 1) * prev_at(prev, l, a, -l + 1) + r1_at(r1, i, -1) * prev_at(prev, l, a, l - 1)
    } else {
        r1_at(r1, i, 0) * prev_at(prev, l, a, b)
    }
}

fn term_v(m: isize, n: isize, l: isize, r1: &[f64], prev: &[f64]) -> f64 {
    if m == 0 {
        term_p(1, 1, n, l, r1, prev) + term_p(-1, -1, n, l, r1, prev)
    } else if m > 0 {
        let d: f64 = if m == 1 { 1.0 } else { 0.0 };
        term_p(1, m - 1, n, l, r1, prev) * (1.0 + d).sqrt() - term_p(-1, -m + 1, n, l, r1, prev) * (1.0 - d)
    } else {
        let d: f64 = if m == -1 { 1.0 } else { 0.0 };
        term_p(1, m + 1, n, l, r1, prev) * (1.0 - d) + term_p(-1, -m - 1, n, l, r1, prev) * (1.0 + d).sqrt()
    }
}

fn term_w(m: isize, n: isize, l: isize, r1: &[f64], prev: &[f64]) -> f64 {
    // Only called for m ≠ 0 (w = 0 at m = 0).
    if m > 0 {
        term_p(1, m + 1, n, l, r1, prev) + term_p(-1, -m - 1, n, l, r1, prev)
    } else {
        term_p(1, m - 1, n, l, r1, prev) - term_p(-1, -m + 1, n, l, r1, prev)
    }
}
