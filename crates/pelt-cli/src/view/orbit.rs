//! The viewer's orbit camera and light: yaw and pitch around the mesh's bounding-sphere centre
//! (+Z up, as in Blender, from which Pelt's meshes come), a zoom factor relative to the distance
//! that frames the sphere, and the light direction as yaw and pitch in object space.

use glam::DVec3;
use glam::dcamera::rh::proj::directx;
use glam::dcamera::rh::view::look_at_mat4;
use pelt_core::mesh::bounding_sphere;
use pelt_render::Camera;

/// Vertical field of view.
const FOV_Y: f64 = 40.0 * std::f64::consts::PI / 180.0;
/// Radians of orbit or light turn per pixel dragged.
pub const RADIANS_PER_PIXEL: f64 = 0.01;
/// Pitch stays short of the poles, where the up vector would be parallel to the view.
const MAX_PITCH: f64 = 89.0 * std::f64::consts::PI / 180.0;
/// Zoom range, relative to the framing distance.
const ZOOM: (f64, f64) = (0.2, 20.0);
/// Zoom factor per wheel line.
const ZOOM_STEP: f64 = 1.1;
/// The first view: from the front (−Y, Blender's front view), a little above.
const START_PITCH: f64 = 15.0 * std::f64::consts::PI / 180.0;

/// The mesh's bounding sphere, fur included.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    pub centre: DVec3,
    pub radius: f64,
}

impl Sphere {
    /// The sphere around the box of `positions`, grown by `fur` (the tallest hair); a point
    /// mesh still gets a positive radius.
    pub fn around(positions: &[[f32; 3]], fur: f64) -> Sphere {
        let (centre, reach) = bounding_sphere(positions);
        let radius = reach + fur.max(0.0);
        Sphere {
            centre,
            radius: if radius > 0.0 { radius } else { 1.0 },
        }
    }
}

/// Where the camera is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    pub yaw: f64,
    pub pitch: f64,
    /// Distance over the framing distance.
    pub zoom: f64,
}

impl Default for Orbit {
    fn default() -> Self {
        Orbit {
            yaw: 0.0,
            pitch: START_PITCH,
            zoom: 1.0,
        }
    }
}

impl Orbit {
    /// Turns by a drag of `dx, dy` pixels: right turns the object right, down tilts it down.
    pub fn rotate(&mut self, dx: f64, dy: f64) {
        self.yaw = (self.yaw - dx * RADIANS_PER_PIXEL).rem_euclid(std::f64::consts::TAU);
        self.pitch = (self.pitch + dy * RADIANS_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// Moves closer by `lines` wheel lines (negative: away).
    pub fn zoom_by(&mut self, lines: f64) {
        self.zoom = (self.zoom * ZOOM_STEP.powf(-lines)).clamp(ZOOM.0, ZOOM.1);
    }

    /// The eye's unit direction from the centre.
    fn direction(&self) -> DVec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        DVec3::new(cp * sy, -cp * cy, sp)
    }

    /// The camera for a `width × height` image of `sphere`.
    pub fn camera(&self, sphere: &Sphere, width: u32, height: u32) -> Camera {
        let aspect = f64::from(width.max(1)) / f64::from(height.max(1));
        // The narrower of the two fields of view must hold the sphere.
        let half = ((FOV_Y / 2.0).tan() * aspect.min(1.0)).atan();
        let distance = self.zoom * sphere.radius / half.sin();
        let eye = sphere.centre + distance * self.direction();
        let near = (distance - sphere.radius).max(0.01 * sphere.radius);
        let far = distance + sphere.radius;
        // +Z up: the pitch limit keeps the view off the up axis. The projection is onto wgpu's
        // clip space (depth in [0, 1], y up).
        let view = look_at_mat4(eye, sphere.centre, DVec3::Z);
        let projection = directx::perspective(FOV_Y, aspect, near, far);
        Camera {
            view: view.as_mat4().to_cols_array(),
            projection: projection.as_mat4().to_cols_array(),
            width,
            height,
        }
    }
}

/// A direction as yaw (around +Z, 0 toward −Y) and pitch (above the XY plane).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Angles {
    pub yaw: f64,
    pub pitch: f64,
}

impl Angles {
    /// The angles of `d` (non-zero).
    pub fn of(d: [f32; 3]) -> Angles {
        let [x, y, z] = d.map(f64::from);
        Angles {
            yaw: x.atan2(-y),
            pitch: z.atan2(x.hypot(y)),
        }
    }

    /// Turns by a drag of `dx, dy` pixels.
    pub fn rotate(&mut self, dx: f64, dy: f64) {
        self.yaw = (self.yaw + dx * RADIANS_PER_PIXEL).rem_euclid(std::f64::consts::TAU);
        let pole = std::f64::consts::FRAC_PI_2;
        self.pitch = (self.pitch - dy * RADIANS_PER_PIXEL).clamp(-pole, pole);
    }

    /// The unit direction.
    pub fn direction(&self) -> [f32; 3] {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        [cp * sy, -cp * cy, sp].map(|v| v as f32)
    }
}

#[cfg(test)]
mod tests;
