//! # Pelt
//!
//! Real-time fur on any mesh, after Lengyel, Praun, Finkelstein and Hoppe, "Real-Time Fur over
//! Arbitrary Surfaces" (I3D 2001): lapped texture patches aligned to a painted comb field, a tileable
//! hair volume sampled into shell and fin textures, precomputed radiance transfer for hair
//! self-shadowing, and a wgpu preview renderer.
//!
//! This crate is the pipeline without a GPU or Python (no wgpu, no pyo3): the renderer
//! (`pelt-render`), the Python module (`pelt-python`) and the command line (`pelt-cli`) are layers
//! on top. Start with [`FurMesh`].

pub mod camera;
#[doc(hidden)]
pub mod cg;
pub mod error;
pub mod export;
pub mod field;
pub mod guard;
pub mod hair;
pub mod heap;
pub mod lapped;
pub mod memory;
pub mod mesh;
pub mod params;
pub mod pipeline;
pub mod placement;
pub mod presets;
pub mod progress;
pub mod prt;
pub mod reference;
#[doc(hidden)]
pub mod rng;
pub mod scene;
#[cfg(test)]
mod test_support;
pub mod texture;
pub mod threads;
pub mod volume;

pub use error::{MeshError, PeltError, Result};
pub use mesh::{FurMesh, MeshInput, MeshStats};

/// The crate version, as reported by `pelt.__version__` and `pelt bench`.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
