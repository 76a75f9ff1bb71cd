//! The reference's rays: the preview's camera ([`Camera`], the same matrices) turned into a ray
//! per image point.

use glam::{DMat4, DVec3, DVec4, Vec3A};

use crate::camera::{Camera, MAX_IMAGE_SIDE};
use crate::error::{PeltError, Result};

/// Rays through image points, in object space.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RayGenerator {
    clip_to_object: DMat4,
    eye: Option<DVec3>,
    width: f64,
    height: f64,
}

impl Camera {
    /// Checks the camera and prepares its rays.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `camera.width`, `camera.height`, `camera.view` or
    /// `camera.projection` when a side is out of range, a value is not finite or `projection ·
    /// view` cannot be inverted.
    pub(crate) fn rays(&self) -> Result<RayGenerator> {
        self.check(MAX_IMAGE_SIDE)?;
        let view = DMat4::from_cols_array(&self.view.map(f64::from));
        let projection = DMat4::from_cols_array(&self.projection.map(f64::from));
        let clip = projection * view;
        let inverse = clip.inverse();
        // The inverse maps clip corners back; a singular matrix leaves non-finite values or
        // fails to return identity.
        let check = clip * inverse - DMat4::IDENTITY;
        if !inverse.is_finite() || check.to_cols_array().iter().any(|v| v.abs() > 1e-6) {
            return Err(PeltError::parameter(
                "camera.projection",
                "projection · view must be invertible",
            ));
        }
        // A perspective projection's last row is (0, 0, −1, 0): the eye is the view-space origin.
        let perspective = projection.row(3).w.abs() < 0.5;
        let eye = perspective.then(|| view.inverse().w_axis.truncate());
        Ok(RayGenerator {
            clip_to_object: inverse,
            eye,
            width: f64::from(self.width),
            height: f64::from(self.height),
        })
    }
}

impl RayGenerator {
    /// The ray through image point `(x, y)` in pixels (0 at the top left corner): its origin on
    /// the near plane and unit direction, in object space.
    pub(crate) fn ray(&self, x: f64, y: f64) -> (Vec3A, Vec3A) {
        let ndc_x = x / self.width * 2.0 - 1.0;
        let ndc_y = 1.0 - y / self.height * 2.0;
        let unproject = |z: f64| {
            let p = self.clip_to_object * DVec4::new(ndc_x, ndc_y, z, 1.0);
            p.truncate() / p.w
        };
        let near = unproject(0.0);
        let far = unproject(1.0);
        let direction = (far - near).normalize();
        (near.as_vec3a(), direction.as_vec3a())
    }

    /// The eye in object space for a perspective camera, `None` for an orthographic one.
    pub(crate) fn eye(&self) -> Option<Vec3A> {
        self.eye.map(|e| e.as_vec3a())
    }
}
