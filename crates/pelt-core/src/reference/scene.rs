//! The traceable scene: the fur's strands cut into short chunks and the skin's triangles under one
//! BVH, with the two queries the renderer needs: the nearest hit along a view ray, and whether
//! anything blocks a shadow ray.

use glam::{Vec3, Vec3A};
use obvhs::aabb::Aabb;

use super::bvh::{AXIS_DIRECTIONS, Bvh};
use super::geometry::{FurGeometry, SkinPoint};
use super::intersect::{HairSegment, ray_segment, ray_triangle};
use super::sampler::{Lights, Sampler};
use crate::error::{PeltError, Result};
use crate::rng::Rng;

/// Segments per BVH primitive: a chunk's box stays close to its hair while the tree holds a
/// quarter of the boxes a primitive per segment would.
const CHUNK: u32 = 8;

/// What a view ray hit.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Hit {
    /// A hair: its strand, the index of its segment's first point, the place along it.
    Hair { strand: u32, point: u32, s: f32, t: f32 },
    /// The skin: a triangle and the weights of its 2nd and 3rd corner.
    Skin { triangle: u32, b1: f32, b2: f32, t: f32 },
}

impl Hit {
    pub(crate) fn t(&self) -> f32 {
        match *self {
            Hit::Hair { t, .. } | Hit::Skin { t, .. } => t,
        }
    }
}

/// A strand chunk: up to [`CHUNK`] segments starting at a point.
#[derive(Debug, Clone, Copy)]
struct Chunk {
    strand: u32,
    point: u32,
    segments: u32,
}

/// The fur and its skin, ready to trace.
pub struct ReferenceScene {
    pub(crate) geometry: FurGeometry,
    chunks: Vec<Chunk>,
    bvh: Bvh,
}

impl ReferenceScene {
    /// Builds the BVH over `geometry`.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] (`strands`) when the geometry holds no strand: an asset
    /// baked without hair (density 0, every vertex bald) has nothing for the reference to draw.
    pub fn new(geometry: FurGeometry) -> Result<Self> {
        if geometry.strands.is_empty() {
            return Err(PeltError::parameter(
                "strands",
                "the asset has no hair strands (hair density 0, or every vertex bald): \
                 nothing for the reference to render",
            ));
        }
        let mut chunks = Vec::new();
        for (i, span) in geometry.strands.iter().enumerate() {
            let segments = span.count - 1;
            let mut first = 0;
            while first < segments {
                let n = CHUNK.min(segments - first);
                chunks.push(Chunk {
                    strand: i as u32,
                    point: span.first + first,
                    segments: n,
                });
                first += n;
            }
        }
        let mut boxes: Vec<Aabb> = chunks
            .iter()
            .map(|c| {
                let mut b = Aabb::empty();
                for p in &geometry.points[c.point as usize..=(c.point + c.segments) as usize] {
                    let r = Vec3A::splat(p[3]);
                    let q = Vec3A::new(p[0], p[1], p[2]);
                    b = b.union(&Aabb::new(q - r, q + r));
                }
                b
            })
            .collect();
        if let Some(skin) = &geometry.skin {
            boxes.extend(skin.triangles.iter().map(|t| {
                let mut b = Aabb::empty();
                for &v in t {
                    b.extend(skin.positions[v as usize]);
                }
                b
            }));
        }
        let bvh = Bvh::new(&boxes);
        Ok(ReferenceScene {
            geometry,
            chunks,
            bvh,
        })
    }

    /// The scene's bounds: lowest and highest corner.
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let b = self.bvh.bounds();
        (b.min.into(), b.max.into())
    }

    /// Number of strands.
    pub fn strand_count(&self) -> usize {
        self.geometry.strands.len()
    }

    fn segment(&self, point: u32) -> HairSegment {
        let a = self.geometry.points[point as usize];
        let b = self.geometry.points[point as usize + 1];
        HairSegment {
            a: Vec3A::new(a[0], a[1], a[2]),
            b: Vec3A::new(b[0], b[1], b[2]),
            ra: a[3],
            rb: b[3],
        }
    }

    fn triangle(&self, index: usize) -> [Vec3A; 3] {
        let skin = self
            .geometry
            .skin
            .as_ref()
            .expect("triangles exist only with a skin");
        skin.triangles[index].map(|v| skin.positions[v as usize])
    }

    /// The nearest hit along `origin + t · direction` (`direction` unit), `t` in `(t_min, t_max)`.
    pub(crate) fn nearest(&self, origin: Vec3A, direction: Vec3A, t_min: f32, t_max: f32) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        let ray = Bvh::ray(origin, direction, t_min, t_max);
        self.bvh.nearest(ray, |ray, prim| {
            match self.test(prim, ray.origin, ray.direction, ray.tmin, ray.tmax, None) {
                Some(h) => {
                    best = Some(h);
                    h.t()
                }
                None => f32::INFINITY,
            }
        });
        best
    }

    /// Whether anything lies on `origin + t · direction` for `t` in `(t_min, t_max)`, ignoring
    /// strand `skip_strand` (a hair does not shadow itself: Kajiya–Kay already integrates over
    /// its cross-section).
    pub(crate) fn blocked(
        &self,
        origin: Vec3A,
        direction: Vec3A,
        t_min: f32,
        t_max: f32,
        skip_strand: Option<u32>,
    ) -> bool {
        let ray = Bvh::ray(origin, direction, t_min, t_max);
        self.bvh.any(ray, |ray, prim| {
            self.test(prim, ray.origin, ray.direction, ray.tmin, ray.tmax, skip_strand)
                .is_some()
        })
    }

    fn test(
        &self,
        prim: usize,
        origin: Vec3A,
        direction: Vec3A,
        t_min: f32,
        t_max: f32,
        skip_strand: Option<u32>,
    ) -> Option<Hit> {
        if let Some(chunk) = self.chunks.get(prim) {
            if skip_strand == Some(chunk.strand) {
                return None;
            }
            let mut best: Option<Hit> = None;
            let mut limit = t_max;
            for k in 0..chunk.segments {
                let point = chunk.point + k;
                if let Some(h) = ray_segment(origin, direction, &self.segment(point), t_min, limit) {
                    limit = h.t;
                    best = Some(Hit::Hair {
                        strand: chunk.strand,
                        point,
                        s: h.s,
                        t: h.t,
                    });
                }
            }
            best
        } else {
            let triangle = prim - self.chunks.len();
            ray_triangle(origin, direction, self.triangle(triangle), t_min, t_max).map(|h| Hit::Skin {
                triangle: triangle as u32,
                b1: h.b1,
                b2: h.b2,
                t: h.t,
            })
        }
    }

    /// The hair's unit tangent (root to tip) and albedo at a hit.
    pub(crate) fn hair_at(&self, strand: u32, point: u32, s: f32) -> (Vec3A, Vec3) {
        let HairSegment { a, b, .. } = self.segment(point);
        let span = &self.geometry.strands[strand as usize];
        let along = ((point - span.first) as f32 + s) / (span.count - 1) as f32;
        let albedo = span.root_color.lerp(span.tip_color, along);
        ((b - a).normalize_or_zero(), albedo)
    }

    /// The skin at a hit, facing `view`.
    pub(crate) fn skin_at(&self, triangle: u32, b1: f32, b2: f32, view: Vec3A) -> SkinPoint {
        let skin = self.geometry.skin.as_ref().expect("a skin hit needs a skin");
        skin.at(triangle, Vec3::new(1.0 - b1 - b2, b1, b2), view)
    }

    /// Which pixels of `camera`'s image the skin covers at their centre (the hair ignored): the
    /// outline the alpha profile measures from. Every pixel is `false` without a skin.
    ///
    /// # Errors
    /// As [`Camera`]'s checks in [`super::render_reference`].
    pub fn skin_mask(&self, camera: &crate::camera::Camera) -> Result<Vec<bool>> {
        let rays = camera.rays()?;
        let width = camera.width as usize;
        let mut mask = vec![false; width * camera.height as usize];
        if self.geometry.skin.is_none() {
            return Ok(mask);
        }
        crate::threads::pool().install(|| {
            use rayon::prelude::*;
            mask.par_chunks_mut(width).enumerate().for_each(|(y, row)| {
                for (x, m) in row.iter_mut().enumerate() {
                    let (origin, direction) = rays.ray(x as f64 + 0.5, y as f64 + 0.5);
                    *m = self.nearest_skin(origin, direction).is_some();
                }
            });
        });
        Ok(mask)
    }

    /// The nearest skin triangle along a ray, the hair ignored.
    fn nearest_skin(&self, origin: Vec3A, direction: Vec3A) -> Option<(f32, usize)> {
        let ray = Bvh::ray(origin, direction, 0.0, f32::INFINITY);
        let mut nearest = None;
        self.bvh.nearest(ray, |ray, prim| {
            if prim < self.chunks.len() {
                return f32::INFINITY;
            }
            let tri = prim - self.chunks.len();
            match ray_triangle(ray.origin, ray.direction, self.triangle(tri), ray.tmin, ray.tmax) {
                Some(h) => {
                    nearest = Some((h.t, tri));
                    h.t
                }
                None => f32::INFINITY,
            }
        });
        nearest
    }

    /// Whether a ray from `origin` leaves the skin through its back face in every axis direction:
    /// then `origin` is enclosed by the mesh.
    pub(crate) fn encloses(&self, origin: Vec3A) -> bool {
        if self.geometry.skin.is_none() {
            return false;
        }
        AXIS_DIRECTIONS.into_iter().all(|d| {
            let nearest = self.nearest_skin(origin, d);
            nearest.is_some_and(|(_, tri)| {
                let p = self.triangle(tri);
                (p[1] - p[0]).cross(p[2] - p[0]).dot(d) > 0.0
            })
        })
    }
}

impl Sampler for ReferenceScene {
    fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        ReferenceScene::bounds(self)
    }

    fn encloses(&self, eye: Vec3A) -> bool {
        ReferenceScene::encloses(self, eye)
    }

    /// The nearest hair or skin, lit by every light through a shadow ray.
    fn sample(&self, origin: Vec3A, direction: Vec3A, lights: &Lights<'_>, rng: &mut Rng) -> (Vec3, f32) {
        let Some(hit) = self.nearest(origin, direction, 0.0, f32::INFINITY) else {
            return (Vec3::ZERO, 0.0);
        };
        let point = origin + hit.t() * direction;
        let view = -direction;
        let blocked = |from: Vec3A, skip: Option<u32>| {
            move |toward: Vec3A, _: &mut Rng| {
                if self.blocked(from, toward, lights.epsilon, f32::INFINITY, skip) {
                    0.0
                } else {
                    1.0
                }
            }
        };
        let radiance = match hit {
            Hit::Hair {
                strand, point: p, s, ..
            } => {
                let (tangent, albedo) = self.hair_at(strand, p, s);
                let shading = lights.shading();
                lights.direct(
                    rng,
                    |l| shading.hair(tangent, l, view, albedo),
                    blocked(point, Some(strand)),
                )
            }
            Hit::Skin { triangle, b1, b2, .. } => {
                let skin = self.skin_at(triangle, b1, b2, view);
                lights.skin(&skin, rng, blocked(point + skin.face * lights.epsilon, None))
            }
        };
        (radiance, 1.0)
    }
}
