//! What a frame needs from the camera ([`pelt_core::camera::Camera`]): the checked matrices and the
//! viewer's position in object space that lighting (Lengyel et al. 2001, §2.4: the half vector)
//! and the fin fade (§2.3: fin normal · view direction) need.

use glam::{DMat4, DVec4, Mat4, Vec4};
pub use pelt_core::camera::{Camera, MAX_IMAGE_SIDE};
use pelt_core::error::{PeltError, Result};

/// What the shaders need from the camera, computed in f64 once per frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct CameraFrame {
    /// `projection · view`.
    pub view_proj: Mat4,
    /// Its inverse (clip space back to object space).
    pub inverse_view_proj: Mat4,
    /// The eye in object space, homogeneous: `w = 1` a position (perspective), `w = 0` the unit
    /// direction toward the viewer (orthographic).
    pub eye: Vec4,
}

/// The inverse of `m`, or `None` when its determinant is (relatively) zero.
pub(super) fn invert(m: &DMat4) -> Option<DMat4> {
    let det = m.determinant();
    // Relative to the product of the column lengths (Hadamard's bound on |det|), which scales
    // with the matrix column by column: a camera 1000 units away is as invertible as one nearby.
    let bound: f64 = (0..4).map(|c| m.col(c).length()).product();
    if !det.is_finite() || bound.is_nan() || det.abs() <= 1e-12 * bound {
        return None;
    }
    Some(m.inverse())
}

impl CameraFrame {
    /// Checks the camera's sizes against `max_side` (the adapter's limit) and its matrices, and
    /// derives what the shaders need.
    pub(super) fn of(camera: &Camera, max_side: u32) -> Result<CameraFrame> {
        camera.check(max_side)?;
        let wide = |m: &[f32; 16]| Mat4::from_cols_array(m).as_dmat4();
        let (view, proj) = (wide(&camera.view), wide(&camera.projection));
        let inverse_view = invert(&view)
            .ok_or_else(|| PeltError::parameter("camera.view", "is singular (not invertible)"))?;
        let inverse_proj = invert(&proj)
            .ok_or_else(|| PeltError::parameter("camera.projection", "is singular (not invertible)"))?;
        let last = proj.row(3);
        let eye_view = match (last.x == 0.0 && last.y == 0.0, last.z != 0.0, last.w != 0.0) {
            (true, true, false) => DVec4::W,
            (true, false, true) => DVec4::Z,
            _ => {
                return Err(PeltError::parameter(
                    "camera.projection",
                    "last row must be (0, 0, c, 0) (perspective) or (0, 0, 0, w) (orthographic)",
                ));
            }
        };
        let eye = inverse_view * eye_view;
        let eye = if eye_view.w == 1.0 {
            (eye.truncate() / eye.w).extend(1.0)
        } else {
            let toward = eye.truncate();
            (toward / toward.length()).extend(0.0)
        };
        if !eye.is_finite() {
            return Err(PeltError::parameter(
                "camera.view",
                "does not give a finite eye position",
            ));
        }
        let view_proj = (proj * view).as_mat4();
        let inverse_view_proj = (inverse_view * inverse_proj).as_mat4();
        if !(view_proj.is_finite() && inverse_view_proj.is_finite()) {
            return Err(PeltError::parameter("camera", "projection · view overflows f32"));
        }
        Ok(CameraFrame {
            view_proj,
            inverse_view_proj,
            eye: eye.as_vec4(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn translation(z: f64) -> DMat4 {
        DMat4::from_translation(DVec3::new(0.0, 0.0, z))
    }

    #[test]
    fn far_cameras_invert_and_flat_ones_do_not() {
        // A camera 1000 (or 1e9) units away was called singular by an absolute threshold.
        for z in [-1.0, -1000.0, -1e9] {
            let inverse = invert(&translation(z)).expect("a translation is invertible");
            assert_eq!(inverse.w_axis.z, -z);
        }
        // Row 2 becomes (0, 0, 0, −5): z is flattened away.
        let mut flat = translation(-5.0);
        flat.z_axis.z = 0.0;
        assert!(invert(&flat).is_none());
        let tiny = translation(0.0) * 1e-30;
        assert!(
            invert(&tiny).is_some(),
            "a uniformly tiny scale is still invertible"
        );
    }
}
