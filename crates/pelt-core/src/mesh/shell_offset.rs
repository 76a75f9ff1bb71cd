//! Where the shells and fins stand off the skin (Lengyel et al. 2001, §2.3 and §3): layer `l` of
//! a stack spaced `spacing` apart (share of the fur depth) lies at
//! `l · spacing · fur_depth · length · g` from the skin, with the growth direction
//! `g = n + c − n (n · c)` (the normal sheared by the tangential part of the comb vector `c`).
//!
//! The renderer computes the same in `render/common.wgsl` (`growth`) and `render/surface.wgsl`;
//! the geometry export bakes it with these functions, so both agree.

use glam::{DVec3, Vec3};

/// The growth direction at a vertex with unit normal `normal` and comb vector `comb`:
/// `n + c − n (n · c)`.
pub fn growth(normal: [f32; 3], comb: [f32; 3]) -> [f64; 3] {
    let (n, c) = (Vec3::from(normal).as_dvec3(), Vec3::from(comb).as_dvec3());
    (n + c - n * n.dot(c)).to_array()
}

/// `position` lifted to `height` (share of the fur depth, `layer · spacing` for a shell, 1 for a
/// fin's top) along the growth direction, scaled by `fur_depth · length`.
pub fn lifted(
    position: [f32; 3],
    normal: [f32; 3],
    comb: [f32; 3],
    height: f64,
    fur_depth: f64,
    length: f32,
) -> [f32; 3] {
    let g = growth(normal, comb);
    let scale = height * fur_depth * f64::from(length);
    (Vec3::from(position).as_dvec3() + scale * DVec3::from(g))
        .as_vec3()
        .to_array()
}

/// The layer that shell `shell` (1-based, `1..=shells`) of `shells` drawn shows in a stack of
/// `layers` layers: `round(shell · (layers − 1) / shells)`, halves rounded up, in integers so the
/// choice is exact. Fewer shells than layers keep the full fur depth; `shells = layers − 1` shows
/// every layer above the skin once.
pub fn shell_layer(shell: usize, shells: usize, layers: usize) -> usize {
    let drawn = shells.max(1);
    let top = layers.saturating_sub(1);
    (shell * top * 2 + drawn) / (2 * drawn)
}
