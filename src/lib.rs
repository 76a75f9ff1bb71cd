//! # Pelt
//!
//! Real-time fur on any mesh, after Lengyel, Praun, Finkelstein and Hoppe, "Real-Time Fur over
//! Arbitrary Surfaces" (I3D 2001): lapped texture patches aligned to a painted comb field, a tileable
//! hair volume sampled into shell and fin textures, precomputed radiance transfer for hair
//! self-shadowing, and a wgpu preview renderer.
//!
//! This package is Pelt's Rust API, one dependency for a user of the library: it re-exports
//! `pelt-core` (the pipeline without a GPU or Python) and, with the feature `render`,
//! `pelt-render` as [`render`]. Start with [`FurMesh`].

pub use pelt_core::*;

#[cfg(feature = "render")]
pub use pelt_render as render;
