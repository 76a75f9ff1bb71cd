//! Helpers shared by the integration tests: camera matrices written out from their definitions,
//! the golden-image check of DESIGN.md §3, the command-line tests' small bake and the render tests'
//! small hair volume and furred torus. Each test
//! binary uses a part of them.
#![allow(dead_code)]

pub mod bake;
pub mod golden;
#[cfg(feature = "render")]
pub mod torus;
pub mod volume;

/// Row-major `m[row][col]` to the column-major array the renderer takes.
pub fn column_major(rows: [[f64; 4]; 4]) -> [f32; 16] {
    std::array::from_fn(|i| rows[i % 4][i / 4] as f32)
}

fn norm(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / l)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// A right-handed view matrix (row-major) from `eye` toward `target` with `up` roughly up.
pub fn look_at_rows(eye: [f64; 3], target: [f64; 3], up: [f64; 3]) -> [[f64; 4]; 4] {
    let f = norm([target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]]);
    let s = norm(cross(f, up));
    let u = cross(s, f);
    [
        [s[0], s[1], s[2], -dot(s, eye)],
        [u[0], u[1], u[2], -dot(u, eye)],
        [-f[0], -f[1], -f[2], dot(f, eye)],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

/// [`look_at_rows`] toward the origin, column-major.
pub fn look_at(eye: [f64; 3], up: [f64; 3]) -> [f32; 16] {
    column_major(look_at_rows(eye, [0.0; 3], up))
}

/// A perspective projection (row-major) to wgpu's clip space (depth in `[0, 1]`) with a
/// vertical field of view `fov_deg` and a square image.
pub fn perspective_rows(fov_deg: f64, near: f64, far: f64) -> [[f64; 4]; 4] {
    let t = 1.0 / (0.5 * fov_deg).to_radians().tan();
    [
        [t, 0.0, 0.0, 0.0],
        [0.0, t, 0.0, 0.0],
        [0.0, 0.0, far / (near - far), near * far / (near - far)],
        [0.0, 0.0, -1.0, 0.0],
    ]
}

/// An orthographic projection (column-major) showing `[-half, half]²` of the view plane, view
/// depths `near..far` mapped to clip depth `0..1`.
pub fn orthographic(half: f64, near: f64, far: f64) -> [f32; 16] {
    column_major([
        [1.0 / half, 0.0, 0.0, 0.0],
        [0.0, 1.0 / half, 0.0, 0.0],
        [0.0, 0.0, 1.0 / (near - far), near / (near - far)],
        [0.0, 0.0, 0.0, 1.0],
    ])
}

/// `a · b` for row-major 4 × 4 matrices.
pub fn mul(a: &[[f64; 4]; 4], b: &[[f64; 4]; 4]) -> [[f64; 4]; 4] {
    std::array::from_fn(|r| std::array::from_fn(|c| (0..4).map(|k| a[r][k] * b[k][c]).sum()))
}

/// The parameter an [`pelt::PeltError::InvalidParameter`] names (any other error fails the test).
pub fn parameter_name(e: pelt::PeltError) -> String {
    match e {
        pelt::PeltError::InvalidParameter { name, .. } => name,
        other => panic!("expected an invalid parameter, got {other}"),
    }
}
