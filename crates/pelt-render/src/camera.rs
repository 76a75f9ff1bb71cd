//! What a frame needs from the camera ([`pelt_core::camera::Camera`]): the checked matrices and the
//! viewer's position in object space that lighting (Lengyel et al. 2001, §2.4: the half vector)
//! and the fin fade (§2.3: fin normal · view direction) need.

pub use pelt_core::camera::{Camera, MAX_IMAGE_SIDE};
use pelt_core::error::{PeltError, Result};

/// What the shaders need from the camera, computed in f64 once per frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct CameraFrame {
    /// `projection · view`, column-major.
    pub view_proj: [f32; 16],
    /// Its inverse, column-major (clip space back to object space).
    pub inverse_view_proj: [f32; 16],
    /// The eye in object space, homogeneous: `w = 1` a position (perspective), `w = 0` the unit
    /// direction toward the viewer (orthographic).
    pub eye: [f32; 4],
}

type M4 = [[f64; 4]; 4];

/// Column-major f32 to `m[row][col]` in f64.
fn rows(m: &[f32; 16]) -> M4 {
    std::array::from_fn(|r| std::array::from_fn(|c| f64::from(m[c * 4 + r])))
}

fn mul(a: &M4, b: &M4) -> M4 {
    std::array::from_fn(|r| std::array::from_fn(|c| (0..4).map(|k| a[r][k] * b[k][c]).sum()))
}

/// Inverse by cofactors, or `None` when the determinant is (relatively) zero.
pub(super) fn invert(m: &M4) -> Option<M4> {
    let minor = |skip_r: usize, skip_c: usize| {
        // The three indices other than `skip`, in order.
        let idx = |skip: usize| -> [usize; 3] { std::array::from_fn(|k| k + usize::from(k >= skip)) };
        let (r, c) = (idx(skip_r), idx(skip_c));
        let e = |i: usize, j: usize| m[r[i]][c[j]];
        e(0, 0) * (e(1, 1) * e(2, 2) - e(1, 2) * e(2, 1)) - e(0, 1) * (e(1, 0) * e(2, 2) - e(1, 2) * e(2, 0))
            + e(0, 2) * (e(1, 0) * e(2, 1) - e(1, 1) * e(2, 0))
    };
    let cof: M4 = std::array::from_fn(|r| {
        std::array::from_fn(|c| {
            let sign = if (r + c) % 2 == 0 { 1.0 } else { -1.0 };
            sign * minor(r, c)
        })
    });
    let det: f64 = (0..4).map(|c| m[0][c] * cof[0][c]).sum();
    // Relative to the product of the column lengths (Hadamard's bound on |det|), which scales
    // with the matrix column by column: a camera 1000 units away is as invertible as one nearby.
    let bound: f64 = (0..4)
        .map(|c| (0..4).map(|r| m[r][c] * m[r][c]).sum::<f64>().sqrt())
        .product();
    if !det.is_finite() || bound.is_nan() || det.abs() <= 1e-12 * bound {
        return None;
    }
    // inverse = adjugate / det, the adjugate being the transposed cofactor matrix
    Some(std::array::from_fn(|r| std::array::from_fn(|c| cof[c][r] / det)))
}

impl CameraFrame {
    /// Checks the camera's sizes against `max_side` (the adapter's limit) and its matrices, and
    /// derives what the shaders need.
    pub(super) fn of(camera: &Camera, max_side: u32) -> Result<CameraFrame> {
        camera.check(max_side)?;
        let (view, proj) = (rows(&camera.view), rows(&camera.projection));
        let inverse_view = invert(&view)
            .ok_or_else(|| PeltError::parameter("camera.view", "is singular (not invertible)"))?;
        let inverse_proj = invert(&proj)
            .ok_or_else(|| PeltError::parameter("camera.projection", "is singular (not invertible)"))?;
        let last = proj[3];
        let eye_view = match (last[0] == 0.0 && last[1] == 0.0, last[2] != 0.0, last[3] != 0.0) {
            (true, true, false) => [0.0, 0.0, 0.0, 1.0],
            (true, false, true) => [0.0, 0.0, 1.0, 0.0],
            _ => {
                return Err(PeltError::parameter(
                    "camera.projection",
                    "last row must be (0, 0, c, 0) (perspective) or (0, 0, 0, w) (orthographic)",
                ));
            }
        };
        let eye: [f64; 4] = std::array::from_fn(|r| (0..4).map(|k| inverse_view[r][k] * eye_view[k]).sum());
        let eye = if eye_view[3] == 1.0 {
            [eye[0] / eye[3], eye[1] / eye[3], eye[2] / eye[3], 1.0]
        } else {
            let len = (eye[0] * eye[0] + eye[1] * eye[1] + eye[2] * eye[2]).sqrt();
            [eye[0] / len, eye[1] / len, eye[2] / len, 0.0]
        };
        if !eye.iter().all(|v| v.is_finite()) {
            return Err(PeltError::parameter(
                "camera.view",
                "does not give a finite eye position",
            ));
        }
        let vp = mul(&proj, &view);
        let view_proj: [f32; 16] = std::array::from_fn(|i| vp[i % 4][i / 4] as f32);
        let inverse = mul(&inverse_view, &inverse_proj);
        let inverse_view_proj: [f32; 16] = std::array::from_fn(|i| inverse[i % 4][i / 4] as f32);
        if !view_proj.iter().chain(&inverse_view_proj).all(|v| v.is_finite()) {
            return Err(PeltError::parameter("camera", "projection · view overflows f32"));
        }
        Ok(CameraFrame {
            view_proj,
            inverse_view_proj,
            eye: eye.map(|v| v as f32),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn translation(z: f64) -> M4 {
        [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, z],
            [0.0, 0.0, 0.0, 1.0],
        ]
    }

    #[test]
    fn far_cameras_invert_and_flat_ones_do_not() {
        // A camera 1000 (or 1e9) units away was called singular by an absolute threshold.
        for z in [-1.0, -1000.0, -1e9] {
            let inverse = invert(&translation(z)).expect("a translation is invertible");
            assert_eq!(inverse[2][3], -z);
        }
        let mut flat = translation(-5.0);
        flat[2] = [0.0, 0.0, 0.0, -5.0];
        assert!(invert(&flat).is_none());
        let tiny = translation(0.0).map(|row| row.map(|v| v * 1e-30));
        assert!(
            invert(&tiny).is_some(),
            "a uniformly tiny scale is still invertible"
        );
    }
}
