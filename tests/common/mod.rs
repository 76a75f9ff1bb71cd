//! Helpers shared by the integration tests: camera matrices (glam's right-handed view and wgpu-depth
//! projections),
//! the golden-image check of DESIGN.md §3, the command-line tests' small bake and the render tests'
//! small hair volume and furred torus. Each test
//! binary uses a part of them.
#![allow(dead_code)]

use glam::DMat4;
use glam::dcamera::rh::proj::directx;
use glam::dcamera::rh::view::look_at_mat4;

pub mod bake;
pub mod golden;
#[cfg(feature = "render")]
pub mod torus;
pub mod volume;

/// The lapped patches of `mesh` at `tile_size` object units per tile, the rest at defaults.
pub fn patches_at(mesh: &pelt::FurMesh, tile_size: f64) -> pelt::lapped::Patches {
    let params = pelt::lapped::PatchParams {
        tile_size,
        ..pelt::lapped::PatchParams::default()
    };
    pelt::lapped::build_patches(mesh, &params).unwrap()
}

/// `m` as the column-major f32 array the renderer takes.
pub fn column_major(m: DMat4) -> [f32; 16] {
    m.as_mat4().to_cols_array()
}

/// A right-handed view matrix from `eye` toward `target` with the unit vector `up` roughly up.
pub fn view_matrix(eye: [f64; 3], target: [f64; 3], up: [f64; 3]) -> DMat4 {
    look_at_mat4(eye.into(), target.into(), up.into())
}

/// [`view_matrix`] toward the origin, column-major.
pub fn look_at(eye: [f64; 3], up: [f64; 3]) -> [f32; 16] {
    column_major(view_matrix(eye, [0.0; 3], up))
}

/// A perspective projection to wgpu's clip space (depth in `[0, 1]`) with a vertical field of
/// view `fov_deg` and a square image.
pub fn perspective(fov_deg: f64, near: f64, far: f64) -> DMat4 {
    directx::perspective(fov_deg.to_radians(), 1.0, near, far)
}

/// An orthographic projection (column-major) showing `[-half, half]²` of the view plane, view
/// depths `near..far` mapped to clip depth `0..1`.
pub fn orthographic(half: f64, near: f64, far: f64) -> [f32; 16] {
    column_major(directx::orthographic(-half, half, -half, half, near, far))
}

/// The parameter an [`pelt::PeltError::InvalidParameter`] names (any other error fails the test).
pub fn parameter_name(e: pelt::PeltError) -> String {
    match e {
        pelt::PeltError::InvalidParameter { name, .. } => name,
        other => panic!("expected an invalid parameter, got {other}"),
    }
}
