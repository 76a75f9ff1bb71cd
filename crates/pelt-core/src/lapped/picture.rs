//! A small CPU picture of a patch layout for demos and reports: an orthographic, z-buffered
//! rendering of the mesh with each patch in its own color (shaded by the angle to the viewer),
//! bald faces grey, and a short dark line along the hair direction at the visible vertices.
//! It needs no GPU, so the demo can save it anywhere.

use glam::Vec3;

use super::{NO_PATCH, Patches};
use crate::error::{PeltError, Result};
use crate::mesh::FurMesh;

/// Largest picture side, pixels.
pub const MAX_SIDE: u32 = 8192;
/// Background (transparent white).
const BACKGROUND: [u8; 4] = [255, 255, 255, 0];
/// Hair line color.
const HAIR: [u8; 4] = [20, 20, 20, 255];
/// Bald face color.
const BALD: [f32; 3] = [0.6, 0.6, 0.6];

/// How to look at the mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct PictureParams {
    /// Width and height in pixels, each in `[1, MAX_SIDE]`.
    pub size: [u32; 2],
    /// Direction the camera looks along (object space); finite, nonzero.
    pub view: [f32; 3],
    /// Length of the hair lines as a share of the mesh's bounding-box diagonal, `[0, 1]`
    /// (0 draws none).
    pub hair_length: f32,
    /// A hair line at every `hair_every`-th vertex, `>= 1`.
    pub hair_every: usize,
}

impl Default for PictureParams {
    fn default() -> Self {
        PictureParams {
            size: [512, 512],
            view: [0.0, 1.0, -0.3],
            hair_length: 0.03,
            hair_every: 1,
        }
    }
}

impl PictureParams {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming the first field out of range.
    pub fn validate(&self) -> Result<()> {
        if self.size.iter().any(|&s| !(1..=MAX_SIDE).contains(&s)) {
            return Err(PeltError::parameter(
                "size",
                format!("width and height must be in [1, {MAX_SIDE}], got {:?}", self.size),
            ));
        }
        let v = self.view;
        if !v.iter().all(|c| c.is_finite()) || v.iter().all(|&c| c == 0.0) {
            return Err(PeltError::parameter(
                "view",
                format!("must be a finite nonzero vector, got {v:?}"),
            ));
        }
        if !(0.0..=1.0).contains(&self.hair_length) {
            return Err(PeltError::parameter(
                "hair_length",
                format!("must be in [0, 1], got {}", self.hair_length),
            ));
        }
        if self.hair_every == 0 {
            return Err(PeltError::parameter("hair_every", "must be at least 1, got 0"));
        }
        Ok(())
    }
}

/// A well-spread color per patch id (golden-ratio hue steps, full saturation, bright).
fn patch_color(id: u32) -> [f32; 3] {
    let hue = (f64::from(id) * 0.618_033_988_749_895).fract() * 6.0;
    let x = 1.0 - (hue % 2.0 - 1.0).abs();
    let (r, g, b) = match hue as u32 {
        0 => (1.0, x, 0.0),
        1 => (x, 1.0, 0.0),
        2 => (0.0, 1.0, x),
        3 => (0.0, x, 1.0),
        4 => (x, 0.0, 1.0),
        _ => (1.0, 0.0, x),
    };
    [r, g, b].map(|c| (0.25 + 0.75 * c) as f32)
}

/// Renders `patches` on `mesh` as RGBA8 rows, top row first.
///
/// # Errors
/// [`PeltError::InvalidParameter`] when `params` is out of range or `patches` was built for a
/// mesh of another size.
pub fn picture(mesh: &FurMesh, patches: &Patches, params: &PictureParams) -> Result<Vec<u8>> {
    params.validate()?;
    if patches.patch.len() != mesh.face_count() || patches.direction.len() != mesh.vertex_count() {
        return Err(PeltError::parameter(
            "patches",
            format!(
                "were built for {} triangles and {} vertices, the mesh has {} and {}",
                patches.patch.len(),
                patches.direction.len(),
                mesh.face_count(),
                mesh.vertex_count()
            ),
        ));
    }
    let [w, h] = params.size.map(|s| s as usize);
    // Lengths in f64, so a view, a face or a mesh of any finite f32 size has one.
    let length = params
        .view
        .iter()
        .map(|&c| f64::from(c).powi(2))
        .sum::<f64>()
        .sqrt();
    let forward = Vec3::from(params.view.map(|c| (f64::from(c) / length) as f32));
    // Object +Z is up on screen (as in Blender's front view), unless the view runs along Z.
    let hint = if forward.z.abs() > 0.999 { Vec3::Y } else { Vec3::Z };
    let side = forward.cross(hint);
    let right = side / side.length();
    let up = right.cross(forward);
    // View coordinates (right, up, depth), the depth moved `bias` toward the viewer.
    let project = |p: Vec3, bias: f32| [p.dot(right), p.dot(up), p.dot(forward) - bias];
    // Screen placement: the projected bounding box fills the picture less a margin.
    let projected: Vec<[f32; 3]> = mesh
        .positions()
        .iter()
        .map(|&p| project(Vec3::from(p), 0.0))
        .collect();
    let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
    for p in &projected {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f32::MIN_POSITIVE);
    let scale = 0.9 * (w.min(h) as f32) / extent;
    let centre = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
    let to_screen = |p: [f32; 3]| {
        [
            w as f32 / 2.0 + (p[0] - centre[0]) * scale,
            h as f32 / 2.0 - (p[1] - centre[1]) * scale,
            p[2],
        ]
    };
    let screen: Vec<[f32; 3]> = projected.iter().map(|&p| to_screen(p)).collect();
    let mut depth = vec![f32::INFINITY; w * h];
    let mut rgba: Vec<[u8; 4]> = vec![BACKGROUND; w * h];

    for (f, tri) in mesh.triangles().iter().enumerate() {
        let [a, b, c] = tri.map(|v| screen[v as usize]);
        let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if area.abs() < 1e-12 {
            continue;
        }
        let p = tri.map(|v| Vec3::from(mesh.positions()[v as usize]));
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let n_length = n.as_dvec3().length();
        let facing = (f64::from(n.dot(forward)).abs() / n_length.max(f64::MIN_POSITIVE)) as f32;
        let base = match patches.patch[f] {
            NO_PATCH => BALD,
            id => patch_color(id),
        };
        let shade = 0.35 + 0.65 * facing;
        let color = base.map(|c| (255.0 * (c * shade).clamp(0.0, 1.0)) as u8);
        let x0 = a[0].min(b[0]).min(c[0]).floor().max(0.0) as usize;
        let x1 = (a[0].max(b[0]).max(c[0]).ceil() as usize).min(w.saturating_sub(1));
        let y0 = a[1].min(b[1]).min(c[1]).floor().max(0.0) as usize;
        let y1 = (a[1].max(b[1]).max(c[1]).ceil() as usize).min(h.saturating_sub(1));
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                let edge =
                    |u: [f32; 3], v: [f32; 3]| (v[0] - u[0]) * (py - u[1]) - (v[1] - u[1]) * (px - u[0]);
                let (wa, wb, wc) = (edge(b, c) / area, edge(c, a) / area, edge(a, b) / area);
                if wa < 0.0 || wb < 0.0 || wc < 0.0 {
                    continue;
                }
                let z = wa * a[2] + wb * b[2] + wc * c[2];
                let i = y * w + x;
                if z < depth[i] {
                    depth[i] = z;
                    rgba[i] = [color[0], color[1], color[2], 255];
                }
            }
        }
    }

    if params.hair_length > 0.0 {
        let diagonal = mesh
            .stats()
            .bbox_max
            .iter()
            .zip(mesh.stats().bbox_min)
            .map(|(a, b)| (f64::from(*a) - f64::from(b)).powi(2))
            .sum::<f64>()
            .sqrt() as f32;
        let hair = params.hair_length * diagonal;
        // Lines sit a little in front of the surface so the z-test keeps the visible ones.
        let bias = 0.01 * extent;
        for v in (0..mesh.vertex_count()).step_by(params.hair_every) {
            if Vec3::from(mesh.normals()[v]).dot(forward) > 0.0 {
                continue;
            }
            let p = Vec3::from(mesh.positions()[v]);
            let tip = p + hair * Vec3::from(patches.direction[v]);
            let (s, t) = (to_screen(project(p, bias)), to_screen(project(tip, bias)));
            let steps = ((t[0] - s[0]).abs().max((t[1] - s[1]).abs()).ceil() as usize).max(1);
            for k in 0..=steps {
                let a = k as f32 / steps as f32;
                let (x, y, z) = (
                    s[0] + a * (t[0] - s[0]),
                    s[1] + a * (t[1] - s[1]),
                    s[2] + a * (t[2] - s[2]),
                );
                if x < 0.0 || y < 0.0 || x >= w as f32 || y >= h as f32 {
                    continue;
                }
                let i = y as usize * w + x as usize;
                if z <= depth[i] {
                    rgba[i] = HAIR;
                }
            }
        }
    }
    Ok(rgba.into_iter().flatten().collect())
}
