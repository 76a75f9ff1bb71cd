//! The camera every picture of Pelt is drawn with: the preview (`render`) and the reference
//! renderer (`reference`) take the same matrices, so their images line up pixel for pixel.

use glam::DMat4;

use crate::error::{PeltError, Result};

/// Largest image side accepted before the adapter's own limit is asked.
pub const MAX_IMAGE_SIDE: u32 = 16384;

/// A camera. Matrices are column-major 4 × 4 (`m[col * 4 + row]`, as numpy's `matrix.T.ravel()`
/// and Blender's `Matrix` columns give them).
///
/// `view` maps object space to view space (right-handed, the camera looking down −z);
/// `projection` maps view space to wgpu's clip space (depth in `[0, 1]`, y up). A projection whose
/// last row is `(0, 0, −1, 0)` is a perspective one (the eye sits at the view-space origin); one
/// whose last row is `(0, 0, 0, 1)` is orthographic (the eye is at infinity along +z).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Object to view space, column-major.
    pub view: [f32; 16],
    /// View to clip space, column-major.
    pub projection: [f32; 16],
    /// Image width in pixels, `[1, MAX_IMAGE_SIDE]` (and the adapter's limit).
    pub width: u32,
    /// Image height in pixels, `[1, MAX_IMAGE_SIDE]` (and the adapter's limit).
    pub height: u32,
}

/// OpenGL clip depth `[-1, 1]` to wgpu's `[0, 1]`: `z' = (z + w) / 2`, applied after the
/// projection.
const GL_TO_WGPU_DEPTH: DMat4 = DMat4::from_cols_array(&[
    1.0, 0.0, 0.0, 0.0, //
    0.0, 1.0, 0.0, 0.0, //
    0.0, 0.0, 0.5, 0.0, //
    0.0, 0.0, 0.5, 1.0, //
]);

impl Camera {
    /// Checks the sides against `max_side` (and [`MAX_IMAGE_SIDE`]) and that every matrix
    /// element is finite.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `camera.width`, `camera.height`, `camera.view` or
    /// `camera.projection`.
    pub fn check(&self, max_side: u32) -> Result<()> {
        let limit = max_side.min(MAX_IMAGE_SIDE);
        for (name, side) in [("camera.width", self.width), ("camera.height", self.height)] {
            if !(1..=limit).contains(&side) {
                return Err(PeltError::parameter(
                    name,
                    format!("must be in [1, {limit}], got {side}"),
                ));
            }
        }
        for (name, m) in [
            ("camera.view", &self.view),
            ("camera.projection", &self.projection),
        ] {
            if let Some(i) = m.iter().position(|v| !v.is_finite()) {
                return Err(PeltError::parameter(
                    name,
                    format!("element {i} (column {}, row {}) is not finite", i / 4, i % 4),
                ));
            }
        }
        Ok(())
    }

    /// A camera from matrices in the math convention (row-major `m[row][col]`, applied as
    /// `M · v`, as numpy's `np.array(mathutils.Matrix)` gives them) with an OpenGL projection
    /// (clip depth `[-1, 1]`, as Blender's `region_3d.window_matrix` and
    /// `camera.calc_matrix_camera` give), remapped to wgpu's depth `[0, 1]`. `view` maps the
    /// mesh's object space to view space (in Blender: `view_matrix @ object.matrix_world`).
    /// Nothing is checked here; the renderers check the result.
    pub fn from_gl(view: [[f32; 4]; 4], projection: [[f32; 4]; 4], width: u32, height: u32) -> Camera {
        let gl = DMat4::from_cols_array_2d(&projection.map(|row| row.map(f64::from))).transpose();
        let wgpu_projection = (GL_TO_WGPU_DEPTH * gl).to_cols_array();
        Camera {
            view: std::array::from_fn(|i| view[i % 4][i / 4]),
            projection: wgpu_projection.map(|v| v as f32),
            width,
            height,
        }
    }
}
