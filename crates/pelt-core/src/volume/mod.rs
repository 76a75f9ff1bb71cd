//! The hair volume: strands sampled into the layers of a tileable shell texture.
//!
//! Lengyel et al. 2001, §2.2 sample the geometric hair of one toroidal tile into an RGBA image per
//! shell layer and a fin texture; §2.4 reduces the stack for distant objects. The PRT shell-fur
//! paper (`prt-shell-fur`, §2.1) computes each hair's contribution to a texel as the share of the
//! texel its cross-section covers, so that hairs do not jump from texel to texel between layers.
//! One stage per file:
//!
//! - [`coverage`]: the area a hair's circular cross-section covers in each texel (exact, the
//!   paper's approximation, supersampled), and [`footprint`], the fast exact path over a disk;
//! - `grid`: floors and toroidal wrapping without library calls;
//! - [`strand_table`]: the strands flattened in raster order of their roots for sampling;
//! - [`shells`]: one layer's coverage, color and hair tangent, with `splat` adding the hairs'
//!   shares to its per-texel sums;
//! - `stack`: the shell layers two at a time, with LOD level 1 and mipmaps made pair by pair;
//! - [`fin`]: the fin texture, a slab of hair seen from the side;
//! - [`slices`]: the virtual-planes renderer's slices, every slab of the tile seen from the side;
//! - [`lod`]: composited shell pairs and mipmaps;
//! - [`bake`]: the whole volume ([`bake_volume`]) with its trim and statistics.

pub mod bake;
pub mod coverage;
pub mod fin;
pub mod footprint;
mod grid;
pub mod lod;
mod params;
pub mod peak;
pub mod shells;
pub mod slices;
mod splat;
mod stack;
pub mod strand_table;

#[cfg(test)]
mod tests;

pub use bake::{HairVolume, VolumeParams, VolumeStats, bake_strands, bake_volume};
pub use slices::{PlaneParams, PlaneSlices, bake_slices};
