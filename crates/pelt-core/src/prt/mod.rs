//! Precomputed radiance transfer (PRT): spherical harmonics and the transfer bake.
//!
//! PRT stores, for every shell texel, how light arriving from each direction is transferred to the
//! viewer, expressed in the real spherical-harmonics (SH) basis of §2.3 ("PRT Basis Functions") of
//! the PRT shell-fur paper (`prt-shell-fur`): the paper keeps the 5 lowest bands (25 functions),
//! Pelt supports up to 8 bands (64 functions) so the order can be raised without new code.
//!
//! - [`sh`]: the basis (evaluation, index helpers), projection of sampled functions, equirectangular
//!   environment images and spherical-cap lights, and exact rotation of coefficient vectors.
//! - [`sphere`]: direction sets and quadrature rules on the sphere used to bake and to check bakes.
//! - [`transfer`]: the bake of transfer coefficients over a density volume (§2.2), by the paper's
//!   brute-force march (`march.rs`) or a layer sweep (`sweep.rs`) over a shared density model
//!   (`field.rs`), projected onto SH by `accumulate.rs`.
//! - [`bands`]: per-band energy and the choice of the smallest order that lights a fixed test set
//!   within a tolerance (the paper's open question whether fewer bands suffice).
//! - [`pack`]: coefficient textures, 4 coefficients per RGBA texel (§2.3), as float16 or as 8-bit
//!   with a per-coefficient scale and bias.

mod accumulate;
pub mod bands;
mod field;
mod march;
pub mod pack;
mod params;
pub mod peak;
pub mod sh;
pub mod sphere;
mod sweep;
pub mod transfer;
mod volume;
pub mod volume_input;

pub use transfer::{Method, Phase, Transfer, TransferParams, TransferVolume, bake_transfer, transmittance};

#[cfg(test)]
mod tests;
#[cfg(test)]
mod transfer_tests;
