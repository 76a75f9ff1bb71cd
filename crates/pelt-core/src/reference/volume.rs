//! The reference's second mode, the hybrid paper's own (§3.2): the baked density volume ray
//! marched through the prisms the triangles extrude, single scattering with the Kajiya–Kay
//! phase, attenuation toward the light and toward the eye. Rendered with the strands' camera,
//! lights and convergence ([`super::render::render_volume_reference`]), it splits the preview's
//! error in two: the strands against their volume, and the volume against the shells.
//!
//! - **Prisms.** Triangle `t` with corners `P_k` and heights `up_k` (growth × fur depth ×
//!   length, as the shells and the strands use) spans `P_k + z · up_k` for `z` from 0 to the
//!   volume's top. Each side quad is cut along the diagonal from the bottom of its lower vertex
//!   id, the same on both sides of an edge, so neighbouring prisms share their faces and a
//!   ray's face crossings pair up into the spans it spends inside each prism.
//! - **Tile coordinates.** The paper locates each step by slicing its prism at the step's
//!   height and taking barycentric coordinates in the slice. Here each face crossing carries
//!   exact coordinates (barycentric weights `b`, height `z`), and the steps between a span's two
//!   crossings interpolate them linearly. The prism's map is bilinear in `(b, z)` (the corners'
//!   up vectors differ), so the error is second order in how much `up` turns across a
//!   triangle: a small share of a texel on the canonical scenes.
//! - **Density.** The extinction is the bake's at the tile point, divided by how much the
//!   prism's slice at that height outgrew the triangle: the strands keep their count and width
//!   as the lift spreads them (a convex skin's tips are sparser than its roots).
//! - **Estimator.** Each step of the view ray gets the opacity `1 − e^{−σ Δt}`
//!   ([`super::density`] gives `σ`); one step is drawn in proportion to its share of the
//!   composite and lit by each light through the transmittance of a march toward it (0 when
//!   the march meets the skin), times the composite's alpha. That is an unbiased estimate of the
//!   marched single-scattering sum at one shadow march per light and sample. The skin behind
//!   the fur adds its light times the view's remaining transmittance. Steps are at most two texels
//!   or layers apart, jittered by one offset per sample.

use std::cell::RefCell;
use std::f32::consts::PI;

use glam::{Vec2, Vec3, Vec3A};
use obvhs::aabb::Aabb;

use super::bvh::{AXIS_DIRECTIONS, Bvh};
use super::density::DensityField;
use super::geometry::{Skin, growth_vectors, lateral_scale, mean_root_color, skin_of};
use super::intersect::ray_triangle;
use super::sampler::{Lights, Sampler};
use crate::error::{Num, PeltError, Result};
use crate::hair::Strand;
use crate::lapped::{NO_PATCH, Patches};
use crate::mesh::FurMesh;
// The transfer bake's bound on `|t · n|`, so the two density models agree.
use crate::prt::volume_input::MIN_CROSSING_COSINE;
use crate::rng::Rng;
use crate::volume::HairVolume;

/// Steps per texel or layer crossed: the steps are jittered, so the optical depth is estimated
/// without bias at any rate; half a step per texel saves a quarter of the time and left the
/// short-furred sphere's error against the strands where it was (0.11).
const STEPS_PER_TEXEL: f32 = 0.5;
/// Most steps in one prism span (a grazing ray across a large triangle).
const MAX_SPAN_STEPS: usize = 256;

/// One triangle's prism.
#[derive(Debug, Clone)]
pub(super) struct Prism {
    /// Bottom corners 0–2 (the skin triangle), top corners 3–5.
    corners: [Vec3A; 6],
    uv: [Vec2; 3],
    /// `pelt_color` at the corners.
    tint: [Vec3; 3],
    /// Per corner, object units per fur depth of height.
    up: [Vec3A; 3],
    dpdu: Vec3A,
    dpdv: Vec3A,
    /// Unit normal of the triangle.
    normal: Vec3A,
    /// Height of the top corners, fur depths.
    top: f32,
    /// Object units per tile unit across the triangle.
    scale: f32,
    /// The slice at height `z` has `1 + a z + b z²` times the triangle's area (projected on its
    /// plane): `[a, b]` ([`slice_growth`]).
    growth: [f32; 2],
    /// Side `k` (corners `k`, `k + 1`) is cut from bottom `k` to top `k + 1` when set, else from
    /// bottom `k + 1` to top `k`.
    cut_from_first: [bool; 3],
}

/// Where a line crosses a prism's face.
#[derive(Debug, Clone, Copy)]
struct Crossing {
    t: f32,
    w: Vec3,
    z: f32,
    bottom: bool,
}

/// The part of a ray inside one prism, with the tile coordinates at both ends.
#[derive(Debug, Clone, Copy)]
struct Span {
    prism: u32,
    t: [f32; 2],
    w: [Vec3; 2],
    z: [f32; 2],
}

/// A view-ray step: where, its opacity, and its prism coordinates.
#[derive(Debug, Clone, Copy)]
struct Step {
    t: f32,
    alpha: f32,
    prism: u32,
    w: Vec3,
    z: f32,
}

/// The nearest skin crossing: distance, triangle, barycentric weights.
#[derive(Debug, Clone, Copy)]
struct SkinHit {
    t: f32,
    triangle: u32,
    w: Vec3,
}

#[derive(Default)]
struct Scratch {
    spans: Vec<Span>,
    steps: Vec<Step>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// The density volume over the mesh, ready to march.
pub struct VolumeScene {
    prisms: Vec<Prism>,
    field: DensityField,
    skin: Skin,
    bvh: Bvh,
}

impl VolumeScene {
    /// The volume of a bake: `volume` (the bake's hair volume, sampled from `strands`) over the
    /// prisms of `mesh` through the `patches`' corner UVs, `fur_depth` object units tall at
    /// length multiplier 1; the skin as the strands' reference has it.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] when `fur_depth` is not positive and finite, the patches
    /// do not belong to the mesh, the volume's sizes disagree or it holds no hair, or every
    /// triangle is bald.
    pub fn from_bake(
        mesh: &FurMesh,
        patches: &Patches,
        volume: &HairVolume,
        strands: &[Strand],
        fur_depth: f64,
    ) -> Result<Self> {
        let field = DensityField::from_volume(volume, strands)?;
        Self::with_field(
            mesh,
            &patches.uv,
            &patches.patch,
            field,
            mean_root_color(strands),
            fur_depth,
        )
    }

    /// The prisms of `mesh` (corner UVs `uv`, patch per triangle `patch`) filled with `field`;
    /// the skin's albedo `mean_root` × `pelt_color`.
    pub(crate) fn with_field(
        mesh: &FurMesh,
        uv: &[[[f32; 2]; 3]],
        patch: &[u32],
        field: DensityField,
        mean_root: Vec3,
        fur_depth: f64,
    ) -> Result<Self> {
        if !(fur_depth.is_finite() && fur_depth > 0.0) {
            return Err(PeltError::parameter(
                "fur_depth",
                format!("must be positive and finite, got {}", Num(fur_depth)),
            ));
        }
        if uv.len() != mesh.face_count() || patch.len() != mesh.face_count() {
            return Err(PeltError::parameter(
                "patches",
                format!("hold {} triangles, the mesh has {}", uv.len(), mesh.face_count()),
            ));
        }
        if !field.has_hair() {
            return Err(PeltError::parameter(
                "volume",
                "the asset's hair volume is empty (hair density 0): nothing for the reference to render",
            ));
        }
        let up = growth_vectors(mesh, fur_depth as f32);
        let positions = mesh.positions();
        let top = field.top();
        let prisms: Vec<Prism> = mesh
            .triangles()
            .iter()
            .enumerate()
            .map(|(t, tri)| {
                let p = tri.map(|v| Vec3A::from(positions[v as usize]));
                let bald = patch[t] == NO_PATCH;
                let up = tri.map(|v| if bald { Vec3A::ZERO } else { up[v as usize] });
                let tint = tri.map(|v| {
                    mesh.color().map_or(Vec3::ONE, |c| {
                        Vec3::new(c[v as usize][0], c[v as usize][1], c[v as usize][2])
                    })
                });
                prism(p, up, top, uv[t], tint, *tri)
            })
            .collect();
        if prisms
            .iter()
            .all(|p: &Prism| p.up.iter().all(|u| *u == Vec3A::ZERO))
        {
            return Err(PeltError::parameter(
                "volume",
                "every triangle is bald (no patch, or hair length 0): nothing for the reference to render",
            ));
        }
        Ok(Self::assemble(prisms, field, skin_of(mesh, mean_root)))
    }

    fn assemble(prisms: Vec<Prism>, field: DensityField, skin: Skin) -> Self {
        let boxes: Vec<Aabb> = prisms
            .iter()
            .map(|p| {
                p.corners
                    .iter()
                    .fold(Aabb::empty(), |b, &c| b.union(&Aabb::new(c, c)))
            })
            .collect();
        let bvh = Bvh::new(&boxes);
        VolumeScene {
            prisms,
            field,
            skin,
            bvh,
        }
    }

    /// Number of prisms (the mesh's triangles).
    pub fn prism_count(&self) -> usize {
        self.prisms.len()
    }

    /// Collects into `spans` the parts of `origin + t · direction`, `t` in `(t_min, ∞)`, inside
    /// each prism, and returns the nearest skin crossing. With `stop_at_skin` the traversal ends
    /// at the first skin crossing found (a shadow ray: blocked).
    fn gather(
        &self,
        origin: Vec3A,
        direction: Vec3A,
        t_min: f32,
        stop_at_skin: bool,
        spans: &mut Vec<Span>,
    ) -> Option<SkinHit> {
        spans.clear();
        let mut skin: Option<SkinHit> = None;
        let ray = Bvh::ray(origin, direction, t_min, f32::INFINITY);
        self.bvh.nearest(ray, |ray, id| {
            let prism = &self.prisms[id];
            let mut list = [Crossing {
                t: 0.0,
                w: Vec3::ZERO,
                z: 0.0,
                bottom: false,
            }; 8];
            let n = prism.crossings(origin, direction, &mut list);
            if n % 2 == 1 {
                // A ray through an edge or corner counted once too often or too rarely: the
                // prism is skipped for this ray (a set of measure zero).
                return f32::INFINITY;
            }
            let list = &mut list[..n];
            list.sort_by(|a, b| a.t.total_cmp(&b.t));
            let mut found = f32::INFINITY;
            for c in list.iter().filter(|c| c.bottom && c.t > t_min && c.t < ray.tmax) {
                if skin.is_none_or(|s| c.t < s.t) {
                    skin = Some(SkinHit {
                        t: c.t,
                        triangle: id as u32,
                        w: c.w,
                    });
                    found = c.t;
                }
            }
            for pair in list.chunks_exact(2) {
                let (a, b) = (pair[0], pair[1]);
                if b.t <= t_min || a.t >= b.t {
                    continue;
                }
                let start = if a.t < t_min {
                    (t_min - a.t) / (b.t - a.t)
                } else {
                    0.0
                };
                spans.push(Span {
                    prism: id as u32,
                    t: [a.t.max(t_min), b.t],
                    w: [a.w.lerp(b.w, start), b.w],
                    z: [a.z + (b.z - a.z) * start, b.z],
                });
            }
            if stop_at_skin && skin.is_some() {
                return t_min;
            }
            found
        });
        skin
    }

    /// Calls `step(t, Δt, w, z)` at the jittered steps of `span` up to `t_end`.
    fn march(&self, span: &Span, t_end: f32, jitter: f32, mut step: impl FnMut(f32, f32, Vec3, f32)) {
        let prism = &self.prisms[span.prism as usize];
        let end = span.t[1].min(t_end);
        if end <= span.t[0] {
            return;
        }
        let keep = (end - span.t[0]) / (span.t[1] - span.t[0]);
        let w1 = span.w[0].lerp(span.w[1], keep);
        let z1 = span.z[0] + (span.z[1] - span.z[0]) * keep;
        let uv = |w: Vec3| prism.uv[0] * w.x + prism.uv[1] * w.y + prism.uv[2] * w.z;
        let texels = (uv(w1) - uv(span.w[0])).length() * self.field.resolution() as f32;
        let layers = (z1 - span.z[0]).abs() / self.field.spacing();
        let n = ((STEPS_PER_TEXEL * texels.max(layers)).ceil() as usize).clamp(1, MAX_SPAN_STEPS);
        let dt = (end - span.t[0]) / n as f32;
        for k in 0..n {
            let f = (k as f32 + jitter) / n as f32;
            step(
                span.t[0] + f * (end - span.t[0]),
                dt,
                span.w[0].lerp(w1, f),
                span.z[0] + (z1 - span.z[0]) * f,
            );
        }
    }

    /// Extinction along unit `direction` and the hair's unit tangent at prism coordinates.
    fn extinction(&self, prism: &Prism, w: Vec3, z: f32, direction: Vec3A) -> (f32, Vec3A) {
        let uv = prism.uv[0] * w.x + prism.uv[1] * w.y + prism.uv[2] * w.z;
        let d = self.field.density(uv, z);
        if d.coverage <= 0.0 || d.radius <= 0.0 || prism.scale <= 0.0 {
            return (0.0, prism.normal);
        }
        let up = prism.up[0] * w.x + prism.up[1] * w.y + prism.up[2] * w.z;
        let tangent = (d.tangent.x * prism.dpdu + d.tangent.y * prism.dpdv + d.tangent.z * up)
            .normalize_or(prism.normal);
        let across = direction.cross(tangent).length();
        let crossing = tangent.dot(prism.normal).abs().max(MIN_CROSSING_COSINE);
        let sigma = 2.0 * d.coverage * across / (PI * d.radius * prism.scale * crossing);
        (sigma / prism.slice_area(z), tangent)
    }

    /// Transmittance from `point` toward unit `direction`: 0 past the skin.
    fn transmittance(
        &self,
        point: Vec3A,
        direction: Vec3A,
        epsilon: f32,
        jitter: f32,
        spans: &mut Vec<Span>,
    ) -> f32 {
        if self.gather(point, direction, epsilon, true, spans).is_some() {
            return 0.0;
        }
        let mut depth = 0.0f32;
        for span in spans.iter() {
            let prism = &self.prisms[span.prism as usize];
            self.march(span, f32::INFINITY, jitter, |_, dt, w, z| {
                depth += self.extinction(prism, w, z, direction).0 * dt;
            });
        }
        (-depth).exp()
    }

    /// Light reaching the eye from the skin at `hit`, times π, before the fur in front.
    fn skin_light(
        &self,
        hit: &SkinHit,
        point: Vec3A,
        view: Vec3A,
        lights: &Lights<'_>,
        rng: &mut Rng,
        spans: &mut Vec<Span>,
    ) -> Vec3 {
        let skin = self.skin.at(hit.triangle, hit.w, view);
        let lifted = point + skin.face * lights.epsilon;
        lights.skin(&skin, rng, |toward, rng| {
            self.transmittance(lifted, toward, lights.epsilon, rng.next_f64() as f32, spans)
        })
    }

    /// Whether the nearest skin crossing along `direction` is a back face.
    fn inside_along(&self, origin: Vec3A, direction: Vec3A) -> bool {
        let mut spans = Vec::new();
        self.gather(origin, direction, 0.0, false, &mut spans)
            .is_some_and(|hit| {
                let p = &self.prisms[hit.triangle as usize].corners;
                (p[1] - p[0]).cross(p[2] - p[0]).dot(direction) > 0.0
            })
    }
}

pub(super) fn prism(
    p: [Vec3A; 3],
    up: [Vec3A; 3],
    top: f32,
    uv: [[f32; 2]; 3],
    tint: [Vec3; 3],
    ids: [u32; 3],
) -> Prism {
    let uv2 = uv.map(Vec2::from);
    let (u1, u2) = (uv2[1] - uv2[0], uv2[2] - uv2[0]);
    let den = u1.perp_dot(u2);
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let (dpdu, dpdv) = if den.abs() > 0.0 {
        ((e1 * u2.y - e2 * u1.y) / den, (e2 * u1.x - e1 * u2.x) / den)
    } else {
        (Vec3A::ZERO, Vec3A::ZERO)
    };
    Prism {
        corners: [
            p[0],
            p[1],
            p[2],
            p[0] + top * up[0],
            p[1] + top * up[1],
            p[2] + top * up[2],
        ],
        uv: uv2,
        tint,
        up,
        dpdu,
        dpdv,
        normal: e1.cross(e2).normalize_or_zero(),
        top,
        scale: lateral_scale(&uv, &p),
        growth: slice_growth(e1, e2, up[1] - up[0], up[2] - up[0]),
        cut_from_first: [0, 1, 2].map(|k| ids[k] < ids[(k + 1) % 3]),
    }
}

/// How the slices of a prism grow with height: lifted by `z` times its corners' up vectors
/// (differing by `d1`, `d2` along its edges `e1`, `e2`), the triangle has `1 + a z + b z²` times
/// its area, projected on its own plane; `[a, b]`, 0 for no area. The strands stand on the same
/// lift and keep their count and width, so their density at height `z` is the tile's over that
/// (the preview's shells thin out alike, `hair_density` in pelt-render).
fn slice_growth(e1: Vec3A, e2: Vec3A, d1: Vec3A, d2: Vec3A) -> [f32; 2] {
    let area = e1.cross(e2);
    let norm = area.length_squared();
    if norm.is_nan() || norm <= 0.0 {
        return [0.0; 2];
    }
    let linear = e1.cross(d2) + d1.cross(e2);
    [linear.dot(area) / norm, d1.cross(d2).dot(area) / norm]
}

/// How far a slice may shrink or grow over the triangle (at a hollow's focus the lifted
/// surface has no area).
pub(super) const MIN_SLICE_AREA: f32 = 0.25;

impl Prism {
    /// The slice at height `z` over the triangle's area (past a hollow's focus the slice turns
    /// over and grows again), within [`MIN_SLICE_AREA`] and its inverse.
    pub(super) fn slice_area(&self, z: f32) -> f32 {
        let [a, b] = self.growth;
        (1.0 + z * (a + z * b))
            .abs()
            .clamp(MIN_SLICE_AREA, 1.0 / MIN_SLICE_AREA)
    }

    /// Every crossing of the line `origin + t · direction` with the prism's eight faces
    /// (bottom, top, two triangles per side), in face order; returns how many.
    fn crossings(&self, origin: Vec3A, direction: Vec3A, out: &mut [Crossing; 8]) -> usize {
        let top_z = self.top;
        let corner = |i: usize| -> (Vec3A, Vec3, f32) {
            let k = i % 3;
            (self.corners[i], Vec3::AXES[k], if i < 3 { 0.0 } else { top_z })
        };
        let mut faces = [[0usize; 3]; 8];
        faces[0] = [0, 1, 2];
        faces[1] = [3, 4, 5];
        for k in 0..3 {
            let (a, b) = (k, (k + 1) % 3);
            let (ta, tb) = (a + 3, b + 3);
            let pair = if self.cut_from_first[k] {
                [[a, b, tb], [a, tb, ta]]
            } else {
                [[a, b, ta], [b, tb, ta]]
            };
            faces[2 + 2 * k] = pair[0];
            faces[3 + 2 * k] = pair[1];
        }
        let mut n = 0;
        for (f, face) in faces.iter().enumerate() {
            let c = face.map(corner);
            let Some(hit) = ray_triangle(
                origin,
                direction,
                [c[0].0, c[1].0, c[2].0],
                f32::NEG_INFINITY,
                f32::INFINITY,
            ) else {
                continue;
            };
            let b0 = 1.0 - hit.b1 - hit.b2;
            out[n] = Crossing {
                t: hit.t,
                w: c[0].1 * b0 + c[1].1 * hit.b1 + c[2].1 * hit.b2,
                z: c[0].2 * b0 + c[1].2 * hit.b1 + c[2].2 * hit.b2,
                bottom: f == 0,
            };
            n += 1;
        }
        n
    }
}

impl Sampler for VolumeScene {
    fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let b = self.bvh.bounds();
        (b.min.into(), b.max.into())
    }

    /// Enclosed when the nearest skin is a back face along each axis direction.
    fn encloses(&self, eye: Vec3A) -> bool {
        AXIS_DIRECTIONS.into_iter().all(|d| self.inside_along(eye, d))
    }

    fn sample(&self, origin: Vec3A, direction: Vec3A, lights: &Lights<'_>, rng: &mut Rng) -> (Vec3, f32) {
        SCRATCH.with_borrow_mut(|scratch| self.sample_with(origin, direction, lights, rng, scratch))
    }
}

impl VolumeScene {
    fn sample_with(
        &self,
        origin: Vec3A,
        direction: Vec3A,
        lights: &Lights<'_>,
        rng: &mut Rng,
        scratch: &mut Scratch,
    ) -> (Vec3, f32) {
        let Scratch { spans, steps } = scratch;
        let skin = self.gather(origin, direction, 0.0, false, spans);
        let t_end = skin.map_or(f32::INFINITY, |s| s.t);
        let jitter = rng.next_f64() as f32;
        steps.clear();
        for span in spans.iter() {
            let prism = &self.prisms[span.prism as usize];
            self.march(span, t_end, jitter, |t, dt, w, z| {
                let sigma = self.extinction(prism, w, z, direction).0;
                if sigma > 0.0 {
                    steps.push(Step {
                        t,
                        alpha: 1.0 - (-sigma * dt).exp(),
                        prism: span.prism,
                        w,
                        z,
                    });
                }
            });
        }
        steps.sort_by(|a, b| a.t.total_cmp(&b.t));
        let mut through = 1.0f32;
        for s in steps.iter() {
            through *= 1.0 - s.alpha;
        }
        let composite = 1.0 - through;
        let view = -direction;
        let mut radiance = Vec3::ZERO;
        if composite > 0.0 {
            // The step whose share of the composite holds the draw.
            let mut goal = rng.next_f64() as f32 * composite;
            let mut before = 1.0f32;
            let mut chosen = steps[steps.len() - 1];
            for s in steps.iter() {
                let share = before * s.alpha;
                if goal < share {
                    chosen = *s;
                    break;
                }
                goal -= share;
                before *= 1.0 - s.alpha;
            }
            let prism = &self.prisms[chosen.prism as usize];
            let (_, tangent) = self.extinction(prism, chosen.w, chosen.z, direction);
            let uv = prism.uv[0] * chosen.w.x + prism.uv[1] * chosen.w.y + prism.uv[2] * chosen.w.z;
            let tint = prism.tint[0] * chosen.w.x + prism.tint[1] * chosen.w.y + prism.tint[2] * chosen.w.z;
            let albedo = self.field.color(uv, chosen.z) * tint;
            let point = origin + chosen.t * direction;
            let shading = lights.shading();
            let lit = lights.direct(
                rng,
                |l| shading.hair(tangent, l, view, albedo),
                |toward, rng| self.transmittance(point, toward, lights.epsilon, rng.next_f64() as f32, spans),
            );
            radiance += composite * lit;
        }
        match skin {
            Some(hit) => {
                let point = origin + hit.t * direction;
                radiance += through * self.skin_light(&hit, point, view, lights, rng, spans);
                (radiance, 1.0)
            }
            None => (radiance, composite),
        }
    }
}
