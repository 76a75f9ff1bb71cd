//! Precomputed radiance transfer (PRT): the spherical-harmonics foundation.
//!
//! PRT stores, for every shell texel, how light arriving from each direction is transferred to the
//! viewer, expressed in the real spherical-harmonics (SH) basis of §2.3 ("PRT Basis Functions") of
//! the PRT shell-fur paper (`prt-shell-fur`): the paper keeps the 5 lowest bands (25 functions),
//! Pelt supports up to 8 bands (64 functions) so the order can be raised without new code.
//!
//! - [`sh`]: the basis (evaluation, index helpers), projection of sampled functions, equirectangular
//!   environment images and spherical-cap lights, and exact rotation of coefficient vectors.
//! - [`sphere`]: direction sets and quadrature rules on the sphere used to bake and to check bakes.

pub mod sh;
pub mod sphere;

#[cfg(test)]
mod tests;
