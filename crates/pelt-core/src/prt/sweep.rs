//! The fast transfer method: per direction, carry the optical depth down through the layers.
//!
//! The brute march of §2.2 of the PRT shell-fur paper costs one march per voxel and direction;
//! the sweep shares the work between voxels. For a direction `ω` with `ω_z > 0`, index parallel
//! rays by the grid point `q` where they leave the skin: ray `q` crosses layer `j` at
//! `q + j·d`, where `d = s·(ω_x, ω_y)/ω_z` is the lateral shift per layer gap. Its optical depth
//! above layer `j` obeys
//!
//! ```text
//! C_j(q) = C_{j+1}(q) + σ·ℓ·G_j(q + j·d),    C_{L−1} = 0,    ℓ = s/ω_z,
//! G_j(p) = ∫₀¹ (1−f)·ρ_j(p + f·d) + f·ρ_{j+1}(p + f·d) df,
//! ```
//!
//! so the carry itself needs no resampling: every ray keeps its slot `q`, and `G_j` is read at a
//! shift that is the same for every ray. A voxel `p` of layer `l` sees its own gap `G_l(p)` on its
//! own grid, and the rest of its path is ray `q = p − l·d`, read from `C_{l+1}` by bilinear
//! interpolation: one resampling per voxel and direction, instead of one per layer as when the
//! carried depth is itself resampled layer by layer (which blurs shadows more with every layer).
//! The interpolation is done on the rays' transmittance `e^{−C}`, not on `C`: a hair edge between
//! two rays then shades a voxel by the share of the footprint, where interpolated depth would
//! darken it (`e^{−mean τ} < mean e^{−τ}`). It is the sweep's main error (about 2 % RMS of the
//! transmittance of the second layer for texel-wide hairs, less higher up and none at the skin).
//!
//! `G` is integrated exactly for the density model by a [`SegmentKernel`] while the shift per gap
//! is at most `sweep_step · sweep_max_samples` texels. Near the horizon the path through one gap
//! is long (`|d| = s·tan θ`, unbounded); there the sweep takes at most `sweep_max_samples` midpoint
//! samples per gap from a box-prefiltered level of the layers ([`Pyramid`]) whose box matches the
//! sample spacing, so the cost per direction stays bounded however grazing the direction; from a
//! box as wide as the tile on, the layer mean is exact and one sample suffices. Once every ray of
//! a layer has an optical depth above [`TAU_CUT`], the layers below are set to 0.

use rayon::prelude::*;

use super::accumulate::{PhaseField, Projector, RowAccumulator};
use super::field::{Pyramid, SegmentKernel, Term, add_shifted};
use super::volume::{ExtraRows, RayGeometry, TAU_CUT, Volume};
use crate::error::Result;
use crate::progress::Progress;

/// Optical depths are clamped here so that huge densities stay finite (no `inf · 0` later).
const TAU_CLAMP: f32 = 1.0e4;

/// Bytes of per-direction buffers (chain, two scratch grids and one layer of transmittance) held
/// at once; directions are swept in groups that fit.
const GROUP_BYTES: usize = 64 << 20;

/// How one direction samples a layer gap: pyramid level and number of samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct GapPlan {
    pub level: usize,
    pub samples: usize,
}

impl GapPlan {
    /// Level 0 (the exact kernel) while `shift_len ≤ step · max_samples`; beyond, the finest level
    /// whose sample count stays within `max_samples` at spacing `step · 2^level`; the top level
    /// (the layer mean) needs one sample.
    pub(super) fn new(shift_len: f64, step: f64, max_samples: usize, top: usize) -> Self {
        let mut level = 0;
        loop {
            if level >= top {
                return GapPlan {
                    level: top,
                    samples: 1,
                };
            }
            let spacing = step * (1u64 << level) as f64;
            let samples = (shift_len / spacing).ceil();
            if samples <= max_samples as f64 {
                return GapPlan {
                    level,
                    samples: (samples as usize).max(1),
                };
            }
            level += 1;
        }
    }
}

/// The state of one direction during the sweep.
pub(super) struct SweepRay {
    ray: RayGeometry,
    plan: GapPlan,
    /// `C_{j+1}(q)`: optical depth above layer `j + 1` along ray `q`, when at layer `j`.
    chain: Vec<f32>,
    /// Smallest value of `chain`.
    chain_min: f32,
    /// Scratch: one gap's depth on a grid.
    gap: Vec<f32>,
    /// Scratch: `e^{−C_{j+1}}`, the transmittance along each ray.
    ray_t: Vec<f32>,
    /// The gap kernel at offset 0 (the voxel's own gap), the same for every layer.
    near_kernel: Option<SegmentKernel>,
    /// Every voxel is opaque from the current layer down.
    opaque: bool,
}

impl SweepRay {
    pub(super) fn new(dir: [f64; 3], vol: &Volume<'_>, sigma: f64, step: f64, max_samples: usize) -> Self {
        let ray = RayGeometry::new(dir, vol.spacing);
        let shift_len = ray.shift[0].hypot(ray.shift[1]);
        let res = vol.resolution;
        let plan = GapPlan::new(shift_len, step, max_samples, Pyramid::top_level(res));
        let near_kernel =
            (plan.level == 0).then(|| SegmentKernel::new([0.0; 2], ray.shift, sigma * ray.length, res));
        SweepRay {
            ray,
            plan,
            chain: vec![0.0; res * res],
            chain_min: 0.0,
            gap: vec![0.0; res * res],
            ray_t: vec![0.0; res * res],
            near_kernel,
            opaque: false,
        }
    }

    pub(super) fn plan(&self) -> GapPlan {
        self.plan
    }

    /// Moves to layer `j` (called for `j = L−1, L−2, …, 0` in turn) and writes the transmittance
    /// of that layer's voxels to `t` (`res²`). `lower` is layer `j`'s pyramid, `upper` layer
    /// `j + 1`'s (`None` at the top layer).
    pub(super) fn step(
        &mut self,
        vol: &Volume<'_>,
        sigma: f64,
        j: usize,
        lower: &Pyramid,
        upper: Option<&Pyramid>,
        t: &mut [f32],
    ) {
        let res = vol.resolution;
        let Some(upper) = upper else {
            // Nothing lies above the top layer.
            self.chain.fill(0.0);
            self.chain_min = 0.0;
            self.opaque = false;
            t.fill(1.0);
            return;
        };
        // T = e^{−own gap} · (interpolated ray transmittance) ≤ e^{−min C}, and C only grows
        // further down.
        if self.opaque || f64::from(self.chain_min) > TAU_CUT {
            self.opaque = true;
            t.fill(0.0);
            return;
        }
        // The rest of the path: voxel p of layer j lies on ray q = p − j·d.
        self.ray_t.copy_from_slice(&self.chain);
        exp_neg(&mut self.ray_t);
        t.fill(0.0);
        let (dx, dy) = (j as f64 * self.ray.shift[0], j as f64 * self.ray.shift[1]);
        add_shifted(
            t,
            res,
            -dx,
            -dy,
            &[Term {
                img: &self.ray_t,
                scale: 1.0,
            }],
        );
        // The voxel's own gap, on its own grid.
        self.gap.fill(0.0);
        self.add_gap(vol, sigma, j, 0.0, lower, upper);
        exp_neg(&mut self.gap);
        for (t, g) in t.iter_mut().zip(&self.gap) {
            *t = t.clamp(0.0, 1.0) * g;
        }
        // C_j = C_{j+1} + σ·ℓ·G_j(q + j·d).
        self.gap.fill(0.0);
        self.add_gap(vol, sigma, j, j as f64, lower, upper);
        let mut min = f32::INFINITY;
        for (c, g) in self.chain.iter_mut().zip(&self.gap) {
            *c = (*c + g).min(TAU_CLAMP);
            min = min.min(*c);
        }
        self.chain_min = min;
    }

    /// Adds `σ·ℓ·G_j(p + base·d)` for every grid point `p` to `self.gap`: exactly by a segment
    /// kernel at pyramid level 0, else with midpoint samples `f` read at the shifts `(base + f)·d`.
    fn add_gap(
        &mut self,
        vol: &Volume<'_>,
        sigma: f64,
        j: usize,
        base: f64,
        lower: &Pyramid,
        upper: &Pyramid,
    ) {
        let (empty0, empty1) = (vol.empty[j], vol.empty[j + 1]);
        if empty0 && empty1 {
            return;
        }
        let res = vol.resolution;
        let GapPlan { level, samples } = self.plan;
        if level == 0 {
            let (lo, hi) = (lower.level(0), upper.level(0));
            if base == 0.0 {
                if let Some(kernel) = &self.near_kernel {
                    kernel.apply(&mut self.gap, res, lo, hi);
                }
            } else {
                let o = [base * self.ray.shift[0], base * self.ray.shift[1]];
                SegmentKernel::new(o, self.ray.shift, sigma * self.ray.length, res).apply(
                    &mut self.gap,
                    res,
                    lo,
                    hi,
                );
            }
            return;
        }
        let depth = sigma * self.ray.length / samples as f64;
        for k in 0..samples {
            let f = (k as f64 + 0.5) / samples as f64;
            let s = base + f;
            let terms = [
                Term {
                    img: lower.level(level),
                    scale: (depth * (1.0 - f)) as f32,
                },
                Term {
                    img: upper.level(level),
                    scale: (depth * f) as f32,
                },
            ];
            let used = match (empty0, empty1) {
                (false, false) => &terms[..],
                (false, true) => &terms[..1],
                _ => &terms[1..],
            };
            add_shifted(
                &mut self.gap,
                res,
                s * self.ray.shift[0],
                s * self.ray.shift[1],
                used,
            );
        }
    }
}

/// `v ← e^{−v}` for optical depths `v ≥ 0`, 0 beyond [`TAU_CUT`].
///
/// A branch-free polynomial the compiler vectorizes (libm's `expf` is a call per value and took a
/// sixth of the sweep): `e^{−v} = 2^{−n}·e^{−r·ln 2}` with `n` the nearest integer to `v·log₂e`,
/// so `|r·ln 2| ≤ 0.35` and a degree-6 Taylor polynomial is within 1.2·10⁻⁷ relative, about f32's
/// own rounding; `2^{−n}` is built from exponent bits. Conversions truncate (plain SSE2), which
/// rounds to nearest after adding ½ to a non-negative value.
fn exp_neg(values: &mut [f32]) {
    const LN2: f32 = std::f32::consts::LN_2;
    const LOG2E: f32 = std::f32::consts::LOG2_E;
    const CUT: f32 = TAU_CUT as f32;
    for v in values {
        let x = v.clamp(0.0, CUT);
        let y = x * LOG2E;
        let n = (y + 0.5) as i32;
        let u = (y - n as f32) * LN2;
        let p = 1.0
            - u * (1.0
                - u * (0.5 - u * (1.0 / 6.0 - u * (1.0 / 24.0 - u * (1.0 / 120.0 - u * (1.0 / 720.0))))));
        let scale = f32::from_bits(((127 - n) as u32) << 23);
        *v = if *v > CUT { 0.0 } else { p * scale };
    }
}

/// Transmittance of every voxel toward one direction (`[layer][y][x]`).
pub(super) fn transmittance(
    vol: &Volume<'_>,
    sigma: f64,
    step: f64,
    max_samples: usize,
    dir: [f64; 3],
) -> Vec<f32> {
    let res2 = vol.resolution * vol.resolution;
    let mut ray = SweepRay::new(dir, vol, sigma, step, max_samples);
    let max_level = ray.plan().level;
    let mut out = vec![0.0; vol.voxel_count()];
    let mut upper: Option<Pyramid> = None;
    for j in (0..vol.layers).rev() {
        let lower = Pyramid::build(vol.layer(j), vol.resolution, max_level);
        ray.step(
            vol,
            sigma,
            j,
            &lower,
            upper.as_ref(),
            &mut out[j * res2..(j + 1) * res2],
        );
        upper = Some(lower);
    }
    out
}

/// Accumulates the projection of every voxel's transmittance into `out` (`[voxel][sh channel]`)
/// and the extra channels of sampled rows.
///
/// Directions go in groups sized to [`GROUP_BYTES`]; within a group the layers are swept top-down
/// in lockstep: all rays of the group advance one layer in parallel, then that layer's rows are
/// accumulated in parallel, each voxel summing its directions in projector order.
#[allow(clippy::too_many_arguments)]
pub(super) fn bake(
    vol: &Volume<'_>,
    sigma: f64,
    step: f64,
    max_samples: usize,
    projector: &Projector,
    phase: &PhaseField,
    progress: &Progress<'_>,
    out: &mut [f32],
    extra: &mut ExtraRows,
) -> Result<()> {
    let res = vol.resolution;
    let res2 = res * res;
    let n = projector.sh_channels;
    let group = (GROUP_BYTES / (16 * res2)).max(1);
    let dirs: Vec<usize> = (0..projector.dirs.len()).collect();
    for group_dirs in dirs.chunks(group) {
        let mut rays: Vec<SweepRay> = group_dirs
            .iter()
            .map(|&i| SweepRay::new(projector.dirs[i], vol, sigma, step, max_samples))
            .collect();
        let max_level = rays.iter().map(|r| r.plan().level).max().unwrap_or(0);
        let mut t = vec![0.0f32; group_dirs.len() * res2];
        let mut upper: Option<Pyramid> = None;
        for j in (0..vol.layers).rev() {
            let lower = Pyramid::build(vol.layer(j), res, max_level);
            rays.par_iter_mut()
                .zip(t.par_chunks_mut(res2))
                .try_for_each(|(ray, t)| {
                    ray.step(vol, sigma, j, &lower, upper.as_ref(), t);
                    progress.advance(1)
                })?;
            let layer_out = &mut out[j * res2 * n..(j + 1) * res2 * n];
            let layer_extra = &mut extra.rows[j * res..(j + 1) * res];
            layer_out
                .par_chunks_mut(res * n)
                .zip(layer_extra.par_iter_mut())
                .enumerate()
                .for_each_init(
                    || RowAccumulator::new(projector, phase, res),
                    |acc, (y, (out_row, extra_row))| {
                        acc.load((j * res + y) * res, out_row, extra_row.as_deref());
                        for (g, &dir) in group_dirs.iter().enumerate() {
                            let row = &t[g * res2 + y * res..g * res2 + (y + 1) * res];
                            acc.add(dir, row, extra_row.is_some());
                        }
                        acc.store(out_row, extra_row.as_deref_mut());
                    },
                );
            upper = Some(lower);
        }
    }
    Ok(())
}
