//! The canonical scenes the picture is measured on, built in code (nothing to download): four
//! shapes, short and long fur, five lights, each seen by one fixed camera.
//!
//! Sizes are in units of the object's radius `R` (the sphere's radius, the patch's half width,
//! Suzanne's and the torus's bounding radius): short fur is `0.05 R` deep, long fur `0.2 R`, and
//! the tile is `0.3 R` wide. Suns have strength π (a white Lambertian surface facing one has
//! radiance 1); the environment is a sky of radiance `0.6 + 0.4 z`.

use std::sync::Arc;

use glam::Vec3;
use glam::camera::rh::proj::directx::perspective;
use glam::camera::rh::view::look_at_mat4;

use super::ReferenceLight;
use crate::camera::Camera;
use crate::error::Result;
use crate::mesh::{FurMesh, MeshInput, shapes};
use crate::pipeline::BakeParams;
use crate::prt::{sh, sphere};

/// The object under the fur.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// A flat square, `[-1, 1]²`, 8,192 triangles.
    Patch,
    /// A welded unit sphere, 16,128 triangles.
    Sphere,
    /// Blender's Suzanne subdivided twice, 15,488 triangles.
    Suzanne,
    /// A torus (radii 1 and 0.35), 9,216 triangles.
    Torus,
}

/// How deep the fur is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FurLength {
    /// `0.05 R`.
    Short,
    /// `0.2 R`.
    Long,
}

/// Where the light comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LightSetup {
    /// A sun behind the camera.
    Eye,
    /// A sun from the camera's right.
    Side,
    /// A sun behind the object, about level with it (2° below the horizon as the camera sees
    /// it): the fur's rim catches the light, little else does.
    Back,
    /// A sun straight above.
    Top,
    /// The sky, no sun.
    Environment,
}

impl Shape {
    /// Every shape.
    pub const ALL: [Shape; 4] = [Shape::Patch, Shape::Sphere, Shape::Suzanne, Shape::Torus];

    /// Its name in case names.
    pub fn name(self) -> &'static str {
        match self {
            Shape::Patch => "patch",
            Shape::Sphere => "sphere",
            Shape::Suzanne => "suzanne",
            Shape::Torus => "torus",
        }
    }

    /// The mesh and its radius `R`.
    fn mesh(self) -> (Vec<[f32; 3]>, Vec<[u32; 3]>, f32) {
        match self {
            Shape::Patch => {
                let (positions, triangles) = shapes::square(64);
                (positions, triangles, 1.0)
            }
            Shape::Sphere => {
                let (p, t) = shapes::uv_sphere(128, 64);
                (p, t, 1.0)
            }
            Shape::Suzanne => {
                let data = shapes::subdivide(&shapes::suzanne(), 2);
                let radius = data
                    .positions
                    .iter()
                    .map(|p| Vec3::from(*p).length())
                    .fold(0.0, f32::max);
                (data.positions, data.triangles, radius)
            }
            Shape::Torus => {
                let (p, t) = shapes::torus(96, 48);
                (p, t, 1.35)
            }
        }
    }
}

impl FurLength {
    /// Both lengths.
    pub const ALL: [FurLength; 2] = [FurLength::Short, FurLength::Long];

    /// Its name in case names.
    pub fn name(self) -> &'static str {
        match self {
            FurLength::Short => "short",
            FurLength::Long => "long",
        }
    }

    fn share(self) -> f32 {
        match self {
            FurLength::Short => 0.05,
            FurLength::Long => 0.2,
        }
    }
}

impl LightSetup {
    /// Every light.
    pub const ALL: [LightSetup; 5] = [
        LightSetup::Eye,
        LightSetup::Side,
        LightSetup::Back,
        LightSetup::Top,
        LightSetup::Environment,
    ];

    /// Its name in case names.
    pub fn name(self) -> &'static str {
        match self {
            LightSetup::Eye => "eye",
            LightSetup::Side => "side",
            LightSetup::Back => "back",
            LightSetup::Top => "top",
            LightSetup::Environment => "environment",
        }
    }
}

/// A canonical scene: what to bake, how to look at it and how to light it.
#[derive(Debug, Clone)]
pub struct CanonicalScene {
    /// `<shape>.<length>.<light>`.
    pub name: String,
    /// The mesh, without paint (white, length 1, no comb).
    pub mesh: Arc<FurMesh>,
    /// The bake: default hair, tile `0.3 R`, fur depth `0.05 R` or `0.2 R`.
    pub params: BakeParams,
    /// Square image of `side` pixels, 30° field of view, the object filling about 80%.
    pub camera: Camera,
    /// One sun, or the sky.
    pub lights: Vec<ReferenceLight>,
    /// Where the camera is, object space.
    pub eye: [f32; 3],
    /// Radius of the sphere around the origin the camera frames (the object and its fur).
    pub reach: f32,
}

/// From the front (−y, as Blender's front view), a little above.
const VIEW_DIRECTION: Vec3 = Vec3::new(0.0, -1.0, 0.35);
/// Vertical field of view, radians.
const FIELD_OF_VIEW: f32 = std::f32::consts::FRAC_PI_6;

/// Builds scene `shape` with `length` fur under `light`, seen in a `side`-pixel square.
///
/// # Errors
/// Whatever [`FurMesh::new`] returns for the built-in meshes (nothing, on a valid build).
pub fn canonical_scene(
    shape: Shape,
    length: FurLength,
    light: LightSetup,
    side: u32,
) -> Result<CanonicalScene> {
    let (positions, triangles, radius) = shape.mesh();
    let mesh = Arc::new(FurMesh::new(MeshInput::new(&positions, &triangles))?);
    let mut params = BakeParams::default();
    params.patches.tile_size = f64::from(0.3 * radius);
    params.fur_depth = Some(f64::from(length.share() * radius));

    let reach = radius * (1.0 + length.share());
    let (camera, eye) = framing([0.0; 3], reach, side, side);
    let toward_eye = VIEW_DIRECTION.normalize();
    let sun = |d: Vec3| ReferenceLight::Sun {
        direction: d.normalize().to_array(),
        strength: std::f32::consts::PI,
        color: [1.0; 3],
    };
    let right = Vec3::Z.cross(toward_eye).normalize();
    let lights = match light {
        LightSetup::Eye => vec![sun(toward_eye)],
        LightSetup::Side => vec![sun(right)],
        LightSetup::Back => vec![sun(-toward_eye + 0.3 * Vec3::Z)],
        LightSetup::Top => vec![sun(Vec3::Z)],
        LightSetup::Environment => vec![sky()?],
    };
    Ok(CanonicalScene {
        name: format!("{}.{}.{}", shape.name(), length.name(), light.name()),
        mesh,
        params,
        camera,
        lights,
        eye,
        reach,
    })
}

impl CanonicalScene {
    /// The fur depth's length on screen at the object's centre, pixels.
    pub fn fur_depth_pixels(&self) -> f64 {
        let eye = Vec3::from(self.eye);
        let pixels_per_unit = f64::from(self.camera.height)
            / 2.0
            / f64::from((0.5 * FIELD_OF_VIEW).tan())
            / f64::from(eye.length());
        self.params.fur_depth() * pixels_per_unit
    }
}

/// A camera looking at the sphere of `radius` around `centre` from the front (−y, as Blender's
/// front view) and a little above, the sphere filling about 80% of a `width × height` image
/// (30° vertical field of view); and where the eye is.
pub fn framing(centre: [f32; 3], radius: f32, width: u32, height: u32) -> (Camera, [f32; 3]) {
    let centre = Vec3::from(centre);
    let distance = radius / 0.8 / (0.5 * FIELD_OF_VIEW).tan();
    let eye = centre + VIEW_DIRECTION.normalize() * distance;
    let view = look_at_mat4(eye, centre, Vec3::Z);
    let aspect = width as f32 / height.max(1) as f32;
    let projection = perspective(FIELD_OF_VIEW, aspect, 0.05 * distance, 4.0 * distance);
    let camera = Camera {
        view: view.to_cols_array(),
        projection: projection.to_cols_array(),
        width,
        height,
    };
    (camera, eye.to_array())
}

/// The sky `0.6 + 0.4 z` as order-2 SH (exact: it is linear in the direction).
fn sky() -> Result<ReferenceLight> {
    let directions = sphere::fibonacci_directions(4096);
    let weights = vec![4.0 * std::f64::consts::PI / directions.len() as f64; directions.len()];
    let values: Vec<f64> = directions.iter().map(|d| 0.6 + 0.4 * d[2]).collect();
    let coefficients = sh::project_samples(2, &directions, &weights, &values)?;
    Ok(ReferenceLight::Environment {
        sh: coefficients.iter().map(|&c| [c as f32; 3]).collect(),
    })
}
