//! Projection of per-direction transmittance onto the SH basis (the sum of §2.3 of the PRT
//! shell-fur paper, eq. 7 applied to the transfer instead of the lighting), shared by both
//! transfer methods.
//!
//! `t_k(x) = Σ_i w_i · B_k(ω_i) · T(x, ω_i) · phase(x, ω_i)`: the weights `w_i · B_k(ω_i)` are
//! tabulated once per direction ([`Projector`]), and one row of voxels is accumulated at a time
//! in a channel-major scratch buffer so the inner loop is a contiguous `acc += weight · values`.
//! Each voxel sums its directions in one fixed order, so the result does not depend on how
//! the rows are spread over threads.

use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};

use super::sh;
use crate::error::Result;

/// The phase term of the transfer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Phase {
    /// Every direction weighs 1 (the paper's "light reaching each voxel").
    #[default]
    Isotropic,
    /// Kajiya–Kay diffuse `sin(t, ω)` with the voxel's hair tangent `t`.
    KajiyaKay,
}

/// Mean of `sin(t, ω)` over the sphere: the Kajiya–Kay phase of a voxel without a tangent.
pub(super) const KAJIYA_KAY_MEAN: f32 = std::f32::consts::FRAC_PI_4;

/// The directions of a bake that can see the sky (`ω_z > 0`) and their projection weights.
pub(super) struct Projector {
    /// Unit directions, in the order their terms are summed.
    pub dirs: Vec<[f64; 3]>,
    /// Basis coefficients per direction, `channels` each: `w_i · Y_k(ω_i)` for the SH channels,
    /// then `w_i · L_j(ω_i)` for any extra channels (test lights of band selection).
    weights: Vec<f32>,
    /// SH channels (`order²`).
    pub sh_channels: usize,
    /// Extra channels after the SH ones.
    pub extra_channels: usize,
}

impl Projector {
    /// `directions` with quadrature weight `weight` each, SH to `order`, and extra channels whose
    /// value at a direction is `extra(ω)` (a slice of `extra_channels` values).
    pub(super) fn new(
        order: usize,
        directions: &[[f64; 3]],
        weight: f64,
        extra_channels: usize,
        extra: impl Fn([f64; 3], &mut [f64]),
    ) -> Result<Self> {
        let sh_channels = sh::coeff_count(order);
        let channels = sh_channels + extra_channels;
        let dirs: Vec<[f64; 3]> = directions.iter().copied().filter(|d| d[2] > 0.0).collect();
        let mut weights = Vec::with_capacity(dirs.len() * channels);
        let mut y = vec![0.0; sh_channels];
        let mut e = vec![0.0; extra_channels];
        for &d in &dirs {
            sh::eval(order, d, &mut y)?;
            extra(d, &mut e);
            weights.extend(y.iter().chain(&e).map(|v| (weight * v) as f32));
        }
        Ok(Projector {
            dirs,
            weights,
            sh_channels,
            extra_channels,
        })
    }

    pub(super) fn channels(&self) -> usize {
        self.sh_channels + self.extra_channels
    }

    fn weights(&self, dir: usize) -> &[f32] {
        let c = self.channels();
        &self.weights[dir * c..(dir + 1) * c]
    }
}

/// Per-voxel phase factors of one bake.
pub(super) enum PhaseField {
    Isotropic,
    /// Unit tangents per voxel, zero where there is no hair.
    KajiyaKay(Vec<Vec3>),
}

impl PhaseField {
    pub(super) fn new(phase: Phase, tangents: Option<&[[f32; 3]]>) -> Self {
        match (phase, tangents) {
            (Phase::KajiyaKay, Some(t)) => {
                PhaseField::KajiyaKay(t.iter().map(|&v| unit_or_zero(Vec3::from(v))).collect())
            }
            _ => PhaseField::Isotropic,
        }
    }
}

/// Below this length a tangent counts as "no hair here".
const MIN_TANGENT: f32 = 1e-6;

fn unit_or_zero(t: Vec3) -> Vec3 {
    let len = t.length();
    // A division by the length, not `normalize`'s product with its reciprocal: it rounds otherwise.
    if len < MIN_TANGENT { Vec3::ZERO } else { t / len }
}

/// Kajiya–Kay diffuse phase `sin(t, ω) = √(1 − (t·ω)²)`; the sphere mean π/4 without a tangent.
#[inline]
pub(super) fn kajiya_kay(t: Vec3, d: Vec3) -> f32 {
    if t == Vec3::ZERO {
        return KAJIYA_KAY_MEAN;
    }
    let c = t.dot(d);
    (1.0 - c * c).max(0.0).sqrt()
}

/// Accumulates one row of voxels over many directions.
pub(super) struct RowAccumulator<'a> {
    projector: &'a Projector,
    phase: &'a PhaseField,
    /// `[channel][voxel]` scratch for the row.
    acc: Vec<f32>,
    /// `T · phase` of the row for one direction.
    values: Vec<f32>,
    len: usize,
    /// Flat index of the row's first voxel (for tangents).
    first: usize,
}

impl<'a> RowAccumulator<'a> {
    pub(super) fn new(projector: &'a Projector, phase: &'a PhaseField, len: usize) -> Self {
        RowAccumulator {
            projector,
            phase,
            acc: vec![0.0; projector.channels() * len],
            values: vec![0.0; len],
            len,
            first: 0,
        }
    }

    /// Starts the row whose first voxel has flat index `first`, from the partial sums in `out`
    /// (`[voxel][sh channel]`, as earlier direction groups left them) and `extra` (`[voxel][extra
    /// channel]`, or `None` when this row does not track extra channels).
    pub(super) fn load(&mut self, first: usize, out: &[f32], extra: Option<&[f32]>) {
        self.first = first;
        let (n, e, len) = (
            self.projector.sh_channels,
            self.projector.extra_channels,
            self.len,
        );
        for (v, coeffs) in out.chunks_exact(n).enumerate() {
            for (k, &c) in coeffs.iter().enumerate() {
                self.acc[k * len + v] = c;
            }
        }
        match extra {
            Some(extra) => {
                for (v, vals) in extra.chunks_exact(e.max(1)).enumerate().take(len) {
                    for (k, &c) in vals.iter().enumerate() {
                        self.acc[(n + k) * len + v] = c;
                    }
                }
            }
            None => self.acc[n * len..].fill(0.0),
        }
    }

    /// Adds direction `dir` (an index into the projector) with transmittances `t` (one per voxel).
    /// Extra channels are accumulated only when `with_extra`.
    pub(super) fn add(&mut self, dir: usize, t: &[f32], with_extra: bool) {
        let d = DVec3::from(self.projector.dirs[dir]).as_vec3();
        match self.phase {
            PhaseField::Isotropic => self.values.copy_from_slice(t),
            PhaseField::KajiyaKay(tangents) => {
                let tangents = &tangents[self.first..self.first + self.len];
                for ((v, &t), &tan) in self.values.iter_mut().zip(t).zip(tangents) {
                    *v = t * kajiya_kay(tan, d);
                }
            }
        }
        // A fully shadowed row adds nothing; skipping it only saves time.
        if self.values.iter().all(|&v| v == 0.0) {
            return;
        }
        let channels = if with_extra {
            self.projector.channels()
        } else {
            self.projector.sh_channels
        };
        let len = self.len;
        for (k, &w) in self.projector.weights(dir)[..channels].iter().enumerate() {
            for (a, &v) in self.acc[k * len..(k + 1) * len].iter_mut().zip(&self.values) {
                *a += w * v;
            }
        }
    }

    /// Writes the row back: SH channels to `out` (`[voxel][channel]`), extra channels to `extra`.
    pub(super) fn store(&self, out: &mut [f32], extra: Option<&mut [f32]>) {
        let (n, e, len) = (
            self.projector.sh_channels,
            self.projector.extra_channels,
            self.len,
        );
        for (v, coeffs) in out.chunks_exact_mut(n).enumerate() {
            for (k, c) in coeffs.iter_mut().enumerate() {
                *c = self.acc[k * len + v];
            }
        }
        if let Some(extra) = extra {
            for (v, vals) in extra.chunks_exact_mut(e.max(1)).enumerate().take(len) {
                for (k, c) in vals.iter_mut().enumerate() {
                    *c = self.acc[(n + k) * len + v];
                }
            }
        }
    }
}
